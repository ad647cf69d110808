//! Ray-casting throughput on the peers' forest (../shared/anchors): the
//! same camera rays as `embree_rays.py` (640×480, one per pixel centre)
//! plus one shadow ray per hit toward the light, on one thread, cast one
//! by one (`lmfilm`), with the camera rays in 4 × 4 pixel packets
//! (`lmfilm-packets`, as the renderer casts a pixel's samples), and with
//! their shadow rays in bundles too (`lmfilm-bundles`, as the renderer
//! casts a pixel's shadow rays). Prints Mrays/s in the anchor's format;
//! `make bench-render` runs them.
//!
//! Then two criterion cases (issue 13): `vision/10_actors_64x64`, ten
//! actors' 64×64 vision windows into the forest's BVH, and
//! `vision/frame_640x480_16spp`, one final-quality frame render of the
//! same BVH (the render alone, against Mitsuba's `render_s`).
//! `cargo bench --bench render -- vision` runs only those.

use std::path::Path;
use std::time::Instant;

use criterion::Criterion;
use glam::{Vec3, Vec3A};
use lmfilm::actors::perception::vision::{self, OwnBody, View};
use lmfilm::lsys::{Animation, NoSensors};
use lmfilm::render::accel::Query;
use lmfilm::render::camera::CameraRays;
use lmfilm::render::{render_with, Accel, Settings};
use lmfilm::turtle::{build_scene, NoWorld, Options, Surfaces};

fn main() {
    // `cargo test --all-targets` runs benches without `--bench`: skip.
    if !std::env::args().any(|a| a == "--bench") {
        return;
    }
    let root = env!("CARGO_MANIFEST_DIR");
    if !Path::new(&format!("{root}/target/forest.obj")).exists() {
        eprintln!("target/forest.obj is missing: run `python3 ../shared/anchors/make_forest_obj.py 16 11 target/forest.obj` (make bench-render does)");
        return;
    }
    // Positional arguments are criterion filters: with one, only the
    // criterion cases run.
    let filtered = std::env::args().skip(1).any(|a| !a.starts_with('-'));
    let (w, h) = (640u32, 480u32);
    let t0 = Instant::now();
    let mut anim =
        Animation::load(&[format!("{root}/scenes/bench/forest.lm")], &mut NoSensors).unwrap();
    let surfaces = Surfaces::load(&anim).unwrap();
    let (scene, _) = build_scene(
        &mut anim,
        &surfaces,
        &mut Vec::new(),
        &mut NoWorld,
        Options::default(),
    )
    .unwrap();
    let t1 = Instant::now();
    let accel = Accel::new(scene.clone());
    let build = t1.elapsed().as_secs_f64();
    let load = (t1 - t0).as_secs_f64();
    if !filtered {
        rays_per_second(&scene, &accel, load, build, w, h);
    }
    let mut c = Criterion::default().sample_size(10).configure_from_args();
    let mut g = c.benchmark_group("vision");
    // Ten actors around the forest at eye height, looking at its middle.
    let views: Vec<View> = (0..10)
        .map(|k| {
            let a = k as f32 * std::f32::consts::TAU / 10.0;
            View::new(
                Vec3::new(30.0 * a.sin(), 2.0 + k as f32, 30.0 * a.cos()),
                Vec3::new(0.0, 6.0, 0.0),
                450,
                0.1,
                1000.0,
            )
        })
        .collect();
    g.bench_function("10_actors_64x64", |b| {
        b.iter(|| {
            views
                .iter()
                .map(|v| vision::see(&accel, &OwnBody::default(), v, 64))
                .collect::<Vec<_>>()
        })
    });
    // What `lmfilm still -o forest.png` renders (a PNG: no layer rays),
    // Mitsuba's render's work: 16 samples and their shadow rays.
    let mut settings = Settings::final_quality(w, h);
    settings.layers = false;
    g.bench_function("frame_640x480_16spp", |b| {
        b.iter(|| render_with(&accel, &settings, &|_, _| {}))
    });
    g.finish();
    c.final_summary();
}

/// Camera rays through each pixel centre plus a shadow ray per hit, on
/// one thread, best of 7 (the anchors' measure).
fn rays_per_second(
    scene: &lmfilm::scene::Scene,
    accel: &Accel,
    load: f64,
    build: f64,
    w: u32,
    h: u32,
) {
    let cam = CameraRays::new(&scene.camera, w, h);
    let light = Vec3A::from(scene.lights[0].position);
    let mut best = f64::MAX;
    let (mut rays, mut hits) = (0usize, 0usize);
    for _ in 0..7 {
        let t = Instant::now();
        rays = 0;
        hits = 0;
        let mut blocked = 0usize;
        for y in 0..h {
            for x in 0..w {
                let d = cam.dir(x as f32 + 0.5, y as f32 + 0.5);
                rays += 1;
                if let Some(hit) = accel.cast(cam.eye(), d, 0.0, f32::INFINITY) {
                    hits += 1;
                    rays += 1;
                    blocked += usize::from(shadowed(accel, light, cam.eye(), d, hit.t));
                }
            }
        }
        std::hint::black_box(blocked);
        best = best.min(t.elapsed().as_secs_f64());
    }
    println!(
        "lmfilm triangles {} load_s {load:.3} build_s {build:.3} rays {rays} hit_frac {:.3} best_s {best:.3} Mrays_per_s {:.2}",
        scene.expanded_counts().1,
        hits as f64 / (w * h) as f64,
        rays as f64 / best / 1e6
    );
    // The camera rays in packets of 4 × 4 pixels (`Accel::cast_all`, as
    // the renderer casts a pixel's samples), their shadow rays one by one,
    // then in bundles (`Accel::occluded_all`).
    for (name, bundled) in [("lmfilm-packets", false), ("lmfilm-bundles", true)] {
        let (rays, hits, best) = packets(accel, &cam, light, w, h, bundled);
        println!(
            "{name} rays {rays} hit_frac {:.3} best_s {best:.3} Mrays_per_s {:.2}",
            hits as f64 / (w * h) as f64,
            rays as f64 / best / 1e6
        );
    }
}

/// The rays, the hits and the best of seven times of the anchors' rays
/// with the camera rays in packets of 4 × 4 pixels, and their shadow rays
/// in bundles or not.
fn packets(
    accel: &Accel,
    cam: &CameraRays,
    light: Vec3A,
    w: u32,
    h: u32,
    bundled: bool,
) -> (usize, usize, f64) {
    let mut best = f64::MAX;
    let (mut rays, mut hits) = (0, 0);
    let (mut queries, mut got) = (Vec::new(), Vec::new());
    let (mut shadows, mut answers) = (Vec::new(), Vec::new());
    for _ in 0..7 {
        let t = Instant::now();
        rays = 0;
        hits = 0;
        let mut blocked = 0usize;
        for ty in (0..h).step_by(4) {
            for tx in (0..w).step_by(4) {
                queries.clear();
                for y in ty..(ty + 4).min(h) {
                    for x in tx..(tx + 4).min(w) {
                        queries.push(Query {
                            origin: cam.eye(),
                            dir: cam.dir(x as f32 + 0.5, y as f32 + 0.5),
                            tmin: 0.0,
                            tmax: f32::INFINITY,
                        });
                    }
                }
                accel.cast_all(&queries, &mut got);
                rays += queries.len();
                shadows.clear();
                for (q, hit) in queries.iter().zip(&got) {
                    if let Some(hit) = hit {
                        shadows.push(shadow(light, q.origin, q.dir, hit.t));
                    }
                }
                if bundled {
                    accel.occluded_all(&shadows, &mut answers);
                    blocked += answers.iter().filter(|&&b| b).count();
                } else {
                    let blocked_one = |q: &Query| accel.occluded(q.origin, q.dir, q.tmin, q.tmax);
                    blocked += shadows.iter().filter(|q| blocked_one(q)).count();
                }
                hits += shadows.len();
                rays += shadows.len();
            }
        }
        std::hint::black_box(blocked);
        best = best.min(t.elapsed().as_secs_f64());
    }
    (rays, hits, best)
}

/// Whether the shadow ray from the hit at `t` along `o + t·d` toward the
/// light is blocked (the anchors' shadow ray).
fn shadowed(accel: &Accel, light: Vec3A, o: Vec3A, d: Vec3A, t: f32) -> bool {
    let q = shadow(light, o, d, t);
    accel.occluded(q.origin, q.dir, q.tmin, q.tmax)
}

/// The shadow ray from the hit at `t` along `o + t·d` toward the light.
fn shadow(light: Vec3A, o: Vec3A, d: Vec3A, t: f32) -> Query {
    let p = o + d * t;
    let to = light - p;
    let dir = to.normalize();
    Query {
        origin: p + dir * 1e-3,
        dir,
        tmin: 0.0,
        tmax: to.length(),
    }
}
