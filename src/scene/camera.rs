//! The camera and lights of a frame (`Camera_AnimationParameters`, `l`).

use glam::Vec3;
use serde::{Deserialize, Serialize};

/// A pinhole camera as Iris GL's `lookat` and `perspective` define it.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Camera {
    pub eye: Vec3,
    pub look_at: Vec3,
    /// Rotation about the viewing axis, degrees.
    pub twist: f32,
    /// Vertical field of view, degrees.
    pub fov_y: f32,
    pub aspect: f32,
    pub near: f32,
    pub far: f32,
    /// Default image size in pixels (from the window position).
    pub width: u32,
    pub height: u32,
    /// The thin lens of the path tracer's depth of field (the Whitted
    /// preview keeps the pinhole).
    pub lens: Lens,
}

/// A thin lens: the aperture's radius and the distance in focus (m);
/// radius 0 is the pinhole, focus 0 focuses on the look-at point
/// (`focusDistance`/`aperture` in the camera section, `l` par3 = 14).
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct Lens {
    pub radius: f32,
    pub focus: f32,
}

impl Camera {
    /// Orthonormal (right, up, forward) of the view, twist applied.
    pub fn basis(&self) -> (Vec3, Vec3, Vec3) {
        let f = (self.look_at - self.eye).normalize_or(Vec3::NEG_Z);
        let world_up = if f.cross(Vec3::Y).length_squared() < 1e-12 {
            Vec3::Z
        } else {
            Vec3::Y
        };
        let r = f.cross(world_up).normalize();
        let u = r.cross(f);
        let (s, c) = self.twist.to_radians().sin_cos();
        (r * c + u * s, u * c - r * s, f)
    }

    /// The distance in focus: the lens's, else the look-at point's.
    pub fn focus_distance(&self) -> f32 {
        if self.lens.focus > 0.0 {
            self.lens.focus
        } else {
            (self.look_at - self.eye).length().max(1e-3)
        }
    }
}

/// What kind of light a [`Light`] is.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub enum LightKind {
    /// At `position`, hard shadows.
    #[default]
    Point,
    /// From infinitely far, travelling along `direction` (the sun).
    Directional { direction: Vec3 },
    /// A sphere of `radius` at `position`: soft shadows.
    Sphere { radius: f32 },
}

/// A light: white or grey for vision's colour coding (3.1.2, rule 3).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Light {
    pub position: Vec3,
    pub color: Vec3,
    pub kind: LightKind,
}

impl Light {
    /// A point light.
    pub fn point(position: Vec3, color: Vec3) -> Self {
        Light {
            position,
            color,
            kind: LightKind::Point,
        }
    }
}
