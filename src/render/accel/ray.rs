//! The one ray the accelerator walks: prepared once for the slab tests
//! of the BVH nodes and for the watertight triangle tests.

use glam::Vec3A;

/// The largest reciprocal of a direction's component, as Embree's
/// `rcp_safe`: times any coordinate a scene may hold (±1e18,
/// [`crate::scene::MAX_MAGNITUDE`]) it stays finite. With `f32::MAX`, a
/// ray along an axis from a point beyond ±1 made `origin·inv` infinite,
/// its slab distances NaN, and with an unbounded `tmax` the walk entered
/// a node's empty slots (the path tracer's sky rays found it).
pub(crate) const INV_LIMIT: f32 = 1e18;

/// A ray prepared for slab tests — reciprocal direction (finite and at
/// most [`INV_LIMIT`], so neither 0·∞ nor an overflow makes a NaN) and
/// origin times it — and for watertight triangle
/// tests: `axes` puts the direction's largest component last (z), `shear`
/// maps the direction onto that axis.
#[derive(Clone, Copy, Debug)]
pub struct Ray {
    pub origin: Vec3A,
    pub direction: Vec3A,
    pub tmin: f32,
    /// The instant within the shutter, 0..1, at which the ray sees
    /// moving shapes and instances (see [`crate::render::motion`]).
    pub time: f32,
    pub(crate) inv: Vec3A,
    pub(crate) origin_inv: Vec3A,
    pub(crate) negative: [bool; 3],
    pub axes: [usize; 3],
    pub shear: Vec3A,
    /// The origin's coordinates in the order of `axes`.
    pub permuted_origin: Vec3A,
}

impl Ray {
    pub fn new(origin: Vec3A, direction: Vec3A, tmin: f32) -> Ray {
        // Lane by lane, the same divisions as one at a time.
        let r = Vec3A::ONE / direction;
        let inv = Vec3A::select(r.is_finite_mask(), r, Vec3A::splat(INV_LIMIT))
            .clamp(Vec3A::splat(-INV_LIMIT), Vec3A::splat(INV_LIMIT))
            .copysign(direction);
        let d = direction.to_array();
        let ad = direction.abs();
        let kz = largest_axis(ad.x > ad.y, ad.x > ad.z, ad.y > ad.z);
        let [kx, ky, kz] = frame(kz, d[kz] < 0.0);
        let o = origin.to_array();
        Ray {
            origin,
            direction,
            tmin,
            time: 0.0,
            inv,
            origin_inv: origin * inv,
            negative: d.map(|c| c.is_sign_negative()),
            axes: [kx, ky, kz],
            shear: Vec3A::new(d[kx], d[ky], 1.0) / Vec3A::splat(d[kz]),
            permuted_origin: Vec3A::new(o[kx], o[ky], o[kz]),
        }
    }

    /// What rays must share to be traced as one packet: their direction's
    /// signs (a node's near sides) and axis order (a triangle's frame).
    pub fn key(&self) -> ([bool; 3], [usize; 3]) {
        (self.negative, self.axes)
    }
}

/// The axis a ray's frame puts last (z), from the comparisons of its
/// direction's magnitudes |x| > |y|, |x| > |z| and |y| > |z|: the largest
/// (of equal ones, z before x and y, y before x).
pub(crate) fn largest_axis(x_over_y: bool, x_over_z: bool, y_over_z: bool) -> usize {
    match (x_over_y, x_over_z, y_over_z) {
        (true, true, _) => 0,
        (false, _, true) => 1,
        _ => 2,
    }
}

/// The axes of a ray's frame with `kz` last, kept right-handed (x and y
/// swapped where the direction's `kz` component is negative, `flip`) so
/// the edge functions' signs hold.
pub(crate) fn frame(kz: usize, flip: bool) -> [usize; 3] {
    let (kx, ky) = ((kz + 1) % 3, (kz + 2) % 3);
    if flip {
        [ky, kx, kz]
    } else {
        [kx, ky, kz]
    }
}
