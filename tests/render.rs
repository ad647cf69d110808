//! The ray tracer on real scenes (issue 4).

mod common;
use common::*;
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
    let img = render(&s, &Settings::preview(w, h));
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
    let img = render(&s, &Settings::preview(41, 41));
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
    let accel = Accel::new(&s);
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
    a.advance_to(100, &mut NoSensors);
    let (s, _) = scene(&mut a);
    let mut st = Settings::final_quality(64, 48);
    st.spp = 4;
    st.filter = Filter::Gaussian;
    let run = |n: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .unwrap();
        pool.install(|| render(&s, &st))
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
    // 250 concentric spheres, radii 0.9^k: their boxes nest, so the builder
    // can only merge the two smallest at a time — a chain far deeper than
    // a fixed traversal stack (obvhs's wide one has 32 entries) could hold.
    let n = 250;
    let mut axiom = String::new();
    for k in 0..n {
        axiom.push_str(&format!("a () () () () ({}) ", 2.0 * 0.9f64.powi(k)));
    }
    let s = scene_of(&format!("Axiom\n{axiom}\n"));
    let accel = Accel::new(&s);
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
    let img = render(&s, &st);
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
    let img = render(&s, &Settings::final_quality(64, 36));
    let blue: Vec<f32> = img.rgba.iter().map(|p| p[2] - p[0]).collect();
    let (lo, hi) = blue
        .iter()
        .fold((f32::MAX, f32::MIN), |(a, b), v| (a.min(*v), b.max(*v)));
    assert!(hi - lo > 0.1, "white clouds and blue sky: {lo} {hi}");
}
