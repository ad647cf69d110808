//! Tessellation of the analytic shapes, for exports (OBJ) that only know
//! triangles. The renderer intersects shapes exactly and never uses this.
//!
//! Every round shape is a solid of revolution around the local x axis (the
//! turtle's heading), so it is built from a profile `(x, r)` swept around x.
//! Ring vertices are computed once and shared by both neighbouring bands,
//! so the meshes are closed with bit-identical positions along every edge.

use std::f64::consts::PI;

use glam::{Affine3A, Vec3};

use super::{Scene, Shape, ShapeKind, Triangle};

/// Appends triangles approximating `shape` in its geometry's coordinates
/// (`shape.transform` applied), counter-clockwise seen from outside.
///
/// `resolution` is the number of segments around the axis (at least 3);
/// spheres get `resolution / 2` (at least 2) bands from pole to pole, and
/// sphere caps the same density. Circle vertices sit at angles 2πk/n from
/// +y towards +z. A `Trunk` is tessellated as the true union of its cone
/// frustum and its two end spheres (one closed surface). Negative or NaN
/// lengths and radii count as 0, so bad input gives empty or flat meshes,
/// never a panic.
pub fn tessellate(shape: &Shape, resolution: u32, out: &mut Vec<Triangle>) {
    let n = resolution.max(3) as usize;
    let bands = (resolution / 2).max(2) as usize;
    let start = out.len();
    match shape.kind {
        ShapeKind::Box => push_box(shape, out),
        ShapeKind::Cylinder => {
            let profile = [(0.0, 0.0), (0.0, 1.0), (1.0, 1.0), (1.0, 0.0)];
            lathe(&profile, n, shape, out);
        }
        ShapeKind::Sphere => lathe(&union_profile(0.0, 1.0, 1.0, bands), n, shape, out),
        ShapeKind::Capsule { length } => lathe(
            &union_profile(length.into(), 1.0, 1.0, bands),
            n,
            shape,
            out,
        ),
        ShapeKind::Trunk { length, r0, r1 } => {
            let profile = union_profile(length.into(), r0.into(), r1.into(), bands);
            lathe(&profile, n, shape, out)
        }
    }
    fix_winding(&mut out[start..], &shape.transform);
}

/// All triangles of `scene` in world coordinates: for each instance (in
/// order) its geometry's shapes tessellated at the geometry's resolution,
/// then its triangles, moved by the instance transform. Instances naming a
/// missing geometry are skipped.
pub fn expand(scene: &Scene) -> Vec<Triangle> {
    let mut out = Vec::new();
    let mut local = Vec::new();
    for inst in &scene.instances {
        let Some(g) = scene.geometries.get(inst.geometry as usize) else {
            continue;
        };
        local.clear();
        for s in &g.shapes {
            tessellate(s, g.resolution, &mut local);
        }
        local.extend_from_slice(&g.triangles);
        let start = out.len();
        out.extend(local.iter().map(|t| Triangle {
            v: t.v.map(|p| inst.transform.transform_point3(p)),
            ..*t
        }));
        fix_winding(&mut out[start..], &inst.transform);
    }
    out
}

/// How many triangles [`expand`] makes, without keeping them: each
/// shared geometry is tessellated once, one shape at a time, so an
/// export can be refused before its triangles are allocated.
pub fn expanded_count(scene: &Scene) -> u64 {
    let mut per_geometry: Vec<Option<u64>> = vec![None; scene.geometries.len()];
    let mut scratch = Vec::new();
    let mut total = 0u64;
    for inst in &scene.instances {
        let k = inst.geometry as usize;
        let (Some(g), Some(count)) = (scene.geometries.get(k), per_geometry.get_mut(k)) else {
            continue;
        };
        total += *count.get_or_insert_with(|| {
            let shapes: u64 = g
                .shapes
                .iter()
                .map(|s| {
                    scratch.clear();
                    tessellate(s, g.resolution, &mut scratch);
                    scratch.len() as u64
                })
                .sum();
            shapes + g.triangles.len() as u64
        });
    }
    total
}

/// A mirroring transform turns counter-clockwise into clockwise; swapping
/// two vertices keeps the normals pointing outwards.
fn fix_winding(tris: &mut [Triangle], transform: &Affine3A) {
    if transform.matrix3.determinant() < 0.0 {
        for t in tris {
            t.v.swap(1, 2);
        }
    }
}

/// The 12 triangles of [0,1]×[−½,½]×[−½,½].
fn push_box(shape: &Shape, out: &mut Vec<Triangle>) {
    // Corner i has x = bit 0, y = bit 1, z = bit 2.
    let c: [Vec3; 8] = std::array::from_fn(|i| {
        let local = Vec3::new(
            (i & 1) as f32,
            ((i >> 1) & 1) as f32 - 0.5,
            ((i >> 2) & 1) as f32 - 0.5,
        );
        shape.transform.transform_point3(local)
    });
    // Faces as quads, counter-clockwise seen from outside: −x, +x, −y, +y, −z, +z.
    const QUADS: [[usize; 4]; 6] = [
        [0, 4, 6, 2],
        [1, 3, 7, 5],
        [0, 1, 5, 4],
        [2, 6, 7, 3],
        [0, 2, 3, 1],
        [4, 5, 7, 6],
    ];
    for q in QUADS {
        push(out, shape, [c[q[0]], c[q[1]], c[q[2]]]);
        push(out, shape, [c[q[0]], c[q[2]], c[q[3]]]);
    }
}

fn push(out: &mut Vec<Triangle>, shape: &Shape, v: [Vec3; 3]) {
    out.push(Triangle {
        v,
        material: shape.material,
        symbol: shape.symbol,
    });
}

/// Sweeps the profile `(x, r)` around x with `n` segments. The profile runs
/// from the axis at its start to the axis at its end with the solid on the
/// axis side, which makes the triangles counter-clockwise from outside.
fn lathe(profile: &[(f64, f64)], n: usize, shape: &Shape, out: &mut Vec<Triangle>) {
    let (sin, cos): (Vec<f64>, Vec<f64>) = (0..n)
        .map(|k| (2.0 * PI * k as f64 / n as f64).sin_cos())
        .unzip();
    // One ring per profile point; a point on the axis is a single pole vertex.
    let rings: Vec<Vec<Vec3>> = profile
        .iter()
        .map(|&(x, r)| {
            let count = if r > 0.0 { n } else { 1 };
            (0..count)
                .map(|k| {
                    let local = Vec3::new(x as f32, (r * cos[k]) as f32, (r * sin[k]) as f32);
                    shape.transform.transform_point3(local)
                })
                .collect()
        })
        .collect();
    for (i, w) in profile.windows(2).enumerate() {
        let (a, b) = (&rings[i], &rings[i + 1]);
        if w[0] == w[1] || (a.len() == 1 && b.len() == 1) {
            continue;
        }
        for k in 0..n {
            let k1 = (k + 1) % n;
            match (a.len(), b.len()) {
                (1, _) => push(out, shape, [a[0], b[k1], b[k]]),
                (_, 1) => push(out, shape, [a[k], a[k1], b[0]]),
                _ => {
                    push(out, shape, [a[k], a[k1], b[k1]]);
                    push(out, shape, [a[k], b[k1], b[k]]);
                }
            }
        }
    }
}

/// Profile of the union of a sphere of radius `r0` at x = 0, a cone frustum
/// from radius `r0` at 0 to `r1` at `length`, and a sphere of radius `r1` at
/// `length`: the largest of the three radii at each sampled x. Samples are
/// the spheres' latitudes (`bands` per half turn) where that sphere is the
/// outline, the frustum ends and the x where two pieces cross, so every
/// kink of the outline is a vertex.
/// Capsules (r0 = r1 = 1) and spheres (length 0) are special cases.
fn union_profile(length: f64, r0: f64, r1: f64, bands: usize) -> Vec<(f64, f64)> {
    // `max` drops NaN, so bad input degrades to zero sizes.
    let (len, r0, r1) = (length.max(0.0), r0.max(0.0), r1.max(0.0));
    let sphere = |c: f64, r: f64, x: f64| (r * r - (x - c) * (x - c)).max(0.0).sqrt();
    let frustum = |x: f64| {
        if len > 0.0 && (0.0..=len).contains(&x) {
            r0 + (r1 - r0) * (x / len)
        } else {
            0.0
        }
    };
    let s0 = |x: f64| {
        if x.abs() <= r0 {
            sphere(0.0, r0, x)
        } else {
            0.0
        }
    };
    let s1 = |x: f64| {
        if (x - len).abs() <= r1 {
            sphere(len, r1, x)
        } else {
            0.0
        }
    };
    let radius = |x: f64| s0(x).max(s1(x)).max(frustum(x));
    let lo = (-r0).min(len - r1);
    let hi = r0.max(len + r1);

    let mut xs = vec![0.0, len];
    for i in 0..=bands {
        // sin of a symmetric angle puts the equator exactly at the centre.
        let s = (PI * (i as f64 / bands as f64 - 0.5)).sin();
        // Latitudes only where that sphere is the outline, not inside.
        let (x0, x1) = (r0 * s, len + r1 * s);
        if s0(x0) >= radius(x0) {
            xs.push(x0);
        }
        if s1(x1) >= radius(x1) {
            xs.push(x1);
        }
    }
    if len > 0.0 {
        // Sphere/frustum crossings: a sphere of radius r meets the line
        // r − t·u (u = distance from its centre) at u = 2rt / (1 + t²);
        // the frustum narrows by t = (r0 − r1)/length away from x = 0 and
        // by −t away from x = length.
        let t = (r0 - r1) / len;
        let u = 2.0 * t / (1.0 + t * t);
        xs.push(r0 * u);
        xs.push(len + r1 * u);
        // Sphere/sphere crossing.
        xs.push((r0 * r0 - r1 * r1 + len * len) / (2.0 * len));
    }
    xs.retain(|x| x.is_finite() && (lo..=hi).contains(x));
    xs.push(lo);
    xs.push(hi);
    xs.sort_by(f64::total_cmp);
    let eps = 1e-9 * hi.max(-lo).max(f64::MIN_POSITIVE);
    xs.dedup_by(|b, a| *b - *a <= eps);

    let mut profile: Vec<(f64, f64)> = xs.iter().map(|&x| (x, radius(x))).collect();
    if profile.len() < 2 {
        return Vec::new();
    }
    // The ends are poles even where rounding leaves a tiny radius.
    profile[0].1 = 0.0;
    let last = profile.len() - 1;
    profile[last].1 = 0.0;
    drop_collinear(profile)
}

/// Removes profile points on a straight line between their neighbours
/// (the flat part of a capsule), which would only add needless rings.
fn drop_collinear(points: Vec<(f64, f64)>) -> Vec<(f64, f64)> {
    let mut kept: Vec<(f64, f64)> = Vec::with_capacity(points.len());
    for (i, &p) in points.iter().enumerate() {
        if let (Some(&a), Some(&c)) = (kept.last(), points.get(i + 1)) {
            let (u, v) = ((p.0 - a.0, p.1 - a.1), (c.0 - a.0, c.1 - a.1));
            let cross = u.0 * v.1 - u.1 * v.0;
            let dot = u.0 * v.0 + u.1 * v.1;
            if cross.abs() <= 1e-9 * dot.abs() && dot > 0.0 {
                continue;
            }
        }
        kept.push(p);
    }
    kept
}

#[cfg(test)]
mod tests {
    use super::*;

    fn shape(kind: ShapeKind) -> Shape {
        Shape {
            kind,
            transform: Affine3A::IDENTITY,
            material: 3,
            symbol: 7,
        }
    }

    #[test]
    fn box_has_12_triangles_with_outward_normals() {
        let mut out = Vec::new();
        tessellate(&shape(ShapeKind::Box), 8, &mut out);
        assert_eq!(out.len(), 12);
        let centre = Vec3::new(0.5, 0.0, 0.0);
        for t in &out {
            let c = (t.v[0] + t.v[1] + t.v[2]) / 3.0;
            assert!(t.normal().dot(c - centre) > 0.0);
            assert_eq!((t.material, t.symbol), (3, 7));
        }
    }

    #[test]
    fn sphere_triangle_count_and_first_vertex_on_y() {
        let mut out = Vec::new();
        tessellate(&shape(ShapeKind::Sphere), 8, &mut out);
        // 4 bands: 2 pole fans of 8 and 2 bands of 16.
        assert_eq!(out.len(), 8 * 2 + 16 * 2);
        // First fan triangle: pole (−1,0,0), ring k = 1, ring k = 0 (on +y).
        let r = std::f32::consts::FRAC_1_SQRT_2;
        assert!(out[0].v[2].distance(Vec3::new(-r, r, 0.0)) < 1e-6);
    }

    #[test]
    fn resolution_is_clamped() {
        let mut out = Vec::new();
        tessellate(&shape(ShapeKind::Cylinder), 0, &mut out);
        // 3 segments: 2 cap fans of 3 and one side band of 6.
        assert_eq!(out.len(), 12);
    }

    #[test]
    fn capsule_has_no_extra_rings_on_its_side() {
        let p = union_profile(2.0, 1.0, 1.0, 8);
        // Two hemispheres of 4 bands each: 5 + 5 points (equators included).
        assert_eq!(p.len(), 10);
        assert_eq!(p[4], (0.0, 1.0));
        assert_eq!(p[5], (2.0, 1.0));
    }

    #[test]
    fn tapered_trunk_outline_has_its_kinks() {
        // Sphere r0 = 1 leaves the frustum (1 → 0.5 over 2) at x = 0.47.
        let t: f64 = 0.25;
        let x = 2.0 * t / (1.0 + t * t);
        let p = union_profile(2.0, 1.0, 0.5, 8);
        assert!(p.iter().any(|q| (q.0 - x).abs() < 1e-12), "{p:?}");
        // Outline points all lie on the union's boundary, never outside.
        for &(x, r) in &p[1..p.len() - 1] {
            let s0 = (1.0 - x * x).max(0.0).sqrt();
            let s1 = (0.25 - (x - 2.0) * (x - 2.0)).max(0.0).sqrt();
            let f = if (0.0..=2.0).contains(&x) {
                1.0 - 0.25 * x
            } else {
                0.0
            };
            assert!((r - s0.max(s1).max(f)).abs() < 1e-12);
        }
    }

    #[test]
    fn bad_sizes_do_not_panic() {
        let mut out = Vec::new();
        for kind in [
            ShapeKind::Capsule { length: f32::NAN },
            ShapeKind::Trunk {
                length: -1.0,
                r0: f32::NAN,
                r1: -2.0,
            },
            ShapeKind::Trunk {
                length: 0.0,
                r0: 0.0,
                r1: 0.0,
            },
        ] {
            tessellate(&shape(kind), 16, &mut out);
        }
        assert!(out.iter().all(|t| t.v.iter().all(|p| p.is_finite())));
    }

    #[test]
    fn mirrored_transform_keeps_normals_outward() {
        let mut s = shape(ShapeKind::Sphere);
        s.transform = Affine3A::from_scale(Vec3::new(-1.0, 1.0, 1.0));
        let mut out = Vec::new();
        tessellate(&s, 16, &mut out);
        for t in &out {
            let c = (t.v[0] + t.v[1] + t.v[2]) / 3.0;
            assert!(t.normal().dot(c) > 0.0);
        }
    }
}
