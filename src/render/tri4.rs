//! Four triangles tested against one ray at once, as Embree's
//! `Triangle4`: a BVH leaf of up to four triangles costs one test instead
//! of four. The test is the watertight one of Woop, Benthin and Wald
//! (JCGT 2013): vertices are moved into a frame where the ray runs along
//! +z, and the 2-D edge functions decide, so a ray through a shared edge
//! or vertex of a closed mesh always finds one of its triangles.

use glam::{Vec3, Vec3A, Vec4};

use super::bvh4::Ray;

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
        let (mut mask, t) = self.lanes(ray, tmax);
        let mut best: Option<(f32, usize)> = None;
        while mask != 0 {
            let lane = mask.trailing_zeros() as usize;
            mask &= mask - 1;
            // Lanes come lowest first: only a nearer one replaces.
            if best.map_or(true, |(bt, _)| t[lane] < bt) {
                best = Some((t[lane], lane));
            }
        }
        best
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
            let f =
                |p: f32, q: f32, r: f32, s: f32| (p as f64 * q as f64 - r as f64 * s as f64) as f32;
            u[l] = f(cx[l], by[l], cy[l], bx[l]);
            w[l] = f(ax[l], cy[l], ay[l], cx[l]);
            x[l] = f(bx[l], ay[l], by[l], ax[l]);
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
