//! Exact ray intersection with the unit shapes of [`crate::scene::shape`]
//! and with triangles, for the BVH ray tracer.
//!
//! Rays arrive with unnormalised directions (a world ray mapped by the
//! inverse transform), so every returned t is the world t. Round shapes
//! first normalise the direction and restart the ray at its closest
//! approach to the shape's centre: the quadratics then stay well
//! conditioned however far away the ray starts, and that distance rejects
//! most misses before any root is taken.

use glam::Vec3A;

pub use crate::scene::shape::{bounds, local_bounds, triangle_bounds};
use crate::scene::shape::{valid_capsule, valid_trunk};
use crate::scene::ShapeKind;

/// A hit in the shape's local space: ray parameter t and the outward
/// geometric normal (local space, need not be normalised).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LocalHit {
    pub t: f32,
    pub normal: Vec3A,
}

/// Closest intersection with t in (tmin, tmax) of the ray o + t·d with the
/// unit shape `kind`, in local space (d need not be normalised; t is the
/// parameter of that ray). A ray starting inside finds the exit with the
/// outward normal. Degenerate or non-finite parameters never hit.
#[inline]
pub fn shape(kind: ShapeKind, o: Vec3A, d: Vec3A, tmin: f32, tmax: f32) -> Option<LocalHit> {
    if !(o.is_finite() && d.is_finite()) {
        return None;
    }
    match kind {
        ShapeKind::Box => unit_box(o, d, tmin, tmax),
        ShapeKind::Sphere => unit_sphere(o, d, tmin, tmax),
        ShapeKind::Cylinder => cylinder(o, d, tmin, tmax),
        ShapeKind::Capsule { length } => capsule(length, o, d, tmin, tmax),
        ShapeKind::Trunk { length, r0, r1 } => trunk(length, r0, r1, o, d, tmin, tmax),
    }
}

#[inline]
fn in_range(t: f32, tmin: f32, tmax: f32) -> bool {
    t > tmin && t < tmax
}

#[inline]
fn unit_box(o: Vec3A, d: Vec3A, tmin: f32, tmax: f32) -> Option<LocalHit> {
    const LO: Vec3A = Vec3A::new(0.0, -0.5, -0.5);
    const HI: Vec3A = Vec3A::new(1.0, 0.5, 0.5);
    let (a, b) = ((LO - o) / d, (HI - o) / d);
    let (mut lo, mut hi) = (a.min(b), a.max(b));
    // A ray parallel to a slab is inside it everywhere or nowhere (and the
    // divisions above gave infinities or NaN there).
    let flat = d.cmpeq(Vec3A::ZERO);
    if flat.any() {
        let inside = o.cmpge(LO) & o.cmple(HI);
        if (flat & !inside).any() {
            return None;
        }
        lo = Vec3A::select(flat, Vec3A::NEG_INFINITY, lo);
        hi = Vec3A::select(flat, Vec3A::INFINITY, hi);
    }
    let (near, far) = (lo.max_element(), hi.min_element());
    if near > far {
        return None;
    }
    // The entry face faces against the ray, the exit face along it; at an
    // edge both faces' axes count.
    if in_range(near, tmin, tmax) {
        let n = Vec3A::select(lo.cmpeq(Vec3A::splat(near)), -d.signum(), Vec3A::ZERO);
        Some(LocalHit { t: near, normal: n })
    } else if in_range(far, tmin, tmax) {
        let n = Vec3A::select(hi.cmpeq(Vec3A::splat(far)), d.signum(), Vec3A::ZERO);
        Some(LocalHit { t: far, normal: n })
    } else {
        None
    }
}

/// A ray restarted at its closest approach to a centre, with unit
/// direction: the point at parameter u is `o + u·d` and its t is
/// `(s0 + u)·inv_len`.
struct LocalRay {
    o: Vec3A,
    d: Vec3A,
    s0: f32,
    inv_len: f32,
}

impl LocalRay {
    /// None when the ray misses the ball (centre, radius) or d is zero.
    #[inline]
    fn near(o: Vec3A, d: Vec3A, centre: Vec3A, radius: f32) -> Option<LocalRay> {
        let (dn, len) = unit_dir(d)?;
        let s0 = (centre - o).dot(dn);
        let o = o + s0 * dn;
        let r = radius * (1.0 + 1e-4);
        if (o - centre).length_squared() > r * r {
            return None;
        }
        Some(LocalRay {
            o,
            d: dn,
            s0,
            inv_len: 1.0 / len,
        })
    }

    #[inline]
    fn t(&self, u: f32) -> f32 {
        (self.s0 + u) * self.inv_len
    }

    #[inline]
    fn at(&self, u: f32) -> Vec3A {
        self.o + u * self.d
    }

    /// Entry and exit parameters of the sphere (centre, r).
    #[inline]
    fn sphere(&self, centre: Vec3A, r: f32) -> Option<(f32, f32)> {
        let oc = self.o - centre;
        let b = oc.dot(self.d);
        let q = oc - b * self.d;
        let h2 = r * r - q.length_squared();
        if h2 < 0.0 {
            return None;
        }
        let h = h2.sqrt();
        Some((-b - h, -b + h))
    }

    /// Entry and exit parameters of the infinite cylinder of radius r
    /// around x; unbounded when the ray runs inside it parallel to x.
    #[inline]
    fn side(&self, r: f32) -> Option<(f32, f32)> {
        let (o, d) = (self.o, self.d);
        let a = d.y * d.y + d.z * d.z;
        if a == 0.0 {
            return (o.y * o.y + o.z * o.z <= r * r).then_some((f32::NEG_INFINITY, f32::INFINITY));
        }
        let k = (o.y * d.y + o.z * d.z) / a;
        let (qy, qz) = (o.y - k * d.y, o.z - k * d.z);
        let h2 = r * r - (qy * qy + qz * qz);
        if h2 < 0.0 {
            return None;
        }
        let h = (h2 / a).sqrt();
        Some((-k - h, -k + h))
    }

    /// Entry and exit parameters of the slab lo ≤ x ≤ hi.
    #[inline]
    fn slab(&self, lo: f32, hi: f32) -> Option<(f32, f32)> {
        let (ox, dx) = (self.o.x, self.d.x);
        if dx == 0.0 {
            return (lo..=hi)
                .contains(&ox)
                .then_some((f32::NEG_INFINITY, f32::INFINITY));
        }
        let (a, b) = ((lo - ox) / dx, (hi - ox) / dx);
        Some(if dx > 0.0 { (a, b) } else { (b, a) })
    }
}

/// Unit direction and length of d, also for lengths whose square
/// under- or overflows.
#[inline]
fn unit_dir(d: Vec3A) -> Option<(Vec3A, f32)> {
    let l2 = d.length_squared();
    if (1e-30..=1e30).contains(&l2) {
        let len = l2.sqrt();
        return Some((d / len, len));
    }
    let m = d.abs().max_element();
    if !(m > 0.0 && m.is_finite()) {
        return None;
    }
    let ds = d / m;
    let l = ds.length();
    Some((ds / l, m * l))
}

#[inline]
fn unit_sphere(o: Vec3A, d: Vec3A, tmin: f32, tmax: f32) -> Option<LocalHit> {
    let ray = LocalRay::near(o, d, Vec3A::ZERO, 1.0)?;
    let (u0, u1) = ray.sphere(Vec3A::ZERO, 1.0)?;
    [u0, u1].into_iter().find_map(|u| {
        let t = ray.t(u);
        in_range(t, tmin, tmax).then(|| LocalHit {
            t,
            normal: ray.at(u),
        })
    })
}

#[inline]
fn cylinder(o: Vec3A, d: Vec3A, tmin: f32, tmax: f32) -> Option<LocalHit> {
    // Centre (½,0,0); the rims are √(1¼) away.
    let ray = LocalRay::near(o, d, Vec3A::new(0.5, 0.0, 0.0), 1.118_034)?;
    let (s0, s1) = ray.side(1.0)?;
    let (x0, x1) = ray.slab(0.0, 1.0)?;
    let (u0, cap0) = if x0 > s0 { (x0, true) } else { (s0, false) };
    let (u1, cap1) = if x1 < s1 { (x1, true) } else { (s1, false) };
    if u0 > u1 {
        return None;
    }
    [(u0, cap0, -1.0), (u1, cap1, 1.0)]
        .into_iter()
        .find_map(|(u, cap, sign)| {
            let t = ray.t(u);
            in_range(t, tmin, tmax).then(|| {
                let normal = if cap {
                    Vec3A::new(sign * ray.d.x.signum(), 0.0, 0.0)
                } else {
                    let p = ray.at(u);
                    Vec3A::new(0.0, p.y, p.z)
                };
                LocalHit { t, normal }
            })
        })
}

/// The capsule is convex and lies inside the infinite cylinder around its
/// axis: where the ray enters (leaves) that cylinder tells whether it
/// enters (leaves) the capsule through the side or through the sphere at
/// that end (Quílez's capsule test). A miss of that sphere is a miss.
#[inline]
fn capsule(length: f32, o: Vec3A, d: Vec3A, tmin: f32, tmax: f32) -> Option<LocalHit> {
    if !valid_capsule(length) {
        return None;
    }
    let half = 0.5 * length;
    let ray = LocalRay::near(o, d, Vec3A::new(half, 0.0, 0.0), half + 1.0)?;
    let (s0, s1) = ray.side(1.0)?;
    // The capsule's crossing where the cylinder's is at u; parallel rays
    // (u infinite) land on the sphere ahead or behind.
    let crossing = |u: f32, entry: bool| {
        let x = ray.o.x + u * ray.d.x;
        if (0.0..=length).contains(&x) {
            let p = ray.at(u);
            return Some((u, Vec3A::new(0.0, p.y, p.z)));
        }
        let c = Vec3A::new(if x < 0.0 { 0.0 } else { length }, 0.0, 0.0);
        let (u0, u1) = ray.sphere(c, 1.0)?;
        let u = if entry { u0 } else { u1 };
        Some((u, ray.at(u) - c))
    };
    let (u, normal) = crossing(s0, true)?;
    let t = ray.t(u);
    if in_range(t, tmin, tmax) {
        return Some(LocalHit { t, normal });
    }
    let (u, normal) = crossing(s1, false)?;
    let t = ray.t(u);
    in_range(t, tmin, tmax).then_some(LocalHit { t, normal })
}

/// How far (relative to the trunk's size) a crossing may lie inside another
/// piece and still count, so rounding cannot open a seam.
const SEAM: f32 = 4e-6;

/// The union of a sphere of radius r0 at 0, a cone frustum from r0 at 0 to
/// r1 at `length`, and a sphere of radius r1 at `length`. It is not convex
/// (grooves where a sphere dips under the cone), so every crossing of each
/// piece's surface is a candidate and counts only if it does not lie inside
/// another piece; a small margin keeps the seams closed. The frustum's end
/// disks lie inside the spheres and are never visible.
#[inline]
fn trunk(
    length: f32,
    r0: f32,
    r1: f32,
    o: Vec3A,
    d: Vec3A,
    tmin: f32,
    tmax: f32,
) -> Option<LocalHit> {
    if !valid_trunk(length, r0, r1) {
        return None;
    }
    let r = r0.max(r1);
    let (lo, hi) = ((-r0).min(length - r1), r0.max(length + r1));
    let half = 0.5 * (hi - lo);
    let radius = (half * half + r * r).sqrt();
    let ray = LocalRay::near(o, d, Vec3A::new(lo + half, 0.0, 0.0), radius)?;

    let eps = SEAM * radius;
    let end = Vec3A::new(length, 0.0, 0.0);
    // Radius slope, and the factor turning a radial gap into a distance.
    // A cone too short for them is a disk inside the larger sphere.
    let s = (r1 - r0) / length;
    let w = (1.0 + s * s).sqrt();
    let cone = length > 0.0 && w.is_finite();
    let s = if cone { s } else { 0.0 };
    let in_sphere =
        |p: Vec3A, c: Vec3A, r: f32| r > eps && (p - c).length_squared() < (r - eps) * (r - eps);
    let in_frustum = |p: Vec3A| {
        cone && p.x > eps && p.x < length - eps && {
            let rho = (p.y * p.y + p.z * p.z).sqrt();
            r0 + s * p.x - rho > eps * w
        }
    };

    let mut best = Nearest {
        hit: None,
        tmin,
        tmax,
    };
    if r0 > 0.0 {
        if let Some(span) = ray.sphere(Vec3A::ZERO, r0) {
            best.offer(&ray, span, 0.0, |p| {
                (!in_frustum(p) && !in_sphere(p, end, r1)).then_some(p)
            });
        }
    }
    if r1 > 0.0 {
        if let Some(span) = ray.sphere(end, r1) {
            best.offer(&ray, span, 0.0, |p| {
                (!in_frustum(p) && !in_sphere(p, Vec3A::ZERO, r0)).then_some(p - end)
            });
        }
    }
    if cone {
        // y² + z² = (r0 + s·x)² along the ray: a·u² + 2b·u + c = 0.
        let (o, d) = (ray.o, ray.d);
        let (k, kd) = (r0 + s * o.x, s * d.x);
        let a = d.y * d.y + d.z * d.z - kd * kd;
        let b = o.y * d.y + o.z * d.z - k * kd;
        let c = o.y * o.y + o.z * o.z - k * k;
        let disc = b * b - a * c;
        if disc >= 0.0 {
            // Stable roots; a = 0 (ray along the cone's slope) leaves the
            // one finite root c/q, and the other turns infinite.
            let q = -(b + disc.sqrt().copysign(b));
            let (ua, ub) = (q / a, c / q);
            let lead = eps * ray.inv_len;
            best.offer(&ray, (ua.min(ub), ua.max(ub)), lead, |p| {
                ((0.0..=length).contains(&p.x)
                    && !in_sphere(p, Vec3A::ZERO, r0)
                    && !in_sphere(p, end, r1))
                .then(|| Vec3A::new(-s * (r0 + s * p.x).max(0.0), p.y, p.z))
            });
        }
    }
    best.hit
}

/// The nearest visible crossing so far of a trunk.
struct Nearest {
    hit: Option<LocalHit>,
    tmin: f32,
    tmax: f32,
}

impl Nearest {
    /// Offers the crossings at u0 ≤ u1; `visible` gives the normal of a
    /// crossing on the outer surface. A crossing must come `lead` before
    /// the nearest so far: where the cone meets a sphere at a rim, the
    /// sphere's normal is the right one.
    #[inline]
    fn offer(
        &mut self,
        ray: &LocalRay,
        (u0, u1): (f32, f32),
        lead: f32,
        visible: impl Fn(Vec3A) -> Option<Vec3A>,
    ) {
        let bound = self.hit.map_or(self.tmax, |h| h.t - lead);
        for u in [u0, u1] {
            let t = ray.t(u);
            if t > self.tmin && t < bound {
                if let Some(normal) = visible(ray.at(u)) {
                    self.hit = Some(LocalHit { t, normal });
                    return;
                }
            }
        }
    }
}
