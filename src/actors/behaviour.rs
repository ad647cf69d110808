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

use super::live::state::{ALIGN, LISTEN_WORDS, LOOK_AROUND, STOP, TALK, WALK};
use super::live::Living;
use crate::lsys::automata::{Automata, AutomataCommand};
use crate::sound::air::Ongoing;

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
pub struct Script {
    pub automata: Automata,
    pub commands: Vec<AutomataCommand>,
}

impl Script {
    /// A command string that only names its automata.
    pub fn of(automata: Automata) -> Self {
        Script {
            automata,
            commands: Vec::new(),
        }
    }
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
pub struct Progress {
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

impl Living {
    /// Pushes a command string on the behaviour stack.
    pub fn push(&mut self, script: Script) {
        self.stack.push(script);
    }

    /// The running automata ends: the next command string is popped, its
    /// commands set the state, and its automata runs from the start; with
    /// an empty stack the actor runs none.
    pub fn pop(&mut self) {
        self.progress = Progress::default();
        match self.stack.pop() {
            Some(script) => {
                for c in &script.commands {
                    self.apply(c);
                }
                self.automata = Some(script.automata);
            }
            None => self.automata = None,
        }
    }

    /// `e` par1 = 0 (C.6): the command string is pushed and popped at
    /// once, so its automata replaces the running one.
    pub fn activate(&mut self, script: Script) {
        self.push(script);
        self.pop();
    }

    /// The running automata's work for this frame, after the sense step.
    pub fn act(&mut self, senses: &Senses, deeds: &mut Vec<Deed>) {
        match self.automata {
            Some(Automata::Observe) => self.observe(),
            Some(Automata::WalkLocal) => self.walk_local(senses.dt as f32),
            Some(Automata::AutoAlign) => self.auto_align(senses.dt as f32),
            Some(Automata::Talk) => self.talk(senses, deeds),
            Some(Automata::Listen) => self.listen(senses),
            Some(Automata::WalkContinuously) => self.walk_continuously(senses.dt as f32),
            Some(Automata::Referee) => self.referee(),
            Some(Automata::TennisErrorDetection) => self.tennis_error_detection(senses),
            Some(Automata::PlayTennis) => self.play_tennis(senses, deeds),
            Some(Automata::WalkStepworthy) => self.walk_stepworthy(senses.dt as f32),
            // watch: vision and memory only; L-system: the productions
            // act (5.10); follow_turtle: `M` moves it (the window).
            _ => {}
        }
    }

    /// Where the actor looks, horizontally (its body's direction).
    pub(crate) fn heading(&self) -> Vec3 {
        let d = self.look_at - self.eye;
        let flat = Vec3::new(d.x, 0.0, d.z).normalize_or_zero();
        if flat == Vec3::ZERO {
            Vec3::Z
        } else {
            flat
        }
    }

    fn look_along(&mut self, dir: Vec3) {
        let dist = (self.look_at - self.eye).length().max(1e-3);
        self.look_at = self.eye + dir * dist;
    }

    /// `observe` (5.3): the eyes turn once around, half a view angle a
    /// frame so that consecutive windows overlap, then the automata ends.
    fn observe(&mut self) {
        if self.progress.turned >= TAU - 1e-4 {
            return self.pop();
        }
        self.state = LOOK_AROUND;
        let step = self.half_view().min(TAU - self.progress.turned);
        self.turn_eyes(step);
        self.progress.turned += step;
    }

    /// Half the view angle, radians: how far the eyes turn a frame when
    /// looking around, so that consecutive windows overlap.
    pub(super) fn half_view(&self) -> f32 {
        (self.fov as f32 / 20.0).to_radians()
    }

    /// The eyes turn by `a` radians to the left.
    pub(super) fn turn_eyes(&mut self, a: f32) {
        let d = self.look_at - self.eye;
        self.look_at = self.eye + turn(d, a);
    }

    /// Turns the heading toward `dir` by at most `max` radians; returns
    /// the angle left.
    fn turn_toward(&mut self, dir: Vec3, max: f32) -> f32 {
        let h = self.heading();
        let a = angle_to(h, dir);
        let step = a.clamp(-max, max);
        self.look_along(turn(h, step));
        a - step
    }

    /// `walk_local` (table 5.1.1): to the actual goal by local vision
    /// only — toward the goal when the way ahead is free (`?31` = 0),
    /// turning away from the closest obstacle otherwise — at `speed`.
    /// It ends on arrival (`eps_arrived`), or at once without a goal.
    fn walk_local(&mut self, dt: f32) {
        let Some(goal) = self.actual_goal() else {
            return self.pop();
        };
        if self.sensor(33) > 0.0 {
            self.state = STOP;
            return self.pop();
        }
        self.state = WALK;
        let max = TURN_SPEED * dt;
        let obstacle = self.percepts.as_ref().map_or(0.0, |p| p.obstacle);
        if obstacle != 0.0 {
            // Obstacle on the left (−1): turn right, and the other way.
            let h = self.heading();
            self.look_along(turn(h, obstacle as f32 * max));
            return;
        }
        let to_goal = goal - self.eye;
        self.turn_toward(to_goal, max);
        let flat = Vec3::new(to_goal.x, 0.0, to_goal.z).length();
        let step = (self.speed * dt).min(flat);
        let h = self.heading();
        self.eye += h * step;
        self.look_at += h * step;
    }

    /// `auto_align` (19): turns to the `align` point, then ends.
    fn auto_align(&mut self, dt: f32) {
        let Some(p) = self.align else {
            return self.pop();
        };
        self.state = ALIGN;
        let left = self.turn_toward(p - self.eye, TURN_SPEED * dt);
        if left.abs() < 1e-4 {
            self.pop();
        }
    }

    /// The actor's voice: its sound source.
    pub fn voice(&self) -> u32 {
        ACTOR_SOURCE.saturating_add(self.id as u32)
    }

    /// `talk` (5.4): says its words one after the other, each when the
    /// one before has ended (it hears its own voice), then clears the
    /// table and ends.
    fn talk(&mut self, senses: &Senses, deeds: &mut Vec<Deed>) {
        let voice = self.voice();
        if senses.heard.iter().any(|e| e.source == voice) {
            return;
        }
        self.state = TALK;
        match self.words.first().copied() {
            Some(sound) => {
                self.words.remove(0);
                deeds.push(Deed::Say {
                    sound,
                    source: voice,
                    at: self.eye,
                });
            }
            None => self.pop(),
        }
    }

    /// `listen` (5.5): captures the next n sound events of its source
    /// (`listen_to`), in the order they begin, then ends; what it heard
    /// stays in `heard_words`.
    fn listen(&mut self, senses: &Senses) {
        let Some((source, n)) = self.listen_to else {
            return self.pop();
        };
        self.state = LISTEN_WORDS;
        let since = *self.progress.since.get_or_insert(senses.time);
        let mut new: Vec<(u32, f64)> = senses
            .heard
            .iter()
            .filter(|e| e.source == source && e.start >= since)
            .map(|e| (e.sound, e.start))
            .filter(|e| !self.progress.captured.contains(e))
            .collect();
        new.sort_by(|a, b| a.1.total_cmp(&b.1));
        self.progress.captured.extend(new);
        if self.progress.captured.len() >= n {
            self.progress.captured.truncate(n);
            self.heard_words = self.progress.captured.iter().map(|e| e.0).collect();
            self.pop();
        }
    }
}
