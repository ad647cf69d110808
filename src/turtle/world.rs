//! What the turtle asks of the world above it: particles, actors,
//! trajectories, the sound log, scripts (`TurtleWorld`, implemented by the
//! film's view), and the requests it sends.

use glam::DVec3;

use crate::lsys::{Sensors, Who};
use crate::scene::body::Skeleton;
use crate::scene::motor::Drive;
use crate::scene::rig::Targets;

/// What the turtle may ask of higher layers (particles, trajectories,
/// the sound log); the defaults answer for a world without them. The
/// same window answers the expressions the turtle evaluates (growth
/// functions) as their [`Sensors`].
pub trait TurtleWorld: Sensors {
    /// Force of the particle fields at `p`, added to the tropism force.
    fn field(&mut self, _p: DVec3) -> DVec3 {
        DVec3::ZERO
    }
    /// The `C` symbol `who` maps its particle and the turtle (C.4);
    /// returns where the turtle goes, if it moves.
    fn map_particle(&mut self, _who: Who, _mapping: ParticleMapping) -> Option<DVec3> {
        None
    }
    /// Velocity of the particle mapped to symbol `who` (`$` par2 = 4).
    fn particle_velocity(&mut self, _who: Who) -> Option<DVec3> {
        None
    }
    /// Position of the particle mapped to symbol `who` (`l` par3 = 4).
    fn particle_position(&mut self, _who: Who) -> Option<DVec3> {
        None
    }
    /// Position and direction of imported trajectory `n` (`$` par2 = 5).
    fn trace(&mut self, _n: i64) -> Option<(DVec3, DVec3)> {
        None
    }
    /// How many actors the film has (`NBR_actors`).
    fn actor_count(&self) -> usize {
        0
    }
    /// An `M` or `g` symbol maps actor `actor` — or, for None, the
    /// current actor — and the turtle (C.5); returns where the turtle
    /// goes, when it goes to the actor.
    fn map_actor(&mut self, _actor: Option<u32>, _mapping: ActorMapping) -> Option<ActorPose> {
        None
    }
    /// The `I` symbol: the records of the traced actors (`trace_actor`)
    /// are written for this frame.
    fn record_actors(&mut self) {}
    /// The planned path actor `actor` shows (its `turtle` 3, show path),
    /// key points from where it is.
    fn shown_path(&mut self, _actor: u32) -> Vec<DVec3> {
        Vec::new()
    }
    /// Microphone `mic` placed at `p` (`l` par3 = 8, 10).
    fn microphone(&mut self, _mic: i64, _p: DVec3) {}
    /// A sound event of the `T` symbol, for the sound event handler.
    fn sound(&mut self, _request: SoundCue) {}
    /// The `E` symbol: run script `number` with the integer growth values.
    fn command(&mut self, _number: i64, _values: [i64; 3]) {}
    /// A part of actor `actor`'s body: drawn in its own `M` branch, so
    /// its vision looks through it (other actors and the camera see it).
    fn body(&mut self, _actor: u32, _part: BodyPart) {}
    /// Drives the motor of body `key` (its L-system and symbol), drawn in
    /// actor `owner`'s `M` branch if any, for this frame: its actor adds
    /// what it gives a body (gaze, ground, footholds), its motor carried
    /// from the frames before gives the pose. None: the world keeps no
    /// motors (the body takes the pose of a fresh one).
    fn drive_body(
        &mut self,
        _key: (usize, u64),
        _owner: Option<u32>,
        _drive: Drive,
    ) -> Option<(Skeleton, Targets)> {
        None
    }
}

/// A primitive drawn in an actor's own `M` branch: by the symbol that
/// drew it, or the instance a placement there made.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BodyPart {
    Symbol(u64),
    Object(u32),
}

/// What a `C` symbol asks of the particle layer (C.4), in world
/// coordinates.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ParticleMapping {
    /// par1 = 0 at local age < Δt: the particle starts at the turtle with
    /// mass par2 and velocity par4..6.
    Start {
        at: DVec3,
        mass: f64,
        velocity: DVec3,
    },
    /// par1 = 0 later: the turtle goes to the evolved particle.
    Follow,
    /// par1 = 1: the particle, and the turtle, at par4..6.
    Place { at: DVec3 },
    /// par1 = 6: the particle at the turtle.
    Turtle { at: DVec3 },
    /// par1 = 5: the particle at the racket of actor par4, and the turtle
    /// with it.
    Racket { actor: u32 },
}

/// What an `M` or `g` symbol asks of an actor (C.5), in world
/// coordinates.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ActorMapping {
    /// `M` par1 = 7: the turtle goes to the actor's eye, looking where it
    /// looks, and the actor becomes the current actor — unless it runs
    /// `follow_turtle`, which follows the turtle (`at`, heading `h`).
    ToTurtle {
        at: DVec3,
        h: DVec3,
    },
    /// `g` par1 = 0, 2: the actor's eye at `eye`, looking at `look_at`.
    Place {
        eye: DVec3,
        look_at: DVec3,
    },
    /// `g` par1 = 1: the actor's local goal at `at`.
    LocalGoal {
        at: DVec3,
    },
    /// `M` par1 = 14, 15: the camera, or the look-at point, of the
    /// actor's memory display at `at`.
    DisplayEye {
        at: DVec3,
    },
    DisplayLookAt {
        at: DVec3,
    },
}

/// Where `M` par1 = 7 puts the turtle: at the actor's eye `at`, H along
/// `h`; with `upright`, L vertical (turtle 1, footholds: H is then the
/// horizontal part of `h`); and the material it activates, if any.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ActorPose {
    pub at: DVec3,
    pub h: DVec3,
    pub upright: bool,
    pub material: Option<u32>,
}

impl ActorPose {
    /// The turtle at `eye`, looking at `look_at`.
    pub fn looking(eye: DVec3, look_at: DVec3) -> Self {
        ActorPose {
            at: eye,
            h: look_at - eye,
            upright: false,
            material: None,
        }
    }
}

/// What a `T` symbol asks of the sound event handler (C.6), in world
/// coordinates.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum SoundCue {
    /// par1 = 0: play sound `sound` back (no place: heard as is).
    Play { sound: u32 },
    /// par1 = 1: source `source` starts sound `sound` at `at`.
    Emit { sound: u32, source: u32, at: DVec3 },
    /// par1 = 2: source `source` moves to `at`.
    Move { source: u32, at: DVec3 },
}

/// A world with no particles, trajectories or sound log, whose sensors
/// give their defaults.
#[derive(Debug, Default, Clone, Copy)]
pub struct NoWorld;

impl Sensors for NoWorld {}

impl TurtleWorld for NoWorld {}
