//! The camera's rays: the pinhole's direction through any point of the
//! image, one at a time or a lane each (the same bits), and the thin
//! lens's rays of the path tracer's depth of field.

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
    /// The lens's aperture radius and distance in focus.
    radius: f32,
    focus: f32,
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
            radius: c.lens.radius,
            focus: c.focus_distance(),
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

    /// The thin lens's ray through image position (px, py) from the
    /// lens point `u` (two uniform numbers): it passes through the point
    /// the pinhole ray meets on the plane in focus, so that plane is
    /// sharp and a point at distance z is spread over a circle of
    /// diameter 2·radius·|z − focus|/z on that plane. The pinhole's ray
    /// where the radius is 0.
    pub fn lens_ray(&self, px: f32, py: f32, u: (f32, f32)) -> (Vec3A, Vec3A) {
        let d = self.dir(px, py);
        if self.radius <= 0.0 {
            return (self.eye, d);
        }
        let (lx, ly) = disc(u);
        let focal = self.eye + d * (self.focus / d.dot(self.forward));
        let o = self.eye + self.radius * (lx * self.right + ly * self.up);
        (o, (focal - o).normalize())
    }

    pub fn eye(&self) -> Vec3A {
        self.eye
    }
}

/// A uniform point of the unit disc (Shirley and Chiu's concentric map:
/// strata stay compact).
fn disc(u: (f32, f32)) -> (f32, f32) {
    let (a, b) = (2.0 * u.0 - 1.0, 2.0 * u.1 - 1.0);
    if a == 0.0 && b == 0.0 {
        return (0.0, 0.0);
    }
    let quarter = std::f32::consts::FRAC_PI_4;
    let (r, phi) = if a.abs() > b.abs() {
        (a, quarter * (b / a))
    } else {
        (b, 2.0 * quarter - quarter * (a / b))
    };
    (r * phi.cos(), r * phi.sin())
}
