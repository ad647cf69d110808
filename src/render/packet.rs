//! Up to sixteen rays traced together: a pixel's samples, which the
//! renderer casts as one packet (`Accel::cast_all`). One fetch of a node
//! or a triangle serves them all, and its test runs across the rays, one
//! per SIMD lane, in the lane forms of [`super::wide`]. Every lane
//! computes the single-ray test's operations in the same order, so each
//! ray enters the boxes and hits the triangles its own walk would, and
//! every form gives the same bits (DESIGN §4).

use super::bvh4::Ray;

/// Rays a packet holds: one bit each of a `u32` mask.
pub const LANES: usize = 16;

/// One value per ray of a packet.
pub type Lanes = [f32; LANES];

/// Rays whose directions have the same signs and the same largest axis,
/// so that a node's near sides and a triangle's sheared frame are the
/// same for all of them; in the structure-of-arrays form the tests read.
/// Lanes outside the packet's mask repeat one of its rays.
pub struct RayPacket<'a> {
    /// The rays, as given (those outside the mask too).
    pub rays: &'a [Ray; LANES],
    pub inv: [Lanes; 3],
    pub origin_inv: [Lanes; 3],
    pub tmin: Lanes,
    pub shear: [Lanes; 3],
    pub permuted_origin: [Lanes; 3],
    pub negative: [bool; 3],
    pub axes: [usize; 3],
}

impl RayPacket<'_> {
    /// The packet of `rays[i]` for the lanes `i` of `mask` (not empty),
    /// which must share [`Ray::key`].
    pub fn new(rays: &[Ray; LANES], mask: u32) -> RayPacket<'_> {
        let first = &rays[mask.trailing_zeros() as usize];
        let zero = [[0.0; LANES]; 3];
        let mut p = RayPacket {
            rays,
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
                p.inv[a][i] = r.inv[a];
                p.origin_inv[a][i] = r.origin_inv[a];
                p.shear[a][i] = r.shear[a];
                p.permuted_origin[a][i] = r.permuted_origin[a];
            }
            p.tmin[i] = r.tmin;
        }
        p
    }
}

/// Rays to trace together: one packet, or rays that may need several.
/// (It lives on the stack for one pixel; boxing the packet would
/// allocate per pixel.)
#[allow(clippy::large_enum_variant)]
pub enum Rays<'a> {
    /// Rays of one key, their packet made.
    Packet(RayPacket<'a>),
    /// Rays to split into packets by key ([`groups`]).
    Mixed(&'a [Ray; LANES]),
}

impl<'a> Rays<'a> {
    /// The rays, one per lane.
    pub fn rays(&self) -> &'a [Ray; LANES] {
        match self {
            Rays::Packet(p) => p.rays,
            Rays::Mixed(r) => r,
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
