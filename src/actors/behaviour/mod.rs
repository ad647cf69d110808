//! The behaviour stack and the automata that act (thesis 5.1, 5.3–5.5,
//! 6.3.4). Each actor runs one automata at a time; when it ends, the next
//! command string is popped from the actor's stack and its commands set
//! the state variables (those it does not name keep their values). After
//! the sense step, every actor acts in actor order (DESIGN §4): it reads
//! only what it perceives — its window's percepts, the sounds it hears —
//! and its own state, and what it does to the world outside itself (its
//! voice) comes back as [`Deed`]s for the film to carry out.

use std::f32::consts::TAU;

use glam::Vec3;

use crate::lsys::automata::{Automata, AutomataCommand};
use crate::sound::air::Ongoing;

mod simple;

/// Sound source of actor n's voice: `ACTOR_SOURCE + n`.
pub const ACTOR_SOURCE: u32 = 2000;

/// Whether sound source `source` is an actor's voice.
pub fn is_voice(source: u32) -> bool {
    (ACTOR_SOURCE..ACTOR_SOURCE.saturating_add(super::MAX_ACTORS as u32)).contains(&source)
}

/// How fast an actor turns (walk_local, auto_align), in radians a second.
const TURN_SPEED: f32 = std::f32::consts::FRAC_PI_2;

/// One command string of a behaviour stack: an automata and the
/// commands that set the actor's state when it is popped.
#[derive(Debug, Clone, PartialEq)]
pub struct Behaviour {
    pub automata: Automata,
    pub commands: Vec<AutomataCommand>,
}

impl Behaviour {
    /// A command string that only names its automata.
    pub fn of(automata: Automata) -> Self {
        Behaviour {
            automata,
            commands: Vec::new(),
        }
    }
}

/// What `talk` and `listen` (5.4, 5.5) keep: the words to say, what to
/// listen for and what was heard (the referee's calls and the players'
/// answers pass through them).
#[derive(Debug, Clone, Default)]
pub struct Conversation {
    /// The sounds `talk` says (`words_to_speak`), first first.
    pub words: Vec<u32>,
    /// What `listen` waits for: the next n events of a source.
    pub listen_to: Option<(u32, usize)>,
    /// The sounds `listen` captured last, in the order they began.
    pub heard_words: Vec<u32>,
}

/// What an actor perceives of the world beyond its window this frame.
pub struct Senses<'a> {
    /// The on-going sound events it hears (audition, 3.4).
    pub heard: &'a [Ongoing],
    pub time: f64,
    pub dt: f64,
}

/// What an actor does to the world outside itself.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Deed {
    /// Says sound `sound` with its voice (source [`ACTOR_SOURCE`] + its
    /// number) at `at`.
    Say { sound: u32, source: u32, at: Vec3 },
    /// A tennis server tosses the ball (5.6): the ball, the first
    /// particle `C` par1 = 0 started, is at `at` with `velocity`.
    Toss { at: Vec3, velocity: Vec3 },
}

/// Where the running automata is in its work.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct AutomataProgress {
    /// `observe`: how far the eyes have turned, radians.
    pub turned: f32,
    /// `listen`: when it began, and the events captured so far (sound,
    /// start), in the order they began.
    pub since: Option<f64>,
    pub captured: Vec<(u32, f64)>,
}

/// `v` turned by `a` radians about the vertical axis (toward +x from +z
/// for a > 0: to the actor's left).
pub(crate) fn turn(v: Vec3, a: f32) -> Vec3 {
    let (s, c) = a.sin_cos();
    Vec3::new(v.x * c + v.z * s, v.y, -v.x * s + v.z * c)
}

/// The signed horizontal angle from `from` to `to` (positive: to the left).
pub(crate) fn angle_to(from: Vec3, to: Vec3) -> f32 {
    let (a, b) = (Vec3::new(from.x, 0.0, from.z), Vec3::new(to.x, 0.0, to.z));
    (a.z * b.x - a.x * b.z).atan2(a.x * b.x + a.z * b.z)
}
