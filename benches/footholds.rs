//! Step planning on sparse footholds (thesis 5.9.3, 7.3.2): a field of
//! 500 stones, a 25 × 20 grid 0.7 apart jittered by up to ±0.1 from a
//! fixed seed (about 17 × 13 units), Df_max 1.0, the default gait and the
//! thesis's weights, planned corner to corner (`plan500`).
//!
//! `cargo bench --bench footholds -- --sample-size 10`

use criterion::Criterion;
use glam::Vec2;
use lmfilm::actors::footholds::plan::{plan, Gait, Weights};

/// The stones, row by row from the corner at the origin.
fn field() -> Vec<Vec2> {
    let mut seed = 0x2545_f491_4f6c_dd1d_u64;
    let mut jitter = move || {
        // SplitMix64, mapped to [-0.1, 0.1).
        seed = seed.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = seed;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        ((z ^ (z >> 31)) >> 40) as f32 / (1u32 << 24) as f32 * 0.2 - 0.1
    };
    (0..20)
        .flat_map(|row| (0..25).map(move |col| (row, col)))
        .map(|(row, col)| Vec2::new(col as f32 * 0.7 + jitter(), row as f32 * 0.7 + jitter()))
        .collect()
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
    group.finish();
}
