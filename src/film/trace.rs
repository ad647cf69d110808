//! What `lmfilm trace` lists of each frame (DESIGN §5): one JSON object
//! per frame, built as a serializable record from the frame loop's state.

use std::io;

use serde::Serialize;

use super::Film;
use crate::actors::live::Living;
use crate::lsys::automata::Automata;

/// One frame: its particles, its actors and the sound events it started.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Record {
    pub frame: u64,
    pub time: f64,
    pub particles: Vec<ParticleRecord>,
    pub actors: Vec<ActorRecord>,
    pub sound_events: Vec<SoundEventRecord>,
}

/// A placed particle (code C.4.1).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ParticleRecord {
    pub id: u64,
    pub pos: [f64; 3],
    pub vel: [f64; 3],
    pub mass: f64,
}

/// An actor of the film's actor table: its number, the automata it runs
/// (none when its stack is empty), its `state` and `tennis_state`, where its eye is and
/// looks, the goal it heads for, how many voxels its visual memory holds,
/// and its thing of interest (`interest`, else `rgb_interest`) as the
/// last sense step found it: whether, on how many pixels, and where
/// (eq. 3.1.9).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ActorRecord {
    pub id: usize,
    pub automata: Option<&'static str>,
    pub state: i64,
    pub tennis_state: i64,
    pub pos: [f32; 3],
    pub look_at: [f32; 3],
    pub goal: Option<[f32; 3]>,
    /// Why it last gave a goal up (no way within its memory's cube, …).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub gave_up: Option<String>,
    pub memory_voxels: u64,
    pub found: bool,
    pub pixels: u32,
    pub position: Option<[f32; 3]>,
    /// Its walk on footholds, once it runs `walk_stepworthy`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub footing: Option<FootingRecord>,
}

/// A `walk_stepworthy` actor's walk: the foothold it stands on, the
/// foot it last set down, whether it turns on the spot, its last local
/// map (each foothold's x, y, z and size in voxels), its destination,
/// the footholds planned ahead, and how many paths it found (of them,
/// after an obstacle on the planned path).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FootingRecord {
    pub on: Option<[f32; 3]>,
    pub foot: Option<&'static str>,
    pub turning: bool,
    pub map: Vec<[f32; 4]>,
    pub destination: Option<[f32; 3]>,
    pub ahead: Vec<[f32; 3]>,
    pub plans: u32,
    pub replans: u32,
}

impl ActorRecord {
    fn of(l: &Living) -> ActorRecord {
        let thing =
            l.percepts
                .as_ref()
                .and_then(|p| if l.interest.is_some() { p.thing } else { p.rgb });
        ActorRecord {
            id: l.id,
            automata: l.automata.map(|a| a.name()),
            state: l.state,
            tennis_state: l.tennis.state,
            pos: l.eye.to_array(),
            look_at: l.look_at.to_array(),
            goal: l.actual_goal().map(|g| g.to_array()),
            gave_up: l.gave_up.clone(),
            memory_voxels: l.memory.as_ref().map_or(0, |m| m.voxels()),
            found: thing.is_some(),
            pixels: thing.map_or(0, |t| t.pixels),
            position: thing.map(|t| t.position.to_array()),
            footing: (l.footing.plans > 0 || l.automata == Some(Automata::WalkStepworthy)).then(
                || {
                    let f = &l.footing;
                    FootingRecord {
                        on: f.on.map(|p| p.to_array()),
                        foot: f.foot.map(|f| f.name()),
                        turning: f.turning(),
                        map: f
                            .map
                            .iter()
                            .map(|m| [m.at.x, m.at.y, m.at.z, m.voxels as f32])
                            .collect(),
                        destination: f.destination.map(|p| p.to_array()),
                        ahead: f.ahead.iter().map(|p| p.at.to_array()).collect(),
                        plans: f.plans,
                        replans: f.replans,
                    }
                },
            ),
        }
    }
}

/// A sound event the frame started.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SoundEventRecord {
    pub sound: u32,
    pub source: u32,
    pub pos: [f64; 3],
}

impl Record {
    /// The record of the frame the film's loop handed out last.
    pub fn of(film: &Film) -> Option<Record> {
        let frame = film.frame()?;
        let time = frame.time();
        Some(Record {
            frame: frame.number(),
            time,
            particles: film
                .particles()
                .iter()
                .filter(|p| p.is_placed())
                .map(|p| ParticleRecord {
                    id: p.id,
                    pos: p.pos.to_array(),
                    vel: p.vel.to_array(),
                    mass: p.mass,
                })
                .collect(),
            actors: film.living().iter().map(ActorRecord::of).collect(),
            sound_events: film
                .ongoing()
                .iter()
                .filter(|e| e.start == time)
                .map(|e| SoundEventRecord {
                    sound: e.sound,
                    source: e.source,
                    pos: e.position.to_array(),
                })
                .collect(),
        })
    }

    /// The record as one line of JSON: `, ` and `: ` between items,
    /// numbers as Rust writes them, `null` for a number JSON cannot hold.
    pub fn to_line(&self) -> String {
        let mut out = Vec::new();
        let mut ser = serde_json::Serializer::with_formatter(&mut out, Spaced);
        self.serialize(&mut ser)
            .expect("a record of numbers always serializes");
        String::from_utf8(out).expect("serde_json writes UTF-8")
    }
}

/// `, ` before every item but the first.
fn comma<W: ?Sized + io::Write>(w: &mut W, first: bool) -> io::Result<()> {
    if first {
        Ok(())
    } else {
        w.write_all(b", ")
    }
}

/// JSON with a space after each `,` and `:`, as the trace has always
/// been written (so a reader diffing two traces sees the same bytes).
struct Spaced;

impl serde_json::ser::Formatter for Spaced {
    fn begin_array_value<W: ?Sized + io::Write>(
        &mut self,
        w: &mut W,
        first: bool,
    ) -> io::Result<()> {
        comma(w, first)
    }

    fn begin_object_key<W: ?Sized + io::Write>(
        &mut self,
        w: &mut W,
        first: bool,
    ) -> io::Result<()> {
        comma(w, first)
    }

    fn begin_object_value<W: ?Sized + io::Write>(&mut self, w: &mut W) -> io::Result<()> {
        w.write_all(b": ")
    }

    /// Shortest round-trip digits without a forced `.0` (`0`, `1.5`).
    fn write_f64<W: ?Sized + io::Write>(&mut self, w: &mut W, value: f64) -> io::Result<()> {
        write!(w, "{value}")
    }

    fn write_f32<W: ?Sized + io::Write>(&mut self, w: &mut W, value: f32) -> io::Result<()> {
        write!(w, "{value}")
    }
}
