//! Generated terraces for the conditional 3D search (issue 36, heuristic
//! 9 with the collision test 6): a lower floor, stairs of single steps up
//! to a plateau, a gap crossed by a bridge (or not: then the goal is out
//! of reach) to a second plateau with the goal. Laid on cells of one
//! search voxel (0.5) with every surface inside a voxel, as `terrain.lm`
//! (docs/actors.md, "The height of a support heuristic's path"). The
//! ground truth is the cells' own graph: a step to a neighbouring cell
//! with ground at most one level up or down.

use std::collections::VecDeque;

use super::support::written;
use crate::common::Rng;
use lmfilm::film::Film;
use lmfilm::lsys::Source;
use lmfilm::turtle::Options;

/// A cell's side, and where the grid begins (x, z of cell 0, 0).
const CELL: f32 = 0.5;
const X0: f32 = -9.0;
const Z0: f32 = -4.0;

/// Cells: the level of their ground (its top at 0.25 + 0.5·level), or
/// none (the void).
struct Terraces {
    levels: Vec<Vec<Option<u32>>>,
    start: (usize, usize),
    goal: (usize, usize),
    /// Boxes: cell x range, cell z range, bottom and top heights.
    boxes: Vec<([usize; 2], [usize; 2], f32, f32)>,
}

fn top(level: u32) -> f32 {
    0.25 + 0.5 * level as f32
}

impl Terraces {
    fn generate(seed: u64, bridge: bool) -> Terraces {
        let mut rng = Rng(seed.wrapping_mul(0x2545_F491_4F6C_DD1D) | 1);
        let floor = 6 + rng.below(6);
        let depth = 8 + rng.below(6);
        let plateau = 4 + rng.below(4);
        let gap = 2 + rng.below(4);
        let far = 4 + rng.below(4);
        let stairs_z = rng.below(depth - 3);
        let bridge_z = rng.below(depth - 3);
        let width = floor + 3 + plateau + gap + far;
        let mut levels = vec![vec![None; depth]; width];
        let mut boxes = Vec::new();
        let mut put = |xs: [usize; 2], zs: [usize; 2], level: u32, bottom: f32| {
            for row in levels.iter_mut().take(xs[1]).skip(xs[0]) {
                for c in row.iter_mut().take(zs[1]).skip(zs[0]) {
                    *c = Some(level);
                }
            }
            boxes.push((xs, zs, bottom, top(level)));
        };
        put([0, floor], [0, depth], 0, -0.25);
        for k in 0..3 {
            put(
                [floor + k, floor + k + 1],
                [stairs_z, stairs_z + 3],
                k as u32 + 1,
                -0.25,
            );
        }
        let a = floor + 3;
        put([a, a + plateau], [0, depth], 4, -0.25);
        let b = a + plateau;
        if bridge {
            put([b, b + gap], [bridge_z, bridge_z + 3], 4, top(4) - 0.2);
        }
        put([b + gap, width], [0, depth], 4, -0.25);
        Terraces {
            levels,
            start: (1 + rng.below(floor - 2), 1 + rng.below(depth - 2)),
            goal: (width - 2 - rng.below(far - 2), 1 + rng.below(depth - 2)),
            boxes,
        }
    }

    /// Whether a cell is ground an actor a voxel wide can stand on, as
    /// heuristic 9 asks: its four neighbours hold ground at most a level
    /// from its own (a bridge or a flight of steps is three cells wide).
    fn walkable(&self, (x, z): (usize, usize)) -> bool {
        let Some(Some(l)) = self.levels.get(x).and_then(|r| r.get(z)) else {
            return false;
        };
        let near = [
            (x.wrapping_sub(1), z),
            (x + 1, z),
            (x, z.wrapping_sub(1)),
            (x, z + 1),
        ];
        near.iter().all(|&(a, b)| {
            matches!(self.levels.get(a).and_then(|r| r.get(b)), Some(Some(m)) if m.abs_diff(*l) <= 1)
        })
    }

    /// Whether steps between walkable neighbouring cells, at most one
    /// level apart, lead from the start to the goal.
    fn reachable(&self) -> bool {
        let (w, d) = (self.levels.len(), self.levels[0].len());
        let mut seen = vec![vec![false; d]; w];
        let mut todo = VecDeque::from([self.start]);
        seen[self.start.0][self.start.1] = true;
        while let Some((x, z)) = todo.pop_front() {
            let here = self.levels[x][z].expect("on ground");
            let near = [
                (x.wrapping_sub(1), z),
                (x + 1, z),
                (x, z.wrapping_sub(1)),
                (x, z + 1),
            ];
            for (a, b) in near {
                let Some(Some(l)) = self.levels.get(a).and_then(|r| r.get(b)) else {
                    continue;
                };
                if !seen[a][b] && l.abs_diff(here) <= 1 && self.walkable((a, b)) {
                    seen[a][b] = true;
                    todo.push_back((a, b));
                }
            }
        }
        seen[self.goal.0][self.goal.1]
    }

    fn centre(&self, (x, z): (usize, usize)) -> (f32, f32) {
        (X0 + (x as f32 + 0.5) * CELL, Z0 + (z as f32 + 0.5) * CELL)
    }

    /// The level under world point (x, z), None over the void.
    fn level_at(&self, x: f32, z: f32) -> Option<u32> {
        let (i, j) = (((x - X0) / CELL).floor(), ((z - Z0) / CELL).floor());
        if i < 0.0 || j < 0.0 {
            return None;
        }
        *self.levels.get(i as usize)?.get(j as usize)?
    }

    fn scene(&self, window: u32, fov: u32) -> String {
        let mut axiom = String::new();
        for (xs, zs, bottom, top) in &self.boxes {
            // 0.01 inside their columns: what vision sees of a box falls
            // in the voxels it fills.
            let x = X0 + xs[0] as f32 * CELL + 0.01;
            let dx = (xs[1] - xs[0]) as f32 * CELL - 0.02;
            let zc = Z0 + (zs[0] + zs[1]) as f32 * CELL / 2.0;
            let dz = (zs[1] - zs[0]) as f32 * CELL - 0.02;
            axiom += &format!(
                "[ f () () () (2) ({}) ({}) ({}) c () () () () ({dx}) ({}) ({dz}) ]\n",
                written(x),
                written((bottom + top) / 2.0),
                written(zc),
                top - bottom
            );
        }
        let (sx, sz) = self.centre(self.start);
        let (gx, gz) = self.centre(self.goal);
        let eye = |c: (usize, usize)| top(self.levels[c.0][c.1].expect("ground")) + 0.5;
        format!(
            "Camera_AnimationParameters\nt_final_interval 300.0 0.04\nOptions\nNBR_actors 1\n\
             iVisionWinSize 0 {window} 8\n\
             actorNbr_automata 0 walk_continuously init 0 -16 16 0.25 obs {sx} {} {sz} lat {} {} {sz} \
             fov {fov} vision_range 0.3 30 30 goal {gx} {} {gz} speed 3 heuristic 9 coll_test_func 6 \
             ahead 4 rel_search_level 1\n\
             Axiom\n{axiom}Productions\nEndProductions\n",
            eye(self.start),
            sx + 1.0,
            eye(self.start),
            eye(self.goal),
        )
    }
}

/// Walks terraces `seed`: (arrived, gave up, fell, what).
fn walk(seed: u64, bridge: bool) -> (bool, bool, bool, String) {
    let t = Terraces::generate(seed, bridge);
    let mut rng = Rng(seed ^ 0x7777 | 1);
    let (window, fov) = ([32, 48, 64][rng.below(3)], [900, 1200][rng.below(2)]);
    let text = t.scene(window, fov);
    if let Ok(dir) = std::env::var("LMFILM_WORLDS_DUMP") {
        std::fs::write(format!("{dir}/terraces_{seed}_{bridge}.lm"), &text).unwrap();
    }
    let mut film = Film::from_sources(
        &[Source::new("terraces.lm", &text)],
        None,
        Options::default(),
    )
    .unwrap_or_else(|e| panic!("{e}"));
    let (gx, gz) = t.centre(t.goal);
    let mut fell = false;
    let mut arrived = false;
    while film.next_frame().unwrap().is_some() {
        let a = &film.living()[0];
        // Its eye over ground, at most a step over it: never over the void.
        match t.level_at(a.eye.x, a.eye.z) {
            Some(l) => fell |= a.eye.y < top(l) + 0.2,
            None => fell = true,
        }
        if (a.eye.x - gx).hypot(a.eye.z - gz) < 0.3 {
            arrived = true;
            break;
        }
        if a.gave_up.is_some() {
            break;
        }
    }
    let a = &film.living()[0];
    let what = format!(
        "seed {seed}, bridge {bridge}, window {window}, fov {fov}: at {}, gave up {:?}",
        a.eye, a.gave_up
    );
    (arrived, a.gave_up.is_some(), fell, what)
}

fn check(seeds: std::ops::Range<u64>) {
    let mut failures = Vec::new();
    for seed in seeds {
        for bridge in [true, false] {
            let reachable = Terraces::generate(seed, bridge).reachable();
            assert_eq!(reachable, bridge, "seed {seed}: the ground truth");
            let (arrived, gave_up, fell, what) = walk(seed, bridge);
            if fell {
                failures.push(format!("fell: {what}"));
            }
            if reachable && !arrived {
                failures.push(format!("not arrived: {what}"));
            }
            if !reachable && !gave_up {
                failures.push(format!("unreachable, not reported: {what}"));
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// The bounded sample CI runs: one field with its bridge, one without.
#[test]
fn a_sample_of_generated_terraces() {
    check(0..1);
}

/// More: `cargo test --test actors many_generated_terraces -- --ignored`
/// (30 terraces, each with its bridge and without).
#[test]
#[ignore]
fn many_generated_terraces() {
    check(0..30);
}
