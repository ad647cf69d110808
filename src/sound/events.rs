//! The sound event log (thesis table B7, DESIGN §5): the data types, the
//! builder the frame loop appends to, the reader and the writer.
//!
//! One keyword with its arguments per line; `#` starts a comment. Keywords
//! before the first `TIME` line may only declare sources and microphones;
//! positions and `PLAY` belong to a frame. The builder checks the same rules
//! as the reader, so every [`EventLog`] that exists is one the renderer can
//! use, and `parse(&write(log))` gives back `log` exactly.

use std::collections::{BTreeMap, BTreeSet};
use std::fmt::{self, Write as _};

use glam::DVec3;

use crate::source::{Diagnostic, Source};

/// Largest magnitude of a position or orientation: as in a definition
/// file (`lsys::scan::MAX_NUMBER`).
pub const MAX_VALUE: f64 = 1e30;

/// Latest `TIME`, in seconds: a year, far beyond any soundtrack.
pub const MAX_TIME: f64 = 3.2e7;

/// One line of the log after its keyword has been read.
#[derive(Debug, Clone, PartialEq)]
pub enum Event {
    /// `INIT_source n x y z ox oy oz`: a source that `SP` may move.
    Source {
        n: u32,
        position: DVec3,
        orientation: DVec3,
    },
    /// `CONST_S n x y z ox oy oz`: a source that never moves.
    ConstSource {
        n: u32,
        position: DVec3,
        orientation: DVec3,
    },
    /// `INIT_mic n x y z ox oy oz`.
    Mic {
        n: u32,
        position: DVec3,
        orientation: DVec3,
    },
    /// `INIT_ears l r` (lmfilm's): microphones l and r are a listener's
    /// left and right ears; each hears in the shadow of the head between
    /// them (docs/sound-events.md, "Ears").
    Ears { left: u32, right: u32 },
    /// `INIT_ambix n` (lmfilm's): microphone n is also heard as a
    /// first-order ambisonic master (AmbiX), turned as its orientation
    /// (`INIT_mic`'s, then each `MO`) says (docs/sound-events.md,
    /// "The ambisonic master").
    Ambix { n: u32 },
    /// `INIT_dist_matrix`: the thesis's renderer needed it after the
    /// declarations; kept for compatibility, it has no effect.
    DistMatrix,
    /// `SP n x y z`.
    SourcePosition { n: u32, position: DVec3 },
    /// `SO n ox oy oz` (recorded; sources are omnidirectional).
    SourceOrientation { n: u32, orientation: DVec3 },
    /// `MP n x y z`.
    MicPosition { n: u32, position: DVec3 },
    /// `MO n ox oy oz`: where microphone n faces (its ambisonic master's
    /// front; the other microphones are omnidirectional).
    MicOrientation { n: u32, orientation: DVec3 },
    /// `PLAY n FILE`: source n starts emitting FILE at the frame's time.
    Play { n: u32, file: String },
}

/// A `TIME t` line and the events that follow it up to the next one.
#[derive(Debug, Clone, PartialEq)]
pub struct TimedEvents {
    /// Seconds.
    pub time: f64,
    pub events: Vec<Event>,
}

/// Why the builder refused an event. `arg` is the argument at fault
/// (0 = the keyword), so the reader can put its caret under it.
#[derive(Debug, Clone, PartialEq)]
pub struct LogError {
    pub message: String,
    arg: usize,
}

impl LogError {
    fn new(arg: usize, message: impl Into<String>) -> Self {
        LogError {
            message: message.into(),
            arg,
        }
    }
}

impl fmt::Display for LogError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.message)
    }
}

impl std::error::Error for LogError {}

/// A source's kind, to refuse `SP` on a constant source.
#[derive(Debug, Clone, Copy, PartialEq)]
enum SourceKind {
    Moving,
    Constant,
}

/// A valid sound event log: declarations, then frames in increasing time.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct EventLog {
    init: Vec<Event>,
    frames: Vec<TimedEvents>,
    sources: BTreeMap<u32, SourceKind>,
    mics: BTreeSet<u32>,
    /// The microphones that are ears.
    ears: BTreeSet<u32>,
    /// The microphone of the ambisonic master.
    ambix: Option<u32>,
}

impl EventLog {
    pub fn new() -> Self {
        Self::default()
    }

    /// The declarations before the first `TIME` line.
    pub fn init(&self) -> &[Event] {
        &self.init
    }

    pub fn frames(&self) -> &[TimedEvents] {
        &self.frames
    }

    /// Every event in file order, with the time of its frame (`None`
    /// before the first `TIME`).
    pub fn events(&self) -> impl Iterator<Item = (Option<f64>, &Event)> {
        let init = self.init.iter().map(|e| (None, e));
        let framed = self
            .frames
            .iter()
            .flat_map(|f| f.events.iter().map(move |e| (Some(f.time), e)));
        init.chain(framed)
    }

    /// The microphone of the ambisonic master (`INIT_ambix`).
    pub fn ambix(&self) -> Option<u32> {
        self.ambix
    }

    /// Declared microphone numbers, ascending: the soundtrack's channel order.
    pub fn mic_numbers(&self) -> Vec<u32> {
        self.mics.iter().copied().collect()
    }

    /// The spacing of the last two `TIME` keys; one frame alone counts as
    /// the thesis's 1/25 s (sound frames of 0.04 s, 2.4.3).
    pub fn frame_interval(&self) -> f64 {
        match self.frames.as_slice() {
            [.., a, b] => b.time - a.time,
            _ => 0.04,
        }
    }

    /// The soundtrack's length in seconds: from 0 to the last `TIME` plus
    /// one frame interval, so frame n's sound ends where frame n+1 starts.
    /// No frame at all: 0.
    pub fn duration(&self) -> f64 {
        self.frames
            .last()
            .map_or(0.0, |f| f.time + self.frame_interval())
    }

    /// Starts a frame at `time` seconds: finite, ≥ 0, after the previous one.
    pub fn frame(&mut self, time: f64) -> Result<(), LogError> {
        if !(0.0..=MAX_TIME).contains(&time) {
            return Err(LogError::new(
                1,
                format!("TIME must be a time ≥ 0 and ≤ {MAX_TIME:e} seconds, got {time}"),
            ));
        }
        if let Some(last) = self.frames.last() {
            if time <= last.time {
                return Err(LogError::new(
                    1,
                    format!(
                        "TIME {time} does not come after the previous TIME {}; times must increase",
                        last.time
                    ),
                ));
            }
        }
        self.frames.push(TimedEvents {
            time,
            events: Vec::new(),
        });
        Ok(())
    }

    /// `INIT_source n x y z 0 0 0`.
    pub fn declare_source(&mut self, n: u32, position: impl Into<DVec3>) -> Result<(), LogError> {
        self.push(Event::Source {
            n,
            position: position.into(),
            orientation: DVec3::ZERO,
        })
    }

    /// `CONST_S n x y z 0 0 0`: a source that never moves.
    pub fn declare_constant_source(
        &mut self,
        n: u32,
        position: impl Into<DVec3>,
    ) -> Result<(), LogError> {
        self.push(Event::ConstSource {
            n,
            position: position.into(),
            orientation: DVec3::ZERO,
        })
    }

    /// `INIT_mic n x y z 0 0 0`.
    pub fn declare_mic(&mut self, n: u32, position: impl Into<DVec3>) -> Result<(), LogError> {
        self.push(Event::Mic {
            n,
            position: position.into(),
            orientation: DVec3::ZERO,
        })
    }

    /// `SP n x y z` in the current frame.
    pub fn source_position(&mut self, n: u32, position: impl Into<DVec3>) -> Result<(), LogError> {
        self.push(Event::SourcePosition {
            n,
            position: position.into(),
        })
    }

    /// `MP n x y z` in the current frame.
    pub fn mic_position(&mut self, n: u32, position: impl Into<DVec3>) -> Result<(), LogError> {
        self.push(Event::MicPosition {
            n,
            position: position.into(),
        })
    }

    /// `PLAY n FILE` in the current frame: FILE is a name without blanks,
    /// resolved when the log is rendered (see [`super::library`]).
    pub fn play(&mut self, n: u32, file: impl Into<String>) -> Result<(), LogError> {
        self.push(Event::Play {
            n,
            file: file.into(),
        })
    }

    /// Appends any event after checking it against what came before.
    pub fn push(&mut self, event: Event) -> Result<(), LogError> {
        self.check(&event)?;
        match &event {
            Event::Source { n, .. } => {
                self.sources.insert(*n, SourceKind::Moving);
            }
            Event::ConstSource { n, .. } => {
                self.sources.insert(*n, SourceKind::Constant);
            }
            Event::Mic { n, .. } => {
                self.mics.insert(*n);
            }
            Event::Ears { left, right } => {
                self.ears.extend([*left, *right]);
            }
            Event::Ambix { n } => self.ambix = Some(*n),
            _ => {}
        }
        match self.frames.last_mut() {
            Some(frame) => frame.events.push(event),
            None => self.init.push(event),
        }
        Ok(())
    }

    fn check(&self, event: &Event) -> Result<(), LogError> {
        let finite = |v: DVec3, first_arg: usize, what: &str| match v
            .to_array()
            .iter()
            .position(|x| !(x.is_finite() && x.abs() <= MAX_VALUE))
        {
            Some(i) => Err(LogError::new(
                first_arg + i,
                format!("the {what} must be finite and within ±{MAX_VALUE:e}, got {v}"),
            )),
            None => Ok(()),
        };
        let in_frame = |keyword: &str| {
            if self.frames.is_empty() {
                Err(LogError::new(
                    0,
                    format!("{keyword} before the first TIME line: it must belong to a frame"),
                ))
            } else {
                Ok(())
            }
        };
        let source = |n: u32, keyword: &str| {
            match self.sources.get(&n) {
            None => Err(LogError::new(
                1,
                format!("{keyword}: source {n} is not declared; declare it first with INIT_source or CONST_S"),
            )),
            Some(SourceKind::Constant) if keyword != "PLAY" => Err(LogError::new(
                1,
                format!("{keyword}: source {n} was declared constant (CONST_S) and cannot move or turn; declare it with INIT_source"),
            )),
            Some(_) => Ok(()),
        }
        };
        let mic = |n: u32, keyword: &str| {
            if self.mics.contains(&n) {
                Ok(())
            } else {
                Err(LogError::new(
                    1,
                    format!(
                        "{keyword}: microphone {n} is not declared; declare it first with INIT_mic"
                    ),
                ))
            }
        };
        match event {
            Event::Source {
                n,
                position,
                orientation,
            }
            | Event::ConstSource {
                n,
                position,
                orientation,
            } => {
                if self.sources.contains_key(n) {
                    return Err(LogError::new(1, format!("source {n} is declared twice")));
                }
                finite(*position, 2, "position")?;
                finite(*orientation, 5, "orientation")
            }
            Event::Mic {
                n,
                position,
                orientation,
            } => {
                if self.mics.contains(n) {
                    return Err(LogError::new(
                        1,
                        format!("microphone {n} is declared twice"),
                    ));
                }
                finite(*position, 2, "position")?;
                finite(*orientation, 5, "orientation")
            }
            Event::Ears { left, right } => {
                if !self.frames.is_empty() {
                    return Err(LogError::new(
                        0,
                        "INIT_ears after the first TIME line: a listener's ears are declared with the microphones",
                    ));
                }
                for (k, n) in [(1, left), (2, right)] {
                    mic(*n, "INIT_ears").map_err(|e| LogError::new(k, e.message))?;
                    if self.ears.contains(n) {
                        return Err(LogError::new(
                            k,
                            format!("INIT_ears: microphone {n} is already an ear"),
                        ));
                    }
                    if self.ambix == Some(*n) {
                        return Err(LogError::new(
                            k,
                            format!("INIT_ears: microphone {n} makes the ambisonic master; an ear needs a microphone of its own"),
                        ));
                    }
                }
                if left == right {
                    return Err(LogError::new(
                        2,
                        format!("INIT_ears: microphone {left} cannot be both ears"),
                    ));
                }
                Ok(())
            }
            Event::Ambix { n } => {
                if !self.frames.is_empty() {
                    return Err(LogError::new(
                        0,
                        "INIT_ambix after the first TIME line: the ambisonic microphone is declared with the microphones",
                    ));
                }
                mic(*n, "INIT_ambix")?;
                if let Some(m) = self.ambix {
                    return Err(LogError::new(
                        1,
                        format!("INIT_ambix: microphone {m} already makes the ambisonic master; a film has one"),
                    ));
                }
                if self.ears.contains(n) {
                    return Err(LogError::new(
                        1,
                        format!("INIT_ambix: microphone {n} is an ear; the ambisonic master needs a microphone of its own"),
                    ));
                }
                Ok(())
            }
            Event::DistMatrix => Ok(()),
            Event::SourcePosition { n, position } => {
                in_frame("SP")?;
                source(*n, "SP")?;
                finite(*position, 2, "position")
            }
            Event::SourceOrientation { n, orientation } => {
                in_frame("SO")?;
                source(*n, "SO")?;
                finite(*orientation, 2, "orientation")
            }
            Event::MicPosition { n, position } => {
                in_frame("MP")?;
                mic(*n, "MP")?;
                finite(*position, 2, "position")
            }
            Event::MicOrientation { n, orientation } => {
                in_frame("MO")?;
                mic(*n, "MO")?;
                finite(*orientation, 2, "orientation")
            }
            Event::Play { n, file } => {
                in_frame("PLAY")?;
                source(*n, "PLAY")?;
                if file.is_empty() || file.starts_with('#') || file.chars().any(char::is_whitespace)
                {
                    return Err(LogError::new(
                        2,
                        format!("PLAY: the file name {file:?} must be non-empty, without blanks, and not start with #"),
                    ));
                }
                Ok(())
            }
        }
    }
}

/// The keywords, their canonical spelling and their argument names.
const KEYWORDS: &[(&str, &str)] = &[
    ("TIME", "t"),
    ("INIT_source", "n x y z ox oy oz"),
    ("CONST_S", "n x y z ox oy oz"),
    ("INIT_mic", "n x y z ox oy oz"),
    ("INIT_ears", "l r"),
    ("INIT_ambix", "n"),
    ("INIT_dist_matrix", ""),
    ("SP", "n x y z"),
    ("SO", "n ox oy oz"),
    ("MP", "n x y z"),
    ("MO", "n ox oy oz"),
    ("PLAY", "n FILE"),
];

/// A parsed events file with its text, so that a later error about one of
/// its `PLAY` lines (a sound file that is missing) can point at the line.
#[derive(Debug, Clone)]
pub struct EventsFile {
    pub source: Source,
    pub log: EventLog,
    /// Byte offset of each `PLAY`'s file name, in log order.
    play_offsets: Vec<usize>,
}

impl EventsFile {
    /// Reads the log in `source`; errors are `file:line:column: message`.
    pub fn parse(source: Source) -> Result<Self, Diagnostic> {
        let mut log = EventLog::new();
        let mut play_offsets = Vec::new();
        let mut line_start = 0;
        for line in source.text.split_inclusive('\n') {
            let tokens = tokens(line, line_start);
            line_start += line.len();
            let Some(&(key_at, keyword)) = tokens.first() else {
                continue;
            };
            let Some(&(canonical, arg_names)) = KEYWORDS
                .iter()
                .find(|(k, _)| k.eq_ignore_ascii_case(keyword))
            else {
                return Err(source.error(
                    key_at,
                    format!(
                        "unknown keyword {keyword:?}; the keywords are {}",
                        KEYWORDS
                            .iter()
                            .map(|(k, _)| *k)
                            .collect::<Vec<_>>()
                            .join(", ")
                    ),
                ));
            };
            let want = arg_names.split_whitespace().count();
            let args = &tokens[1..];
            if args.len() != want {
                let at = args.get(want).map_or(key_at, |a| a.0);
                return Err(source.error(
                    at,
                    format!(
                        "{canonical} takes {want} argument{} ({canonical} {arg_names}), got {}",
                        if want == 1 { "" } else { "s" },
                        args.len()
                    ),
                ));
            }
            let line = read_line(canonical, args).map_err(|(i, m)| source.error(args[i].0, m))?;
            let result = match line {
                Line::Time(t) => log.frame(t).map(|()| None),
                Line::Event(e) => {
                    let play = matches!(e, Event::Play { .. });
                    log.push(e).map(|()| play.then(|| args[1].0))
                }
            };
            match result {
                Ok(Some(offset)) => play_offsets.push(offset),
                Ok(None) => {}
                Err(e) => {
                    let at = if e.arg == 0 {
                        key_at
                    } else {
                        args[e.arg - 1].0
                    };
                    return Err(source.error(at, e.message));
                }
            }
        }
        Ok(EventsFile {
            source,
            log,
            play_offsets,
        })
    }

    /// A diagnostic at the file name of the `k`-th `PLAY` (0-based).
    pub fn play_error(&self, k: usize, message: impl Into<String>) -> Diagnostic {
        let offset = self.play_offsets.get(k).copied().unwrap_or(0);
        self.source.error(offset, message)
    }
}

/// Reads the log in `text`; `path` names the file in error messages.
pub fn parse(text: &str, path: &str) -> Result<EventLog, Diagnostic> {
    EventsFile::parse(Source::new(path, text)).map(|f| f.log)
}

/// The log as text, one keyword per line; numbers in Rust's shortest
/// round-trip form, so [`parse`] reads back the same values.
pub fn write(log: &EventLog) -> String {
    let mut out = String::new();
    for e in &log.init {
        write_event(&mut out, e);
    }
    for frame in &log.frames {
        let _ = writeln!(out, "TIME {}", frame.time);
        for e in &frame.events {
            write_event(&mut out, e);
        }
    }
    out
}

fn write_event(out: &mut String, e: &Event) {
    let v = |v: &DVec3| format!("{} {} {}", v.x, v.y, v.z);
    let _ = match e {
        Event::Source {
            n,
            position,
            orientation,
        } => writeln!(out, "INIT_source {n} {} {}", v(position), v(orientation)),
        Event::ConstSource {
            n,
            position,
            orientation,
        } => writeln!(out, "CONST_S {n} {} {}", v(position), v(orientation)),
        Event::Mic {
            n,
            position,
            orientation,
        } => writeln!(out, "INIT_mic {n} {} {}", v(position), v(orientation)),
        Event::Ears { left, right } => writeln!(out, "INIT_ears {left} {right}"),
        Event::Ambix { n } => writeln!(out, "INIT_ambix {n}"),
        Event::DistMatrix => writeln!(out, "INIT_dist_matrix"),
        Event::SourcePosition { n, position } => writeln!(out, "SP {n} {}", v(position)),
        Event::SourceOrientation { n, orientation } => writeln!(out, "SO {n} {}", v(orientation)),
        Event::MicPosition { n, position } => writeln!(out, "MP {n} {}", v(position)),
        Event::MicOrientation { n, orientation } => writeln!(out, "MO {n} {}", v(orientation)),
        Event::Play { n, file } => writeln!(out, "PLAY {n} {file}"),
    };
}

/// The whitespace-separated tokens of a line with their byte offsets in
/// the file; a token starting with `#` ends the line.
fn tokens(line: &str, line_start: usize) -> Vec<(usize, &str)> {
    let mut out = Vec::new();
    let mut start = None;
    for (i, c) in line.char_indices().chain([(line.len(), ' ')]) {
        match (start, c.is_whitespace()) {
            (None, false) if c == '#' => break,
            (None, false) => start = Some(i),
            (Some(s), true) => {
                out.push((line_start + s, &line[s..i]));
                start = None;
            }
            _ => {}
        }
    }
    out
}

type Token<'a> = (usize, &'a str);

/// A keyword line read, not yet checked against the log.
enum Line {
    Time(f64),
    Event(Event),
}

/// The meaning of a keyword line whose argument count is right. Errors
/// carry the index of the argument at fault.
fn read_line(keyword: &str, args: &[Token]) -> Result<Line, (usize, String)> {
    let num = |i: usize| number(args[i]).map_err(|m| (i, m));
    let vec = |i: usize| Ok::<_, (usize, String)>(DVec3::new(num(i)?, num(i + 1)?, num(i + 2)?));
    let id = |i: usize| {
        args[i].1.parse::<u32>().map_err(|_| {
            (
                i,
                format!(
                    "{keyword}: {:?} is not a source or microphone number (an integer ≥ 0)",
                    args[i].1
                ),
            )
        })
    };
    Ok(Line::Event(match keyword {
        "TIME" => return Ok(Line::Time(num(0)?)),
        "INIT_source" => Event::Source {
            n: id(0)?,
            position: vec(1)?,
            orientation: vec(4)?,
        },
        "CONST_S" => Event::ConstSource {
            n: id(0)?,
            position: vec(1)?,
            orientation: vec(4)?,
        },
        "INIT_mic" => Event::Mic {
            n: id(0)?,
            position: vec(1)?,
            orientation: vec(4)?,
        },
        "INIT_ears" => Event::Ears {
            left: id(0)?,
            right: id(1)?,
        },
        "INIT_ambix" => Event::Ambix { n: id(0)? },
        "INIT_dist_matrix" => Event::DistMatrix,
        "SP" => Event::SourcePosition {
            n: id(0)?,
            position: vec(1)?,
        },
        "SO" => Event::SourceOrientation {
            n: id(0)?,
            orientation: vec(1)?,
        },
        "MP" => Event::MicPosition {
            n: id(0)?,
            position: vec(1)?,
        },
        "MO" => Event::MicOrientation {
            n: id(0)?,
            orientation: vec(1)?,
        },
        _ => Event::Play {
            n: id(0)?,
            file: args[1].1.to_string(),
        },
    }))
}

/// A finite decimal number.
fn number((_, text): Token) -> Result<f64, String> {
    match text.parse::<f64>() {
        Ok(x) if x.is_finite() => Ok(x),
        _ => Err(format!("{text:?} is not a finite number")),
    }
}
