//! Generated stepping-stone fields (issue 36): stones the size of a foot
//! along a wandering way with a gap to go round, stray stones beside it,
//! their tops at any height against the memory's voxels; the ground
//! truth is the stones' own graph (steps shorter than the longest step,
//! `foothold_step`'s 1.0). A `walk_stepworthy` actor who knows nothing of
//! them walks to the stone nearest its goal, over windows of 40–64
//! pixels, eyes at 1.2–1.8, with and without `foothold_plane`, with a
//! head drawn round its eye or none.

use glam::Vec3;

use super::support::written;
use crate::common::Rng;
use lmfilm::film::Film;
use lmfilm::lsys::Source;
use lmfilm::turtle::Options;

/// The longest step (`foothold_step`'s default df_max).
const DF_MAX: f32 = 1.0;

/// Uniform in [a, b), as the stones' f32.
fn uniform(rng: &mut Rng, a: f32, b: f32) -> f32 {
    rng.uniform(a.into(), b.into()) as f32
}

/// A field: the stones' centres on the ground (x, z), the first the
/// start, and the top's height.
struct Field {
    stones: Vec<(f32, f32)>,
    goal: (f32, f32),
    top: f32,
}

impl Field {
    /// Stones 0.55–0.75 apart along a way heading +z with a sideways
    /// wander; past a third of it the straight way has a gap (a missing
    /// stone), and a detour of stones to the east goes round it; stray
    /// stones lie beside the way.
    fn generate(seed: u64) -> Field {
        let mut rng = Rng(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1);
        let mut stones = vec![(0.0, 0.0)];
        let (mut x, mut z) = (0.0f32, 0.0f32);
        let n = 8 + rng.below(3);
        for k in 1..n {
            z += uniform(&mut rng, 0.55, 0.75);
            x += uniform(&mut rng, -0.25, 0.25);
            if k == n / 3 {
                // The gap: this stone is missing; a detour east goes round.
                let (dx, dz) = (x + 0.6, z - 0.3);
                stones.push((dx, dz));
                stones.push((dx + 0.1, dz + 0.6));
                stones.push((dx, dz + 1.2));
                z += 0.65;
                continue;
            }
            stones.push((x, z));
        }
        let last = *stones.last().expect("stones");
        for _ in 0..3 {
            let s = stones[1 + rng.below(stones.len() - 1)];
            stones.push((s.0 - uniform(&mut rng, 1.2, 1.8), s.1));
        }
        Field {
            stones,
            goal: (last.0, last.1 + 0.3),
            top: uniform(&mut rng, -0.05, 0.05),
        }
    }

    /// Whether steps shorter than `DF_MAX` lead from the first stone to
    /// the one nearest the goal (breadth first over the stones).
    fn reachable(&self) -> bool {
        let d = |a: (f32, f32), b: (f32, f32)| (a.0 - b.0).hypot(a.1 - b.1);
        let end = (0..self.stones.len())
            .min_by(|&a, &b| d(self.stones[a], self.goal).total_cmp(&d(self.stones[b], self.goal)))
            .expect("stones");
        let mut seen = vec![false; self.stones.len()];
        let mut todo = vec![0];
        seen[0] = true;
        while let Some(i) = todo.pop() {
            let here = self.stones[i];
            for (j, s) in self.stones.iter().enumerate() {
                if !seen[j] && d(here, *s) < DF_MAX {
                    seen[j] = true;
                    todo.push(j);
                }
            }
        }
        seen[end]
    }
}

/// Settings drawn over the range the thesis's actors use.
struct Settings {
    window: u32,
    eye: f32,
    plane: bool,
    head: bool,
}

fn scene(f: &Field, s: &Settings) -> String {
    let mut axiom = String::new();
    if s.head {
        axiom += "[ M () (7) () (0) a () () () () (0.24) ]\n";
    }
    for &(x, z) in &f.stones {
        // A box 0.05 thick whose top is at f.top.
        axiom += &format!(
            "[ f () () () (2) ({}) ({}) ({}) + () () () () (90) c () () () () (0.05) (0.3) (0.3) ]\n",
            written(x),
            written(f.top - 0.05),
            written(z)
        );
    }
    let (x0, z0) = f.stones[0];
    format!(
        "Camera_AnimationParameters\nt_final_interval 30.0 0.04\nOptions\nNBR_actors 1\n\
         iVisionWinSize 0 {} 8\n\
         actorNbr_automata 0 walk_stepworthy init 10 -4 8.8 0.05 obs {x0} {} {z0} lat {x0} {} {} \
         fov 900 goal {} {} {} speed 1.2 size_actor 0.35{}\n\
         Axiom\n{axiom}Productions\nEndProductions\n",
        s.window,
        f.top + s.eye,
        f.top,
        z0 + 3.0,
        f.goal.0,
        f.top,
        f.goal.1,
        if s.plane { " foothold_plane 0" } else { "" }
    )
}

/// Walks field `seed`: whether the actor ended within a step of the goal
/// stone, and every foothold it stood on lay on a stone.
fn walk(seed: u64) -> (bool, bool, String) {
    let f = Field::generate(seed);
    let mut rng = Rng(seed ^ 0x5555 | 1);
    let s = Settings {
        window: [40, 48, 50, 64][rng.below(4)],
        eye: [1.2, 1.6, 1.8][rng.below(3)],
        plane: rng.below(2) == 0,
        head: rng.below(2) == 0,
    };
    let text = scene(&f, &s);
    let mut film = Film::from_sources(&[Source::new("stones.lm", &text)], None, Options::default())
        .unwrap_or_else(|e| panic!("{e}"));
    let mut on_stones = true;
    while film.next_frame().unwrap().is_some() {
        let a = &film.living()[0];
        if let Some(on) = a.footing.on {
            let near = f
                .stones
                .iter()
                .any(|&(x, z)| (on.x - x).hypot(on.z - z) < 0.2);
            on_stones &= near;
        }
        if a.gave_up.is_some() || (a.footing.plans > 0 && a.footing.destination.is_none()) {
            break;
        }
    }
    let a = &film.living()[0];
    let goal = Vec3::new(f.goal.0, a.eye.y, f.goal.1);
    let arrived = a.gave_up.is_none() && a.eye.distance(goal) < DF_MAX;
    let what = format!(
        "seed {seed}: window {}, eye {}, plane {}, head {}, top {:.3}, at {}, gave up {:?}",
        s.window, s.eye, s.plane, s.head, f.top, a.eye, a.gave_up
    );
    (arrived, on_stones, what)
}

fn check(seeds: impl Iterator<Item = u64>) {
    let mut failures = Vec::new();
    let mut n = 0;
    for seed in seeds {
        assert!(
            Field::generate(seed).reachable(),
            "seed {seed}: the field itself"
        );
        let (arrived, on_stones, what) = walk(seed);
        n += 1;
        if !arrived {
            failures.push(format!("not arrived: {what}"));
        }
        if !on_stones {
            failures.push(format!("stood off the stones: {what}"));
        }
    }
    println!("{} of {n} stone fields walked", n - failures.len());
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// The bounded sample CI runs.
#[test]
fn a_sample_of_stepping_stone_fields() {
    check(0..3);
}

/// More fields: `cargo test --test actors stepping_stone_fields -- --ignored`.
#[test]
#[ignore]
fn many_stepping_stone_fields() {
    check(0..30);
}
