//! The path search (issue 14) on a maze in a 128 × 128 × 8 visual memory
//! (voxel 1, a floor at y = 0, walls 1 voxel thick from y = 1 to 7, a
//! recursive-backtracker maze from a fixed seed), corner to corner at
//! y = 1, against an A* (4-connected, Manhattan distance, binary heap) on
//! the same voxel graph: its arcs are the heuristic's candidates, asked
//! of the same memory through the same `SearchGrid`.
//!
//! - `maze1/h0`: corridors 1 voxel wide (one voxel per cell), heuristic 0;
//!   heuristic 1 (a voxel of clearance) has no path there at all.
//! - `maze3/h1`: corridors 3 voxels wide, heuristic 1.
//!
//! Cases: `plan` (world points in and out, Algorithms 1–4), `algorithm1`
//! (`search` alone, the depth-first part), `astar`.
//!
//! `cargo bench --bench path -- --sample-size 10`

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use criterion::Criterion;
use lmfilm::actors::perception::octree::{Cube, Octree, Voxel};
use lmfilm::actors::planning::heuristics::{candidates, heuristic, Heuristic};
use lmfilm::actors::planning::path::{plan, plan_voxels, search, SearchGrid};
use rustc_hash::FxHashMap;

const EDGE: u32 = 128;
const HEIGHT: u32 = 8;
const LIMIT: usize = 1 << 20;

/// The memory of a maze whose cells are `lane` voxels wide, walls 1.
fn maze(lane: u32) -> Octree {
    let pitch = lane + 1;
    let cells = EDGE / pitch;
    // open[x][z]: the voxel column is free.
    let mut open = vec![vec![false; EDGE as usize]; EDGE as usize];
    let mut carve = |x0: u32, z0: u32, w: u32, d: u32| {
        for x in x0..x0 + w {
            for z in z0..z0 + d {
                open[x as usize][z as usize] = true;
            }
        }
    };
    let mut seen = vec![false; (cells * cells) as usize];
    let mut stack = vec![(0u32, 0u32)];
    seen[0] = true;
    carve(1, 1, lane, lane);
    let mut seed = 0x2545_f491_4f6c_dd1d_u64;
    while let Some(&(cx, cz)) = stack.last() {
        let next: Vec<(u32, u32)> = [(1i64, 0i64), (-1, 0), (0, 1), (0, -1)]
            .iter()
            .map(|&(dx, dz)| (i64::from(cx) + dx, i64::from(cz) + dz))
            .filter(|&(x, z)| {
                (0..i64::from(cells)).contains(&x) && (0..i64::from(cells)).contains(&z)
            })
            .map(|(x, z)| (x as u32, z as u32))
            .filter(|&(x, z)| !seen[(x * cells + z) as usize])
            .collect();
        if next.is_empty() {
            stack.pop();
            continue;
        }
        // xorshift64: the same maze on every machine.
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        let (nx, nz) = next[(seed % next.len() as u64) as usize];
        seen[(nx * cells + nz) as usize] = true;
        carve(nx * pitch + 1, nz * pitch + 1, lane, lane);
        // The wall between the two cells.
        let (wx, wz) = (cx.max(nx) * pitch, cz.max(nz) * pitch);
        if nx != cx {
            carve(wx, cz * pitch + 1, 1, lane);
        } else {
            carve(cx * pitch + 1, wz, lane, 1);
        }
        stack.push((nx, nz));
    }
    let mut m = Octree::new(Cube::new(0.0, f64::from(EDGE), 1.0), false);
    for x in 0..EDGE {
        for z in 0..EDGE {
            m.insert([x, 0, z], 0);
            if !open[x as usize][z as usize] {
                for y in 1..HEIGHT {
                    m.insert([x, y, z], 0);
                }
            }
        }
    }
    m
}

/// A*: the path length in voxels and the nodes expanded.
fn astar(h: &Heuristic, grid: &SearchGrid, start: Voxel, end: Voxel) -> Option<(usize, usize)> {
    let manhattan = |v: Voxel| -> u32 { (0..3).map(|i| v[i].abs_diff(end[i])).sum() };
    let mut g: FxHashMap<Voxel, u32> = FxHashMap::from_iter([(start, 0)]);
    let mut heap = BinaryHeap::from([Reverse((manhattan(start), 0u32, start))]);
    let mut expanded = 0;
    while let Some(Reverse((_, gu, u))) = heap.pop() {
        if gu > g[&u] {
            continue;
        }
        expanded += 1;
        if u == end {
            return Some((gu as usize + 1, expanded));
        }
        for w in candidates(h, u, |v| grid.is_empty(v)) {
            let gw = gu + 1;
            if g.get(&w).is_none_or(|&old| gw < old) {
                g.insert(w, gw);
                heap.push(Reverse((gw + manhattan(w), gw, w)));
            }
        }
    }
    None
}

fn main() {
    // `cargo test --all-targets` runs benches without `--bench`: skip.
    if !std::env::args().any(|a| a == "--bench") {
        return;
    }
    let mut c = Criterion::default().configure_from_args().sample_size(10);
    for (name, lane, n) in [("maze1/h0", 1, 0), ("maze3/h1", 3, 1)] {
        let m = maze(lane);
        let h = heuristic(n).unwrap();
        let grid = SearchGrid::new(&m, 0);
        // The middles of the corner cells.
        let (near, far) = (lane / 2 + 1, EDGE - lane - 1 + lane / 2 + 1);
        let (s, e) = ([near, 1, near], [far, 1, far]);
        let (a, b) = (grid.centre(s), grid.centre(e));
        let p = plan_voxels(h, s, e, |v| grid.is_empty(v), LIMIT).expect("the maze has a path");
        let (len, expanded) = astar(h, &grid, s, e).expect("A* finds it too");
        println!(
            "{name}: plan visited {} (Algorithm 1), corridor {}, searched path {} voxels, planned path {} voxels; A* expanded {expanded}, path {len} voxels",
            p.visited,
            p.corridor,
            p.searched.len(),
            p.path.len()
        );
        if n == 0 {
            let h1 = heuristic(1).unwrap();
            println!(
                "{name}: heuristic 1 finds a path: {}",
                plan(&m, a, b, h1, 0, LIMIT).is_ok()
            );
        }
        let mut group = c.benchmark_group(name);
        group.bench_function("plan", |bench| {
            bench.iter(|| plan(&m, a, b, h, 0, LIMIT).unwrap())
        });
        group.bench_function("algorithm1", |bench| {
            bench.iter(|| search(h, s, e, |v| grid.is_empty(v), LIMIT).unwrap())
        });
        group.bench_function("astar", |bench| {
            bench.iter(|| astar(h, &grid, s, e).unwrap())
        });
        group.finish();
    }
}
