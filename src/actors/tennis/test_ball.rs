//! A ball for the tests: gravity and linear air damping k per second,
//! the exact solution of thesis eq. 5.6.3 with gravity added.

use glam::DVec3;

pub const G: f64 = 9.81;

#[derive(Debug, Clone, Copy)]
pub struct Ball {
    pub p: DVec3,
    pub v: DVec3,
    pub k: f64,
}

impl Ball {
    /// Its position t seconds after it was at `p` with velocity `v`.
    pub fn at(&self, t: f64) -> DVec3 {
        let e = (1.0 - (-self.k * t).exp()) / self.k;
        let terminal = DVec3::new(0.0, -G / self.k, 0.0);
        self.p + (self.v - terminal) * e + terminal * t
    }

    /// When it is at height h on its way down (bisection on the falling
    /// branch after the apex).
    pub fn down_at(&self, h: f64) -> f64 {
        let apex = (self.v.y * self.k / G).ln_1p().max(0.0) / self.k;
        let (mut lo, mut hi) = (apex, apex + 10.0);
        for _ in 0..200 {
            let mid = 0.5 * (lo + hi);
            if self.at(mid).y > h {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        0.5 * (lo + hi)
    }
}
