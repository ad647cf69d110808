//! An actor's visual memory against OctoMap (issue 13): the 72 depth
//! scans of `../shared/anchors/octomap_scans.py` (64 × 64 rays each,
//! 294,912 points, a viewer walking a circle in a 40 × 4 × 40 room of
//! pillars) integrated at voxel 0.25 in the world cube −2 … 42:
//!
//! - `occupied_only`: one insertion per point, stamped with the view
//!   number (OctoMap's `updateNode` per point);
//! - `insert_forget`: each view's insertions, then the forgetting of 3.1.4
//!   against the view's depths (compare with OctoMap's ray-cleared
//!   `insertPointCloud`).
//!
//! The scans come from a binary file (scripts/octomap_scans_export.py)
//! named by `LMFILM_SCANS`:
//!
//! ```sh
//! target/anchors-env/bin/python ../shared/anchors/octomap_scans.py make target/scans.npz
//! target/anchors-env/bin/python scripts/octomap_scans_export.py target/scans.npz target/scans.bin
//! LMFILM_SCANS=target/scans.bin cargo bench --bench memory
//! ```

use std::time::Instant;

use criterion::{Criterion, Throughput};
use glam::DVec3;
use lmfilm::actors::perception::memory::{DepthView, VisualMemory};
use lmfilm::actors::perception::octree::Cube;

const VOXEL: f64 = 0.25;

struct Scans {
    views: Vec<DepthView>,
    points: Vec<Vec<[f64; 3]>>,
}

fn read(path: &str) -> Result<Scans, String> {
    let bytes = std::fs::read(path).map_err(|e| format!("{path}: {e}"))?;
    let mut at = 0usize;
    let mut take = |n: usize| -> Result<&[u8], String> {
        let s = bytes
            .get(at..at + n)
            .ok_or_else(|| format!("{path}: truncated"))?;
        at += n;
        Ok(s)
    };
    if take(8)? != b"LMSCANS1" {
        return Err(format!("{path}: not an LMSCANS1 file"));
    }
    let u32_of = |s: &[u8]| u32::from_le_bytes(s.try_into().unwrap());
    let f64_of = |s: &[u8]| f64::from_le_bytes(s.try_into().unwrap());
    let views = u32_of(take(4)?);
    let edge = u32_of(take(4)?);
    let fov = f64_of(take(8)?);
    let mut scans = Scans {
        views: Vec::new(),
        points: Vec::new(),
    };
    for _ in 0..views {
        let mut v3 = || -> Result<DVec3, String> {
            let s = take(24)?;
            Ok(DVec3::new(
                f64_of(&s[0..8]),
                f64_of(&s[8..16]),
                f64_of(&s[16..24]),
            ))
        };
        let eye = v3()?;
        let look_at = v3()?;
        let n = u32_of(take(4)?) as usize;
        if n != (edge * edge) as usize {
            return Err(format!("{path}: a view with misses ({n} points)"));
        }
        let s = take(24 * n)?;
        let pts: Vec<[f64; 3]> = s
            .chunks_exact(24)
            .map(|c| [f64_of(&c[0..8]), f64_of(&c[8..16]), f64_of(&c[16..24])])
            .collect();
        let distances = pts
            .iter()
            .map(|p| (DVec3::from_array(*p) - eye).length() as f32)
            .collect();
        scans.views.push(DepthView {
            eye: eye.as_vec3(),
            look_at: look_at.as_vec3(),
            twist: 0.0,
            fov_y: fov as f32,
            near: 0.0,
            far: f32::INFINITY,
            edge,
            distances,
        });
        scans.points.push(pts);
    }
    Ok(scans)
}

fn cube() -> Cube {
    Cube::new(-2.0, 42.0, VOXEL)
}

fn occupied_only(s: &Scans) -> VisualMemory {
    let mut m = VisualMemory::with_thesis_rule(cube());
    for (f, pts) in s.points.iter().enumerate() {
        for p in pts {
            m.insert(*p, f as u32);
        }
    }
    m
}

fn insert_forget(s: &Scans) -> (VisualMemory, u64) {
    let mut m = VisualMemory::with_thesis_rule(cube());
    let mut removed = 0;
    for (f, (pts, view)) in s.points.iter().zip(&s.views).enumerate() {
        for p in pts {
            m.insert(*p, f as u32);
        }
        removed += m.forget(view, f as u32).removed;
    }
    (m, removed)
}

fn best(runs: usize, f: impl Fn()) -> f64 {
    (0..runs)
        .map(|_| {
            let t = Instant::now();
            f();
            t.elapsed().as_secs_f64()
        })
        .fold(f64::MAX, f64::min)
}

fn main() {
    // `cargo test --all-targets` runs benches without `--bench`: skip.
    if !std::env::args().any(|a| a == "--bench") {
        return;
    }
    let Ok(path) = std::env::var("LMFILM_SCANS") else {
        eprintln!(
            "LMFILM_SCANS is not set: make the scans with \
             `octomap_scans.py make target/scans.npz` and \
             `scripts/octomap_scans_export.py target/scans.npz target/scans.bin`, \
             then run LMFILM_SCANS=target/scans.bin cargo bench --bench memory"
        );
        return;
    };
    let scans = match read(&path) {
        Ok(s) => s,
        Err(e) => {
            eprintln!("{e}");
            return;
        }
    };
    let n: usize = scans.points.iter().map(Vec::len).sum();

    let mut c = Criterion::default().configure_from_args().sample_size(10);
    let mut g = c.benchmark_group("memory");
    g.throughput(Throughput::Elements(n as u64));
    g.bench_function("occupied_only", |b| b.iter(|| occupied_only(&scans)));
    g.bench_function("insert_forget", |b| b.iter(|| insert_forget(&scans)));
    g.finish();

    // The anchor's format, best of 5.
    let t = best(5, || {
        occupied_only(&scans);
    });
    let m = occupied_only(&scans);
    println!(
        "lmfilm occupied_only voxel {VOXEL} points {n} s {t:.3} points_per_s {:.0} memory_bytes {} voxels {} stored {} bytes_per_voxel {:.1}",
        n as f64 / t,
        m.octree().memory_bytes(),
        m.voxels(),
        m.octree().stored_count(),
        m.octree().memory_bytes() as f64 / m.voxels() as f64
    );
    let t = best(5, || {
        insert_forget(&scans);
    });
    let (m, removed) = insert_forget(&scans);
    println!(
        "lmfilm insert_forget voxel {VOXEL} points {n} s {t:.3} points_per_s {:.0} memory_bytes {} voxels {} stored {} removed {removed} bytes_per_voxel {:.1}",
        n as f64 / t,
        m.memory_bytes(),
        m.voxels(),
        m.octree().stored_count(),
        m.memory_bytes() as f64 / m.voxels() as f64
    );
}
