//! Ray-casting throughput on the peers' forest (../shared/anchors): the
//! same camera rays as `embree_rays.py` (640×480, one per pixel centre)
//! plus one shadow ray per hit toward the light, on one thread. Prints
//! Mrays/s in the anchor's format; `make bench-render` runs both.

use std::path::Path;
use std::time::Instant;

use glam::Vec3A;
use lmfilm::lsys::{Animation, NoSensors};
use lmfilm::render::sample::CameraRays;
use lmfilm::render::Accel;
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
                    let p = cam.eye() + d * hit.t;
                    let to = light - p;
                    let sd = to.normalize();
                    blocked += usize::from(accel.occluded(p + sd * 1e-3, sd, 0.0, to.length()));
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
}
