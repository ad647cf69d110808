//! The point a ray meets: its material, position, normal facing the ray
//! (bumped) and colour (marbled), and how secondary rays leave it.

use glam::{Vec3, Vec3A};

use super::texture;
use crate::render::accel::{Accel, Hit};
use crate::scene::material::Texture;

/// Offset of secondary rays from the surface, relative to the scene size
/// of ordinary scenes (metres).
pub(crate) const EPS: f32 = 1e-4;

/// A point of a surface as shading sees it (found once, for the shadow
/// rays cast ahead and for the shading).
#[derive(Debug, Clone, Copy)]
pub struct Point {
    /// The index of its material (one the scene has).
    pub(in crate::render) material: usize,
    pub(in crate::render) p: Vec3A,
    /// The unit normal facing the incoming ray (bumped).
    pub(in crate::render) n: Vec3A,
    pub(in crate::render) diffuse: Vec3,
    /// Whether the ray comes from outside the surface.
    pub(in crate::render) outside: bool,
}

/// The point where the unit ray `o + t·d` meets `hit`; None without a
/// material (such a point is black).
pub fn point(accel: &Accel, hit: &Hit, o: Vec3A, d: Vec3A) -> Option<Point> {
    let material = hit.material as usize;
    let m = accel.scene.materials.get(material)?;
    let p = o + hit.t * d;
    let outside = hit.normal.dot(d) < 0.0;
    let mut n = if outside { hit.normal } else { -hit.normal };
    let mut diffuse = m.diffuse;
    match m.texture {
        Some(Texture::Marble) => diffuse = diffuse.lerp(Vec3::splat(0.95), texture::marble(p)),
        Some(Texture::Bump) => n = texture::bump(p, n, 0.3),
        Some(Texture::Cloud) | None => {}
    }
    Some(Point {
        material,
        p,
        n,
        diffuse,
        outside,
    })
}

/// Secondary rays leave from just off the surface, on the side `n` faces.
pub(super) fn lift(p: Vec3A, n: Vec3A) -> Vec3A {
    p + n * EPS * (1.0 + p.abs().max_element())
}
