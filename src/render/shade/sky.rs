//! The sky: what a ray sees where it hits nothing (the background of
//! `D` 15, a gradient from the zenith colour to a lighter horizon, or a
//! uniform sky).

use glam::{Vec3, Vec3A};

use super::texture;
use crate::render::accel::Accel;
use crate::scene::Sky;

/// Horizon colour of a sky: its zenith colour lightened toward white.
fn horizon(zenith: Vec3) -> Vec3 {
    zenith.lerp(Vec3::ONE, 0.6)
}

/// What a ray sees where it hits nothing: black, or the sky of `D` 15
/// (a gradient, or uniform where `D` 15 gave its colour).
pub fn background(accel: &Accel, dir: Vec3A) -> Vec3 {
    let bg = accel.scene.background;
    if bg == Vec3::ZERO || accel.scene.sky == Sky::Uniform {
        bg
    } else {
        texture::sky(dir, bg, horizon(bg))
    }
}

/// The sky as a light: [`background`] without the gradient's painted
/// clouds (a detail for the eye; as light they only add noise, and their
/// noise function was half of a path-traced frame's time).
pub fn sky_light(accel: &Accel, dir: Vec3A) -> Vec3 {
    let bg = accel.scene.background;
    if bg == Vec3::ZERO || accel.scene.sky == Sky::Uniform {
        return bg;
    }
    let up = dir.try_normalize().map_or(0.0, |d| d.y.max(0.0));
    horizon(bg).lerp(bg, up)
}
