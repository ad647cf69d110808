//! Step planning on sparse footholds (thesis 5.9.3, 7.3.2): a field of
//! 500 stones, a 25 × 20 grid 0.7 apart jittered by up to ±0.1 from a
//! fixed seed (about 17 × 13 units), Df_max 1.0, the default gait and the
//! thesis's weights, planned corner to corner (`plan500`); and the local
//! map of the same field extracted from a visual memory of voxels 0.05
//! whose stone tops (0.3 × 0.3: 6 × 6 voxels) fill one layer and their
//! sides ring the layer under it (`map500`, 5.9.2).
//!
//! `cargo bench --bench footholds -- --sample-size 10`

use criterion::Criterion;
use glam::Vec2;
use lmfilm::actors::footholds::map::{local_map, Region};
use lmfilm::actors::footholds::plan::{plan, Gait, Weights};
use lmfilm::actors::perception::octree::{Cube, Octree};

/// The stones, row by row from the corner at the origin, each jittered
/// by up to ±0.1 from the crate's keyed random stream.
fn field() -> Vec<Vec2> {
    let jitter = |slot: u64| lmfilm::random::unit(17, slot) as f32 * 0.2 - 0.1;
    (0..20u64)
        .flat_map(|row| (0..25u64).map(move |col| (row, col)))
        .map(|(row, col)| {
            let k = 2 * (row * 25 + col);
            Vec2::new(
                col as f32 * 0.7 + jitter(k),
                row as f32 * 0.7 + jitter(k + 1),
            )
        })
        .collect()
}

/// A memory holding the stones of `field`, tops at y = 0.
fn memory(stones: &[Vec2]) -> Octree {
    let mut t = Octree::new(Cube::new(-1.025, 18.975, 0.05), true);
    for s in stones {
        for i in 0..6 {
            for j in 0..6 {
                let (x, z) = (s.x - 0.125 + 0.05 * i as f32, s.y - 0.125 + 0.05 * j as f32);
                let at = |y: f64| [f64::from(x), y, f64::from(z)];
                t.insert_point(at(0.0), 1);
                if i == 0 || j == 0 || i == 5 || j == 5 {
                    t.insert_point(at(-0.05), 1);
                }
            }
        }
    }
    t
}

fn main() {
    // `cargo test --all-targets` runs benches without `--bench`: skip.
    if !std::env::args().any(|a| a == "--bench") {
        return;
    }
    let mut c = Criterion::default().configure_from_args().sample_size(10);
    let stones = field();
    let (start, goal) = (0, stones.len() - 1);
    let facing = stones[goal] - stones[start];
    let (gait, weights) = (Gait::default(), Weights::default());
    let p = plan(&stones, start, goal, facing, &gait, &weights).expect("the field has a walk");
    println!(
        "plan500: {} states, {} halts, cost {:.3}, {} states settled",
        p.steps.len(),
        p.steps.iter().filter(|s| s.is_halt()).count(),
        p.cost,
        p.settled
    );
    let mut group = c.benchmark_group("footholds");
    group.bench_function("plan500", |bench| {
        bench.iter(|| plan(&stones, start, goal, facing, &gait, &weights).unwrap())
    });
    let tree = memory(&stones);
    let region = Region {
        centre: glam::Vec3::new(8.4, 0.0, 6.65),
        range: 12.0,
        plane: 0.0,
    };
    println!(
        "map500: {} footholds from {} voxels",
        local_map(&tree, &region, 4, 0.3).len(),
        tree.voxel_count()
    );
    group.bench_function("map500", |bench| {
        bench.iter(|| local_map(&tree, &region, 4, 0.3))
    });
    group.finish();
}
