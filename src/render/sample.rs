//! Pixel sampling: stratified jitter whose offsets are a hash of
//! (frame, pixel, sample) (DESIGN §4), box or Gaussian weights; and the
//! one interface every integrator renders rows through ([`Integrate`]).

use glam::Vec3;

use super::accel::{Accel, Hit};
use super::camera::CameraRays;
use super::path::bsdf::Bsdf;
use super::settings::{Filter, Integrator, Settings};
use super::shade;
use crate::random::{self, Stream};

/// One pixel's values.
pub struct PixelOut {
    pub rgba: [f32; 4],
    pub depth: f32,
    pub normal: [f32; 3],
    pub object: u32,
    /// The albedo of the surface the centre ray meets (1 for none, and
    /// where the frame is not denoised).
    pub albedo: [f32; 3],
    /// The variance of the pixel's mean luminance (0 for one sample).
    pub variance: f32,
}

/// What the ray through a pixel's centre meets: the layers' surface.
#[derive(Clone, Copy)]
pub struct Centre {
    pub hit: Hit,
    /// Its BSDF's albedo, textures included, where the denoiser wants it
    /// (else 1: no shading on the way of a frame that is not denoised).
    pub albedo: Vec3,
}

impl Centre {
    /// The centre ray's `hit` of pixel (x, y), with its surface's albedo
    /// when `st` denoises.
    pub fn of(
        accel: &Accel,
        cam: &CameraRays,
        st: &Settings,
        hit: Hit,
        (x, y): (u32, u32),
    ) -> Centre {
        if !st.denoise {
            return Centre {
                hit,
                albedo: Vec3::ONE,
            };
        }
        let d = cam.dir(x as f32 + 0.5, y as f32 + 0.5);
        let albedo = shade::point(accel, &hit, cam.eye(), d).map_or(Vec3::ZERO, |pt| {
            let m = &accel.scene.materials[pt.material];
            Bsdf::new(m, pt.diffuse, pt.n, pt.outside).albedo()
        });
        Centre { hit, albedo }
    }
}

/// The offsets of `n` samples within the pixel of key `key` into `out`:
/// sample s in cell s of a near-square grid, jittered by the hash of
/// (frame, pixel, sample): [`random::unit`] of the pixel's key, slots 2s
/// and 2s + 1, whose [`random::slot_hash`]es are `slots`.
fn offsets(n: u32, key: u64, slots: &[u64], out: &mut Vec<(f32, f32)>) {
    out.clear();
    if n == 1 {
        out.push((0.5, 0.5));
        return;
    }
    let cols = (n as f32).sqrt().ceil() as u32;
    let rows = n.div_ceil(cols);
    out.extend((0..n).zip(slots.chunks_exact(2)).map(|(s, slot)| {
        let (cx, cy) = (s % cols, s / cols);
        let jx = random::unit_of(key, slot[0]) as f32;
        let jy = random::unit_of(key, slot[1]) as f32;
        (
            (cx as f32 + jx) / cols as f32,
            (cy as f32 + jy) / rows as f32,
        )
    }));
}

/// How a pixel's light is computed: each integrator is one type behind
/// this interface (as pbrt-v4's), holding its own buffers for a row, and
/// is named once in [`super::integrator::start`].
pub trait Integrate {
    /// Renders row `y`, every pixel into `put(x, pixel)`: its colour from
    /// `st.spp` samples at the offsets of [`Samples::at`], weighted by
    /// the filter ([`filtered`]), the other layers from the ray through
    /// the pixel centre ([`centre`]).
    fn row(
        &mut self,
        accel: &Accel,
        cam: &CameraRays,
        st: &Settings,
        y: u32,
        put: &mut dyn FnMut(u32, PixelOut),
    );
}

/// The offsets of a pixel's samples and their colours, kept from pixel
/// to pixel of a row so that a pixel allocates nothing.
#[derive(Default)]
pub struct Samples {
    pub offsets: Vec<(f32, f32)>,
    /// The [`random::slot_hash`]es of the offsets' slots (the same for
    /// every pixel).
    slots: Vec<u64>,
    /// Each sample's colour, and whether its ray met a surface.
    pub colours: Vec<(Vec3, bool)>,
}

impl Samples {
    /// Pixel (x, y)'s samples' offsets; returns the pixel's key. The
    /// path tracer's keys are the same every frame (as Cycles' default,
    /// unanimated seed): a region that does not change renders the same
    /// samples, so its noise, and what the denoiser leaves of it, stays
    /// still rather than flickering from frame to frame.
    pub fn at(&mut self, st: &Settings, x: u32, y: u32) -> u64 {
        let frame = match st.integrator {
            Integrator::Path => 0,
            Integrator::Whitted => st.frame,
        };
        let key = random::key(frame, Stream::Pixel, (u64::from(y) << 32) | u64::from(x), 0);
        let n = st.spp.max(1);
        if self.slots.len() != 2 * n as usize {
            self.slots = (0..2 * u64::from(n)).map(random::slot_hash).collect();
        }
        offsets(n, key, &self.slots, &mut self.offsets);
        key
    }

    /// Pixel (x, y) once `colours(key, samples)` has put its samples'
    /// colours in `samples.colours`: filtered, with the centre ray's
    /// layers.
    pub fn pixel(
        &mut self,
        accel: &Accel,
        cam: &CameraRays,
        st: &Settings,
        (x, y): (u32, u32),
        colours: impl FnOnce(u64, &mut Samples),
    ) -> PixelOut {
        let key = self.at(st, x, y);
        colours(key, self);
        let samples = self.offsets.iter().zip(&self.colours);
        filtered(
            st,
            samples.map(|(&o, &(c, hit))| (o, c, hit)),
            centre(accel, cam, st, x, y),
        )
    }
}

/// What the ray through pixel (x, y)'s centre meets, where the layers
/// are wanted.
pub fn centre(accel: &Accel, cam: &CameraRays, st: &Settings, x: u32, y: u32) -> Option<Centre> {
    if !st.layers {
        return None;
    }
    let hit = accel.cast(
        cam.eye(),
        cam.dir(x as f32 + 0.5, y as f32 + 0.5),
        0.0,
        f32::INFINITY,
    )?;
    Some(Centre::of(accel, cam, st, hit, (x, y)))
}

/// A pixel from its samples, as (offset in the pixel, colour, whether
/// the ray met a surface), weighted by the filter, and what the centre
/// ray met.
pub fn filtered(
    st: &Settings,
    samples: impl Iterator<Item = ((f32, f32), Vec3, bool)>,
    centre: Option<Centre>,
) -> PixelOut {
    let mut sum = [0.0f32; 4];
    let mut wsum = 0.0f32;
    // The samples' luminance moments, for the variance of their mean.
    let (mut l1, mut l2, mut n) = (0.0f32, 0.0f32, 0u32);
    for ((ox, oy), c, hit) in samples {
        let l = luminance(c);
        (l1, l2, n) = (l1 + l, l2 + l * l, n + 1);
        let w = match st.filter {
            Filter::Box => 1.0,
            Filter::Gaussian => {
                let (dx, dy) = (ox - 0.5, oy - 0.5);
                (-(dx * dx + dy * dy) / (2.0 * 0.25)).exp()
            }
        };
        sum[0] += w * c.x;
        sum[1] += w * c.y;
        sum[2] += w * c.z;
        sum[3] += w * f32::from(u8::from(hit));
        wsum += w;
    }
    let variance = if n > 1 {
        let mean = l1 / n as f32;
        ((l2 / n as f32 - mean * mean) / (n - 1) as f32).max(0.0)
    } else {
        0.0
    };
    PixelOut {
        rgba: sum.map(|v| v / wsum),
        depth: centre.map_or(f32::INFINITY, |c| c.hit.t),
        normal: centre.map_or([0.0; 3], |c| c.hit.normal.to_array()),
        object: centre.map_or(u32::MAX, |c| c.hit.object),
        albedo: centre.map_or([1.0; 3], |c| c.albedo.to_array()),
        variance,
    }
}

/// Rec. 709 luminance of a linear colour.
pub fn luminance(c: Vec3) -> f32 {
    0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z
}
