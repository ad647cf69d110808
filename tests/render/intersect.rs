//! Exact ray intersection against brute force: every shape is described
//! again as a signed distance function (in f64), the reference marches
//! along the ray to the first sign change and bisects it, and the normal is
//! the function's finite-difference gradient there.

use glam::{Affine3A, DVec3, Mat3, Vec3, Vec3A};
use lmfilm::aabb::Aabb;
use lmfilm::render::accel::shapes::*;
use lmfilm::render::accel::tri4::triangle;
use lmfilm::scene::*;

/// xorshift64*, so the rays are the same on every run.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_f491_4f6c_dd1d)
    }

    /// Uniform in [0, 1).
    fn f(&mut self) -> f32 {
        (self.next() >> 40) as f32 / (1u64 << 24) as f32
    }

    fn range(&mut self, a: f32, b: f32) -> f32 {
        a + (b - a) * self.f()
    }

    fn vec(&mut self, lo: Vec3A, hi: Vec3A) -> Vec3A {
        Vec3A::new(
            self.range(lo.x, hi.x),
            self.range(lo.y, hi.y),
            self.range(lo.z, hi.z),
        )
    }

    fn unit(&mut self) -> Vec3A {
        loop {
            let v = self.vec(Vec3A::splat(-1.0), Vec3A::ONE);
            let l = v.length();
            if (0.1..=1.0).contains(&l) {
                return v / l;
            }
        }
    }
}

const KINDS: [ShapeKind; 12] = [
    ShapeKind::Box,
    ShapeKind::Sphere,
    ShapeKind::Cylinder,
    ShapeKind::Capsule { length: 1.7 },
    ShapeKind::Capsule { length: 0.0 },
    ShapeKind::Trunk {
        length: 2.0,
        r0: 1.0,
        r1: 0.5,
    },
    ShapeKind::Trunk {
        length: 1.5,
        r0: 0.3,
        r1: 0.9,
    },
    // The big start sphere swallows most of the cone.
    ShapeKind::Trunk {
        length: 0.6,
        r0: 1.0,
        r1: 0.2,
    },
    // A pointed cone with a ball at its end.
    ShapeKind::Trunk {
        length: 2.0,
        r0: 0.0,
        r1: 0.6,
    },
    ShapeKind::Trunk {
        length: 1.0,
        r0: 0.7,
        r1: 0.7,
    },
    // Two concentric spheres: the larger shows.
    ShapeKind::Trunk {
        length: 0.0,
        r0: 0.5,
        r1: 1.0,
    },
    // Barely longer than the grooves are deep.
    ShapeKind::Trunk {
        length: 1e-3,
        r0: 0.8,
        r1: 0.3,
    },
];

fn d3(v: Vec3A) -> DVec3 {
    DVec3::new(v.x as f64, v.y as f64, v.z as f64)
}

/// Distance from q to the segment a–b in the (x, ρ) half-plane.
fn seg(q: (f64, f64), a: (f64, f64), b: (f64, f64)) -> f64 {
    let (ex, ey) = (b.0 - a.0, b.1 - a.1);
    let (px, py) = (q.0 - a.0, q.1 - a.1);
    let l2 = ex * ex + ey * ey;
    let h = if l2 > 0.0 {
        ((px * ex + py * ey) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    ((px - h * ex).powi(2) + (py - h * ey).powi(2)).sqrt()
}

/// Signed distance (negative inside) to the frustum solid, from its
/// meridian section; the axis edge is no surface.
fn frustum(p: DVec3, l: f64, r0: f64, r1: f64) -> f64 {
    let q = (p.x, (p.y * p.y + p.z * p.z).sqrt());
    let d = seg(q, (0.0, 0.0), (0.0, r0))
        .min(seg(q, (0.0, r0), (l, r1)))
        .min(seg(q, (l, r1), (l, 0.0)));
    let inside = (0.0..=l).contains(&q.0) && q.1 <= r0 + (r1 - r0) * q.0 / l;
    if inside {
        -d
    } else {
        d
    }
}

/// Signed distance to the unit shape: exact for each piece, a lower bound
/// of the distance for the trunk's union, so stepping by it never skips a
/// surface.
fn sdf(kind: ShapeKind, p: DVec3) -> f64 {
    match kind {
        ShapeKind::Box => {
            let q = (p - DVec3::new(0.5, 0.0, 0.0)).abs() - DVec3::splat(0.5);
            q.max(DVec3::ZERO).length() + q.max_element().min(0.0)
        }
        ShapeKind::Sphere => p.length() - 1.0,
        ShapeKind::Cylinder => {
            let dx = (p.x - 0.5).abs() - 0.5;
            let dr = (p.y * p.y + p.z * p.z).sqrt() - 1.0;
            dx.max(dr).min(0.0) + (dx.max(0.0).powi(2) + dr.max(0.0).powi(2)).sqrt()
        }
        ShapeKind::Capsule { length } => {
            let x = p.x.clamp(0.0, length as f64);
            (p - DVec3::new(x, 0.0, 0.0)).length() - 1.0
        }
        ShapeKind::Trunk { length, r0, r1 } => {
            let (l, r0, r1) = (length as f64, r0 as f64, r1 as f64);
            let s = (p.length() - r0).min((p - DVec3::new(l, 0.0, 0.0)).length() - r1);
            if l > 0.0 {
                s.min(frustum(p, l, r0, r1))
            } else {
                s
            }
        }
    }
}

fn grad(kind: ShapeKind, p: DVec3, h: f64) -> DVec3 {
    let f = |e: DVec3| (sdf(kind, p + e) - sdf(kind, p - e)) / (2.0 * h);
    DVec3::new(f(DVec3::X * h), f(DVec3::Y * h), f(DVec3::Z * h))
}

/// The outward normal at a surface point, or None near an edge or seam
/// where differences at two scales disagree.
fn ref_normal(kind: ShapeKind, p: DVec3) -> Option<DVec3> {
    let (a, b) = (grad(kind, p, 1e-5), grad(kind, p, 1e-4));
    let ok = (a.length() - 1.0).abs() < 0.02 && a.normalize().dot(b.normalize()) > 0.9999;
    ok.then(|| a.normalize())
}

/// First surface crossing of o + t·d with t in (tmin, tmax): steps by the
/// distance bound (at least `FLOOR` long), then bisects the sign change.
fn reference(kind: ShapeKind, o: DVec3, d: DVec3, tmin: f64, tmax: f64) -> Option<f64> {
    const FLOOR: f64 = 4e-4;
    let Aabb { min: lo, max: hi } = local_bounds(kind);
    let (lo, hi) = (d3(lo) - 0.01, d3(hi) + 0.01);
    let (mut t0, mut t1) = (tmin, tmax);
    for i in 0..3 {
        if d[i] == 0.0 {
            if o[i] < lo[i] || o[i] > hi[i] {
                return None;
            }
            continue;
        }
        let (a, b) = ((lo[i] - o[i]) / d[i], (hi[i] - o[i]) / d[i]);
        t0 = t0.max(a.min(b));
        t1 = t1.min(a.max(b));
    }
    if t0 >= t1 {
        return None;
    }
    let dl = d.length();
    let f = |t: f64| sdf(kind, o + t * d);
    let inside = f(t0) < 0.0;
    let mut t = t0;
    let mut ft = f(t0);
    loop {
        let tn = (t + ft.abs().max(FLOOR) / dl).min(t1);
        let fnext = f(tn);
        if (fnext < 0.0) != inside {
            let (mut a, mut b) = (t, tn);
            for _ in 0..80 {
                let m = 0.5 * (a + b);
                if (f(m) < 0.0) == inside {
                    a = m;
                } else {
                    b = m;
                }
            }
            return Some(b);
        }
        if tn >= t1 {
            return None;
        }
        (t, ft) = (tn, fnext);
    }
}

#[derive(Default)]
struct Tally {
    rays: usize,
    hits: usize,
    bad: usize,
    normals_checked: usize,
    max_err: f64,
}

/// Compares one ray; returns a description of a disagreement.
fn compare(
    kind: ShapeKind,
    o: Vec3A,
    d: Vec3A,
    tmin: f32,
    tmax: f32,
    tally: &mut Tally,
) -> Option<String> {
    tally.rays += 1;
    let got = shape(kind, o, d, tmin, tmax);
    let want = reference(kind, d3(o), d3(d), tmin as f64, tmax as f64);
    let dl = d3(d).length();
    match (got, want) {
        (None, None) => None,
        (Some(h), Some(t)) => {
            tally.hits += 1;
            if !(h.t > tmin && h.t < tmax) {
                return Some(format!("t {} outside ({tmin}, {tmax})", h.t));
            }
            let err = (h.t as f64 - t).abs() * dl / (t * dl).max(1.0);
            tally.max_err = tally.max_err.max(err);
            if err > 1e-3 {
                return Some(format!("t {} vs reference {t}", h.t));
            }
            if let Some(n) = ref_normal(kind, d3(o) + t * d3(d)) {
                tally.normals_checked += 1;
                let cos = d3(h.normal).normalize().dot(n);
                if cos.is_nan() || cos <= 0.99 {
                    return Some(format!("normal {} vs reference {n} (cos {cos})", h.normal));
                }
            }
            None
        }
        (g, w) => Some(format!("hit {g:?} vs reference {w:?}")),
    }
}

fn check(kind: ShapeKind, tally: &Tally, failures: &[String], budget: f64) {
    let allowed = (budget * tally.rays as f64).floor() as usize;
    println!(
        "{kind:?}: {} rays, {} hits, {} normals checked, {} disagreements, max t error {:.2e}",
        tally.rays, tally.hits, tally.normals_checked, tally.bad, tally.max_err
    );
    assert!(
        tally.bad <= allowed,
        "{kind:?}: {} of {} rays disagree, e.g. {:#?}",
        tally.bad,
        tally.rays,
        &failures[..failures.len().min(8)]
    );
}

#[test]
fn shapes_match_brute_force_from_anywhere() {
    let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
    for kind in KINDS {
        let Aabb { min: lo, max: hi } = local_bounds(kind);
        let mut tally = Tally::default();
        let mut failures = Vec::new();
        for i in 0..4000 {
            let o = rng.vec(lo - 1.5, hi + 1.5);
            let dir = if i % 10 == 0 {
                rng.unit()
            } else {
                rng.vec(lo, hi) - o
            };
            if dir.length() < 1e-3 {
                continue;
            }
            // Any length: the caller's rays come through a scaling inverse.
            let scale = 10f32.powf(rng.range(-2.0, 2.0));
            let d = dir.normalize() * scale;
            let (tmin, tmax) = match i % 4 {
                0 => (0.0, f32::INFINITY),
                1 => (rng.range(0.0, 2.0) / scale, f32::INFINITY),
                2 => (0.0, rng.range(0.5, 4.0) / scale),
                _ => (1e-4 / scale, 1e30),
            };
            if let Some(f) = compare(kind, o, d, tmin, tmax, &mut tally) {
                tally.bad += 1;
                failures.push(format!("o {o} d {d} ({tmin}, {tmax}): {f}"));
            }
        }
        assert!(tally.hits > 1000, "{kind:?}: too few hits to mean much");
        check(kind, &tally, &failures, 0.005);
    }
}

#[test]
fn rays_from_inside_find_the_exit() {
    let mut rng = Rng(0x2545_f491_4f6c_dd1d);
    for kind in KINDS {
        let Aabb { min: lo, max: hi } = local_bounds(kind);
        let mut tally = Tally::default();
        let mut failures = Vec::new();
        for _ in 0..2000 {
            let o = loop {
                let p = rng.vec(lo, hi);
                if sdf(kind, d3(p)) < -0.01 {
                    break p;
                }
            };
            let d = rng.unit() * 10f32.powf(rng.range(-2.0, 2.0));
            let fail = match shape(kind, o, d, 0.0, f32::INFINITY) {
                None => Some("no exit".to_string()),
                Some(h) if h.normal.dot(d).is_nan() || h.normal.dot(d) <= 0.0 => {
                    Some(format!("inward normal {}", h.normal))
                }
                Some(_) => compare(kind, o, d, 0.0, f32::INFINITY, &mut tally),
            };
            if let Some(f) = fail {
                tally.bad += 1;
                failures.push(format!("o {o} d {d}: {f}"));
            }
        }
        check(kind, &tally, &failures, 0.001);
    }
}

/// The same ray scaled by any factor meets the shape at the same point.
#[test]
fn direction_length_does_not_matter() {
    let mut rng = Rng(7);
    for kind in KINDS {
        let Aabb { min: lo, max: hi } = local_bounds(kind);
        let mut hits = 0;
        for _ in 0..200 {
            let o = rng.vec(lo - 2.0, hi + 2.0);
            let d = (rng.vec(lo, hi) - o).normalize();
            let Some(base) = shape(kind, o, d, 0.0, f32::INFINITY) else {
                continue;
            };
            hits += 1;
            for k in [1e-25f32, 1e-12, 1e-3, 1e3, 1e12, 1e25] {
                let h = shape(kind, o, d * k, 0.0, f32::INFINITY)
                    .unwrap_or_else(|| panic!("{kind:?}: scale {k} misses"));
                let err = (h.t * k - base.t).abs();
                assert!(
                    err <= 1e-4 * base.t.max(1.0),
                    "{kind:?} scale {k}: {} vs {}",
                    h.t * k,
                    base.t
                );
            }
        }
        assert!(hits > 50, "{kind:?}");
    }
}

/// The caller maps a world ray by the inverse transform and keeps t.
#[test]
fn transformed_rays_keep_world_t() {
    let m = Affine3A::from_scale_rotation_translation(
        Vec3::new(2.0, 0.5, 1.5),
        glam::Quat::from_euler(glam::EulerRot::XYZ, 0.3, -0.7, 1.1),
        Vec3::new(3.0, -1.0, 2.0),
    );
    let inv = m.inverse();
    let mut rng = Rng(99);
    let mut hits = 0;
    for _ in 0..500 {
        let o = rng.vec(Vec3A::splat(-6.0), Vec3A::splat(8.0));
        let d = (m.transform_point3a(rng.unit() * 0.9) - o) * rng.range(0.1, 3.0);
        let (lo, ld) = (inv.transform_point3a(o), inv.transform_vector3a(d));
        let h = shape(ShapeKind::Sphere, lo, ld, 0.0, f32::INFINITY).expect("aimed inside");
        hits += 1;
        // The world point lies on the ellipsoid.
        let p = inv.transform_point3a(o + h.t * d);
        assert!((p.length() - 1.0).abs() < 1e-4, "{p}");
    }
    assert_eq!(hits, 500);
}

#[test]
fn degenerate_shapes_and_rays_never_hit() {
    let bad = [
        ShapeKind::Capsule { length: f32::NAN },
        ShapeKind::Capsule { length: -1.0 },
        ShapeKind::Capsule {
            length: f32::INFINITY,
        },
        ShapeKind::Trunk {
            length: f32::NAN,
            r0: 1.0,
            r1: 1.0,
        },
        ShapeKind::Trunk {
            length: -1.0,
            r0: 1.0,
            r1: 1.0,
        },
        ShapeKind::Trunk {
            length: 1.0,
            r0: -1.0,
            r1: 1.0,
        },
        ShapeKind::Trunk {
            length: 1.0,
            r0: 1.0,
            r1: f32::NAN,
        },
        ShapeKind::Trunk {
            length: 1.0,
            r0: 0.0,
            r1: 0.0,
        },
        ShapeKind::Trunk {
            length: 1.0,
            r0: f32::INFINITY,
            r1: 1.0,
        },
    ];
    let mut rng = Rng(3);
    for kind in bad {
        for _ in 0..200 {
            let o = rng.vec(Vec3A::splat(-3.0), Vec3A::splat(3.0));
            let d = rng.unit();
            assert_eq!(shape(kind, o, d, 0.0, f32::INFINITY), None, "{kind:?}");
        }
        let Aabb { min: lo, max: hi } = local_bounds(kind);
        assert!(!(lo.is_finite() && hi.is_finite()), "{kind:?}");
    }
    let o = Vec3A::new(-3.0, 0.1, 0.05);
    for kind in KINDS {
        assert!(
            shape(kind, o, Vec3A::X, 0.0, f32::INFINITY).is_some(),
            "{kind:?}"
        );
        for (o, d) in [
            (o, Vec3A::ZERO),
            (o, Vec3A::new(f32::NAN, 0.0, 0.0)),
            (o, Vec3A::new(f32::INFINITY, 0.0, 0.0)),
            (Vec3A::new(f32::NAN, 0.0, 0.0), Vec3A::X),
            (Vec3A::new(f32::NEG_INFINITY, 0.0, 0.0), Vec3A::X),
        ] {
            assert_eq!(
                shape(kind, o, d, 0.0, f32::INFINITY),
                None,
                "{kind:?} {o} {d}"
            );
        }
        assert_eq!(shape(kind, o, Vec3A::X, f32::NAN, f32::INFINITY), None);
        assert_eq!(shape(kind, o, Vec3A::X, 0.0, f32::NAN), None);
        assert_eq!(shape(kind, o, Vec3A::X, 0.0, 0.5), None);
    }
}

/// Exact reference for a triangle in f64: the plane crossing t and the
/// smallest barycentric coordinate there (negative outside).
fn ref_triangle(v: &[Vec3; 3], o: DVec3, d: DVec3) -> Option<(f64, f64)> {
    let [a, b, c] = v.map(|p| p.as_dvec3());
    let n = (b - a).cross(c - a);
    let t = n.dot(a - o) / n.dot(d);
    let p = o + t * d;
    let w = (b - p)
        .cross(c - p)
        .dot(n)
        .min((c - p).cross(a - p).dot(n))
        .min((a - p).cross(b - p).dot(n));
    t.is_finite().then_some((t, w / n.length_squared()))
}

#[test]
fn triangles_match_exact_reference() {
    let mut rng = Rng(11);
    let (mut rays, mut hits, mut bad) = (0, 0, Vec::new());
    for _ in 0..200 {
        let v: [Vec3; 3] = std::array::from_fn(|_| rng.vec(Vec3A::splat(-1.0), Vec3A::ONE).into());
        let normal = Vec3A::from((v[1] - v[0]).cross(v[2] - v[0]));
        for _ in 0..40 {
            rays += 1;
            let o = rng.vec(Vec3A::splat(-3.0), Vec3A::splat(3.0));
            // Aim at points of the plane in and a little around the triangle.
            let (s, t) = (rng.range(-0.2, 1.0), rng.range(-0.2, 1.0));
            let aim = Vec3A::from(v[0] + s * (v[1] - v[0]) + t * (v[2] - v[0]));
            let d = (aim - o) * 10f32.powf(rng.range(-2.0, 2.0));
            let got = triangle(&v, o, d, 0.0, f32::INFINITY);
            let r = ref_triangle(&v, d3(o), d3(d));
            let want = r.filter(|&(t, m)| t > 0.0 && m >= 0.0);
            // Rays through an edge may go either way.
            let edge = r.is_some_and(|(_, m)| m.abs() < 1e-5);
            match (got, want) {
                (Some(h), Some((t, _))) => {
                    hits += 1;
                    // Grazing rays pin t down less.
                    let cos = d3(normal).normalize().dot(d3(d).normalize());
                    let tol = 1e-5 * t.max(1.0 / d3(d).length()) / cos.abs();
                    assert!((h as f64 - t).abs() <= tol, "{h} vs {t} cos {cos}");
                }
                (None, None) => {}
                _ if edge => {}
                (g, w) => bad.push(format!("{v:?} o {o} d {d}: {g:?} vs {w:?}")),
            }
        }
    }
    assert!(hits > 2000, "{hits} of {rays}");
    assert!(
        bad.is_empty(),
        "{} of {rays}: {:#?}",
        bad.len(),
        &bad[..bad.len().min(5)]
    );
    // Ranges are open.
    let v = [Vec3::X, Vec3::Y, Vec3::Z];
    let o = Vec3A::ZERO;
    let d = Vec3A::ONE;
    let t = triangle(&v, o, d, 0.0, 1.0).expect("hit");
    assert!((t - 1.0 / 3.0).abs() < 1e-6);
    assert_eq!(triangle(&v, o, d, t, 1.0), None);
    assert_eq!(triangle(&v, o, d, 0.0, t), None);
    assert!(triangle(&v, o + 2.0 * d, -d, 0.0, 1.0).is_none());
    assert!(triangle(&v, o + 2.0 * d, -d, 0.0, 2.0).is_some());
    assert_eq!(triangle(&v, o, Vec3A::ZERO, 0.0, 1.0), None);
    assert_eq!(triangle(&v, o, Vec3A::splat(f32::NAN), 0.0, 1.0), None);
    assert_eq!(
        triangle(
            &[Vec3::X, Vec3::X * 2.0, Vec3::X * 3.0],
            o,
            Vec3A::X,
            0.0,
            9.0
        ),
        None
    );
}

/// A closed mesh stays closed: rays from inside through its edges and
/// vertices always find a triangle.
#[test]
fn triangles_are_watertight() {
    // An octahedron with perturbed vertices, so edges are not axis-aligned.
    let mut rng = Rng(5);
    let p: Vec<Vec3> = [Vec3::X, -Vec3::X, Vec3::Y, -Vec3::Y, Vec3::Z, -Vec3::Z]
        .iter()
        .map(|&a| {
            a * rng.range(0.7, 1.3) + Vec3::from(rng.vec(Vec3A::splat(-0.1), Vec3A::splat(0.1)))
        })
        .collect();
    let faces = [
        [0, 2, 4],
        [2, 1, 4],
        [1, 3, 4],
        [3, 0, 4],
        [2, 0, 5],
        [1, 2, 5],
        [3, 1, 5],
        [0, 3, 5],
    ];
    let tris: Vec<[Vec3; 3]> = faces.iter().map(|f| f.map(|i| p[i])).collect();
    let edges: Vec<(usize, usize)> = faces
        .iter()
        .flat_map(|f| [(f[0], f[1]), (f[1], f[2]), (f[2], f[0])])
        .collect();
    for i in 0..20000 {
        let o = rng.vec(Vec3A::splat(-0.2), Vec3A::splat(0.2));
        let aim = if i % 5 == 0 {
            Vec3A::from(p[i % 6])
        } else {
            let (a, b) = edges[i % edges.len()];
            Vec3A::from(p[a].lerp(p[b], rng.f()))
        };
        let d = aim - o;
        let n = tris
            .iter()
            .filter(|v| triangle(v, o, d, 0.0, f32::INFINITY).is_some())
            .count();
        assert!(n > 0, "ray {o} → {aim} slips through");
    }
}

fn random_transform(rng: &mut Rng) -> Affine3A {
    loop {
        let m = Mat3::from_cols(
            rng.vec(Vec3A::splat(-2.0), Vec3A::splat(2.0)).into(),
            rng.vec(Vec3A::splat(-2.0), Vec3A::splat(2.0)).into(),
            rng.vec(Vec3A::splat(-2.0), Vec3A::splat(2.0)).into(),
        );
        if m.determinant().abs() > 0.1 {
            let t = rng.vec(Vec3A::splat(-5.0), Vec3A::splat(5.0));
            return Affine3A::from_mat3_translation(m, t.into());
        }
    }
}

#[test]
fn bounds_contain_the_shape() {
    let mut rng = Rng(17);
    for kind in KINDS {
        let Aabb { min: lo, max: hi } = local_bounds(kind);
        for _ in 0..50 {
            let transform = random_transform(&mut rng);
            let s = Shape {
                kind,
                transform,
                material: 0,
                symbol: 0,
            };
            let Aabb { min, max } = bounds(&s).expect("finite");
            // Tight: the box around the 8 transformed corners.
            let corners = (0..8).map(|i| {
                let f = Vec3A::new((i & 1) as f32, ((i >> 1) & 1) as f32, ((i >> 2) & 1) as f32);
                transform.transform_point3a(lo + f * (hi - lo))
            });
            let (cmin, cmax) = corners.fold((Vec3A::INFINITY, Vec3A::NEG_INFINITY), |(a, b), c| {
                (a.min(c), b.max(c))
            });
            assert!(
                (cmin - min).abs().max_element() < 1e-4 && (cmax - max).abs().max_element() < 1e-4
            );
            let mut n = 0;
            while n < 200 {
                // Surface points too: push a sample out to the boundary.
                let p = rng.vec(lo, hi);
                if sdf(kind, d3(p)) > 0.0 {
                    continue;
                }
                n += 1;
                let w = transform.transform_point3(p.into());
                let w = Vec3A::from(w);
                assert!(
                    w.cmpge(min).all() && w.cmple(max).all(),
                    "{kind:?}: {w} outside {min}..{max}"
                );
            }
            for p in [lo, hi] {
                let w = Vec3A::from(transform.transform_point3(p.into()));
                assert!(
                    w.cmpge(min).all() && w.cmple(max).all(),
                    "{kind:?}: corner {w} outside"
                );
            }
        }
    }
}

#[test]
fn non_finite_bounds_are_none() {
    let shape_with = |transform: Affine3A, kind| Shape {
        kind,
        transform,
        material: 0,
        symbol: 0,
    };
    let mut nan = Affine3A::IDENTITY;
    nan.translation.y = f32::NAN;
    let mut inf = Affine3A::IDENTITY;
    inf.matrix3.x_axis.z = f32::INFINITY;
    let huge = Affine3A::from_scale_rotation_translation(
        Vec3::splat(f32::MAX),
        glam::Quat::IDENTITY,
        Vec3::splat(f32::MAX),
    );
    for kind in KINDS {
        assert!(bounds(&shape_with(Affine3A::IDENTITY, kind)).is_some());
        assert_eq!(bounds(&shape_with(nan, kind)), None, "{kind:?}");
        assert_eq!(bounds(&shape_with(inf, kind)), None, "{kind:?}");
        assert_eq!(bounds(&shape_with(huge, kind)), None, "{kind:?}");
    }
    let degenerate = ShapeKind::Trunk {
        length: -1.0,
        r0: 1.0,
        r1: 1.0,
    };
    assert_eq!(bounds(&shape_with(Affine3A::IDENTITY, degenerate)), None);
    assert_eq!(
        bounds(&shape_with(
            Affine3A::IDENTITY,
            ShapeKind::Capsule { length: f32::NAN }
        )),
        None
    );

    let v = [
        Vec3::ZERO,
        Vec3::new(1.0, -2.0, 0.5),
        Vec3::new(-1.0, 3.0, 2.0),
    ];
    assert_eq!(
        triangle_bounds(&v),
        Some(Aabb::new(
            Vec3A::new(-1.0, -2.0, 0.0),
            Vec3A::new(1.0, 3.0, 2.0)
        ))
    );
    for bad in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY] {
        let mut w = v;
        w[1].z = bad;
        assert_eq!(triangle_bounds(&w), None);
    }
}

/// Circles where two pieces of a trunk meet (x, ρ): the frustum's end rims
/// and its crossings with either sphere, and the spheres' crossing.
fn seams(length: f32, r0: f32, r1: f32) -> Vec<(f64, f64)> {
    let (l, r0, r1) = (length as f64, r0 as f64, r1 as f64);
    let t = (r0 - r1) / l;
    let u = 2.0 * t / (1.0 + t * t);
    let xs = [(0.0, r0), (l, r1)];
    let sphere = |c: f64, r: f64, x: f64| (x, (r * r - (x - c) * (x - c)).sqrt());
    let mut out = xs.to_vec();
    out.push(sphere(0.0, r0, r0 * u));
    out.push(sphere(l, r1, l + r1 * u));
    out.push(sphere(0.0, r0, (r0 * r0 - r1 * r1 + l * l) / (2.0 * l)));
    // A pointed end (r = 0) is no seam: rays may just touch the apex.
    out.retain(|&(x, r)| x.is_finite() && r.is_finite() && r > 0.0);
    out
}

/// Rays through the seams of a trunk neither slip through them from
/// outside nor leave through them too late from inside.
#[test]
fn trunk_seams_are_closed() {
    let mut rng = Rng(23);
    for kind in KINDS {
        let ShapeKind::Trunk { length, r0, r1 } = kind else {
            continue;
        };
        let Aabb { min: lo, max: hi } = local_bounds(kind);
        let mut tally = Tally::default();
        let mut failures = Vec::new();
        for (x, r) in seams(length, r0, r1) {
            for _ in 0..2000 {
                let a = rng.range(0.0, std::f32::consts::TAU);
                let s = Vec3A::new(x as f32, r as f32 * a.cos(), r as f32 * a.sin());
                let far = rng.vec(lo - 2.0, hi + 2.0);
                let tangent = grad(kind, d3(s), 1e-3)
                    .normalize()
                    .dot(d3(s - far).normalize())
                    .abs()
                    < 1e-2;
                if tangent {
                    continue;
                }
                if sdf(kind, d3(far)) > 0.01 {
                    // Aimed at a point of the closed solid: hits by then.
                    let d = (s - far) * rng.range(0.1, 10.0);
                    let ok = shape(kind, far, d, 0.0, f32::INFINITY)
                        .is_some_and(|h| (h.t - 1.0 / (d.length() / (s - far).length())) < 1e-4);
                    tally.rays += 1;
                    if !ok {
                        tally.bad += 1;
                        failures.push(format!("{far} → {s}: late or no hit"));
                    }
                } else if sdf(kind, d3(far)) < -0.01 {
                    // A ray through a groove only touches the surface
                    // there, so it may stop at t = 1 or go on.
                    let d = s - far;
                    let touch = shape(kind, far, d, 0.0, f32::INFINITY)
                        .is_some_and(|h| (h.t - 1.0).abs() < 1e-5);
                    if touch {
                        tally.rays += 1;
                    } else if let Some(f) = compare(kind, far, d, 0.0, f32::INFINITY, &mut tally) {
                        tally.bad += 1;
                        failures.push(format!("{far} → {s} from inside: {f}"));
                    }
                }
            }
        }
        check(kind, &tally, &failures, 0.0);
    }
}

/// A pack of four (or fewer) triangles finds what testing them one by one
/// finds: the nearest hit and its lane; padding lanes never hit; `hits`
/// agrees.
#[test]
fn triangle_packs_match_single_tests() {
    use lmfilm::render::accel::ray::Ray;
    use lmfilm::render::accel::tri4::Tri4;
    let mut rng = Rng(17);
    let mut hits = 0;
    for i in 0..3000 {
        let n = 1 + i % 4;
        let tris: Vec<[Vec3; 3]> = (0..n)
            .map(|_| std::array::from_fn(|_| rng.vec(Vec3A::splat(-1.0), Vec3A::ONE).into()))
            .collect();
        let o = rng.vec(Vec3A::splat(-3.0), Vec3A::splat(3.0));
        let d = rng.vec(Vec3A::splat(-0.5), Vec3A::splat(0.5)) - o;
        let tmax = rng.range(1.0, 4.0);
        let single = tris
            .iter()
            .enumerate()
            .filter_map(|(lane, v)| triangle(v, o, d, 0.0, tmax).map(|t| (t, lane)))
            .fold(None, |b: Option<(f32, usize)>, h| match b {
                Some(b) if b.0 <= h.0 => Some(b),
                _ => Some(h),
            });
        let pack = Tri4::pack(&tris);
        let ray = Ray::new(o, d, 0.0);
        let got = pack.intersect(&ray, tmax);
        assert_eq!(got, single, "ray {o} {d}");
        assert_eq!(pack.hits(&ray, tmax), got.is_some());
        hits += usize::from(got.is_some());
    }
    assert!(hits > 500, "{hits} hits");
}

/// Rays along an axis, from points beyond ±1, with no far limit: a grid
/// of boxes above and below is found exactly where a box is (their
/// slab distances once overflowed to NaN and the walk entered a node's
/// empty slots and panicked: the path tracer's sky rays).
#[test]
fn axis_rays_without_a_far_limit() {
    use lmfilm::render::Accel;
    let shapes: Vec<Shape> = (0..100)
        .map(|k| Shape {
            kind: ShapeKind::Box,
            // The unit box [0,1] × [−½,½]², moved to cell (x, z) at y = 10.
            transform: Affine3A::from_translation(Vec3::new(
                (k % 10) as f32 * 3.0,
                10.0,
                (k / 10) as f32 * 3.0 + 0.5,
            )),
            material: 0,
            symbol: k,
        })
        .collect();
    let scene = Scene {
        frame: 0,
        time: 0.0,
        camera: Camera {
            eye: Vec3::ZERO,
            look_at: Vec3::NEG_Z,
            twist: 0.0,
            fov_y: 50.0,
            aspect: 1.0,
            near: 0.1,
            far: 1e4,
            width: 8,
            height: 8,
            lens: Lens::default(),
        },
        lights: Vec::new(),
        materials: material::table(),
        geometries: vec![Geometry {
            name: "grid".into(),
            shapes,
            triangles: Vec::new(),
            resolution: 8,
        }],
        instances: vec![Instance {
            geometry: 0,
            transform: Affine3A::IDENTITY,
            object: 0,
        }],
        background: Vec3::ZERO,
        sky: Sky::Gradient,
    };
    let accel = Accel::new(scene);
    for k in 0..100 {
        let (x, z) = ((k % 10) as f32 * 3.0, (k / 10) as f32 * 3.0 + 0.5);
        for (dx, inside) in [(0.5, true), (1.5, false), (-0.7, false)] {
            for (y, dir) in [(-7.0, Vec3A::Y), (27.0, Vec3A::NEG_Y)] {
                let o = Vec3A::new(x + dx, y, z);
                let hit = accel.cast(o, dir, 0.0, f32::INFINITY);
                assert_eq!(
                    accel.occluded(o, dir, 0.0, f32::INFINITY),
                    inside,
                    "{o} {dir}"
                );
                assert_eq!(hit.is_some(), inside, "{o} {dir}");
                if let Some(h) = hit {
                    // Both ways the box's near face is 16.5 away.
                    assert!((h.t - 16.5).abs() < 1e-4, "{o} {dir}: t {}", h.t);
                }
            }
        }
    }
}
