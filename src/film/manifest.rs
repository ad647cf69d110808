//! `manifest.json` (DESIGN §4, §5): what went into a film and the sha256 of
//! everything that came out, so two runs can be compared byte for byte and
//! `lmfilm verify` can tell which output was damaged or lost.
//!
//! The file holds no timestamps or host names, its object keys are sorted
//! (struct fields are declared in alphabetical order, maps are `BTreeMap`s)
//! and floats are written in their shortest round-trip form, so identical
//! inputs give identical bytes.

use std::collections::BTreeMap;
use std::fmt;
use std::fs::File;
use std::io::{self, Read};
use std::path::{Component, Path, PathBuf};

use serde::{Deserialize, Serialize};
use sha2::{Digest, Sha256};

use crate::scene::atomic::write_atomic;

/// The manifest's file name inside the output folder.
pub const MANIFEST_FILE: &str = "manifest.json";

/// One scene file of the film, in command-line order (the first file's
/// options apply to the whole film).
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct SceneFile {
    /// The file as named on the command line (or the built-in film's name).
    pub file: String,
    pub sha256: String,
}

/// The contents of `manifest.json`. Fields are in alphabetical order
/// because serde writes them in declaration order.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Manifest {
    /// Δt, the time between two frames, in seconds.
    pub dt: f64,
    /// sha256 of every output (frames, snapshots, soundtrack), keyed by its
    /// path relative to the output folder, with `/` separators.
    pub files: BTreeMap<String, String>,
    pub frame_count: u64,
    /// The version of lmfilm that wrote the outputs.
    pub lmfilm_version: String,
    /// The options that shape the outputs (preset, size, samples, …), as
    /// the caller renders them to text.
    pub options: BTreeMap<String, String>,
    pub scenes: Vec<SceneFile>,
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
        }
    }
}

impl std::error::Error for Error {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            Error::Io { source, .. } => Some(source),
            Error::Json { source, .. } => Some(source),
            Error::UnsafePath { .. } => None,
        }
    }
}

impl Manifest {
    /// An empty manifest for a film of `frame_count` frames Δt apart,
    /// stamped with this program's version.
    pub fn new(dt: f64, frame_count: u64) -> Manifest {
        Manifest {
            dt,
            files: BTreeMap::new(),
            frame_count,
            lmfilm_version: env!("CARGO_PKG_VERSION").to_string(),
            options: BTreeMap::new(),
            scenes: Vec::new(),
        }
    }

    /// Records a scene file by its contents (already in memory: the caller
    /// parsed it, and the built-in film has no file).
    pub fn add_scene(&mut self, file: &str, contents: &[u8]) {
        self.scenes.push(SceneFile {
            file: file.to_string(),
            sha256: sha256_bytes(contents),
        });
    }

    /// Hashes the output `dir/rel` and records it under `rel`.
    pub fn add_file(&mut self, dir: &Path, rel: &Path) -> Result<(), Error> {
        let key = manifest_key(rel)?;
        let path = dir.join(rel);
        let hash = sha256_file(&path).map_err(|source| Error::Io { path, source })?;
        self.files.insert(key, hash);
        Ok(())
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

    /// Reads `dir/manifest.json`, refusing paths outside the folder.
    pub fn read(dir: &Path) -> Result<Manifest, Error> {
        let path = dir.join(MANIFEST_FILE);
        let text = std::fs::read_to_string(&path).map_err(|source| Error::Io {
            path: path.clone(),
            source,
        })?;
        let manifest: Manifest =
            serde_json::from_str(&text).map_err(|source| Error::Json { path, source })?;
        for key in manifest.files.keys() {
            if manifest_key(Path::new(key)).ok().as_deref() != Some(key.as_str()) {
                return Err(Error::UnsafePath { path: key.clone() });
            }
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

/// Lowercase hex sha256 of `bytes`.
pub fn sha256_bytes(bytes: &[u8]) -> String {
    hex(&Sha256::digest(bytes))
}

/// Lowercase hex sha256 of a file, read in blocks so that large EXRs are
/// never held in memory whole.
pub fn sha256_file(path: &Path) -> io::Result<String> {
    let mut file = File::open(path)?;
    let mut hasher = Sha256::new();
    let mut buf = vec![0u8; 1 << 16];
    loop {
        match file.read(&mut buf) {
            Ok(0) => return Ok(hex(&hasher.finalize())),
            Ok(n) => hasher.update(&buf[..n]),
            Err(e) if e.kind() == io::ErrorKind::Interrupted => {}
            Err(e) => return Err(e),
        }
    }
}

fn hex(bytes: &[u8]) -> String {
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}

/// A listed output that does not match the manifest.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Problem {
    /// The file is gone.
    Missing { file: String },
    /// The file's bytes changed.
    Mismatch {
        file: String,
        expected: String,
        found: String,
    },
    /// The file exists but cannot be read (permissions, a folder, …).
    Unreadable { file: String, error: String },
}

impl Problem {
    /// The output's path relative to the output folder.
    pub fn file(&self) -> &str {
        match self {
            Problem::Missing { file }
            | Problem::Mismatch { file, .. }
            | Problem::Unreadable { file, .. } => file,
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
        }
    }
}

/// The outcome of [`verify`].
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct VerifyReport {
    /// How many files the manifest lists.
    pub checked: usize,
    /// Every listed file that is missing or differs, in path order.
    pub problems: Vec<Problem>,
}

impl VerifyReport {
    /// Whether every listed file is present and intact.
    pub fn is_ok(&self) -> bool {
        self.problems.is_empty()
    }
}

/// Re-hashes every output listed in `dir/manifest.json`. Files that are
/// not listed are ignored; the scene files are inputs outside the folder
/// and are recorded, not checked. `Err` only when the manifest itself
/// cannot be read.
pub fn verify(dir: &Path) -> Result<VerifyReport, Error> {
    let manifest = Manifest::read(dir)?;
    let problems = manifest
        .files
        .iter()
        .filter_map(|(file, expected)| check(dir, file, expected))
        .collect();
    Ok(VerifyReport {
        checked: manifest.files.len(),
        problems,
    })
}

/// The problem with one listed file, if any.
fn check(dir: &Path, file: &str, expected: &str) -> Option<Problem> {
    let file = file.to_string();
    match sha256_file(&dir.join(&file)) {
        Ok(found) if found == expected => None,
        Ok(found) => Some(Problem::Mismatch {
            file,
            expected: expected.to_string(),
            found,
        }),
        Err(e) if e.kind() == io::ErrorKind::NotFound => Some(Problem::Missing { file }),
        Err(e) => Some(Problem::Unreadable {
            file,
            error: e.to_string(),
        }),
    }
}
