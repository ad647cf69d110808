//! Vision and visual memory together (thesis 3.1.3): what a window sees
//! lands in the memory where it is, and an actor turning 360° in a room
//! memorises its walls.

use std::collections::BTreeSet;

use glam::Vec3;
use lmfilm::actors::perception::memory::VisualMemory;
use lmfilm::actors::perception::octree::Cube;
use lmfilm::actors::perception::vision::{self, OwnBody, View};
use lmfilm::render::Accel;
use lmfilm::scene::ShapeKind;

use crate::vision::{cuboid, scene};

/// A 20 × 6 × 20 room (walls 0.2 thick) seen from its middle.
fn room() -> Accel {
    let walls = [
        (Vec3::new(-0.2, 0.0, 0.0), Vec3::new(0.0, 6.0, 20.0)),
        (Vec3::new(20.0, 0.0, 0.0), Vec3::new(20.2, 6.0, 20.0)),
        (Vec3::new(0.0, 0.0, -0.2), Vec3::new(20.0, 6.0, 0.0)),
        (Vec3::new(0.0, 0.0, 20.0), Vec3::new(20.0, 6.0, 20.2)),
        (Vec3::new(0.0, -0.2, 0.0), Vec3::new(20.0, 0.0, 20.0)),
        (Vec3::new(0.0, 6.0, 0.0), Vec3::new(20.0, 6.2, 20.0)),
    ];
    let shapes: Vec<_> = walls
        .iter()
        .map(|&(lo, hi)| (ShapeKind::Box, cuboid(lo, hi), 1))
        .collect();
    Accel::new(scene(&shapes, &[], Vec3::new(10.0, 5.0, 10.0)))
}

const EYE: Vec3 = Vec3::new(10.0, 3.0, 10.0);

/// The view after turning `k` twelfths of a full turn.
fn view(k: u32) -> View {
    let a = k as f32 * std::f32::consts::TAU / 12.0;
    let look_at = EYE + Vec3::new(a.cos(), 0.0, a.sin());
    View::new(EYE, look_at, 600, 0.1, 100.0)
}

/// Voxel edge 0.5 with boundaries at −0.25 + 0.5 k: every wall plane
/// runs through the middle of its voxels.
fn cube() -> Cube {
    Cube::new(-1.25, 22.75, 0.5)
}

#[test]
fn a_seen_point_projects_back_to_its_pixel() {
    let accel = room();
    let window = vision::see(&accel, &OwnBody::default(), &view(1), 32);
    let depth = window.depth_view();
    let mut hits = 0;
    for y in 0..32 {
        for x in 0..32 {
            let p = window.pixel(x, y);
            if p.hit() {
                let (pixel, d) = depth.project(p.position).unwrap();
                assert_eq!(pixel, (x, y));
                assert!(
                    (d - p.distance).abs() < 1e-3 * p.distance,
                    "{d} {}",
                    p.distance
                );
                hits += 1;
            }
        }
    }
    assert_eq!(hits, 32 * 32, "a closed room is seen everywhere");
}

#[test]
fn turning_around_memorises_the_walls() {
    let accel = room();
    let mut memory = VisualMemory::with_thesis_rule(cube());
    for k in 0..12 {
        let window = vision::see(&accel, &OwnBody::default(), &view(k), 64);
        memory.integrate(&window.depth_view(), k);
    }
    let stored: BTreeSet<_> = memory
        .octree()
        .occupied_voxels()
        .into_iter()
        .map(|(v, _)| v)
        .collect();
    // The walls' inner faces, voxelised: every voxel a point of them lies in.
    let mut truth = BTreeSet::new();
    let tree = memory.octree();
    let steps = |a: f64, b: f64| {
        let n = ((b - a) / 0.05).round() as u32;
        (0..=n).map(move |i| a + (b - a) * f64::from(i) / f64::from(n))
    };
    for y in steps(0.0, 6.0) {
        for s in steps(0.0, 20.0) {
            for p in [[0.0, y, s], [20.0, y, s], [s, y, 0.0], [s, y, 20.0]] {
                truth.insert(tree.voxel(p).unwrap());
            }
        }
    }
    let found = truth.iter().filter(|&v| stored.contains(v)).count();
    let share = found as f64 / truth.len() as f64;
    assert!(
        share >= 0.95,
        "{found} of {} wall voxels memorised",
        truth.len()
    );
}
