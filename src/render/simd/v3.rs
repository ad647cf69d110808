//! Sixteen 3-vectors as three [`Wide`] values, one vector per lane: a
//! pixel's samples shaded together ([`super::batch`]). Each operation is
//! the one glam's `Vec3A` (SSE2) and `Vec3` compute, lane by lane in the
//! same order — a dot product is `(x·x′ + y·y′) + z·z′`, `normalize`
//! divides by the length, `normalize_or_zero` multiplies by its
//! reciprocal — so a lane holds the bits the scalar shading gets
//! (`batch`'s tests compare them).

use std::ops::{Add, Mul, Neg, Sub};

use glam::{Vec3, Vec3A};

use super::wide::{Mask, Wide};
use super::Lanes;
use crate::render::accel::ray::INV_LIMIT;

#[derive(Clone, Copy)]
pub struct V3<W> {
    pub x: W,
    pub y: W,
    pub z: W,
}

impl<W: Wide> V3<W> {
    #[inline(always)]
    pub fn splat(v: Vec3A) -> Self {
        V3 {
            x: W::splat(v.x),
            y: W::splat(v.y),
            z: W::splat(v.z),
        }
    }

    #[inline(always)]
    pub fn splat3(v: Vec3) -> Self {
        Self::splat(v.into())
    }

    #[inline(always)]
    pub fn load(a: &[Lanes; 3]) -> Self {
        V3 {
            x: W::load(&a[0]),
            y: W::load(&a[1]),
            z: W::load(&a[2]),
        }
    }

    #[inline(always)]
    pub fn store(self) -> [Lanes; 3] {
        [self.x.store(), self.y.store(), self.z.store()]
    }

    /// Each lane's vector times that lane's `s`.
    #[inline(always)]
    pub fn scale(self, s: W) -> Self {
        V3 {
            x: self.x.mul(s),
            y: self.y.mul(s),
            z: self.z.mul(s),
        }
    }

    #[inline(always)]
    pub fn dot(self, o: Self) -> W {
        self.x.mul(o.x).add(self.y.mul(o.y)).add(self.z.mul(o.z))
    }

    #[inline(always)]
    pub fn length(self) -> W {
        self.dot(self).sqrt()
    }

    /// `Vec3A::normalize`: divided by the length.
    #[inline(always)]
    pub fn normalize(self) -> Self {
        let length = self.length();
        V3 {
            x: self.x.div(length),
            y: self.y.div(length),
            z: self.z.div(length),
        }
    }

    /// `Vec3A::normalize_or_zero`: times the reciprocal length where
    /// that is finite and positive, else zero.
    #[inline(always)]
    pub fn normalize_or_zero(self) -> Self {
        let rcp = W::splat(1.0).div(self.length());
        let zero = W::splat(0.0);
        // Finite: `rcp − rcp` is 0 (NaN for ±∞ and NaN).
        let ok = rcp.sub(rcp).eq(zero).and(rcp.gt(zero));
        let v = self.scale(rcp);
        V3 {
            x: W::select(ok, v.x, zero),
            y: W::select(ok, v.y, zero),
            z: W::select(ok, v.z, zero),
        }
    }

    /// Each lane's vector divided by that lane's `s`.
    #[inline(always)]
    pub fn over(self, s: W) -> Self {
        V3 {
            x: self.x.div(s),
            y: self.y.div(s),
            z: self.z.div(s),
        }
    }

    /// Where every component is finite (`v.is_finite()`).
    #[inline(always)]
    pub fn finite(self) -> W::Mask {
        // `c − c` is 0, but NaN for ±∞ and NaN.
        let zero = W::splat(0.0);
        let (x, y, z) = (self.x.sub(self.x), self.y.sub(self.y), self.z.sub(self.z));
        x.eq(zero).and(y.eq(zero)).and(z.eq(zero))
    }

    /// The magnitudes (`v.abs()` for components that are not NaN).
    #[inline(always)]
    pub fn abs(self) -> Self {
        let zero = W::splat(0.0);
        V3 {
            x: self.x.max(zero.sub(self.x)),
            y: self.y.max(zero.sub(self.y)),
            z: self.z.max(zero.sub(self.z)),
        }
    }

    /// `Ray::new`'s reciprocal: `1 / c` with its magnitude held to
    /// [`INV_LIMIT`], ±`INV_LIMIT` with the sign of `c` where it is not
    /// finite (`c` neither −0 nor NaN).
    #[inline(always)]
    pub fn recip_clamped(self) -> Self {
        V3 {
            x: recip_clamped(self.x),
            y: recip_clamped(self.y),
            z: recip_clamped(self.z),
        }
    }

    /// Where any component is not 0 (`v != Vec3A::ZERO`).
    #[inline(always)]
    pub fn nonzero(self) -> W::Mask {
        let zero = W::splat(0.0);
        self.x.ne(zero).or(self.y.ne(zero)).or(self.z.ne(zero))
    }

    /// `v.abs().max_element()` for finite components.
    #[inline(always)]
    pub fn max_abs(self) -> W {
        let a = self.abs();
        a.x.max(a.z).max(a.y)
    }

    /// Lane by lane, `a` where `m` is set, else `b`.
    #[inline(always)]
    pub fn select(m: W::Mask, a: Self, b: Self) -> Self {
        V3 {
            x: W::select(m, a.x, b.x),
            y: W::select(m, a.y, b.y),
            z: W::select(m, a.z, b.z),
        }
    }
}

/// See [`V3::recip_clamped`].
#[inline(always)]
fn recip_clamped<W: Wide>(c: W) -> W {
    let (zero, limit) = (W::splat(0.0), W::splat(INV_LIMIT));
    let r = W::splat(1.0).div(c);
    let size = W::select(r.sub(r).eq(zero), r.max(zero.sub(r)).min(limit), limit);
    W::select(c.lt(zero), zero.sub(size), size)
}

impl<W: Wide> Add for V3<W> {
    type Output = Self;
    #[inline(always)]
    fn add(self, o: Self) -> Self {
        V3 {
            x: self.x.add(o.x),
            y: self.y.add(o.y),
            z: self.z.add(o.z),
        }
    }
}

impl<W: Wide> Sub for V3<W> {
    type Output = Self;
    #[inline(always)]
    fn sub(self, o: Self) -> Self {
        V3 {
            x: self.x.sub(o.x),
            y: self.y.sub(o.y),
            z: self.z.sub(o.z),
        }
    }
}

/// Component by component.
impl<W: Wide> Mul for V3<W> {
    type Output = Self;
    #[inline(always)]
    fn mul(self, o: Self) -> Self {
        V3 {
            x: self.x.mul(o.x),
            y: self.y.mul(o.y),
            z: self.z.mul(o.z),
        }
    }
}

/// The sign flipped (−0 for 0, as glam's negation).
impl<W: Wide> Neg for V3<W> {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        self.scale(W::splat(-1.0))
    }
}
