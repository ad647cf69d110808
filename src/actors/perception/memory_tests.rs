//! Tests of the visual memory: octree addressing, neighbours, merging,
//! the forgetting rule of 3.1.4, projection and determinism.

use glam::Vec3;

use super::memory::{DepthView, Forgetting, VisualMemory};
use super::octree::{Cube, Octree, Voxel};

/// The thesis's example cube: `init 10 -20 300 2.0`.
fn thesis_cube() -> Cube {
    Cube::new(-20.0, 300.0, 2.0)
}

#[test]
fn addressing_round_trips() {
    let t = Octree::new(thesis_cube(), true);
    // 320 / 2 = 160 voxels per edge: range 2^8 = 256.
    assert_eq!(t.levels(), 8);
    assert_eq!(t.voxels_per_edge(), 160);
    assert_eq!(t.voxel([-20.0, -20.0, -20.0]), Some([0, 0, 0]));
    // trunc((20 + 1.9) / 2) = 10, trunc((20 + 2.0) / 2) = 11.
    assert_eq!(t.voxel([1.9, 2.0, -19.0]), Some([10, 11, 0]));
    assert_eq!(t.voxel([300.0, 0.0, 0.0]), None);
    assert_eq!(t.voxel([-20.001, 0.0, 0.0]), None);
    assert_eq!(t.voxel([f64::NAN, 0.0, 0.0]), None);
    // The son at depth 0 is the most significant bit: 4·x + 2·y + z.
    assert_eq!(t.path([128, 0, 0]), vec![4, 0, 0, 0, 0, 0, 0, 0]);
    assert_eq!(t.path([0, 128, 1]), vec![2, 0, 0, 0, 0, 0, 0, 1]);
    assert_eq!(t.path([159, 159, 159]), vec![7, 0, 0, 7, 7, 7, 7, 7]);
    for x in (0..160).step_by(7) {
        for y in (0..160).step_by(11) {
            for z in (0..160).step_by(13) {
                let v = [x, y, z];
                assert_eq!(t.voxel_of_path(&t.path(v)), v);
                assert_eq!(t.voxel(t.centre(v)), Some(v));
                let (lo, e) = t.voxel_box(v);
                assert_eq!(e, 2.0);
                assert_eq!(t.voxel(lo), Some(v));
            }
        }
    }
}

#[test]
fn neighbours_inside_and_at_faces() {
    let t = Octree::new(thesis_cube(), true);
    let inner = t.neighbours([50, 60, 70]);
    assert_eq!(inner.len(), 26);
    let mut sorted = inner.clone();
    sorted.sort_unstable();
    sorted.dedup();
    assert_eq!(sorted.len(), 26);
    for n in &inner {
        let d: Vec<i64> = (0..3).map(|i| i64::from(n[i]) - [50, 60, 70][i]).collect();
        assert!(d.iter().all(|c| c.abs() <= 1) && d.iter().any(|&c| c != 0));
    }
    assert_eq!(inner[0], [49, 59, 69]);
    assert_eq!(inner[25], [51, 61, 71]);
    assert_eq!(t.neighbours([0, 0, 0]).len(), 7);
    assert_eq!(t.neighbours([159, 159, 159]).len(), 7);
    assert_eq!(t.neighbours([0, 0, 80]).len(), 11);
    assert_eq!(t.neighbours([0, 80, 80]).len(), 17);
    // At depth 7 voxels span 2 finest voxels (edge_size = 2).
    let coarse = t.neighbours_at([51, 61, 71], 7);
    assert_eq!(coarse.len(), 26);
    assert!(coarse.contains(&[48, 58, 68]) && coarse.contains(&[52, 62, 72]));
}

#[test]
fn eight_occupied_sons_merge_into_their_father() {
    let mut t = Octree::new(thesis_cube(), true);
    let empty = t.memory_bytes();
    for (i, s) in (0..8u32).enumerate() {
        t.insert(
            [10 + (s >> 2 & 1), 20 + (s >> 1 & 1), 30 + (s & 1)],
            i as u32,
        );
    }
    assert_eq!(t.voxel_count(), 8);
    assert_eq!(t.stored_count(), 1);
    assert_eq!(t.occupied(), vec![([10, 20, 30], 7, 7)]);
    assert_eq!(t.get([11, 21, 31]), Some(7));
    assert_eq!(t.get([12, 20, 30]), None);
    // A 4³ block merges two levels up.
    for x in 8..12 {
        for y in 20..24 {
            for z in 28..32 {
                t.insert([x, y, z], 9);
            }
        }
    }
    assert_eq!(t.voxel_count(), 64);
    assert_eq!(t.stored_count(), 1);
    assert_eq!(t.occupied(), vec![([8, 20, 28], 6, 9)]);
    assert_eq!(t.occupied_voxels().len(), 64);
    // Removing one voxel splits the merged voxels that hold it.
    assert!(t.remove([9, 21, 29]));
    assert!(!t.remove([9, 21, 29]));
    assert_eq!(t.voxel_count(), 63);
    assert_eq!(t.get([9, 21, 29]), None);
    assert_eq!(t.get([8, 21, 29]), Some(9));
    assert_eq!(t.stored_count(), 7 + 7);
    let vs = t.occupied_voxels();
    assert_eq!(vs.len(), 63);
    assert!(vs.iter().all(|&(v, l)| l == 9 && v != [9, 21, 29]));
    for (v, _) in vs {
        assert!(t.remove(v));
    }
    assert_eq!(t.voxel_count(), 0);
    assert_eq!(t.stored_count(), 0);
    assert!(t.occupied().is_empty());
    // Freed nodes are reused, not leaked.
    let before = t.memory_bytes();
    t.insert([100, 100, 100], 1);
    assert_eq!(t.memory_bytes(), before);
    assert!(before >= empty);
}

/// A view from the origin along +z through planes z = c (nearest wins);
/// 32 × 32 pixels, 60°.
fn view(eye: Vec3, planes: &[f32]) -> DepthView {
    let mut v = DepthView {
        eye,
        look_at: eye + Vec3::Z,
        twist: 0.0,
        fov_y: 60.0,
        near: 0.1,
        far: 100.0,
        edge: 32,
        distances: Vec::new(),
    };
    let rays = v.rays();
    for y in 0..32 {
        for x in 0..32 {
            let d = Vec3::from(rays.dir(x as f32 + 0.5, y as f32 + 0.5));
            let t = planes
                .iter()
                .map(|&c| (c - eye.z) / d.z)
                .filter(|t| *t > 0.0)
                .fold(f32::INFINITY, f32::min);
            v.distances.push(t);
        }
    }
    v
}

fn room_cube() -> Cube {
    Cube::new(-16.0, 16.0, 0.25)
}

/// Voxels of the plane z = c (layer index) in the memory.
fn layer(m: &VisualMemory, c: f32) -> Vec<Voxel> {
    let k = ((c + 16.0) / 0.25) as u32;
    m.octree()
        .occupied_voxels()
        .into_iter()
        .filter(|(v, _)| v[2] == k)
        .map(|(v, _)| v)
        .collect()
}

#[test]
fn projecting_a_pixels_hit_gives_back_the_pixel() {
    let mut v = view(Vec3::new(0.3, -0.2, 0.1), &[7.0]);
    v.twist = 17.0;
    v.look_at = Vec3::new(1.0, 0.5, 6.0);
    let rays = v.rays();
    for y in 0..32 {
        for x in 0..32 {
            let p = v.eye + Vec3::from(rays.dir(x as f32 + 0.5, y as f32 + 0.5)) * 5.0;
            let ((px, py), d) = v.project(p).unwrap();
            assert_eq!((px, py), (x, y));
            assert!((d - 5.0).abs() < 1e-4);
        }
    }
    assert_eq!(v.project(v.eye - (v.look_at - v.eye)), None);
}

/// Runs images `frames` through `m`, wall A (z = 5) present before
/// `gone`, the back wall (z = 10) always; returns A's voxel count after
/// each image.
fn run(m: &mut VisualMemory, frames: std::ops::Range<u32>, gone: u32) -> Vec<usize> {
    let eye = Vec3::new(0.0, 0.0, 0.0);
    frames
        .map(|f| {
            let planes: &[f32] = if f < gone { &[5.0, 10.0] } else { &[10.0] };
            m.integrate(&view(eye, planes), f);
            layer(m, 5.0).len()
        })
        .collect()
}

#[test]
fn a_wall_that_disappears_is_forgotten_after_n_images_seen_more_than_m_times() {
    let mut m = VisualMemory::with_thesis_rule(room_cube());
    assert_eq!((m.rule().n, m.rule().m), (5, 3));
    let counts = run(&mut m, 0..10, 5);
    let a = counts[4];
    assert!(a > 500, "{a}");
    // Gone from image 5 on: seen missing at 5, 6, 7, 8, 9 (5 > 3 times);
    // eliminated at the end of the 10th image, not one earlier.
    assert_eq!(&counts[..9], &[a; 9]);
    assert_eq!(counts[9], 0);
    assert!(m.suspects().occupied().is_empty());
    // The back wall stays.
    assert!(layer(&m, 10.0).len() > 600);
}

#[test]
fn three_sightings_are_not_enough_and_x_is_cleared() {
    let mut m = VisualMemory::with_thesis_rule(room_cube());
    // Gone from image 7: missing at 7, 8, 9 (3, not more than 3) when
    // the 10th image eliminates, then X restarts: 10 … 14.
    let counts = run(&mut m, 0..15, 7);
    let a = counts[0];
    assert!(a > 500);
    assert_eq!(&counts[..14], &[a; 14]);
    assert_eq!(counts[14], 0);
}

#[test]
fn n_and_m_are_configurable() {
    let cube = room_cube();
    let mut rule = Forgetting::thesis(cube.voxel_edge);
    rule.n = 2;
    rule.m = 1;
    let mut m = VisualMemory::new(cube, rule);
    // Gone from image 2: missing at 2 and 3, eliminated after image 3.
    let counts = run(&mut m, 0..4, 2);
    assert_eq!(counts[0], counts[2]);
    assert_eq!(counts[3], 0);
}

#[test]
fn a_wall_hidden_behind_another_is_not_forgotten() {
    let mut m = VisualMemory::with_thesis_rule(room_cube());
    let eye = Vec3::ZERO;
    // The far wall is seen alone, then a nearer wall hides it for good.
    for f in 0..5 {
        m.integrate(&view(eye, &[10.0]), f);
    }
    let far = layer(&m, 10.0);
    assert!(far.len() > 600);
    for f in 5..40 {
        let s = m.integrate(&view(eye, &[5.0, 10.0]), f);
        assert!(s.tested > 0);
        assert_eq!(s.removed, 0, "frame {f}");
    }
    assert_eq!(layer(&m, 10.0), far);
    assert!(layer(&m, 5.0).len() > 500);
}

/// splitmix64 points in the room cube.
fn points(seed: u64, n: usize) -> Vec<[f64; 3]> {
    let mut s = seed;
    let mut next = move || {
        s = s.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = s;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    };
    // A dense cluster (merges) and a sparse spread.
    (0..n)
        .map(|i| {
            let span = if i % 2 == 0 { 2.0 } else { 30.0 };
            [(); 3].map(|_| -15.0 + next() * span)
        })
        .collect()
}

#[test]
fn insertion_is_deterministic() {
    let pts = points(1997, 200_000);
    let build = |order: &mut dyn Iterator<Item = &[f64; 3]>| {
        let mut t = Octree::new(room_cube(), true);
        for p in order {
            assert!(t.insert_point(*p, 3));
        }
        t
    };
    let a = build(&mut pts.iter());
    let b = build(&mut pts.iter());
    let c = build(&mut pts.iter().rev());
    assert!(a.stored_count() < a.voxel_count());
    assert_eq!(a.occupied(), b.occupied());
    assert_eq!(a.memory_bytes(), b.memory_bytes());
    // The same set in another order gives the same tree.
    assert_eq!(a.occupied(), c.occupied());
    assert_eq!(a.voxel_count(), c.voxel_count());
    let mut want: Vec<Voxel> = pts.iter().map(|p| a.voxel(*p).unwrap()).collect();
    want.sort_unstable();
    want.dedup();
    let mut got: Vec<Voxel> = a.occupied_voxels().into_iter().map(|(v, _)| v).collect();
    got.sort_unstable();
    assert_eq!(got, want);
}
