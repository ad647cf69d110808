//! Analytic shapes as unit shapes under affine transforms, so every shape
//! of appendix C.3 is intersected exactly in its local frame.
//!
//! Local axes: x = the turtle's heading H, y = left L, z = up U.

use glam::{Affine3A, Vec3, Vec3A};
use serde::{Deserialize, Serialize};

use crate::aabb::{self, Aabb};

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

/// The symbol identifier of what is drawn for the viewer only — an
/// actor's planned path (`turtle` 3) — and is not part of the world the
/// actors see: their vision looks through it.
pub const OVERLAY: u64 = u64::MAX;

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

/// Local-space AABB of a unit shape; NaN for parameters that describe no
/// solid (negative, NaN or infinite sizes), so that [`bounds`] rejects
/// them.
pub fn local_bounds(kind: ShapeKind) -> Aabb {
    let (min, max) = match kind {
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
    };
    Aabb::new(min, max)
}

/// Conservative AABB of a shape in its geometry's coordinates: the box
/// around the 8 transformed corners of [`local_bounds`], padded by a few
/// ulps against rounding. None for non-finite transforms or shapes, and
/// for bounds beyond ±[`crate::aabb::MAX_COORDINATE`].
pub fn bounds(shape: &Shape) -> Option<Aabb> {
    aabb::transformed_padded(&local_bounds(shape.kind), &shape.transform)
}

/// AABB of a triangle; None when a coordinate is not finite or beyond
/// ±[`crate::aabb::MAX_COORDINATE`].
pub fn triangle_bounds(v: &[Vec3; 3]) -> Option<Aabb> {
    aabb::around(&v.map(Vec3A::from))
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
