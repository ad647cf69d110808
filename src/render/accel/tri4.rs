//! Four triangles tested against one ray at once, as Embree's
//! `Triangle4`: a BVH leaf of up to four triangles costs one test instead
//! of four. The test is the watertight one of Woop, Benthin and Wald
//! (JCGT 2013): vertices are moved into a frame where the ray runs along
//! +z, and the 2-D edge functions decide, so a ray through a shared edge
//! or vertex of a closed mesh always finds one of its triangles.

use std::sync::OnceLock;

use glam::{Vec3, Vec3A, Vec4};

use super::packet::{Bits, RayPacket};
use super::ray::Ray;
use crate::render::simd::wide::{Mask, Wide};
use crate::render::simd::{Lanes, LANES};

/// Up to four triangles, one `Vec4` per vertex coordinate (144 bytes:
/// their indices are kept apart, as only a hit needs them). Unused lanes
/// hold NaN, which fails every comparison.
#[derive(Clone, Copy)]
pub struct Tri4 {
    v: [[Vec4; 3]; 3],
}

impl Tri4 {
    /// Packs up to four triangles. Their owner orders them by index, so
    /// that the lowest lane among equally near hits is the lowest index.
    pub fn pack(tris: &[[Vec3; 3]]) -> Tri4 {
        let mut p = Tri4 {
            v: [[Vec4::NAN; 3]; 3],
        };
        for (lane, v) in tris.iter().enumerate().take(4) {
            for (corner, point) in v.iter().enumerate() {
                for k in 0..3 {
                    p.v[corner][k][lane] = point[k];
                }
            }
        }
        p
    }

    /// The nearest lane hit with t in (ray.tmin, tmax): `(t, lane)`; of
    /// equally near ones, the lowest lane.
    #[inline(always)]
    pub fn intersect(&self, ray: &Ray, tmax: f32) -> Option<(f32, usize)> {
        let (mask, t) = self.lanes(ray, tmax);
        nearest(mask, &t, tmax)
    }

    /// Whether any lane is hit with t in (ray.tmin, tmax).
    #[inline(always)]
    pub fn hits(&self, ray: &Ray, tmax: f32) -> bool {
        self.lanes(ray, tmax).0 != 0
    }

    /// The lanes hit with t in (ray.tmin, tmax), and each lane's t.
    #[inline(always)]
    fn lanes(&self, ray: &Ray, tmax: f32) -> (u32, [f32; 4]) {
        let s = Vec4::splat;
        // (`min`: the axes are below 3 already; it tells the compiler so,
        // and spares a bounds check per corner.)
        let [kx, ky, kz] = ray.axes.map(|k| k.min(2));
        let (sx, sy, sz) = (s(ray.shear.x), s(ray.shear.y), s(ray.shear.z));
        let o = ray.permuted_origin;
        let (ox, oy, oz) = (s(o.x), s(o.y), s(o.z));
        // Each corner relative to the origin, sheared; read straight from
        // the pack by axis (a local array indexed by axis went through
        // the stack).
        let corner = |p: &[Vec4; 3]| {
            let z = p[kz] - oz;
            (p[kx] - ox - sx * z, p[ky] - oy - sy * z, z)
        };
        let ((ax, ay, az), (bx, by, bz), (cx, cy, cz)) =
            (corner(&self.v[0]), corner(&self.v[1]), corner(&self.v[2]));
        let mut u = cx * by - cy * bx;
        let mut w = ax * cy - ay * cx;
        let mut x = bx * ay - by * ax;
        let zero = Vec4::ZERO;
        let mut exact = (u.cmpeq(zero) | w.cmpeq(zero) | x.cmpeq(zero)).bitmask();
        // Exactly on an edge in f32: decide it in f64 so both neighbours
        // agree (rare, so lane by lane).
        while exact != 0 {
            let l = exact.trailing_zeros() as usize;
            exact &= exact - 1;
            u[l] = edge_f64(cx[l], by[l], cy[l], bx[l]);
            w[l] = edge_f64(ax[l], cy[l], ay[l], cx[l]);
            x[l] = edge_f64(bx[l], ay[l], by[l], ax[l]);
        }
        let negative = u.cmplt(zero) | w.cmplt(zero) | x.cmplt(zero);
        let positive = u.cmpgt(zero) | w.cmpgt(zero) | x.cmpgt(zero);
        let det = u + w + x;
        let inside = !(negative & positive) & det.cmpne(zero);
        // Most packs a walk tests are missed: skip the division for them.
        if !inside.any() {
            return (0, [0.0; 4]);
        }
        let t = (u * (sz * az) + w * (sz * bz) + x * (sz * cz)) / det;
        let hit = inside & t.cmpgt(s(ray.tmin)) & t.cmplt(s(tmax));
        // An array, not the `Vec4`: indexing a `Vec4` by a run-time lane
        // compiles to a jump table.
        (hit.bitmask(), t.to_array())
    }

    /// Of the rays `rays` of packet `p`, those that hit the pack's
    /// triangle `j` with t in (tmin, tfar), and each ray's t: lane by
    /// lane the operations of [`Self::lanes`] (whose lanes are
    /// triangles, where these are rays), in the lane form `W`.
    #[inline(always)]
    pub fn packet_lanes<W: Wide>(
        &self,
        j: usize,
        p: &RayPacket,
        rays: u32,
        tfar: &Lanes,
    ) -> (u32, Lanes) {
        let [kx, ky, kz] = p.axes.map(|k| k.min(2));
        let vertex = |c: usize| {
            let v = &self.v[c];
            [
                v[kx].to_array()[j],
                v[ky].to_array()[j],
                v[kz].to_array()[j],
            ]
        };
        let (a, b, c) = (vertex(0), vertex(1), vertex(2));
        let [sx, sy, sz] = p.shear.each_ref().map(W::load);
        let [ox, oy, oz] = p.permuted_origin.each_ref().map(W::load);
        let (shear, origin) = ([sx, sy], [ox, oy, oz]);
        let ((ax, ay, az), (bx, by, bz), (cx, cy, cz)) = (
            corner(a, shear, origin),
            corner(b, shear, origin),
            corner(c, shear, origin),
        );
        let mut u = cx.mul(by).sub(cy.mul(bx));
        let mut w = ax.mul(cy).sub(ay.mul(cx));
        let mut x = bx.mul(ay).sub(by.mul(ax));
        let zero = W::splat(0.0);
        let exact = rays & u.eq(zero).or(w.eq(zero)).or(x.eq(zero)).bits();
        if exact != 0 {
            // Exactly on an edge in f32: decided in f64, as the single test.
            // Stored one by one: `.map(W::store)` was left out of line
            // with its AVX stores (see `super::wide`).
            let [axs, ays, bxs, bys, cxs, cys] = [
                ax.store(),
                ay.store(),
                bx.store(),
                by.store(),
                cx.store(),
                cy.store(),
            ];
            let (mut us, mut ws, mut xs) = (u.store(), w.store(), x.store());
            for i in Bits(exact) {
                us[i] = edge_f64(cxs[i], bys[i], cys[i], bxs[i]);
                ws[i] = edge_f64(axs[i], cys[i], ays[i], cxs[i]);
                xs[i] = edge_f64(bxs[i], ays[i], bys[i], axs[i]);
            }
            (u, w, x) = (W::load(&us), W::load(&ws), W::load(&xs));
        }
        let negative = u.lt(zero).or(w.lt(zero)).or(x.lt(zero));
        let positive = u.gt(zero).or(w.gt(zero)).or(x.gt(zero));
        let det = u.add(w).add(x);
        let inside = negative.and(positive).andnot(det.ne(zero));
        // Most triangles a walk tests are missed: skip the divisions.
        if rays & inside.bits() == 0 {
            return (0, [0.0; LANES]);
        }
        let t = u
            .mul(sz.mul(az))
            .add(w.mul(sz.mul(bz)))
            .add(x.mul(sz.mul(cz)))
            .div(det);
        let hit = inside.and(t.gt(W::load(&p.tmin))).and(t.lt(W::load(tfar)));
        (rays & hit.bits(), t.store())
    }

    /// The triangles of the pack (a pack of fewer than four holds NaN in
    /// the rest).
    #[inline(always)]
    pub fn count(&self) -> usize {
        4 - self.v[0][0].is_nan_mask().bitmask().count_ones() as usize
    }
}

/// A triangle corner `q` relative to the packet's origin, sheared (as
/// [`Tri4::packet_lanes`] wants it; a function, not a closure: see
/// [`crate::render::simd::wide`]).
#[inline(always)]
fn corner<W: Wide>(q: [f32; 3], [sx, sy]: [W; 2], [ox, oy, oz]: [W; 3]) -> (W, W, W) {
    let z = W::splat(q[2]).sub(oz);
    (
        W::splat(q[0]).sub(ox).sub(sx.mul(z)),
        W::splat(q[1]).sub(oy).sub(sy.mul(z)),
        z,
    )
}

/// The edge function `p·q − r·s` in f64, rounded once: for a lane whose
/// f32 edge function is exactly 0 (every path decides such lanes alike).
#[inline]
fn edge_f64(p: f32, q: f32, r: f32, s: f32) -> f32 {
    (p as f64 * q as f64 - r as f64 * s as f64) as f32
}

/// Of the lanes of `mask` (of `t`, four), the nearest under `bound` and
/// its lane; of equally near ones, the lowest lane.
#[inline(always)]
fn nearest(mut mask: u32, t: &[f32], bound: f32) -> Option<(f32, usize)> {
    let mut best: Option<(f32, usize)> = None;
    while mask != 0 {
        let lane = mask.trailing_zeros() as usize;
        mask &= mask - 1;
        // Lanes come lowest first: only a nearer one replaces.
        if t[lane] < best.map_or(bound, |(bt, _)| bt) {
            best = Some((t[lane], lane));
        }
    }
    best
}

/// Which instructions the tests run, chosen at run time: the baseline
/// (SSE2 on x86-64: a pack of four triangles at a time, packets as four
/// SSE registers), AVX (two packs at once, packets as two registers) or
/// AVX-512 (the same single-ray tests, packets in one register). Every
/// lane of each computes the same IEEE operations in the same order (no
/// fused multiply-add), so they give the same bits (DESIGN §4).
/// Narrowest first.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Simd {
    Baseline,
    Avx,
    Avx512,
}

/// The environment variable that caps the path renders take (a
/// [`Simd::name`]): a farm checks that a wide machine gives an old one's
/// bytes by rendering there with `baseline`.
pub const SIMD_VAR: &str = "LMFILM_SIMD";

impl Simd {
    /// Every path, narrowest first.
    pub const ALL: [Simd; 3] = [Simd::Baseline, Simd::Avx, Simd::Avx512];

    /// The path renders take: the widest this machine has, at most
    /// [`SIMD_VAR`]'s (read once; empty or a value that is no name is
    /// ignored here, and the command line refuses the latter).
    pub fn detect() -> Simd {
        static CHOSEN: OnceLock<Simd> = OnceLock::new();
        *CHOSEN.get_or_init(|| {
            let widest = Simd::available().into_iter().max();
            Simd::capped(
                widest.unwrap_or(Simd::Baseline),
                std::env::var(SIMD_VAR).ok().as_deref(),
            )
        })
    }

    /// `widest`, or the path named `cap` where that is narrower.
    fn capped(widest: Simd, cap: Option<&str>) -> Simd {
        cap.and_then(Simd::parse)
            .map_or(widest, |cap| cap.min(widest))
    }

    /// The path named `baseline`, `avx` or `avx512`.
    pub fn parse(name: &str) -> Option<Simd> {
        Simd::ALL.into_iter().find(|s| s.name() == name)
    }

    /// The path's name, as [`SIMD_VAR`] takes it.
    pub fn name(self) -> &'static str {
        match self {
            Simd::Baseline => "baseline",
            Simd::Avx => "avx",
            Simd::Avx512 => "avx512",
        }
    }

    /// Every one this machine has, narrowest first (tests compare them).
    pub fn available() -> Vec<Simd> {
        let mut all = vec![Simd::Baseline];
        #[cfg(target_arch = "x86_64")]
        {
            if std::arch::is_x86_feature_detected!("avx") {
                all.push(Simd::Avx);
            }
            if std::arch::is_x86_feature_detected!("avx512f") {
                all.push(Simd::Avx512);
            }
        }
        all
    }
}

/// The nearest hit of each of `packs` under the bound, in pack order:
/// `hit(j, t, lane)` is told pack `j`'s and returns the new bound (a
/// closest-hit search lowers it). Returns the last bound. With AVX two
/// packs are tested under the same bound and the second's hit is then
/// held to the first's: what the baseline, one pack after the other,
/// finds.
#[inline(always)]
pub fn nearest_each(
    packs: &[Tri4],
    ray: &Ray,
    mut tmax: f32,
    simd: Simd,
    mut hit: impl FnMut(usize, f32, usize) -> f32,
) -> f32 {
    let mut first = 0;
    #[cfg(target_arch = "x86_64")]
    if simd != Simd::Baseline {
        while first + 1 < packs.len() {
            // SAFETY: `Simd::Avx` and `Avx512` are chosen only where the CPU
            // has AVX.
            let (mask, t) = unsafe { avx::lanes_pair(&packs[first], &packs[first + 1], ray, tmax) };
            for half in 0..2 {
                let lanes = (mask >> (4 * half)) & 0b1111;
                if let Some((th, lane)) = nearest(lanes, &t[4 * half..], tmax) {
                    tmax = hit(first + half, th, lane);
                }
            }
            first += 2;
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = simd;
    for (j, p) in packs.iter().enumerate().skip(first) {
        if let Some((t, lane)) = p.intersect(ray, tmax) {
            tmax = hit(j, t, lane);
        }
    }
    tmax
}

/// Whether any of `packs` is hit under `tmax`.
#[inline(always)]
pub fn any_hit(packs: &[Tri4], ray: &Ray, tmax: f32, simd: Simd) -> bool {
    let mut first = 0;
    #[cfg(target_arch = "x86_64")]
    if simd != Simd::Baseline {
        while first + 1 < packs.len() {
            // SAFETY: `Simd::Avx` and `Avx512` are chosen only where the CPU
            // has AVX.
            if unsafe { avx::lanes_pair(&packs[first], &packs[first + 1], ray, tmax) }.0 != 0 {
                return true;
            }
            first += 2;
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = simd;
    packs[first..].iter().any(|p| p.hits(ray, tmax))
}

/// The AVX test of two packs, lane for lane [`Tri4::lanes`].
#[cfg(target_arch = "x86_64")]
mod avx {
    use std::arch::x86_64::*;

    use super::{Ray, Tri4};

    /// [`Tri4::lanes`] of `p` (lanes 0–3) and `q` (lanes 4–7) at once.
    #[target_feature(enable = "avx")]
    pub unsafe fn lanes_pair(p: &Tri4, q: &Tri4, ray: &Ray, tmax: f32) -> (u32, [f32; 8]) {
        let [kx, ky, kz] = ray.axes.map(|k| k.min(2));
        let set = |x: f32| _mm256_set1_ps(x);
        let (sx, sy, sz) = (set(ray.shear.x), set(ray.shear.y), set(ray.shear.z));
        let o = ray.permuted_origin;
        let (ox, oy, oz) = (set(o.x), set(o.y), set(o.z));
        // Corner `c`'s coordinate `k` of both packs in one register.
        macro_rules! both {
            ($c:expr, $k:expr) => {
                _mm256_insertf128_ps::<1>(
                    _mm256_castps128_ps256(__m128::from(p.v[$c][$k])),
                    __m128::from(q.v[$c][$k]),
                )
            };
        }
        macro_rules! corner {
            ($c:expr) => {{
                let z = _mm256_sub_ps(both!($c, kz), oz);
                (
                    _mm256_sub_ps(_mm256_sub_ps(both!($c, kx), ox), _mm256_mul_ps(sx, z)),
                    _mm256_sub_ps(_mm256_sub_ps(both!($c, ky), oy), _mm256_mul_ps(sy, z)),
                    z,
                )
            }};
        }
        let (ax, ay, az) = corner!(0);
        let (bx, by, bz) = corner!(1);
        let (cx, cy, cz) = corner!(2);
        let (sub, mul) = (|a, b| _mm256_sub_ps(a, b), |a, b| _mm256_mul_ps(a, b));
        let mut u = sub(mul(cx, by), mul(cy, bx));
        let mut w = sub(mul(ax, cy), mul(ay, cx));
        let mut x = sub(mul(bx, ay), mul(by, ax));
        let zero = _mm256_setzero_ps();
        let eq = |a| _mm256_cmp_ps::<_CMP_EQ_OQ>(a, zero);
        let mut exact = _mm256_movemask_ps(_mm256_or_ps(_mm256_or_ps(eq(u), eq(w)), eq(x))) as u32;
        if exact != 0 {
            // As the baseline: such lanes decided in f64.
            let arr = |v: __m256| {
                let mut a = [0f32; 8];
                _mm256_storeu_ps(a.as_mut_ptr(), v);
                a
            };
            let (axa, aya, bxa, bya, cxa, cya) =
                (arr(ax), arr(ay), arr(bx), arr(by), arr(cx), arr(cy));
            let (mut ua, mut wa, mut xa) = (arr(u), arr(w), arr(x));
            while exact != 0 {
                let l = exact.trailing_zeros() as usize;
                exact &= exact - 1;
                ua[l] = super::edge_f64(cxa[l], bya[l], cya[l], bxa[l]);
                wa[l] = super::edge_f64(axa[l], cya[l], aya[l], cxa[l]);
                xa[l] = super::edge_f64(bxa[l], aya[l], bya[l], axa[l]);
            }
            u = _mm256_loadu_ps(ua.as_ptr());
            w = _mm256_loadu_ps(wa.as_ptr());
            x = _mm256_loadu_ps(xa.as_ptr());
        }
        let or3 = |a, b, c| _mm256_or_ps(_mm256_or_ps(a, b), c);
        let lt = |a| _mm256_cmp_ps::<_CMP_LT_OQ>(a, zero);
        let gt = |a| _mm256_cmp_ps::<_CMP_GT_OQ>(a, zero);
        let negative = or3(lt(u), lt(w), lt(x));
        let positive = or3(gt(u), gt(w), gt(x));
        let det = _mm256_add_ps(_mm256_add_ps(u, w), x);
        let inside = _mm256_andnot_ps(
            _mm256_and_ps(negative, positive),
            _mm256_cmp_ps::<_CMP_NEQ_UQ>(det, zero),
        );
        if _mm256_movemask_ps(inside) == 0 {
            return (0, [0.0; 8]);
        }
        let num = _mm256_add_ps(
            _mm256_add_ps(mul(u, mul(sz, az)), mul(w, mul(sz, bz))),
            mul(x, mul(sz, cz)),
        );
        let t = _mm256_div_ps(num, det);
        let hit = _mm256_and_ps(
            _mm256_and_ps(inside, _mm256_cmp_ps::<_CMP_GT_OQ>(t, set(ray.tmin))),
            _mm256_cmp_ps::<_CMP_LT_OQ>(t, set(tmax)),
        );
        let mut ts = [0f32; 8];
        _mm256_storeu_ps(ts.as_mut_ptr(), t);
        (_mm256_movemask_ps(hit) as u32, ts)
    }
}

/// One triangle's hit t in (tmin, tmax) for the ray `o + t·d` (tests and
/// single queries; the BVH tests four at once).
pub fn triangle(v: &[Vec3; 3], o: Vec3A, d: Vec3A, tmin: f32, tmax: f32) -> Option<f32> {
    if !(o.is_finite() && d.is_finite()) || d == Vec3A::ZERO {
        return None;
    }
    Tri4::pack(&[*v])
        .intersect(&Ray::new(o, d, tmin), tmax)
        .map(|(t, _)| t)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_environment_caps_the_path_by_name() {
        for s in Simd::ALL {
            assert_eq!(Simd::parse(s.name()), Some(s));
        }
        assert_eq!(Simd::parse("sse2"), None);
        assert_eq!(Simd::capped(Simd::Avx512, Some("avx")), Simd::Avx);
        assert_eq!(Simd::capped(Simd::Avx512, Some("baseline")), Simd::Baseline);
        // Never wider than the machine's, whatever is asked.
        assert_eq!(Simd::capped(Simd::Avx, Some("avx512")), Simd::Avx);
        assert_eq!(Simd::capped(Simd::Avx, None), Simd::Avx);
        assert_eq!(Simd::capped(Simd::Avx, Some("AVX")), Simd::Avx);
    }

    #[test]
    fn equally_near_lanes_give_the_lowest_lane() {
        let tri = |y: f32| {
            [
                Vec3::new(-1.0, y, -1.0),
                Vec3::new(1.0, y, -1.0),
                Vec3::new(0.0, y, 1.0),
            ]
        };
        let ray = Ray::new(Vec3A::new(0.0, 2.0, 0.0), -Vec3A::Y, 0.0);
        for (heights, want) in [
            ([0.0; 4], (2.0, 0)),
            ([0.0, 0.0, 1.0, 1.0], (1.0, 2)),
            ([0.0, 1.0, 0.5, 1.0], (1.0, 1)),
        ] {
            let pack = Tri4::pack(&heights.map(tri));
            assert_eq!(
                pack.intersect(&ray, f32::INFINITY),
                Some(want),
                "{heights:?}"
            );
            assert!(pack.hits(&ray, f32::INFINITY));
            assert!(!pack.hits(&ray, 0.5));
        }
    }
}
