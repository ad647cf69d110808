//! The navigation automata `walk_continuously` (thesis 5.2.4): the states
//! search_new_path and move. Searching pops a goal from the goal stack
//! and plans a path through the free voxels of the actor's visual memory
//! (Algorithms 1–4, [`crate::actors::planning::path`]); moving follows the path spline
//! through its key points ([`crate::actors::planning::spline`], shaped by `inertia`) at
//! `speed`, and tests the next `ahead` key points with the
//! `coll_test_func` heuristic against the memory as vision updates it,
//! searching again when one is blocked.
//! Every `optim_rate` frames it walks straight to the last of the next
//! `optim_ahead` key points it sees clearly (Algorithm 5).
//! With no path it pushes itself and observes (5.3); still without one it
//! explores (5.2.2): Algorithm 1 walked for real, voxel by voxel, while
//! the memory fills, until it reaches the goal or knows it is enclosed.

use glam::Vec3;

use super::behaviour::Behaviour;
use super::footholds::map::{ground_layers, Region};
use crate::actors::perception::memory::DepthView;
use crate::actors::perception::octree::{Octree, Voxel};
use crate::actors::perception::vision::{Pixel, Window};
use crate::actors::planning::heuristics::{self, collision_free, Heuristic};
use crate::actors::planning::path::{self, Band, Explorer, ExplorerStep, NoPlan, SearchGrid};
use crate::actors::planning::spline::{self, Piece};
use crate::lsys::automata::Automata;
use crate::lsys::Limits;

mod guard;
mod walk_continuously;

/// How an actor navigates, as its automata commands set it (table B6:
/// `heuristic`, `coll_test_func`, `rel_search_level`, `ahead`, `inertia`,
/// `optim_rate`, `optim_ahead`) and the film's limits bound it.
#[derive(Debug, Clone)]
pub struct Tuning {
    /// The search and the collision test heuristics (table G.1).
    pub heuristic: i64,
    pub coll_test_func: i64,
    /// Search voxels of 2^level memory voxels a side.
    pub rel_search_level: u32,
    /// Key points of the path tested for collisions.
    pub ahead: i64,
    pub inertia: f32,
    /// Algorithm 5 every `optim_rate` frames (0: never) over the next
    /// `optim_ahead` key points.
    pub optim_rate: i64,
    pub optim_ahead: i64,
    /// Most voxels one of its path searches may add to its path
    /// ([`Limits::plan_voxels`]).
    pub max_plan_voxels: usize,
    /// It plays on an open court (a tennis player runs to its place):
    /// it walks without a memory and its view is not checked.
    pub open_court: bool,
}

impl Default for Tuning {
    /// The thesis's defaults.
    fn default() -> Tuning {
        Tuning {
            heuristic: 1,
            coll_test_func: 3,
            rel_search_level: 1,
            ahead: 3,
            inertia: 0.0,
            optim_rate: 0,
            optim_ahead: 5,
            max_plan_voxels: Limits::default().plan_voxels,
            open_court: false,
        }
    }
}

/// What a navigating actor keeps between frames.
#[derive(Debug, Clone, Default)]
pub struct Navigation {
    pub tuning: Tuning,
    /// The planned path's key points ahead, first next.
    pub path: Vec<Vec3>,
    /// The goal it walks to, popped from the goal stack.
    pub destination: Option<Vec3>,
    /// The unit direction it walks in (zero standing).
    pub heading: Vec3,
    /// The path spline's piece it walks along, and how far it is on it.
    pub piece: Option<Piece>,
    pub travelled: f32,
    /// Searches in a row without a path.
    pub failures: u32,
    /// The explore mode's search, and the voxel centre it walks to.
    pub explorer: Option<Explorer<'static>>,
    pub target: Option<Vec3>,
    /// Frames since the last local optimisation (Algorithm 5).
    pub since_optimised: i64,
    /// The explorer's last voxel was a dead end and the actor has looked
    /// around there: its candidates are taken once more, then it walks on.
    pub looked_around: bool,
    /// The layers of a planar search laid on the ground it saw, fixed
    /// from a search to the next (the explorer's voxels are of this grid).
    pub band: Option<Band>,
    /// Where it stood when it last moved, and how long it has not moved
    /// on from there while heading for a goal.
    pub still_at: Vec3,
    pub still_for: f32,
    /// Times it left the explore mode for a plan on its memory, for this
    /// destination: a memory that keeps forgetting a wall it sees at a
    /// grazing angle would otherwise send it round for ever.
    pub detours: u32,
}

/// Plans it may leave the explore mode for, per destination; past them
/// it explores to the end (5.2.2), which settles whether a way exists.
const MAX_DETOURS: u32 = 3;

/// Most points `turtle 3` shows of a path: a path thousands of voxels
/// long is dotted more sparsely, so the display's cost stays bounded (a
/// path of 700,000 voxels drew 1.4 M spheres a frame, issue 43).
const MAX_SHOWN: usize = 2048;

/// Fewest search voxels along the memory cube's edge a plan can find a
/// way round anything in: with fewer, one obstacle fills a search voxel
/// as wide as a third of the world.
const MIN_SEARCH_EDGE: u32 = 4;

/// Seconds a navigating actor may head for a goal without moving on by
/// half a search voxel before it notices it is stuck.
const STUCK_SECONDS: f32 = 3.0;

/// The radius of the ground a planar search looks for under the eye, in
/// search voxels.
const GROUND_RANGE: f32 = 32.0;

/// Whether heuristic `h` searches in the horizontal plane of the start
/// (its candidates all have dy = 0): then the path keeps the eye's height.
fn planar(h: &Heuristic) -> bool {
    h.tested
        .iter()
        .all(|&(n, _)| h.numbering[usize::from(n) - 1][1] == 0)
}

/// Whether heuristic `h` asks some voxel to be occupied (a support):
/// then unseen ground bars its way as a hole would.
fn needs_support(h: &Heuristic) -> bool {
    h.tested.iter().any(|&(_, c)| c.contains('!'))
}

/// Whether beside search voxel `v` (one of its four horizontal
/// neighbours) the memory holds nothing at its level nor in the two
/// voxels under it: ground not yet seen, or a drop the actor cannot tell
/// from it.
fn ground_unseen_beside(grid: &SearchGrid, v: Voxel) -> bool {
    [[1, 0], [0, -1], [-1, 0], [0, 1]].iter().any(|&[dx, dz]| {
        let (Some(x), Some(z)) = (v[0].checked_add_signed(dx), v[2].checked_add_signed(dz)) else {
            return false;
        };
        (0..3).all(|k| {
            v[1].checked_sub(k)
                .is_some_and(|y| grid.is_empty([x, y, z]))
        })
    })
}

/// Algorithm 5's test of key point `p` in the last window: it projects
/// into the window with nothing in front of it, and no pixel of its row
/// or column that shows something nearer than `p` lies within the
/// actor's size (`size_actor` in pixels at that pixel's depth) of it.
fn clearly_visible(window: &Window, view: &DepthView, p: Vec3, size: f32) -> bool {
    let Some(((x, y), d)) = view.project(p) else {
        return false;
    };
    if window.pixel(x, y).distance < d {
        return false;
    }
    let near = |q: &Pixel, offset: u32| {
        q.distance < d && (offset as f32) < size / window.footprint(q.depth)
    };
    (0..window.edge).all(|k| {
        !near(window.pixel(k, y), k.abs_diff(x)) && !near(window.pixel(x, k), k.abs_diff(y))
    })
}
