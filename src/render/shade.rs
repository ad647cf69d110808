//! Whitted shading as Rayshade does it: ambient + Lambert + Phong per
//! material, point lights with hard shadows, mirror reflection and
//! refraction to a depth limit, procedural marble, bump and sky.

use glam::{Vec3, Vec3A};

use super::accel::{Accel, Hit, Query};
use super::settings::Settings;
use super::texture;
use crate::random;
use crate::scene::material::Texture;
use crate::scene::{Light, LightKind, Material};

/// Offset of secondary rays from the surface, relative to the scene size
/// of ordinary scenes (metres).
pub(super) const EPS: f32 = 1e-4;

/// Extra passes a ray may make through cloud layers beyond `max_depth`.
const CLOUD_PASSES: u32 = 4;

/// Horizon colour of a sky: its zenith colour lightened toward white.
fn horizon(zenith: Vec3) -> Vec3 {
    zenith.lerp(Vec3::ONE, 0.6)
}

/// What a ray sees where it hits nothing: black, or the sky of `D` 15.
pub fn background(accel: &Accel, dir: Vec3A) -> Vec3 {
    let bg = accel.scene.background;
    if bg == Vec3::ZERO {
        Vec3::ZERO
    } else {
        texture::sky(dir, bg, horizon(bg))
    }
}

fn reflect(d: Vec3A, n: Vec3A) -> Vec3A {
    d - 2.0 * d.dot(n) * n
}

/// Refraction of unit `d` at unit `n` (facing `d`) for η = n1/n2; None on
/// total internal reflection.
fn refract(d: Vec3A, n: Vec3A, eta: f32) -> Option<Vec3A> {
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

/// A point of a surface as shading sees it (found once, for the shadow
/// rays cast ahead and for the shading).
#[derive(Debug, Clone, Copy)]
pub struct Point {
    /// The index of its material (one the scene has).
    pub(super) material: usize,
    p: Vec3A,
    /// The unit normal facing the incoming ray (bumped).
    pub(super) n: Vec3A,
    pub(super) diffuse: Vec3,
    /// Whether the ray comes from outside the surface.
    outside: bool,
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
fn lift(p: Vec3A, n: Vec3A) -> Vec3A {
    p + n * EPS * (1.0 + p.abs().max_element())
}

/// The unit direction from `p` to `light`'s centre and its distance (∞
/// for a directional light).
pub(super) fn toward(light: &Light, p: Vec3A) -> (Vec3A, f32) {
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

/// A uniform point on the unit sphere from slot `slot` of `key`.
fn sphere_point(key: u64, slot: u64) -> Vec3A {
    let z = 1.0 - 2.0 * random::unit(key, 2 * slot) as f32;
    let phi = std::f32::consts::TAU * random::unit(key, 2 * slot + 1) as f32;
    let r = (1.0 - z * z).max(0.0).sqrt();
    Vec3A::new(r * phi.cos(), r * phi.sin(), z)
}
