//! Motion blur's data: where each moving shape and instance of a frame
//! is when the shutter closes, found by pairing the frame's scene with
//! the next frame's. A ray of the path tracer carries an instant of the
//! shutter ([`super::accel::Ray::time`]) and meets each moving thing
//! where its transform, interpolated between open and close, puts it.
//!
//! Transforms are interpolated entry by entry, so every point of a
//! moving shape travels on a straight line: the union of the bounds at
//! both ends holds it all the time (the trees stay conservative), and a
//! turn of a few degrees per frame is followed to second order.
//! Triangles (polygons, meshes) do not move within a frame.

use glam::Affine3A;

use crate::scene::{shape::OVERLAY, Scene};

/// The transforms at shutter close of what moves, by the frame's own
/// indices; `None` where a thing stands still or has no partner in the
/// next frame.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Motion {
    /// Per geometry, per analytic shape: local → geometry.
    pub shapes: Vec<Vec<Option<Affine3A>>>,
    /// Per instance: geometry → world.
    pub instances: Vec<Option<Affine3A>>,
}

/// The transform a fraction `t` of the way from `a` to `b`.
pub fn lerp(a: &Affine3A, b: &Affine3A, t: f32) -> Affine3A {
    Affine3A {
        matrix3: a.matrix3 * (1.0 - t) + b.matrix3 * t,
        translation: a.translation.lerp(b.translation, t),
    }
}

/// `end` where it differs from `start`.
fn moved(start: &Affine3A, end: Affine3A) -> Option<Affine3A> {
    (end != *start && end.is_finite()).then_some(end)
}

impl Motion {
    /// The motion of `now` toward `next` (the following frame) over the
    /// fraction `shutter` (0..=1) of the frame interval that the shutter
    /// stays open. A shape's partner is the shape of the same kind drawn
    /// by the same symbol (symbol identifiers are stable across frames)
    /// in the geometry of the same index and name, where the symbol drew
    /// one shape only; an instance's is the instance of the same index
    /// and geometry, where both frames place as many.
    pub fn between(now: &Scene, next: &Scene, shutter: f32) -> Motion {
        let t = if shutter.is_finite() {
            shutter.clamp(0.0, 1.0)
        } else {
            0.0
        };
        let shapes = now
            .geometries
            .iter()
            .enumerate()
            .map(|(g, geo)| {
                let Some(later) = next.geometries.get(g).filter(|l| l.name == geo.name) else {
                    return vec![None; geo.shapes.len()];
                };
                // Each symbol's one shape in the next frame (None: several).
                let mut by_symbol = std::collections::HashMap::new();
                for (j, s) in later.shapes.iter().enumerate() {
                    by_symbol
                        .entry(s.symbol)
                        .and_modify(|e| *e = None)
                        .or_insert(Some(j));
                }
                geo.shapes
                    .iter()
                    .map(|s| {
                        let j = (*by_symbol.get(&s.symbol)?)?;
                        let other = &later.shapes[j];
                        (s.symbol != OVERLAY && other.kind == s.kind)
                            .then(|| moved(&s.transform, lerp(&s.transform, &other.transform, t)))?
                    })
                    .collect()
            })
            .collect();
        let instances = if now.instances.len() == next.instances.len() {
            now.instances
                .iter()
                .zip(&next.instances)
                .map(|(a, b)| {
                    (a.geometry == b.geometry)
                        .then(|| moved(&a.transform, lerp(&a.transform, &b.transform, t)))?
                })
                .collect()
        } else {
            vec![None; now.instances.len()]
        };
        Motion { shapes, instances }
    }

    /// Whether nothing moves.
    pub fn is_still(&self) -> bool {
        self.instances.iter().all(Option::is_none)
            && self.shapes.iter().flatten().all(Option::is_none)
    }
}
