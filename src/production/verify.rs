//! `lmfilm verify` (DESIGN §4): checks a film folder's whole chain — the
//! manifest against the records it was assembled from, every listed
//! file's bytes, every record against the inputs it names (a frame
//! against its snapshot, the soundtrack against its event log, the MP4
//! against its frames), the frames the film shows that are not rendered,
//! and files in `frames/` and `scene/` that nothing accounts for.

use std::fmt;
use std::io;
use std::path::Path;

use super::assemble;
use super::digest::sha256_file;
use super::folder::{way_out, Bounds};
use super::frames::FrameSelection;
use super::manifest::{self, Manifest};
use super::record::{self, DeriveRecord};
use crate::film::names::{self, EVENTS_FILE, SOUNDTRACK_FILE};
use crate::film::names::{frame_record_path, mp4_paths, SOUND_RECORD};
use crate::source::refused;

/// One thing wrong with a folder.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Problem {
    /// A listed file is gone.
    Missing { file: String },
    /// A listed file's bytes changed.
    Mismatch {
        file: String,
        expected: String,
        found: String,
    },
    /// A listed file exists but cannot be read (permissions, a folder, …).
    Unreadable { file: String, error: String },
    /// A file in `frames/` or `scene/` that no record accounts for.
    Extra { file: String },
    /// Frames the film shows that have no valid render.
    NotRendered { frames: String },
    /// An output whose record names other inputs than the folder's.
    Stale { file: String, why: String },
    /// `manifest.json` differs from what the records say.
    Manifest { what: String },
    /// The records themselves cannot be read or disagree.
    Records { what: String },
}

impl Problem {
    /// The file concerned, relative to the folder ("" for the folder).
    pub fn file(&self) -> &str {
        match self {
            Problem::Missing { file }
            | Problem::Mismatch { file, .. }
            | Problem::Unreadable { file, .. }
            | Problem::Extra { file }
            | Problem::Stale { file, .. } => file,
            Problem::NotRendered { .. } => "frames",
            Problem::Manifest { .. } => names::MANIFEST_FILE,
            Problem::Records { .. } => "",
        }
    }
}

impl fmt::Display for Problem {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Problem::Missing { file } => write!(f, "{file}: missing"),
            Problem::Mismatch {
                file,
                expected,
                found,
            } => write!(
                f,
                "{file}: sha256 mismatch (manifest {expected}, file {found})"
            ),
            Problem::Unreadable { file, error } => write!(f, "{file}: cannot read: {error}"),
            Problem::Extra { file } => write!(
                f,
                "{file}: not an output of this film (stray, past the film's end or of another film)"
            ),
            Problem::NotRendered { frames } => {
                write!(f, "frames {frames}: not rendered (incomplete film)")
            }
            Problem::Stale { file, why } => write!(f, "{file}: {why}"),
            Problem::Manifest { what } => write!(f, "{}: {what}", names::MANIFEST_FILE),
            Problem::Records { what } => f.write_str(what),
        }
    }
}

/// The outcome of [`verify`].
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Report {
    /// How many files the manifest lists.
    pub checked: usize,
    /// Everything wrong, in a stable order.
    pub problems: Vec<Problem>,
}

impl Report {
    /// Whether the folder is a complete, intact film.
    pub fn is_ok(&self) -> bool {
        self.problems.is_empty()
    }
}

/// Checks the folder. `Err` only when `manifest.json` itself cannot be
/// read; every other fault is a [`Problem`].
pub fn verify(dir: &Path) -> Result<Report, manifest::Error> {
    let stored = Manifest::read(dir)?;
    let mut problems = Vec::new();
    match assemble::assemble(dir) {
        Ok(assembled) => {
            problems.extend(differences(&stored, &assembled));
            let rec = record::open(dir).ok();
            if let Some(rec) = &rec {
                problems.extend(chain(dir, rec, &assembled));
            }
            problems.extend(
                assemble::extra_files(dir, &assembled)
                    .into_iter()
                    .map(|file| Problem::Extra { file }),
            );
        }
        Err(e) => problems.push(Problem::Records {
            what: e.to_string(),
        }),
    }
    // Images read at most to the size the film's frames were rendered at.
    let render = stored
        .options
        .iter()
        .filter_map(|(k, v)| Some((k.strip_prefix("render.")?, v.as_str())));
    let bounds = Bounds::of_settings(render, stored.frame_count);
    let files: Vec<Problem> = stored
        .files
        .iter()
        .filter_map(|(file, expected)| check(dir, file, expected, &bounds))
        .collect();
    // The MP4 whose bytes are its record's, read back as a player would.
    let mp4 = names::key(&mp4_paths(&stored.name).0);
    if stored.files.contains_key(&mp4) && !files.iter().any(|p| p.file() == mp4) {
        problems.extend(video(dir, &mp4, &stored));
    }
    problems.extend(files);
    Ok(Report {
        checked: stored.files.len(),
        problems,
    })
}

/// How the stored manifest differs from the one the records give.
fn differences(stored: &Manifest, assembled: &Manifest) -> Vec<Problem> {
    let mut out = Vec::new();
    let mut field = |name: &str, same: bool| {
        if !same {
            out.push(Problem::Manifest {
                what: format!("`{name}` differs from what the records say (edited by hand?)"),
            });
        }
    };
    field("dt", stored.dt.to_bits() == assembled.dt.to_bits());
    field("frame_count", stored.frame_count == assembled.frame_count);
    field("inputs", stored.inputs == assembled.inputs);
    field(
        "lmfilm_version",
        stored.lmfilm_version == assembled.lmfilm_version,
    );
    field("name", stored.name == assembled.name);
    field("options", stored.options == assembled.options);
    field("scenes", stored.scenes == assembled.scenes);
    field("selection", stored.selection == assembled.selection);
    for (file, hash) in &assembled.files {
        match stored.files.get(file) {
            None => out.push(Problem::Manifest {
                what: format!("does not list {file}"),
            }),
            Some(h) if h != hash => out.push(Problem::Manifest {
                what: format!("lists {file} with another hash than its record"),
            }),
            Some(_) => {}
        }
    }
    for file in stored.files.keys() {
        if !assembled.files.contains_key(file) {
            out.push(Problem::Manifest {
                what: format!("lists {file}, which no valid record accounts for"),
            });
        }
    }
    out
}

/// The chain of records: frames the film shows without a valid render,
/// frames rendered from another snapshot, a soundtrack of another log,
/// an MP4 of other frames.
fn chain(dir: &Path, rec: &DeriveRecord, assembled: &Manifest) -> Vec<Problem> {
    let mut out = Vec::new();
    let name = &rec.inputs.name;
    let selection =
        FrameSelection::from_text(&rec.selection).unwrap_or_else(|_| FrameSelection::all());
    let mut missing = Vec::new();
    for k in selection.frames(rec.frame_count, super::frames::Shard::all()) {
        let rel = frame_record_path(name, k);
        let key = names::key(&rel);
        if assembled.files.contains_key(&key) {
            continue;
        }
        match record::read::<record::FrameRecord>(&dir.join(&rel)) {
            Ok(Some(_)) => out.push(Problem::Stale {
                file: key,
                why: "rendered from another snapshot than the derivation's: render it again".into(),
            }),
            Err(e) => out.push(Problem::Stale { file: key, why: e }),
            Ok(None) => missing.push(k),
        }
    }
    if !missing.is_empty() {
        out.push(Problem::NotRendered {
            frames: assemble::list(&missing),
        });
    }
    if !assembled.files.contains_key(SOUNDTRACK_FILE) {
        let why = if dir.join(SOUND_RECORD).exists() {
            format!("rendered from another {EVENTS_FILE}: render it again with `lmfilm sound DIR`")
        } else {
            "not rendered: `lmfilm sound DIR`".into()
        };
        out.push(Problem::Stale {
            file: SOUNDTRACK_FILE.into(),
            why,
        });
    }
    let (mp4, mp4_record) = mp4_paths(name);
    let mp4_key = names::key(&mp4);
    if dir.join(&mp4).exists() && !assembled.files.contains_key(&mp4_key) {
        let why = if dir.join(&mp4_record).exists() {
            "made from other frames or another soundtrack: `lmfilm mux DIR` makes it again"
        } else {
            "no record says what it was made of: `lmfilm mux DIR` makes it again"
        };
        out.push(Problem::Stale {
            file: mp4_key,
            why: why.into(),
        });
    }
    out
}

/// What is wrong with the film's MP4 as a player reads it
/// ([`super::video::check_shape`]).
fn video(dir: &Path, mp4: &str, film: &Manifest) -> Option<Problem> {
    let shape = super::video::check_shape(&dir.join(mp4), film.frame_count, film.dt);
    shape.err().map(|why| Problem::Stale {
        file: mp4.to_string(),
        why: format!("{why}: `lmfilm mux DIR` makes it again"),
    })
}

/// The problem with one listed file, if any. It is read as a regular
/// file of at most its bound: a folder, a device or a pipe is a problem
/// named with the way out, never waited on.
fn check(dir: &Path, file: &str, expected: &str, bounds: &Bounds) -> Option<Problem> {
    let file = file.to_string();
    match sha256_file(&dir.join(&file), bounds.limit(&file)) {
        Ok(found) if found == expected => None,
        Ok(found) => Some(Problem::Mismatch {
            file,
            expected: expected.to_string(),
            found,
        }),
        Err(e) if e.kind() == io::ErrorKind::NotFound => Some(Problem::Missing { file }),
        Err(e) if refused(&e).is_some() => Some(Problem::Unreadable {
            error: format!("{e}; {}", way_out(dir, &file)),
            file,
        }),
        Err(e) => Some(Problem::Unreadable {
            file,
            error: e.to_string(),
        }),
    }
}
