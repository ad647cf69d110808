//! The path search (thesis 5.2, appendix G) on hand-built grids and on
//! random 2D grids against breadth-first search.

use std::collections::{BTreeMap, BTreeSet, VecDeque};

use lmfilm::actors::perception::octree::{Cube, Octree, Voxel};
use lmfilm::actors::planning::heuristics::{candidates, heuristic, Heuristic};
use lmfilm::actors::planning::path::{
    extend, label, plan, plan_voxels, search, shortest, Explorer, ExplorerStep, NoPlan, MAX_LABEL,
};
use proptest::prelude::*;

/// A 16 × 1 × 16 grid: `walls[z][x]`.
#[derive(Debug, Clone)]
struct Grid {
    walls: Vec<Vec<bool>>,
}

impl Grid {
    fn is_empty(&self, v: Voxel) -> bool {
        v[1] == 0
            && (v[2] as usize) < self.walls.len()
            && (v[0] as usize) < self.walls[0].len()
            && !self.walls[v[2] as usize][v[0] as usize]
    }

    fn parse(rows: &[&str]) -> Grid {
        Grid {
            walls: rows
                .iter()
                .map(|r| r.chars().map(|c| c == '#').collect())
                .collect(),
        }
    }
}

/// Breadth-first distances from `start` over the arcs of `h`, within
/// `inside` when given.
fn bfs(
    h: &Heuristic,
    start: Voxel,
    empty: &dyn Fn(Voxel) -> bool,
    inside: Option<&BTreeSet<Voxel>>,
) -> BTreeMap<Voxel, usize> {
    let mut d = BTreeMap::from([(start, 0)]);
    let mut q = VecDeque::from([start]);
    while let Some(u) = q.pop_front() {
        let du = d[&u];
        for w in candidates(h, u, empty) {
            if inside.is_some_and(|s| !s.contains(&w)) || d.contains_key(&w) {
                continue;
            }
            d.insert(w, du + 1);
            q.push_back(w);
        }
    }
    d
}

/// `path` runs from start to end, each voxel a candidate of the one
/// before (so empty and, for 0 and 1, 4-connected in the plane).
fn assert_valid(h: &Heuristic, path: &[Voxel], start: Voxel, end: Voxel, g: &Grid) {
    assert_eq!(path.first(), Some(&start));
    assert_eq!(path.last(), Some(&end));
    for w in path.windows(2) {
        assert!(candidates(h, w[0], |v| g.is_empty(v)).contains(&w[1]));
        let step: u32 = (0..3).map(|i| w[0][i].abs_diff(w[1][i])).sum();
        assert_eq!(step, 1);
    }
    let distinct: BTreeSet<&Voxel> = path.iter().collect();
    assert_eq!(distinct.len(), path.len(), "a voxel twice");
}

fn grid_strategy() -> impl Strategy<Value = (Grid, Voxel, Voxel)> {
    (
        prop::collection::vec(prop::collection::vec(prop::bool::weighted(0.3), 16), 16),
        (0u32..16, 0u32..16, 0u32..16, 0u32..16),
    )
        .prop_map(|(mut walls, (sx, sz, ex, ez))| {
            walls[sz as usize][sx as usize] = false;
            walls[ez as usize][ex as usize] = false;
            (Grid { walls }, [sx, 0, sz], [ex, 0, ez])
        })
}

fn check_against_bfs(n: u32, g: &Grid, start: Voxel, end: Voxel) {
    let h = heuristic(n).unwrap();
    let empty = |v: Voxel| g.is_empty(v);
    let reach = bfs(h, start, &empty, None);
    let found = search(h, start, end, empty, 10_000);
    assert_eq!(found.is_some(), reach.contains_key(&end));
    let Some(searched) = found else {
        assert!(plan_voxels(h, start, end, empty, 10_000).is_none());
        return;
    };
    assert_valid(h, &searched, start, end, g);
    let p = plan_voxels(h, start, end, empty, 10_000).unwrap();
    assert_eq!(p.searched, searched);
    assert_valid(h, &p.path, start, end, g);
    assert!(p.path.len() <= searched.len());
    assert!(p.path.len() > reach[&end], "shorter than the shortest path");
    let corridor: BTreeSet<Voxel> = extend(h, &searched, empty).into_keys().collect();
    assert_eq!(corridor.len(), p.corridor);
    let within = bfs(h, start, &empty, Some(&corridor));
    assert_eq!(p.path.len(), within[&end] + 1);
    assert_eq!(plan_voxels(h, start, end, empty, 10_000), Some(p));
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(300))]

    #[test]
    fn heuristic_0_agrees_with_breadth_first_search((g, s, e) in grid_strategy()) {
        check_against_bfs(0, &g, s, e);
    }

    #[test]
    fn heuristic_1_agrees_with_breadth_first_search((g, s, e) in grid_strategy()) {
        // Fewer walls, or heuristic 1 (a voxel of clearance) rarely passes.
        let mut g = g;
        for (z, row) in g.walls.iter_mut().enumerate() {
            for (x, w) in row.iter_mut().enumerate() {
                *w &= (x * 7 + z * 3) % 4 == 0;
            }
        }
        g.walls[s[2] as usize][s[0] as usize] = false;
        g.walls[e[2] as usize][e[0] as usize] = false;
        check_against_bfs(1, &g, s, e);
    }
}

#[test]
fn start_is_end() {
    let g = Grid::parse(&["..", ".."]);
    let h = heuristic(0).unwrap();
    let p = plan_voxels(h, [1, 0, 1], [1, 0, 1], |v| g.is_empty(v), 10).unwrap();
    assert_eq!(p.path, [[1, 0, 1]]);
    assert_eq!(p.visited, 1);
}

/// The figure 5.2.1 situation: the aim lies behind a wall, the depth-first
/// search runs into the pocket first, and Algorithms 2–4 cut the detour.
#[test]
fn the_corridor_shortens_the_searched_path() {
    let g = Grid::parse(&[
        "..........",
        "....E.....",
        "..........",
        "..######..",
        "..#....#..",
        "..#....#..",
        "..#....#..",
        "..........",
        "..........",
        "....S.....",
    ]);
    let (s, e) = ([4, 0, 9], [4, 0, 1]);
    let h = heuristic(0).unwrap();
    let p = plan_voxels(h, s, e, |v| g.is_empty(v), 1000).unwrap();
    assert_valid(h, &p.path, s, e, &g);
    assert!(p.path.len() < p.searched.len());
    let empty = |v: Voxel| g.is_empty(v);
    // Shortest within the corridor, which need not hold the shortest
    // path of the whole grid (the thesis promises no more).
    let mut corridor = extend(h, &p.searched, empty);
    let inside: BTreeSet<Voxel> = corridor.keys().copied().collect();
    assert_eq!(p.path.len(), bfs(h, s, &empty, Some(&inside))[&e] + 1);
    assert!(p.path.len() > bfs(h, s, &empty, None)[&e]);
    // Algorithm 3's labels grow by one along the path.
    label(h, &mut corridor, s, empty);
    for (i, v) in p.path.iter().enumerate() {
        assert_eq!(corridor[v], i as u32);
    }
    assert_eq!(shortest(h, &corridor, e, empty), Some(p.path.clone()));
    assert!(corridor.values().all(|&l| l != MAX_LABEL));
}

#[test]
fn no_path_and_the_search_bound() {
    let g = Grid::parse(&["..#..", "..#..", "..#.."]);
    let h = heuristic(0).unwrap();
    assert_eq!(
        search(h, [0, 0, 0], [4, 0, 0], |v| g.is_empty(v), 1000),
        None
    );
    let open = Grid::parse(&["..........", ".........."]);
    assert!(search(h, [0, 0, 0], [9, 0, 1], |v| open.is_empty(v), 1000).is_some());
    assert_eq!(
        search(h, [0, 0, 0], [9, 0, 1], |v| open.is_empty(v), 5),
        None
    );
}

/// Explore mode: every move is to a neighbour of the voxel before, and an
/// enclosed actor visits every voxel it can reach before it gives up.
#[test]
fn the_explorer_walks_one_voxel_at_a_time() {
    let g = Grid::parse(&[
        "#######...",
        "#.....#...",
        "#.##..#...",
        "#..#..#...",
        "#######..E",
    ]);
    let h = heuristic(0).unwrap();
    let mut e = Explorer::new(h, [1, 0, 1], [9, 0, 4]);
    let mut at: Voxel = [1, 0, 1];
    let mut seen = BTreeSet::from([at]);
    let outcome = loop {
        match e.step(|v| g.is_empty(v)) {
            ExplorerStep::Go(v) => {
                let d: u32 = (0..3).map(|i| at[i].abs_diff(v[i])).sum();
                assert_eq!(d, 1, "{at:?} → {v:?}");
                at = v;
                seen.insert(v);
            }
            other => break other,
        }
    };
    assert_eq!(outcome, ExplorerStep::Enclosed);
    assert_eq!(at, [1, 0, 1], "back at the start");
    let inside = bfs(h, [1, 0, 1], &|v| g.is_empty(v), None);
    assert_eq!(seen, inside.keys().copied().collect());
    assert_eq!(e.visited(), seen.len());
    assert!(e.path().is_empty());
    // The memory fills on the way: a wall seen late stops the walk there.
    let open = Grid::parse(&["......"]);
    let mut e = Explorer::new(h, [0, 0, 0], [5, 0, 0]);
    let mut steps = Vec::new();
    loop {
        let reached = steps.len();
        match e.step(|v: Voxel| open.is_empty(v) && !(reached >= 2 && v == [3, 0, 0])) {
            ExplorerStep::Go(v) => steps.push(v),
            s => {
                assert_eq!(s, ExplorerStep::Enclosed);
                break;
            }
        }
    }
    assert_eq!(steps, [[1, 0, 0], [2, 0, 0], [1, 0, 0], [0, 0, 0]]);
}

/// `plan` on a memory octree: world points in, world centres out, around
/// a wall, at the memory's voxels and at twice their edge.
#[test]
fn plan_goes_around_a_wall_in_the_memory() {
    let mut m = Octree::new(Cube::new(0.0, 16.0, 0.5), false);
    // A wall at x = 4 … 4.5 from z = 0 to z = 12, one voxel high.
    for z in 0..24 {
        m.insert([8, 0, z], 1);
    }
    let h = heuristic(0).unwrap();
    let (a, b) = ([1.2, 0.2, 1.2], [7.2, 0.2, 1.2]);
    for level in [0, 1] {
        let p = plan(&m, a, b, h, level, 10_000).unwrap();
        let edge = 0.5 * f64::from(1u32 << level);
        // Centres of the search voxels, consecutive ones one edge apart.
        for w in p.windows(2) {
            let d: f64 = (0..3).map(|i| (w[0][i] - w[1][i]).abs()).sum();
            assert!((d - edge).abs() < 1e-9);
        }
        assert!(p.iter().any(|q| q[2] > 6.0), "around the wall's end");
        assert!(p.iter().all(|q| !(4.0..4.5).contains(&q[0]) || q[2] > 6.0));
        let half = edge / 2.0;
        assert_eq!(p[0], [0, 1, 2].map(|i| (a[i] / edge).floor() * edge + half));
        assert_eq!(plan(&m, a, b, h, level, 10_000), Ok(p));
    }
    // The end inside the wall, or outside the cube: no path.
    assert_eq!(
        plan(&m, a, [4.2, 0.2, 1.0], h, 0, 10_000),
        Err(NoPlan::Occupied)
    );
    assert_eq!(
        plan(&m, a, [20.0, 0.2, 1.0], h, 0, 10_000),
        Err(NoPlan::Outside)
    );
    // A closed wall: the search exhausts the side and says so.
    for x in 0..32 {
        m.insert([x, 0, 24], 1);
        m.insert([8, 0, x], 1);
    }
    assert_eq!(plan(&m, a, b, h, 0, 100_000), Err(NoPlan::NoWay));
}

/// A 3D world of voxel columns for heuristic 9, one character a column
/// (rows are z, characters x): a digit d is solid from y = 0 to d, a
/// letter a–j a single voxel at y = 0–9 (a bridge), `.` nothing (a drop
/// to the bottom of the grid). The grid is 10 high; past its sides and
/// top everything is occupied, as past a memory's cube.
struct Terrain {
    columns: Vec<Vec<u8>>,
}

impl Terrain {
    fn parse(rows: &[&str]) -> Terrain {
        Terrain {
            columns: rows.iter().map(|r| r.bytes().collect()).collect(),
        }
    }

    fn occupied(&self, v: Voxel) -> bool {
        let Some(&c) = self
            .columns
            .get(v[2] as usize)
            .and_then(|r| r.get(v[0] as usize))
        else {
            return true;
        };
        match c {
            b'0'..=b'9' => v[1] <= u32::from(c - b'0'),
            b'a'..=b'j' => v[1] == u32::from(c - b'a'),
            _ => v[1] >= 10,
        }
    }

    fn is_empty(&self, v: Voxel) -> bool {
        v[1] < 10 && !self.occupied(v)
    }

    /// The voxel under `v` is occupied: something to stand on.
    fn supported(&self, v: Voxel) -> bool {
        v[1] > 0 && self.occupied([v[0], v[1] - 1, v[2]])
    }
}

/// Every voxel of `path` is free and stands on an occupied one, and each
/// move is one voxel sideways, at most one up or down.
fn assert_walkable(path: &[Voxel], t: &Terrain) {
    for v in path {
        assert!(t.is_empty(*v), "{v:?} occupied");
        assert!(
            t.supported(*v),
            "{v:?} has no support: the actor would fall"
        );
    }
    for w in path.windows(2) {
        let side = w[0][0].abs_diff(w[1][0]) + w[0][2].abs_diff(w[1][2]);
        assert_eq!(side, 1, "{:?} → {:?}", w[0], w[1]);
        assert!(w[0][1].abs_diff(w[1][1]) <= 1, "{:?} → {:?}", w[0], w[1]);
    }
}

/// A lower floor (top y = 3), stairs of single steps (4, 5, 6) up to a
/// higher floor (top 7) without walls, a gap down to the bottom of the
/// grid, a bridge (h: one voxel at y = 7) over it, and the far floor.
const TERRAIN: [&str; 9] = [
    "......................",
    ".333333456777....777..",
    ".333333456777....777..",
    ".333333456777hhhh777..",
    ".333333456777hhhh777..",
    ".333333456777hhhh777..",
    ".333333456777....777..",
    ".333333456777....777..",
    "......................",
];

#[test]
fn heuristic_9_climbs_the_stairs_and_crosses_the_bridge() {
    let t = Terrain::parse(&TERRAIN);
    let h = heuristic(9).unwrap();
    let empty = |v: Voxel| t.is_empty(v);
    let (start, end) = ([2, 4, 2], [18, 8, 4]);
    let p = plan_voxels(h, start, end, empty, 100_000).expect("a way up and over");
    assert_walkable(&p.searched, &t);
    assert_walkable(&p.path, &t);
    // Up the three steps one at a time, then over the bridge at y = 8.
    let heights: BTreeSet<u32> = p.path.iter().map(|v| v[1]).collect();
    assert_eq!(heights, BTreeSet::from([4, 5, 6, 7, 8]));
    assert!(p.path.iter().any(|v| (13..17).contains(&v[0])));
    for v in p.path.iter().filter(|v| (13..17).contains(&v[0])) {
        assert!(
            (3..=5).contains(&v[2]) && v[1] == 8,
            "off the bridge: {v:?}"
        );
    }
    // Down again: the same stairs, one step at a time.
    let back = plan_voxels(h, end, start, empty, 100_000).expect("the way back");
    assert_walkable(&back.path, &t);
    assert_eq!(back.path.len(), p.path.len());
    // The explorer, walked for real, never stands over nothing either,
    // backtracking included.
    let mut e = Explorer::new(h, start, end);
    let mut walked = vec![start];
    loop {
        match e.step(empty) {
            ExplorerStep::Go(v) => walked.push(v),
            ExplorerStep::Arrived => break,
            ExplorerStep::Enclosed => panic!("enclosed"),
        }
    }
    assert_walkable(&walked, &t);
}

#[test]
fn heuristic_9_does_not_step_off_an_edge() {
    let h = heuristic(9).unwrap();
    // Without the bridge the gap is a cliff on both sides: no way.
    let rows: Vec<String> = TERRAIN.iter().map(|r| r.replace('h', ".")).collect();
    let rows: Vec<&str> = rows.iter().map(String::as_str).collect();
    let t = Terrain::parse(&rows);
    let empty = |v: Voxel| t.is_empty(v);
    assert_eq!(search(h, [2, 4, 2], [18, 8, 4], empty, 100_000), None);
    // Everything it can reach from the start stands on a support: the
    // higher floor's open edges and the gap's edges are never crossed.
    let reach = bfs(h, [2, 4, 2], &empty, None);
    assert!(
        reach.keys().any(|v| v[1] == 8),
        "it reaches the higher floor"
    );
    for v in reach.keys() {
        assert!(t.supported(*v), "{v:?}");
        assert!(v[0] < 13, "{v:?} past the edge");
    }
    // Without the stairs, the higher floor is out of reach.
    let flat: Vec<String> = TERRAIN
        .iter()
        .map(|r| r.replace(['4', '5', '6'], "3"))
        .collect();
    let flat: Vec<&str> = flat.iter().map(String::as_str).collect();
    let t = Terrain::parse(&flat);
    let reach = bfs(h, [2, 4, 2], &|v| t.is_empty(v), None);
    assert!(reach.keys().all(|v| v[1] == 4 && v[0] < 10));
    // A step of two voxels is no stair.
    let steep: Vec<String> = TERRAIN.iter().map(|r| r.replace('4', "5")).collect();
    let steep: Vec<&str> = steep.iter().map(String::as_str).collect();
    let t = Terrain::parse(&steep);
    let reach = bfs(h, [2, 4, 2], &|v| t.is_empty(v), None);
    assert!(reach.keys().all(|v| v[1] == 4));
    // A wall beyond a gap (the third term, a step up two voxels ahead)
    // does not lure it over the gap.
    let t = Terrain::parse(&[".......", ".333.9.", ".333.9.", ".333.9.", "......."]);
    let reach = bfs(h, [1, 4, 2], &|v| t.is_empty(v), None);
    assert!(reach.keys().all(|v| v[0] <= 3), "{reach:?}");
}

/// The explore mode's look around (docs/actors.md): a voxel just reached
/// without a candidate is a dead end; reopened, its candidates are taken
/// again with what the memory holds then, and the walk goes on.
#[test]
fn a_dead_end_reopened_takes_its_candidates_again() {
    let h = heuristic(9).unwrap();
    // At first the floor is known only under the start and around it;
    // the rest of the room, toward the end at z = 6, is unseen.
    let seen = Terrain::parse(&[".....", ".333.", ".333.", ".333.", "....."]);
    let full = Terrain::parse(&[
        "33333", "33333", "33333", "33333", "33333", "33333", "33333", "33333",
    ]);
    let (start, end) = ([2, 4, 2], [2, 4, 6]);
    let mut e = Explorer::new(h, start, end);
    assert!(e.dead_end(|v| seen.is_empty(v)));
    // Not reopened: the next step gives up the start at once.
    let mut gave_up = e.clone();
    assert_eq!(gave_up.step(|v| seen.is_empty(v)), ExplorerStep::Enclosed);
    // Reopened after looking around: the corridor is there.
    e.reopen();
    assert!(!e.dead_end(|v| full.is_empty(v)));
    assert_eq!(e.step(|v| full.is_empty(v)), ExplorerStep::Go([2, 4, 3]));
    assert!(!e.dead_end(|v| full.is_empty(v)));
    // A voxel walked back to is no dead end: its candidates were taken
    // when it was reached.
    let mut back = Explorer::new(h, start, end);
    let closed = |v: Voxel| full.is_empty(v) && v[2] < 4;
    let (mut steps, mut returned) = (0, false);
    while let ExplorerStep::Go(v) = back.step(closed) {
        steps += 1;
        if v == start && steps > 1 {
            assert!(!back.dead_end(closed));
            returned = true;
        }
    }
    assert!(returned);
}
