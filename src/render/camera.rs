//! The pinhole camera's rays: a direction through any point of the
//! image, one at a time or a lane each (the same bits).

use glam::Vec3A;

use super::simd::v3::V3;
use super::simd::wide::Wide;
use crate::scene::Camera;

/// The pinhole camera as ray generator for an image of w × h.
pub struct CameraRays {
    eye: Vec3A,
    right: Vec3A,
    up: Vec3A,
    forward: Vec3A,
    tan: f32,
    aspect: f32,
    w: f32,
    h: f32,
}

impl CameraRays {
    pub fn new(c: &Camera, w: u32, h: u32) -> Self {
        let (right, up, forward) = c.basis();
        CameraRays {
            eye: c.eye.into(),
            right: right.into(),
            up: up.into(),
            forward: forward.into(),
            tan: (c.fov_y.clamp(0.01, 179.0).to_radians() / 2.0).tan(),
            aspect: w as f32 / h.max(1) as f32,
            w: w as f32,
            h: h as f32,
        }
    }

    /// Unit direction through image position (px, py), in pixels from the
    /// top-left corner.
    pub fn dir(&self, px: f32, py: f32) -> Vec3A {
        let sx = (2.0 * px / self.w - 1.0) * self.tan * self.aspect;
        let sy = (1.0 - 2.0 * py / self.h) * self.tan;
        (self.forward + sx * self.right + sy * self.up).normalize()
    }

    /// [`CameraRays::dir`] of each lane's (px, py), the same bits.
    #[inline(always)]
    pub fn dirs<W: Wide>(&self, px: W, py: W) -> V3<W> {
        let (one, two) = (W::splat(1.0), W::splat(2.0));
        let sx = two.mul(px).div(W::splat(self.w)).sub(one);
        let sx = sx.mul(W::splat(self.tan)).mul(W::splat(self.aspect));
        let sy = one.sub(two.mul(py).div(W::splat(self.h)));
        let sy = sy.mul(W::splat(self.tan));
        (V3::splat(self.forward) + V3::splat(self.right).scale(sx) + V3::splat(self.up).scale(sy))
            .normalize()
    }

    pub fn eye(&self) -> Vec3A {
        self.eye
    }
}
