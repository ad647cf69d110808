//! The path search of a navigating actor (thesis 5.2.1–5.2.2): the
//! heuristic depth-first search of Algorithm 1 over the free voxels of
//! its visual memory, then Algorithms 2–4, which widen that path into a
//! corridor (the "pathOctree") and take the shortest path through it.
//!
//! Voxels are search voxels: `2^rel_search_level` memory voxels on a side
//! ([`SearchGrid`]). Everything here is a pure function of the memory,
//! the end points and the heuristic: the treated set, the corridor and
//! the candidate lists of a plan are hash maps (Fx, fixed keys) only
//! looked up, never iterated for a result, and every tie is broken by the
//! heuristic's candidate order, so the same call gives the same path on
//! any machine and thread count (DESIGN §4).

use std::collections::VecDeque;

use rustc_hash::{FxHashMap, FxHashSet};

use super::heuristics::{candidates, Heuristic};
use crate::actors::perception::octree::{Octree, Voxel};

/// The label of a corridor voxel Algorithm 3 has not reached.
pub const MAX_LABEL: u32 = u32::MAX;

/// An entry of Algorithm 1's candidate list: a candidate, or the label
/// "new_neighbours" that opens the candidates of one path voxel.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Entry {
    NewNeighbours,
    Candidate(Voxel),
}

/// What the explorer does next.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ExplorerStep {
    /// Go to this voxel: the next candidate, or one voxel back along the
    /// path when every candidate of the last one failed (backtracking).
    Go(Voxel),
    /// The path reaches the end voxel.
    Arrived,
    /// Every voxel the heuristic can reach from the start was tried: no
    /// path to the end exists under this heuristic.
    Enclosed,
}

/// Algorithm 1 one voxel at a time, so that the explore mode (5.2.2) can
/// walk it for real while the memory fills: the candidates of a path
/// voxel are taken when it is reached, with the memory of that moment.
#[derive(Debug, Clone)]
pub struct Explorer<'h> {
    heuristic: &'h Heuristic,
    end: Voxel,
    path: Vec<Voxel>,
    cand_list: Vec<Entry>,
    /// The already_treated list (membership only, never iterated).
    treated: FxHashSet<Voxel>,
    /// Voxels added to the path so far, backtracking included.
    visited: usize,
    /// The last path voxel's candidates are still to be added.
    pending: bool,
}

impl<'h> Explorer<'h> {
    /// The search from `start` to `end`: `add_path(start)`; the start is
    /// treated, so no candidate list brings it back.
    pub fn new(heuristic: &'h Heuristic, start: Voxel, end: Voxel) -> Self {
        Explorer {
            heuristic,
            end,
            path: vec![start],
            cand_list: Vec::new(),
            treated: FxHashSet::from_iter([start]),
            visited: 1,
            pending: true,
        }
    }

    /// The heuristic it searches with.
    pub fn heuristic(&self) -> &'h Heuristic {
        self.heuristic
    }

    /// The path so far, start first.
    pub fn path(&self) -> &[Voxel] {
        &self.path
    }

    /// Voxels added to the path so far (the start included).
    pub fn visited(&self) -> usize {
        self.visited
    }

    /// One move of Algorithm 1. `is_empty` says whether a voxel is free
    /// now (false past the grid); a candidate found occupied when its
    /// turn comes (the memory filled meanwhile) is skipped.
    pub fn step(&mut self, is_empty: impl FnMut(Voxel) -> bool) -> ExplorerStep {
        self.step_in(&mut Fresh {
            h: self.heuristic,
            is_empty,
        })
    }

    /// [`step`](Self::step) with the candidate lists and the voxels of
    /// `ask`.
    fn step_in(&mut self, ask: &mut impl Ask) -> ExplorerStep {
        loop {
            let Some(&last) = self.path.last() else {
                return ExplorerStep::Enclosed;
            };
            if last == self.end {
                return ExplorerStep::Arrived;
            }
            if self.pending {
                self.pending = false;
                let listed = ask.candidates(last);
                self.add_candidates(listed);
            }
            // get_next_candidate: each label on top closes a path voxel
            // whose candidates all failed.
            match self.cand_list.pop() {
                None => return ExplorerStep::Enclosed,
                Some(Entry::NewNeighbours) => {
                    self.path.pop();
                    return match self.path.last() {
                        Some(&back) => ExplorerStep::Go(back),
                        None => ExplorerStep::Enclosed,
                    };
                }
                Some(Entry::Candidate(c)) => {
                    if !ask.is_empty(c) {
                        continue;
                    }
                    self.path.push(c);
                    self.visited += 1;
                    self.pending = true;
                    return ExplorerStep::Go(c);
                }
            }
        }
    }

    /// The last path voxel, not reached yet, turned out occupied: it
    /// leaves the path, and the voxel before it is the one to go back to
    /// (its other candidates come next).
    pub fn retreat(&mut self) -> Option<Voxel> {
        if self.path.len() > 1 {
            self.path.pop();
            self.pending = false;
        }
        self.path.last().copied()
    }

    /// Whether the last path voxel, just reached, has no candidate with
    /// the memory as it is now, so that the next step would walk back.
    /// Takes its candidates (what the next step would do first); false
    /// for a voxel walked back to, whose candidates were taken before,
    /// and at the end.
    pub fn dead_end(&mut self, mut is_empty: impl FnMut(Voxel) -> bool) -> bool {
        let Some(&last) = self.path.last() else {
            return false;
        };
        if !self.pending || last == self.end {
            return false;
        }
        self.pending = false;
        self.add_candidates(candidates(self.heuristic, last, &mut is_empty));
        self.cand_list.last() == Some(&Entry::NewNeighbours)
    }

    /// At a [`dead_end`](Self::dead_end): its label is dropped, so that
    /// the next step takes the last path voxel's candidates again, with
    /// the memory as it will be then (after the actor has looked around).
    pub fn reopen(&mut self) {
        if self.cand_list.last() == Some(&Entry::NewNeighbours) {
            self.cand_list.pop();
            self.pending = true;
        }
    }

    /// add_candidates_to_candList: the heuristic's candidates `x` of the
    /// last path voxel not yet treated, after the label, the nearest to
    /// the end on top (so tried first); equal distances keep the table's
    /// order.
    fn add_candidates(&mut self, mut x: Vec<Voxel>) {
        x.retain(|c| !self.treated.contains(c));
        x.sort_by_key(|c| distance2(*c, self.end));
        self.cand_list.push(Entry::NewNeighbours);
        for &c in x.iter().rev() {
            self.treated.insert(c);
            self.cand_list.push(Entry::Candidate(c));
        }
    }
}

/// What the algorithms ask of the memory: a voxel's candidates under the
/// heuristic, and whether a voxel is free.
trait Ask {
    fn candidates(&mut self, v: Voxel) -> Vec<Voxel>;
    fn is_empty(&mut self, v: Voxel) -> bool;
}

/// Asks the memory each time (the explore mode: it fills meanwhile).
struct Fresh<'h, F> {
    h: &'h Heuristic,
    is_empty: F,
}

impl<F: FnMut(Voxel) -> bool> Ask for Fresh<'_, F> {
    fn candidates(&mut self, v: Voxel) -> Vec<Voxel> {
        candidates(self.h, v, &mut self.is_empty)
    }

    fn is_empty(&mut self, v: Voxel) -> bool {
        (self.is_empty)(v)
    }
}

/// Asks the memory once per voxel for its candidates: during one plan
/// the memory does not change, and Algorithms 2–4 ask again for most of
/// the voxels Algorithm 1 met (a list per voxel is cheaper to look up
/// than the dozen voxels it is made of; docs/performance.md).
struct Memo<'h, F> {
    fresh: Fresh<'h, F>,
    lists: FxHashMap<Voxel, Vec<Voxel>>,
}

impl<F: FnMut(Voxel) -> bool> Ask for Memo<'_, F> {
    fn candidates(&mut self, v: Voxel) -> Vec<Voxel> {
        if let Some(x) = self.lists.get(&v) {
            return x.clone();
        }
        let x = self.fresh.candidates(v);
        self.lists.insert(v, x.clone());
        x
    }

    fn is_empty(&mut self, v: Voxel) -> bool {
        self.fresh.is_empty(v)
    }
}

/// The squared distance between two voxels, in voxels².
fn distance2(a: Voxel, b: Voxel) -> u64 {
    (0..3)
        .map(|i| {
            let d = i64::from(a[i]) - i64::from(b[i]);
            (d * d) as u64
        })
        .sum()
}

/// Why a plan found no path.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NoPlan {
    /// The start or the end lies outside the memory's cube.
    Outside,
    /// The end voxel is occupied: no candidate could reach it.
    Occupied,
    /// Algorithm 1 exhausted the space it could reach under the
    /// heuristic: no way exists.
    NoWay,
    /// Algorithm 1 added more voxels to its path than it may (the limit
    /// `--max-plan-voxels`): the search gave up, a way may exist.
    TooLong { visited: usize },
}

/// Runs `e` to its end: an error when no path exists or more than
/// `max_visited` voxels were added to the path (the search gives up).
fn run(e: &mut Explorer, ask: &mut impl Ask, max_visited: usize) -> Result<(), NoPlan> {
    loop {
        match e.step_in(ask) {
            ExplorerStep::Arrived => return Ok(()),
            ExplorerStep::Enclosed => return Err(NoPlan::NoWay),
            ExplorerStep::Go(_) if e.visited() > max_visited => {
                return Err(NoPlan::TooLong {
                    visited: e.visited(),
                })
            }
            ExplorerStep::Go(_) => {}
        }
    }
}

/// Algorithm 1: a path from `start` to `end` under heuristic `h` (each
/// voxel a candidate of the one before), None when there is none or the
/// search adds more than `max_visited` voxels to its path.
pub fn search(
    h: &Heuristic,
    start: Voxel,
    end: Voxel,
    is_empty: impl FnMut(Voxel) -> bool,
    max_visited: usize,
) -> Option<Vec<Voxel>> {
    let mut e = Explorer::new(h, start, end);
    run(&mut e, &mut Fresh { h, is_empty }, max_visited).ok()?;
    Some(e.path)
}

/// The corridor of Algorithms 2–4: voxel → label.
pub type Corridor = FxHashMap<Voxel, u32>;

/// Algorithm 2: the path voxels and their candidates under `h`, each
/// labelled [`MAX_LABEL`].
pub fn extend(h: &Heuristic, path: &[Voxel], is_empty: impl FnMut(Voxel) -> bool) -> Corridor {
    extend_in(path, &mut Fresh { h, is_empty })
}

fn extend_in(path: &[Voxel], ask: &mut impl Ask) -> Corridor {
    let mut corridor = Corridor::default();
    for &v in path {
        corridor.insert(v, MAX_LABEL);
        for c in ask.candidates(v) {
            corridor.insert(c, MAX_LABEL);
        }
    }
    corridor
}

/// Algorithm 3: labels each corridor voxel with its distance from
/// `start` (unit arcs, breadth first). An arc goes from u to each of its
/// candidates under `h` inside the corridor, so a labelled path obeys the
/// heuristic's conditions as Algorithm 1's did.
pub fn label(
    h: &Heuristic,
    corridor: &mut Corridor,
    start: Voxel,
    is_empty: impl FnMut(Voxel) -> bool,
) {
    label_in(corridor, start, &mut Fresh { h, is_empty });
}

fn label_in(corridor: &mut Corridor, start: Voxel, ask: &mut impl Ask) {
    let Some(l) = corridor.get_mut(&start) else {
        return;
    };
    *l = 0;
    let mut queue = VecDeque::from([(start, 0)]);
    while let Some((u, d)) = queue.pop_front() {
        for w in ask.candidates(u) {
            if let Some(l) = corridor.get_mut(&w) {
                if *l == MAX_LABEL {
                    *l = d + 1;
                    queue.push_back((w, d + 1));
                }
            }
        }
    }
}

/// Algorithm 4: the shortest path from the start (label 0) to `end`,
/// walking back from `end` to the neighbour of least label; the
/// neighbours of x are the corridor voxels with an arc into x, in the
/// table's order, the first of least label winning. None when
/// Algorithm 3 did not reach `end`.
pub fn shortest(
    h: &Heuristic,
    corridor: &Corridor,
    end: Voxel,
    is_empty: impl FnMut(Voxel) -> bool,
) -> Option<Vec<Voxel>> {
    shortest_in(h, corridor, end, &mut Fresh { h, is_empty })
}

fn shortest_in(
    h: &Heuristic,
    corridor: &Corridor,
    end: Voxel,
    ask: &mut impl Ask,
) -> Option<Vec<Voxel>> {
    let mut x = end;
    let mut lx = *corridor.get(&end).filter(|&&l| l != MAX_LABEL)?;
    let mut path = vec![x];
    while lx != 0 {
        // Algorithm 3 reached x from a voxel labelled lx − 1 with an arc
        // into x, and none with an arc has less: min_label(S) is the
        // first voxel of label lx − 1 with an arc into x, so only those
        // are asked for their candidates. None would be a broken corridor.
        let y = h.tested.iter().find_map(|&(n, _)| {
            let y = offset(x, h.numbering[usize::from(n) - 1].map(|c| -c))?;
            (corridor.get(&y) == Some(&(lx - 1)) && ask.candidates(y).contains(&x)).then_some(y)
        })?;
        path.push(y);
        (x, lx) = (y, lx - 1);
    }
    path.reverse();
    Some(path)
}

/// v + d, None below the grid.
fn offset(v: Voxel, d: [i32; 3]) -> Option<Voxel> {
    let mut out = [0u32; 3];
    for i in 0..3 {
        out[i] = u32::try_from(i64::from(v[i]) + i64::from(d[i])).ok()?;
    }
    Some(out)
}

/// The result of [`plan_voxels`].
#[derive(Debug, Clone, PartialEq)]
pub struct Planned {
    /// Algorithm 1's path.
    pub searched: Vec<Voxel>,
    /// Algorithm 4's path, start first.
    pub path: Vec<Voxel>,
    /// Voxels Algorithm 1 added to its path, backtracking included.
    pub visited: usize,
    /// Voxels of the corridor (those Algorithm 3 labels at most).
    pub corridor: usize,
}

/// Algorithms 1 → 2 → 3 → 4 on search voxels; None when Algorithm 1
/// finds no path within `max_visited`.
pub fn plan_voxels(
    h: &Heuristic,
    start: Voxel,
    end: Voxel,
    is_empty: impl FnMut(Voxel) -> bool,
    max_visited: usize,
) -> Option<Planned> {
    plan_in(h, start, end, is_empty, max_visited).ok()
}

/// [`plan_voxels`], saying why no path was found.
fn plan_in(
    h: &Heuristic,
    start: Voxel,
    end: Voxel,
    is_empty: impl FnMut(Voxel) -> bool,
    max_visited: usize,
) -> Result<Planned, NoPlan> {
    let mut ask = Memo {
        fresh: Fresh { h, is_empty },
        lists: FxHashMap::default(),
    };
    let mut e = Explorer::new(h, start, end);
    run(&mut e, &mut ask, max_visited)?;
    let mut corridor = extend_in(e.path(), &mut ask);
    label_in(&mut corridor, start, &mut ask);
    // Algorithm 1's path lies in the corridor: Algorithm 4 finds one.
    let path = shortest_in(h, &corridor, end, &mut ask).ok_or(NoPlan::NoWay)?;
    Ok(Planned {
        visited: e.visited(),
        searched: e.path,
        path,
        corridor: corridor.len(),
    })
}

/// The search voxels over a visual memory: `2^level` memory voxels on a
/// side (`rel_search_level`, appendix G), empty when all of them are.
///
/// A planar search may stand on a [`Band`]: its layers are then laid
/// around the ground instead of from the cube's floor, so that the floor
/// is never in the layer the actor walks in, whatever the eye's height
/// and the voxel sizes (docs/actors.md, "The ground of a planar search").
#[derive(Debug, Clone, Copy)]
pub struct SearchGrid<'a> {
    memory: &'a Octree,
    level: u32,
    /// Search voxels along an edge.
    edge: u32,
    band: Option<Band>,
}

/// The layers of a planar search laid on the ground (memory layers,
/// `lo..hi` half-open): the actor's layer from just above the ground to
/// its eye, the ground's layer under it; the others are `2^level` memory
/// layers thick, upward from the actor's and downward from the ground's.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Band {
    /// The search layer the actor walks in.
    pub layer: u32,
    /// Its memory layers: from just above the ground to the eye's.
    pub lo: u32,
    pub hi: u32,
    /// The lowest memory layer of the ground's search layer (`layer` −
    /// 1), which ends at `lo`.
    pub ground: u32,
    /// The memory layer holding most of the ground.
    pub floor: u32,
    /// The eye's memory layer: the actor's search layer, even when it
    /// lies in the ground's (an eye less than a voxel over the ground).
    pub eye: u32,
}

impl Band {
    /// The band of an eye in memory layer `eye` over ground whose full
    /// voxels lie in memory layers `ground_lo..=ground_hi` (a surface on a
    /// layer boundary fills two), most in `floor`, for search voxels of
    /// `side` layers.
    pub fn new(eye: u32, (ground_lo, floor, ground_hi): (u32, u32, u32), side: u32) -> Band {
        // An eye in the ground's own layer cannot tell the ground from
        // what stands on it there: its layer begins over the ground.
        let lo = ground_hi + 1;
        let hi = (eye + 1).max(lo + side);
        let ground = ground_lo.min(lo.saturating_sub(side));
        Band {
            layer: ground.div_ceil(side) + 1,
            lo,
            hi,
            ground,
            floor,
            eye,
        }
    }
}

impl<'a> SearchGrid<'a> {
    /// The grid of `memory` at `rel_search_level` (at most the memory's
    /// levels: one search voxel then covers the whole cube).
    pub fn new(memory: &'a Octree, rel_search_level: u32) -> Self {
        let level = rel_search_level.min(memory.levels());
        let edge = memory.voxels_per_edge().div_ceil(1 << level);
        SearchGrid {
            memory,
            level,
            edge,
            band: None,
        }
    }

    /// The grid with its layers laid on `band` (None: from the cube's
    /// floor).
    pub fn on(self, band: Option<Band>) -> Self {
        SearchGrid { band, ..self }
    }

    /// Search voxels along an edge of the cube.
    pub fn edge(&self) -> u32 {
        self.edge
    }

    /// Memory layers a search voxel is thick.
    fn side(&self) -> u32 {
        1 << self.level
    }

    /// The memory layers (half-open) of search layer j; empty past the
    /// cube.
    fn layers(&self, j: u32) -> (u32, u32) {
        let side = self.side();
        let limit = self.memory.voxels_per_edge();
        let (lo, hi) = match self.band {
            None => (
                j.saturating_mul(side),
                j.saturating_add(1).saturating_mul(side),
            ),
            Some(b) if j == b.layer => (b.lo, b.hi),
            Some(b) if j == b.layer - 1 => (b.ground, b.lo),
            Some(b) if j > b.layer => {
                let k = j - b.layer;
                (
                    b.hi.saturating_add((k - 1).saturating_mul(side)),
                    b.hi.saturating_add(k.saturating_mul(side)),
                )
            }
            Some(b) => {
                // Below the ground's layer: k layers under it.
                let k = b.layer - 1 - j;
                let top = i64::from(b.ground) - i64::from((k - 1) * side);
                let bottom = top - i64::from(side);
                (bottom.max(0) as u32, top.max(0) as u32)
            }
        };
        (lo.min(limit), hi.min(limit))
    }

    /// The search layer holding memory layer m.
    fn layer_of(&self, m: u32) -> u32 {
        let side = self.side();
        match self.band {
            None => m >> self.level,
            Some(b) if m >= b.hi => b.layer + 1 + (m - b.hi) / side,
            Some(b) if m >= b.lo || m == b.eye => b.layer,
            Some(b) if m >= b.ground => b.layer - 1,
            Some(b) => b.layer - 2 - (b.ground - 1 - m) / side,
        }
    }

    /// The search voxel holding world point p, None outside the cube.
    pub fn voxel(&self, p: [f64; 3]) -> Option<Voxel> {
        self.memory
            .voxel(p)
            .map(|v| [v[0] >> self.level, self.layer_of(v[1]), v[2] >> self.level])
    }

    /// The world centre of search voxel v.
    pub fn centre(&self, v: Voxel) -> [f64; 3] {
        let cube = self.memory.cube();
        let side = f64::from(self.side());
        let (lo, hi) = self.layers(v[1]);
        let at = |c: u32| cube.min + (f64::from(c) + 0.5) * side * cube.voxel_edge;
        let y = cube.min + f64::from(lo + hi) / 2.0 * cube.voxel_edge;
        [at(v[0]), y, at(v[2])]
    }

    /// Whether no memory voxel of v is occupied; false past the cube
    /// (the cube's faces are walls to the search).
    pub fn is_empty(&self, v: Voxel) -> bool {
        let (y0, y1) = self.layers(v[1]);
        if v[0] >= self.edge || v[2] >= self.edge || y0 >= y1 {
            return false;
        }
        let limit = self.memory.voxels_per_edge();
        let range = |c: u32| (c << self.level)..((c + 1) << self.level).min(limit);
        range(v[0])
            .all(|x| (y0..y1).all(|y| range(v[2]).all(|z| self.memory.get([x, y, z]).is_none())))
    }
}

/// The path from `start` to `end` (world points) through the free voxels
/// of the memory octree under heuristic `h`, at `rel_search_level`: see
/// [`plan_on`].
pub fn plan(
    memory: &Octree,
    start: [f64; 3],
    end: [f64; 3],
    h: &Heuristic,
    rel_search_level: u32,
    max_visited: usize,
) -> Result<Vec<[f64; 3]>, NoPlan> {
    plan_on(
        &SearchGrid::new(memory, rel_search_level),
        start,
        end,
        h,
        max_visited,
    )
}

/// The path from `start` to `end` (world points) through the free search
/// voxels of `grid` under heuristic `h`, as the world centres of its
/// search voxels, start first: Algorithm 1 (giving up past `max_visited`
/// voxels), then Algorithms 2–4. An error when an end point is outside
/// the cube, the end voxel is occupied (no candidate could reach it: the
/// search would only exhaust the space), no path exists under `h`, or
/// the search gave up.
pub fn plan_on(
    grid: &SearchGrid,
    start: [f64; 3],
    end: [f64; 3],
    h: &Heuristic,
    max_visited: usize,
) -> Result<Vec<[f64; 3]>, NoPlan> {
    let (Some(s), Some(e)) = (grid.voxel(start), grid.voxel(end)) else {
        return Err(NoPlan::Outside);
    };
    if s != e && !grid.is_empty(e) {
        return Err(NoPlan::Occupied);
    }
    let planned = plan_in(h, s, e, |v| grid.is_empty(v), max_visited)?;
    Ok(planned.path.iter().map(|&v| grid.centre(v)).collect())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::actors::perception::octree::Cube;
    use crate::actors::planning::heuristics::heuristic;

    /// The nearest candidate to the aim goes first; equal distances keep
    /// the table's order (1 = +x before 4 = +z); the candidate list holds
    /// a label before each voxel's candidates.
    #[test]
    fn candidates_nearest_first_ties_in_table_order() {
        let h = heuristic(0).unwrap();
        let open = |v: Voxel| v[1] == 0 && v[0] < 8 && v[2] < 8;
        let mut e = Explorer::new(h, [3, 0, 3], [3, 0, 0]);
        assert_eq!(e.step(open), ExplorerStep::Go([3, 0, 2]));
        let mut e = Explorer::new(h, [3, 0, 3], [6, 0, 6]);
        assert_eq!(e.step(open), ExplorerStep::Go([4, 0, 3]));
        // The start's label, then its other candidates, farthest lowest
        // (the table's order reversed among equals).
        let c = Entry::Candidate;
        assert_eq!(
            e.cand_list,
            [
                Entry::NewNeighbours,
                c([2, 0, 3]),
                c([3, 0, 2]),
                c([3, 0, 4])
            ]
        );
        // The next step opens the candidates of [4, 0, 3] with a label.
        assert_eq!(e.step(open), ExplorerStep::Go([4, 0, 4]));
        assert_eq!(e.cand_list[4], Entry::NewNeighbours);
        assert_eq!(e.visited(), 3);
    }

    /// The U-trap of issue 36 in small: a floor in memory layer 2 (y
    /// 1..1.5), an eye in layer 3. Laid from the cube's floor, the eye's
    /// search layer (memory layers 2, 3) holds the floor: no way. Laid on
    /// the ground, the actor's layer runs from just above the floor to
    /// its eye, and the floor is its support.
    #[test]
    fn a_planar_search_laid_on_the_ground() {
        let mut m = Octree::new(Cube::new(0.0, 8.0, 0.5), false);
        for x in 0..16 {
            for z in 0..16 {
                m.insert([x, 2, z], 1);
            }
        }
        let (a, b) = ([1.2, 1.6, 1.2], [6.2, 1.6, 6.2]);
        let h1 = heuristic(1).unwrap();
        assert_eq!(
            plan_on(&SearchGrid::new(&m, 1), a, b, h1, 10_000),
            Err(NoPlan::Occupied)
        );
        let band = Band::new(3, (2, 2, 2), 2);
        assert_eq!(
            band,
            Band {
                layer: 2,
                lo: 3,
                hi: 5,
                ground: 1,
                floor: 2,
                eye: 3
            }
        );
        let grid = SearchGrid::new(&m, 1).on(Some(band));
        assert_eq!(grid.voxel(a), Some([1, 2, 1]));
        assert!(grid.is_empty([1, 2, 1]) && !grid.is_empty([1, 1, 1]));
        assert_eq!(grid.centre([1, 2, 1])[1], 2.0);
        assert!(plan_on(&grid, a, b, h1, 10_000).is_ok());
        // A search that may add fewer voxels than the way is long gives up.
        assert_eq!(
            plan_on(&grid, a, b, h1, 5),
            Err(NoPlan::TooLong { visited: 6 })
        );
        // Heuristic 7 walks on it: the floor is under every voxel.
        let h7 = heuristic(7).unwrap();
        assert!(plan_on(&grid, a, b, h7, 10_000).is_ok());
        // A low wall across the room, from the floor up to half the
        // eye's height, bars the way.
        for z in 0..16 {
            m.insert([8, 3, z], 1);
        }
        let grid = SearchGrid::new(&m, 1).on(Some(band));
        assert_eq!(plan_on(&grid, a, b, h1, 10_000), Err(NoPlan::NoWay));
        // Layers over and under the band are a search voxel thick.
        assert_eq!(grid.layers(3), (5, 7));
        assert_eq!(grid.layers(0), (0, 1));
        assert_eq!(grid.layer_of(6), 3);
        assert_eq!(grid.layer_of(0), 0);
    }

    /// A search voxel of level 1 is empty only when its eight memory
    /// voxels are; past the cube it is occupied.
    #[test]
    fn search_voxels_at_a_relative_level() {
        let mut m = Octree::new(Cube::new(0.0, 8.0, 1.0), false);
        m.insert([3, 1, 2], 1);
        let g = SearchGrid::new(&m, 1);
        assert!(!g.is_empty([1, 0, 1]));
        assert!(g.is_empty([1, 0, 0]) && g.is_empty([0, 0, 1]));
        assert!(!g.is_empty([4, 0, 0]));
        assert_eq!(g.voxel([3.5, 1.5, 2.5]), Some([1, 0, 1]));
        assert_eq!(g.centre([1, 0, 1]), [3.0, 1.0, 3.0]);
        let g0 = SearchGrid::new(&m, 0);
        assert!(!g0.is_empty([3, 1, 2]) && g0.is_empty([2, 1, 2]));
        // A level past the memory's is its whole cube.
        assert!(!SearchGrid::new(&m, 9).is_empty([0, 0, 0]));
    }
}
