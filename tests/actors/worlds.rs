//! Generated worlds: seeded mazes, traps, pillar fields and
//! closed rooms a person would find fair, each with its ground truth
//! computed from its own geometry, walked by a `walk_continuously` actor
//! who knows nothing of them, over the range of settings the thesis
//! allows (window, view angle, memory voxel, search level, eye height,
//! heuristic, floor or none, a body drawn around the eye or none).
//!
//! CI runs a bounded sample ([`a_sample_of_generated_worlds`]); `make
//! test-worlds` runs hundreds and prints the table of docs/actors.md
//! ([`hundreds_of_generated_worlds`]).

use std::collections::BinaryHeap;

use lmfilm::film::Film;
use lmfilm::lsys::Source;
use lmfilm::turtle::Options;

use super::support::written;
use crate::common::Rng;

/// Walls are this high and thick; corridors are a cell less a wall wide.
const HEIGHT: f64 = 2.0;
const THICK: f64 = 0.2;
const CELL: f64 = 2.5;
/// Seconds a second of the film lasts per frame, and the actor's speed.
const DT: f64 = 0.04;
const SPEED: f64 = 2.0;
/// The actor is arrived within this distance of its goal (floor plane).
const ARRIVED: f64 = 0.25;
/// The longest a world is walked: exploring a closed room voxel by
/// voxel at `rel_search_level` 0 takes minutes of film.
const SECONDS: f64 = 1000.0;

/// An axis-aligned wall standing on the floor: x0..x1 × z0..z1.
#[derive(Debug, Clone, Copy)]
pub struct Wall {
    x0: f64,
    x1: f64,
    z0: f64,
    z1: f64,
}

impl Wall {
    fn new(x0: f64, x1: f64, z0: f64, z1: f64) -> Wall {
        Wall {
            x0: x0.min(x1),
            x1: x0.max(x1),
            z0: z0.min(z1),
            z1: z0.max(z1),
        }
    }

    /// Distance from (x, z) to the wall on the floor plane; 0 inside.
    fn distance(&self, x: f64, z: f64) -> f64 {
        let dx = (self.x0 - x).max(x - self.x1).max(0.0);
        let dz = (self.z0 - z).max(z - self.z1).max(0.0);
        dx.hypot(dz)
    }

    fn contains(&self, x: f64, z: f64) -> bool {
        x > self.x0 && x < self.x1 && z > self.z0 && z < self.z1
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum Family {
    /// A perfect maze of cells: one way between any two.
    Maze,
    /// A maze with walls taken out: circuits.
    LoopMaze,
    /// The actor inside a U, its goal beyond the closed end.
    UTrap,
    /// The actor at the centre of a spiral, its goal outside.
    Spiral,
    /// An open field of pillars.
    Pillars,
    /// A closed room, the goal outside: unreachable.
    Closed,
}

pub const FAMILIES: [Family; 6] = [
    Family::Maze,
    Family::LoopMaze,
    Family::UTrap,
    Family::Spiral,
    Family::Pillars,
    Family::Closed,
];

/// A generated world: its walls, where the actor starts, its goal, and
/// the square (min, max on x and z) the memory's cube must hold.
#[derive(Debug, Clone)]
pub struct World {
    pub family: Family,
    pub walls: Vec<Wall>,
    pub start: (f64, f64),
    pub goal: (f64, f64),
    pub bounds: (f64, f64),
}

/// A cell of a grid (column, row), and an open passage between two
/// neighbouring cells.
type Cell = (usize, usize);
type Passage = (Cell, Cell);

/// The walls of a grid of `cols` × `rows` cells with the open passages
/// `open`, the outer walls closed.
fn cell_walls(cols: usize, rows: usize, open: &[Passage]) -> Vec<Wall> {
    let is_open = |a: Cell, b: Cell| {
        open.iter()
            .any(|&(p, q)| (p, q) == (a, b) || (q, p) == (a, b))
    };
    let h = THICK / 2.0;
    let mut walls = Vec::new();
    // Vertical walls (along z) at x = i·CELL, between columns i−1 and i.
    for i in 0..=cols {
        for j in 0..rows {
            let inner = i > 0 && i < cols && is_open((i - 1, j), (i, j));
            if !inner {
                let x = i as f64 * CELL;
                walls.push(Wall::new(
                    x - h,
                    x + h,
                    j as f64 * CELL - h,
                    (j + 1) as f64 * CELL + h,
                ));
            }
        }
    }
    // Horizontal walls (along x) at z = j·CELL.
    for j in 0..=rows {
        for i in 0..cols {
            let inner = j > 0 && j < rows && is_open((i, j - 1), (i, j));
            if !inner {
                let z = j as f64 * CELL;
                walls.push(Wall::new(
                    i as f64 * CELL - h,
                    (i + 1) as f64 * CELL + h,
                    z - h,
                    z + h,
                ));
            }
        }
    }
    walls
}

/// A perfect maze by the recursive backtracker: the passages opened.
fn perfect_maze(rng: &mut Rng, cols: usize, rows: usize) -> Vec<Passage> {
    let mut seen = vec![false; cols * rows];
    let mut stack = vec![(0usize, 0usize)];
    seen[0] = true;
    let mut open = Vec::new();
    while let Some(&(i, j)) = stack.last() {
        let mut next = Vec::new();
        if i > 0 {
            next.push((i - 1, j));
        }
        if i + 1 < cols {
            next.push((i + 1, j));
        }
        if j > 0 {
            next.push((i, j - 1));
        }
        if j + 1 < rows {
            next.push((i, j + 1));
        }
        next.retain(|&(a, b)| !seen[b * cols + a]);
        if next.is_empty() {
            stack.pop();
            continue;
        }
        let n = next[rng.below(next.len())];
        seen[n.1 * cols + n.0] = true;
        open.push(((i, j), n));
        stack.push(n);
    }
    open
}

fn centre(i: usize, j: usize) -> (f64, f64) {
    ((i as f64 + 0.5) * CELL, (j as f64 + 0.5) * CELL)
}

/// Turns a world a quarter turn `k` times about the centre of `bounds`.
fn turned(mut w: World, k: usize) -> World {
    let c = (w.bounds.0 + w.bounds.1) / 2.0;
    let turn = |(x, z): (f64, f64)| (c - (z - c), x);
    for _ in 0..k % 4 {
        w.start = turn(w.start);
        w.goal = turn(w.goal);
        w.walls = w
            .walls
            .iter()
            .map(|v| {
                let (a, b) = (turn((v.x0, v.z0)), turn((v.x1, v.z1)));
                Wall::new(a.0, b.0, a.1, b.1)
            })
            .collect();
    }
    w
}

impl World {
    /// The world of `family` for `seed`.
    pub fn generate(family: Family, seed: u64) -> World {
        let mut rng = Rng(0x9E37_79B9_7F4A_7C15 ^ seed.wrapping_mul(0x2545_F491_4F6C_DD1D) | 1);
        let world = match family {
            Family::Maze | Family::LoopMaze => {
                let (cols, rows) = (3 + rng.below(3), 3 + rng.below(3));
                let mut open = perfect_maze(&mut rng, cols, rows);
                if family == Family::LoopMaze {
                    // Take out interior walls not yet open: circuits.
                    for _ in 0..1 + cols * rows / 4 {
                        let (i, j) = (rng.below(cols - 1), rng.below(rows));
                        open.push(((i, j), (i + 1, j)));
                        let (i, j) = (rng.below(cols), rng.below(rows - 1));
                        open.push(((i, j), (i, j + 1)));
                    }
                }
                World {
                    family,
                    walls: cell_walls(cols, rows, &open),
                    start: centre(0, 0),
                    goal: centre(cols - 1, rows - 1),
                    bounds: (-2.0, cols.max(rows) as f64 * CELL + 2.0),
                }
            }
            Family::Spiral => {
                // Cells visited in a square spiral from the centre out of
                // an n × n grid, each open to the next; the outermost one
                // opens out of the grid to the goal.
                let n = 3 + 2 * rng.below(2);
                let mut order = vec![(n / 2, n / 2)];
                let (mut x, mut z) = (n as i64 / 2, n as i64 / 2);
                let dirs = [(1i64, 0i64), (0, 1), (-1, 0), (0, -1)];
                let (mut d, mut len) = (rng.below(4), 1);
                while order.len() < n * n {
                    for _ in 0..2 {
                        for _ in 0..len {
                            x += dirs[d % 4].0;
                            z += dirs[d % 4].1;
                            if (0..n as i64).contains(&x) && (0..n as i64).contains(&z) {
                                order.push((x as usize, z as usize));
                            }
                        }
                        d += 1;
                    }
                    len += 1;
                }
                let open: Vec<_> = order
                    .windows(2)
                    .filter(|w| w[0].0.abs_diff(w[1].0) + w[0].1.abs_diff(w[1].1) == 1)
                    .map(|w| (w[0], w[1]))
                    .collect();
                let mut walls = cell_walls(n, n, &open);
                // The exit: the last cell (a corner) opens on, in the
                // spiral's direction, to the goal outside.
                let [prev, last] = [order[n * n - 2], order[n * n - 1]];
                let dir = (last.0 as i64 - prev.0 as i64, last.1 as i64 - prev.1 as i64);
                let (cx, cz) = centre(last.0, last.1);
                let door = (
                    cx + dir.0 as f64 * CELL / 2.0,
                    cz + dir.1 as f64 * CELL / 2.0,
                );
                walls.retain(|w| w.distance(door.0, door.1) > 0.3);
                World {
                    family,
                    walls,
                    start: centre(n / 2, n / 2),
                    goal: (
                        cx + dir.0 as f64 * (CELL + 1.5),
                        cz + dir.1 as f64 * (CELL + 1.5),
                    ),
                    bounds: (-2.0 * CELL, n as f64 * CELL + 2.0 * CELL),
                }
            }
            Family::UTrap => {
                // The U: sides along z from 0 to depth, closed at
                // depth; the actor inside, its goal beyond the closed end.
                let width = rng.uniform(6.0, 12.0);
                let depth = rng.uniform(8.0, 15.0);
                let beyond = rng.uniform(4.0, 9.0);
                let h = THICK / 2.0;
                let x0 = 6.0;
                let walls = vec![
                    Wall::new(x0 - h, x0 + h, 6.0, 6.0 + depth),
                    Wall::new(x0 + width - h, x0 + width + h, 6.0, 6.0 + depth),
                    Wall::new(x0 - h, x0 + width + h, 6.0 + depth - h, 6.0 + depth + h),
                ];
                let start = (x0 + width / 2.0, 6.0 + rng.uniform(2.0, depth - 3.0));
                let goal = (
                    x0 + width / 2.0 + rng.uniform(-2.0, 2.0),
                    6.0 + depth + beyond,
                );
                let side = 6.0 + depth + beyond + 5.0;
                World {
                    family,
                    walls,
                    start,
                    goal,
                    bounds: (0.0, side.max(x0 + width + 6.0)),
                }
            }
            Family::Pillars => {
                // Pillars on a jittered lattice of 4 m: gaps of 2.3 m at
                // least between them.
                let n = 4 + rng.below(2);
                let mut walls = Vec::new();
                for i in 0..n {
                    for j in 0..n {
                        if rng.below(5) == 0 {
                            continue;
                        }
                        let s = rng.uniform(0.4, 1.2);
                        let (x, z) = (
                            4.0 + 4.0 * i as f64 + rng.uniform(-0.25, 0.25),
                            4.0 + 4.0 * j as f64 + rng.uniform(-0.25, 0.25),
                        );
                        walls.push(Wall::new(
                            x - s / 2.0,
                            x + s / 2.0,
                            z - s / 2.0,
                            z + s / 2.0,
                        ));
                    }
                }
                let side = 4.0 * n as f64 + 4.0;
                World {
                    family,
                    walls,
                    start: (2.0 + 4.0 * rng.below(n) as f64, 2.0),
                    goal: (2.0 + 4.0 * rng.below(n) as f64, side - 2.0),
                    bounds: (0.0, side),
                }
            }
            Family::Closed => {
                let (cols, rows) = (2 + rng.below(2), 2 + rng.below(2));
                World {
                    family,
                    walls: cell_walls(cols, rows, &perfect_maze(&mut rng, cols, rows)),
                    start: centre(0, 0),
                    goal: (cols as f64 * CELL + 3.0, rows as f64 * CELL / 2.0),
                    bounds: (-2.0, cols.max(rows) as f64 * CELL + 5.0),
                }
            }
        };
        turned(world, rng.below(4))
    }

    /// The ground truth from the walls alone: on a grid of `res`, the
    /// free points at least `clearance` from every wall, 8-connected; the
    /// shortest walkable length from start to goal, None when the goal
    /// cannot be reached.
    pub fn shortest(&self, clearance: f64) -> Option<f64> {
        let res = 0.1;
        let (lo, hi) = self.bounds;
        let n = ((hi - lo) / res).ceil() as usize + 1;
        let at = |i: usize| lo + i as f64 * res;
        let cell = |p: f64| (((p - lo) / res).round().max(0.0) as usize).min(n - 1);
        let free: Vec<bool> = (0..n * n)
            .map(|k| {
                let (x, z) = (at(k % n), at(k / n));
                let inside = x > lo + clearance && x < hi - clearance;
                inside
                    && z > lo + clearance
                    && z < hi - clearance
                    && self.walls.iter().all(|w| w.distance(x, z) >= clearance)
            })
            .collect();
        let s = cell(self.start.1) * n + cell(self.start.0);
        let g = cell(self.goal.1) * n + cell(self.goal.0);
        if !free[s] || !free[g] {
            return None;
        }
        // Dijkstra on millimetres (integer keys: deterministic).
        let mut dist = vec![u64::MAX; n * n];
        let mut heap = BinaryHeap::new();
        dist[s] = 0;
        heap.push(std::cmp::Reverse((0u64, s)));
        let step = (res * 1000.0) as u64;
        let diag = (res * 1000.0 * std::f64::consts::SQRT_2) as u64;
        while let Some(std::cmp::Reverse((d, k))) = heap.pop() {
            if k == g {
                return Some(d as f64 / 1000.0);
            }
            if d > dist[k] {
                continue;
            }
            let (x, z) = ((k % n) as i64, (k / n) as i64);
            for (dx, dz) in [
                (1, 0),
                (-1, 0),
                (0, 1),
                (0, -1),
                (1, 1),
                (1, -1),
                (-1, 1),
                (-1, -1),
            ] {
                let (a, b) = (x + dx, z + dz);
                if a < 0 || b < 0 || a >= n as i64 || b >= n as i64 {
                    continue;
                }
                let m = b as usize * n + a as usize;
                let cost = if dx != 0 && dz != 0 { diag } else { step };
                if free[m] && d + cost < dist[m] {
                    dist[m] = d + cost;
                    heap.push(std::cmp::Reverse((d + cost, m)));
                }
            }
        }
        None
    }
}

/// The settings an actor walks a world with.
#[derive(Debug, Clone, Copy)]
pub struct Settings {
    pub window: u32,
    /// Tenths of a degree.
    pub fov: u32,
    pub voxel: f64,
    pub level: u32,
    pub eye: f64,
    pub heuristic: u32,
    pub floor: bool,
    /// A sphere drawn around the eye in its own `M` branch.
    pub body: bool,
}

impl Settings {
    /// Settings drawn over the range the thesis allows, with search
    /// voxels of 0.25 to 0.5 (corridors are 2.3 wide).
    pub fn draw(rng: &mut Rng) -> Settings {
        let (voxel, level) = [(0.125, 1), (0.25, 0), (0.25, 1), (0.5, 0), (0.125, 2)][rng.below(5)];
        let floor = rng.below(4) != 0;
        // Heuristic 7 walks on a support: it needs a floor.
        let heuristic = if floor {
            [0, 1, 1, 7][rng.below(4)]
        } else {
            [0, 1][rng.below(2)]
        };
        Settings {
            window: [24, 33, 40, 48, 64][rng.below(5)],
            fov: [450, 600, 900, 1200][rng.below(4)],
            voxel,
            level,
            eye: [0.4, 0.75, 1.0, 1.6][rng.below(4)],
            heuristic,
            floor,
            body: rng.below(2) == 0,
        }
    }
}

/// The scene of `world` walked with `s`, for `seconds`.
pub fn scene(world: &World, s: &Settings, seconds: f64, facing: f64) -> String {
    let (lo, hi) = world.bounds;
    let (sx, sz) = world.start;
    let (gx, gz) = world.goal;
    // The memory's cube holds the world and the eye's height.
    let (min, max) = (lo - 1.0, hi.max(lo + 2.0 * HEIGHT) + 1.0);
    let coll = if s.heuristic == 7 { 8 } else { 3 };
    let mut axiom = String::new();
    if s.floor {
        axiom += &format!(
            "[ f () () () (2) ({}) (0.5_) ({}) c () () () () ({}) (1) ({}) ]\n",
            written(lo - 1.0),
            written((lo + hi) / 2.0),
            hi - lo + 2.0,
            hi - lo + 2.0
        );
    }
    for w in &world.walls {
        axiom += &format!(
            "[ f () () () (2) ({}) ({}) ({}) c () () () () ({}) ({}) ({}) ]\n",
            written(w.x0),
            HEIGHT / 2.0,
            written((w.z0 + w.z1) / 2.0),
            w.x1 - w.x0,
            HEIGHT,
            w.z1 - w.z0
        );
    }
    if s.body {
        axiom += "[ M () (7) () (0) a () () () () (0.3) ]\n";
    }
    format!(
        "Camera_AnimationParameters\nt_final_interval {seconds} {DT}\n\
         Options\nNBR_actors 1\niVisionWinSize 0 {} 8\n\
         actorNbr_automata 0 walk_continuously init 0 {min} {max} {} obs {sx} {} {sz} lat {} {} {} fov {} vision_range 0.1 60 60 goal {gx} {} {gz} speed {SPEED} heuristic {} coll_test_func {coll} rel_search_level {} size_actor 0.6\n\
         Axiom\n{axiom}Productions\nEndProductions\n",
        s.window,
        s.voxel,
        s.eye,
        sx + facing.cos(),
        s.eye,
        sz + facing.sin(),
        s.fov,
        s.eye,
        s.heuristic,
        s.level,
    )
}

/// What an actor did in a world.
#[derive(Debug, Clone)]
pub struct Walk {
    pub reached: bool,
    /// The reason it gave its goal up, if it did.
    pub gave_up: Option<String>,
    pub walked: f64,
    pub frames: u64,
    /// Frames its eye was inside a wall.
    pub wall_entries: u32,
    /// Its eye, frame by frame (the trace, for the thread test).
    pub trail: Vec<[f32; 3]>,
}

/// Walks `world` with `s` frame by frame until the actor is at its goal,
/// has given it up, or `seconds` have passed.
pub fn walk(world: &World, s: &Settings, seconds: f64, facing: f64) -> Walk {
    let text = scene(world, s, seconds, facing);
    if let Ok(d) = std::env::var("DUMP") {
        std::fs::write(format!("{d}/{:?}_{}.lm", world.family, text.len()), &text).unwrap();
    }
    let mut film = Film::from_sources(&[Source::new("world.lm", &text)], None, Options::default())
        .unwrap_or_else(|e| panic!("{e}\n{text}"));
    let mut w = Walk {
        reached: false,
        gave_up: None,
        walked: 0.0,
        frames: 0,
        wall_entries: 0,
        trail: Vec::new(),
    };
    let mut last: Option<[f32; 3]> = None;
    while let Some(frame) = film.next_frame().unwrap() {
        w.frames = frame.number();
        let a = &film.living()[0];
        let p = a.eye.to_array();
        let (x, z) = (f64::from(p[0]), f64::from(p[2]));
        if let Some(q) = last {
            w.walked += f64::from(p[0] - q[0]).hypot(f64::from(p[2] - q[2]));
        }
        last = Some(p);
        w.trail.push(p);
        if world.walls.iter().any(|wall| wall.contains(x, z)) {
            w.wall_entries += 1;
        }
        if (x - world.goal.0).hypot(z - world.goal.1) < ARRIVED {
            w.reached = true;
            break;
        }
        if a.gave_up.is_some() {
            w.gave_up = a.gave_up.clone();
            break;
        }
    }
    w
}

/// One world of the suite: family, seed, settings, and what happened.
struct Case {
    family: Family,
    shortest: Option<f64>,
    walk: Walk,
    settings: Settings,
    seed: u64,
}

fn run_case(family: Family, seed: u64) -> Case {
    let world = World::generate(family, seed);
    // Settings drawn apart from the world, and per family.
    let mut rng = Rng((seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) ^ family as u64) | 1);
    let settings = Settings::draw(&mut rng);
    let facing = rng.uniform(0.0, std::f64::consts::TAU);
    let shortest = world.shortest(0.3);
    // LMFILM_WORLDS_DUMP=DIR writes each world's scene, to run it alone.
    if let Ok(dir) = std::env::var("LMFILM_WORLDS_DUMP") {
        let text = scene(&world, &settings, SECONDS, facing);
        std::fs::write(format!("{dir}/{family:?}_{seed}.lm"), text).unwrap();
    }
    let walk = walk(&world, &settings, SECONDS, facing);
    Case {
        family: world.family,
        shortest,
        walk,
        settings,
        seed,
    }
}

/// The table row of one family: worlds, reachable, reached, mean walked
/// / shortest, mean frames to goal, wall entries, unreachable reported.
fn summary(cases: &[Case], family: Family) -> String {
    let of: Vec<&Case> = cases.iter().filter(|c| c.family == family).collect();
    let reachable: Vec<&&Case> = of.iter().filter(|c| c.shortest.is_some()).collect();
    let reached: Vec<&&&Case> = reachable.iter().filter(|c| c.walk.reached).collect();
    let ratio = reached
        .iter()
        .map(|c| c.walk.walked / c.shortest.expect("reachable"))
        .sum::<f64>()
        / reached.len().max(1) as f64;
    let frames =
        reached.iter().map(|c| c.walk.frames as f64).sum::<f64>() / reached.len().max(1) as f64;
    let entries: u32 = of.iter().map(|c| c.walk.wall_entries).sum();
    let unreachable = of.len() - reachable.len();
    let reported = of
        .iter()
        .filter(|c| c.shortest.is_none() && c.walk.gave_up.is_some())
        .count();
    format!(
        "| {family:?} | {} | {}/{} | {:.2} | {:.0} | {entries} | {reported}/{unreachable} |",
        of.len(),
        reached.len(),
        reachable.len(),
        ratio,
        frames
    )
}

/// Checks the targets on `cases`, naming each world that fails.
fn check(cases: &[Case], rate: f64) {
    let mut failures = Vec::new();
    for c in cases {
        let name = format!(
            "{:?} seed {} ({:?}): reached {}, gave up {:?}, frames {}, walls {}",
            c.family,
            c.seed,
            c.settings,
            c.walk.reached,
            c.walk.gave_up,
            c.walk.frames,
            c.walk.wall_entries
        );
        if c.walk.wall_entries > 0 {
            failures.push(format!("entered a wall: {name}"));
        }
        match c.shortest {
            Some(_) if !c.walk.reached => {
                let strict = matches!(c.family, Family::Maze | Family::UTrap | Family::Spiral);
                if strict {
                    failures.push(format!("a reachable goal not reached: {name}"));
                } else {
                    eprintln!("a reachable goal not reached (within the rate): {name}");
                }
            }
            None if c.walk.gave_up.is_none() => {
                failures.push(format!("an unreachable goal not reported: {name}"))
            }
            _ => {}
        }
    }
    let reachable = cases.iter().filter(|c| c.shortest.is_some()).count();
    let reached = cases
        .iter()
        .filter(|c| c.shortest.is_some() && c.walk.reached)
        .count();
    if (reached as f64) < rate * reachable as f64 {
        failures.push(format!("{reached} of {reachable} reachable goals reached"));
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

fn table(cases: &[Case]) -> String {
    let mut t = String::from(
        "| family | worlds | reached / reachable | walked / shortest | frames to goal | wall entries | unreachable reported |\n|---|---|---|---|---|---|---|\n",
    );
    for f in FAMILIES {
        t += &summary(cases, f);
        t.push('\n');
    }
    t
}

/// The ground truth is the walls' own: a U's goal is reachable, a closed
/// room's is not, and the shortest way round a U is longer than straight.
#[test]
fn the_ground_truth_comes_from_the_walls() {
    for seed in 0..4 {
        let u = World::generate(Family::UTrap, seed);
        let straight = (u.goal.0 - u.start.0).hypot(u.goal.1 - u.start.1);
        let round = u.shortest(0.3).expect("a U is open on one side");
        assert!(round > straight + 4.0, "{round} against {straight}");
        assert_eq!(World::generate(Family::Closed, seed).shortest(0.3), None);
        for f in [
            Family::Maze,
            Family::LoopMaze,
            Family::Spiral,
            Family::Pillars,
        ] {
            assert!(
                World::generate(f, seed).shortest(0.3).is_some(),
                "{f:?} {seed}"
            );
        }
    }
}

/// The bounded sample CI runs: two worlds of each family.
#[test]
fn a_sample_of_generated_worlds() {
    let cases: Vec<Case> = FAMILIES
        .iter()
        .flat_map(|&f| (0..2).map(move |k| (f, 1000 + k)))
        .map(|(f, seed)| run_case(f, seed))
        .collect();
    eprintln!("{}", table(&cases));
    check(&cases, 0.98);
}

/// The same world gives the same trace on 1 and 2 threads.
#[test]
fn a_generated_world_is_walked_the_same_on_one_and_two_threads() {
    let world = World::generate(Family::LoopMaze, 7);
    let s = Settings::draw(&mut Rng(77));
    let on = |n: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .unwrap()
            .install(|| walk(&world, &s, 60.0, 0.3).trail)
    };
    assert_eq!(on(1), on(2));
}

/// Hundreds of worlds: `make test-worlds` (the table of docs/actors.md).
#[test]
#[ignore]
fn hundreds_of_generated_worlds() {
    let n: u64 = std::env::var("LMFILM_WORLDS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(50);
    let cases: Vec<Case> = FAMILIES
        .iter()
        .flat_map(|&f| (0..n).map(move |k| (f, k)))
        .map(|(f, seed)| run_case(f, seed))
        .collect();
    println!("{}", table(&cases));
    check(&cases, 0.98);
}
