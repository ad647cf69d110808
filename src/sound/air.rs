//! The sound event handler of 2.4.2 ("air"): the table of on-going sound
//! events the actors hear (`?60`–`?62`), and the frame-by-frame event log
//! the soundtrack is rendered from (table B7).
//!
//! Each frame the log gets `TIME t`, the position of every microphone
//! (`MP`) and of every source that moved (`SP`), and a `PLAY` for each
//! event started. Microphones are declared by `Sound_event_file`'s
//! `INIT_mic`; `l` par3 = 8/10 moves them. A scene that declares none
//! gets microphone 0 at the camera, as the thesis rendered its films.

use std::collections::BTreeMap;
use std::path::PathBuf;

use glam::DVec3;

use super::events::{Event, EventLog, LogError};
use super::library::{self, Library};
use crate::lsys::options::Command;

/// Source of the sounds `T` par1 = 0 plays back with no place: it sits
/// at the microphones' centre, so it is heard without delay or Doppler.
pub const AMBIENT_SOURCE: u32 = 999_999;

/// Half the distance between a listener's ears, metres (an adult head's
/// 17.5 cm).
pub const HALF_HEAD: f64 = 0.0875;

/// One on-going sound event.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ongoing {
    pub sound: u32,
    pub source: u32,
    pub position: DVec3,
    pub start: f64,
    pub end: f64,
}

pub struct Air {
    log: EventLog,
    library: Library,
    search: Vec<PathBuf>,
    /// Length in seconds of each sound file met so far.
    durations: BTreeMap<u32, Option<f64>>,
    ongoing: Vec<Ongoing>,
    /// The on-going events as the audition sensors last heard them
    /// ([`Air::sense`]).
    heard: Vec<Ongoing>,
    /// How many events at the end of `ongoing` started after the last
    /// reading, and those of them that ended before the next: a sound
    /// shorter than a frame is still heard once.
    fresh: usize,
    missed: Vec<Ongoing>,
    mics: BTreeMap<u32, DVec3>,
    /// Microphones that follow the camera (none declared: microphone 0,
    /// or the two ears of `INIT_ears`).
    follow_camera: bool,
    /// The listener's ears (`INIT_ears l r`).
    ears: Option<(u32, u32)>,
    /// The ambisonic microphone (`INIT_ambix n`), when it follows the
    /// camera: it faces where the camera looks (`MO` each frame).
    ambix: Option<u32>,
    sources: BTreeMap<u32, DVec3>,
    /// Sources whose position changed this frame.
    moved: BTreeMap<u32, DVec3>,
    /// The last move of each source this frame (`T` par1 = 2): where to,
    /// and how many on-going events there were then. Those events take
    /// the position at the end of the frame, so a move costs O(log n)
    /// rather than a walk over every on-going event.
    moves: BTreeMap<u32, (usize, DVec3)>,
    time: f64,
    warnings: Vec<String>,
}

/// Numbers `at..at + 3` of a command (the options parser checked the
/// count; a short list reads as zeros rather than panicking).
fn vec3(c: &Command, at: usize) -> DVec3 {
    let n = |i: usize| c.numbers.get(at + i).copied().unwrap_or(0.0);
    DVec3::new(n(0), n(1), n(2))
}

impl Air {
    /// A handler whose log starts with the initialisations of a
    /// `Sound_event_file` option (`INIT_mic`, `INIT_source`, `CONST_S`,
    /// `INIT_dist_matrix`); sound files are looked up along `search`.
    /// An error carries where its item is in the definition's text.
    pub fn new(
        inits: &[Command],
        library: Library,
        search: Vec<PathBuf>,
    ) -> Result<Air, (Option<usize>, String)> {
        let mut air = Air {
            log: EventLog::new(),
            library,
            search,
            durations: BTreeMap::new(),
            ongoing: Vec::new(),
            heard: Vec::new(),
            fresh: 0,
            missed: Vec::new(),
            mics: BTreeMap::new(),
            follow_camera: false,
            ears: None,
            ambix: None,
            sources: BTreeMap::new(),
            moved: BTreeMap::new(),
            moves: BTreeMap::new(),
            time: 0.0,
            warnings: Vec::new(),
        };
        let bad =
            |c: &Command, e: LogError| (Some(c.at), format!("Sound_event_file: {} {e}", c.name));
        let mut ears = Vec::new();
        let mut ambix = Vec::new();
        for c in inits {
            let n = c.numbers.first().map_or(0, |&n| n as u32);
            let (position, orientation) = (vec3(c, 1), vec3(c, 4));
            let event = match c.name.to_ascii_uppercase().as_str() {
                "INIT_MIC" => {
                    air.mics.insert(n, position);
                    Event::Mic { n, position, orientation }
                }
                "INIT_SOURCE" => {
                    air.sources.insert(n, position);
                    Event::Source { n, position, orientation }
                }
                "CONST_S" => {
                    air.sources.insert(n, position);
                    Event::ConstSource { n, position, orientation }
                }
                "INIT_DIST_MATRIX" => Event::DistMatrix,
                "INIT_EARS" => {
                    // Declared once the microphones are: below.
                    let r = c.numbers.get(1).map_or(0, |&n| n as u32);
                    ears.push((n, r, c.at));
                    continue;
                }
                "INIT_AMBIX" => {
                    ambix.push((n, c.at));
                    continue;
                }
                _ => {
                    return Err((Some(c.at), format!(
                        "Sound_event_file: `{}` is not an initialisation (INIT_mic, INIT_source, CONST_S, INIT_ears, INIT_ambix, INIT_dist_matrix); the animation writes the rest",
                        c.name
                    )))
                }
            };
            let r = air.log.push(event);
            r.map_err(|e| bad(c, e))?;
        }
        if air.mics.is_empty() {
            air.follow_camera = true;
            if let Some(&(_, _, at)) = ears.get(1) {
                return Err((
                    Some(at),
                    "Sound_event_file: INIT_ears: the camera has one pair of ears; declare microphones (INIT_mic) for more listeners".into(),
                ));
            }
            if let Some(&(n, at)) = ambix.get(1) {
                return Err((
                    Some(at),
                    format!("Sound_event_file: INIT_ambix {n}: microphone {} already makes the ambisonic master; a film has one", ambix[0].0),
                ));
            }
            air.ears = ears.first().map(|&(l, r, _)| (l, r));
            air.ambix = ambix.first().map(|&(n, _)| n);
            let mut camera = air.ears.map_or(vec![0], |(l, r)| vec![l, r]);
            // The ambisonic microphone at the eye: the camera's own
            // microphone 0 when there are no ears, else one more.
            camera.extend(air.ambix.filter(|n| !camera.contains(n)));
            for m in camera {
                if air.mics.insert(m, DVec3::ZERO).is_none() {
                    let declared = air.log.declare_mic(m, DVec3::ZERO);
                    declared.map_err(|e| (None, e.to_string()))?;
                }
            }
        }
        for (left, right, at) in ears {
            air.log
                .push(Event::Ears { left, right })
                .map_err(|e| (Some(at), format!("Sound_event_file: {e}")))?;
        }
        for (n, at) in ambix {
            air.log
                .push(Event::Ambix { n })
                .map_err(|e| (Some(at), format!("Sound_event_file: {e}")))?;
        }
        Ok(air)
    }

    /// Starts frame time `t`; events that have ended leave the table.
    pub fn begin_frame(&mut self, t: f64) -> Result<(), String> {
        self.time = t;
        self.log.frame(t).map_err(|e| e.to_string())?;
        self.apply_moves();
        let fresh = &self.ongoing[self.ongoing.len() - self.fresh..];
        self.missed.extend(fresh.iter().filter(|e| e.end <= t));
        self.fresh = fresh.iter().filter(|e| e.end > t).count();
        self.ongoing.retain(|e| e.end > t);
        Ok(())
    }

    /// Microphone `mic` placed at `p` (`l` par3 = 8, 10).
    pub fn microphone(&mut self, mic: u32, p: DVec3) {
        self.mics.insert(mic, p);
    }

    /// Source `source` at `p` this frame.
    fn place(&mut self, source: u32, p: DVec3) -> Result<(), String> {
        match self.sources.insert(source, p) {
            None => self
                .log
                .declare_source(source, p)
                .map_err(|e| e.to_string()),
            Some(old) if old != p => {
                self.moved.insert(source, p);
                Ok(())
            }
            Some(_) => Ok(()),
        }
    }

    /// Length of sound `n`'s file, None when the library lacks it (warned
    /// once).
    fn duration(&mut self, n: u32) -> Option<(f64, String)> {
        let Some(file) = self.library.file_name(n).map(str::to_string) else {
            if self.durations.insert(n, None).is_none() {
                self.warnings
                    .push(format!("sound {n} is not in the sound library: skipped"));
            }
            return None;
        };
        if !self.durations.contains_key(&n) {
            let d = library::resolve(&file, &self.search).and_then(|f| f.duration().ok());
            if d.is_none() {
                self.warnings.push(format!(
                    "sound {n} ({file}) was not found or is not a WAV file: skipped"
                ));
            }
            self.durations.insert(n, d);
        }
        self.durations[&n].map(|d| (d, file))
    }

    /// Carries out a `T` request at the current frame.
    pub fn play(&mut self, sound: u32, source: u32, at: DVec3) -> Result<(), String> {
        let Some((length, file)) = self.duration(sound) else {
            return Ok(());
        };
        self.place(source, at)?;
        self.ongoing.push(Ongoing {
            sound,
            source,
            position: at,
            start: self.time,
            end: self.time + length,
        });
        self.fresh += 1;
        self.log.play(source, file).map_err(|e| e.to_string())
    }

    /// Moves source `source` (`T` par1 = 2), and with it the events it
    /// emits (at the end of the frame: [`Air::apply_moves`]).
    pub fn move_source(&mut self, source: u32, at: DVec3) -> Result<(), String> {
        self.place(source, at)?;
        self.moves.insert(source, (self.ongoing.len(), at));
        Ok(())
    }

    /// Each event started before its source's last move takes the
    /// position of that move; the events started after it keep theirs.
    fn apply_moves(&mut self) {
        if self.moves.is_empty() {
            return;
        }
        for (k, e) in self.ongoing.iter_mut().enumerate() {
            if let Some(&(before, at)) = self.moves.get(&e.source) {
                if k < before {
                    e.position = at;
                }
            }
        }
        self.moves.clear();
    }

    /// The microphones' centre: where sounds with no place are heard.
    pub fn centre(&self) -> DVec3 {
        self.mics.values().sum::<DVec3>() / self.mics.len().max(1) as f64
    }

    /// Writes the frame's microphone and moved source positions; the
    /// camera ended the frame at `eye`, its image's right along `right`
    /// and looking along `forward` (unit vectors: the ears on the camera
    /// are either side of `eye` along `right`, its ambisonic microphone
    /// faces `forward`).
    pub fn end_frame(
        &mut self,
        eye: DVec3,
        (right, forward): (DVec3, DVec3),
    ) -> Result<(), String> {
        self.apply_moves();
        match (self.follow_camera, self.ears) {
            (true, Some((l, r))) => {
                self.mics.insert(l, eye - right * HALF_HEAD);
                self.mics.insert(r, eye + right * HALF_HEAD);
            }
            (true, None) => {
                self.mics.insert(0, eye);
            }
            _ => {}
        }
        let facing = self.ambix.filter(|_| self.follow_camera);
        if let Some(n) = facing {
            self.mics.insert(n, eye);
        }
        if self.ongoing.iter().any(|e| e.source == AMBIENT_SOURCE) {
            let c = self.centre();
            self.place(AMBIENT_SOURCE, c)?;
        }
        for (&m, &p) in &self.mics {
            self.log.mic_position(m, p).map_err(|e| e.to_string())?;
        }
        if let Some(n) = facing {
            let turned = Event::MicOrientation {
                n,
                orientation: forward,
            };
            self.log.push(turned).map_err(|e| e.to_string())?;
        }
        for (s, p) in std::mem::take(&mut self.moved) {
            self.log.source_position(s, p).map_err(|e| e.to_string())?;
        }
        Ok(())
    }

    /// The audition sensors take their reading (DESIGN §1 step 3): what
    /// `?60`–`?62` hear from this frame's derivation through the next
    /// frame's interpretation, while new events start. An event that
    /// started after the last reading and has already ended is heard too.
    pub fn sense(&mut self) {
        self.heard.clone_from(&self.ongoing);
        if !self.missed.is_empty() {
            self.heard.append(&mut self.missed);
            self.heard.sort_by(|a, b| a.start.total_cmp(&b.start));
        }
        self.fresh = 0;
    }

    /// The on-going events at the last reading, oldest first.
    pub fn heard(&self) -> &[Ongoing] {
        &self.heard
    }

    /// The on-going events, at their positions as of the last
    /// [`Air::end_frame`].
    pub fn ongoing(&self) -> &[Ongoing] {
        &self.ongoing
    }

    /// Warnings gathered so far (unknown sounds), each once.
    pub fn take_warnings(&mut self) -> Vec<String> {
        std::mem::take(&mut self.warnings)
    }

    pub fn log(&self) -> &EventLog {
        &self.log
    }
}

/// `?61` over a table of on-going events: the sound `source` emits, the
/// latest started.
pub fn sound_of_source(ongoing: &[Ongoing], source: u32) -> Option<u32> {
    let e = ongoing.iter().rev().find(|e| e.source == source)?;
    Some(e.sound)
}

/// `?62` over a table of on-going events: the source emitting `sound`,
/// the latest started.
pub fn source_of_sound(ongoing: &[Ongoing], sound: u32) -> Option<u32> {
    let e = ongoing.iter().rev().find(|e| e.sound == sound)?;
    Some(e.source)
}
