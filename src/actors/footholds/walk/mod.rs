//! The automata `walk_stepworthy` (thesis figure 5.9.5): initialization,
//! look_around (observe and memorise), create the local map, pop a
//! destination (end when there is none), search_new_path (back to
//! look_around when there is no path), and walking step by step — back to
//! look_around when the destination foothold is reached, or when the
//! memory shows an obstacle on a voxel along the planned path: a foothold
//! gone from under a planned step, or something standing on the way.
//!
//! The actor knows the stones only through its memory, which its vision
//! fills (and empties, by forgetting) at every sense step.

use glam::{Vec2, Vec3};

use super::map::{self, Foothold, Region};
use super::plan::{self, Foot, Gait, Weights};
use crate::actors::behaviour::{angle_to, turn, Behaviour};
use crate::lsys::automata::Automata;

mod walk_stepworthy;

/// Looks around and searches in a row without a path before the actor
/// gives the destination up (the thesis loops; a film must not hang).
const MAX_LOOKS: u32 = 3;
/// Shortest time of one step, seconds.
const MIN_STEP_TIME: f32 = 0.25;
/// Time to bring the feet together at a halt, seconds.
const HALT_TIME: f32 = 0.3;
/// How fast the actor turns on the spot, radians a second.
const TURN_SPEED: f32 = std::f32::consts::PI;
/// A turn smaller than this (radians) is made while stepping.
const TURN_ON_SPOT: f32 = 0.1;
/// How high a step lifts the actor, as a share of the step's length: a
/// walking body's hips rise a little over the standing foot.
const HOP: f32 = 0.05;
/// Least height of the eye over the plane, world units.
const MIN_STAND: f32 = 0.1;
/// How far ahead, in longest steps, the planned path is checked against
/// the memory: nearer, vision sees the stones clearly; farther, a small
/// stone seen at a grazing angle comes and goes in the memory.
const CHECKED_STEPS: f32 = 2.5;
/// The local map's radius and smallest foothold before any `foothold_map`.
const DEFAULT_RANGE: f32 = 10.0;
const DEFAULT_MIN_VOXELS: u32 = 4;
/// A foot's length, world units (metres): the largest foothold.
const DEFAULT_FOOT: f32 = 0.3;

/// The configuration of `walk_stepworthy`, set by its commands.
#[derive(Debug, Clone, PartialEq)]
pub struct WalkSettings {
    /// `foothold_plane`: the plane's height; None: the busiest layer of
    /// the memory under the eye, found at the first map.
    pub plane: Option<f32>,
    pub gait: Gait,
    pub weights: Weights,
    /// `foothold_map`: the map's radius and smallest foothold.
    pub range: f32,
    pub min_voxels: u32,
    /// `foothold_map`'s third number: the largest foothold, world units;
    /// pieces of the map that fit in a square this size are one.
    pub foot: f32,
}

impl Default for WalkSettings {
    fn default() -> Self {
        WalkSettings {
            plane: None,
            gait: Gait::default(),
            weights: Weights::default(),
            range: DEFAULT_RANGE,
            min_voxels: DEFAULT_MIN_VOXELS,
            foot: DEFAULT_FOOT,
        }
    }
}

/// Where the automata is (figure 5.9.5).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
enum Phase {
    #[default]
    Initialization,
    /// Back from look_around: create the local map, pop a destination.
    CreateMap,
    Walking,
}

/// A planned foothold ahead: where, and the foot set on it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Planned {
    pub at: Vec3,
    pub foot: Foot,
    /// Feet together there: the start, or a halt.
    pub together: bool,
}

/// What the actor's body does now.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Motion {
    /// A step (or the feet brought together) from `from` to `to`.
    Step { from: Vec3, to: Vec3, time: f32 },
    /// Turning on the spot, feet together, from one heading to another.
    Turn { from: Vec3, to: Vec3, time: f32 },
}

/// What a `walk_stepworthy` actor keeps between frames.
#[derive(Debug, Clone, Default)]
pub struct Footing {
    pub settings: WalkSettings,
    phase: Phase,
    /// The foothold plane, once known, and the eye's height over it.
    pub plane: Option<f32>,
    stand: f32,
    /// The plane its last map was made on, kept or not.
    last_plane: Option<f32>,
    /// The last local map.
    pub map: Vec<Foothold>,
    /// The destination it walks to, popped from the goal stack.
    pub destination: Option<Vec3>,
    /// The planned footholds ahead, the next first.
    pub ahead: Vec<Planned>,
    /// The foothold it stands on, the foot it last set down, where its
    /// body faces.
    pub on: Option<Vec3>,
    pub foot: Option<Foot>,
    pub heading: Vec3,
    /// Whether its feet are together on `on` (or it has not stepped yet).
    together: bool,
    /// Where each foot stands (`[left, right]`), once it has stepped.
    pub stones: [Option<Vec3>; 2],
    motion: Option<(Motion, f32)>,
    /// The foothold a walk ended on short of its destination: ending
    /// there again means the map leads no nearer.
    stuck_at: Option<Vec3>,
    /// Look-arounds in a row without a path, and for an obstacle before
    /// a step was made.
    failures: u32,
    blocked: u32,
    /// Paths found, and of them those searched because the memory showed
    /// an obstacle on the planned path.
    pub plans: u32,
    pub replans: u32,
}

impl Footing {
    /// Whether the actor turns on the spot (turtle 1 shows it red).
    pub fn turning(&self) -> bool {
        matches!(self.motion, Some((Motion::Turn { .. }, _)))
    }

    /// Where its soles are now, on the foothold plane, and which is in
    /// the air (`[left, right]`): each on its foothold, the stepping one
    /// on its way (lifted by [`SOLE_LIFT`] mid-step); feet on one
    /// foothold stand side by side on it. None before its first step.
    pub fn soles(&self) -> Option<([Vec3; 2], [bool; 2])> {
        let plane = self.plane?;
        let [Some(left), Some(right)] = self.stones else {
            return None;
        };
        let mut soles = [left, right];
        let mut swinging = [false; 2];
        if let (Some((Motion::Step { to, time, .. }, t)), Some(foot)) = (self.motion, self.foot) {
            let k = foot_index(foot);
            let u = if time > 0.0 {
                (t / time).clamp(0.0, 1.0)
            } else {
                1.0
            };
            let smooth = u * u * (3.0 - 2.0 * u);
            soles[k] = soles[k].lerp(to, smooth);
            soles[k].y = plane + SOLE_LIFT * (std::f32::consts::PI * u).sin();
            swinging[k] = true;
        }
        if ground(soles[0]).distance(ground(soles[1])) < 2.0 * SIDE_BY_SIDE {
            let h = flat(self.heading);
            let left = Vec3::new(h.z, 0.0, -h.x) * SIDE_BY_SIDE;
            let middle = soles[0].midpoint(soles[1]);
            soles = [middle + left, middle - left];
        }
        for (k, s) in soles.iter_mut().enumerate() {
            if !swinging[k] {
                s.y = plane;
            }
        }
        Some((soles, swinging))
    }
}

/// How high a stepping sole lifts over the footholds, and how far apart
/// feet on one foothold stand from its middle (world units).
pub const SOLE_LIFT: f32 = 0.1;
const SIDE_BY_SIDE: f32 = 0.06;

/// A foot's place in `[left, right]`.
fn foot_index(f: Foot) -> usize {
    match f {
        Foot::Left => 0,
        Foot::Right => 1,
    }
}

/// The horizontal part of `v`, normalised (zero when vertical).
fn flat(v: Vec3) -> Vec3 {
    Vec3::new(v.x, 0.0, v.z).normalize_or_zero()
}

fn ground(p: Vec3) -> Vec2 {
    Vec2::new(p.x, p.z)
}

/// The unsigned angle between two horizontal directions.
fn angle(a: Vec3, b: Vec3) -> f32 {
    a.dot(b).clamp(-1.0, 1.0).acos()
}

/// The footholds a walk from `start` may reach, steps shorter than
/// `df_max` apart (whatever the gait), in index order.
fn reachable(points: &[Vec2], start: usize, df_max: f32) -> Vec<usize> {
    let mut seen = vec![false; points.len()];
    seen[start] = true;
    let mut todo = vec![start];
    while let Some(i) = todo.pop() {
        for (j, p) in points.iter().enumerate() {
            if !seen[j] && p.distance(points[i]) < df_max {
                seen[j] = true;
                todo.push(j);
            }
        }
    }
    (0..points.len()).filter(|&i| seen[i]).collect()
}
