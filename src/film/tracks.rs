//! Imported and exported data of a film (thesis 6.3.3): the data
//! channels `?50` reads ([`super::channels`]) and actor trajectories.
//!
//! A trajectory file is ASCII text, one record per line:
//!
//! ```text
//! Actor <actor> <state> <time> <x> <y> <z>
//! ```
//!
//! `import_trace actor FILE` reads the records of `actor` (others are
//! ignored) when the film loads; `$` par2 = 5 par3 = actor puts the
//! turtle on that trajectory at the frame's time. `trace_actor actor
//! FILE` collects, at each frame where an `I` symbol is interpreted, the
//! actor's record; `derive` writes them into the output folder.

use std::path::{Component, Path};

use glam::DVec3;

use super::channels::{self, number, read_source, words, Channel};
use crate::actors::live::Living;
use crate::error::{Error, Result};
use crate::lsys::options::OptionItem;
use crate::lsys::Animation;
use crate::source::{Diagnostic, FileRef, Source};

/// An imported trajectory: times strictly increasing.
#[derive(Debug, Clone, PartialEq)]
pub struct ActorTrack {
    pub actor: i64,
    pub times: Vec<f64>,
    pub points: Vec<DVec3>,
    /// Direction of motion of each segment (between record k and k+1);
    /// a stationary segment keeps the one before it (+x at the start).
    dirs: Vec<DVec3>,
}

impl ActorTrack {
    fn new(actor: i64, times: Vec<f64>, points: Vec<DVec3>) -> Self {
        let mut dirs = Vec::with_capacity(points.len().saturating_sub(1));
        let mut last = DVec3::X;
        for w in points.windows(2) {
            let d = w[1] - w[0];
            if d.length_squared() > 0.0 && d.is_finite() {
                last = d.normalize();
            }
            dirs.push(last);
        }
        ActorTrack {
            actor,
            times,
            points,
            dirs,
        }
    }

    /// Position and direction of motion at time `t`: linear between the
    /// records around `t`, clamped at both ends.
    pub fn at(&self, t: f64) -> (DVec3, DVec3) {
        let n = self.points.len();
        let first_dir = self.dirs.first().copied().unwrap_or(DVec3::X);
        let last_dir = self.dirs.last().copied().unwrap_or(DVec3::X);
        if t.is_nan() || t <= self.times[0] {
            return (self.points[0], first_dir);
        }
        if t >= self.times[n - 1] {
            return (self.points[n - 1], last_dir);
        }
        // times[k] <= t < times[k + 1]
        let k = self.times.partition_point(|&x| x <= t) - 1;
        let f = (t - self.times[k]) / (self.times[k + 1] - self.times[k]);
        let (a, b) = (self.points[k], self.points[k + 1]);
        let p = if f == 0.0 { a } else { a + (b - a) * f };
        (p, self.dirs[k])
    }
}

/// Parses a trajectory file, keeping the records of `actor`; `file` is
/// where the scene names it (for a file without any of them).
pub fn parse_trace(
    src: &Source,
    actor: i64,
    file: &FileRef,
) -> std::result::Result<ActorTrack, Diagnostic> {
    let (mut times, mut points) = (Vec::new(), Vec::new());
    let format = "a record is `Actor <actor> <state> <time> <x> <y> <z>`";
    let mut offset = 0;
    for line in src.text.split_inclusive('\n') {
        let base = offset;
        offset += line.len();
        let ws: Vec<(usize, &str)> = words(line).map(|(at, w)| (base + at, w)).collect();
        let Some(&(at, head)) = ws.first() else {
            continue;
        };
        if head != "Actor" {
            return Err(src.error(at, format!("`{head}` is not a record; {format}")));
        }
        if ws.len() < 7 {
            let end = base + line.trim_end().len();
            return Err(src.error(
                end,
                format!("the record has {} of its 7 words; {format}", ws.len()),
            ));
        }
        if let Some(&(at, w)) = ws.get(7) {
            return Err(src.error(at, format!("`{w}` after the record; {format}")));
        }
        let int = |(at, w): (usize, &str), what: &str| {
            w.parse::<i64>()
                .map_err(|_| src.error(at, format!("{what} `{w}` is not a whole number")))
        };
        let id = int(ws[1], "the actor number")?;
        int(ws[2], "the state")?;
        let t = number(src, ws[3].0, ws[3].1, "the time")?;
        let mut p = [0.0; 3];
        for (k, v) in p.iter_mut().enumerate() {
            let (at, w) = ws[4 + k];
            *v = number(src, at, w, "a coordinate")?;
        }
        if id != actor {
            continue;
        }
        if times.last().is_some_and(|&last| t <= last) {
            return Err(src.error(
                ws[3].0,
                format!(
                    "time {t} of actor {actor} is not after its record before ({}); records of an actor go forward in time",
                    times.last().copied().unwrap_or_default()
                ),
            ));
        }
        times.push(t);
        points.push(DVec3::from_array(p));
    }
    if times.is_empty() {
        return Err(file.error(format!("{} holds no record of actor {actor}", src.name)));
    }
    Ok(ActorTrack::new(actor, times, points))
}

/// A `trace_actor` declaration and the records `I` collected for it.
#[derive(Debug, Clone)]
pub struct Export {
    pub actor: i64,
    pub file: FileRef,
    /// The records so far, one line each.
    pub text: String,
    /// The last frame a record was written for.
    last: Option<u64>,
}

/// The film's imported and exported data (owned by the film; the window
/// lends it to the lower layers).
#[derive(Debug, Clone, Default)]
pub struct Tracks {
    pub channels: Vec<Channel>,
    pub imports: Vec<ActorTrack>,
    pub exports: Vec<Export>,
    /// The time of the frame being interpreted.
    pub time: f64,
    /// Whether an `I` asked for the actors' records in this frame.
    pub wanted: bool,
}

/// The longest name of one folder or file in a trace file's path (most
/// file systems' own limit) and of the whole path.
const MAX_COMPONENT: usize = 255;
const MAX_PATH: usize = 1024;

/// Why `name` cannot be written into the output folder, if it cannot:
/// it must be a relative path inside it naming a file (no `/` at the
/// end), of names the file system takes, and not one of lmfilm's own.
pub fn output_name(name: &str) -> std::result::Result<(), String> {
    let path = Path::new(name);
    if name.is_empty() || !path.components().all(|c| matches!(c, Component::Normal(_))) {
        return Err(format!(
            "the trace file `{name}` is not a relative path inside the output folder (no `..`, no leading `/`); nothing is written outside it"
        ));
    }
    if name.ends_with('/') || name.ends_with("/.") {
        return Err(format!(
            "the trace file `{name}` names a folder; name a file in it, e.g. `{}/actor.trace`",
            name.trim_end_matches(['/', '.'])
        ));
    }
    if let Some(long) = path.iter().find(|c| c.len() > MAX_COMPONENT) {
        return Err(format!(
            "the trace file `{name}` has a name of {} bytes (`{}…`); a file system takes at most {MAX_COMPONENT}",
            long.len(),
            long.to_string_lossy().chars().take(16).collect::<String>()
        ));
    }
    if name.len() > MAX_PATH {
        return Err(format!(
            "the trace file's path is {} bytes long; at most {MAX_PATH}",
            name.len()
        ));
    }
    let first = path
        .components()
        .next()
        .map(|c| c.as_os_str().to_string_lossy().into_owned())
        .unwrap_or_default();
    if super::names::is_own(&first, name) {
        return Err(format!(
            "the trace file `{name}` would overwrite lmfilm's own outputs; name it otherwise, e.g. `actor.trace`"
        ));
    }
    Ok(())
}

/// Whether the trace file `file` can be written in the output folder
/// `dir` as it is now: no folder or file on its way is a link (lmfilm
/// never writes through one: it could lead out of the folder), a file,
/// where the way goes on, or a folder, where the trace goes. The error
/// points at the scene's line, and is said before the film derives.
pub fn check_target(dir: &Path, file: &FileRef) -> Result<()> {
    let parts: Vec<_> = Path::new(&file.name).iter().collect();
    let mut at = dir.to_path_buf();
    for (k, part) in parts.iter().enumerate() {
        at.push(part);
        let Ok(meta) = std::fs::symlink_metadata(&at) else {
            return Ok(()); // nothing there yet: lmfilm makes it
        };
        let last = k + 1 == parts.len();
        let problem = if meta.file_type().is_symlink() {
            "is a link; lmfilm never writes through a link (it could lead out of the output folder)"
        } else if !last && !meta.is_dir() {
            "is a file, where the trace's path needs a folder"
        } else if last && !meta.is_file() {
            "is a folder or a special file, not a file lmfilm can write"
        } else {
            continue;
        };
        let msg = format!(
            "the trace file `{}`: {} {problem}; remove it or name the trace otherwise",
            file.name,
            at.display()
        );
        return Err(file.error(msg).into());
    }
    Ok(())
}

impl Tracks {
    /// Reads the channels and imported trajectories of `anim` (relative
    /// to the folder of the file that declares them) and checks the
    /// exported ones: an actor `living` has, a name inside the output
    /// folder, each file once.
    pub fn load(anim: &Animation, living: &[Living]) -> Result<Tracks> {
        let mut t = Tracks {
            channels: channels::load(anim)?,
            ..Tracks::default()
        };
        for ls in &anim.systems {
            let dir = Path::new(&ls.def.name).parent().unwrap_or(Path::new("."));
            for o in &ls.def.options {
                match o {
                    OptionItem::ImportTrace { actor, file } => {
                        let src = read_source(dir, file, "trace file")?;
                        t.imports.push(parse_trace(&src, *actor, file)?);
                    }
                    OptionItem::TraceActor { actor, file } => {
                        if !living.iter().any(|l| l.id as i64 == *actor) {
                            let msg = format!(
                                "`trace_actor` names actor {actor}, but the film has {} actor(s) (NBR_actors)",
                                living.len()
                            );
                            return Err(file.error(msg).into());
                        }
                        output_name(&file.name).map_err(|m| Error::from(file.error(m)))?;
                        if t.exports.iter().any(|e| e.file.name == file.name) {
                            let msg = format!("`{}` is already a trace file", file.name);
                            return Err(file.error(msg).into());
                        }
                        // A trace cannot be a file and a folder of another.
                        let inside = |a: &str, b: &str| Path::new(b).starts_with(a) && a != b;
                        if let Some(e) = t.exports.iter().find(|e| {
                            inside(&e.file.name, &file.name) || inside(&file.name, &e.file.name)
                        }) {
                            let msg = format!(
                                "`{}` and the trace file `{}` cannot both be written: one would be a folder of the other",
                                file.name, e.file.name
                            );
                            return Err(file.error(msg).into());
                        }
                        t.exports.push(Export {
                            actor: *actor,
                            file: file.clone(),
                            text: String::new(),
                            last: None,
                        });
                    }
                    _ => {}
                }
            }
        }
        Ok(t)
    }

    /// `?50`: channel `c` at time `arg`, or why it cannot be read.
    pub fn channel(&self, c: f64, arg: f64) -> std::result::Result<f64, String> {
        let k = c as usize;
        match self.channels.get(k).filter(|_| k as f64 == c) {
            Some(ch) => Ok(ch.at(arg)),
            None => Err(format!(
                "`?50` reads data channel {c}, but the film declares {} (NbrChannels_listOfNames; channels are numbered from 0)",
                self.channels.len()
            )),
        }
    }

    /// The imported trajectory of `actor` at the current time.
    pub fn trace(&self, actor: i64) -> Option<(DVec3, DVec3)> {
        let tr = self.imports.iter().rev().find(|t| t.actor == actor)?;
        Some(tr.at(self.time))
    }

    /// Writes the record of every traced actor for `frame` (once per
    /// frame), if an `I` asked for them.
    pub fn record(&mut self, frame: u64, living: &[Living]) {
        if !std::mem::take(&mut self.wanted) {
            return;
        }
        for e in &mut self.exports {
            if e.last == Some(frame) {
                continue;
            }
            e.last = Some(frame);
            if let Some(a) = living.iter().find(|l| l.id as i64 == e.actor) {
                e.text.push_str(&record_line(a, self.time));
            }
        }
    }

    /// The exported trajectories: the file as the scene names it and
    /// its text.
    pub fn exported(&self) -> Vec<(&FileRef, &str)> {
        self.exports
            .iter()
            .map(|e| (&e.file, e.text.as_str()))
            .collect()
    }
}

/// One record, its numbers in Rust's shortest round-trip form.
pub fn record_line(a: &Living, time: f64) -> String {
    format!(
        "Actor {} {} {} {} {} {}\n",
        a.id, a.state, time, a.eye.x, a.eye.y, a.eye.z
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn file() -> FileRef {
        FileRef::new(
            &Source::new("s.lm", "import_trace 0 t.trace"),
            15,
            "t.trace",
        )
    }

    fn trace(text: &str, actor: i64) -> std::result::Result<ActorTrack, Diagnostic> {
        parse_trace(&Source::new("t.trace", text), actor, &file())
    }

    #[test]
    fn trajectories_interpolate_and_clamp() {
        let text = "Actor 0 0 0 0 0 0\nActor 1 0 0 9 9 9\n\nActor 0 3 1 2 0 0\nActor 0 3 2 2 0 0\nActor 0 1 3 2 0 4\n";
        let t = trace(text, 0).unwrap();
        assert_eq!(t.times, [0.0, 1.0, 2.0, 3.0]);
        assert_eq!(t.at(-1.0), (DVec3::ZERO, DVec3::X));
        assert_eq!(t.at(0.5), (DVec3::new(1.0, 0.0, 0.0), DVec3::X));
        // Stationary: the direction before.
        assert_eq!(t.at(1.5), (DVec3::new(2.0, 0.0, 0.0), DVec3::X));
        assert_eq!(t.at(2.5), (DVec3::new(2.0, 0.0, 2.0), DVec3::Z));
        assert_eq!(t.at(9.0), (DVec3::new(2.0, 0.0, 4.0), DVec3::Z));
    }

    #[test]
    fn bad_records_are_located() {
        let cases = [
            ("Actr 0 0 0 0 0 0\n", 1, 1, "not a record"),
            ("Actor 0 0 0 0 0\n", 1, 16, "6 of its 7 words"),
            ("Actor 0 0 0 0 0 0 0\n", 1, 19, "after the record"),
            ("\nActor x 0 0 0 0 0\n", 2, 7, "actor number"),
            ("Actor 0 0.5 0 0 0 0\n", 1, 9, "state"),
            ("Actor 0 0 0 0 inf 0\n", 1, 15, "finite"),
            (
                "Actor 0 0 1 0 0 0\nActor 0 0 1 0 0 0\n",
                2,
                11,
                "forward in time",
            ),
        ];
        for (text, line, column, what) in cases {
            let e = trace(text, 0).unwrap_err();
            assert_eq!((e.line, e.column), (line, column), "{text:?}: {e}");
            assert!(e.message.contains(what), "{text:?}: {e}");
        }
        let e = trace("Actor 1 0 0 0 0 0\n", 0).unwrap_err();
        assert_eq!((e.file.as_str(), e.line, e.column), ("s.lm", 1, 16));
    }

    #[test]
    fn trace_files_stay_inside_the_output_folder() {
        assert!(output_name("a.trace").is_ok());
        assert!(output_name("tracks/a.trace").is_ok());
        for bad in [
            "../x",
            "/tmp/x",
            "a/../../x",
            "",
            "manifest.json",
            "frames/x",
            "f.mp4",
        ] {
            assert!(output_name(bad).is_err(), "{bad}");
        }
    }
}
