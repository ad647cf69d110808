//! The one window through which the lower layers see the film's world
//! (DESIGN §2): the L-system's [`Sensors`] and the turtle's
//! [`TurtleWorld`], made for each use from split borrows of the film's
//! parts — the particles, the sound event handler, the scripts.
//!
//! Sensor functions read what the sense step recorded (the particle
//! table and the on-going sounds as the frame's interpretation left
//! them, [`Physics::touch`] and [`Air::heard`]); the turtle's requests
//! act on the live world. An expression therefore never sees the world
//! change while a frame is being interpreted or derived.

use std::collections::BTreeMap;
use std::path::PathBuf;

use glam::DVec3;

use crate::actors::live::Living;
use crate::error::Error;
use crate::lsys::automata::Automata;
use crate::lsys::{Sensors, Who};
use crate::physics::{Mode, Particle, Physics};
use crate::scene::body::Skeleton;
use crate::scene::motor::{Drive, Motor};
use crate::scene::rig::Targets;
use crate::sound::air::{self, Air, AMBIENT_SOURCE};
use crate::source::FileRef;
use crate::turtle::{ActorMapping, ActorPose, BodyPart, ParticleMapping, SoundCue, TurtleWorld};

use super::tracks::Tracks;

/// The `turtle` mapping that shows the planned path (6.3.4).
const SHOW_PATH: i64 = 3;
/// `turtle` 1: walking on footholds, the body upright and coloured by
/// its feet (6.3.4).
const FOOTHOLD: i64 = 1;
/// `turtle` 2: the tennis racket, facing along its stroke (6.3.4).
const RACKET: i64 = 2;
/// `turtle` 4: the interactive racket (6.3.4).
const INTERACTIVE_RACKET: i64 = 4;

/// A `command_file` declaration: number, script, two text arguments.
pub(super) type CommandScript = (i64, FileRef, String, String);

/// The scripts a scene may run (only with the user's consent) and the
/// folder they live in.
pub(super) type Scripts = (Vec<CommandScript>, PathBuf);

/// The world as one frame's interpretation or derivation sees it.
pub(super) struct WorldView<'a> {
    pub air: &'a mut Air,
    pub physics: &'a mut Physics,
    /// The particle of the last `C` interpreted: the "current particle"
    /// of `?20`, `?34`, `$` par2 = 4 and `l` par3 = 4, 5.
    pub current: Option<Who>,
    pub scripts: Option<&'a Scripts>,
    /// The actors, as the last sense step left them, and the one the last
    /// `M` par1 = 7 interpreted made current: the actor of the sensor
    /// functions of symbols outside any `M` branch.
    pub living: &'a mut [Living],
    pub actor: Option<u32>,
    pub frame: u64,
    /// The first failure of a turtle request; it stops the frame.
    pub error: Option<Error>,
    /// The imported and exported data (`?50`, `$` par2 = 5, `I`).
    pub tracks: Option<&'a mut Tracks>,
    /// The motors of the bodies the turtle holds, kept from frame to
    /// frame (none where a use keeps no bodies).
    pub bodies: Option<&'a mut Bodies>,
}

/// The motor of each body the turtle holds, by its L-system and symbol.
pub(super) type Bodies = BTreeMap<(usize, u64), Motor>;

/// The particle of symbol `who` in `get`'s table, or else `current`'s
/// when it belongs to the same L-system.
fn particle_of<'p>(
    get: impl Fn(u64) -> Option<&'p Particle>,
    current: Option<Who>,
    who: Who,
) -> Option<&'p Particle> {
    get(who.symbol).or_else(|| get(current.filter(|c| c.lsys == who.lsys)?.symbol))
}

impl<'a> WorldView<'a> {
    /// The window on the film's live parts at frame `frame`, with the
    /// current particle and actor; it runs no script until given them.
    pub fn on(
        air: &'a mut Air,
        physics: &'a mut Physics,
        living: &'a mut [Living],
        tracks: &'a mut Tracks,
        current: Option<Who>,
        actor: Option<u32>,
        frame: u64,
    ) -> Self {
        WorldView {
            air,
            physics,
            current,
            scripts: None,
            living,
            actor,
            frame,
            error: None,
            tracks: Some(tracks),
            bodies: None,
        }
    }

    /// The actor `actor` names, or else the current actor, or else actor 0.
    fn actor_of(&mut self, actor: Option<u32>) -> Option<&mut Living> {
        let id = actor.or(self.actor).unwrap_or(0);
        self.living.get_mut(id as usize)
    }

    /// Swim phase (radians) of `who`'s particle, or the current one's, as
    /// last sensed.
    fn phase(&self, who: Who) -> f64 {
        let touch = self.physics.touch();
        particle_of(|id| touch.get(id), self.current, who).map_or(0.0, |p| p.phase)
    }

    /// The live particle of symbol `who`, or else the current one.
    fn live(&self, who: Who) -> Option<&Particle> {
        particle_of(|id| self.physics.get(id), self.current, who)
    }

    fn fail(&mut self, e: Error) {
        self.error.get_or_insert(e);
    }

    /// Runs script `number` as the thesis did: the frame number, the two
    /// declared arguments and the three values.
    fn run_script(&mut self, number: i64, values: [i64; 3]) {
        let Some((scripts, dir)) = self.scripts else {
            return;
        };
        let Some((_, script, a1, a2)) = scripts.iter().find(|s| s.0 == number) else {
            return self.fail(Error::input(format!(
                "`E` runs script {number}, which no command_file declares"
            )));
        };
        let path = dir.join(&script.name);
        // A script that is not a file is reported where the scene names it.
        if !path.is_file() {
            let e = script.error(format!(
                "script {} (command_file {number}) is not a file",
                path.display()
            ));
            return self.fail(e.into());
        }
        let status = std::process::Command::new(&path)
            .current_dir(dir)
            .arg(self.frame.to_string())
            .args([a1, a2])
            .args(values.map(|v| v.to_string()))
            .status();
        match status {
            Ok(s) if s.success() => {}
            Ok(s) => self.fail(Error::other(format!(
                "script {} (command_file {number}) failed: {s}",
                script.name
            ))),
            Err(e) => self.fail(Error::other(
                script
                    .error(format!(
                        "script {} (command_file {number}) cannot run: {e}",
                        path.display()
                    ))
                    .to_string(),
            )),
        }
    }
}

/// `v` as a sound or source number, when it is one exactly.
fn whole(v: f64) -> Option<u32> {
    let n = v as u32;
    (f64::from(n) == v).then_some(n)
}

impl Sensors for WorldView<'_> {
    /// `?30`–`?39`: the percepts and state of the symbol's actor.
    fn actor(&mut self, code: u8, who: Who) -> f64 {
        match self.actor_of(who.actor) {
            Some(a) => a.sensor(code),
            None => crate::lsys::NoSensors.actor(code, who),
        }
    }

    /// `?20`: the swim motor, sin(phase)·5 (table B5); `?18` as default.
    fn particle(&mut self, code: u8, who: Who) -> f64 {
        match code {
            20 => self.phase(who).sin() * 5.0,
            18 => -9.81,
            _ => 0.0,
        }
    }

    /// `?34`: the swim phase in degrees.
    fn phase_degrees(&mut self, who: Who) -> f64 {
        self.phase(who).to_degrees()
    }

    /// `?40`: the magnitude of the field at `p`.
    fn force(&mut self, p: [f64; 3]) -> f64 {
        self.physics.touch().field_at(DVec3::from_array(p)).length()
    }

    /// `?15`, `?19`, `?26`, `?27`: the tennis fields of the physics layer
    /// (no peak detector listens during derivation).
    fn tennis(&mut self, q: &crate::lsys::FieldQuery) -> crate::lsys::FieldValue {
        crate::physics::tennis::field(q).field
    }

    /// `?50`: the data channel at `arg`; a channel the film does not
    /// declare stops the frame (as an undeclared script does).
    fn channel(&mut self, channel: f64, arg: f64) -> f64 {
        let read = match self.tracks.as_deref() {
            Some(t) => t.channel(channel, arg),
            None => Ok(0.0),
        };
        read.unwrap_or_else(|e| {
            self.fail(Error::input(e));
            0.0
        })
    }

    fn sounds_playing(&mut self) -> f64 {
        self.air.heard().len() as f64
    }

    fn sound_of_source(&mut self, source: f64) -> f64 {
        let found = whole(source).and_then(|n| air::sound_of_source(self.air.heard(), n));
        found.map_or(-1.0, f64::from)
    }

    fn source_of_sound(&mut self, sound: f64) -> f64 {
        let found = whole(sound).and_then(|n| air::source_of_sound(self.air.heard(), n));
        found.map_or(-1.0, f64::from)
    }
}

/// Microphones and sound events go to the handler, `C` and tropism to
/// the particles; the first error stops the frame.
impl TurtleWorld for WorldView<'_> {
    fn field(&mut self, p: DVec3) -> DVec3 {
        self.physics.field_at(p)
    }

    fn map_particle(&mut self, who: Who, mapping: ParticleMapping) -> Option<DVec3> {
        let id = who.symbol;
        let to = match mapping {
            ParticleMapping::Start { at, mass, velocity } => {
                self.physics.start(id, at, mass, velocity);
                None
            }
            ParticleMapping::Follow => self.physics.get(id).map(|p| p.pos),
            ParticleMapping::Place { at } => {
                self.physics.place(id, at, Mode::Placed);
                Some(at)
            }
            ParticleMapping::Turtle { at } => {
                self.physics.place(id, at, Mode::Turtle);
                None
            }
            ParticleMapping::Racket { actor } => {
                let at = self.living.get(actor as usize)?.eye.as_dvec3();
                self.physics.place(id, at, Mode::Racket);
                Some(at)
            }
        };
        if self.physics.get(id).is_some() {
            self.current = Some(who);
        }
        to
    }

    fn particle_velocity(&mut self, who: Who) -> Option<DVec3> {
        self.live(who).map(|p| p.vel)
    }

    fn particle_position(&mut self, who: Who) -> Option<DVec3> {
        self.live(who).map(|p| p.pos)
    }

    fn actor_count(&self) -> usize {
        self.living.len()
    }

    fn map_actor(&mut self, actor: Option<u32>, mapping: ActorMapping) -> Option<ActorPose> {
        let time = self.physics.time();
        let a = self.actor_of(actor)?;
        let id = a.id as u32;
        let v = DVec3::as_vec3;
        // A point the actor could take must stay finite as its f32 state
        // (a turtle at 1e60 is finite as f64, infinite as f32).
        let points = match mapping {
            ActorMapping::ToTurtle { at, h } => vec![at, at + h],
            ActorMapping::Place { eye, look_at } => vec![eye, look_at],
            ActorMapping::LocalGoal { at }
            | ActorMapping::DisplayEye { at }
            | ActorMapping::DisplayLookAt { at } => vec![at],
        };
        let limit = f64::from(crate::aabb::MAX_COORDINATE);
        if let Some(p) = points
            .iter()
            .find(|p| !(p.is_finite() && p.abs().max_element() <= limit))
        {
            a.note_once(
                "beyond",
                &format!(
                    "the turtle maps it to ({:e}, {:e}, {:e}), beyond ±{:e}: skipped (its eye, look-at and goals stay as they were)",
                    p.x,
                    p.y,
                    p.z,
                    crate::aabb::MAX_COORDINATE
                ),
            );
            return None;
        }
        match mapping {
            ActorMapping::ToTurtle { at, h } => {
                // It follows the turtle rather than lead it: by its
                // automata, or as the interactive racket, which a user's
                // motion drives (offline: what the turtle follows, such
                // as an imported trajectory; 6.3.4).
                let driven = a.turtle == INTERACTIVE_RACKET;
                let stroke = (a.turtle == RACKET)
                    .then(|| a.racket_normal(time))
                    .flatten();
                let eye = a.eye.as_dvec3();
                let to = if driven || a.automata == Some(Automata::FollowTurtle) {
                    (a.eye, a.look_at) = (v(&at), v(&(at + h)));
                    None
                } else if let Some(n) = stroke {
                    // The racket faces its motion along its planned path.
                    Some(ActorPose::looking(eye, (a.eye + n).as_dvec3()))
                } else if a.turtle == FOOTHOLD {
                    // Upright along its body's heading, coloured by its feet.
                    Some(ActorPose {
                        h: a.footing.heading.as_dvec3(),
                        upright: true,
                        material: a.foothold_material(),
                        ..ActorPose::looking(eye, eye)
                    })
                } else {
                    Some(ActorPose::looking(eye, a.look_at.as_dvec3()))
                };
                self.actor = Some(id);
                return to;
            }
            ActorMapping::Place { eye, look_at } => (a.eye, a.look_at) = (v(&eye), v(&look_at)),
            ActorMapping::LocalGoal { at } => {
                a.local_goals.insert(0, v(&at));
            }
            ActorMapping::DisplayEye { at } => a.display.eye = Some(v(&at)),
            ActorMapping::DisplayLookAt { at } => a.display.look_at = Some(v(&at)),
        }
        None
    }

    fn shown_path(&mut self, actor: u32) -> Vec<DVec3> {
        match self.living.get(actor as usize) {
            Some(a) if a.turtle == SHOW_PATH => {
                a.shown_path().iter().map(|p| p.as_dvec3()).collect()
            }
            // The footholds it plans to step on.
            Some(a) if a.turtle == FOOTHOLD => {
                a.footing.ahead.iter().map(|p| p.at.as_dvec3()).collect()
            }
            _ => Vec::new(),
        }
    }

    fn microphone(&mut self, mic: i64, p: DVec3) {
        match u32::try_from(mic) {
            Ok(m) => self.air.microphone(m, p),
            Err(_) => self.fail(Error::input(format!("microphone number {mic} must be ≥ 0"))),
        }
    }

    fn sound(&mut self, request: SoundCue) {
        let r = match request {
            SoundCue::Play { sound } => {
                let c = self.air.centre();
                self.air.play(sound, AMBIENT_SOURCE, c)
            }
            SoundCue::Emit { sound, source, at } => self.air.play(sound, source, at),
            SoundCue::Move { source, at } => self.air.move_source(source, at),
        };
        if let Err(e) = r {
            self.fail(Error::input(e));
        }
    }

    fn command(&mut self, number: i64, values: [i64; 3]) {
        self.run_script(number, values);
    }

    fn trace(&mut self, n: i64) -> Option<(DVec3, DVec3)> {
        self.tracks.as_deref()?.trace(n)
    }

    fn body(&mut self, actor: u32, part: BodyPart) {
        if let Some(a) = self.living.get_mut(actor as usize) {
            match part {
                BodyPart::Symbol(id) => a.body.add_symbol(id),
                BodyPart::Object(object) => a.body.add_object(object),
            }
        }
    }

    fn drive_body(
        &mut self,
        key: (usize, u64),
        owner: Option<u32>,
        mut drive: Drive,
    ) -> Option<(Skeleton, Targets)> {
        if let Some(a) = owner.and_then(|a| self.living.get(a as usize)) {
            // What an actor gives its body: its gaze; on footholds, the
            // plane, its body's direction and where its soles are.
            drive.gaze = Some(a.look_at);
            // Walking on footholds, or still standing where that walk
            // left it.
            let soles = a.footing.soles(a.eye, a.look_at - a.eye);
            let walking = a.automata == Some(Automata::WalkStepworthy)
                || a.stack
                    .iter()
                    .any(|b| b.automata == Automata::WalkStepworthy);
            let standing = soles.is_some_and(|(s, _)| {
                let middle = s[0].midpoint(s[1]);
                glam::Vec2::new(middle.x - a.eye.x, middle.z - a.eye.z).length() < 0.3
            });
            if walking || (a.footing.stepped() && standing) {
                drive.ground = a.footing.ground().unwrap_or(0.0);
                drive.facing = (a.footing.heading != glam::Vec3::ZERO).then_some(a.footing.heading);
                drive.soles = soles;
            }
        }
        let bodies = self.bodies.as_deref_mut()?;
        let motor = bodies.entry(key).or_insert_with(|| Motor::new(&drive));
        let targets = motor.drive(&drive);
        Some((motor.skeleton().clone(), targets))
    }

    /// `I`: the film writes the traced actors' records after the frame.
    fn record_actors(&mut self) {
        if let Some(t) = self.tracks.as_deref_mut() {
            t.wanted = true;
        }
    }
}
