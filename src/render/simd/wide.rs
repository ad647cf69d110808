//! Sixteen f32 lanes (a ray packet's) as one value, for the packet tests,
//! in four forms: `Scalar` (any target, and the tests' reference), `Sse`
//! (4 × SSE2, every x86-64), `Avx` (2 × AVX) and `Avx512` (one AVX-512
//! register), the last two chosen at run time. Each method is one IEEE
//! operation per lane, the same in every form — `max`/`min` are
//! `maxps`/`minps` (`a > b ? a : b`, `a < b ? a : b`), no fused
//! multiply-add — so every form computes the same bits (DESIGN §4).
//!
//! Code generic over `Wide` runs inside `#[target_feature]` functions, and
//! its helpers must be `#[inline(always)]` functions, never closures: a
//! closure does not inherit the target features, and one the compiler
//! leaves out of line calls each AVX operation out of line (AVX2 packets
//! ran 4× slower so; `scripts/bench_render.sh` refuses such a build).

use super::{Lanes, LANES};

/// Sixteen lanes of f32.
pub trait Wide: Copy {
    /// The result of a comparison, one flag per lane.
    type Mask: Mask;
    /// Registers a value takes (1 to 16): what a test costs, whatever the
    /// lanes in use.
    const REGISTERS: u32;
    fn splat(x: f32) -> Self;
    fn load(a: &Lanes) -> Self;
    fn store(self) -> Lanes;
    fn add(self, o: Self) -> Self;
    fn sub(self, o: Self) -> Self;
    fn mul(self, o: Self) -> Self;
    fn div(self, o: Self) -> Self;
    fn max(self, o: Self) -> Self;
    fn min(self, o: Self) -> Self;
    /// The square root (correctly rounded, as `f32::sqrt`).
    fn sqrt(self) -> Self;
    fn lt(self, o: Self) -> Self::Mask;
    fn le(self, o: Self) -> Self::Mask;
    fn gt(self, o: Self) -> Self::Mask;
    fn eq(self, o: Self) -> Self::Mask;
    /// Unordered not-equal (true where either is NaN).
    fn ne(self, o: Self) -> Self::Mask;
    /// Lane i of `a` where lane i of `m` is set, else of `b`.
    fn select(m: Self::Mask, a: Self, b: Self) -> Self;
    /// The flags of the bits of `bits`, lane i at bit i.
    #[inline(always)]
    fn flags(bits: u32) -> Self::Mask {
        let mut a = [0.0; LANES];
        for (i, v) in a.iter_mut().enumerate() {
            *v = f32::from(u8::from(bits >> i & 1 != 0));
        }
        Self::splat(0.0).lt(Self::load(&a))
    }
    /// The least lane; no lane may be NaN (in any order: the same
    /// value, but for the sign of a zero).
    #[inline(always)]
    fn least(self) -> f32 {
        self.store()
            .into_iter()
            .fold(f32::INFINITY, |m, x| if x < m { x } else { m })
    }
}

/// Sixteen flags.
pub trait Mask: Copy {
    fn and(self, o: Self) -> Self;
    fn or(self, o: Self) -> Self;
    /// `!self & o`.
    fn andnot(self, o: Self) -> Self;
    /// The flags as bits, lane i at bit i.
    fn bits(self) -> u32;
}

/// Flags as the bits of a `u32` (the scalar and AVX-512 forms').
impl Mask for u32 {
    #[inline(always)]
    fn and(self, o: Self) -> Self {
        self & o
    }
    #[inline(always)]
    fn or(self, o: Self) -> Self {
        self | o
    }
    #[inline(always)]
    fn andnot(self, o: Self) -> Self {
        !self & o
    }
    #[inline(always)]
    fn bits(self) -> u32 {
        self
    }
}

/// The reference form: one lane at a time.
#[derive(Clone, Copy)]
pub struct Scalar(Lanes);

impl Scalar {
    #[inline(always)]
    fn map2(self, o: Self, f: impl Fn(f32, f32) -> f32) -> Self {
        Scalar(std::array::from_fn(|i| f(self.0[i], o.0[i])))
    }

    #[inline(always)]
    fn test(self, o: Self, f: impl Fn(f32, f32) -> bool) -> u32 {
        (0..LANES).fold(0, |m, i| m | u32::from(f(self.0[i], o.0[i])) << i)
    }
}

impl Wide for Scalar {
    type Mask = u32;
    const REGISTERS: u32 = 16;
    #[inline(always)]
    fn splat(x: f32) -> Self {
        Scalar([x; LANES])
    }
    #[inline(always)]
    fn load(a: &Lanes) -> Self {
        Scalar(*a)
    }
    #[inline(always)]
    fn store(self) -> Lanes {
        self.0
    }
    #[inline(always)]
    fn add(self, o: Self) -> Self {
        self.map2(o, |a, b| a + b)
    }
    #[inline(always)]
    fn sub(self, o: Self) -> Self {
        self.map2(o, |a, b| a - b)
    }
    #[inline(always)]
    fn mul(self, o: Self) -> Self {
        self.map2(o, |a, b| a * b)
    }
    #[inline(always)]
    fn div(self, o: Self) -> Self {
        self.map2(o, |a, b| a / b)
    }
    #[inline(always)]
    fn max(self, o: Self) -> Self {
        self.map2(o, |a, b| if a > b { a } else { b })
    }
    #[inline(always)]
    fn min(self, o: Self) -> Self {
        self.map2(o, |a, b| if a < b { a } else { b })
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        Scalar(self.0.map(f32::sqrt))
    }
    #[inline(always)]
    fn lt(self, o: Self) -> u32 {
        self.test(o, |a, b| a < b)
    }
    #[inline(always)]
    fn le(self, o: Self) -> u32 {
        self.test(o, |a, b| a <= b)
    }
    #[inline(always)]
    fn gt(self, o: Self) -> u32 {
        self.test(o, |a, b| a > b)
    }
    #[inline(always)]
    fn eq(self, o: Self) -> u32 {
        self.test(o, |a, b| a == b)
    }
    #[inline(always)]
    fn ne(self, o: Self) -> u32 {
        self.test(o, |a, b| a != b)
    }
    #[inline(always)]
    fn select(m: u32, a: Self, b: Self) -> Self {
        Scalar(std::array::from_fn(|i| {
            if m >> i & 1 != 0 {
                a.0[i]
            } else {
                b.0[i]
            }
        }))
    }
}

#[cfg(target_arch = "x86_64")]
pub use x86::{Avx, Avx512, Sse};

#[cfg(target_arch = "x86_64")]
mod x86 {
    use std::arch::x86_64::*;

    use super::{Lanes, Mask, Wide};

    /// Four SSE registers (SSE2 is part of x86-64).
    #[derive(Clone, Copy)]
    pub struct Sse([__m128; 4]);

    /// Two AVX registers. Use it only in functions compiled for AVX
    /// (`#[target_feature(enable = "avx")]`), on CPUs that have it.
    #[derive(Clone, Copy)]
    pub struct Avx([__m256; 2]);

    /// One AVX-512 register, under the same terms for AVX-512F.
    #[derive(Clone, Copy)]
    pub struct Avx512(__m512);

    /// A comparison's lanes, all ones or all zeros, in SSE registers.
    #[derive(Clone, Copy)]
    pub struct SseMask([__m128; 4]);

    /// The same in AVX registers.
    #[derive(Clone, Copy)]
    pub struct AvxMask([__m256; 2]);

    // SAFETY (every `unsafe` below): a form is used only where its
    // instructions exist, and loads and stores stay within the 16 lanes.

    macro_rules! lanes {
        ($t:ident, $m:ident, $n:expr, $w:expr, $set1:path, $loadu:path, $storeu:path,
         $movemask:path, $select:path, $and:path, $or:path, $andnot:path,
         $sqrt:path, [$($name:ident => $f:path),*], [$($cmp:ident => $g:path),*]
         $(, least => $least:path)?) => {
            impl Wide for $t {
                type Mask = $m;
                const REGISTERS: u32 = $n;
                #[inline(always)]
                fn splat(x: f32) -> Self {
                    $t([unsafe { $set1(x) }; $n])
                }
                #[inline(always)]
                fn load(a: &Lanes) -> Self {
                    $t(std::array::from_fn(|k| unsafe { $loadu(a[k * $w..].as_ptr()) }))
                }
                #[inline(always)]
                fn store(self) -> Lanes {
                    let mut a = [0f32; 16];
                    for k in 0..$n {
                        unsafe { $storeu(a[k * $w..].as_mut_ptr(), self.0[k]) };
                    }
                    a
                }
                #[inline(always)]
                fn sqrt(self) -> Self {
                    $t(std::array::from_fn(|k| unsafe { $sqrt(self.0[k]) }))
                }
                $(
                    #[inline(always)]
                    fn $name(self, o: Self) -> Self {
                        $t(std::array::from_fn(|k| unsafe { $f(self.0[k], o.0[k]) }))
                    }
                )*
                $(
                    #[inline(always)]
                    fn $cmp(self, o: Self) -> $m {
                        $m(std::array::from_fn(|k| unsafe { $g(self.0[k], o.0[k]) }))
                    }
                )*
                #[inline(always)]
                fn select(m: $m, a: Self, b: Self) -> Self {
                    $t(std::array::from_fn(|k| unsafe { $select(m.0[k], a.0[k], b.0[k]) }))
                }
                $(
                    #[inline(always)]
                    fn least(self) -> f32 {
                        unsafe { $least(self.0) }
                    }
                )?
            }

            impl Mask for $m {
                #[inline(always)]
                fn and(self, o: Self) -> Self {
                    $m(std::array::from_fn(|k| unsafe { $and(self.0[k], o.0[k]) }))
                }
                #[inline(always)]
                fn or(self, o: Self) -> Self {
                    $m(std::array::from_fn(|k| unsafe { $or(self.0[k], o.0[k]) }))
                }
                #[inline(always)]
                fn andnot(self, o: Self) -> Self {
                    $m(std::array::from_fn(|k| unsafe { $andnot(self.0[k], o.0[k]) }))
                }
                #[inline(always)]
                fn bits(self) -> u32 {
                    (0..$n).fold(0, |m, k| m | (unsafe { $movemask(self.0[k]) } as u32) << (k * $w))
                }
            }
        };
    }

    lanes!(Sse, SseMask, 4, 4, _mm_set1_ps, _mm_loadu_ps, _mm_storeu_ps, _mm_movemask_ps,
        select128, _mm_and_ps, _mm_or_ps, _mm_andnot_ps, _mm_sqrt_ps, [
        add => _mm_add_ps, sub => _mm_sub_ps, mul => _mm_mul_ps, div => _mm_div_ps,
        max => _mm_max_ps, min => _mm_min_ps
    ], [
        lt => _mm_cmplt_ps, le => _mm_cmple_ps, gt => _mm_cmpgt_ps, eq => _mm_cmpeq_ps,
        ne => _mm_cmpneq_ps
    ]);

    lanes!(Avx, AvxMask, 2, 8, _mm256_set1_ps, _mm256_loadu_ps, _mm256_storeu_ps,
        _mm256_movemask_ps, select256, _mm256_and_ps, _mm256_or_ps, _mm256_andnot_ps, sqrt256, [
        add => _mm256_add_ps, sub => _mm256_sub_ps, mul => _mm256_mul_ps, div => _mm256_div_ps,
        max => _mm256_max_ps, min => _mm256_min_ps
    ], [
        lt => lt256, le => le256, gt => gt256, eq => eq256, ne => ne256
    ], least => least256);

    /// Lanes of `a` where `m` is set, else of `b` (no SSE4.1 blend).
    #[inline(always)]
    unsafe fn select128(m: __m128, a: __m128, b: __m128) -> __m128 {
        _mm_or_ps(_mm_and_ps(m, a), _mm_andnot_ps(m, b))
    }

    macro_rules! avx_fn {
        ($($name:ident($($arg:ident),*) => $body:expr;)*) => {
            $(
                #[inline]
                #[target_feature(enable = "avx")]
                unsafe fn $name($($arg: __m256),*) -> __m256 {
                    $body
                }
            )*
        };
    }

    /// The least of 16 lanes, pairwise rather than the default's chain of
    /// 16 dependent minimums (a packet walk orders a node's children by
    /// it; 1 % fewer instructions a frame).
    #[inline]
    #[target_feature(enable = "avx")]
    unsafe fn least256([a, b]: [__m256; 2]) -> f32 {
        let m = _mm256_min_ps(a, b);
        let m = _mm_min_ps(_mm256_castps256_ps128(m), _mm256_extractf128_ps::<1>(m));
        let m = _mm_min_ps(m, _mm_movehl_ps(m, m));
        _mm_cvtss_f32(_mm_min_ss(m, _mm_shuffle_ps::<1>(m, m)))
    }
    avx_fn! {
        select256(m, a, b) => _mm256_blendv_ps(b, a, m);
        sqrt256(a) => _mm256_sqrt_ps(a);
        lt256(a, b) => _mm256_cmp_ps::<_CMP_LT_OQ>(a, b);
        le256(a, b) => _mm256_cmp_ps::<_CMP_LE_OQ>(a, b);
        gt256(a, b) => _mm256_cmp_ps::<_CMP_GT_OQ>(a, b);
        eq256(a, b) => _mm256_cmp_ps::<_CMP_EQ_OQ>(a, b);
        ne256(a, b) => _mm256_cmp_ps::<_CMP_NEQ_UQ>(a, b);
    }

    macro_rules! avx512_ops {
        ($($name:ident => $f:ident),*; $($cmp:ident => $p:ident),*) => {
            $(
                #[inline(always)]
                fn $name(self, o: Self) -> Self {
                    Avx512(unsafe { $f(self.0, o.0) })
                }
            )*
            $(
                #[inline(always)]
                fn $cmp(self, o: Self) -> u32 {
                    u32::from(unsafe { _mm512_cmp_ps_mask::<$p>(self.0, o.0) })
                }
            )*
        };
    }

    impl Wide for Avx512 {
        type Mask = u32;
        const REGISTERS: u32 = 1;
        #[inline(always)]
        fn splat(x: f32) -> Self {
            Avx512(unsafe { _mm512_set1_ps(x) })
        }
        #[inline(always)]
        fn load(a: &Lanes) -> Self {
            Avx512(unsafe { _mm512_loadu_ps(a.as_ptr()) })
        }
        #[inline(always)]
        fn store(self) -> Lanes {
            let mut a = [0f32; 16];
            unsafe { _mm512_storeu_ps(a.as_mut_ptr(), self.0) };
            a
        }
        avx512_ops!(add => _mm512_add_ps, sub => _mm512_sub_ps, mul => _mm512_mul_ps,
            div => _mm512_div_ps, max => _mm512_max_ps, min => _mm512_min_ps;
            lt => _CMP_LT_OQ, le => _CMP_LE_OQ, gt => _CMP_GT_OQ, eq => _CMP_EQ_OQ,
            ne => _CMP_NEQ_UQ);
        #[inline(always)]
        fn sqrt(self) -> Self {
            Avx512(unsafe { _mm512_sqrt_ps(self.0) })
        }
        #[inline(always)]
        fn select(m: u32, a: Self, b: Self) -> Self {
            Avx512(unsafe { _mm512_mask_blend_ps(m as u16, b.0, a.0) })
        }
        #[inline(always)]
        fn least(self) -> f32 {
            unsafe { _mm512_reduce_min_ps(self.0) }
        }
    }
}

#[cfg(all(test, target_arch = "x86_64"))]
mod tests {
    use super::*;

    /// Every result of every form, as bits: each operation on each pair.
    fn results<W: Wide>(a: &Lanes, b: &Lanes) -> Vec<u32> {
        let (x, y) = (W::load(a), W::load(b));
        let mut out = Vec::new();
        for v in [
            x.add(y),
            x.sub(y),
            x.mul(y),
            x.div(y),
            x.max(y),
            x.min(y),
            x.sqrt(),
            W::select(x.lt(y), x, y),
        ] {
            out.extend(v.store().map(f32::to_bits));
        }
        // `least` of lanes without NaN; zeros compared by value.
        let clean = W::select(x.eq(x), x, W::splat(1.0));
        out.push((clean.least() + 0.0).to_bits());
        for m in [x.lt(y), x.le(y), x.gt(y), x.eq(y), x.ne(y)] {
            out.push(m.bits());
            out.push(m.and(x.le(y)).or(x.eq(y)).andnot(x.ne(y)).bits());
        }
        out
    }

    #[target_feature(enable = "avx")]
    unsafe fn avx(a: &Lanes, b: &Lanes) -> Vec<u32> {
        results::<Avx>(a, b)
    }

    #[target_feature(enable = "avx512f")]
    unsafe fn avx512(a: &Lanes, b: &Lanes) -> Vec<u32> {
        results::<Avx512>(a, b)
    }

    /// The forms agree bit for bit with the scalar reference, NaN, signed
    /// zeros, infinities and subnormals included (the pairs are every
    /// special value against every other, then random ones).
    #[test]
    fn every_form_computes_the_scalar_bits() {
        let special = [
            0.0,
            -0.0,
            1.0,
            -1.5,
            f32::INFINITY,
            f32::NEG_INFINITY,
            f32::NAN,
            f32::MIN_POSITIVE / 8.0,
            f32::MAX,
            3.0e-39,
            7.25,
            -0.1,
        ];
        let mut pairs: Vec<(f32, f32)> = special
            .iter()
            .flat_map(|&a| special.iter().map(move |&b| (a, b)))
            .collect();
        let mut seed = 0x9e37_79b9_7f4a_7c15u64;
        pairs.extend((0..4096).map(|_| {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            let f = |s: u64| f32::from_bits((s >> 32) as u32 & 0xbfff_ffff);
            (f(seed), f(seed.rotate_left(17)))
        }));
        for chunk in pairs.chunks(LANES) {
            let (mut a, mut b) = ([0f32; LANES], [0f32; LANES]);
            for (i, &(x, y)) in chunk.iter().enumerate() {
                (a[i], b[i]) = (x, y);
            }
            let want = results::<Scalar>(&a, &b);
            assert_eq!(results::<Sse>(&a, &b), want, "{a:?} {b:?}");
            if std::arch::is_x86_feature_detected!("avx") {
                // SAFETY: the CPU has AVX.
                assert_eq!(unsafe { avx(&a, &b) }, want, "{a:?} {b:?}");
            }
            if std::arch::is_x86_feature_detected!("avx512f") {
                // SAFETY: the CPU has AVX-512F.
                assert_eq!(unsafe { avx512(&a, &b) }, want, "{a:?} {b:?}");
            }
        }
    }
}
