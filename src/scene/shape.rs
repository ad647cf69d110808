//! Analytic shapes as unit shapes under affine transforms, so every shape
//! of appendix C.3 is intersected exactly in its local frame.
//!
//! Local axes: x = the turtle's heading H, y = left L, z = up U.

use glam::{Affine3A, Vec3, Vec3A};
use serde::{Deserialize, Serialize};

use super::MAX_COORDINATE;

/// A unit shape in local coordinates.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum ShapeKind {
    /// [0,1] × [−½,½] × [−½,½]: cubes `c d`.
    Box,
    /// Radius 1 at the origin: spheres `a`, ellipsoids `s`.
    Sphere,
    /// Radius 1 around x from 0 to 1, closed by disks: cylinders `o`,
    /// segments `R S`.
    Cylinder,
    /// Radius 1 around x from 0 to `length`, ending in half spheres of
    /// radius 1: capsules `O N`.
    Capsule { length: f32 },
    /// A cone around x from 0 to `length`, radius `r0` to `r1`, ending in
    /// spheres of those radii: trunks `P Q` (rigid transform).
    Trunk { length: f32, r0: f32, r1: f32 },
}

/// One analytic shape.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Shape {
    pub kind: ShapeKind,
    /// Local → world (of its geometry).
    pub transform: Affine3A,
    pub material: u32,
    /// Identifier of the symbol that drew it (stable across frames).
    pub symbol: u64,
}

/// One triangle, counter-clockwise seen from the side its normal faces.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Triangle {
    pub v: [Vec3; 3],
    pub material: u32,
    pub symbol: u64,
}

impl Triangle {
    pub fn normal(&self) -> Vec3 {
        (self.v[1] - self.v[0])
            .cross(self.v[2] - self.v[0])
            .normalize_or_zero()
    }
}

/// Local-space AABB (min, max) of a unit shape; NaN for parameters that
/// describe no solid (negative, NaN or infinite sizes), so that [`bounds`]
/// rejects them.
pub fn local_bounds(kind: ShapeKind) -> (Vec3A, Vec3A) {
    match kind {
        ShapeKind::Box => (Vec3A::new(0.0, -0.5, -0.5), Vec3A::new(1.0, 0.5, 0.5)),
        ShapeKind::Sphere => (Vec3A::splat(-1.0), Vec3A::ONE),
        ShapeKind::Cylinder => (Vec3A::new(0.0, -1.0, -1.0), Vec3A::ONE),
        ShapeKind::Capsule { length } if valid_capsule(length) => {
            (Vec3A::splat(-1.0), Vec3A::new(length + 1.0, 1.0, 1.0))
        }
        ShapeKind::Trunk { length, r0, r1 } if valid_trunk(length, r0, r1) => {
            let r = r0.max(r1);
            (
                Vec3A::new((-r0).min(length - r1), -r, -r),
                Vec3A::new(r0.max(length + r1), r, r),
            )
        }
        _ => (Vec3A::NAN, Vec3A::NAN),
    }
}

/// Conservative AABB of a shape in its geometry's coordinates: the box
/// around the 8 transformed corners of [`local_bounds`], padded by a few
/// ulps against rounding. None for non-finite transforms or shapes, and
/// for bounds beyond ±[`MAX_COORDINATE`].
pub fn bounds(shape: &Shape) -> Option<(Vec3A, Vec3A)> {
    let (lo, hi) = local_bounds(shape.kind);
    transformed_box(&shape.transform, lo, hi)
}

/// AABB of a triangle; None when a coordinate is not finite or beyond
/// ±[`MAX_COORDINATE`].
pub fn triangle_bounds(v: &[Vec3; 3]) -> Option<(Vec3A, Vec3A)> {
    let (a, b, c) = (Vec3A::from(v[0]), Vec3A::from(v[1]), Vec3A::from(v[2]));
    let (lo, hi) = (a.min(b).min(c), a.max(b).max(c));
    // min and max may drop a NaN: the corners are checked themselves.
    let finite = a.is_finite() && b.is_finite() && c.is_finite();
    (finite && within(lo, hi)).then_some((lo, hi))
}

/// Whether a box is finite and within ±[`MAX_COORDINATE`] (NaN is not).
pub fn within(min: Vec3A, max: Vec3A) -> bool {
    let m = Vec3A::splat(MAX_COORDINATE);
    min.cmpge(-m).all() && max.cmple(m).all()
}

fn transformed_box(m: &Affine3A, lo: Vec3A, hi: Vec3A) -> Option<(Vec3A, Vec3A)> {
    if !(m.is_finite() && lo.is_finite() && hi.is_finite()) {
        return None;
    }
    let c = (lo + hi) * 0.5;
    let e = (hi - lo) * 0.5;
    let m3 = &m.matrix3;
    let wc = m.transform_point3a(c);
    let we = m3.x_axis.abs() * e.x + m3.y_axis.abs() * e.y + m3.z_axis.abs() * e.z;
    let pad = (wc.abs() + we) * (4.0 * f32::EPSILON);
    let (min, max) = (wc - we - pad, wc + we + pad);
    within(min, max).then_some((min, max))
}

pub(crate) fn valid_capsule(length: f32) -> bool {
    length.is_finite() && length >= 0.0
}

/// A trunk needs one positive radius; a zero radius makes a pointed cone
/// and a zero length the larger of two concentric spheres.
pub(crate) fn valid_trunk(length: f32, r0: f32, r1: f32) -> bool {
    length.is_finite()
        && length >= 0.0
        && r0.is_finite()
        && r1.is_finite()
        && r0 >= 0.0
        && r1 >= 0.0
        && r0.max(r1) > 0.0
}
