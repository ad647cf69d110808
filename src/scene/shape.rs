//! Analytic shapes as unit shapes under affine transforms, so every shape
//! of appendix C.3 is intersected exactly in its local frame.
//!
//! Local axes: x = the turtle's heading H, y = left L, z = up U.

use glam::{Affine3A, Vec3};
use serde::{Deserialize, Serialize};

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
