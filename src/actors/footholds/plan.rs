//! Optimal step planning on sparse foothold locations (thesis 5.9.3,
//! 7.3.2): a walking actor crossing a river on stones plans which stone
//! each foot lands on, where it halts, and pays for long steps, changes
//! of step length and turns (eq. 7.3.1).
//!
//! A walking state ([`Step`]) is (previous foothold, current foothold,
//! foot on the current one). The graph of states is generated on demand
//! and searched with Dijkstra's algorithm. Everything is a pure function
//! of the inputs: the hash maps are only looked up, never iterated for a
//! result, and equal costs are broken by the states' indices, so the same
//! call gives the same plan on any machine (DESIGN §4).

use std::cmp::Ordering;
use std::collections::BinaryHeap;

use glam::{DVec2, Vec2};
use rustc_hash::FxHashMap;

/// The foot standing on a state's current foothold.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Foot {
    Left,
    Right,
}

impl Foot {
    /// The other foot: feet alternate from state to state.
    pub fn other(self) -> Foot {
        match self {
            Foot::Left => Foot::Right,
            Foot::Right => Foot::Left,
        }
    }

    /// Its name, as the trace lists it.
    pub fn name(self) -> &'static str {
        match self {
            Foot::Left => "left",
            Foot::Right => "right",
        }
    }
}

/// The weights of the arc cost, eq. 7.3.1:
/// `p0·distance^n0 + p1·|speed change|^n1 + p2·turning angle^n2`.
///
/// A term whose base is 0 contributes 0 whatever its exponent (so
/// `n = 0` does not make a halt's zero distance cost `p0`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Weights {
    /// Weight of the step distance.
    pub p0: f64,
    /// Exponent of the step distance.
    pub n0: f64,
    /// Weight of the step-length change.
    pub p1: f64,
    /// Exponent of the step-length change.
    pub n1: f64,
    /// Weight of the turning angle (radians).
    pub p2: f64,
    /// Exponent of the turning angle.
    pub n2: f64,
}

impl Default for Weights {
    /// The thesis's values: p0 = n0 = p1 = n1 = 1, p2 = 5, n2 = 2.
    fn default() -> Weights {
        Weights {
            p0: 1.0,
            n0: 1.0,
            p1: 1.0,
            n1: 1.0,
            p2: 5.0,
            n2: 2.0,
        }
    }
}

impl Weights {
    /// Dijkstra needs non-negative arc costs: finite, non-negative
    /// weights and exponents.
    fn is_valid(&self) -> bool {
        [self.p0, self.n0, self.p1, self.n1, self.p2, self.n2]
            .iter()
            .all(|v| v.is_finite() && *v >= 0.0)
    }
}

/// The walking model's limits (world units).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Gait {
    /// A step is shorter than this (strictly): Df_max.
    pub df_max: f32,
    /// The most a step may be longer or shorter than the one before it
    /// (the `next_step_characteristic`); starting and halting are exempt.
    pub max_change: f32,
}

impl Default for Gait {
    /// Steps under 1 unit, changing by at most 0.5.
    fn default() -> Gait {
        Gait {
            df_max: 1.0,
            max_change: 0.5,
        }
    }
}

impl Gait {
    /// A positive Df_max and a non-negative change (either may be
    /// infinite: no limit).
    fn is_valid(&self) -> bool {
        self.df_max > 0.0 && self.max_change >= 0.0
    }
}

/// A walking state: the foot `foot` stands on `current`, the other foot
/// left `previous` (indices into the footholds). `previous == current`:
/// feet assembled, at rest.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct Step {
    pub previous: usize,
    pub current: usize,
    pub foot: Foot,
}

impl Step {
    /// Feet assembled on one foothold: the actor stands (the start, or
    /// after a halt), with no body direction.
    pub fn is_halt(&self) -> bool {
        self.previous == self.current
    }
}

/// An optimal sequence of walking states.
#[derive(Debug, Clone, PartialEq)]
pub struct Plan {
    /// From the start state (assembled on the start, foot Left) to an
    /// assembled state on the goal.
    pub steps: Vec<Step>,
    /// The sum of the arc costs.
    pub cost: f64,
    /// States Dijkstra settled: the search's work, for the benchmark.
    pub settled: usize,
}

/// Position of a foothold in f64, where costs are computed.
fn at(footholds: &[Vec2], i: usize) -> DVec2 {
    footholds[i].as_dvec2()
}

/// The length of the step that led into `s`: 0 when assembled.
fn length(footholds: &[Vec2], s: &Step) -> f64 {
    at(footholds, s.current).distance(at(footholds, s.previous))
}

/// The body direction of a moving state, (current − previous)
/// normalized; none when assembled (or on two coincident footholds).
fn body(footholds: &[Vec2], s: &Step) -> Option<DVec2> {
    (at(footholds, s.current) - at(footholds, s.previous)).try_normalize()
}

/// Whether the arc `a → b` exists: `b` starts where `a` stands, the feet
/// alternate, and `b` is either the halt of a moving `a` or a step to
/// another foothold nearer than Df_max that, unless `a` is assembled,
/// changes the step length by at most `max_change`.
fn allowed(footholds: &[Vec2], a: &Step, b: &Step, gait: &Gait) -> bool {
    if b.previous != a.current || b.foot == a.foot {
        return false;
    }
    if b.is_halt() {
        // No stepping in place: only a moving state halts.
        return !a.is_halt();
    }
    let d_b = at(footholds, a.current).distance(at(footholds, b.current));
    if d_b >= f64::from(gait.df_max) {
        return false;
    }
    a.is_halt() || (d_b - length(footholds, a)).abs() <= f64::from(gait.max_change)
}

/// `p·base^n`, 0 when the base (or the weight) is 0.
fn term(p: f64, base: f64, n: f64) -> f64 {
    if base == 0.0 || p == 0.0 {
        0.0
    } else {
        p * base.powf(n)
    }
}

/// The cost of the arc `a → b`, eq. 7.3.1–7.3.3: the distance between
/// the current footholds (0 for a halt), the change of step length and
/// the turning angle between the body directions (0 when either state is
/// assembled: the actor turns on the spot while standing). `a_facing`
/// gives `a` an explicit orientation instead: the start faces the
/// destination, so its first step pays its turn; `None` for every other
/// state (a zero vector means no orientation either). Panics when a
/// state's index is out of range of `footholds`.
pub fn cost(
    footholds: &[Vec2],
    a: &Step,
    b: &Step,
    a_facing: Option<Vec2>,
    weights: &Weights,
) -> f64 {
    let distance = at(footholds, a.current).distance(at(footholds, b.current));
    let speed_change = (length(footholds, a) - length(footholds, b)).abs();
    let from = match a_facing {
        Some(f) => f.as_dvec2().try_normalize(),
        None => body(footholds, a),
    };
    let angle = match (from, body(footholds, b)) {
        (Some(u), Some(v)) => u.perp_dot(v).abs().atan2(u.dot(v)),
        _ => 0.0,
    };
    term(weights.p0, distance, weights.n0)
        + term(weights.p1, speed_change, weights.n1)
        + term(weights.p2, angle, weights.n2)
}

/// A node's identity: the start is its own node, distinct from an
/// ordinary assembled state on the same foothold (it has an orientation).
type Key = (bool, Step);

/// A heap entry, ordered so that `BinaryHeap` pops the cheapest first
/// and equal costs in the order of the node keys.
struct Entry {
    cost: f64,
    key: Key,
    node: usize,
}

impl PartialEq for Entry {
    fn eq(&self, other: &Entry) -> bool {
        self.cmp(other) == Ordering::Equal
    }
}

impl Eq for Entry {}

impl PartialOrd for Entry {
    fn partial_cmp(&self, other: &Entry) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for Entry {
    fn cmp(&self, other: &Entry) -> Ordering {
        other
            .cost
            .total_cmp(&self.cost)
            .then_with(|| other.key.cmp(&self.key))
    }
}

/// The footholds bucketed in a uniform grid, built once per search, so a
/// foothold's neighbours within Df_max come from its 3 × 3 cells. Cells
/// are a hair larger than Df_max (and than 2^-20 of the map's extent, to
/// keep cell numbers exact), which only adds candidates the distance
/// test then drops.
struct Grid {
    origin: DVec2,
    cell: f64,
    cells: FxHashMap<(i64, i64), Vec<usize>>,
}

impl Grid {
    fn new(footholds: &[Vec2], df_max: f32) -> Grid {
        let (lo, hi) = footholds.iter().fold(
            (DVec2::splat(f64::MAX), DVec2::splat(f64::MIN)),
            |(lo, hi), p| (lo.min(p.as_dvec2()), hi.max(p.as_dvec2())),
        );
        let extent = (hi - lo).max_element().max(0.0);
        let cell = f64::from(df_max).max(extent / f64::from(1u32 << 20)) * (1.0 + 1e-6);
        let mut grid = Grid {
            origin: lo,
            cell,
            cells: FxHashMap::default(),
        };
        for (i, p) in footholds.iter().enumerate() {
            let c = grid.cell_of(p.as_dvec2());
            grid.cells.entry(c).or_default().push(i);
        }
        grid
    }

    fn cell_of(&self, p: DVec2) -> (i64, i64) {
        let c = ((p - self.origin) / self.cell).floor();
        (c.x as i64, c.y as i64)
    }

    /// The footholds in the 3 × 3 cells around `p` (a superset of those
    /// within Df_max).
    fn near(&self, p: DVec2) -> impl Iterator<Item = usize> + '_ {
        let (cx, cz) = self.cell_of(p);
        (-1..=1)
            .flat_map(move |dx| (-1..=1).map(move |dz| (cx + dx, cz + dz)))
            .filter_map(|c| self.cells.get(&c))
            .flatten()
            .copied()
    }
}

/// A node of the search: its state, best known cost, the node it was
/// reached from, and whether it is settled.
struct Node {
    key: Key,
    cost: f64,
    parent: Option<usize>,
    settled: bool,
}

/// The cheapest walk from `start` to feet assembled on `goal`, by
/// Dijkstra's algorithm over the walking states, stopping when a goal
/// state is settled. The start stands with feet assembled, foot Left,
/// facing `facing` (the thesis faces the destination: pass
/// `footholds[goal] - footholds[start]`); so the first step is the Right
/// foot's, and it pays its turn away from `facing`.
///
/// `None` when no walk exists, when `start` or `goal` is out of range, or
/// when an input is not finite (a position, `facing`), a weight or
/// exponent is negative, or the gait's limits are not positive.
pub fn plan(
    footholds: &[Vec2],
    start: usize,
    goal: usize,
    facing: Vec2,
    gait: &Gait,
    weights: &Weights,
) -> Option<Plan> {
    if start >= footholds.len()
        || goal >= footholds.len()
        || !footholds.iter().all(|p| p.is_finite())
        || !facing.is_finite()
        || !gait.is_valid()
        || !weights.is_valid()
    {
        return None;
    }
    let origin = Step {
        previous: start,
        current: start,
        foot: Foot::Left,
    };
    if start == goal {
        return Some(Plan {
            steps: vec![origin],
            cost: 0.0,
            settled: 0,
        });
    }
    let grid = Grid::new(footholds, gait.df_max);
    let mut nodes = vec![Node {
        key: (true, origin),
        cost: 0.0,
        parent: None,
        settled: false,
    }];
    let mut index: FxHashMap<Key, usize> = FxHashMap::default();
    index.insert((true, origin), 0);
    let mut heap = BinaryHeap::new();
    heap.push(Entry {
        cost: 0.0,
        key: (true, origin),
        node: 0,
    });
    let mut settled = 0;
    let mut candidates = Vec::new();
    while let Some(Entry { cost: g, node, .. }) = heap.pop() {
        if nodes[node].settled || g > nodes[node].cost {
            continue;
        }
        nodes[node].settled = true;
        settled += 1;
        let (is_start, a) = nodes[node].key;
        if !is_start && a.is_halt() && a.current == goal {
            return Some(Plan {
                steps: path(&nodes, node),
                cost: g,
                settled,
            });
        }
        let facing = is_start.then_some(facing);
        let foot = a.foot.other();
        candidates.clear();
        candidates.push(Step {
            previous: a.current,
            current: a.current,
            foot,
        });
        candidates.extend(
            grid.near(at(footholds, a.current))
                .filter(|&n| n != a.current)
                .map(|n| Step {
                    previous: a.current,
                    current: n,
                    foot,
                }),
        );
        for b in candidates
            .iter()
            .filter(|b| allowed(footholds, &a, b, gait))
        {
            let through = g + cost(footholds, &a, b, facing, weights);
            let key = (false, *b);
            let next = *index.entry(key).or_insert_with(|| {
                nodes.push(Node {
                    key,
                    cost: f64::INFINITY,
                    parent: None,
                    settled: false,
                });
                nodes.len() - 1
            });
            let n = &mut nodes[next];
            // Ties keep the first parent: the settle order is fixed.
            if !n.settled && through < n.cost {
                n.cost = through;
                n.parent = Some(node);
                heap.push(Entry {
                    cost: through,
                    key,
                    node: next,
                });
            }
        }
    }
    None
}

/// The states from the start to `node`, following the parents.
fn path(nodes: &[Node], mut node: usize) -> Vec<Step> {
    let mut steps = vec![nodes[node].key.1];
    while let Some(p) = nodes[node].parent {
        steps.push(nodes[p].key.1);
        node = p;
    }
    steps.reverse();
    steps
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The test maps' randomness: the crate's keyed stream, one key per
    /// case, one slot per draw.
    struct Rng {
        key: u64,
        slot: u64,
    }

    impl Rng {
        fn next(&mut self) -> f64 {
            self.slot += 1;
            crate::random::unit(self.key, self.slot)
        }

        fn range(&mut self, lo: f64, hi: f64) -> f64 {
            lo + (hi - lo) * self.next()
        }
    }

    fn start_of(s: usize) -> Step {
        Step {
            previous: s,
            current: s,
            foot: Foot::Left,
        }
    }

    /// Every state `a` may go to, by brute force over all footholds (no
    /// grid), filtered by the arc rules.
    fn successors(footholds: &[Vec2], a: &Step, gait: &Gait) -> Vec<Step> {
        (0..footholds.len())
            .map(|n| Step {
                previous: a.current,
                current: n,
                foot: a.foot.other(),
            })
            .filter(|b| allowed(footholds, a, b, gait))
            .collect()
    }

    /// The cheapest cost by depth-first enumeration of the simple paths
    /// from the start to a goal state, pruned only where no cheaper goal
    /// can follow (costs are non-negative): a partial path no cheaper
    /// than the best complete one, or reaching a state no cheaper than
    /// an earlier partial path did.
    fn exhaustive(
        footholds: &[Vec2],
        start: usize,
        goal: usize,
        facing: Vec2,
        gait: &Gait,
        weights: &Weights,
    ) -> Option<f64> {
        struct Search<'a> {
            footholds: &'a [Vec2],
            goal: usize,
            facing: Vec2,
            gait: &'a Gait,
            weights: &'a Weights,
            on_path: Vec<Key>,
            labels: FxHashMap<Key, f64>,
            best: Option<f64>,
        }
        impl Search<'_> {
            fn go(&mut self, key: Key, g: f64) {
                if self.best.is_some_and(|b| g >= b)
                    || self.on_path.contains(&key)
                    || self.labels.get(&key).is_some_and(|&l| g >= l)
                {
                    return;
                }
                self.labels.insert(key, g);
                let (is_start, a) = key;
                if !is_start && a.is_halt() && a.current == self.goal {
                    self.best = Some(g);
                    return;
                }
                self.on_path.push(key);
                let facing = is_start.then_some(self.facing);
                for b in successors(self.footholds, &a, self.gait) {
                    let c = cost(self.footholds, &a, &b, facing, self.weights);
                    self.go((false, b), g + c);
                }
                self.on_path.pop();
            }
        }
        if start == goal {
            return Some(0.0);
        }
        let mut s = Search {
            footholds,
            goal,
            facing,
            gait,
            weights,
            on_path: Vec::new(),
            labels: FxHashMap::default(),
            best: None,
        };
        s.go((true, start_of(start)), 0.0);
        s.best
    }

    /// Asserts `p` is a valid walk: from the start state to feet
    /// assembled on the goal, every arc allowed, feet alternating, and
    /// the cost the sum of the arc costs.
    fn check(
        footholds: &[Vec2],
        p: &Plan,
        start: usize,
        goal: usize,
        facing: Vec2,
        gait: &Gait,
        weights: &Weights,
    ) {
        assert_eq!(p.steps[0], start_of(start));
        let last = p.steps.last().unwrap();
        assert!(last.is_halt() && last.current == goal, "{:?}", p.steps);
        let mut sum = 0.0;
        for (i, w) in p.steps.windows(2).enumerate() {
            assert!(allowed(footholds, &w[0], &w[1], gait), "{w:?}");
            assert_ne!(w[0].foot, w[1].foot);
            let facing = (i == 0).then_some(facing);
            sum += cost(footholds, &w[0], &w[1], facing, weights);
        }
        assert!(
            (sum - p.cost).abs() <= 1e-9 * sum.max(1.0),
            "{sum} vs {}",
            p.cost
        );
    }

    /// The cost of a given walk, arc by arc.
    fn walk_cost(footholds: &[Vec2], steps: &[Step], facing: Vec2, weights: &Weights) -> f64 {
        steps
            .windows(2)
            .enumerate()
            .map(|(i, w)| cost(footholds, &w[0], &w[1], (i == 0).then_some(facing), weights))
            .sum()
    }

    /// The walk over `stones` in order, halting where `halts` says
    /// (after arriving on that stone) and at the end.
    fn walk(stones: &[usize], halts: &[usize]) -> Vec<Step> {
        let mut steps = vec![start_of(stones[0])];
        for &n in &stones[1..] {
            let a = *steps.last().unwrap();
            steps.push(Step {
                previous: a.current,
                current: n,
                foot: a.foot.other(),
            });
            if halts.contains(&n) || n == *stones.last().unwrap() {
                steps.push(Step {
                    previous: n,
                    current: n,
                    foot: a.foot,
                });
            }
        }
        steps
    }

    fn line(n: usize, spacing: f32) -> Vec<Vec2> {
        (0..n).map(|i| Vec2::new(i as f32 * spacing, 0.0)).collect()
    }

    #[test]
    fn dijkstra_matches_exhaustive_search() {
        let mut found = 0;
        for case in 0..200u64 {
            let mut r = Rng { key: case, slot: 0 };
            let n = 6 + (r.next() * 3.0) as usize;
            let footholds: Vec<Vec2> = (0..n)
                .map(|_| Vec2::new(r.range(0.0, 3.0) as f32, r.range(0.0, 3.0) as f32))
                .collect();
            let gait = Gait {
                df_max: r.range(1.2, 1.8) as f32,
                max_change: r.range(0.2, 1.2) as f32,
            };
            let weights = Weights {
                p0: r.range(0.0, 5.0),
                n0: r.range(0.5, 3.0),
                p1: r.range(0.0, 5.0),
                n1: r.range(0.5, 3.0),
                p2: r.range(0.0, 5.0),
                n2: r.range(0.5, 3.0),
            };
            let (start, goal) = (0, n - 1);
            let facing = footholds[goal] - footholds[start];
            let best = exhaustive(&footholds, start, goal, facing, &gait, &weights);
            let p = plan(&footholds, start, goal, facing, &gait, &weights);
            match (best, p) {
                (None, None) => {}
                (Some(b), Some(p)) => {
                    found += 1;
                    assert!(
                        (b - p.cost).abs() <= 1e-9 * b.max(1.0),
                        "case {case}: exhaustive {b}, Dijkstra {}",
                        p.cost
                    );
                    check(&footholds, &p, start, goal, facing, &gait, &weights);
                }
                (b, p) => panic!("case {case}: exhaustive {b:?}, Dijkstra {p:?}"),
            }
        }
        // Most maps have a walk: the comparison is not vacuous.
        assert!(found > 100, "{found} walks in 200 maps");
    }

    #[test]
    fn straight_line_steps_on_every_stone() {
        let stones = line(12, 0.6);
        let (gait, weights) = (Gait::default(), Weights::default());
        let facing = stones[11] - stones[0];
        let p = plan(&stones, 0, 11, facing, &gait, &weights).unwrap();
        check(&stones, &p, 0, 11, facing, &gait, &weights);
        let all: Vec<usize> = (0..12).collect();
        assert_eq!(p.steps, walk(&all, &[]));
        // The thesis's first move: the Right foot.
        assert_eq!(p.steps[1].foot, Foot::Right);
    }

    /// Stones along x up to a corner, then along a direction `angle`
    /// away, 0.6 apart: (footholds, index of the corner).
    fn bend(angle: f32) -> (Vec<Vec2>, usize) {
        let mut stones = line(6, 0.6);
        let corner = stones[5];
        let dir = Vec2::from_angle(angle);
        stones.extend((1..6).map(|j| corner + dir * (0.6 * j as f32)));
        (stones, 5)
    }

    #[test]
    fn sharp_turn_halts_gentle_turn_does_not() {
        let (gait, weights) = (Gait::default(), Weights::default());
        for (angle, halts) in [
            (std::f32::consts::FRAC_PI_2, true),
            (15f32.to_radians(), false),
        ] {
            let (stones, corner) = bend(angle);
            let goal = stones.len() - 1;
            let facing = stones[goal] - stones[0];
            let p = plan(&stones, 0, goal, facing, &gait, &weights).unwrap();
            check(&stones, &p, 0, goal, facing, &gait, &weights);
            let order: Vec<usize> = (0..stones.len()).collect();
            let with_halt = walk(&order, &[corner]);
            let without = walk(&order, &[]);
            let (h, w) = (
                walk_cost(&stones, &with_halt, facing, &weights),
                walk_cost(&stones, &without, facing, &weights),
            );
            // Halting at the corner costs the halt (the step length 0.6
            // as speed change) and the restart (distance and speed
            // change 0.6) instead of a step (distance 0.6) turning by
            // the angle, 5·angle².
            let turn = 5.0 * f64::from(angle).powi(2);
            assert!((h - w - (0.6 + 1.2 - (0.6 + turn))).abs() < 1e-5, "{h} {w}");
            assert_eq!(h < w, halts, "angle {angle}: {h} vs {w}");
            let expected = if halts { with_halt } else { without };
            assert_eq!(p.steps, expected, "angle {angle}");
            assert!((p.cost - h.min(w)).abs() < 1e-9);
        }
    }

    #[test]
    fn gap_takes_the_detour_or_has_no_walk() {
        let mut stones = line(5, 0.6);
        // A gap of 1.4 > Df_max, then the far bank.
        stones.extend((0..4).map(|i| Vec2::new(3.8 + 0.6 * i as f32, 0.0)));
        let goal = stones.len() - 1;
        let (gait, weights) = (Gait::default(), Weights::default());
        let facing = stones[goal] - stones[0];
        assert_eq!(plan(&stones, 0, goal, facing, &gait, &weights), None);
        let detour = stones.len();
        stones.push(Vec2::new(3.1, 0.5));
        let p = plan(&stones, 0, goal, facing, &gait, &weights).unwrap();
        check(&stones, &p, 0, goal, facing, &gait, &weights);
        assert!(p.steps.iter().any(|s| s.current == detour));
    }

    #[test]
    fn a_gap_makes_a_halt_only_where_the_curvature_saving_outweighs_the_speed_change() {
        // A line 0.6 apart with the stone at x = 3 missing (a gap of 1.2 >
        // Df_max) and a stone beside the gap, `off` to the side: the walk
        // turns onto it and back. Each halt of the plan saves more turning
        // than it costs in speed change, and each stone it walks over
        // without halting would cost more with a halt.
        let (gait, weights) = (Gait::default(), Weights::default());
        let mut halted = Vec::new();
        for off in [0.15f32, 0.3, 0.5, 0.7] {
            let mut stones: Vec<Vec2> = (0..11)
                .filter(|&i| i != 5)
                .map(|i| Vec2::new(i as f32 * 0.6, 0.0))
                .collect();
            stones.push(Vec2::new(3.0, off));
            let side = stones.len() - 1;
            let goal = side - 1;
            let facing = stones[goal] - stones[0];
            let p = plan(&stones, 0, goal, facing, &gait, &weights).unwrap();
            check(&stones, &p, 0, goal, facing, &gait, &weights);
            let order: Vec<usize> = p
                .steps
                .iter()
                .filter(|s| !s.is_halt())
                .map(|s| s.current)
                .fold(vec![0], |mut o, c| {
                    o.push(c);
                    o
                });
            assert!(order.contains(&side), "{off}: {:?}", p.steps);
            let halts: Vec<usize> = p.steps[1..p.steps.len() - 1]
                .iter()
                .filter(|s| s.is_halt())
                .map(|s| s.current)
                .collect();
            for &k in &order[1..order.len() - 1] {
                let toggled: Vec<usize> = if halts.contains(&k) {
                    halts.iter().copied().filter(|&h| h != k).collect()
                } else {
                    halts.iter().copied().chain([k]).collect()
                };
                let other = walk(&order, &toggled);
                let feasible = other
                    .windows(2)
                    .all(|w| allowed(&stones, &w[0], &w[1], &gait));
                if feasible {
                    let c = walk_cost(&stones, &other, facing, &weights);
                    assert!(
                        c >= p.cost - 1e-9,
                        "{off}: toggling {k} costs {c} < {}",
                        p.cost
                    );
                }
            }
            halted.push(!halts.is_empty());
        }
        // A small side step is taken in stride; a wide one halts.
        assert_eq!(halted.first(), Some(&false), "{halted:?}");
        assert_eq!(halted.last(), Some(&true), "{halted:?}");
    }

    #[test]
    fn deterministic() {
        let (stones, _) = bend(1.0);
        let goal = stones.len() - 1;
        let facing = stones[goal] - stones[0];
        let run = || {
            let (gait, weights) = (Gait::default(), Weights::default());
            plan(&stones, 0, goal, facing, &gait, &weights)
        };
        let a = run();
        assert!(a.is_some());
        assert_eq!(a, run());
    }

    #[test]
    fn start_on_goal_is_the_start() {
        let stones = line(3, 0.6);
        let p = plan(
            &stones,
            1,
            1,
            Vec2::X,
            &Gait::default(),
            &Weights::default(),
        )
        .unwrap();
        assert_eq!(p.steps, vec![start_of(1)]);
        assert_eq!(p.cost, 0.0);
    }

    #[test]
    fn refuses_bad_inputs() {
        let mut stones = line(3, 0.6);
        let (g, w) = (Gait::default(), Weights::default());
        assert_eq!(plan(&stones, 0, 3, Vec2::X, &g, &w), None);
        assert_eq!(plan(&stones, 0, 2, Vec2::NAN, &g, &w), None);
        let neg = Weights { p2: -1.0, ..w };
        assert_eq!(plan(&stones, 0, 2, Vec2::X, &g, &neg), None);
        let flat = Gait { df_max: 0.0, ..g };
        assert_eq!(plan(&stones, 0, 2, Vec2::X, &flat, &w), None);
        assert!(plan(&stones, 0, 2, Vec2::X, &g, &w).is_some());
        stones[1].x = f32::INFINITY;
        assert_eq!(plan(&stones, 0, 2, Vec2::X, &g, &w), None);
    }

    #[test]
    fn zero_bases_cost_nothing() {
        // n = 0: a halt's zero distance and a straight step's zero turn
        // and speed change add nothing.
        let stones = line(3, 0.6);
        let w = Weights {
            p0: 1.0,
            n0: 0.0,
            p1: 1.0,
            n1: 0.0,
            p2: 1.0,
            n2: 0.0,
        };
        let a = Step {
            previous: 0,
            current: 1,
            foot: Foot::Right,
        };
        let halt = Step {
            previous: 1,
            current: 1,
            foot: Foot::Left,
        };
        let straight = Step {
            previous: 1,
            current: 2,
            foot: Foot::Left,
        };
        // The halt changes the step length 0.6 → 0: only that term.
        assert_eq!(cost(&stones, &a, &halt, None, &w), 1.0);
        // A straight step: only the distance.
        assert_eq!(cost(&stones, &a, &straight, None, &w), 1.0);
    }
}
