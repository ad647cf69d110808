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
    /// A step (or the feet brought together) from `from` to `to`, by
    /// the body's foot `foot` (0 left, 1 right; see [`Footing::soles`]).
    Step {
        from: Vec3,
        to: Vec3,
        time: f32,
        foot: usize,
        together: bool,
    },
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
    /// Where each sole stands (`[left, right]`), once it has stepped.
    soles: [Option<Vec3>; 2],
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

    /// The plane its feet stand on: found, else the scene's
    /// (`foothold_plane`).
    pub fn ground(&self) -> Option<f32> {
        self.plane.or(self.settings.plane)
    }

    /// Whether it has stepped on footholds (its soles stand where steps
    /// set them).
    pub fn stepped(&self) -> bool {
        self.soles[0].is_some()
    }

    /// Its left, across its body's direction (`facing` before it has
    /// one).
    fn left(&self, facing: Vec3) -> Vec3 {
        let h = if self.heading == Vec3::ZERO {
            flat(facing)
        } else {
            flat(self.heading)
        };
        Vec3::new(h.z, 0.0, -h.x)
    }

    /// Where the soles stand between steps; before the first step, side
    /// by side under the eye `eye`.
    fn standing(&self, eye: Vec3, facing: Vec3) -> [Vec3; 2] {
        let left = self.left(facing);
        [0, 1].map(|k| self.soles[k].unwrap_or(eye + left * (side(k) * SIDE_BY_SIDE)))
    }

    /// The body's foot that makes a step to `to` planned with `foot`:
    /// bringing the feet together (`together`), the one farther from
    /// `to`, else the planned one.
    fn stepping(&self, foot: Foot, to: Vec3, together: bool, standing: [Vec3; 2]) -> usize {
        if together {
            let d = |k: usize| ground(standing[k]).distance(ground(to));
            usize::from(d(1) > d(0))
        } else {
            foot_index(foot)
        }
    }

    /// Where foot `k` lands on the step to `to`: on `to`, or bringing the
    /// feet together beside the other foot when that one stands on `to`.
    fn landing(&self, k: usize, to: Vec3, together: bool, standing: [Vec3; 2]) -> Vec3 {
        let other = standing[1 - k];
        if together && ground(other).distance(ground(to)) < 2.0 * SIDE_BY_SIDE {
            other + self.left(Vec3::Z) * (side(k) * 2.0 * SIDE_BY_SIDE)
        } else {
            to
        }
    }

    /// Where foot `k` ends a turn on the spot to the heading `to`: beside
    /// the other about the feet's middle.
    fn turned(k: usize, standing: [Vec3; 2], to: Vec3) -> Vec3 {
        let h = flat(to);
        let middle = standing[0].midpoint(standing[1]);
        middle + Vec3::new(h.z, 0.0, -h.x) * (side(k) * SIDE_BY_SIDE)
    }

    /// Where its soles are now, on the foothold plane, and which is in
    /// the air (`[left, right]`): each where it was set down, the
    /// stepping one on its way to its foothold (lifted by [`SOLE_LIFT`]
    /// mid-step); at a halt the feet come side by side; turning on the
    /// spot they step round one after the other. Before the first step
    /// they stand under the eye `eye`, across `facing`. None while the
    /// plane is unknown.
    pub fn soles(&self, eye: Vec3, facing: Vec3) -> Option<([Vec3; 2], [bool; 2])> {
        let plane = self.ground()?;
        let standing = self.standing(eye, facing);
        let mut soles = standing;
        let mut lifted = [0.0f32; 2];
        let lift = |u: f32| SOLE_LIFT * (std::f32::consts::PI * u).sin();
        let smooth = |u: f32| u * u * (3.0 - 2.0 * u);
        match (self.motion, self.foot) {
            (
                Some((
                    Motion::Step {
                        to,
                        time,
                        foot: k,
                        together,
                        ..
                    },
                    t,
                )),
                _,
            ) => {
                let u = progress(t, time);
                let target = self.landing(k, to, together, standing);
                soles[k] = standing[k].lerp(target, smooth(u));
                lifted[k] = lift(u).max(1e-4);
            }
            (Some((Motion::Turn { to, time, .. }, t)), _) => {
                let u = progress(t, time);
                // The left foot steps round in the turn's first half, the
                // right in its second.
                for (k, part) in [(2.0 * u).min(1.0), (2.0 * u - 1.0).max(0.0)]
                    .into_iter()
                    .enumerate()
                {
                    soles[k] = standing[k].lerp(Self::turned(k, standing, to), smooth(part));
                    if part > 0.0 && part < 1.0 {
                        lifted[k] = lift(part).max(1e-4);
                    }
                }
            }
            _ => {}
        }
        for (sole, lift) in soles.iter_mut().zip(lifted) {
            sole.y = plane + lift;
        }
        Some((soles, lifted.map(|l| l > 0.0)))
    }
}

/// How far along a motion of `time` seconds is after `t`: 0 to 1.
fn progress(t: f32, time: f32) -> f32 {
    if time > 0.0 {
        (t / time).clamp(0.0, 1.0)
    } else {
        1.0
    }
}

/// +1 for the left foot, −1 for the right.
fn side(k: usize) -> f32 {
    if k == 0 {
        1.0
    } else {
        -1.0
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
