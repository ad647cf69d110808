//! The path tracer (`--integrator path`): unidirectional, with
//! next-event estimation toward the lights and the sky, multiple
//! importance sampling (power heuristic) between light and BSDF samples
//! of the sky, Russian roulette, the materials as BSDFs ([`bsdf`]) and a
//! thin-lens camera. Every random number is a hash of (frame, pixel,
//! sample, vertex, dimension) (DESIGN §4), so a pixel's value does not
//! depend on the thread that computes it.
//!
//! Radiometry (docs/rendering.md): a thesis light of colour c gives the
//! irradiance π·c at any distance, as Rayshade's lights did (no falloff),
//! so a white diffuse surface facing it has the radiance c the Whitted
//! look shows; the sky is an environment of its own radiance; a scene
//! without a sky is lit by an invisible uniform environment of radiance
//! [`AMBIENT`], Rayshade's ambient term made physical (it is occluded).

pub mod bsdf;

use std::f32::consts::PI;

use glam::{Vec3, Vec3A};

use super::accel::{Accel, Hit, Query};
use super::camera::CameraRays;
use super::sample::{Integrate, PixelOut, Samples};
use super::settings::Settings;
use super::shade::lights::{uniform_sphere, SPHERE_PDF};
use super::shade::{self, lights::toward, texture, EPS};
use crate::random::{self, Stream};
use crate::scene::material::Texture;
use crate::scene::{LightKind, Sky};
use bsdf::Bsdf;

/// The radiance of the environment of a scene without a sky (the
/// materials' ambient factor: Rayshade's ambient 0.2 · diffuse).
pub const AMBIENT: f32 = 0.2;

/// The radiance of `D` 15's gradient sky as a fraction of its colour:
/// with a sun of colour 1 a level surface then takes about 70 % of its
/// light from the sun and 30 % from the sky, as on a clear day (seen
/// whole, the sky's colour would outshine the sun's light two to one
/// and wash the scene out). A sky given its colour is that radiance.
pub const GRADIENT_SKY: f32 = 0.4;

/// The vertex from which Russian roulette may end a path.
const ROULETTE_FROM: u32 = 3;

/// Passes through cloud layers a path may make besides its bounces.
const CLOUD_PASSES: u32 = 4;

/// Random-number dimensions of one vertex (slots `vertex << 32 | dim`).
mod dim {
    pub const PICK: u64 = 0;
    pub const DIRECTION: u64 = 1;
    pub const SKY: u64 = 3;
    pub const ROULETTE: u64 = 5;
    /// One per pass through a cloud layer.
    pub const CLOUDS: u64 = 6;
    /// Two per sphere light, from here on.
    pub const LIGHTS: u64 = 6 + super::CLOUD_PASSES as u64;
}

/// The random number of dimension `dim` at vertex `vertex` of a path.
fn unit(key: u64, vertex: u32, dim: u64) -> f32 {
    random::unit(key, (u64::from(vertex) << 32) | dim) as f32
}

fn pair(key: u64, vertex: u32, dim: u64) -> (f32, f32) {
    (unit(key, vertex, dim), unit(key, vertex, dim + 1))
}

/// The power heuristic's weight of a strategy of pdf `a` against `b`.
fn power(a: f32, b: f32) -> f32 {
    let (a2, b2) = (a * a, b * b);
    if a2 + b2 > 0.0 {
        a2 / (a2 + b2)
    } else {
        0.0
    }
}

/// The radiance of the environment seen along `d`; `direct`: by the
/// camera (or through mirrors and glass only), which sees black where
/// the scene has no sky, and the gradient sky's painted clouds, which
/// light nothing ([`shade::sky_light`]).
fn environment(accel: &Accel, d: Vec3A, direct: bool) -> Vec3 {
    let scene = &accel.scene;
    let scale = if scene.sky == Sky::Gradient {
        GRADIENT_SKY
    } else {
        1.0
    };
    if scene.background == Vec3::ZERO {
        if direct {
            Vec3::ZERO
        } else {
            Vec3::splat(AMBIENT)
        }
    } else if direct {
        shade::background(accel, d) * scale
    } else {
        shade::sky_light(accel, d) * scale
    }
}

/// The path integrator's buffers for a row.
#[derive(Default)]
pub struct PathTracer {
    samples: Samples,
    buffers: Buffers,
}

impl Integrate for PathTracer {
    /// Pixel by pixel: a pixel's camera rays are cast together.
    fn row(
        &mut self,
        accel: &Accel,
        cam: &CameraRays,
        st: &Settings,
        y: u32,
        put: &mut dyn FnMut(u32, PixelOut),
    ) {
        let PathTracer { samples, buffers } = self;
        for x in 0..st.width {
            let pixel = samples.pixel(accel, cam, st, (x, y), |key, s| {
                colours(
                    accel,
                    cam,
                    st,
                    (x, y),
                    key,
                    &s.offsets,
                    buffers,
                    &mut s.colours,
                )
            });
            put(x, pixel);
        }
    }
}

/// A pixel's camera rays and their first hits, kept from pixel to pixel
/// of a row so that a pixel allocates nothing.
#[derive(Default)]
pub struct Buffers {
    queries: Vec<Query>,
    hits: Vec<Option<Hit>>,
}

/// The pixel (x, y)'s samples' colours and whether each camera ray met a
/// surface, into `out`; `offsets` are the samples' positions in the
/// pixel, `key` the pixel's key. Where nothing moves, the camera rays
/// are cast together (the same hits as one at a time, found in packets).
#[allow(clippy::too_many_arguments)]
pub fn colours(
    accel: &Accel,
    cam: &CameraRays,
    st: &Settings,
    (x, y): (u32, u32),
    key: u64,
    offsets: &[(f32, f32)],
    buffers: &mut Buffers,
    out: &mut Vec<(Vec3, bool)>,
) {
    let sample_key = |s: usize| random::key(key, Stream::Pixel, s as u64, 2);
    let Buffers { queries, hits } = buffers;
    queries.clear();
    queries.extend(offsets.iter().enumerate().map(|(s, &(ox, oy))| {
        let u = pair(sample_key(s), u32::MAX, 0);
        let (origin, dir) = cam.lens_ray(x as f32 + ox, y as f32 + oy, u);
        Query {
            origin,
            dir,
            tmin: 0.0,
            tmax: f32::INFINITY,
        }
    }));
    if accel.moves() {
        hits.clear();
    } else {
        accel.cast_all(queries, hits);
    }
    out.clear();
    out.extend(queries.iter().enumerate().map(|(s, q)| {
        let key = sample_key(s);
        let time = unit(key, u32::MAX, 2);
        let first = hits.get(s).copied();
        radiance(accel, (q.origin, q.dir, first), st, key, time)
    }));
}

/// The radiance arriving at `o` from the unit direction `-d` at the
/// instant `time` of the shutter, and whether the ray met a surface;
/// `first`: the ray's hit where it is already known. `st.max_depth`
/// bounces follow the first surface (0: direct light only), as
/// Mitsuba's `max_depth` − 2.
pub fn radiance(
    accel: &Accel,
    (o, d, mut first): (Vec3A, Vec3A, Option<Option<Hit>>),
    st: &Settings,
    key: u64,
    time: f32,
) -> (Vec3, bool) {
    let scene = &*accel.scene;
    let (mut o, mut d) = (o, d);
    let mut light = Vec3::ZERO;
    let mut beta = Vec3::ONE;
    // The pdf of the smooth lobe that chose `d`; 0 after a mirror, glass
    // or the camera (no light sample finds those directions).
    let mut pdf = 0.0f32;
    let mut direct = true;
    let mut met = false;
    let (mut vertex, mut passes) = (0u32, 0u32);
    loop {
        let cast = match first.take() {
            Some(known) => known,
            None => accel.cast_at(o, d, 0.0, f32::INFINITY, time),
        };
        let Some(hit) = cast else {
            let sky = environment(accel, d, direct);
            let w = if pdf > 0.0 {
                power(pdf, SPHERE_PDF)
            } else {
                1.0
            };
            light += beta * sky * w;
            break;
        };
        met |= vertex == 0;
        let Some(pt) = shade::point(accel, &hit, o, d) else {
            break;
        };
        let m = &scene.materials[pt.material];
        let step = EPS * (1.0 + pt.p.abs().max_element());
        if m.texture == Some(Texture::Cloud) && passes < CLOUD_PASSES {
            // A cloud layer is seen (by the camera, in mirrors) where its
            // density's chance says, a diffuse surface of its colour; it
            // lights and shades nothing, as the light samples see
            // through it (it casts no shadow), so a path that scatters
            // on toward it passes.
            let seen = direct
                && unit(key, vertex, dim::CLOUDS + u64::from(passes)) < texture::cloud(pt.p * 0.02);
            if !seen {
                passes += 1;
                o = pt.p + d * step;
                continue;
            }
        }
        let wo = -d;
        let b = Bsdf::new(m, pt.diffuse, pt.n, pt.outside);
        let lift = pt.p + pt.n * step;
        if b.smooth() {
            light += beta * next_event(accel, &b, wo, lift, (key, vertex), time);
        }
        if vertex >= st.max_depth {
            // The last vertex: its BSDF ray still looks for the sky (the
            // other half of the MIS pair), but scatters no more.
            if let Some(s) = b.sample(
                wo,
                unit(key, vertex, dim::PICK),
                pair(key, vertex, dim::DIRECTION),
            ) {
                if s.pdf > 0.0 && !accel.occluded_at(lift, s.wi, 0.0, f32::INFINITY, time) {
                    light += beta
                        * s.weight
                        * environment(accel, s.wi, false)
                        * power(s.pdf, SPHERE_PDF);
                }
            }
            break;
        }
        let Some(s) = b.sample(
            wo,
            unit(key, vertex, dim::PICK),
            pair(key, vertex, dim::DIRECTION),
        ) else {
            break;
        };
        beta *= s.weight;
        pdf = s.pdf;
        direct &= s.pdf == 0.0;
        o = if s.through { pt.p - pt.n * step } else { lift };
        d = s.wi;
        vertex += 1;
        if vertex >= ROULETTE_FROM {
            let q = beta.max_element().min(0.95);
            if q <= 0.0 || unit(key, vertex, dim::ROULETTE) >= q {
                break;
            }
            beta /= q;
        }
        if !beta.is_finite() {
            break;
        }
    }
    (light, met)
}

/// The light arriving at `lift` (just off a surface of BSDF `b`, seen
/// from `wo`) straight from the lights and the sky, shadows cast.
fn next_event(
    accel: &Accel,
    b: &Bsdf,
    wo: Vec3A,
    lift: Vec3A,
    (key, vertex): (u64, u32),
    time: f32,
) -> Vec3 {
    let mut light = Vec3::ZERO;
    for (li, l) in accel.scene.lights.iter().enumerate() {
        let (wi, dist) = match l.kind {
            LightKind::Sphere { radius } => {
                let u = pair(key, vertex, dim::LIGHTS + 2 * li as u64);
                let q = Vec3A::from(l.position) + radius * uniform_sphere(u);
                let to = q - lift;
                (to.normalize_or_zero(), to.length())
            }
            _ => toward(l, lift),
        };
        if wi == Vec3A::ZERO {
            continue;
        }
        let f = b.eval(wo, wi);
        if f == Vec3::ZERO || accel.occluded_at(lift, wi, 0.0, dist, time) {
            continue;
        }
        // Irradiance π·c on a surface facing the light.
        light += f * (PI * l.color) * b_cos(b, wi);
    }
    // The sky, sampled uniformly, weighed against the BSDF's own samples.
    let wi = uniform_sphere(pair(key, vertex, dim::SKY));
    let f = b.eval(wo, wi);
    if f != Vec3::ZERO && !accel.occluded_at(lift, wi, 0.0, f32::INFINITY, time) {
        let w = power(SPHERE_PDF, b.pdf(wo, wi));
        light += f * environment(accel, wi, false) * (b_cos(b, wi) * w / SPHERE_PDF);
    }
    light
}

/// The cosine of `wi` with the BSDF's normal.
fn b_cos(b: &Bsdf, wi: Vec3A) -> f32 {
    b.normal().dot(wi).max(0.0)
}

#[cfg(test)]
mod tests;
