//! The ray tracer on real scenes (issue 4).

use crate::common::*;
use glam::{Vec3, Vec3A};
use lmfilm::lsys::NoSensors;
use lmfilm::render::{render, Accel, Filter, Settings};
use lmfilm::scene::Scene;

fn scene_of(text: &str) -> Scene {
    scene(&mut from_text(text)).0
}

/// A sphere of radius 1 at the origin seen from (0, 0, 10).
const SPHERE: &str = "Camera_AnimationParameters\nobserver 0 0 10\nlookatPoint 0 0 0\nviewAngle 300\nAxiom\nm () (7) a () () () () (2)\n";

#[test]
fn sphere_covers_its_projected_disc() {
    let s = scene_of(SPHERE);
    let (w, h) = (400, 400);
    let img = render(s.clone(), &Settings::preview(w, h));
    let covered = img.rgba.iter().filter(|p| p[3] > 0.5).count() as f64;
    // Silhouette half-angle asin(r/D), projected with the 30° field.
    let alpha = (1.0f64 / 10.0).asin();
    let radius_px = alpha.tan() / 15f64.to_radians().tan() * (h as f64 / 2.0);
    let disc = std::f64::consts::PI * radius_px * radius_px;
    assert!(
        (covered / disc - 1.0).abs() < 0.02,
        "covered {covered} disc {disc}"
    );
}

#[test]
fn depth_layer_holds_distance_minus_radius_at_the_centre() {
    let s = scene_of(SPHERE);
    let img = render(s.clone(), &Settings::preview(41, 41));
    let c = 20 * 41 + 20;
    assert!((img.depth[c] - 9.0).abs() < 1e-4, "{}", img.depth[c]);
    assert!((Vec3::from_array(img.normal[c]) - Vec3::Z).length() < 1e-3);
    assert_eq!(img.object[c], 0);
    assert_eq!(img.depth[0], f32::INFINITY);
    assert_eq!(img.object[0], u32::MAX);
}

#[test]
fn cast_reports_distance_material_normal_and_vision_colour() {
    let s = scene_of(SPHERE);
    let accel = Accel::new(s.clone());
    let hit = accel
        .cast(Vec3A::new(0.0, 0.0, 10.0), -Vec3A::Z, 0.0, f32::INFINITY)
        .unwrap();
    assert!((hit.t - 9.0).abs() < 1e-5);
    assert_eq!(s.materials[hit.material as usize].name, "white");
    assert!((hit.normal - Vec3A::Z).length() < 1e-5);
    assert_eq!(hit.vision, s.materials[hit.material as usize].vision);
    assert!(accel
        .cast(Vec3A::new(0.0, 5.0, 10.0), -Vec3A::Z, 0.0, f32::INFINITY)
        .is_none());
    assert!(accel.occluded(Vec3A::new(0.0, 0.0, 10.0), -Vec3A::Z, 0.0, 20.0));
    assert!(!accel.occluded(Vec3A::new(0.0, 0.0, 10.0), -Vec3A::Z, 0.0, 8.0));
}

#[test]
fn identical_for_any_thread_count() {
    let mut a = load("cours_tree3.lm");
    a.advance_to(100, &mut NoSensors).unwrap();
    let (s, _) = scene(&mut a);
    let mut st = Settings::final_quality(64, 48);
    st.spp = 4;
    st.filter = Filter::Gaussian;
    let run = |n: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .unwrap();
        pool.install(|| render(s.clone(), &st))
    };
    let (one, two) = (run(1), run(2));
    let bits = |i: &lmfilm::render::Image| {
        i.rgba
            .iter()
            .flatten()
            .map(|v| v.to_bits())
            .collect::<Vec<_>>()
    };
    assert_eq!(bits(&one), bits(&two));
    assert!(one.rgba.iter().any(|p| p[3] > 0.0), "the tree is in view");
}

#[test]
fn pathologically_deep_scene_finds_everything() {
    // 250 nested spheres, radii 0.9^k: their boxes nest, so the builder
    // can only merge the two smallest at a time — a chain far deeper than
    // a fixed traversal stack (obvhs's wide one has 32 entries) could hold.
    // Each is off centre by 10⁻⁴ of its radius: coincident centres would
    // be grouped into a balanced tree.
    let n = 250;
    let mut axiom = String::new();
    for k in 0..n {
        let r = 0.9f64.powi(k);
        let d = 1e-4 * r;
        axiom.push_str(&format!(
            "f () () () () ({d}) a () () () () ({}) f () () () () ({d}_) ",
            2.0 * r
        ));
    }
    let s = scene_of(&format!("Axiom\n{axiom}\n"));
    let accel = Accel::new(s.clone());
    assert!(accel.depth() > 32, "a chain {} levels deep", accel.depth());
    for k in 0..n - 1 {
        // From between shells k + 1 and k, outward: shell k is the nearest.
        let (r0, r1) = (0.9f32.powi(k), 0.9f32.powi(k + 1));
        let y = (r0 + r1) / 2.0;
        let hit = accel.cast(Vec3A::new(0.0, y, 0.0), Vec3A::Y, 0.0, f32::INFINITY);
        assert!(
            hit.is_some_and(|h| (h.t - (r0 - y)).abs() < 1e-3 * r0),
            "shell {k}: {hit:?}"
        );
    }
}

/// Ground values seen from above with a cube on the ground, one sample per
/// pixel, hard or soft shadows by the light `l`.
fn ground_values(light: &str) -> Vec<f32> {
    let text = format!(
        "Camera_AnimationParameters\nobserver 0 20 0.01\nlookatPoint 0 0 0\nviewAngle 600\nAxiom\n{light} m () (8) D () (2) () () (0) f () () () (2) (1_) (0) (0) c () () () () (2) (2) (2)\n"
    );
    let s = scene_of(&text);
    let mut st = Settings::final_quality(80, 80);
    st.spp = 1;
    st.light_samples = 16;
    let img = render(s.clone(), &st);
    // Pixels of the ground (depth ≈ 20) only, by their red value.
    img.rgba
        .iter()
        .zip(&img.depth)
        .filter(|(_, d)| (**d - 20.0).abs() < 0.5)
        .map(|(p, _)| p[0])
        .collect()
}

#[test]
fn directional_light_gives_hard_shadows_and_sphere_light_soft_ones() {
    // The sun, slanted: the lit ground has one value, the shadow another.
    let sun = ground_values("l () () () (12) (1) (2_) (0.5)");
    let (lo, hi) = sun
        .iter()
        .fold((f32::MAX, f32::MIN), |(a, b), v| (a.min(*v), b.max(*v)));
    assert!(hi > lo + 0.1, "lit {hi} shadow {lo}");
    assert!(
        sun.iter().all(|v| *v == lo || *v == hi),
        "hard shadows: two values only"
    );
    let lit = sun.iter().filter(|v| **v == hi).count();
    assert!(lit > sun.len() / 2, "most of the ground is lit");
    // A sphere light of radius 3 gives a penumbra of in-between values.
    let soft = ground_values("l () (3) () (13) (8) (10) (2)");
    let (lo, hi) = soft
        .iter()
        .fold((f32::MAX, f32::MIN), |(a, b), v| (a.min(*v), b.max(*v)));
    let between = soft
        .iter()
        .filter(|v| **v > lo + 0.02 && **v < hi - 0.02)
        .count();
    assert!(between > 20, "penumbra pixels: {between}");
}

#[test]
fn cloud_layer_is_see_through_and_casts_no_shadow() {
    // Under the sun the ground looks the same with and without clouds.
    let sun = "l () () () (12) (0.3) (1_) (0.2)";
    let clear = ground_values(sun);
    let cloudy = ground_values(&format!("{sun} D () (16) () () (400) (15) (400)"));
    assert!(!clear.is_empty());
    assert_eq!(clear, cloudy);
    // Looking up: clouds and the sky between them.
    let s = scene_of("Camera_AnimationParameters\nobserver 0 2 0\nlookatPoint 0 50 -100\nAxiom\nD () (15) D () (16) () () (400) (15) (400)\n");
    let img = render(s.clone(), &Settings::final_quality(64, 36));
    let blue: Vec<f32> = img.rgba.iter().map(|p| p[2] - p[0]).collect();
    let (lo, hi) = blue
        .iter()
        .fold((f32::MAX, f32::MIN), |(a, b), v| (a.min(*v), b.max(*v)));
    assert!(hi - lo > 0.1, "white clouds and blue sky: {lo} {hi}");
}

/// A small deterministic generator for the brute-force comparison.
struct Lcg(u64);
impl Lcg {
    fn f(&mut self) -> f32 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 40) as f32 / (1u64 << 24) as f32
    }
    fn range(&mut self, a: f32, b: f32) -> f32 {
        a + (b - a) * self.f()
    }
    fn vec(&mut self, r: f32) -> Vec3 {
        Vec3::new(self.range(-r, r), self.range(-r, r), self.range(-r, r))
    }
    /// `n` triangles of corners within `size` of centres within `spread`.
    fn triangles(&mut self, n: usize, spread: f32, size: f32) -> Vec<lmfilm::scene::Triangle> {
        (0..n)
            .map(|i| {
                let c = self.vec(spread);
                lmfilm::scene::Triangle {
                    v: [c + self.vec(size), c + self.vec(size), c + self.vec(size)],
                    material: 0,
                    symbol: i as u64,
                }
            })
            .collect()
    }

    fn affine(&mut self, spread: f32) -> glam::Affine3A {
        let q = glam::Quat::from_euler(
            glam::EulerRot::XYZ,
            self.f() * 6.3,
            self.f() * 6.3,
            self.f() * 6.3,
        );
        let s = Vec3::new(
            self.range(0.3, 1.5),
            self.range(0.3, 1.5),
            self.range(0.3, 1.5),
        );
        glam::Affine3A::from_scale_rotation_translation(s, q, self.vec(spread))
    }
}

/// Nearest hit over every primitive of every instance, by brute force:
/// (t, instance, is shape, index).
fn brute_force(s: &Scene, o: Vec3A, d: Vec3A, tmax: f32) -> Option<(f32, usize, bool, usize)> {
    use lmfilm::render::accel::shapes::shape;
    use lmfilm::render::accel::tri4::triangle;
    let mut best: Option<(f32, usize, bool, usize)> = None;
    let mut keep = |h: (f32, usize, bool, usize)| {
        if best.is_none_or(|b| h.0 < b.0) {
            best = Some(h);
        }
    };
    for (k, inst) in s.instances.iter().enumerate() {
        let inv = inst.transform.inverse();
        let (lo, ld) = (inv.transform_point3a(o), inv.transform_vector3a(d));
        let g = &s.geometries[inst.geometry as usize];
        for (i, sh) in g.shapes.iter().enumerate() {
            let si = sh.transform.inverse();
            if let Some(h) = shape(
                sh.kind,
                si.transform_point3a(lo),
                si.transform_vector3a(ld),
                0.0,
                tmax,
            ) {
                keep((h.t, k, true, i));
            }
        }
        for (i, t) in g.triangles.iter().enumerate() {
            if let Some(t) = triangle(&t.v, lo, ld, 0.0, tmax) {
                keep((t, k, false, i));
            }
        }
    }
    best
}

#[test]
fn two_level_bvh_matches_brute_force() {
    use lmfilm::render::accel::Prim;
    use lmfilm::scene::{Geometry, Instance, Shape, ShapeKind};
    let mut rng = Lcg(7);
    let mut s = scene_of(SPHERE);
    let kinds = [
        ShapeKind::Sphere,
        ShapeKind::Box,
        ShapeKind::Cylinder,
        ShapeKind::Capsule { length: 1.5 },
    ];
    let geometry = |shapes: usize, tris: usize, rng: &mut Lcg| Geometry {
        name: String::new(),
        shapes: (0..shapes)
            .map(|i| Shape {
                kind: kinds[i % 4],
                transform: rng.affine(6.0) * glam::Affine3A::from_scale(Vec3::splat(0.3)),
                material: 0,
                symbol: i as u64,
            })
            .collect(),
        triangles: rng.triangles(tris, 6.0, 0.6),
        resolution: 8,
    };
    // A mixed geometry, a triangles-only one, and one with a single
    // primitive (its tree is one leaf).
    s.geometries = vec![
        geometry(300, 300, &mut rng),
        geometry(0, 200, &mut rng),
        geometry(1, 0, &mut rng),
    ];
    s.instances = (0..40)
        .map(|k| Instance {
            geometry: k % 3,
            transform: rng.affine(25.0),
            object: k,
        })
        .collect();
    for single in [false, true] {
        if single {
            s.instances.truncate(1);
        }
        let accel = Accel::new(s.clone());
        let mut hits = 0;
        for _ in 0..3000 {
            let o = Vec3A::from(rng.vec(40.0));
            let d = Vec3A::from(rng.vec(25.0)) - o;
            let tmax = rng.range(0.5, 2.0);
            let want = brute_force(&s, o, d, tmax);
            let got = accel.cast(o, d, 0.0, tmax);
            match (got, want) {
                (Some(h), Some((t, k, is_shape, i))) => {
                    hits += 1;
                    assert!((h.t - t).abs() <= 1e-5 * t.max(1.0), "{} vs {t}", h.t);
                    let prim = if is_shape {
                        Prim::Shape(i as u32)
                    } else {
                        Prim::Triangle(i as u32)
                    };
                    // Exact ties may go either way.
                    assert!(
                        h.t != t || (h.instance as usize == k && h.prim == prim),
                        "{h:?} vs {k} {prim:?}"
                    );
                }
                (None, None) => {}
                (g, w) => panic!("ray {o} {d} {tmax}: {g:?} vs {w:?}"),
            }
            assert_eq!(
                accel.occluded(o, d, 0.0, tmax),
                want.is_some(),
                "occlusion of {o} {d}"
            );
        }
        assert!(hits > if single { 30 } else { 600 }, "{hits} hits");
    }
}

/// Every primitive lands in exactly one leaf, whatever the tree's shape
/// after obvhs's reinsertion pass (which moves the root's children).
#[test]
fn bvh4_leaves_cover_every_primitive_once() {
    use lmfilm::render::accel::bvh4::Bvh4;
    use obvhs::aabb::Aabb;
    let mut rng = Lcg(3);
    for n in [1usize, 2, 3, 5, 17, 100, 1000, 20000, 70000] {
        for clustered in [false, true] {
            let boxes: Vec<Aabb> = (0..n)
                .map(|i| {
                    let c = if clustered && i % 2 == 0 {
                        rng.vec(1.0)
                    } else {
                        rng.vec(100.0)
                    };
                    let e = Vec3A::from(rng.vec(0.5).abs()) + 0.01;
                    Aabb::new(Vec3A::from(c) - e, Vec3A::from(c) + e)
                })
                .collect();
            for max_leaf in [1, 16] {
                let t = Bvh4::build(&boxes, max_leaf).unwrap();
                let mut seen = vec![0u32; n];
                for l in 0..t.leaf_count() {
                    for &p in t.leaf(l) {
                        seen[p as usize] += 1;
                    }
                }
                assert!(seen.iter().all(|&c| c == 1), "n {n} clustered {clustered}");
            }
        }
    }
}

/// Mean luminance of the pixels that see the sphere of `SPHERE` drawn in
/// material `m` under a sky, rendered with `settings`.
fn sphere_luminance(m: u32, settings: &Settings) -> f32 {
    let text = SPHERE.replace("m () (7)", &format!("D () (15) m () ({m})"));
    let img = render(scene_of(&text), settings);
    let on: Vec<_> = (0..img.object.len())
        .filter(|&i| img.object[i] != u32::MAX)
        .map(|i| {
            let [r, g, b, _] = img.rgba[i];
            0.2126 * r + 0.7152 * g + 0.0722 * b
        })
        .collect();
    assert!(!on.is_empty());
    on.iter().sum::<f32>() / on.len() as f32
}

#[test]
fn preview_mirrors_and_glass_are_not_black() {
    // 13 = mirror, 19 = quartz (a transparent crystal).
    for m in [13, 19] {
        let preview = sphere_luminance(m, &Settings::preview(64, 64));
        let mut final_quality = Settings::final_quality(64, 64);
        final_quality.spp = 1;
        let full = sphere_luminance(m, &final_quality);
        assert!(
            preview > 0.25,
            "material {m}: preview {preview}, final {full}"
        );
        // A cheap look, yet near what the full bounces see.
        assert!(
            (preview - full).abs() < 0.5 * full,
            "material {m}: preview {preview}, final {full}"
        );
    }
}

#[test]
fn equally_near_hits_resolve_to_the_lowest_primitive_whatever_the_walk() {
    // Two identical ground squares (two triangles each), red drawn first,
    // then yellow, then a third in white: every ray down meets three
    // triangles at the same distance, and takes the first drawn's.
    let s = scene_of(
        "Camera_AnimationParameters\nobserver 0 10 1\nlookatPoint 0 0 0\nAxiom\n\
         m () (4) D () (2) m () (5) D () (2) m () (7) D () (2)\n",
    );
    let accel = Accel::new(s.clone());
    for i in 0..400 {
        let (x, z) = (
            (i % 20) as f32 * 37.3 - 370.0,
            (i / 20) as f32 * 41.1 - 390.0,
        );
        let hit = accel
            .cast(Vec3A::new(x, 5.0, z), -Vec3A::Y, 0.0, f32::INFINITY)
            .unwrap();
        assert_eq!(s.materials[hit.material as usize].name, "red", "at {x} {z}");
        assert!((hit.t - 5.0).abs() < 1e-4);
    }
}

/// A geometry of `n` triangles of corners within 0.8 of centres within 5,
/// the first `copies` of them repeated (equally near hits).
fn soup(rng: &mut Lcg, n: usize, copies: usize) -> lmfilm::scene::Geometry {
    let mut triangles = rng.triangles(n, 5.0, 0.8);
    triangles.extend_from_within(..copies);
    lmfilm::scene::Geometry {
        name: String::new(),
        shapes: Vec::new(),
        triangles,
        resolution: 8,
    }
}

/// `n` instances of geometry `g`: the identity, then turned and scaled
/// ones; their objects numbered from `object`.
fn soup_instances(rng: &mut Lcg, g: u32, n: u32, object: u32) -> Vec<lmfilm::scene::Instance> {
    (0..n)
        .map(|k| lmfilm::scene::Instance {
            geometry: g,
            transform: if k == 0 {
                glam::Affine3A::IDENTITY
            } else {
                rng.affine(12.0)
            },
            object: object + k,
        })
        .collect()
}

/// The triangle test's paths (the baseline and each wider one this
/// machine has, chosen at run time) find the same hits, bit for bit, and
/// render the same bytes (DESIGN §4): a dense soup of triangles with
/// copies (equally near hits) under several instances, cast and
/// rendered.
#[test]
fn every_simd_path_gives_the_same_hits_and_bytes() {
    use lmfilm::render::accel::tri4::Simd;
    let paths = Simd::available();
    let mut rng = Lcg(11);
    let mut s = scene_of(SPHERE);
    s.geometries = vec![soup(&mut rng, 4000, 500)];
    s.instances = soup_instances(&mut rng, 0, 6, 0);
    let rays: Vec<(Vec3A, Vec3A, f32)> = (0..20_000)
        .map(|_| {
            let o = Vec3A::from(rng.vec(20.0));
            (o, Vec3A::from(rng.vec(6.0)) - o, rng.range(0.5, 3.0))
        })
        .collect();
    let trace = |simd: Simd| {
        let accel = Accel::new(s.clone()).with_simd(simd);
        rays.iter()
            .map(|&(o, d, tmax)| (accel.cast(o, d, 0.0, tmax), accel.occluded(o, d, 0.0, tmax)))
            .collect::<Vec<_>>()
    };
    let base = trace(Simd::Baseline);
    assert!(base.iter().filter(|h| h.0.is_some()).count() > 5000);
    let mut st = Settings::final_quality(64, 48);
    st.spp = 2;
    let image = |simd: Simd| {
        let accel = Accel::new(s.clone()).with_simd(simd);
        let img = lmfilm::render::render_with(&accel, &st, &|_, _| {});
        img.rgba
            .iter()
            .flatten()
            .map(|v| v.to_bits())
            .collect::<Vec<_>>()
    };
    let base_image = image(Simd::Baseline);
    let covered = base_image.chunks(4).filter(|p| f32::from_bits(p[3]) > 0.0);
    assert!(covered.count() > 1000, "the soup fills the view");
    for &simd in &paths[1..] {
        let got = trace(simd);
        for (k, (g, b)) in got.iter().zip(&base).enumerate() {
            let bits =
                |h: &Option<lmfilm::render::Hit>| h.map(|h| (h.t.to_bits(), h.instance, h.prim));
            assert_eq!((bits(&g.0), g.1), (bits(&b.0), b.1), "{simd:?}, ray {k}");
        }
        assert_eq!(image(simd), base_image, "{simd:?}");
    }
}

/// Rays cast in packets (`Accel::cast_all`, as the renderer casts a
/// pixel's samples) find what each cast alone finds, bit for bit, in every
/// lane form the machine has: bundles of 16 nearly parallel rays (packets
/// in full, leaves tested together) and scattered ones (packets split by
/// direction signs), from one point or from points apart, into a soup of
/// triangles with copies (equally near hits) under turned and scaled
/// instances, and a sphere; rays that cannot hit anything and bounds that
/// stop short among them.
#[test]
fn packets_find_what_single_rays_find() {
    use lmfilm::render::accel::tri4::Simd;
    use lmfilm::render::accel::Query;
    let mut rng = Lcg(23);
    let mut s = scene_of(SPHERE);
    s.geometries.push(soup(&mut rng, 3000, 400));
    s.instances.extend(soup_instances(&mut rng, 1, 5, 10));
    let mut queries = Vec::new();
    for bundle in 0..1500 {
        let o = Vec3A::from(rng.vec(20.0));
        let aim = Vec3A::from(rng.vec(6.0)) - o;
        let spread = if bundle % 3 == 0 { 2.0 } else { 0.05 };
        for lane in 0..16 {
            let dir = match lane {
                // Cannot hit anything: no direction, or not finite.
                5 if bundle % 7 == 0 => Vec3A::ZERO,
                6 if bundle % 11 == 0 => Vec3A::NAN,
                _ => aim + Vec3A::from(rng.vec(spread)),
            };
            let tmax = if lane % 4 == 3 {
                rng.range(0.3, 1.5)
            } else {
                f32::INFINITY
            };
            // Every fifth bundle's rays leave from points apart.
            let origin = if bundle % 5 == 1 {
                o + Vec3A::from(rng.vec(0.5))
            } else {
                o
            };
            queries.push(Query {
                origin,
                dir,
                tmin: if lane == 2 { 0.1 } else { 0.0 },
                tmax,
            });
        }
    }
    let bits = |h: &Option<lmfilm::render::Hit>| {
        h.map(|h| {
            (
                h.t.to_bits(),
                h.instance,
                h.prim,
                h.normal.to_array().map(f32::to_bits),
            )
        })
    };
    let mut hits = 0;
    for simd in Simd::available() {
        let accel = Accel::new(s.clone()).with_simd(simd);
        let mut got = Vec::new();
        accel.cast_all(&queries, &mut got);
        assert_eq!(got.len(), queries.len());
        for (k, (q, g)) in queries.iter().zip(&got).enumerate() {
            let one = accel.cast(q.origin, q.dir, q.tmin, q.tmax);
            assert_eq!(bits(g), bits(&one), "{simd:?}, ray {k}: {q:?}");
            hits += usize::from(one.is_some());
        }
    }
    assert!(hits > 10_000 * Simd::available().len(), "{hits} hits");
}

/// `Accel::occluded_all` answers what `occluded` answers, ray by ray,
/// for bundles of shadow rays (neighbouring points toward one light),
/// scattered ones, rays that cannot hit and rays left unbounded, whole
/// bundles toward a sun (unbounded, some from outside the scene), under
/// instances with transforms, in every SIMD path.
#[test]
fn bundles_find_what_single_shadow_rays_find() {
    use lmfilm::render::accel::tri4::Simd;
    use lmfilm::render::accel::Query;
    let mut rng = Lcg(31);
    let mut s = scene_of(SPHERE);
    s.geometries.push(soup(&mut rng, 3000, 400));
    s.instances.extend(soup_instances(&mut rng, 1, 5, 10));
    let mut queries = Vec::new();
    for bundle in 0..1500 {
        let light = Vec3A::from(rng.vec(30.0));
        let at = Vec3A::from(rng.vec(8.0));
        let spread = if bundle % 3 == 0 { 3.0 } else { 0.05 };
        let lanes = 1 + bundle % 16;
        let sun = (bundle % 5 == 4).then(|| light.normalize());
        let at = if bundle % 10 == 9 { at * 4.0 } else { at };
        for lane in 0..lanes {
            let o = at + Vec3A::from(rng.vec(spread));
            let to = light - o;
            let (dir, tmax) = match lane {
                _ if sun.is_some() => (sun.unwrap(), f32::INFINITY),
                5 if bundle % 7 == 0 => (Vec3A::ZERO, 1.0),
                6 if bundle % 11 == 0 => (Vec3A::NAN, 1.0),
                7 if bundle % 13 == 0 => (to, f32::INFINITY),
                _ => (to.normalize(), to.length()),
            };
            queries.push(Query {
                origin: o,
                dir,
                tmin: if lane == 2 { 0.1 } else { 0.0 },
                tmax,
            });
        }
    }
    let mut blocked = 0;
    for simd in Simd::available() {
        let accel = Accel::new(s.clone()).with_simd(simd);
        let mut got = Vec::new();
        accel.occluded_all(&queries, &mut got);
        assert_eq!(got.len(), queries.len());
        for (k, (q, &g)) in queries.iter().zip(&got).enumerate() {
            let one = accel.occluded(q.origin, q.dir, q.tmin, q.tmax);
            assert_eq!(g, one, "{simd:?}, ray {k}: {q:?}");
            blocked += usize::from(one);
        }
    }
    let per = queries.len() * Simd::available().len();
    assert!(
        blocked > per / 5 && blocked < per * 4 / 5,
        "{blocked} of {per} blocked"
    );
}
