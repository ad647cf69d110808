//! What made each output (DESIGN §4): the records a stage writes beside
//! its outputs, so a re-run redoes exactly the outputs whose inputs
//! changed and `verify` can check the whole chain.
//!
//! * `derive.json`: the derivation's inputs (every scene file and every
//!   file it references, by content hash; the options that change the
//!   derivation; the lmfilm version), and the hash of every snapshot, of
//!   every actor image (`actors/N/*.NNNN.png`) and of the sound event log
//!   it made;
//! * `frames/<name>.NNNN.json`: one per frame, beside the frame — the
//!   snapshot it was rendered from, the render settings (the inset
//!   among them, with the actor image it showed), its files'
//!   hashes. No two render processes ever write the same record;
//! * `soundtrack.json`: the event log's hash, the sound options and the
//!   soundtrack's hash;
//! * `<name>.mp4.json`: the frames and soundtrack the MP4 was made of.
//!
//! Records hold no host names, times or paths outside the folder, so the
//! same inputs give the same records on any machine.

use crate::film::names::DERIVE_RECORD;
use std::collections::BTreeMap;
use std::io;
use std::path::Path;

use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};

use super::digest::{sha256_bytes, sha256_file};
use super::folder::{not_a_file, unreadable, Bounds, MAX_RECORD};
use crate::atomic::write_atomic;
use crate::error::Error;
use crate::film::names::key;
use crate::source::read_file;

/// A file and the sha256 of its bytes.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct FileHash {
    /// As the command line (scenes) or the scene (referenced files) names it.
    pub file: String,
    pub sha256: String,
}

impl FileHash {
    /// Hashes the file at `path` (a regular file of at most `limit`
    /// bytes), recorded under `file`.
    pub fn of(file: &str, path: &Path, limit: u64) -> io::Result<FileHash> {
        Ok(FileHash {
            file: file.to_string(),
            sha256: sha256_file(path, limit)?,
        })
    }
}

/// Everything a derivation depends on. Fields are in alphabetical order
/// (serde writes declaration order), maps are sorted.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct Inputs {
    /// Files the scenes reference (OBJ/MTL surfaces, sound files,
    /// scripts), in the order the scenes name them.
    pub files: Vec<FileHash>,
    pub lmfilm_version: String,
    /// The film's name (its frames are `frames/<name>.NNNN.*`).
    pub name: String,
    /// The options that change the derivation.
    pub options: BTreeMap<String, String>,
    /// The scene files, in command-line order.
    pub scenes: Vec<FileHash>,
}

impl Inputs {
    /// The scenes' file names: what makes a folder one film rather than
    /// another (their contents may change from run to run).
    pub fn film(&self) -> Vec<String> {
        film_of(self.scenes.iter().map(|s| s.file.as_str()))
    }

    /// One hash of all the inputs.
    pub fn key(&self) -> String {
        sha256_bytes(&to_json(self))
    }
}

/// The file names of a film's scenes, as given: what names the film.
pub fn film_of<'a>(scenes: impl Iterator<Item = &'a str>) -> Vec<String> {
    scenes
        .map(|f| {
            Path::new(f)
                .file_name()
                .map_or(f.to_string(), |n| n.to_string_lossy().into_owned())
        })
        .collect()
}

/// `derive.json`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct DeriveRecord {
    /// sha256 of each actor image (`actors/N/vision.NNNN.png`,
    /// `actors/N/memory.NNNN.png`), keyed by its path in the folder.
    #[serde(default)]
    pub actors: BTreeMap<String, String>,
    /// Δt, the time between two frames, in seconds.
    pub dt: f64,
    /// sha256 of `soundtrack.events`.
    pub events: String,
    pub frame_count: u64,
    pub inputs: Inputs,
    /// [`Inputs::key`] of `inputs`.
    pub key: String,
    /// The frames the film shows (`rs_switch`, else all): `A..B` ranges.
    pub selection: Vec<String>,
    /// sha256 of `scene/NNNN.snap`, frame by frame.
    pub snapshots: Vec<String>,
    /// The scene's own sound files, copied into `sounds/` so that the
    /// soundtrack can be rendered wherever the folder is: their paths
    /// in the folder and sha256.
    pub sounds: BTreeMap<String, String>,
    /// The actor trajectories `I` wrote (`trace_actor`): their paths in
    /// the folder and sha256.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub tracks: BTreeMap<String, String>,
}

impl DeriveRecord {
    /// Checks what later stages rely on; the error says what is wrong.
    pub fn validate(&self) -> Result<(), String> {
        if !(self.dt.is_finite() && self.dt > 0.0) {
            return Err(format!("Δt {} is not a positive number", self.dt));
        }
        if self.snapshots.len() as u64 != self.frame_count {
            return Err(format!(
                "{} snapshot hashes for {} frames",
                self.snapshots.len(),
                self.frame_count
            ));
        }
        crate::lsys::options::plain_name(&self.inputs.name)
            .map_err(|why| format!("the film name `{}` {why}", self.inputs.name))?;
        if self.key != self.inputs.key() {
            return Err("its key is not the hash of its inputs".into());
        }
        // Each file once, and a scene's trajectory never one of
        // lmfilm's own (`film::names`).
        let mut seen = std::collections::BTreeSet::new();
        let files = self.actors.keys().chain(self.sounds.keys());
        for path in files.chain(self.tracks.keys()) {
            if !seen.insert(path) {
                return Err(format!("`{path}` is listed twice"));
            }
        }
        for path in self.tracks.keys() {
            let first = path.split('/').next().unwrap_or_default();
            if crate::film::names::is_own(first, path) {
                return Err(format!(
                    "the trajectory `{path}` is listed among lmfilm's own outputs"
                ));
            }
        }
        Ok(())
    }
}

/// `frames/<name>.NNNN.json`: one rendered frame.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct FrameRecord {
    pub frame: u64,
    /// The actor vision image put into the frame (`--inset N`), with
    /// its sha256.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub inset: Option<FileHash>,
    pub lmfilm_version: String,
    /// sha256 of each image, keyed by its path in the folder.
    pub outputs: BTreeMap<String, String>,
    /// The render settings, as text.
    pub render: BTreeMap<String, String>,
    /// sha256 of the snapshot it was rendered from.
    pub snapshot: String,
    /// sha256 of the next frame's snapshot, where the motion toward it
    /// blurs this frame (the path tracer with the shutter open).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub next_snapshot: Option<String>,
}

/// `soundtrack.json`.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct SoundRecord {
    /// sha256 of the event log it was rendered from.
    pub events: String,
    pub lmfilm_version: String,
    /// The sound options, as text.
    pub sound: BTreeMap<String, String>,
    /// sha256 of `soundtrack.wav`.
    pub soundtrack: String,
    /// The channels of the listener's left and right ears, the video's
    /// stereo (none: no ears).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ears: Option<[usize; 2]>,
    /// sha256 of `soundtrack.ambix.wav`, the ambisonic master (none: the
    /// scene asks for none).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ambix: Option<String>,
}

/// `<name>.mp4.json`.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct MuxRecord {
    /// sha256 over the list of PNG frames and their hashes.
    pub frames: String,
    pub lmfilm_version: String,
    /// sha256 of the MP4.
    pub mp4: String,
    /// The frame rate, `N/D` frames per second.
    pub rate: String,
    /// sha256 of the soundtrack muxed in, if any.
    pub soundtrack: Option<String>,
    /// The H.264 quantiser (none: a video made by ffmpeg, before lmfilm
    /// made its own).
    #[serde(default)]
    pub video_qp: Option<u8>,
}

/// This program's version, as records carry it.
pub fn version() -> String {
    env!("CARGO_PKG_VERSION").to_string()
}

/// Pretty JSON with a final newline (sorted keys: see the field order).
pub fn to_json<T: Serialize>(value: &T) -> Vec<u8> {
    let mut text = serde_json::to_vec_pretty(value)
        .expect("records are strings, numbers, sequences and string-keyed maps");
    text.push(b'\n');
    text
}

/// Writes a record atomically.
pub fn write<T: Serialize>(path: &Path, value: &T) -> io::Result<()> {
    write_atomic(path, &to_json(value))
}

/// Reads a record: `Ok(None)` when the file does not exist, `Err` with
/// the reason when it is not a valid record (not a regular file — a
/// folder, a device, a pipe, never waited on —, over [`MAX_RECORD`]
/// bytes, not UTF-8 JSON, NaN or missing fields).
pub fn read<T: DeserializeOwned>(path: &Path) -> Result<Option<T>, String> {
    match read_file(path, MAX_RECORD) {
        Ok(bytes) => parse(path, &bytes).map(Some),
        Err(e) if e.kind() == io::ErrorKind::NotFound => Ok(None),
        Err(e) => Err(format!("{}: {e}", path.display())),
    }
}

fn parse<T: DeserializeOwned>(path: &Path, bytes: &[u8]) -> Result<T, String> {
    serde_json::from_slice(bytes)
        .map_err(|e| format!("{}: not a valid lmfilm record ({e})", path.display()))
}

/// [`read`], where a record that is not a regular file (a folder, a
/// device, a pipe) is an input error naming it and the way out, and any
/// other fault (missing, damaged, too large) is `Ok(None)`: a stage
/// makes such a record again, but never replaces what it did not write.
pub fn read_made<T: DeserializeOwned>(dir: &Path, rel: &Path) -> Result<Option<T>, Error> {
    let path = dir.join(rel);
    match read_file(&path, MAX_RECORD) {
        Ok(bytes) => Ok(parse(&path, &bytes).ok()),
        Err(e) if not_a_file(&e) => Err(unreadable(dir, &key(rel), &e)),
        Err(_) => Ok(None),
    }
}

/// Whether `dir/rel` exists and its bytes hash to `sha256` (read at most
/// to its bound); `Err` when something else than a regular file stands
/// there (a folder, a device, a pipe): the input error names it and the
/// way out. A stage makes a file that is not intact again, but never
/// replaces what it did not write.
pub fn intact(dir: &Path, rel: &Path, sha256: &str, bounds: &Bounds) -> Result<bool, Error> {
    let k = key(rel);
    match sha256_file(&dir.join(rel), bounds.limit(&k)) {
        Ok(h) => Ok(h == sha256),
        Err(e) if not_a_file(&e) => Err(unreadable(dir, &k, &e)),
        Err(_) => Ok(false),
    }
}

/// The derive record of a folder (what `render`, `sound` and `mux` start
/// from), checked, with a message that says what to do when it is
/// missing or damaged.
pub fn open(dir: &Path) -> Result<DeriveRecord, Error> {
    let path = dir.join(DERIVE_RECORD);
    let again = format!(
        "derive the film first: lmfilm derive SCENE.lm -o {}",
        dir.display()
    );
    let bytes = match read_file(&path, MAX_RECORD) {
        Ok(bytes) => bytes,
        Err(e) if e.kind() == io::ErrorKind::NotFound => {
            return Err(Error::input(format!(
                "{}: no {DERIVE_RECORD} — {again}",
                dir.display()
            )))
        }
        Err(e) if not_a_file(&e) => return Err(unreadable(dir, DERIVE_RECORD, &e)),
        Err(e) => return Err(Error::input(format!("{}: {e}; {again}", path.display()))),
    };
    let r: DeriveRecord =
        parse(&path, &bytes).map_err(|e| Error::input(format!("{e}; {again}")))?;
    match r.validate() {
        Ok(()) => Ok(r),
        Err(why) => Err(Error::input(format!("{}: {why}; {again}", path.display()))),
    }
}
