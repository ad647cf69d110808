//! Whitted shading as Rayshade does it: ambient + Lambert + Phong per
//! material, point lights with hard shadows, mirror reflection and
//! refraction to a depth limit (this file, the integrator); lights and
//! their shadows (`lights`), the sky (`sky`), procedural marble, bump
//! and clouds (`texture`).

use glam::{Vec3, Vec3A};

pub mod lights;
pub mod point;
pub mod sky;
pub mod texture;

use super::accel::{Accel, Hit};
use super::settings::Settings;
use crate::scene::material::Texture;
use crate::scene::{LightKind, Material};
pub use lights::shadow_rays;
use lights::{sphere_point, toward};
use point::lift;
pub(crate) use point::EPS;
pub use point::{point, Point};
pub use sky::{background, sky_light};

/// Extra passes a ray may make through cloud layers beyond `max_depth`.
const CLOUD_PASSES: u32 = 4;

/// The mirror image of direction `d` (toward the surface) about `n`.
pub(in crate::render) fn reflect(d: Vec3A, n: Vec3A) -> Vec3A {
    d - 2.0 * d.dot(n) * n
}

/// Refraction of unit `d` at unit `n` (facing `d`) for η = n1/n2; None on
/// total internal reflection.
pub(in crate::render) fn refract(d: Vec3A, n: Vec3A, eta: f32) -> Option<Vec3A> {
    let cos_i = -d.dot(n);
    let k = 1.0 - eta * eta * (1.0 - cos_i * cos_i);
    (k >= 0.0).then(|| (eta * d + (eta * cos_i - k.sqrt()) * n).normalize())
}

/// Colour seen along the unit ray `o + t·d`, and whether it hit anything.
/// `key` keys the random points of soft shadows (one per pixel sample).
pub fn trace(
    accel: &Accel,
    o: Vec3A,
    d: Vec3A,
    st: &Settings,
    depth: u32,
    key: u64,
) -> (Vec3, bool) {
    let Some(hit) = accel.cast(o, d, if depth == 0 { 0.0 } else { EPS }, f32::INFINITY) else {
        return (background(accel, d), false);
    };
    (shade_hit(accel, &hit, o, d, st, depth, key), true)
}

/// Colour of `hit`, the nearest surface the unit ray `o + t·d` meets (as
/// [`trace`] shades it after its cast). Synthetic vision casts its own rays
/// with its clipping range and shades their hits with this.
pub fn shade_hit(
    accel: &Accel,
    hit: &Hit,
    o: Vec3A,
    d: Vec3A,
    st: &Settings,
    depth: u32,
    key: u64,
) -> Vec3 {
    point(accel, hit, o, d).map_or(Vec3::ZERO, |pt| {
        shade_seen(accel, &pt, d, st, depth, key, &[])
    })
}

/// [`shade_hit`] of the [`point`] `pt` met by the unit direction `d`,
/// given whether the [`shadow_rays`] of some lights are blocked, as
/// (light, blocked).
pub fn shade_seen(
    accel: &Accel,
    pt: &Point,
    d: Vec3A,
    st: &Settings,
    depth: u32,
    key: u64,
    seen: &[(usize, bool)],
) -> Vec3 {
    let &Point {
        material,
        p,
        n,
        diffuse,
        outside,
    } = pt;
    let m = &accel.scene.materials[material];
    // A cloud layer lets through what is behind it where it is thin; the
    // pass-through is bounded like any secondary ray.
    if m.texture == Some(Texture::Cloud) {
        let density = texture::cloud(p * 0.02);
        let behind = if density >= 1.0 {
            Vec3::ZERO
        } else if depth < st.max_depth.max(1) + CLOUD_PASSES {
            trace(
                accel,
                p + d * EPS * (1.0 + p.abs().max_element()),
                d,
                st,
                depth + 1,
                key,
            )
            .0
        } else {
            background(accel, d)
        };

        // Clouds scatter light every way: their own colour, unshaded (a
        // lit surface would be dark on the far side of the layer).
        return behind.lerp(diffuse, density);
    }
    shade_surface(accel, m, p, n, d, diffuse, outside, st, depth, key, seen)
}

/// Lights, shadows, reflection and refraction at surface point `p` with
/// unit normal `n` facing the incoming unit direction `d`.
#[allow(clippy::too_many_arguments)]
fn shade_surface(
    accel: &Accel,
    m: &Material,
    p: Vec3A,
    n: Vec3A,
    d: Vec3A,
    diffuse: Vec3,
    outside: bool,
    st: &Settings,
    depth: u32,
    key: u64,
    seen: &[(usize, bool)],
) -> Vec3 {
    let scene = &*accel.scene;
    let mut local = m.ambient;
    let lift = lift(p, n);
    for (li, light) in scene.lights.iter().enumerate() {
        // Direction and distance to the light's centre, for shading.
        let (l, dist) = toward(light, p);
        let ndl = n.dot(l);
        if ndl <= 0.0 || l == Vec3A::ZERO {
            continue;
        }
        let visible = if !st.shadows {
            1.0
        } else if let LightKind::Sphere { radius } = light.kind {
            // Soft shadow: the fraction of points of the sphere in view,
            // sampled by the hash of (pixel, sample, light, point).
            let n_s = st.light_samples.max(1);
            let seen = (0..n_s)
                .filter(|&k| {
                    let slot = (u64::from(depth) << 40) | ((li as u64) << 20) | u64::from(k);
                    let q = Vec3A::from(light.position) + radius * sphere_point(key, slot);
                    let to = q - lift;
                    !accel.occluded(lift, to.normalize_or_zero(), 0.0, to.length())
                })
                .count();
            seen as f32 / n_s as f32
        } else if let Some(&(_, blocked)) = seen.iter().find(|s| s.0 == li) {
            f32::from(u8::from(!blocked))
        } else if accel.occluded(lift, l, 0.0, dist) {
            0.0
        } else {
            1.0
        };
        if visible == 0.0 {
            continue;
        }
        let spec = reflect(-l, n).dot(-d).max(0.0).powf(m.shininess.max(1.0));
        local += visible * light.color * (diffuse * ndl + m.specular * spec);
    }
    let colour = local * (1.0 - m.transmit);
    bounces(accel, m, colour, p, n, d, lift, outside, st, depth, key)
}

/// `colour` (a point's local light) plus what material `m` mirrors and
/// transmits there, traced to the depth limit, or the preview's one look
/// ([`preview_bounce`]): the rest of [`shade_surface`], which
/// [`super::batch`] calls for its samples on mirrors and glass.
#[allow(clippy::too_many_arguments)]
pub(super) fn bounces(
    accel: &Accel,
    m: &Material,
    mut colour: Vec3,
    p: Vec3A,
    n: Vec3A,
    d: Vec3A,
    lift: Vec3A,
    outside: bool,
    st: &Settings,
    depth: u32,
    key: u64,
) -> Vec3 {
    if st.max_depth == 0 && depth == 0 {
        colour += preview_bounce(accel, m, p, n, d, lift, st, key);
    } else if depth < st.max_depth {
        if m.reflect > 0.0 {
            let (c, _) = trace(accel, lift, reflect(d, n).normalize(), st, depth + 1, key);
            colour += m.reflect * c;
        }
        if m.transmit > 0.0 {
            let eta = if outside {
                1.0 / m.ior.max(1e-3)
            } else {
                m.ior
            };
            let below = p - n * EPS * (1.0 + p.abs().max_element());
            let c = match refract(d, n, eta) {
                Some(t) => trace(accel, below, t, st, depth + 1, key).0,
                None => trace(accel, lift, reflect(d, n).normalize(), st, depth + 1, key).0,
            };
            colour += m.transmit * c;
        }
    }
    colour
}

/// What a mirror or glass shows when no bounce is traced (the preview
/// preset, `max_depth` 0), so that they are not black: one look along the
/// reflected ray, and one straight through the object (refraction
/// ignored) to the first surface behind its far side, both shaded with
/// local light only. The final preset traces the real bounces instead.
#[allow(clippy::too_many_arguments)]
fn preview_bounce(
    accel: &Accel,
    m: &Material,
    p: Vec3A,
    n: Vec3A,
    d: Vec3A,
    lift: Vec3A,
    st: &Settings,
    key: u64,
) -> Vec3 {
    let mut colour = Vec3::ZERO;
    if m.reflect > 0.0 {
        let (c, _) = trace(accel, lift, reflect(d, n).normalize(), st, 1, key);
        colour += m.reflect * c;
    }
    if m.transmit > 0.0 {
        let step = d * EPS * (1.0 + p.abs().max_element());
        let mut o = p + step;
        // Leave the object: skip the far sides met from inside (a few, for
        // concave or nested glass).
        for _ in 0..4 {
            match accel.cast(o, d, 0.0, f32::INFINITY) {
                Some(h) if h.normal.dot(d) > 0.0 => o += h.t * d + step,
                _ => break,
            }
        }
        colour += m.transmit * trace(accel, o, d, st, 1, key).0;
    }
    colour
}
