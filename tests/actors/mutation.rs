//! A bounded mutation test of the actors, run on every change (issue
//! 43; the open-ended fuzzing is `tests/fuzz/`, target `actors`).
//!
//! From the shipped actor and tennis scenes, a fixed number of mutants
//! with a fixed seed, each changing what a user placing actors writes:
//! a number of an actor option or automata command replaced by an edge
//! value (0, −1, 10³⁰, a 2²⁰-voxel cube, …), an automata command added
//! (`turtle 3`, a goal 10³⁰ away, `trace_actor 0 actors`, …), an actor
//! line doubled or deleted, a number of an `M` or `g` symbol replaced.
//! Each mutant is loaded and its first frames run. It fails on
//! - a panic;
//! - a refusal at load without a location (file:line:column and caret);
//! - a mutant over its time budget;
//! - a non-finite number in what `trace` prints;
//! - a navigator (walk_continuously, walk_stepworthy) with a goal that
//!   stands still and looks the same way from frame 1 to the last frame
//!   run, away from its goal, without a warning about it or a `gave_up`.

use std::panic::{self, AssertUnwindSafe};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use lmfilm::film::trace::Record;
use lmfilm::film::Film;
use lmfilm::lsys::Source;
use lmfilm::turtle::Options;

use crate::common::{PanicPool, Rng};

/// Mutants in all: about a minute in the test profile on two cores.
/// `LMFILM_ACTOR_MUTANTS` and `LMFILM_ACTOR_SEED` run more or others.
const CASES: u64 = 240;

/// Frames run per mutant.
const FRAMES: usize = 12;

/// Most time one mutant may take, loading and frames together: fifty
/// times what the slowest shipped scene takes here.
const BUDGET: Duration = Duration::from_secs(20);

fn setting(name: &str, default: u64) -> u64 {
    std::env::var(name)
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}

/// The shipped scenes with actors, sorted: (path, text).
fn actor_scenes() -> Vec<(PathBuf, String)> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes");
    let mut out = Vec::new();
    for dir in ["actors", "tennis"] {
        for f in std::fs::read_dir(root.join(dir)).unwrap() {
            let p = f.unwrap().path();
            if p.extension().is_some_and(|e| e == "lm") {
                let text = std::fs::read_to_string(&p).unwrap();
                if text.contains("NBR_actors") {
                    out.push((p, text));
                }
            }
        }
    }
    out.sort();
    out
}

/// What a user may write for a number of an actor option or command.
const NUMBERS: &[&str] = &[
    "0",
    "-1",
    "1",
    "2",
    "3",
    "4",
    "7",
    "15",
    "20",
    "21",
    "0.001",
    "0.5",
    "-0.5",
    "99",
    "1024",
    "1025",
    "100000",
    "1048576",
    "1e15",
    "-1e15",
    "1e30",
    "-1e30",
    "4294967296",
];

/// Commands a user may add to an actor's automata.
const COMMANDS: &[&str] = &[
    "turtle 3",
    "turtle 1",
    "turtle 4",
    "init 0 -524288 524288 1",
    "init 0 -4 4 1 rel_search_level 2",
    "init 0 -5 5 0.001",
    "rel_search_level 20",
    "rel_search_level 0",
    "heuristic 15",
    "heuristic 7",
    "goal 1e30 0 0",
    "goal 0 1e30 0",
    "goal 500000 0 0",
    "goal 0 0 0",
    "local_goal 1e30 1e30 1e30",
    "speed 1e30",
    "speed 0",
    "size_actor 1e30",
    "dist_coll 1e30",
    "vision_range 0 1e30 1e30",
    "vision_range 0.001 0.002 0",
    "fov 1",
    "fov 1799",
    "inertia 1e30",
    "ahead 1000000",
    "optim_rate 1 optim_ahead 1000000",
    "mem_displ_cubes",
    "vis_mem_off",
    "reset_goal",
    "foothold_map 1e30 1",
    "foothold_step 1e30 1e30",
    "trace_actor 0 actors",
];

/// What a user may write in an `M` or `g` symbol's parameter.
const SYMBOL_NUMBERS: &[&str] = &[
    "0", "1", "2", "3", "7", "99", "1_", "0.5", "1e30", "10 60 ^",
];

/// Lines that configure actors.
fn actor_lines(text: &str) -> Vec<usize> {
    text.lines()
        .enumerate()
        .filter(|(_, l)| {
            let l = l.trim_start();
            l.starts_with("actorNbr_automata")
                || l.starts_with("iVisionWinSize")
                || l.starts_with("NBR_actors")
                || l.starts_with("trace_actor")
        })
        .map(|(i, _)| i)
        .collect()
}

/// Axiom and production lines with an `M` or `g` symbol.
fn symbol_lines(text: &str) -> Vec<usize> {
    text.lines()
        .enumerate()
        .filter(|(_, l)| l.contains("M (") || l.contains("g ("))
        .map(|(i, _)| i)
        .collect()
}

fn pick<'a, T>(v: &'a [T], rng: &mut Rng) -> Option<&'a T> {
    (!v.is_empty()).then(|| &v[rng.below(v.len())])
}

/// One mutation of an actor scene.
fn mutate(text: &str, rng: &mut Rng) -> String {
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    let actors = actor_lines(text);
    let symbols = symbol_lines(text);
    match rng.below(5) {
        0 => {
            if let Some(&i) = pick(&actors, rng) {
                let mut words: Vec<String> =
                    lines[i].split_whitespace().map(str::to_string).collect();
                let numeric: Vec<usize> = (1..words.len())
                    .filter(|&k| words[k].parse::<f64>().is_ok())
                    .collect();
                if let Some(&k) = pick(&numeric, rng) {
                    words[k] = pick(NUMBERS, rng).unwrap().to_string();
                    lines[i] = words.join(" ");
                }
            }
        }
        1 => {
            let automata: Vec<usize> = actors
                .iter()
                .copied()
                .filter(|&i| lines[i].trim_start().starts_with("actorNbr_automata"))
                .collect();
            if let Some(&i) = pick(&automata, rng) {
                let c = pick(COMMANDS, rng).unwrap();
                lines[i] = format!("{} {c}", lines[i]);
            }
        }
        2 => {
            if let Some(&i) = pick(&actors, rng) {
                let l = lines[i].clone();
                lines.insert(i, l);
            }
        }
        3 => {
            if let Some(&i) = pick(&actors, rng) {
                lines.remove(i);
            }
        }
        _ => {
            if let Some(&i) = pick(&symbols, rng) {
                let l = &lines[i];
                let groups: Vec<usize> = l.match_indices('(').map(|(k, _)| k).collect();
                if let Some(&k) = pick(&groups, rng) {
                    if let Some(end) = l[k..].find(')') {
                        let n = pick(SYMBOL_NUMBERS, rng).unwrap();
                        lines[i] = format!("{}({n}){}", &l[..k], &l[k + end + 1..]);
                    }
                }
            }
        }
    }
    lines.join("\n") + "\n"
}

/// What went wrong with one mutant, if anything.
fn run_mutant(text: &str, dir: &Path) -> Result<(), String> {
    let mut opts = Options::default();
    opts.limits.memory_bytes = 1 << 30;
    let film = Film::from_sources(&[Source::new("mutant.lm", text)], Some(dir), opts);
    let mut film = match film {
        Ok(f) => f,
        Err(e) => {
            let msg = e.to_string();
            // A refusal names the place: mutant.lm:LINE:COL, the line, a caret.
            let located = msg.contains("mutant.lm:") && msg.contains('^');
            return if located {
                Ok(())
            } else {
                Err(format!("a refusal without a location: {msg}"))
            };
        }
    };
    let mut records = Vec::new();
    let mut warnings = Vec::new();
    for _ in 0..FRAMES {
        match film.next_frame() {
            Ok(Some(_)) => {}
            // A frame may stop the film with an error (exit 2).
            Ok(None) | Err(_) => break,
        }
        warnings.extend(film.frame().unwrap().warnings().iter().cloned());
        let record = Record::of(&film).expect("a frame ran");
        finite(&record)?;
        records.push(record);
    }
    standing(&records, &warnings)
}

/// Every number `trace` prints of the actors and particles is finite.
fn finite(r: &Record) -> Result<(), String> {
    for a in &r.actors {
        let points = [Some(a.pos), Some(a.look_at), a.goal, a.position];
        if points.iter().flatten().flatten().any(|v| !v.is_finite()) {
            return Err(format!(
                "frame {}: actor {} has a non-finite number in trace: pos {:?} look_at {:?} goal {:?} position {:?}",
                r.frame, a.id, a.pos, a.look_at, a.goal, a.position
            ));
        }
    }
    for p in &r.particles {
        if p.pos.iter().chain(&p.vel).any(|v| !v.is_finite()) {
            return Err(format!(
                "frame {}: particle {} is not finite in trace",
                r.frame, p.id
            ));
        }
    }
    Ok(())
}

/// A navigator with a goal that never moves nor turns from frame 1 on,
/// away from its goal, without a word.
fn standing(records: &[Record], warnings: &[String]) -> Result<(), String> {
    let (Some(first), Some(last)) = (records.get(1), records.last()) else {
        return Ok(());
    };
    if records.len() < FRAMES {
        return Ok(());
    }
    for (a, z) in first.actors.iter().zip(&last.actors) {
        let navigating =
            |n: Option<&str>| matches!(n, Some("walk_continuously") | Some("walk_stepworthy"));
        let Some(goal) = a.goal else { continue };
        let arrived = glam::Vec3::from(a.pos).distance(glam::Vec3::from(goal)) < 0.5;
        let still = a.pos == z.pos && a.look_at == z.look_at;
        let said = warnings
            .iter()
            .any(|w| w.contains(&format!("actor {} ", a.id)));
        let silent = !said && z.gave_up.is_none();
        if navigating(a.automata) && navigating(z.automata) && still && !arrived && silent {
            return Err(format!(
                "actor {} ({:?}) stands at {:?} from frame 1 to {} with goal {:?}, without a warning",
                a.id, z.automata, z.pos, last.frame, goal
            ));
        }
    }
    Ok(())
}

/// The threads that run the mutants: only their panics are recorded.
const MUTANT_THREAD: &str = "lmfilm-actor-mutants";

#[test]
fn mutated_actor_scenes_run_or_say_why() {
    let panics = PanicPool::new(MUTANT_THREAD);
    let cases = setting("LMFILM_ACTOR_MUTANTS", CASES);
    let mut rng = Rng(setting("LMFILM_ACTOR_SEED", 0x5eed_ac70));
    let scenes = actor_scenes();
    assert!(scenes.len() >= 10, "the actor scenes are found");
    let mut failures = Vec::new();
    let mut slowest = Duration::ZERO;
    let total = cases + scenes.len() as u64;
    for case in 0..total {
        // The shipped scenes themselves first, then the mutants.
        let k = case as usize % scenes.len();
        let (path, text) = &scenes[k];
        let mutant = if (case as usize) < scenes.len() {
            text.clone()
        } else {
            mutate(text, &mut rng)
        };
        let dir = path.parent().unwrap();
        let start = Instant::now();
        let outcome = panics
            .pool
            .install(|| panic::catch_unwind(AssertUnwindSafe(|| run_mutant(&mutant, dir))));
        let took = start.elapsed();
        slowest = slowest.max(took);
        let what = match outcome {
            Ok(Ok(())) if took > BUDGET => Some(format!("took {took:?}, over {BUDGET:?}")),
            Ok(Ok(())) => None,
            Ok(Err(e)) => Some(e),
            Err(_) => Some(format!("panicked: {}", panics.last_panic())),
        };
        if let Some(w) = what {
            failures.push(format!(
                "case {case} from {}:\n{w}\n--- mutant ---\n{mutant}",
                path.display()
            ));
        }
    }
    drop(panics);
    println!(
        "actor mutants: {total} cases ({} shipped scenes), {} failed, slowest {slowest:?}",
        scenes.len(),
        failures.len()
    );
    assert!(
        failures.is_empty(),
        "{} of the mutants failed; the first:\n{}",
        failures.len(),
        failures[0]
    );
}
