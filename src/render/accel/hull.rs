//! A bundle of coherent segments (a pixel's shadow rays toward one light)
//! bounded by one convex region, so that a tree walk tests each node once
//! for the whole bundle instead of once per ray. The region is an
//! oriented box along the bundle's mean direction, intersected with its
//! world box: two rays from neighbouring points toward the same light
//! make a long thin box around both.
//!
//! The region only decides which boxes are opened; every ray still meets
//! the triangles with its own test. It is padded well beyond the rounding
//! of the tests below, so it opens every box a segment passes through.

use glam::{Vec3A, Vec4};

/// Rounding allowance, relative to the largest coordinate involved
/// (2⁻¹⁶; the projections below round at 2⁻²⁴ per operation).
const PAD: f32 = 1.0 / 65536.0;

/// The region: ranges along an orthonormal frame and along the world
/// axes.
#[derive(Debug, Clone, Copy)]
pub struct Hull {
    /// The frame's axes (the last along the bundle).
    frame: [Vec3A; 3],
    /// Twice the ranges along the frame's axes (the node test compares
    /// doubled centres).
    lo2: [f32; 3],
    hi2: [f32; 3],
    /// The world box.
    lo: Vec3A,
    hi: Vec3A,
}

impl Hull {
    /// The region around the segments between `points` taken in pairs
    /// (each segment's two ends; any order), oriented along `along`.
    /// `scale` is the largest coordinate of the boxes it will be tested
    /// against; None when a point is not finite.
    pub fn around(points: &[Vec3A], along: Vec3A, scale: f32) -> Option<Hull> {
        if points.is_empty() || !points.iter().all(|p| p.is_finite()) {
            return None;
        }
        let d = along.try_normalize()?;
        let (u, v) = d.any_orthonormal_pair();
        let frame = [u, v, d];
        let mut lo = Vec3A::splat(f32::INFINITY);
        let mut hi = Vec3A::splat(f32::NEG_INFINITY);
        let (mut flo, mut fhi) = (lo, hi);
        for &p in points {
            lo = lo.min(p);
            hi = hi.max(p);
            let f = Vec3A::new(p.dot(u), p.dot(v), p.dot(d));
            flo = flo.min(f);
            fhi = fhi.max(f);
        }
        let pad = PAD
            * scale
                .max(lo.abs().max_element())
                .max(hi.abs().max_element());
        let (flo, fhi) = (flo - pad, fhi + pad);
        Some(Hull {
            frame,
            lo2: (2.0 * flo).to_array(),
            hi2: (2.0 * fhi).to_array(),
            lo: lo - pad,
            hi: hi + pad,
        })
    }

    /// Which of four boxes (`lo`, `hi` per axis, a box per lane) may
    /// meet the region: a bit per box. No separating axis among the world
    /// axes and the frame's (the boxes' inverted empty slots never meet
    /// it).
    #[inline(always)]
    pub fn meets(&self, lo: &[Vec4; 3], hi: &[Vec4; 3]) -> u32 {
        let mut m = lo[0].cmple(Vec4::splat(self.hi.x))
            & hi[0].cmpge(Vec4::splat(self.lo.x))
            & lo[1].cmple(Vec4::splat(self.hi.y))
            & hi[1].cmpge(Vec4::splat(self.lo.y))
            & lo[2].cmple(Vec4::splat(self.hi.z))
            & hi[2].cmpge(Vec4::splat(self.lo.z));
        if m.bitmask() == 0 {
            return 0;
        }
        let sum = [lo[0] + hi[0], lo[1] + hi[1], lo[2] + hi[2]];
        let size = [hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]];
        for (k, a) in self.frame.iter().enumerate() {
            // Twice the box's centre and half-width along the axis.
            let c = sum[0] * a.x + sum[1] * a.y + sum[2] * a.z;
            let r = size[0] * a.x.abs() + size[1] * a.y.abs() + size[2] * a.z.abs();
            m &= (c - r).cmple(Vec4::splat(self.hi2[k])) & (c + r).cmpge(Vec4::splat(self.lo2[k]));
        }
        m.bitmask()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn boxes(b: &[(Vec3A, Vec3A)]) -> ([Vec4; 3], [Vec4; 3]) {
        let mut lo = [Vec4::INFINITY; 3];
        let mut hi = [Vec4::NEG_INFINITY; 3];
        for (i, (l, h)) in b.iter().enumerate() {
            for a in 0..3 {
                lo[a][i] = l[a];
                hi[a][i] = h[a];
            }
        }
        (lo, hi)
    }

    #[test]
    fn a_thin_bundle_meets_the_boxes_on_its_way_only() {
        // Two segments from near the origin to (10, 10, 0).
        let pts = [
            Vec3A::ZERO,
            Vec3A::new(10.0, 10.0, 0.0),
            Vec3A::new(0.1, 0.0, 0.0),
            Vec3A::new(10.0, 10.0, 0.0),
        ];
        let h = Hull::around(&pts, Vec3A::new(1.0, 1.0, 0.0), 20.0).unwrap();
        let (lo, hi) = boxes(&[
            // On the way.
            (Vec3A::new(4.5, 4.5, -0.5), Vec3A::new(5.5, 5.5, 0.5)),
            // In the world box, off the diagonal: the frame separates it.
            (Vec3A::new(8.0, 0.0, -1.0), Vec3A::new(9.0, 1.0, 1.0)),
            // Beyond the light.
            (Vec3A::splat(11.0), Vec3A::splat(12.0)),
            // Touching an end exactly.
            (Vec3A::new(-1.0, -1.0, -1.0), Vec3A::ZERO),
        ]);
        assert_eq!(h.meets(&lo, &hi), 0b1001);
    }

    #[test]
    fn empty_slots_and_bad_points() {
        let h = Hull::around(&[Vec3A::ZERO, Vec3A::X], Vec3A::X, 1.0).unwrap();
        let (lo, hi) = boxes(&[]);
        assert_eq!(h.meets(&lo, &hi), 0);
        assert!(Hull::around(&[Vec3A::ZERO, Vec3A::NAN], Vec3A::X, 1.0).is_none());
        assert!(Hull::around(&[Vec3A::ZERO], Vec3A::ZERO, 1.0).is_none());
    }
}
