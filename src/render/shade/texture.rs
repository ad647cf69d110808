//! Rayshade-style procedural textures (noise, turbulence, marble, bump, sky,
//! clouds). Pure f32 functions of their arguments with a fixed permutation
//! table, so every thread and every run sees the same values (DESIGN §4).

use glam::{Vec3, Vec3A};

/// Ken Perlin's reference permutation of 0..=255 ("Improving Noise", 2002);
/// fixed so textures never depend on a random generator or seed.
const PERM: [u8; 256] = [
    151, 160, 137, 91, 90, 15, 131, 13, 201, 95, 96, 53, 194, 233, 7, 225, 140, 36, 103, 30, 69,
    142, 8, 99, 37, 240, 21, 10, 23, 190, 6, 148, 247, 120, 234, 75, 0, 26, 197, 62, 94, 252, 219,
    203, 117, 35, 11, 32, 57, 177, 33, 88, 237, 149, 56, 87, 174, 20, 125, 136, 171, 168, 68, 175,
    74, 165, 71, 134, 139, 48, 27, 166, 77, 146, 158, 231, 83, 111, 229, 122, 60, 211, 133, 230,
    220, 105, 92, 41, 55, 46, 245, 40, 244, 102, 143, 54, 65, 25, 63, 161, 1, 216, 80, 73, 209, 76,
    132, 187, 208, 89, 18, 169, 200, 196, 135, 130, 116, 188, 159, 86, 164, 100, 109, 198, 173,
    186, 3, 64, 52, 217, 226, 250, 124, 123, 5, 202, 38, 147, 118, 126, 255, 82, 85, 212, 207, 206,
    59, 227, 47, 16, 58, 17, 182, 189, 28, 42, 223, 183, 170, 213, 119, 248, 152, 2, 44, 154, 163,
    70, 221, 153, 101, 155, 167, 43, 172, 9, 129, 22, 39, 253, 19, 98, 108, 110, 79, 113, 224, 232,
    178, 185, 112, 104, 218, 246, 97, 228, 251, 34, 242, 193, 238, 210, 144, 12, 191, 179, 162,
    241, 81, 51, 145, 235, 249, 14, 239, 107, 49, 192, 214, 31, 181, 199, 106, 157, 184, 84, 204,
    176, 115, 121, 50, 45, 127, 4, 150, 254, 138, 236, 205, 93, 222, 114, 67, 29, 24, 72, 243, 141,
    128, 195, 78, 66, 215, 61, 156, 180,
];

/// The permutation repeated twice, so `P[P[x] + y]` never needs a wrap.
const P: [u8; 512] = {
    let mut p = [0u8; 512];
    let mut i = 0;
    while i < 512 {
        p[i] = PERM[i % 256];
        i += 1;
    }
    p
};

/// Most octaves `turbulence` sums: beyond this the amplitude (2^-32) is
/// below f32 resolution of the sum, and it bounds the work for huge inputs.
pub const MAX_OCTAVES: u32 = 32;

/// Octaves of turbulence in `marble` (vein detail).
const MARBLE_OCTAVES: u32 = 6;
/// Vein frequency along x in `marble`.
const MARBLE_FREQUENCY: f32 = 3.0;
/// How strongly turbulence distorts the marble veins.
const MARBLE_DISTORTION: f32 = 5.0;
/// Octaves of turbulence in `cloud`.
const CLOUD_OCTAVES: u32 = 5;
/// Turbulence below this is clear sky in `cloud`.
const CLOUD_LOW: f32 = 0.3;
/// Turbulence above this is full cloud in `cloud`.
const CLOUD_HIGH: f32 = 0.8;
/// Finite-difference step of `bump`'s noise gradient.
const BUMP_STEP: f32 = 1.0e-3;
/// Scale of the cloud deck seen by `sky` (larger: smaller clouds).
const SKY_CLOUD_SCALE: f32 = 1.5;
/// Strongest pull toward white in `sky`: the clouds stay faint.
const SKY_CLOUD_STRENGTH: f32 = 0.5;

/// Perlin's quintic fade 6t⁵ − 15t⁴ + 10t³: continuous second derivative.
#[inline]
fn fade(t: f32) -> f32 {
    t * t * t * (t * (t * 6.0 - 15.0) + 10.0)
}

#[inline]
fn lerp(t: f32, a: f32, b: f32) -> f32 {
    a + t * (b - a)
}

/// Dot product of (x, y, z) with one of Perlin's 12 edge gradients picked by `hash`.
#[inline]
fn grad(hash: u8, x: f32, y: f32, z: f32) -> f32 {
    let h = hash & 15;
    let u = if h < 8 { x } else { y };
    let v = if h < 4 {
        y
    } else if h == 12 || h == 14 {
        x
    } else {
        z
    };
    (if h & 1 == 0 { u } else { -u }) + (if h & 2 == 0 { v } else { -v })
}

/// Hermite smoothstep from 0 at `lo` to 1 at `hi`.
#[inline]
fn smoothstep(lo: f32, hi: f32, x: f32) -> f32 {
    let t = ((x - lo) / (hi - lo)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

/// Perlin improved noise in [-1, 1] (clamped; 0 for non-finite input), period 256, fixed table.
pub fn noise(p: Vec3A) -> f32 {
    if !p.is_finite() {
        return 0.0;
    }
    let f = p.floor();
    // Wrapping into the 256-lattice; `as i32` saturates, so huge inputs stay defined.
    let xi = (f.x as i32 & 255) as usize;
    let yi = (f.y as i32 & 255) as usize;
    let zi = (f.z as i32 & 255) as usize;
    let (x, y, z) = (p.x - f.x, p.y - f.y, p.z - f.z);
    let (u, v, w) = (fade(x), fade(y), fade(z));

    let a = P[xi] as usize + yi;
    let aa = P[a] as usize + zi;
    let ab = P[a + 1] as usize + zi;
    let b = P[xi + 1] as usize + yi;
    let ba = P[b] as usize + zi;
    let bb = P[b + 1] as usize + zi;

    let n = lerp(
        w,
        lerp(
            v,
            lerp(u, grad(P[aa], x, y, z), grad(P[ba], x - 1.0, y, z)),
            lerp(
                u,
                grad(P[ab], x, y - 1.0, z),
                grad(P[bb], x - 1.0, y - 1.0, z),
            ),
        ),
        lerp(
            v,
            lerp(
                u,
                grad(P[aa + 1], x, y, z - 1.0),
                grad(P[ba + 1], x - 1.0, y, z - 1.0),
            ),
            lerp(
                u,
                grad(P[ab + 1], x, y - 1.0, z - 1.0),
                grad(P[bb + 1], x - 1.0, y - 1.0, z - 1.0),
            ),
        ),
    );
    // The theoretical extremes of 3-D gradient noise slightly exceed 1;
    // clamping keeps the documented range and stays continuous.
    n.clamp(-1.0, 1.0)
}

/// Sum of |noise| over `octaves` (at most `MAX_OCTAVES`) doubling frequencies with halving amplitude; in [0, 2).
pub fn turbulence(p: Vec3A, octaves: u32) -> f32 {
    let mut sum = 0.0;
    let mut freq = 1.0;
    let mut amp = 1.0;
    for _ in 0..octaves.min(MAX_OCTAVES) {
        sum += amp * noise(p * freq).abs();
        freq *= 2.0;
        amp *= 0.5;
    }
    sum
}

/// Marble in [0, 1]: 0.5 + 0.5·sin(3·p.x + 5·turbulence(p, 6)), veins across x distorted by turbulence.
pub fn marble(p: Vec3A) -> f32 {
    let phase = p.x * MARBLE_FREQUENCY + MARBLE_DISTORTION * turbulence(p, MARBLE_OCTAVES);
    if !phase.is_finite() {
        return 0.5;
    }
    (0.5 + 0.5 * phase.sin()).clamp(0.0, 1.0)
}

/// Noise gradient by central differences (6 evaluations).
fn noise_gradient(p: Vec3A) -> Vec3A {
    let h = BUMP_STEP;
    let d = |e: Vec3A| noise(p + e * h) - noise(p - e * h);
    Vec3A::new(d(Vec3A::X), d(Vec3A::Y), d(Vec3A::Z)) / (2.0 * h)
}

/// Unit normal `n` tilted against the tangential noise gradient at `p` by strength `scale` (0: `n` itself; zero/non-finite `n`: zero).
pub fn bump(p: Vec3A, n: Vec3A, scale: f32) -> Vec3A {
    let Some(n) = n.try_normalize() else {
        return Vec3A::ZERO;
    };
    if scale == 0.0 {
        return n;
    }
    let g = noise_gradient(p);
    // Only the tangential part tilts the normal; the normal part would
    // merely rescale it.
    let tangential = g - n * g.dot(n);
    (n - tangential * scale).try_normalize().unwrap_or(n)
}

/// Sky colour for a view direction: horizon→zenith by the normalised dir.y, plus faint clouds on a deck above, faded out toward the horizon.
pub fn sky(dir: Vec3A, zenith: Vec3, horizon: Vec3) -> Vec3 {
    let Some(d) = dir.try_normalize() else {
        return horizon;
    };
    let up = d.y.max(0.0);
    let base = horizon.lerp(zenith, up);
    if up <= 0.0 {
        return base;
    }
    // Where the ray meets the plane y = 1; the 0.5 keeps the slice off the
    // lattice planes where noise vanishes.
    let deck = Vec3A::new(d.x / up, 0.5, d.z / up) * SKY_CLOUD_SCALE;
    // Near the horizon the deck point runs off to infinity and the clouds
    // would alias; fade them out there.
    let amount = SKY_CLOUD_STRENGTH * cloud(deck) * smoothstep(0.0, 0.3, up);
    base.lerp(Vec3::ONE, amount)
}

/// Cloud density in [0, 1]: smoothstep of turbulence(p, 5) between 0.3 (clear) and 0.8 (dense).
pub fn cloud(p: Vec3A) -> f32 {
    smoothstep(CLOUD_LOW, CLOUD_HIGH, turbulence(p, CLOUD_OCTAVES))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn table_is_a_permutation() {
        let mut seen = [false; 256];
        for &v in &PERM {
            assert!(!seen[v as usize]);
            seen[v as usize] = true;
        }
    }
}
