//! The denoiser (issue 57): an edge-avoiding à-trous wavelet filter
//! (Dammertz et al. 2010) guided by the frame's own layers, with the
//! luminance edge-stopping of SVGF (Schied et al. 2017) driven by each
//! pixel's sample variance. The light is filtered, not the colour: each
//! pixel's colour is divided by its surface's albedo before and
//! multiplied after, so textures stay sharp while the light's noise is
//! smoothed. Three passes of a 5×5 B3-spline kernel, its taps 1, 2 and 4
//! pixels apart, each tap weighted by how alike the two pixels'
//! normals, depths and light are (the light's likeness measured against
//! its noise). Every pixel of a pass is a function of the last pass's
//! image alone, summed in a fixed order: the same bytes for any thread
//! count.

use rayon::prelude::*;

use glam::Vec3;

use super::output::Image;
use super::sample;

/// The B3 spline's taps.
const TAPS: [f32; 5] = [1.0 / 16.0, 1.0 / 4.0, 3.0 / 8.0, 1.0 / 4.0, 1.0 / 16.0];

/// Passes of the filter: a footprint of 2 · (2 + 4 + 8) + 1 = 29 pixels. Tuned
/// with the two constants below on the forest and the gallery at 4 spp
/// against 4096-spp references (docs/performance.md, "The denoiser"):
/// five passes, σ_l 4 and σ_n 128 (SVGF's) gave 1.21× and 1.28× OIDN's
/// error, these 1.10× and 1.18×.
const PASSES: u32 = 3;

/// How many standard deviations of its noise two pixels' light may
/// differ by and still be averaged (SVGF's σ_l).
const SIGMA_LIGHT: f32 = 3.0;

/// The exponent on the cosine between two normals (SVGF's σ_n).
const SIGMA_NORMAL: i32 = 32;

/// Depth tolerance in units of the depth's change along the tap's
/// offset (SVGF's σ_z).
const SIGMA_DEPTH: f32 = 1.0;

/// An albedo below this is not divided by (a black surface's light is
/// its colour).
const LEAST_ALBEDO: f32 = 1e-3;

/// What each pixel's weights are computed from: the frame's layers and
/// what is derived from them.
struct Guide<'a> {
    /// Whether the centre ray met a surface.
    hit: Vec<bool>,
    depth: &'a [f32],
    normal: &'a [[f32; 3]],
    /// The depth's change per pixel across and down (0 where unknown).
    slope: Vec<[f32; 2]>,
    /// The albedo divided by, per channel (1 where too dark).
    albedo: Vec<[f32; 3]>,
}

/// Replaces the frame's colour by its denoised colour, keeping the colour
/// as rendered in `img.noisy`. Needs the layers (depth, normal, albedo)
/// and the per-pixel variance the renderer fills.
pub fn denoise(img: &mut Image) {
    if img.is_empty() {
        return;
    }
    let (w, h) = (img.width as usize, img.height as usize);
    let guide = Guide::of(img, w, h);
    let mut light: Vec<[f32; 3]> = img
        .rgba
        .iter()
        .zip(&guide.albedo)
        .map(|(c, a)| [c[0] / a[0], c[1] / a[1], c[2] / a[2]])
        .collect();
    let mut variance = light_variance(img, &guide, &light, w, h);
    for pass in 0..PASSES {
        (light, variance) = filter_pass(&guide, (&light, &variance), (w, h), 1 << pass);
    }
    // The light times the albedo again; the coverage (alpha) as rendered.
    let denoised = img
        .rgba
        .iter()
        .zip(&light)
        .zip(&guide.albedo)
        .map(|((c, l), a)| [l[0] * a[0], l[1] * a[1], l[2] * a[2], c[3]])
        .collect();
    img.noisy = Some(std::mem::replace(&mut img.rgba, denoised));
}

impl<'a> Guide<'a> {
    fn of(img: &'a Image, w: usize, h: usize) -> Guide<'a> {
        let hit: Vec<bool> = img.depth.iter().map(|d| d.is_finite()).collect();
        let at = |x: usize, y: usize| hit[y * w + x].then(|| img.depth[y * w + x]);
        // Central differences where both neighbours are surfaces, else
        // one-sided: the depth's slope along x and y.
        let slope_along = |x: usize, y: usize, dx: usize, dy: usize| -> f32 {
            let here = at(x, y).unwrap_or(0.0);
            let before = (x >= dx && y >= dy).then(|| at(x - dx, y - dy)).flatten();
            let after = (x + dx < w && y + dy < h)
                .then(|| at(x + dx, y + dy))
                .flatten();
            match (before, after) {
                (Some(b), Some(a)) => 0.5 * (a - b).abs(),
                (Some(b), None) => (here - b).abs(),
                (None, Some(a)) => (a - here).abs(),
                (None, None) => 0.0,
            }
        };
        let slope = (0..w * h)
            .into_par_iter()
            .map(|i| {
                let (x, y) = (i % w, i / w);
                if hit[i] {
                    [slope_along(x, y, 1, 0), slope_along(x, y, 0, 1)]
                } else {
                    [0.0; 2]
                }
            })
            .collect();
        let albedo = img
            .albedo
            .iter()
            .zip(&hit)
            .map(|(a, &hit)| {
                a.map(|v| {
                    if hit && v.is_finite() && v > LEAST_ALBEDO {
                        v
                    } else {
                        1.0
                    }
                })
            })
            .collect();
        Guide {
            hit,
            depth: &img.depth,
            normal: &img.normal,
            slope,
            albedo,
        }
    }

    /// How much pixel `q` (at `offset` pixels from `p`) counts for `p`'s
    /// light, its light's distance to `p`'s measured in `p`'s noise
    /// `sigma`: 0 across a surface's edge (a surface and the sky, normals
    /// apart, depths apart beyond the surface's slope).
    fn weight(&self, p: usize, q: usize, offset: (f32, f32), light: f32, sigma: f32) -> f32 {
        if self.hit[p] != self.hit[q] {
            return 0.0;
        }
        // The light's and the depth's stopping in one exponential.
        let mut exponent = light / sigma;
        let mut w = 1.0;
        if self.hit[p] {
            let (np, nq) = (self.normal[p], self.normal[q]);
            let cos = np[0] * nq[0] + np[1] * nq[1] + np[2] * nq[2];
            if cos <= 0.0 {
                return 0.0;
            }
            w = cos.powi(SIGMA_NORMAL);
            let s = self.slope[p];
            let expected = s[0] * offset.0.abs() + s[1] * offset.1.abs();
            let gap = (self.depth[p] - self.depth[q]).abs();
            exponent += gap / (SIGMA_DEPTH * expected + 1e-3 * self.depth[p]);
        }
        w * exp_neg(exponent)
    }
}

/// e^(−x) for x ≥ 0 (0 past 87, and for NaN), in plain f32 arithmetic:
/// the C library's `expf` picks its code by the CPU (FMA or not) at run
/// time and need not give the same bits everywhere; this does (each
/// operation IEEE-rounded, none fused). 2^(−x·log₂e) as 2^(−n) (the
/// exponent's bits) times 2^(−f), f in [0, 1), by the degree-8 Taylor
/// polynomial of e^(−f·ln 2): relative error under 10⁻⁵ (most of it the
/// rounding of x·log₂e).
fn exp_neg(x: f32) -> f32 {
    if x.is_nan() || x > 87.0 {
        return 0.0;
    }
    let t = x.max(0.0) * std::f32::consts::LOG2_E;
    let n = t as u32; // floor, t ≥ 0
                      // g in [0, ln 2); then Horner's form of Σ (−g)^k / k!, k ≤ 8.
    let g = (t - n as f32) * std::f32::consts::LN_2;
    let p = 1.0 / 5_040.0 - g * (1.0 / 40_320.0);
    let p = 1.0 / 720.0 - g * p;
    let p = 1.0 / 120.0 - g * p;
    let p = 1.0 / 24.0 - g * p;
    let p = 1.0 / 6.0 - g * p;
    let p = 0.5 - g * p;
    let p = 1.0 - g * p;
    let p = 1.0 - g * p;
    // 2^(−n): n ≤ 126 here, a normal number.
    p * f32::from_bits((127 - n) << 23)
}

/// Luminance of a linear colour (Rec. 709).
fn luminance(c: [f32; 3]) -> f32 {
    sample::luminance(Vec3::from(c))
}

/// The variance of each pixel's light: its samples' (divided by its
/// albedo's luminance, squared), or where a frame has one sample a
/// pixel, the spread of the light over its 5×5 neighbours on its own
/// surface.
fn light_variance(img: &Image, guide: &Guide, light: &[[f32; 3]], w: usize, h: usize) -> Vec<f32> {
    let sampled = img.variance.iter().any(|&v| v > 0.0);
    (0..w * h)
        .into_par_iter()
        .map(|i| {
            if sampled {
                let a = luminance(guide.albedo[i]).max(LEAST_ALBEDO);
                return img.variance[i] / (a * a);
            }
            let (x, y) = ((i % w) as isize, (i / w) as isize);
            let (mut m1, mut m2, mut n) = (0.0f32, 0.0f32, 0.0f32);
            for dy in -2..=2isize {
                for dx in -2..=2isize {
                    let (qx, qy) = (x + dx, y + dy);
                    if qx < 0 || qy < 0 || qx >= w as isize || qy >= h as isize {
                        continue;
                    }
                    let q = qy as usize * w + qx as usize;
                    if guide.hit[q] != guide.hit[i] {
                        continue;
                    }
                    let l = luminance(light[q]);
                    (m1, m2, n) = (m1 + l, m2 + l * l, n + 1.0);
                }
            }
            let mean = m1 / n;
            (m2 / n - mean * mean).max(0.0)
        })
        .collect()
}

/// One pass of the filter with its taps `step` pixels apart: each
/// pixel's light and its variance (weights squared) from the last pass's.
fn filter_pass(
    guide: &Guide,
    (light, variance): (&[[f32; 3]], &[f32]),
    (w, h): (usize, usize),
    step: isize,
) -> (Vec<[f32; 3]>, Vec<f32>) {
    // The variance seen through a 3×3 Gaussian: one pixel's estimate is
    // itself noisy.
    let blurred: Vec<f32> = (0..w * h)
        .into_par_iter()
        .map(|i| {
            let (x, y) = ((i % w) as isize, (i / w) as isize);
            let (mut sum, mut wsum) = (0.0f32, 0.0f32);
            for dy in -1..=1isize {
                for dx in -1..=1isize {
                    let (qx, qy) = (x + dx, y + dy);
                    if qx < 0 || qy < 0 || qx >= w as isize || qy >= h as isize {
                        continue;
                    }
                    let k =
                        [0.25, 0.5, 0.25][(dx + 1) as usize] * [0.25, 0.5, 0.25][(dy + 1) as usize];
                    sum += k * variance[qy as usize * w + qx as usize];
                    wsum += k;
                }
            }
            sum / wsum
        })
        .collect();
    let lum: Vec<f32> = light.par_iter().map(|&c| luminance(c)).collect();
    (0..w * h)
        .into_par_iter()
        .map(|p| {
            let (x, y) = ((p % w) as isize, (p / w) as isize);
            let lp = lum[p];
            let sigma = SIGMA_LIGHT * blurred[p].sqrt() + 1e-6;
            let (mut sum, mut wsum, mut vsum) = ([0.0f32; 3], 0.0f32, 0.0f32);
            for (j, ky) in TAPS.iter().enumerate() {
                for (i, kx) in TAPS.iter().enumerate() {
                    let (dx, dy) = ((i as isize - 2) * step, (j as isize - 2) * step);
                    let (qx, qy) = (x + dx, y + dy);
                    if qx < 0 || qy < 0 || qx >= w as isize || qy >= h as isize {
                        continue;
                    }
                    let q = qy as usize * w + qx as usize;
                    let similar = if q == p {
                        1.0
                    } else {
                        let gap = (lp - lum[q]).abs();
                        guide.weight(p, q, (dx as f32, dy as f32), gap, sigma)
                    };
                    let k = kx * ky * similar;
                    for c in 0..3 {
                        sum[c] += k * light[q][c];
                    }
                    wsum += k;
                    vsum += k * k * variance[q];
                }
            }
            (sum.map(|s| s / wsum), vsum / (wsum * wsum))
        })
        .unzip()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::random;

    /// A `w`×`h` frame of one surface facing the camera at depth 5, its
    /// albedo `albedo(x, y)`, lit by `light` with noise of standard
    /// deviation `noise` (a hash of the pixel), the samples' variance
    /// said.
    fn frame(w: u32, h: u32, albedo: impl Fn(u32, u32) -> f32, light: f32, noise: f32) -> Image {
        let mut img = Image::new(w, h);
        for y in 0..h {
            for x in 0..w {
                let i = (y * w + x) as usize;
                let u = random::unit(random::key(0, random::Stream::Pixel, i as u64, 0), 0) as f32;
                // Uniform noise of that deviation: ±√3·σ.
                let l = light + noise * 3f32.sqrt() * (2.0 * u - 1.0);
                let a = albedo(x, y);
                img.rgba[i] = [a * l, a * l, a * l, 1.0];
                img.depth[i] = 5.0;
                img.normal[i] = [0.0, 0.0, 1.0];
                img.albedo[i] = [a; 3];
                img.variance[i] = a * a * noise * noise;
            }
        }
        img
    }

    fn rmse(img: &Image, want: impl Fn(usize) -> f32) -> f32 {
        let sum: f32 = img
            .rgba
            .iter()
            .enumerate()
            .map(|(i, c)| (c[0] - want(i)).powi(2))
            .sum();
        (sum / img.len() as f32).sqrt()
    }

    /// A flat surface's noise falls fivefold, and a checkerboard albedo
    /// (a texture) comes through sharp: the light is filtered, not the
    /// colour. The colour as rendered is kept.
    #[test]
    fn noise_falls_and_texture_stays() {
        let checker = |x: u32, y: u32| {
            if (x / 4 + y / 4).is_multiple_of(2) {
                0.8
            } else {
                0.2
            }
        };
        let mut img = frame(64, 48, checker, 0.5, 0.2);
        let truth = |i: usize| checker(i as u32 % 64, i as u32 / 64) * 0.5;
        let before = rmse(&img, truth);
        let noisy = img.rgba.clone();
        denoise(&mut img);
        let after = rmse(&img, truth);
        assert!(after < before / 5.0, "RMSE {before} → {after}");
        assert_eq!(img.noisy.as_deref(), Some(&noisy[..]));
    }

    /// Two surfaces meeting at a crease (their normals apart) and a
    /// surface against the sky do not bleed into each other.
    #[test]
    fn edges_hold() {
        let mut img = frame(64, 48, |_, _| 0.5, 0.5, 0.1);
        for y in 0..48 {
            for x in 32..64 {
                let i = y * 64 + x;
                if y < 24 {
                    // A wall facing sideways, lit at 0.1.
                    img.normal[i] = [1.0, 0.0, 0.0];
                    img.rgba[i] = [0.05, 0.05, 0.05, 1.0];
                    img.variance[i] = 0.0;
                } else {
                    // The sky, 2.0 and noise-free.
                    img.depth[i] = f32::INFINITY;
                    img.normal[i] = [0.0; 3];
                    img.rgba[i] = [2.0, 2.0, 2.0, 1.0];
                    img.albedo[i] = [1.0; 3];
                    img.variance[i] = 0.0;
                }
            }
        }
        denoise(&mut img);
        for y in 0..48 {
            let (left, right) = (img.rgba[y * 64 + 31][0], img.rgba[y * 64 + 32][0]);
            assert!(
                (left - 0.25).abs() < 0.05,
                "row {y}: the lit surface at {left}"
            );
            let want = if y < 24 { 0.05 } else { 2.0 };
            assert!(
                (right - want).abs() < 1e-3,
                "row {y}: across the edge {right}"
            );
        }
    }

    /// `exp_neg` is e^(−x) to 10⁻⁵ (relative) over the range the
    /// weights use, and 0 past it.
    #[test]
    fn exp_neg_is_the_exponential() {
        let mut x = 0.0f32;
        while x < 87.0 {
            let want = (-f64::from(x)).exp();
            let got = f64::from(exp_neg(x));
            assert!(
                ((got - want) / want).abs() < 1e-5,
                "{x}: {got} against {want}"
            );
            x += 0.0137;
        }
        assert_eq!(exp_neg(88.0), 0.0);
        assert_eq!(exp_neg(f32::INFINITY), 0.0);
        assert_eq!(exp_neg(f32::NAN), 0.0);
        assert_eq!(exp_neg(0.0), 1.0);
    }

    /// The same bits on one thread and on four.
    #[test]
    fn the_same_bits_on_any_number_of_threads() {
        let run = |threads: usize| {
            let mut img = frame(97, 61, |x, _| 0.1 + (x % 7) as f32 / 10.0, 0.7, 0.3);
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            pool.install(|| denoise(&mut img));
            img.rgba
        };
        assert_eq!(run(1), run(4));
    }
}
