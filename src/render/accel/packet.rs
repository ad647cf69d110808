//! Up to sixteen rays traced together: a pixel's samples, which the
//! renderer casts as one packet (`Accel::cast_all`). One fetch of a node
//! or a triangle serves them all, and its test runs across the rays, one
//! per SIMD lane, in the lane forms of [`crate::render::simd::wide`]. Every lane
//! computes the single-ray test's operations in the same order, so each
//! ray enters the boxes and hits the triangles its own walk would, and
//! every form gives the same bits (DESIGN §4).

use glam::Vec3A;

use super::ray::Ray;
use crate::render::simd::{at, Lanes, LANES};

/// Rays whose directions have the same signs and the same largest axis,
/// so that a node's near sides and a triangle's sheared frame are the
/// same for all of them; in the structure-of-arrays form the tests read.
/// Lanes outside the packet's mask repeat one of its rays.
pub struct RayPacket {
    pub origin: [Lanes; 3],
    pub direction: [Lanes; 3],
    pub inv: [Lanes; 3],
    pub origin_inv: [Lanes; 3],
    pub tmin: Lanes,
    pub shear: [Lanes; 3],
    pub permuted_origin: [Lanes; 3],
    pub negative: [bool; 3],
    pub axes: [usize; 3],
}

impl RayPacket {
    /// The packet of `rays[i]` for the lanes `i` of `mask` (not empty),
    /// which must share [`Ray::key`].
    pub fn new(rays: &[Ray; LANES], mask: u32) -> RayPacket {
        let first = &rays[mask.trailing_zeros() as usize];
        let zero = [[0.0; LANES]; 3];
        let mut p = RayPacket {
            origin: zero,
            direction: zero,
            inv: zero,
            origin_inv: zero,
            tmin: [0.0; LANES],
            shear: zero,
            permuted_origin: zero,
            negative: first.negative,
            axes: first.axes,
        };
        for (i, r) in rays.iter().enumerate() {
            let r = if mask >> i & 1 != 0 { r } else { first };
            for a in 0..3 {
                p.origin[a][i] = r.origin[a];
                p.direction[a][i] = r.direction[a];
                p.inv[a][i] = r.inv[a];
                p.origin_inv[a][i] = r.origin_inv[a];
                p.shear[a][i] = r.shear[a];
                p.permuted_origin[a][i] = r.permuted_origin[a];
            }
            p.tmin[i] = r.tmin;
        }
        p
    }

    /// Lane `i`'s origin, direction and `tmin`.
    #[inline(always)]
    pub fn segment(&self, i: usize) -> (Vec3A, Vec3A, f32) {
        (at(&self.origin, i), at(&self.direction, i), self.tmin[i])
    }

    /// Lane `i`'s ray, made where a test needs it alone: the ray the
    /// lane was made from, the same bits. (Making all sixteen with the
    /// lanes, most unused, was 4 % of the forest's render.)
    #[inline(always)]
    pub fn ray(&self, i: usize) -> Ray {
        Ray {
            origin: at(&self.origin, i),
            direction: at(&self.direction, i),
            tmin: self.tmin[i],
            time: 0.0,
            inv: at(&self.inv, i),
            origin_inv: at(&self.origin_inv, i),
            negative: self.negative,
            axes: self.axes,
            shear: at(&self.shear, i),
            permuted_origin: at(&self.permuted_origin, i),
        }
    }
}

/// Rays to trace together: one packet, or rays that may need several.
#[derive(Clone, Copy)]
pub enum Rays<'a> {
    /// Rays of one key, their packet made.
    Packet(&'a RayPacket),
    /// Rays to split into packets by key ([`groups`]).
    Mixed(&'a [Ray; LANES]),
}

impl Rays<'_> {
    /// Lane `i`'s ray.
    #[inline(always)]
    pub fn ray(&self, i: usize) -> Ray {
        match self {
            Rays::Packet(p) => p.ray(i),
            Rays::Mixed(r) => r[i],
        }
    }

    /// Lane `i`'s origin, direction and `tmin`.
    #[inline(always)]
    pub fn segment(&self, i: usize) -> (Vec3A, Vec3A, f32) {
        match self {
            Rays::Packet(p) => p.segment(i),
            Rays::Mixed(r) => (r[i].origin, r[i].direction, r[i].tmin),
        }
    }
}

/// The lanes of `mask` split into groups of one [`Ray::key`] each, in
/// order of their lowest lane.
pub fn groups(rays: &[Ray; LANES], mut mask: u32) -> impl Iterator<Item = u32> + '_ {
    std::iter::from_fn(move || {
        if mask == 0 {
            return None;
        }
        let key = rays[mask.trailing_zeros() as usize].key();
        let mut group = 0;
        let mut m = mask;
        while m != 0 {
            let i = m.trailing_zeros() as usize;
            m &= m - 1;
            if rays[i].key() == key {
                group |= 1 << i;
            }
        }
        mask &= !group;
        Some(group)
    })
}

/// The indices of the set bits of a mask, lowest first.
pub struct Bits(pub u32);

impl Iterator for Bits {
    type Item = usize;

    #[inline(always)]
    fn next(&mut self) -> Option<usize> {
        (self.0 != 0).then(|| {
            let i = self.0.trailing_zeros() as usize;
            self.0 &= self.0 - 1;
            i
        })
    }
}

/// The lanes of `mask` for which `keep` holds, as a mask.
#[inline(always)]
pub fn keep(mask: u32, mut keep: impl FnMut(usize) -> bool) -> u32 {
    Bits(mask).filter(|&i| keep(i)).fold(0, |m, i| m | 1 << i)
}
