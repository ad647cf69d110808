//! The SIMD lanes the accelerator and the shading run on: 4, 8 or 16
//! f32 lanes (`wide`) and vectors of them (`v3`).

pub mod v3;
pub mod wide;

use glam::Vec3A;

/// Rays a packet holds: one bit each of a `u32` mask.
pub const LANES: usize = 16;

/// One value per ray of a packet.
pub type Lanes = [f32; LANES];

/// Lane `i`'s vector of three lane values.
#[inline(always)]
pub fn at(v: &[Lanes; 3], i: usize) -> Vec3A {
    Vec3A::new(v[0][i], v[1][i], v[2][i])
}
