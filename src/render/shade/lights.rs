//! Lights: the direction and distance to a light, the shadow rays a
//! point casts toward the point and directional lights, and the random
//! points of a sphere light's soft shadows.

use glam::Vec3A;

use super::point::{lift, Point};
use crate::random;
use crate::render::accel::{Accel, Query};
use crate::render::settings::Settings;
use crate::scene::material::Texture;
use crate::scene::{Light, LightKind};

/// The unit direction from `p` to `light`'s centre and its distance (∞
/// for a directional light).
pub(crate) fn toward(light: &Light, p: Vec3A) -> (Vec3A, f32) {
    match light.kind {
        LightKind::Directional { direction } => {
            (-Vec3A::from(direction).normalize_or_zero(), f32::INFINITY)
        }
        _ => {
            let to = Vec3A::from(light.position) - p;
            (to.normalize_or_zero(), to.length())
        }
    }
}

/// The hard shadow rays that shading `pt` casts, as (light, ray),
/// pushed onto `out`: one toward each point and directional light the
/// surface faces (sphere lights sample their own). A pixel casts its
/// samples' together ([`Accel::occluded_all`]) and gives the answers to
/// [`shade_seen`].
pub fn shadow_rays(accel: &Accel, pt: &Point, st: &Settings, out: &mut Vec<(usize, Query)>) {
    if !st.shadows || accel.scene.materials[pt.material].texture == Some(Texture::Cloud) {
        return;
    }
    for (li, light) in accel.scene.lights.iter().enumerate() {
        if matches!(light.kind, LightKind::Sphere { .. }) {
            continue;
        }
        let (l, dist) = toward(light, pt.p);
        if pt.n.dot(l) > 0.0 && l != Vec3A::ZERO {
            let origin = lift(pt.p, pt.n);
            out.push((
                li,
                Query {
                    origin,
                    dir: l,
                    tmin: 0.0,
                    tmax: dist,
                },
            ));
        }
    }
}

/// A uniform point on the unit sphere from slot `slot` of `key`.
pub(super) fn sphere_point(key: u64, slot: u64) -> Vec3A {
    uniform_sphere((
        random::unit(key, 2 * slot) as f32,
        random::unit(key, 2 * slot + 1) as f32,
    ))
}

/// A uniform direction on the unit sphere from two uniform numbers; its
/// pdf is [`SPHERE_PDF`].
pub(in crate::render) fn uniform_sphere(u: (f32, f32)) -> Vec3A {
    let z = 1.0 - 2.0 * u.0;
    let phi = std::f32::consts::TAU * u.1;
    let r = (1.0 - z * z).max(0.0).sqrt();
    Vec3A::new(r * phi.cos(), r * phi.sin(), z)
}

/// The pdf of [`uniform_sphere`]: 1/4π.
pub(in crate::render) const SPHERE_PDF: f32 = 1.0 / (4.0 * std::f32::consts::PI);
