//! `manifest.json` (DESIGN §4, §5): what went into a film and the sha256 of
//! everything that came out, so two runs can be compared byte for byte and
//! `lmfilm verify` can tell which output was damaged or lost.
//!
//! The file holds no timestamps or host names, its object keys are sorted
//! (struct fields are declared in alphabetical order, maps are `BTreeMap`s)
//! and floats are written in their shortest round-trip form, so identical
//! inputs give identical bytes.

use crate::film::names::MANIFEST_FILE;
use std::collections::BTreeMap;
use std::fmt;
use std::io;
use std::path::{Component, Path, PathBuf};

use serde::{Deserialize, Serialize};

use super::folder::{way_out, MAX_MANIFEST};
use super::record::{DeriveRecord, FileHash};
use crate::atomic::write_atomic;
use crate::source::{read_file, refused};

/// The contents of `manifest.json`: assembled from the folder's records
/// (see [`super::record`]) by the stage that finishes the film. Fields are
/// in alphabetical order because serde writes them in declaration order.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Manifest {
    /// Δt, the time between two frames, in seconds.
    pub dt: f64,
    /// sha256 of every output and record, keyed by its path relative to
    /// the output folder, with `/` separators.
    pub files: BTreeMap<String, String>,
    pub frame_count: u64,
    /// The files the scenes reference (surfaces, sounds, scripts).
    pub inputs: Vec<FileHash>,
    /// The version of lmfilm that wrote the outputs.
    pub lmfilm_version: String,
    /// The film's name: its frames are `frames/<name>.NNNN.*`.
    pub name: String,
    /// The options that shaped the outputs: `derive.*`, `render.*`,
    /// `sound.*`.
    pub options: BTreeMap<String, String>,
    /// The scene files, in command-line order.
    pub scenes: Vec<FileHash>,
    /// The frames the film shows (`A..B` ranges).
    pub selection: Vec<String>,
}

/// Why a manifest could not be built, read or written.
#[derive(Debug)]
pub enum Error {
    /// A file could not be read or written.
    Io { path: PathBuf, source: io::Error },
    /// `manifest.json` is not a manifest.
    Json {
        path: PathBuf,
        source: serde_json::Error,
    },
    /// A listed path is absolute, leaves the output folder or is not UTF-8,
    /// so it cannot be an output of this folder.
    UnsafePath { path: String },
    /// A value no film can have.
    Invalid { what: String },
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Error::Io { path, source } => write!(f, "{}: {source}", path.display()),
            Error::Json { path, source } => write!(
                f,
                "{}: not a valid lmfilm manifest ({source}); re-run `lmfilm run` to \
                 write it again",
                path.display()
            ),
            Error::UnsafePath { path } => write!(
                f,
                "manifest path `{path}` is not a relative path inside the output folder"
            ),
            Error::Invalid { what } => write!(f, "{MANIFEST_FILE}: {what}"),
        }
    }
}

/// A manifest that cannot be read or written is not the input's fault
/// (exit 1); `verify` says otherwise where it is.
impl From<Error> for crate::error::Error {
    fn from(e: Error) -> Self {
        crate::error::Error::other(e.to_string())
    }
}

impl std::error::Error for Error {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            Error::Io { source, .. } => Some(source),
            Error::Json { source, .. } => Some(source),
            Error::UnsafePath { .. } | Error::Invalid { .. } => None,
        }
    }
}

impl Manifest {
    /// The manifest of a derivation, with no output listed yet.
    pub fn new(rec: &DeriveRecord) -> Manifest {
        let options = rec
            .inputs
            .options
            .iter()
            .map(|(k, v)| (format!("derive.{k}"), v.clone()))
            .collect();
        Manifest {
            dt: rec.dt,
            files: BTreeMap::new(),
            frame_count: rec.frame_count,
            inputs: rec.inputs.files.clone(),
            lmfilm_version: rec.inputs.lmfilm_version.clone(),
            name: rec.inputs.name.clone(),
            options,
            scenes: rec.inputs.scenes.clone(),
            selection: rec.selection.clone(),
        }
    }

    /// The JSON text: pretty-printed, sorted keys, a final newline.
    pub fn to_json(&self) -> String {
        let mut text = serde_json::to_string_pretty(self)
            .expect("string-keyed maps, strings and numbers always serialize");
        text.push('\n');
        text
    }

    /// Writes `dir/manifest.json` atomically.
    pub fn write(&self, dir: &Path) -> Result<(), Error> {
        let path = dir.join(MANIFEST_FILE);
        write_atomic(&path, self.to_json().as_bytes()).map_err(|source| Error::Io { path, source })
    }

    /// Reads `dir/manifest.json` (a regular file of at most
    /// [`MAX_MANIFEST`] bytes: a pipe, a device or a folder is refused,
    /// never waited on), refusing paths outside the folder, a film name
    /// that is not one plain file name and a Δt that is not a positive
    /// number.
    pub fn read(dir: &Path) -> Result<Manifest, Error> {
        let path = dir.join(MANIFEST_FILE);
        let bytes = read_file(&path, MAX_MANIFEST).map_err(|source| {
            // A pipe, a device, a folder or too large: the way out too.
            let source = match refused(&source) {
                Some(_) => io::Error::new(
                    source.kind(),
                    format!("{source}; {}", way_out(dir, MANIFEST_FILE)),
                ),
                None => source,
            };
            Error::Io {
                path: path.clone(),
                source,
            }
        })?;
        let text = String::from_utf8(bytes).map_err(|e| Error::Io {
            path: path.clone(),
            source: io::Error::new(io::ErrorKind::InvalidData, e),
        })?;
        Manifest::parse(&text).map_err(|e| match e {
            Error::Json { source, .. } => Error::Json { path, source },
            e => e,
        })
    }

    /// The manifest in `text` (see [`Manifest::read`]).
    pub fn parse(text: &str) -> Result<Manifest, Error> {
        let manifest: Manifest = serde_json::from_str(text).map_err(|source| Error::Json {
            path: PathBuf::from(MANIFEST_FILE),
            source,
        })?;
        for key in manifest.files.keys() {
            if manifest_key(Path::new(key)).ok().as_deref() != Some(key.as_str()) {
                return Err(Error::UnsafePath { path: key.clone() });
            }
        }
        if crate::lsys::options::plain_name(&manifest.name).is_err() {
            return Err(Error::UnsafePath {
                path: manifest.name.clone(),
            });
        }
        if !(manifest.dt.is_finite() && manifest.dt > 0.0) {
            return Err(Error::Invalid {
                what: format!("Δt {} is not a positive number", manifest.dt),
            });
        }
        Ok(manifest)
    }
}

/// `rel` as a manifest key: plain components joined by `/`; anything that
/// could point outside the output folder is refused.
fn manifest_key(rel: &Path) -> Result<String, Error> {
    let unsafe_path = || Error::UnsafePath {
        path: rel.to_string_lossy().into_owned(),
    };
    let parts = rel
        .components()
        .map(|c| match c {
            Component::Normal(part) => part.to_str().ok_or_else(unsafe_path),
            _ => Err(unsafe_path()),
        })
        .collect::<Result<Vec<_>, _>>()?;
    if parts.is_empty() {
        return Err(unsafe_path());
    }
    Ok(parts.join("/"))
}
