//! A bounded mutation test of the actors, run on every change (issues
//! 43 and 54; the open-ended fuzzing is `tests/fuzz/`, target `actors`).
//!
//! Two rounds, each a fixed number of mutants with a fixed seed, from the
//! shipped actor and tennis scenes:
//!
//! - **single changes** (issue 43): from the `.lm` scenes, each mutant
//!   one change of what a user placing actors writes: a number of an
//!   actor option or automata command replaced by an edge value (0, −1,
//!   10³⁰, a 2²⁰-voxel cube, …), an automata command added (`turtle 3`, a
//!   goal 10³⁰ away, `trace_actor 0 actors`, …), an actor line doubled or
//!   deleted, a number of an `M` or `g` symbol replaced; its first
//!   [`FRAMES`] frames run;
//! - **combined changes** (issue 54): from the `.lm` and the readable
//!   `.lmr` scenes alike (those with a walking actor three times as
//!   often), each mutant 2–5 changes: first a setting of a walking actor
//!   at an edge of its documented range ([`WALK_EDGES`], a window of 1–8
//!   pixels), then 1–4 of those above (in the readable form the
//!   arguments of `actor(…)`, `memory_camera(…)`, `body(…)`, …; `D` 50
//!   bodies too), a number nudged (twice, half, ten times, …), an
//!   automata renamed, an actor number repeated on an automata line, a
//!   trajectory written (`trace_actor` with a name from [`TRACE_NAMES`]
//!   and an `I`), a body played by a motion capture file made from
//!   `scenes/mocap/wave.bvh` with changes of its own; its first
//!   [`COMBINED_FRAMES`] frames run.
//!
//! Each mutant's scene is written into a scratch folder (`in/`, beside
//! copies of the scene folder's data files), loaded from there and run
//! frame by frame in memory. It fails on
//! - **a panic**;
//! - **an unlocated refusal**: an error at load, in a frame, or writing
//!   the film's folder, that names no `file:line:column` with a caret
//!   under the word;
//! - **over time**: a mutant over its budget, loading and frames
//!   together ([`BUDGET`] for 12 frames, as much for every 40 frames
//!   more), or a load or a frame alone over [`FRAME_BUDGET`], both times
//!   the pixels its actors see in a frame over a 64-pixel window's; one
//!   still running after twice its budget (a minute at least) is
//!   reported as a hang (it loops) and left behind on its thread;
//! - **not finite**: a non-finite number in what `trace` prints;
//! - **unrenderable**: a frame that derives but that `render` would
//!   refuse (`scene::snapshot::validate`, what `render` checks of every
//!   snapshot: the user would learn it late, without a location);
//! - **unchecked actor number**: a mutant that loads though one of its
//!   `actorNbr_automata`, `iVisionWinSize` or `trace_actor` lines names
//!   an actor that is not a whole number in 0…`NBR_actors` − 1 (docs,
//!   "What is refused");
//! - **standing**: a navigator with a goal that stands still and looks
//!   the same way from frame 1 to the last frame run, away from its
//!   goal, without a warning about it or a `gave_up`;
//! - **wall entry** ([`walls`]): a navigator's eye enters the frame's
//!   geometry by its own walk. Navigators are the actors running
//!   `walk_continuously` (its explore mode included), `walk_stepworthy`
//!   or `walk_local` before and after the act step, their behaviour
//!   stack unchanged by it. What counts is the act step's own move, from
//!   the eye vision saw from (the frame's sense step, after the turtle's
//!   `M`/`g` and `turtle 4` moves, which the scene makes) to the eye the
//!   automata left: that segment must not enter a surface of the frame's
//!   geometry (the first surface met, looking through the actor's own
//!   body and the drawn path exactly as its vision does, must not face
//!   it), and the eye must not end inside a closed solid it was not in
//!   (every axis ray from it meets the inside of a surface first). A
//!   behaviour popped in the act step (its `obs` puts the eye anywhere:
//!   the scene's doing) is not a walk;
//! - **livelock** ([`livelock`]): a navigator with the same goal for
//!   [`LIVELOCK`] frames or more, without `gave_up` nor a warning naming
//!   it, whose eye is at no more than 4 places (to the millimetre) over
//!   the stretch and which changes its state or place in a third of its
//!   frames at least (it flips), or which neither moves nor turns for
//!   [`FROZEN`] seconds (longer than the 3 s a stuck navigator takes to
//!   notice, docs "Behaviours");
//! - **outside the folder** ([`derive_folder`]): a mutant that writes a
//!   trajectory is also derived (`production::stages::derive`, what
//!   `lmfilm derive` runs, its film cut to [`DERIVE_FRAMES`] frames) into
//!   a fresh output folder holding a link to a folder outside it, a
//!   dangling link and a link to a file outside; nothing outside the
//!   output folder may change, and no new link may appear in it.
//!
//! `LMFILM_ACTOR_MUTANTS` (single round), `LMFILM_ACTOR_COMBINED`
//! (combined round), `LMFILM_ACTOR_FRAMES` (frames of the combined
//! round) and `LMFILM_ACTOR_SEED` (both rounds; by default 0x5eed_ac70
//! for the single round, 1 for the combined one) run more or others;
//! `LMFILM_ACTOR_DUMP=DIR` writes every failing mutant there (its scene,
//! its motion file, what failed) to run it alone ([`one_actor_mutant`]);
//! `LMFILM_ACTOR_VERBOSE=1` also says why each refused mutant was
//! refused, which took over a second, and (with the dump) writes every
//! mutant.

use std::collections::{BTreeMap, BTreeSet};
use std::panic::{self, AssertUnwindSafe};
use std::path::{Path, PathBuf};
use std::sync::mpsc;
use std::time::{Duration, Instant};

use glam::{Vec3, Vec3A};
use lmfilm::actors::live::Living;
use lmfilm::actors::perception::vision::{self, View};
use lmfilm::film::trace::Record;
use lmfilm::film::Film;
use lmfilm::lsys::automata::Automata;
use lmfilm::lsys::Source;
use lmfilm::production::stages::{self, SceneText};
use lmfilm::production::timings::Timings;
use lmfilm::render::Accel;
use lmfilm::turtle::Options;

use crate::common::{fresh_dir, PanicPool, Rng};

/// Single-change mutants: about 14 s in the test profile on two cores.
const CASES: u64 = 240;

/// Frames run per single-change mutant.
const FRAMES: usize = 12;

/// Combined mutants: with [`COMBINED_FRAMES`], about 40 s in the test
/// profile on two cores, beside the single round.
const COMBINED: u64 = 260;

/// Frames run per combined mutant: 8 s of film at 0.04 s, long enough
/// for a navigator to reach the first wall of `navigate.lm` and, stopped
/// there, to stand for [`FROZEN`] seconds.
const COMBINED_FRAMES: usize = 200;

/// Most time one mutant may take, loading and frames together: fifty
/// times what the slowest shipped scene takes here for 12 frames, and
/// over ten times its 150 frames.
const BUDGET: Duration = Duration::from_secs(20);

/// Most time loading a mutant or running one of its frames may take:
/// twenty times the slowest frame the largest window (1024 pixels a
/// side) takes here.
const FRAME_BUDGET: Duration = Duration::from_secs(5);

/// The budget of a mutant run for `frames` frames.
fn budget(frames: usize) -> Duration {
    BUDGET * (frames as u32).div_ceil(40).max(1)
}

/// A mutant still running after this loops: it is left behind.
fn hang(frames: usize) -> Duration {
    (budget(frames) * 2).max(Duration::from_secs(60))
}

/// Frames derived into a folder for a mutant that writes a trajectory.
const DERIVE_FRAMES: u64 = 4;

/// Frames of flipping that make a livelock.
const LIVELOCK: usize = 30;

/// Seconds a navigator may stand without moving or turning.
const FROZEN: f64 = 3.5;

fn setting(name: &str, default: u64) -> u64 {
    std::env::var(name)
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}

/// A shipped scene with actors: its path, text and spelling.
#[derive(Clone)]
struct Scene {
    path: PathBuf,
    text: String,
    readable: bool,
}

/// The shipped scenes with actors in the forms `forms`, sorted.
fn actor_scenes(forms: &[&str]) -> Vec<Scene> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes");
    let mut out = Vec::new();
    for dir in ["actors", "tennis"] {
        for f in std::fs::read_dir(root.join(dir)).unwrap() {
            let p = f.unwrap().path();
            let Some(ext) = p.extension().and_then(|e| e.to_str()) else {
                continue;
            };
            if forms.contains(&ext) {
                let text = std::fs::read_to_string(&p).unwrap();
                if text.contains("NBR_actors") {
                    out.push(Scene {
                        readable: ext == "lmr",
                        path: p,
                        text,
                    });
                }
            }
        }
    }
    out.sort_by(|a, b| a.path.cmp(&b.path));
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

/// [`NUMBERS`] but 1024, for the combined round: a window of 1024
/// pixels a side (the single round's) runs 150 frames for a minute.
fn combined_numbers() -> Vec<&'static str> {
    NUMBERS.iter().copied().filter(|&n| n != "1024").collect()
}

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

/// More commands of the combined round: the settings of table B6 at the
/// edges of their documented ranges, and ordinary values beside them.
const MORE_COMMANDS: &[&str] = &[
    "eps_arrived 0",
    "eps_arrived 0 0",
    "eps_arrived 1e30",
    "eps_arrived 0.000001",
    "eps_look_at 1",
    "eps_look_at -1",
    "speed 1000",
    "speed 20",
    "speed 0.001",
    "fov 2",
    "fov 1200",
    "vision_range 0 0.001 0",
    "vision_range 0.01 1 1",
    "inertia 1",
    "heuristic 0",
    "heuristic 2",
    "heuristic 9",
    "coll_test_func 4",
    "coll_test_func 6",
    "coll_test_func 18",
    "size_actor 0",
    "dist_coll 0",
    "ahead 0",
    "optim_rate 1",
    "goal 0 1 -6",
    "goal 0 0.75 6",
    "init 0 -12 12 0.05",
    "state 11",
    "local_goal 0 0 0",
];

/// The settings of a walking actor at the edges of their documented
/// ranges (table B6), the first change of every combined mutant.
const WALK_EDGES: &[&str] = &[
    "fov 1",
    "fov 2",
    "fov 1799",
    "vision_range 0 0.001 0",
    "vision_range 0.001 0.002 0",
    "vision_range 0.01 1 1",
    "vis_mem_off",
    "speed 1000",
    "speed 1e30",
    "speed 0.001",
    "dist_coll 0",
    "size_actor 0",
    "size_actor 1e30",
    "eps_arrived 0.000001",
    "eps_arrived 1e30",
    "eps_look_at 1",
    "inertia 1",
    "inertia 1e30",
    "ahead 0",
    "ahead 1000000",
    "optim_rate 1",
    "rel_search_level 0",
    "rel_search_level 20",
    "heuristic 0",
    "heuristic 2",
    "heuristic 9",
    "heuristic 15",
    "coll_test_func 4",
    "coll_test_func 18",
    "state 11",
];

/// A vision window's edge at the lower edge of its range (1…1024
/// pixels; the upper edge is the single round's, see [`combined_numbers`]).
fn window_edge(lines: &mut [String], rng: &mut Rng) {
    let windows: Vec<usize> = (0..lines.len())
        .filter(|&i| lines[i].trim_start().starts_with("iVisionWinSize"))
        .collect();
    if let Some(&i) = pick(&windows, rng) {
        let mut words: Vec<String> = lines[i].split_whitespace().map(str::to_string).collect();
        if words.len() > 2 {
            words[2] = ["1", "2", "3", "4", "8"][rng.below(5)].to_string();
            lines[i] = words.join(" ");
        }
    }
}

/// Automata names and numbers a user may write.
const AUTOMATA: &[&str] = &[
    "walk_local",
    "walk_continuously",
    "walk_stepworthy",
    "observe",
    "watch",
    "auto_align",
    "follow_turtle",
    "L-system",
    "talk",
    "3",
    "4",
    "8",
    "9",
    "13",
];

/// Names a user may give a trajectory (`trace_actor`). The output folder
/// holds `link` (a folder outside), `dangling.trace` (a link to a file
/// outside that does not exist) and `victim.trace` (a link to a file
/// outside).
const TRACE_NAMES: &[&str] = &[
    "walk.trace",
    "t/walk.trace",
    "t",
    "t/u",
    "link/out.trace",
    "link",
    "dangling.trace",
    "victim.trace",
    "../out.trace",
    "../../outside/out.trace",
    "actors/0/x.trace",
    "scene",
    "derive.json",
    "sounds/x.trace",
    "frames",
    "a.trace/",
    "./w.trace",
    "pledge.trace",
    "x/../y.trace",
    "LONG",
];

/// What a user may write in an `M`, `g` or `D` symbol's parameter.
const SYMBOL_NUMBERS: &[&str] = &[
    "0", "1", "2", "3", "7", "99", "1_", "0.5", "1e30", "10 60 ^",
];

/// The same in the combined round: in the classic form `1e30` reads as
/// the function `e`, so large numbers are written as powers.
const COMBINED_SYMBOL_NUMBERS: &[&str] = &[
    "0", "1", "2", "3", "7", "99", "1_", "0.5", "0.001", "10 8 ^", "10 30 ^", "10 60 ^",
];

/// The same in the readable form.
const READABLE_NUMBERS: &[&str] = &[
    "0", "1", "2", "3", "7", "99", "-1", "0.5", "1e30", "10 ^ 60", "0.001",
];

/// The readable symbols of actors and bodies whose arguments change.
const READABLE_CALLS: &[&str] = &[
    "actor(",
    "memory_camera(",
    "memory_look_at(",
    "place_eye_level(",
    "body(",
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

/// Whether an axiom or production line holds an `M` or `g` symbol.
fn is_symbol_line(l: &str) -> bool {
    l.contains("M (") || l.contains("g (")
}

fn pick<'a, T>(v: &'a [T], rng: &mut Rng) -> Option<&'a T> {
    (!v.is_empty()).then(|| &v[rng.below(v.len())])
}

/// One mutation of an actor scene (the single round's).
fn mutate(text: &str, rng: &mut Rng) -> String {
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    match rng.below(5) {
        0 => replace_number(&mut lines, rng),
        1 => add_command(&mut lines, COMMANDS, rng),
        2 => double_line(&mut lines, rng),
        3 => delete_line(&mut lines, rng),
        _ => replace_symbol_number(&mut lines, rng),
    }
    lines.join("\n") + "\n"
}

fn replace_number(lines: &mut [String], rng: &mut Rng) {
    replace_number_from(lines, NUMBERS, rng)
}

fn replace_number_from(lines: &mut [String], numbers: &[&str], rng: &mut Rng) {
    let actors = actor_lines(&lines.join("\n"));
    if let Some(&i) = pick(&actors, rng) {
        let mut words: Vec<String> = lines[i].split_whitespace().map(str::to_string).collect();
        let numeric: Vec<usize> = (1..words.len())
            .filter(|&k| words[k].parse::<f64>().is_ok())
            .collect();
        if let Some(&k) = pick(&numeric, rng) {
            words[k] = pick(numbers, rng).unwrap().to_string();
            lines[i] = words.join(" ");
        }
    }
}

/// A number of an actor option or command changed by a step a user
/// might take (twice, half, ten times, a tenth, one more or less, its
/// negative, zero): mostly within the documented ranges. Actor numbers
/// and windows stay.
fn nudge_number(lines: &mut [String], rng: &mut Rng) {
    let actors: Vec<usize> = actor_lines(&lines.join("\n"))
        .into_iter()
        .filter(|&i| {
            let l = lines[i].trim_start();
            // Nor the window's edge: ten times a 96-pixel window runs 150
            // frames for a minute (the window's edges are [`window_edge`]'s).
            !l.starts_with("NBR_actors") && !l.starts_with("iVisionWinSize")
        })
        .collect();
    if let Some(&i) = pick(&actors, rng) {
        let mut words: Vec<String> = lines[i].split_whitespace().map(str::to_string).collect();
        // Not the actor's number.
        let numeric: Vec<usize> = (2..words.len())
            .filter(|&k| words[k].parse::<f64>().is_ok())
            .collect();
        if let Some(&k) = pick(&numeric, rng) {
            let v: f64 = words[k].parse().unwrap();
            let n = [
                v * 2.0,
                v / 2.0,
                v * 10.0,
                v / 10.0,
                v + 1.0,
                v - 1.0,
                -v,
                0.0,
            ][rng.below(8)];
            words[k] = format!("{n}");
            lines[i] = words.join(" ");
        }
    }
}

fn automata_lines(lines: &[String]) -> Vec<usize> {
    (0..lines.len())
        .filter(|&i| lines[i].trim_start().starts_with("actorNbr_automata"))
        .collect()
}

fn add_command(lines: &mut [String], commands: &[&str], rng: &mut Rng) {
    if let Some(&i) = pick(&automata_lines(lines), rng) {
        let c = pick(commands, rng).unwrap();
        lines[i] = format!("{} {c}", lines[i]);
    }
}

fn double_line(lines: &mut Vec<String>, rng: &mut Rng) {
    let actors = actor_lines(&lines.join("\n"));
    if let Some(&i) = pick(&actors, rng) {
        let l = lines[i].clone();
        lines.insert(i, l);
    }
}

fn delete_line(lines: &mut Vec<String>, rng: &mut Rng) {
    let actors = actor_lines(&lines.join("\n"));
    if let Some(&i) = pick(&actors, rng) {
        lines.remove(i);
    }
}

fn replace_symbol_number(lines: &mut [String], rng: &mut Rng) {
    replace_group(lines, is_symbol_line, SYMBOL_NUMBERS, rng)
}

/// One `( … )` group of one of the lines `which` picks replaced by one
/// of `numbers`.
fn replace_group(
    lines: &mut [String],
    which: impl Fn(&str) -> bool,
    numbers: &[&str],
    rng: &mut Rng,
) {
    let symbols: Vec<usize> = (0..lines.len()).filter(|&i| which(&lines[i])).collect();
    if let Some(&i) = pick(&symbols, rng) {
        let l = &lines[i];
        let groups: Vec<usize> = l.match_indices('(').map(|(k, _)| k).collect();
        if let Some(&k) = pick(&groups, rng) {
            if let Some(end) = l[k..].find(')') {
                let n = pick(numbers, rng).unwrap();
                lines[i] = format!("{}({n}){}", &l[..k], &l[k + end + 1..]);
            }
        }
    }
}

/// A mutant: its scene text and, when it plays one, its motion file.
#[derive(Clone)]
struct Mutant {
    text: String,
    readable: bool,
    motion: Option<String>,
}

impl Mutant {
    fn file_name(&self) -> &'static str {
        if self.readable {
            "mutant.lmr"
        } else {
            "mutant.lm"
        }
    }
}

/// 2–5 changes of the combined round.
fn mutate_combined(scene: &Scene, rng: &mut Rng) -> Mutant {
    let mut lines: Vec<String> = scene.text.lines().map(str::to_string).collect();
    let mut motion = None;
    // One setting of a walking actor at an edge of its range, then 1–4
    // changes of any kind.
    if rng.below(5) == 0 {
        window_edge(&mut lines, rng);
    } else {
        add_command(&mut lines, WALK_EDGES, rng);
    }
    let changes = 1 + rng.below(4);
    for _ in 0..changes {
        match rng.below(16) {
            0 | 1 => replace_number_from(&mut lines, &combined_numbers(), rng),
            2 | 3 => nudge_number(&mut lines, rng),
            4 => add_command(&mut lines, COMMANDS, rng),
            5..=7 => add_command(&mut lines, MORE_COMMANDS, rng),
            8 => double_line(&mut lines, rng),
            9 => delete_line(&mut lines, rng),
            10 | 11 if scene.readable => replace_readable_argument(&mut lines, rng),
            10 | 11 => replace_symbol_number_or_body(&mut lines, rng),
            12 => rename_automata(&mut lines, rng),
            13 => repeat_actor_number(&mut lines, rng),
            14 => add_trace(&mut lines, scene.readable, rng),
            _ => {
                add_motion(&mut lines, scene.readable, rng);
                motion = Some(mutate_motion(motion.as_deref().unwrap_or(&wave()), rng));
            }
        }
    }
    Mutant {
        text: lines.join("\n") + "\n",
        readable: scene.readable,
        motion,
    }
}

/// As [`replace_symbol_number`], bodies (`D` 50) included.
fn replace_symbol_number_or_body(lines: &mut [String], rng: &mut Rng) {
    let which = |l: &str| is_symbol_line(l) || l.contains("D () (50)");
    replace_group(lines, which, COMBINED_SYMBOL_NUMBERS, rng)
}

/// One argument of an actor's or a body's readable symbol replaced
/// (`actor(0)` → `actor(7)`, `body(0, hold: 1)` → `body(0, hold: 1e30)`).
fn replace_readable_argument(lines: &mut [String], rng: &mut Rng) {
    let mut calls = Vec::new();
    for (i, l) in lines.iter().enumerate() {
        for c in READABLE_CALLS {
            for (k, _) in l.match_indices(c) {
                // `actor(` is also the end of `memory_camera_actor(`…
                let whole = k == 0
                    || !l.as_bytes()[k - 1].is_ascii_alphanumeric() && l.as_bytes()[k - 1] != b'_';
                if whole {
                    calls.push((i, k + c.len()));
                }
            }
        }
    }
    let Some(&(i, open)) = pick(&calls, rng) else {
        return;
    };
    let l = &lines[i];
    // The arguments up to the matching parenthesis, split at depth 0.
    let mut depth = 0;
    let mut args = vec![open];
    let mut close = None;
    for (k, b) in l.bytes().enumerate().skip(open) {
        match b {
            b'(' => depth += 1,
            b')' if depth == 0 => {
                close = Some(k);
                break;
            }
            b')' => depth -= 1,
            b',' if depth == 0 => args.push(k + 1),
            _ => {}
        }
    }
    let Some(close) = close else { return };
    let a = rng.below(args.len());
    let start = args[a];
    let end = args.get(a + 1).map_or(close, |&n| n - 1);
    let arg = &l[start..end];
    // A named argument keeps its name.
    let name = arg.find(':').map_or("", |c| &arg[..=c]);
    let n = pick(READABLE_NUMBERS, rng).unwrap();
    let spaced = if start > open { " " } else { "" };
    let name = name.trim_start();
    let value = if name.is_empty() {
        format!("{spaced}{n}")
    } else {
        format!("{spaced}{name} {n}")
    };
    lines[i] = format!("{}{value}{}", &l[..start], &l[end..]);
}

/// An automata line's automata replaced by another name or number.
fn rename_automata(lines: &mut [String], rng: &mut Rng) {
    let Some(&i) = pick(&automata_lines(lines), rng) else {
        return;
    };
    let mut words: Vec<String> = lines[i].split_whitespace().map(str::to_string).collect();
    // The automata: the first name, else the last leading number.
    let mut k = 1;
    while k < words.len() && words[k].parse::<f64>().is_ok() {
        k += 1;
    }
    let at = if k < words.len() && is_automata_name(&words[k]) {
        k
    } else {
        k - 1
    };
    if at >= 1 && at < words.len() {
        words[at] = pick(AUTOMATA, rng).unwrap().to_string();
        lines[i] = words.join(" ");
    }
}

fn is_automata_name(w: &str) -> bool {
    Automata::ALL.iter().any(|a| a.name() == w)
}

/// A second actor number on an automata line, as the BNF writes it
/// (`actorNbr_automata 0 0 walk_continuously …`), any number.
fn repeat_actor_number(lines: &mut [String], rng: &mut Rng) {
    let Some(&i) = pick(&automata_lines(lines), rng) else {
        return;
    };
    let mut words: Vec<String> = lines[i].split_whitespace().map(str::to_string).collect();
    if words.len() > 2 {
        // Mostly the line's own actor, as the BNF means it.
        let own = words[1].clone();
        let n = [
            own.as_str(),
            own.as_str(),
            "1",
            "5",
            "99",
            "-1",
            "0.5",
            "4294967296",
        ][rng.below(8)];
        words.insert(2, n.to_string());
        lines[i] = words.join(" ");
    }
}

/// The index of the line that opens section `name` (either spelling).
fn section(lines: &[String], classic: &str, readable: &str) -> Option<usize> {
    lines
        .iter()
        .position(|l| l.trim() == classic || l.trim() == readable)
}

/// A `trace_actor` line with a name of [`TRACE_NAMES`] and an `I` in the
/// axiom, so that every frame adds a record.
fn add_trace(lines: &mut Vec<String>, readable: bool, rng: &mut Rng) {
    let Some(options) = section(lines, "Options", "options") else {
        return;
    };
    let actor = ["0", "0", "0", "0", "0", "1", "5"][rng.below(7)];
    let name = match *pick(TRACE_NAMES, rng).unwrap() {
        "LONG" => "x".repeat(300),
        n => n.to_string(),
    };
    lines.insert(options + 1, format!("trace_actor {actor} {name}"));
    if let Some(axiom) = section(lines, "Axiom", "axiom") {
        let i = if readable { "write_traces" } else { "I" };
        if lines.get(axiom + 1).is_none_or(|l| l.trim() != i) {
            lines.insert(axiom + 1, i.to_string());
        }
    }
}

/// A motion capture (`fig_bvh 1 motion.bvh`, the mutant's motion file)
/// played by a body held by its frame beside the scene.
fn add_motion(lines: &mut Vec<String>, readable: bool, rng: &mut Rng) {
    if lines.iter().any(|l| l.contains("fig_bvh 1 motion.bvh")) {
        return;
    }
    let Some(axiom) = section(lines, "Axiom", "axiom") else {
        return;
    };
    let height = ["1.8", "0.5", "0", "1e30", "0.001"][rng.below(5)];
    let body = if readable {
        format!("[ move_to(1, 0, 1) turn_left(90) body(1, {height}, hold: 0) ]")
    } else {
        format!(
            "[ f () () () (2) (1) (0) (1) + () () () () (90) D () (50) () () (1) ({height}) (0) ]"
        )
    };
    lines.insert(axiom + 1, body);
    match section(lines, "Surfaces", "surfaces") {
        Some(s) => lines.insert(s + 1, "fig_bvh 1 motion.bvh".into()),
        None => {
            let header = if readable { "surfaces" } else { "Surfaces" };
            lines.insert(axiom, "fig_bvh 1 motion.bvh".into());
            lines.insert(axiom, header.into());
        }
    }
}

/// The shipped motion capture.
fn wave() -> String {
    std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/scenes/mocap/wave.bvh"
    ))
    .unwrap()
}

/// 1–3 changes of a motion capture file.
fn mutate_motion(bvh: &str, rng: &mut Rng) -> String {
    let mut lines: Vec<String> = bvh.lines().map(str::to_string).collect();
    for _ in 0..1 + rng.below(3) {
        match rng.below(7) {
            // Every joint without a channel.
            0 => {
                for l in lines.iter_mut() {
                    if l.trim_start().starts_with("CHANNELS") {
                        *l = "CHANNELS 0".into();
                    }
                }
            }
            1 => {
                let n =
                    ["0", "1", "29", "31", "1000000", "1000000000000000000", "-1"][rng.below(7)];
                for l in lines.iter_mut() {
                    if l.starts_with("Frames:") {
                        *l = format!("Frames: {n}");
                    }
                }
            }
            2 => {
                let t = ["0", "1e-30", "1e30", "-1", "0.000001"][rng.below(5)];
                for l in lines.iter_mut() {
                    if l.starts_with("Frame Time:") {
                        *l = format!("Frame Time: {t}");
                    }
                }
            }
            3 => {
                let offsets: Vec<usize> = (0..lines.len())
                    .filter(|&i| lines[i].trim_start().starts_with("OFFSET"))
                    .collect();
                if let Some(&i) = pick(&offsets, rng) {
                    let v = ["0", "1e30", "-1e30", "1e6", "1e-30"][rng.below(5)];
                    lines[i] = format!("OFFSET {v} {v} {v}");
                }
            }
            4 => {
                let motion = lines.iter().position(|l| l == "MOTION").unwrap_or(0);
                let at = motion + 3 + rng.below(lines.len().saturating_sub(motion + 3).max(1));
                if let Some(l) = lines.get_mut(at) {
                    let mut words: Vec<String> = l.split_whitespace().map(str::to_string).collect();
                    if !words.is_empty() {
                        let k = rng.below(words.len());
                        words[k] = ["1e30", "nan", "inf", "-1e30", "1e38"][rng.below(5)].into();
                        *l = words.join(" ");
                    }
                }
            }
            5 => {
                let keep = rng.below(lines.len().max(1));
                lines.truncate(keep);
            }
            _ => {
                let joints: Vec<usize> = (0..lines.len())
                    .filter(|&i| lines[i].trim_start().starts_with("JOINT"))
                    .collect();
                if let Some(&i) = pick(&joints, rng) {
                    lines[i] = "JOINT Hips".into();
                }
            }
        }
    }
    lines.join("\n") + "\n"
}

/// What went wrong with a mutant: the class (one of the module doc's
/// checks) and what happened.
#[derive(Debug, Clone)]
struct Found {
    class: &'static str,
    detail: String,
}

fn found(class: &'static str, detail: String) -> Found {
    Found { class, detail }
}

/// Whether an error names where it went wrong: `FILE:LINE:COLUMN` of a
/// scene or a file it reads, and a caret under the word.
fn located(msg: &str) -> bool {
    const FILES: [&str; 8] = [
        ".lm", ".lmr", ".bvh", ".trace", ".chan", ".obj", ".mtl", ".wav",
    ];
    let digits = |s: &str| s.bytes().take_while(u8::is_ascii_digit).count();
    let place = msg.match_indices(':').any(|(i, _)| {
        let before = &msg[..i];
        let file = FILES.iter().any(|f| before.ends_with(f));
        let rest = &msg[i + 1..];
        let line = digits(rest);
        file && line > 0 && rest[line..].starts_with(':') && digits(&rest[line + 1..]) > 0
    });
    place && msg.contains('^')
}

/// The scene text without its `/* … */` comments.
fn uncommented(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    let mut rest = text;
    while let Some(k) = rest.find("/*") {
        out.push_str(&rest[..k]);
        match rest[k..].find("*/") {
            Some(e) => rest = &rest[k + e + 2..],
            None => return out,
        }
    }
    out.push_str(rest);
    out
}

/// An actor number a loaded scene names that is no actor of it (docs,
/// "What is refused": an actor number < 0 or ≥ `NBR_actors`).
fn unchecked_actor(text: &str) -> Option<String> {
    let text = uncommented(text);
    let count = text.lines().find_map(|l| {
        let mut w = l.split_whitespace();
        (w.next() == Some("NBR_actors")).then(|| w.next()?.parse::<i64>().ok())?
    })?;
    for l in text.lines() {
        let words: Vec<&str> = l.split_whitespace().collect();
        let actors: Vec<&str> = match words.first() {
            Some(&"actorNbr_automata") => {
                let numbers = words[1..]
                    .iter()
                    .take_while(|w| w.parse::<f64>().is_ok())
                    .count();
                let named = words.get(1 + numbers).is_some_and(|w| is_automata_name(w));
                let actors = if named {
                    numbers
                } else {
                    numbers.saturating_sub(1)
                };
                if !(1..=2).contains(&actors) {
                    continue;
                }
                words[1..1 + actors].to_vec()
            }
            Some(&"iVisionWinSize") | Some(&"trace_actor") => {
                words.get(1).copied().into_iter().collect()
            }
            _ => continue,
        };
        for a in actors {
            if !a.parse::<i64>().is_ok_and(|n| (0..count).contains(&n)) {
                return Some(format!(
                    "loaded with `{}`: actor `{a}` is no actor of NBR_actors {count}",
                    l.trim()
                ));
            }
        }
    }
    None
}

/// The scratch folder of a round: `in/` holds the mutant and copies of
/// the scene folder's data files, `a/b/out/` the derived folder (deep,
/// so that `..` twice stays inside), `outside/` what the links point to.
struct Scratch {
    root: PathBuf,
}

impl Scratch {
    fn new(name: &str) -> Scratch {
        let root = fresh_dir("actor-mutants", name);
        let input = root.join("in");
        std::fs::create_dir_all(&input).unwrap();
        let actors = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/actors");
        for f in ["pledge.trace", "pulse.chan"] {
            std::fs::copy(actors.join(f), input.join(f)).unwrap();
        }
        Scratch { root }
    }
}

/// Everything in `dir` (links not followed): path, kind, length and, for
/// a file, its bytes' hash; `skip` left out.
fn listing(dir: &Path, skip: &Path) -> BTreeMap<PathBuf, String> {
    let mut out = BTreeMap::new();
    let mut todo = vec![dir.to_path_buf()];
    while let Some(d) = todo.pop() {
        let Ok(entries) = std::fs::read_dir(&d) else {
            continue;
        };
        for e in entries.flatten() {
            let p = e.path();
            if p == skip {
                continue;
            }
            let Ok(m) = std::fs::symlink_metadata(&p) else {
                continue;
            };
            let what = if m.file_type().is_symlink() {
                format!("link to {:?}", std::fs::read_link(&p).ok())
            } else if m.is_dir() {
                todo.push(p.clone());
                "folder".to_string()
            } else {
                let bytes = std::fs::read(&p).unwrap_or_default();
                format!(
                    "file of {} bytes, {}",
                    m.len(),
                    lmfilm::production::digest::sha256_bytes(&bytes)
                )
            };
            out.insert(p, what);
        }
    }
    out
}

/// The links under `dir`.
fn links(dir: &Path) -> BTreeSet<PathBuf> {
    listing(dir, Path::new(""))
        .into_iter()
        .filter(|(_, w)| w.starts_with("link"))
        .map(|(p, _)| p)
        .collect()
}

/// The scene cut to `frames` frames (its `t_final_interval`), if it says
/// how long it is.
fn cut(text: &str, frames: u64) -> Option<String> {
    let mut done = false;
    let lines: Vec<String> = text
        .lines()
        .map(|l| {
            let words: Vec<&str> = l.split_whitespace().collect();
            if !done && words.len() == 3 && words[0] == "t_final_interval" {
                if let Ok(dt) = words[2].parse::<f64>() {
                    done = true;
                    return format!("t_final_interval {} {}", (frames - 1) as f64 * dt, words[2]);
                }
            }
            l.to_string()
        })
        .collect();
    done.then(|| lines.join("\n") + "\n")
}

/// Derives the mutant (cut short) into a fresh output folder with links
/// out of it, as `lmfilm derive` does, and checks that its errors are
/// located and that nothing outside the folder changed.
fn derive_folder(m: &Mutant, scene_dir: &Path, scratch: &Path) -> Vec<Found> {
    let Some(text) = cut(&m.text, DERIVE_FRAMES) else {
        return Vec::new();
    };
    let out = scratch.join("a/b/out");
    let outside = scratch.join("outside");
    for d in [&out, &outside] {
        let _ = std::fs::remove_dir_all(d);
        std::fs::create_dir_all(d).unwrap();
    }
    std::fs::write(outside.join("victim.trace"), "victim\n").unwrap();
    let planted = [
        ("link", outside.clone()),
        ("dangling.trace", outside.join("dangling.trace")),
        ("victim.trace", outside.join("victim.trace")),
    ];
    for (name, to) in &planted {
        std::os::unix::fs::symlink(to, out.join(name)).unwrap();
    }
    let before = listing(scratch, &out);
    let links_before = links(&out);
    let name = scratch.join("in").join(m.file_name());
    let src = Source::new(name.display().to_string(), text.as_str());
    let mut failures = Vec::new();
    let verbose = std::env::var_os("LMFILM_ACTOR_VERBOSE").is_some();
    let mut refused = |what: &str, msg: String| {
        if verbose {
            println!("deriving ({what}) refused: {msg}");
        }
        if !located(&msg) {
            failures.push(found(
                "unlocated refusal",
                format!("deriving into a folder ({what}): {msg}"),
            ));
        }
    };
    match Film::from_sources(&[src], Some(scene_dir), Options::default()) {
        Err(e) => refused("load", e.to_string()),
        Ok(mut film) => {
            let texts = [SceneText {
                name: name.display().to_string(),
                bytes: text.into_bytes(),
            }];
            match stages::inputs(&film, &texts, "mutant", BTreeMap::new()) {
                Err(e) => refused("inputs", e.to_string()),
                Ok(inputs) => {
                    let timings = Timings::start();
                    if let Err(e) =
                        stages::derive(&mut film, inputs, &out, false, &mut |_, _| {}, &timings)
                    {
                        refused("derive", e.to_string());
                    }
                }
            }
        }
    }
    let after = listing(scratch, &out);
    if verbose {
        println!("derived into {}:", out.display());
        for (p, w) in listing(scratch, Path::new("")) {
            println!("  {} {w}", p.display());
        }
    }
    let changed: Vec<String> = after
        .iter()
        .filter(|(p, w)| before.get(*p) != Some(w))
        .map(|(p, w)| format!("{} ({w})", p.display()))
        .chain(
            before
                .keys()
                .filter(|p| !after.contains_key(*p))
                .map(|p| format!("{} (removed)", p.display())),
        )
        .collect();
    if !changed.is_empty() {
        failures.push(found(
            "file outside the folder",
            format!(
                "deriving into {} changed outside it: {}",
                out.display(),
                changed.join(", ")
            ),
        ));
    }
    let new_links: Vec<_> = links(&out).difference(&links_before).cloned().collect();
    if !new_links.is_empty() {
        failures.push(found(
            "file outside the folder",
            format!("deriving made links in the folder: {new_links:?}"),
        ));
    }
    failures
}

/// What a navigator is: an actor that walks by its own automata.
fn navigates(a: Option<Automata>) -> bool {
    matches!(
        a,
        Some(Automata::WalkContinuously | Automata::WalkStepworthy | Automata::WalkLocal)
    )
}

/// An actor as one frame left it, for the checks over many frames.
#[derive(Debug, Clone)]
struct Seen {
    automata: Option<Automata>,
    /// The navigator it runs, or the one that waits on its stack while
    /// it looks around (`observe`, pushed by a navigator without a way).
    walking: Option<Automata>,
    state: i64,
    stack: usize,
    eye: Vec3,
    look_at: Vec3,
    goal: Option<Vec3>,
    gave_up: bool,
}

impl Seen {
    fn of(a: &Living) -> Seen {
        let waiting = a.stack.last().map(|b| b.automata);
        let walking = if navigates(a.automata) {
            a.automata
        } else if a.automata == Some(Automata::Observe) && navigates(waiting) {
            waiting
        } else {
            None
        };
        Seen {
            automata: a.automata,
            walking,
            state: a.state,
            stack: a.stack.len(),
            eye: a.eye,
            look_at: a.look_at,
            goal: a.actual_goal(),
            gave_up: a.gave_up.is_some(),
        }
    }
}

/// The first surface from `from` toward `to` (no farther), looking
/// through `a`'s own body and the drawn path as its vision does: its
/// distance and whether it faces `from` (the segment enters it there).
fn surface(accel: &Accel, a: &Living, from: Vec3, to: Vec3) -> Option<(f32, bool)> {
    let d = to - from;
    let len = d.length();
    if !(len > 1e-6 && len < 1e7 && from.abs().max_element() < 1e7) {
        return None;
    }
    let w = vision::see(accel, &a.body, &View::new(from, to, 1, 0.0, len), 1);
    let t = w.centre;
    if !(t.is_finite() && t <= len) {
        return None;
    }
    let dir = Vec3A::from(d / len);
    let eps = 1e-4 * t.max(1.0);
    let h = accel.cast(Vec3A::from(from), dir, (t - eps).max(0.0), t + eps)?;
    Some((t, h.normal.dot(dir) < -1e-4))
}

/// Whether `p` is inside a closed solid of the frame: along each axis
/// the first surface met (past `a`'s own body) is met from inside, and
/// more than a millimetre away (an eye on a face is not inside).
fn inside(accel: &Accel, a: &Living, p: Vec3) -> bool {
    const FAR: f32 = 1e6;
    [
        Vec3::X,
        Vec3::NEG_X,
        Vec3::Y,
        Vec3::NEG_Y,
        Vec3::Z,
        Vec3::NEG_Z,
    ]
    .iter()
    .all(|&d| matches!(surface(accel, a, p, p + d * FAR), Some((t, false)) if t > 1e-3))
}

/// The warnings that say an actor's senses cannot keep up with its way
/// (docs/actors.md, "At the edges of the settings"): after one, what its
/// window never saw it may walk into — the film said which setting and
/// the value that keeps it out.
const SENSES_WARNED: [&str; 5] = [
    "with its visual memory off",
    "sees a view ",
    "sees through a window of ",
    "sees no farther than ",
    " a frame (speed ",
];

/// The actor a warning names ("… actor N (automata): …").
fn warned_actor(w: &str) -> Option<usize> {
    let rest = &w[w.find("actor ")? + "actor ".len()..];
    let digits: String = rest.chars().take_while(char::is_ascii_digit).collect();
    digits.parse().ok()
}

/// The wall-entry check of one frame: each navigator's act step (from
/// the eye it saw with to the eye it left) against the frame's geometry.
/// `before` is each actor as the frame before left it; `excused`, the
/// actors told their senses cannot keep up ([`SENSES_WARNED`]), whose
/// entries are a "wall entry after a warning" (counted, not failed).
fn walls(
    frame: u64,
    accel: &Accel,
    living: &[Living],
    before: &[Seen],
    excused: &BTreeSet<usize>,
) -> Option<Found> {
    for (a, b) in living.iter().zip(before) {
        let same_behaviour = b.automata == a.automata && b.stack == a.stack.len();
        if !(navigates(a.automata) && same_behaviour) {
            continue;
        }
        let Some(seen_from) = a.window.as_ref().map(|w| w.view.eye) else {
            continue;
        };
        let (p0, p1) = (seen_from, a.eye);
        if p0 == p1 || !p1.is_finite() {
            continue;
        }
        let name = a.automata.map_or("", |x| x.name());
        // Told its senses cannot keep up: counted, not failed.
        let class = if excused.contains(&a.id) {
            "wall entry after a warning"
        } else {
            "wall entry"
        };
        if let Some((t, true)) = surface(accel, a, p0, p1) {
            return Some(found(
                class,
                format!(
                    "frame {frame}: actor {} ({name}, state {}) walks from {p0} to {p1} ({:.3} in a frame) into a surface {t:.3} along",
                    a.id,
                    a.state,
                    p0.distance(p1)
                ),
            ));
        }
        if inside(accel, a, p1) && !inside(accel, a, p0) {
            return Some(found(
                class,
                format!(
                    "frame {frame}: actor {} ({name}, state {}) walks from {p0} to {p1}, inside a solid",
                    a.id, a.state
                ),
            ));
        }
    }
    None
}

/// The livelock check of one actor over the frames run (`seen[k]` is
/// frame k): the longest stretch of frames with the same navigator and
/// goal, no `gave_up` and no warning naming the actor, in which the eye
/// is at ≤ 4 places and changes state or place in a third of the frames
/// (flips), or neither moves nor turns for [`FROZEN`] seconds.
fn livelock(id: usize, seen: &[Seen], warned: &[bool], dt: f64) -> Option<Found> {
    let frozen = LIVELOCK.max((FROZEN / dt).ceil() as usize);
    let key = |v: Vec3| (v * 1000.0).round().to_array().map(|x| x as i64);
    let mut start = 0;
    while start < seen.len() {
        let s0 = &seen[start];
        // A navigator with a goal, or looking around before it goes on.
        let ok = |s: &Seen| {
            navigates(s0.automata)
                && s.walking == s0.automata
                && s0.goal.is_some()
                && (s.goal == s0.goal || s.automata == Some(Automata::Observe))
                && !s.gave_up
        };
        if !ok(s0) || warned[start] {
            start += 1;
            continue;
        }
        let mut end = start + 1;
        while end < seen.len() && ok(&seen[end]) && !warned[end] {
            end += 1;
        }
        // Within [start, end): windows of LIVELOCK frames.
        let run = &seen[start..end];
        for (j, w) in run.windows(LIVELOCK).enumerate() {
            let places: BTreeSet<_> = w.iter().map(|s| key(s.eye)).collect();
            let changes = w
                .windows(2)
                .filter(|p| {
                    p[0].state != p[1].state
                        || p[0].automata != p[1].automata
                        || key(p[0].eye) != key(p[1].eye)
                })
                .count();
            if places.len() <= 4 && changes * 3 >= LIVELOCK {
                let states: BTreeSet<(&str, i64)> = w
                    .iter()
                    .map(|s| (s.automata.map_or("", |a| a.name()), s.state))
                    .collect();
                let first = start + j;
                let goal = s0.goal.unwrap();
                let places: Vec<String> = places
                    .iter()
                    .map(|p| {
                        format!(
                            "({}, {}, {})",
                            p[0] as f64 / 1e3,
                            p[1] as f64 / 1e3,
                            p[2] as f64 / 1e3
                        )
                    })
                    .collect();
                return Some(found(
                    "livelock",
                    format!(
                        "actor {id} ({}) flips from frame {first} to {}: states {states:?} at {}, {changes} changes, goal {goal} at {:.4}, without gave_up or a warning (and so on to frame {})",
                        s0.automata.map_or("", |a| a.name()),
                        first + LIVELOCK - 1,
                        places.join(" "),
                        w[0].eye.distance(goal),
                        start + run.len() - 1
                    ),
                ));
            }
        }
        if run.len() >= frozen {
            for (k, w) in run.windows(frozen).enumerate() {
                let still = w
                    .iter()
                    .all(|s| s.eye == w[0].eye && s.look_at == w[0].look_at);
                if still {
                    let goal = s0.goal.unwrap();
                    return Some(found(
                        "livelock",
                        format!(
                            "actor {id} ({}, state {}) neither moves nor turns at {} from frame {} to {}, goal {goal} at {:.3}, without gave_up or a warning",
                            s0.automata.map_or("", |a| a.name()),
                            w[0].state,
                            w[0].eye,
                            start + k,
                            start + k + frozen - 1,
                            w[0].eye.distance(goal)
                        ),
                    ));
                }
            }
        }
        start = end;
    }
    None
}

/// How far a mutant went: loaded, frames run, derived into a folder.
#[derive(Debug, Clone, Default)]
struct Went {
    /// The first line of the refusal at load, if refused.
    refused: Option<String>,
    /// Its first wall entry after the film told the actor its senses
    /// cannot keep up ([`SENSES_WARNED`]): said, not failed.
    excused: Option<String>,
    /// How many times the budget it has: the pixels its actors see in a
    /// frame over those of one 64-pixel window (at least 1).
    scale: u32,
    loaded: bool,
    frames: usize,
    derived: bool,
}

/// Runs one mutant: loads it from `scratch/in/`, runs `frames` frames,
/// and (when it writes a trajectory) derives it into a folder.
fn run_mutant(m: &Mutant, scene_dir: &Path, scratch: &Path, frames: usize) -> (Vec<Found>, Went) {
    let mut went = Went::default();
    let input = scratch.join("in");
    let name = input.join(m.file_name());
    std::fs::write(&name, &m.text).unwrap();
    if let Some(bvh) = &m.motion {
        std::fs::write(input.join("motion.bvh"), bvh).unwrap();
    }
    let mut out = Vec::new();
    let mut opts = Options::default();
    opts.limits.memory_bytes = 1 << 30;
    let src = Source::new(name.display().to_string(), m.text.as_str());
    let start = Instant::now();
    let loaded = Film::from_sources(&[src], Some(scene_dir), opts);
    let took = start.elapsed();
    if took > FRAME_BUDGET {
        out.push(found(
            "over time",
            format!("loading took {took:?}, over {FRAME_BUDGET:?}"),
        ));
    }
    let mut film = match loaded {
        Ok(f) => f,
        Err(e) => {
            let msg = e.to_string();
            if !located(&msg) {
                out.push(found("unlocated refusal", format!("at load: {msg}")));
            }
            went.refused = msg.lines().next().map(str::to_string);
            return (out, went);
        }
    };
    went.loaded = true;
    let pixels: u64 = film
        .living()
        .iter()
        .filter_map(|a| a.edge)
        .map(|e| u64::from(e) * u64::from(e))
        .sum();
    went.scale = u32::try_from(pixels.div_ceil(64 * 64))
        .unwrap_or(u32::MAX)
        .max(1);
    if let Some(w) = unchecked_actor(&m.text) {
        out.push(found("unchecked actor number", w));
    }
    let dt = film.dt();
    let mut records = Vec::new();
    let mut warnings = Vec::new();
    // Each actor as the last frame left it (before frame 0: as loaded).
    let mut before: Vec<Seen> = film.living().iter().map(Seen::of).collect();
    let mut seen: Vec<Vec<Seen>> = Vec::new();
    let mut warned: Vec<Vec<bool>> = Vec::new();
    let mut excused: BTreeSet<usize> = BTreeSet::new();
    let first = |out: &mut Vec<Found>, f: Found| {
        if !out.iter().any(|o| o.class == f.class) {
            out.push(f);
        }
    };
    for _ in 0..frames {
        let start = Instant::now();
        let next = film.next_frame().map(|f| f.is_some());
        let took = start.elapsed();
        if took > FRAME_BUDGET * went.scale {
            let k = records.len();
            first(
                &mut out,
                found(
                    "over time",
                    format!(
                        "frame {k} took {took:?}, over {:?}",
                        FRAME_BUDGET * went.scale
                    ),
                ),
            );
        }
        match next {
            Ok(true) => {}
            Ok(false) => break,
            // A frame may stop the film with an error (exit 2): located.
            Err(e) => {
                let msg = e.to_string();
                if !located(&msg) {
                    let k = records.len();
                    first(
                        &mut out,
                        found("unlocated refusal", format!("in frame {k}: {msg}")),
                    );
                }
                break;
            }
        }
        let frame = film.frame().unwrap();
        let number = frame.number();
        let said = frame.warnings().to_vec();
        if let Err(e) = lmfilm::scene::snapshot::validate(frame.scene()) {
            first(
                &mut out,
                found(
                    "unrenderable",
                    format!("frame {number} derives, but render refuses its snapshot: {e}"),
                ),
            );
        }
        excused.extend(
            said.iter()
                .filter(|w| SENSES_WARNED.iter().any(|k| w.contains(k)))
                .filter_map(|w| warned_actor(w)),
        );
        let living = film.living();
        match walls(number, frame.accel(), living, &before, &excused) {
            Some(f) if f.class == "wall entry" => first(&mut out, f),
            Some(f) if went.excused.is_none() => went.excused = Some(f.detail),
            _ => {}
        }
        before = living.iter().map(Seen::of).collect();
        warned.push(
            living
                .iter()
                .map(|a| said.iter().any(|w| w.contains(&format!("actor {} ", a.id))))
                .collect(),
        );
        seen.push(living.iter().map(Seen::of).collect());
        warnings.extend(said);
        let record = Record::of(&film).expect("a frame ran");
        if let Err(e) = finite(&record) {
            first(&mut out, found("not finite", e));
        }
        records.push(record);
        went.frames += 1;
    }
    if let Err(e) = standing(&records, &warnings, frames) {
        first(&mut out, found("standing", e));
    }
    let actors = seen.first().map_or(0, Vec::len);
    for id in 0..actors {
        let of: Vec<Seen> = seen.iter().map(|s| s[id].clone()).collect();
        let w: Vec<bool> = warned.iter().map(|w| w[id]).collect();
        // A warning once names the actor for the rest of the film.
        let w: Vec<bool> = w
            .iter()
            .scan(false, |any, &x| {
                *any |= x;
                Some(*any)
            })
            .collect();
        if let Some(f) = livelock(id, &of, &w, dt) {
            first(&mut out, f);
        }
    }
    drop(film);
    if uncommented(&m.text).contains("trace_actor") {
        went.derived = true;
        for f in derive_folder(m, scene_dir, scratch) {
            first(&mut out, f);
        }
    }
    (out, went)
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
fn standing(records: &[Record], warnings: &[String], frames: usize) -> Result<(), String> {
    let (Some(first), Some(last)) = (records.get(1), records.last()) else {
        return Ok(());
    };
    if records.len() < frames {
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

/// A pool of mutant threads (after a hang, the stuck one is left behind
/// with its pool and a new pool takes over).
fn mutant_pool() -> rayon::ThreadPool {
    rayon::ThreadPoolBuilder::new()
        .thread_name(|_| MUTANT_THREAD.to_string())
        .build()
        .unwrap()
}

/// A round: the shipped scenes themselves first, then `cases` mutants
/// made by `make` (case number → scene index and mutant), each run for
/// `frames` frames. Returns the failures, each with its class.
fn round(
    label: &str,
    scenes: &[Scene],
    cases: u64,
    frames: usize,
    mut make: impl FnMut(u64) -> (usize, Mutant),
) -> Vec<(&'static str, String)> {
    let mut panics = PanicPool::new(MUTANT_THREAD);
    let scratch = Scratch::new(label);
    let dump = std::env::var("LMFILM_ACTOR_DUMP").ok().map(PathBuf::from);
    let verbose = std::env::var_os("LMFILM_ACTOR_VERBOSE").is_some();
    let mut failures = Vec::new();
    let mut slowest = (Duration::ZERO, 0);
    let mut hangs = 0;
    let (mut loaded, mut ran, mut derived, mut excused) = (0, 0, 0, 0);
    let total = cases + scenes.len() as u64;
    let started = Instant::now();
    for case in 0..total {
        let (k, mutant) = if (case as usize) < scenes.len() {
            let s = &scenes[case as usize];
            let m = Mutant {
                text: s.text.clone(),
                readable: s.readable,
                motion: None,
            };
            (case as usize, m)
        } else {
            make(case)
        };
        let scene = &scenes[k];
        let dir = scene.path.parent().unwrap().to_path_buf();
        let (tx, rx) = mpsc::channel();
        let (m, root) = (mutant.clone(), scratch.root.clone());
        let start = Instant::now();
        panics.pool.spawn(move || {
            let r = panic::catch_unwind(AssertUnwindSafe(|| run_mutant(&m, &dir, &root, frames)));
            let _ = tx.send(r);
        });
        let outcome = rx.recv_timeout(hang(frames));
        let took = start.elapsed();
        if took > slowest.0 {
            slowest = (took, case);
        }
        if let Ok(Ok((_, went))) = &outcome {
            if let (Some(r), true) = (&went.refused, verbose) {
                println!("{label} case {case} refused: {r}");
            }
            if verbose && took > Duration::from_secs(1) {
                println!("{label} case {case} took {took:?}: {went:?}");
            }
            // Verbose, every mutant is written.
            if let (Some(d), true) = (&dump, verbose) {
                std::fs::create_dir_all(d).unwrap();
                let ext = if mutant.readable { "lmr" } else { "lm" };
                std::fs::write(d.join(format!("{label}-{case}.{ext}")), &mutant.text).unwrap();
            }
            loaded += usize::from(went.loaded);
            if let Some(e) = &went.excused {
                excused += 1;
                if verbose {
                    println!("{label} case {case}: {e} (after a warning)");
                }
            }
            ran += usize::from(went.frames == frames);
            derived += usize::from(went.derived);
        }
        let what: Vec<Found> = match outcome {
            Ok(Ok((mut found, went))) => {
                let budget = budget(frames) * went.scale.max(1);
                if took > budget && !found.iter().any(|f| f.class == "over time") {
                    found.push(Found {
                        class: "over time",
                        detail: format!("took {took:?}, over {budget:?}"),
                    });
                }
                found
            }
            Ok(Err(_)) => vec![Found {
                class: "panic",
                detail: format!("panicked: {}", panics.last_panic()),
            }],
            Err(_) => {
                hangs += 1;
                panics.pool = mutant_pool();
                vec![Found {
                    class: "over time",
                    detail: format!(
                        "still running after {:?}: it loops (left behind)",
                        hang(frames)
                    ),
                }]
            }
        };
        for f in what {
            let text = format!(
                "{label} case {case} from {}: {}: {}",
                scene.path.display(),
                f.class,
                f.detail
            );
            if let Some(d) = &dump {
                let stem = format!("{label}-{case}-{}", f.class.replace(' ', "_"));
                std::fs::create_dir_all(d).unwrap();
                let ext = if mutant.readable { "lmr" } else { "lm" };
                std::fs::write(d.join(format!("{stem}.{ext}")), &mutant.text).unwrap();
                if let Some(b) = &mutant.motion {
                    std::fs::write(d.join(format!("{stem}.bvh")), b).unwrap();
                }
                std::fs::write(d.join(format!("{stem}.txt")), &text).unwrap();
            }
            failures.push((f.class, format!("{text}\n--- mutant ---\n{}", mutant.text)));
        }
        if hangs >= 3 {
            failures.push(("over time", format!("{label}: stopped after 3 hangs")));
            break;
        }
    }
    println!(
        "{label}: {total} cases ({} shipped scenes), {frames} frames each; {loaded} loaded, {ran} ran every frame, {derived} derived into a folder, {excused} entered a wall after a warning; {} failures, slowest {:?} (case {}), {:?} in all",
        scenes.len(),
        failures.len(),
        slowest.0,
        slowest.1,
        started.elapsed()
    );
    let mut classes: BTreeMap<&str, usize> = BTreeMap::new();
    for (c, _) in &failures {
        *classes.entry(c).or_default() += 1;
    }
    for (c, n) in &classes {
        println!("  {c}: {n}");
    }
    let _ = std::fs::remove_dir_all(&scratch.root);
    drop(panics);
    failures
}

/// Fails with the first failure of each class, and their counts.
fn report(failures: &[(&'static str, String)]) {
    if failures.is_empty() {
        return;
    }
    let mut firsts: BTreeMap<&str, (usize, &str)> = BTreeMap::new();
    for (c, t) in failures {
        firsts.entry(c).or_insert((0, t)).0 += 1;
    }
    let text: Vec<String> = firsts
        .iter()
        .map(|(c, (n, t))| format!("=== {c}: {n} mutant(s); the first:\n{t}"))
        .collect();
    panic!(
        "{} failures of the mutants:\n{}",
        failures.len(),
        text.join("\n")
    );
}

#[test]
fn mutated_actor_scenes_run_or_say_why() {
    let cases = setting("LMFILM_ACTOR_MUTANTS", CASES);
    let mut rng = Rng(setting("LMFILM_ACTOR_SEED", 0x5eed_ac70));
    let scenes = actor_scenes(&["lm"]);
    assert!(scenes.len() >= 10, "the actor scenes are found");
    let failures = round("single", &scenes, cases, FRAMES, |case| {
        let k = case as usize % scenes.len();
        let m = Mutant {
            text: mutate(&scenes[k].text, &mut rng),
            readable: false,
            motion: None,
        };
        (k, m)
    });
    report(&failures);
}

#[test]
fn combined_mutations_of_actor_scenes_run_or_say_why() {
    let cases = setting("LMFILM_ACTOR_COMBINED", COMBINED);
    let frames = setting("LMFILM_ACTOR_FRAMES", COMBINED_FRAMES as u64) as usize;
    // Every seed its own sequence (an odd multiplier, then never 0).
    let seed = setting("LMFILM_ACTOR_SEED", 1) ^ 0xc0_4b1e_d000;
    let mut rng = Rng(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1);
    let scenes = actor_scenes(&["lm", "lmr"]);
    assert!(
        scenes.iter().filter(|s| s.readable).count() >= 10,
        "the readable actor scenes are found"
    );
    // Scenes with a walking actor three times as often as the others.
    let weights: Vec<usize> = scenes
        .iter()
        .map(|s| {
            let walks = ["walk_continuously", "walk_stepworthy"]
                .iter()
                .any(|w| s.text.contains(w));
            if walks {
                3
            } else {
                1
            }
        })
        .collect();
    let total: usize = weights.iter().sum();
    let failures = round("combined", &scenes, cases, frames, |_| {
        let mut at = rng.below(total);
        let k = weights
            .iter()
            .position(|&w| {
                let here = at < w;
                at = at.saturating_sub(w);
                here
            })
            .unwrap();
        (k, mutate_combined(&scenes[k], &mut rng))
    });
    report(&failures);
}

/// The checks catch what they are for (each on a scene made for it).
#[test]
fn the_mutation_checks_see_what_they_check() {
    assert!(located(
        "/tmp/x/mutant.lm:12:38: `fov`: …\n  actorNbr_automata 0 9 fov 0\n   ^"
    ));
    assert!(located("frame 3: /a/motion.bvh:4:2: bad\n x\n ^"));
    assert!(!located(
        "frame 3: cannot write /tmp/out/t: Not a directory"
    ));
    assert!(!located("mutant.lm: 12: no column ^"));
    let scene = "Options\nNBR_actors 1\nactorNbr_automata 0 5 watch\n";
    assert!(unchecked_actor(scene).is_some());
    let scene = "Options\nNBR_actors 2\nactorNbr_automata 0 1 9 obs 0 0 0\ntrace_actor 1 a\n";
    assert!(unchecked_actor(scene).is_none());
    assert!(unchecked_actor("Options\nNBR_actors 1\ntrace_actor 1 a\n").is_some());
    let cut_text = cut(
        "Camera_AnimationParameters\nt_final_interval 16.0 0.04\n",
        4,
    )
    .unwrap();
    assert!(cut_text.contains("t_final_interval 0.12"), "{cut_text}");
    // A livelock: two states at one place beside the goal.
    let at = |state, x: f32| Seen {
        automata: Some(Automata::WalkContinuously),
        walking: Some(Automata::WalkContinuously),
        state,
        stack: 1,
        eye: Vec3::new(x, 0.0, 0.0),
        look_at: Vec3::new(x, 0.0, 1.0),
        goal: Some(Vec3::new(0.0, 0.0, 0.05)),
        gave_up: false,
    };
    let flips: Vec<Seen> = (0..40).map(|k| at(7 + 3 * (k % 2), 0.0)).collect();
    assert!(livelock(0, &flips, &[false; 40], 0.04).is_some());
    assert!(livelock(0, &flips, &[true; 40], 0.04).is_none());
    let walks: Vec<Seen> = (0..40).map(|k| at(10, k as f32 * 0.08)).collect();
    assert!(livelock(0, &walks, &[false; 40], 0.04).is_none());
    // A navigator that looks around (`observe`) every other frame, where
    // it stands, for ever: a livelock too.
    let looks: Vec<Seen> = (0..40)
        .map(|k| {
            let mut s = at(7, 0.0);
            if k % 2 == 1 {
                s.automata = Some(Automata::Observe);
                s.goal = None;
                s.look_at = Vec3::new(k as f32, 0.0, 1.0);
            }
            s
        })
        .collect();
    assert!(livelock(0, &looks, &[false; 40], 0.04).is_some());
}

/// Runs the checks on one scene, e.g. a mutant `LMFILM_ACTOR_DUMP` wrote:
/// `LMFILM_ACTOR_ONE=FILE.lm cargo test --test actors one_actor_mutant --
/// --ignored --nocapture` (its motion file beside it as `FILE.bvh`, its
/// sounds looked up in `scenes/actors`; `LMFILM_ACTOR_FRAMES` frames).
#[test]
#[ignore]
fn one_actor_mutant() {
    let Ok(path) = std::env::var("LMFILM_ACTOR_ONE") else {
        return;
    };
    let path = PathBuf::from(path);
    let text = std::fs::read_to_string(&path).unwrap();
    let motion = std::fs::read_to_string(path.with_extension("bvh")).ok();
    let m = Mutant {
        text,
        readable: path.extension().is_some_and(|e| e == "lmr"),
        motion,
    };
    let frames = setting("LMFILM_ACTOR_FRAMES", COMBINED_FRAMES as u64) as usize;
    let scratch = Scratch::new("one");
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/actors");
    let start = Instant::now();
    let (found, went) = run_mutant(&m, &dir, &scratch.root, frames);
    let _ = std::fs::remove_dir_all(&scratch.root);
    println!("{went:?} in {:?}", start.elapsed());
    for f in &found {
        println!("{}: {}", f.class, f.detail);
    }
    assert!(found.is_empty(), "{} failures", found.len());
}

/// The combined mutants' wall entries kept as regressions (issue 54),
/// each the shipped scene with the settings the mutant changed, judged
/// by the same checks: a walker fast enough to end a piece of its path
/// every frame (`rel_search_level 0`, `speed 20`: 0.25 m pieces, 0.8 m
/// a frame) never turned its eyes to its way and walked into a wall of
/// the maze; with its visual memory off, the navigator walked into a
/// wall once it came within its near clip (0.5), in silence; through a
/// window of 4 or 8 pixels (rays 0.8 or 0.4 apart where it must see, an
/// actor of 0.8) it planned past a corner it had placed only that well
/// and walked into it, in silence; `walk_local` without its collision
/// distance stood before a wall for the rest of the film, in silence.
#[test]
fn combined_mutants_that_walked_into_walls() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/actors");
    let changed = |scene: &str, from: &str, to: &str| {
        let text = std::fs::read_to_string(dir.join(scene)).unwrap();
        assert!(text.contains(from), "{scene} holds {from}");
        text.replacen(from, to, 1)
    };
    let walker = "inertia 0.5 turtle 3 mem_displ_cubes\n";
    let scratch = Scratch::new("walls");
    for text in [
        changed(
            "maze.lm",
            walker,
            &walker.replace('\n', " rel_search_level 0 speed 20\n"),
        ),
        changed("maze.lm", walker, &walker.replace('\n', " vis_mem_off\n")),
        changed("maze.lm", "iVisionWinSize 0 32", "iVisionWinSize 0 4"),
        changed(
            "walker_maze.lm",
            "iVisionWinSize 0 32",
            "iVisionWinSize 0 8",
        ),
        changed(
            "explore.lm",
            "actorNbr_automata 0 watch",
            "actorNbr_automata 0 watch dist_coll 0",
        )
        .replacen("0 walk_continuously init", "0 walk_local init", 1),
    ] {
        let m = Mutant {
            text,
            readable: false,
            motion: None,
        };
        let extra = m
            .text
            .lines()
            .find(|l| l.starts_with("actorNbr_automata 0 w"))
            .unwrap_or("");
        let (found, went) = run_mutant(&m, &dir, &scratch.root, COMBINED_FRAMES);
        assert!(
            went.loaded && went.frames == COMBINED_FRAMES,
            "{extra}: {went:?}"
        );
        let said: Vec<_> = found
            .iter()
            .map(|f| format!("{}: {}", f.class, f.detail))
            .collect();
        assert!(found.is_empty(), "{extra}: {said:?}");
    }
    let _ = std::fs::remove_dir_all(&scratch.root);
}
