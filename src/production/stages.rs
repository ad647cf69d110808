//! The film job in its stages (DESIGN §1, §5), each resumable and each
//! recording what made its outputs (see [`super::record`]):
//!
//! * [`derive`]: the simulation — one snapshot per frame under `scene/`,
//!   the sound event log `soundtrack.events` and `derive.json`;
//! * [`render_frames`]: snapshots into `frames/<name>.NNNN.exr|png`, each
//!   with its record; any subset of frames (a shard), in any number of
//!   processes on any number of machines at once;
//! * [`soundtrack`]: the log into `soundtrack.wav` and its record;
//! * [`mux`]: frames and soundtrack into `<name>.mp4` and its record;
//! * [`super::assemble::finish`]: `manifest.json`, assembled from the
//!   records.
//!
//! A stage skips an output only when its recorded inputs equal the
//! current ones and its bytes still hash to its record; otherwise it makes
//! it again. Every file is written atomically.

use super::record::open;
use crate::film::names::{self, key, AMBIX_FILE, EVENTS_FILE, SOUNDTRACK_FILE};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use rayon::prelude::*;

use super::actor_images;

use super::digest::{sha256_bytes, sha256_file};
use super::folder::{self, unreadable, Bounds};
use super::frames::FrameSelection;
use super::record::{
    self, intact, DeriveRecord, FileHash, FrameRecord, Inputs, MuxRecord, SoundRecord,
};
use super::settings::RenderChoice;
use super::timings::{Stage, Timings};
use super::video_groups::{EncodedGroup, GroupTap, TappedFrame};
use super::{assemble, mux as video_mux, video};
use crate::actors::live::Living;
use crate::atomic::{remove_stale_temps, write_atomic};
use crate::error::Error;
use crate::film::names::ACTORS_DIR;
use crate::film::names::{frame_path, snapshot_path, FRAMES_DIR, SCENE_DIR};
use crate::film::names::{
    frame_record_path, mp4_paths, parse_frame_file, DERIVE_RECORD, SOUNDS_DIR, SOUND_RECORD,
};
use crate::film::{Film, Frame};
use crate::lsys::Limits;
use crate::render::motion::Motion;
use crate::render::{self, output, Accel, ImageFormat};
use crate::scene::snapshot;
use crate::sound;
use crate::sound::wav::MAX_WAV_BYTES;
use crate::source::{read_file, refused};
use std::collections::VecDeque;
use std::sync::mpsc::{sync_channel, Receiver, SyncSender};

/// A scene file as the records name it, with its bytes.
pub struct SceneText {
    pub name: String,
    pub bytes: Vec<u8>,
}

/// Progress of a stage, told after each frame: `(done, total)`.
pub type Tick<'a> = &'a mut dyn FnMut(u64, u64);

/// One frame of a render done: the `done`th of `total`, frame `frame`,
/// rendered now (`made`) or found up to date, `seconds` from its reading
/// to its record.
#[derive(Debug, Clone, Copy)]
pub struct FrameDone {
    pub done: u64,
    pub total: u64,
    pub frame: u64,
    pub made: bool,
    pub seconds: f64,
}

/// What a render says as each frame is done.
pub type FrameProgress<'a> = &'a mut dyn FnMut(FrameDone);

/// What a derivation is made from: the scene texts, the files they
/// reference (hashed now), the film's name and the options that change
/// the derivation.
pub fn inputs(
    film: &Film,
    scenes: &[SceneText],
    name: &str,
    options: BTreeMap<String, String>,
) -> Result<Inputs, Error> {
    let mut files = Vec::new();
    for (file, path) in film.referenced_files() {
        let hash = FileHash::of(&file, &path, MAX_REFERENCED)
            .map_err(|e| Error::input(format!("{}: cannot read: {e}", path.display())))?;
        files.push(hash);
    }
    Ok(Inputs {
        files,
        lmfilm_version: record::version(),
        name: name.to_string(),
        options,
        scenes: scenes
            .iter()
            .map(|s| FileHash {
                file: s.name.clone(),
                sha256: sha256_bytes(&s.bytes),
            })
            .collect(),
    })
}

/// The most bytes hashed of a file a scene references: the largest its
/// readers take (an OBJ's; a sound's, a data channel's, a motion's are
/// smaller).
const MAX_REFERENCED: u64 = crate::scene::obj::MAX_MESH_BYTES;

/// The outputs of lmfilm in a folder: what `--clean` removes.
fn clear(dir: &Path) -> Result<(), Error> {
    if let Ok(Some(old)) = record::read::<DeriveRecord>(&dir.join(DERIVE_RECORD)) {
        remove_tracks(dir, &old.tracks)?;
    }
    for sub in [SCENE_DIR, FRAMES_DIR, SOUNDS_DIR, ACTORS_DIR] {
        let path = dir.join(sub);
        if path.exists() {
            std::fs::remove_dir_all(&path).map_err(|e| Error::io(&path, e))?;
        }
    }
    let Ok(entries) = std::fs::read_dir(dir) else {
        return Ok(());
    };
    for e in entries.flatten() {
        let name = e.file_name().to_string_lossy().into_owned();
        let ours = [
            DERIVE_RECORD,
            names::SETTINGS_FILE,
            SOUND_RECORD,
            EVENTS_FILE,
            SOUNDTRACK_FILE,
            names::MANIFEST_FILE,
        ]
        .contains(&name.as_str())
            || name.ends_with(".mp4")
            || name.ends_with(".mp4.json");
        if ours && e.path().is_file() {
            std::fs::remove_file(e.path()).map_err(|err| Error::io(&e.path(), err))?;
        }
    }
    Ok(())
}

/// The scene names of the film a folder already holds, if any: from its
/// derive record, else from a manifest of an earlier lmfilm.
fn film_in(dir: &Path) -> Option<Vec<String>> {
    if let Ok(Some(r)) = record::read::<DeriveRecord>(&dir.join(DERIVE_RECORD)) {
        return Some(r.inputs.film());
    }
    let text = read_file(&dir.join(names::MANIFEST_FILE), folder::MAX_MANIFEST).ok()?;
    let json: serde_json::Value = serde_json::from_slice(&text).ok()?;
    let scenes = json.get("scenes")?.as_array()?;
    Some(record::film_of(
        scenes.iter().filter_map(|s| s.get("file")?.as_str()),
    ))
}

/// Refuses a folder that holds another film, saying how to start over.
fn check_same_film(dir: &Path, inputs: &Inputs) -> Result<(), Error> {
    let Some(theirs) = film_in(dir) else {
        return Ok(());
    };
    let ours = inputs.film();
    if theirs == ours {
        return Ok(());
    }
    Err(Error::input(format!(
        "{}: this folder holds the film of {}, not of {}; its outputs would be mixed with this one's. \
         Write this film into another folder (-o DIR), or empty this one with --clean",
        dir.display(),
        theirs.join(" "),
        ours.join(" ")
    )))
}

/// Derives every frame of `film` into `dir` and records it; returns the
/// record. Nothing is redone when the folder's record has the same
/// inputs and its outputs are intact. `clean` empties the folder's lmfilm
/// outputs first; without it a folder of another film is refused.
pub fn derive(
    film: &mut Film,
    inputs: Inputs,
    dir: &Path,
    clean: bool,
    progress: Tick,
    timings: &Timings,
) -> Result<(DeriveRecord, bool), Error> {
    claim(dir, &inputs, clean)?;
    derive_announcing(film, inputs, dir, progress, timings, &mut |_, _| Ok(()))
}

/// Makes `dir` the film's folder: created, emptied of lmfilm's outputs
/// with `clean`, else refused when it holds another film.
pub fn claim(dir: &Path, inputs: &Inputs, clean: bool) -> Result<(), Error> {
    std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
    if clean {
        clear(dir)
    } else {
        check_same_film(dir, inputs)
    }
}

/// [`derive`] into a claimed folder, calling `announce(frame, snapshot
/// hash)` as each snapshot is on disk (for the render stage to start on
/// it); nothing is announced when the folder is up to date.
pub fn derive_announcing(
    film: &mut Film,
    inputs: Inputs,
    dir: &Path,
    progress: Tick,
    timings: &Timings,
    announce: &mut dyn FnMut(u64, &str) -> Result<(), Error>,
) -> Result<(DeriveRecord, bool), Error> {
    // Said before deriving, not after the last frame.
    for (file, _) in film.exported_traces() {
        crate::film::tracks::check_target(dir, file)?;
    }
    let scene_dir = dir.join(SCENE_DIR);
    std::fs::create_dir_all(&scene_dir).map_err(|e| Error::io(&scene_dir, e))?;
    remove_stale_temps(&scene_dir);
    remove_stale_temps(dir);
    let key = inputs.key();
    let record_path = dir.join(DERIVE_RECORD);
    if let Ok(Some(old)) = record::read::<DeriveRecord>(&record_path) {
        if old.key == key && old.validate().is_ok() && derived_intact(dir, &old) {
            let frames = old.frame_count;
            progress(frames, frames);
            prune_frames(dir, &old)?;
            actor_images::prune(dir, &old.actors)?;
            return Ok((old, false));
        }
    }
    // The old record no longer says what the folder holds; its trace
    // files are pruned once the new ones are written.
    let old_tracks = match record::read::<DeriveRecord>(&record_path) {
        Ok(Some(old)) => old.tracks,
        _ => BTreeMap::new(),
    };
    if record_path.exists() {
        std::fs::remove_file(&record_path).map_err(|e| Error::io(&record_path, e))?;
    }
    let frames = film.frame_count();
    let mut snapshots = Vec::new();
    let mut actors = BTreeMap::new();
    let mut last = std::time::Instant::now();
    every_frame(film, progress, |frame, living| {
        timings.add(Stage::Derive, last.elapsed());
        for a in living.iter().filter(|a| a.edge.is_some()) {
            timings.add_vision(a.id, a.seeing);
        }
        let path = dir.join(snapshot_path(frame.number()));
        let hash = timings.time(Stage::Snapshot, || {
            let bytes = snapshot::encode(frame.scene());
            let hash = sha256_bytes(&bytes);
            // Derivation is deterministic: an identical snapshot stays.
            if !sha256_file(&path, snapshot::MAX_SNAPSHOT_BYTES).is_ok_and(|h| h == hash) {
                write_atomic(&path, &bytes).map_err(|e| Error::io(&path, e))?;
            }
            Ok::<_, Error>(hash)
        })?;
        announce(frame.number(), &hash)?;
        snapshots.push(hash);
        let written = timings.time(Stage::ActorImages, || {
            actor_images::write(dir, frame.number(), living, &mut actors)
        });
        last = std::time::Instant::now();
        written
    })?;
    let sounds = copy_sounds(film, dir)?;
    let tracks = write_tracks(film, dir, &old_tracks)?;
    let events = write_events(film, &dir.join(EVENTS_FILE))?;
    prune_snapshots(&scene_dir, frames)?;
    actor_images::prune(dir, &actors)?;
    let selection = FrameSelection::resolve(None, film.rs_switch()).to_text();
    let rec = DeriveRecord {
        actors,
        dt: film.dt(),
        events: sha256_bytes(events.as_bytes()),
        frame_count: frames,
        inputs,
        key,
        selection,
        snapshots,
        sounds,
        tracks,
    };
    record::write(&record_path, &rec).map_err(|e| Error::io(&record_path, e))?;
    prune_frames(dir, &rec)?;
    Ok((rec, true))
}

/// Copies the scene's own sound files into `sounds/` (the soundtrack
/// stage may run on another machine, without the scene's folder); a name
/// that is not a plain relative path is left where it is.
fn copy_sounds(film: &Film, dir: &Path) -> Result<BTreeMap<String, String>, Error> {
    let mut copied = BTreeMap::new();
    for (file, path) in film.sound_files() {
        let rel = Path::new(file.as_str());
        let plain = rel
            .components()
            .all(|c| matches!(c, std::path::Component::Normal(_)));
        if !plain {
            continue;
        }
        let bytes = read_file(path, MAX_WAV_BYTES)
            .map_err(|e| Error::input(format!("{}: cannot read: {e}", path.display())))?;
        let to = dir.join(SOUNDS_DIR).join(rel);
        let hash = sha256_bytes(&bytes);
        if !sha256_file(&to, MAX_WAV_BYTES).is_ok_and(|h| h == hash) {
            if let Some(parent) = to.parent() {
                std::fs::create_dir_all(parent).map_err(|e| Error::io(parent, e))?;
            }
            write_atomic(&to, &bytes).map_err(|e| Error::io(&to, e))?;
        }
        copied.insert(key(&Path::new(SOUNDS_DIR).join(rel)), hash);
    }
    Ok(copied)
}

/// Writes the actor trajectories `I` recorded (`trace_actor`) into the
/// folder and removes those of `old` that the film no longer writes;
/// returns their paths in the folder and sha256. The names were checked
/// when the film loaded (inside the folder, not lmfilm's own).
fn write_tracks(
    film: &Film,
    dir: &Path,
    old: &BTreeMap<String, String>,
) -> Result<BTreeMap<String, String>, Error> {
    let mut written = BTreeMap::new();
    for (file, text) in film.exported_traces() {
        crate::film::tracks::output_name(&file.name).map_err(|m| Error::from(file.error(m)))?;
        crate::film::tracks::check_target(dir, file)?;
        let to = dir.join(&file.name);
        if let Some(parent) = to.parent() {
            std::fs::create_dir_all(parent).map_err(|e| Error::io(parent, e))?;
        }
        write_atomic(&to, text.as_bytes()).map_err(|e| Error::io(&to, e))?;
        written.insert(key(Path::new(&file.name)), sha256_bytes(text.as_bytes()));
    }
    let stale = old
        .iter()
        .filter(|(k, _)| !written.contains_key(*k))
        .map(|(k, v)| (k.clone(), v.clone()))
        .collect();
    remove_tracks(dir, &stale)?;
    Ok(written)
}

/// Removes the trace files `tracks` lists (a record's), each only when
/// its name is one lmfilm could have written, inside the folder.
fn remove_tracks(dir: &Path, tracks: &BTreeMap<String, String>) -> Result<(), Error> {
    for name in tracks.keys() {
        if crate::film::tracks::output_name(name).is_ok() {
            let path = dir.join(name);
            if path.is_file() {
                std::fs::remove_file(&path).map_err(|e| Error::io(&path, e))?;
            }
        }
    }
    Ok(())
}

/// Whether every snapshot, actor image, the event log, the sound copies
/// and the trace files still hash to the record (one that is not a
/// regular file is not: the derivation writes it again).
fn derived_intact(dir: &Path, rec: &DeriveRecord) -> bool {
    let bounds = Bounds::new(0, rec.frame_count);
    let ok = |f: &Path, h: &str| intact(dir, f, h, &bounds).unwrap_or(false);
    ok(Path::new(EVENTS_FILE), &rec.events)
        && rec.actors.iter().all(|(f, h)| ok(Path::new(f), h))
        && rec.sounds.iter().all(|(f, h)| ok(Path::new(f), h))
        && rec.tracks.iter().all(|(f, h)| ok(Path::new(f), h))
        && rec
            .snapshots
            .iter()
            .enumerate()
            .all(|(k, h)| ok(&snapshot_path(k as u64), h))
}

/// Removes snapshots past the film's end (an earlier, longer film's).
fn prune_snapshots(scene_dir: &Path, frames: u64) -> Result<(), Error> {
    let Ok(entries) = std::fs::read_dir(scene_dir) else {
        return Ok(());
    };
    for e in entries.flatten() {
        let name = e.file_name().to_string_lossy().into_owned();
        let past_end = name
            .strip_suffix(".snap")
            .filter(|n| n.len() >= 4 && n.bytes().all(|b| b.is_ascii_digit()))
            .and_then(|n| n.parse::<u64>().ok())
            .is_some_and(|k| k >= frames);
        if past_end {
            std::fs::remove_file(e.path()).map_err(|err| Error::io(&e.path(), err))?;
        }
    }
    Ok(())
}

/// Derives every frame of the film through its frame loop, handing each
/// frame to `each` with the actors as its sense step left them; the
/// turtle's warnings are shown once each at the end.
pub fn every_frame(
    film: &mut Film,
    progress: Tick,
    mut each: impl FnMut(&Frame, &[Living]) -> Result<(), Error>,
) -> Result<(), Error> {
    let frames = film.frame_count();
    let mut warnings = std::collections::BTreeSet::new();
    while film.next_frame()?.is_some() {
        let frame = film.frame().expect("the frame just derived");
        warnings.extend(frame.warnings().iter().cloned());
        each(frame, film.living())?;
        progress(frame.number() + 1, frames);
    }
    for w in warnings {
        eprintln!("{w}");
    }
    Ok(())
}

/// Writes the film's sound event log to `path`, creating its folder;
/// returns the log's text.
pub fn write_events(film: &Film, path: &Path) -> Result<String, Error> {
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
    }
    let text = sound::events::write(film.events());
    write_atomic(path, text.as_bytes()).map_err(|e| Error::io(path, e))?;
    Ok(text)
}

/// The scene camera's window (width, height in pixels) of the derived
/// film in `dir`, from its first snapshot: the size a render takes when
/// none is given.
pub fn camera_size(dir: &Path) -> Result<(u32, u32), Error> {
    let rec = open(dir)?;
    if rec.frame_count == 0 {
        return Err(Error::input(format!(
            "{}: the film has no frame",
            dir.display()
        )));
    }
    snapshot_hash(dir, &rec, 0)?;
    let scene =
        snapshot::read(&dir.join(snapshot_path(0))).map_err(|e| Error::input(e.to_string()))?;
    Ok((scene.camera.width, scene.camera.height))
}

/// The snapshot of frame `k`, checked against the derive record.
fn snapshot_hash(dir: &Path, rec: &DeriveRecord, k: u64) -> Result<String, Error> {
    let rel = snapshot_path(k);
    let expected = &rec.snapshots[k as usize];
    match sha256_file(&dir.join(&rel), snapshot::MAX_SNAPSHOT_BYTES) {
        Ok(h) if h == *expected => Ok(h),
        Ok(_) => Err(Error::input(format!(
            "{}: {} does not match {DERIVE_RECORD} (damaged or from another derivation); \
             derive again: lmfilm derive SCENE.lm -o {}",
            dir.display(),
            rel.display(),
            dir.display()
        ))),
        Err(e) if refused(&e).is_some() => Err(unreadable(dir, &key(&rel), &e)),
        Err(e) => Err(Error::input(format!(
            "{}: {e}; derive again: lmfilm derive SCENE.lm -o {}",
            dir.join(&rel).display(),
            dir.display()
        ))),
    }
}

/// Whether frame `k`'s record says it was made from `snapshot` with
/// `render`, and its images are intact (read at most to `bounds`); an
/// error when its record or an image is not a regular file (a folder, a
/// device, a pipe), which a render never replaces.
fn frame_done(
    dir: &Path,
    (name, k): (&str, u64),
    snapshot: &str,
    want: &FrameRecord,
    bounds: &Bounds,
) -> Result<bool, Error> {
    let Some(r) = record::read_made::<FrameRecord>(dir, &frame_record_path(name, k))? else {
        return Ok(false);
    };
    let same = r.snapshot == snapshot
        && r.next_snapshot == want.next_snapshot
        && r.render == want.render
        && r.inset == want.inset
        && r.lmfilm_version == want.lmfilm_version
        && r.outputs.keys().eq(want.outputs.keys());
    if !same {
        return Ok(false);
    }
    for (f, h) in &r.outputs {
        if !intact(dir, Path::new(f), h, bounds)? {
            return Ok(false);
        }
    }
    Ok(true)
}

/// Refuses, before a stage writes anything, each of the folder's files
/// `rels` that it reads or writes where something else than a regular
/// file stands (a folder, a device, a pipe): named, with the way out.
/// Only metadata is read: a pipe is never opened.
pub fn refuse_odd_files(dir: &Path, rels: impl IntoIterator<Item = String>) -> Result<(), Error> {
    rels.into_iter()
        .try_for_each(|rel| folder::check_kind(dir, &rel))
}

/// [`refuse_odd_files`] for what finishing the film reads and writes
/// (`assemble::finish`: the records and the manifest), for the stages
/// that finish it (`render` of every frame, `sound DIR`, `mux`).
pub fn check_finishing(dir: &Path) -> Result<(), Error> {
    let rec = open(dir)?;
    refuse_odd_files(dir, folder::finishing(&rec.inputs.name, rec.frame_count))
}

/// Renders the listed frames of a derived folder with the resolved
/// settings `choice`; a frame is skipped when its record shows it was
/// made from the same snapshot with the same settings and its files are
/// intact. Each frame writes its images, then its record, so shards never
/// write one file. The inset (`choice.inset`): the actor whose vision
/// window goes into the frames' top-left corner, from the folder's
/// `actors/N/vision.NNNN.png` (an actor without one is refused before
/// anything is rendered). Returns how many frames were rendered.
pub fn render_frames(
    dir: &Path,
    frames: &[u64],
    choice: &RenderChoice,
    max_pixels: u64,
    (progress, timings): (FrameProgress, &Timings),
    video: Option<&GroupTap>,
) -> Result<u64, Error> {
    let rec = open(dir)?;
    let insets = match choice.inset {
        Some(a) => actor_images::inset_sources(dir, &rec, a, frames)?,
        None => BTreeMap::new(),
    };
    let blurs = choice.settings().blurs();
    // What the frames read and write, before any is rendered.
    let name = &rec.inputs.name;
    refuse_odd_files(
        dir,
        frames.iter().flat_map(|&k| {
            let mut rels = vec![key(&snapshot_path(k))];
            if blurs && k + 1 < rec.frame_count {
                rels.push(key(&snapshot_path(k + 1)));
            }
            rels.extend(frame_files(name, k).map(|rel| key(&rel)));
            rels.extend(insets.get(&k).map(|i| i.file.clone()));
            rels
        }),
    )?;
    let source = frames.iter().map(|&k| {
        let next = match blurs && k + 1 < rec.frame_count {
            true => Some(snapshot_hash(dir, &rec, k + 1)?),
            false => None,
        };
        Ok((k, snapshot_hash(dir, &rec, k)?, next))
    });
    let job = FrameJob {
        dir,
        name: &rec.inputs.name,
        choice,
        insets: &insets,
        max_pixels,
        timings,
        video,
    };
    job.run(source, frames.len() as u64, progress)
}

/// Renders the listed frames of a film as its derivation announces them
/// (`derive_announcing`): frame k from its snapshot as soon as that is
/// on disk, so that deriving overlaps rendering (issue 45). Only for
/// settings that need nothing of the derivation but each frame's own
/// snapshot: no inset, no motion blur ([`streams`]).
pub fn render_announced(
    dir: &Path,
    name: &str,
    (frames, announced): (&[u64], Receiver<(u64, String)>),
    choice: &RenderChoice,
    max_pixels: u64,
    (progress, timings): (FrameProgress, &Timings),
    video: Option<&GroupTap>,
) -> Result<u64, Error> {
    let wanted: std::collections::BTreeSet<u64> = frames.iter().copied().collect();
    let source = announced
        .into_iter()
        .filter(|(k, _)| wanted.contains(k))
        .map(|(k, hash)| Ok((k, hash, None)));
    let insets = BTreeMap::new();
    let job = FrameJob {
        dir,
        name,
        choice,
        insets: &insets,
        max_pixels,
        timings,
        video,
    };
    job.run(source, frames.len() as u64, progress)
}

/// A pool of as many threads as the current one, named `lmfilm-NAME-i`,
/// for a stage whose parallel work must not queue behind the renderer's
/// rows (they share the cores; the system schedules the threads).
pub fn own_pool(name: &str) -> Result<rayon::ThreadPool, Error> {
    rayon::ThreadPoolBuilder::new()
        .num_threads(rayon::current_num_threads())
        .thread_name({
            let name = name.to_string();
            move |i| format!("lmfilm-{name}-{i}")
        })
        .build()
        .map_err(|e| Error::other(format!("cannot start the {name} stage's threads: {e}")))
}

/// Whether frames with these settings can render as they are derived.
pub fn streams(choice: &RenderChoice) -> bool {
    choice.inset.is_none() && !choice.settings().blurs()
}

/// A frame's number, its snapshot's hash and the next frame's (motion
/// blur), or why they are not known.
type Announced = Result<(u64, String, Option<String>), Error>;

/// Frames rendering at once: the rows of the next fill the cores that
/// the last rows of one leave idle (a frame of 270 rows on 16 cores).
const IN_FLIGHT: usize = 2;

/// A frame on its way through the pipeline: what its record will say,
/// and, unless its files are up to date, its scene and then its image.
struct Prepared {
    index: usize,
    frame: u64,
    /// When its reading began, for the frame's line in a log.
    started: std::time::Instant,
    want: FrameRecord,
    accel: Option<Accel>,
    image: Option<output::Image>,
}

/// What every stage of a render shares.
#[derive(Clone, Copy)]
struct FrameJob<'a> {
    dir: &'a Path,
    /// The film's name, which names its frames.
    name: &'a str,
    choice: &'a RenderChoice,
    insets: &'a BTreeMap<u64, FileHash>,
    max_pixels: u64,
    timings: &'a Timings,
    /// The video's groups, encoded as the frames are written.
    video: Option<&'a GroupTap>,
}

impl FrameJob<'_> {
    /// Renders the frames `source` names, `count` of them, through three
    /// stages, one frame in each (two rendering) and at most one waiting
    /// between two (issue 45): frame n + 2 is read and its BVH built, and
    /// frame n − 1 encoded, hashed and recorded, while frames n and n + 1
    /// render on every core.
    /// Each frame's files depend on its own snapshot only, and are written
    /// here in frame order. Returns how many frames were rendered.
    fn run(
        self,
        source: impl Iterator<Item = Announced> + Send,
        count: u64,
        progress: FrameProgress,
    ) -> Result<u64, Error> {
        let frames_dir = self.dir.join(FRAMES_DIR);
        std::fs::create_dir_all(&frames_dir).map_err(|e| Error::io(&frames_dir, e))?;
        remove_stale_temps(&frames_dir);
        let (to_render, prepared) = sync_channel::<Prepared>(1);
        let (to_write, rendered) = sync_channel::<Prepared>(1);
        std::thread::scope(|scope| {
            let reader = scope.spawn(move || -> Result<(), Error> {
                for (i, announced) in source.enumerate() {
                    let (k, snap, next) = announced?;
                    let p = self.prepare(i, k, snap, next)?;
                    if to_render.send(p).is_err() {
                        break; // a later stage stopped: its error is the one
                    }
                }
                Ok(())
            });
            let renderer = scope.spawn(move || self.render_in_flight(prepared, &to_write));
            // The video stage: each written frame into its group of
            // pictures, on its own thread, in frame order.
            let (to_video, written_frames) = sync_channel::<Option<TappedFrame>>(2);
            if let Some(tap) = self.video {
                scope.spawn(move || tap.encode(written_frames, self.timings));
            }
            // The writer's own pool for the EXR's blocks: in the
            // renderer's, they waited behind whole frames' rows.
            let pool = own_pool("write")?;
            let mut written = 0;
            let mut result = Ok(());
            for p in rendered {
                let (frame, started) = (p.frame, p.started);
                match pool.install(|| self.write(p)) {
                    Ok((i, made, tapped)) => {
                        written += u64::from(made);
                        if self.video.is_some() {
                            let _ = to_video.send(tapped);
                        }
                        progress(FrameDone {
                            done: i as u64 + 1,
                            total: count,
                            frame,
                            made,
                            seconds: started.elapsed().as_secs_f64(),
                        });
                    }
                    Err(e) => {
                        result = Err(e);
                        break;
                    }
                }
            }
            drop(to_video); // the video stage ends with the frames
                            // The earliest stage's error: a later one stopped because of it.
            let joined = |h: std::thread::ScopedJoinHandle<'_, Result<(), Error>>| {
                h.join()
                    .unwrap_or_else(|_| Err(Error::other("a frame stage panicked")))
            };
            joined(reader)?;
            joined(renderer)?;
            result.map(|()| written)
        })
    }

    /// The render stage: frames from `prepared`, [`IN_FLIGHT`] at once
    /// on the pool, handed to `to_write` in the order they came.
    fn render_in_flight(
        self,
        prepared: Receiver<Prepared>,
        to_write: &SyncSender<Prepared>,
    ) -> Result<(), Error> {
        rayon::in_place_scope(|s| {
            let mut flight = VecDeque::new();
            let mut prepared = prepared.into_iter();
            loop {
                if flight.len() < IN_FLIGHT {
                    if let Some(mut p) = prepared.next() {
                        let (done, rendered) = sync_channel(1);
                        s.spawn(move |_| {
                            let _ = done.send(self.render(&mut p).map(|()| p));
                        });
                        flight.push_back(rendered);
                        continue;
                    }
                }
                let Some(rendered) = flight.pop_front() else {
                    return Ok(());
                };
                let p = rendered
                    .recv()
                    .unwrap_or_else(|_| Err(Error::other("a frame's render panicked")))?;
                if to_write.send(p).is_err() {
                    return Ok(()); // the writer stopped: its error is the one
                }
            }
        })
    }

    /// Frame `k`'s record as it will be, and its scene read and its BVH
    /// built unless its files are up to date.
    fn prepare(
        &self,
        index: usize,
        k: u64,
        snap: String,
        next_snapshot: Option<String>,
    ) -> Result<Prepared, Error> {
        let (dir, name) = (self.dir, self.name);
        let st = self.choice.settings();
        let want = FrameRecord {
            frame: k,
            inset: self.insets.get(&k).cloned(),
            lmfilm_version: record::version(),
            outputs: self
                .choice
                .formats
                .formats()
                .iter()
                .map(|f| (key(&frame_path(name, k, f.extension())), String::new()))
                .collect(),
            render: self.choice.record(),
            snapshot: snap.clone(),
            next_snapshot,
        };
        let mut p = Prepared {
            index,
            frame: k,
            started: std::time::Instant::now(),
            want,
            accel: None,
            image: None,
        };
        let bounds = Bounds::new(self.max_pixels, 0);
        if frame_done(dir, (name, k), &snap, &p.want, &bounds)? {
            return Ok(p);
        }
        let read = |k: u64| {
            self.timings.time(Stage::ReadSnapshot, || {
                // The reader's message says to derive again.
                snapshot::read(&dir.join(snapshot_path(k))).map_err(|e| Error::input(e.to_string()))
            })
        };
        let scene = read(k)?;
        let snap_path = dir.join(snapshot_path(k));
        let refuse = |e: String| Error::input(format!("{}: {e}", snap_path.display()));
        Limits::check_pixels(st.width, st.height, self.max_pixels).map_err(refuse)?;
        render::check(&scene).map_err(refuse)?;
        let motion = match p.want.next_snapshot {
            Some(_) => Motion::between(&scene, &read(k + 1)?, st.shutter),
            None => Motion::default(),
        };
        p.accel = Some(self.timings.time(Stage::Accel, || {
            Accel::moving(std::sync::Arc::new(scene), &motion)
        }));
        Ok(p)
    }

    /// Ray-traces a prepared frame, its inset composed in.
    fn render(&self, p: &mut Prepared) -> Result<(), Error> {
        let Some(accel) = p.accel.take() else {
            return Ok(());
        };
        let mut st = self.choice.settings();
        st.frame = p.frame;
        let mut img = self.timings.time(Stage::Render, || {
            render::render_with(&accel, &st, &|_, _| {})
        });
        if let Some(source) = &p.want.inset {
            actor_images::compose(&mut img, &actor_images::read_inset(self.dir, source)?);
        }
        p.image = Some(img);
        Ok(())
    }

    /// Writes a rendered frame's images and then its record; returns its
    /// index, whether it was made now and, when the video is encoded as
    /// frames are written, the frame as its PNG holds it. The EXR and the PNG are encoded
    /// at once (the EXR's blocks on the writer's pool beside the PNG) and
    /// hashed from memory: on many cores this one thread a frame would
    /// otherwise keep pace with the render.
    fn write(&self, mut p: Prepared) -> Result<(usize, bool, Option<TappedFrame>), Error> {
        let Some(img) = p.image.take() else {
            return Ok((p.index, false, None));
        };
        let (dir, name, k) = (self.dir, self.name, p.frame);
        let formats = self.choice.formats.formats();
        let encode = |format: ImageFormat| -> Option<Result<(String, String), Error>> {
            if !formats.contains(&format) {
                return None;
            }
            let rel = frame_path(name, k, format.extension());
            let path = dir.join(&rel);
            let stage = Stage::encoding(format);
            let written = self
                .timings
                .time(stage, || format.encode(&img))
                .and_then(|bytes| {
                    let hash = self.timings.time(Stage::Record, || sha256_bytes(&bytes));
                    self.timings.time(stage, || write_atomic(&path, &bytes))?;
                    Ok(hash)
                });
            Some(
                written
                    .map(|hash| (key(&rel), hash))
                    .map_err(|e| Error::io(&path, e)),
            )
        };
        // Every format at once (the EXR's blocks on the writer's pool
        // beside the PNG).
        let made: Vec<_> = ImageFormat::ALL
            .into_par_iter()
            .map(|f| (f, encode(f)))
            .collect();
        for (format, made) in made {
            match made {
                Some(made) => {
                    let (key, hash) = made?;
                    p.want.outputs.insert(key, hash);
                }
                None => {
                    // Another format's image of an earlier render.
                    let path = dir.join(frame_path(name, k, format.extension()));
                    if path.exists() {
                        std::fs::remove_file(&path).map_err(|e| Error::io(&path, e))?;
                    }
                }
            }
        }
        let rp = dir.join(frame_record_path(name, k));
        self.timings
            .time(Stage::Record, || record::write(&rp, &p.want))
            .map_err(|e| Error::io(&rp, e))?;
        let png = p.want.outputs.get(&key(&frame_path(name, k, PNG)));
        let tapped = self.video.zip(png).map(|(_, png)| TappedFrame {
            frame: k,
            png: png.clone(),
            size: (img.width, img.height),
            rgb: output::srgb8_pixels(&img),
        });
        Ok((p.index, true, tapped))
    }
}

/// The sound options as the soundtrack's record keeps them.
fn sound_record(settings: &sound::SoundSettings) -> BTreeMap<String, String> {
    [
        ("rate", settings.rate.to_string()),
        ("speed_of_sound", settings.speed_of_sound.to_string()),
        ("attenuation", format!("{:?}", settings.attenuation)),
        ("format", format!("{:?}", settings.format)),
        (
            "loudness",
            settings
                .loudness
                .map_or("off".into(), |l| format!("{l} LUFS")),
        ),
    ]
    .into_iter()
    .map(|(k, v)| (k.to_string(), v))
    .collect()
}

/// Renders the folder's sound event log into its soundtrack, unless the
/// soundtrack's record shows the same log and options and its bytes are
/// intact. Returns the renderer's report when it rendered.
pub fn soundtrack(
    dir: &Path,
    settings: &sound::SoundSettings,
) -> Result<Option<sound::SoundtrackReport>, Error> {
    let rec = open(dir)?;
    let bounds = Bounds::new(0, rec.frame_count);
    // What the soundtrack reads and writes, before it is rendered.
    refuse_odd_files(
        dir,
        [EVENTS_FILE, SOUNDTRACK_FILE, AMBIX_FILE, SOUND_RECORD]
            .map(String::from)
            .into_iter()
            .chain(rec.sounds.keys().cloned()),
    )?;
    if !intact(dir, Path::new(EVENTS_FILE), &rec.events, &bounds)? {
        return Err(Error::input(format!(
            "{}: {EVENTS_FILE} does not match {DERIVE_RECORD} (damaged or missing); derive again: lmfilm derive SCENE.lm -o {}",
            dir.display(),
            dir.display()
        )));
    }
    let wav = dir.join(SOUNDTRACK_FILE);
    let record_path = dir.join(SOUND_RECORD);
    let mut want = SoundRecord {
        events: rec.events.clone(),
        lmfilm_version: record::version(),
        sound: sound_record(settings),
        soundtrack: String::new(),
        ears: None,
        ambix: None,
    };
    let master = Path::new(AMBIX_FILE);
    if let Some(old) = record::read_made::<SoundRecord>(dir, Path::new(SOUND_RECORD))? {
        // What the render made (the files, which channels are ears) is
        // the record's; the rest must be the same.
        let same = SoundRecord {
            soundtrack: old.soundtrack.clone(),
            ears: old.ears,
            ambix: old.ambix.clone(),
            ..want.clone()
        };
        let master_intact = match &old.ambix {
            Some(h) => intact(dir, master, h, &bounds)?,
            None => true,
        };
        if old == same
            && master_intact
            && intact(dir, Path::new(SOUNDTRACK_FILE), &old.soundtrack, &bounds)?
        {
            return Ok(None);
        }
    }
    let sounds = dir.join(SOUNDS_DIR);
    let library = sounds.is_dir().then_some(sounds.as_path());
    let report = sound::render_file(&dir.join(EVENTS_FILE), &wav, settings, library, &|_, _| {})?;
    want.soundtrack =
        sha256_file(&wav, bounds.limit(SOUNDTRACK_FILE)).map_err(|e| Error::io(&wav, e))?;
    want.ears = report.ears.map(|(l, r)| [l, r]);
    let master = dir.join(master);
    want.ambix = match &report.ambix {
        Some(_) => Some(
            sha256_file(&master, bounds.limit(AMBIX_FILE)).map_err(|e| Error::io(&master, e))?,
        ),
        None => {
            // A master of an earlier log that asked for one.
            if master.exists() {
                std::fs::remove_file(&master).map_err(|e| Error::io(&master, e))?;
            }
            None
        }
    };
    record::write(&record_path, &want).map_err(|e| Error::io(&record_path, e))?;
    Ok(Some(report))
}

/// What [`mux`] did: the MP4, whether it was made now, how many groups
/// of pictures were encoded while the frames rendered (of how many), and
/// what it had to leave out.
pub struct MuxDone {
    pub mp4: PathBuf,
    pub made: bool,
    pub groups: (usize, usize),
    pub note: Option<String>,
}

/// Frames and soundtrack into `<name>.mp4` (H.264 at the quantiser
/// `qp`, Opus), unless its record shows the same frames, soundtrack,
/// rate and quantiser and the MP4 is intact. The groups of pictures in
/// `ready` (encoded while the frames rendered) are taken where their
/// frames are the folder's.
pub fn mux(dir: &Path, qp: u8, ready: &[EncodedGroup]) -> Result<MuxDone, Error> {
    let rec = open(dir)?;
    let name = &rec.inputs.name;
    let (mp4, record_path) = mp4_paths(name);
    // What the MP4 reads and writes, before it is made.
    refuse_odd_files(
        dir,
        [SOUNDTRACK_FILE, SOUND_RECORD]
            .map(String::from)
            .into_iter()
            .chain([key(&mp4), key(&record_path)])
            .chain(
                (0..rec.frame_count)
                    .flat_map(|k| [PNG, RECORD_EXT].map(|e| key(&frame_path(name, k, e)))),
            ),
    )?;
    if let Some(k) = first_unrendered(dir, &rec) {
        return Err(Error::input(format!(
            "{}: frame {k} has no image yet, and the MP4 needs every frame; `lmfilm render {}` renders the rest",
            dir.display(),
            dir.display()
        )));
    }
    let rate = video_mux::FrameRate::from_dt(rec.dt).map_err(|e| Error::input(e.to_string()))?;
    let frames = assemble::valid_frames(dir, &rec)?;
    // Each PNG as its record says, and the most bytes it may have.
    let mut pngs = Vec::new();
    for (k, f) in &frames {
        let render = f.render.iter().map(|(k, v)| (k.as_str(), v.as_str()));
        let bounds = Bounds::of_settings(render, 0);
        let png = frame_path(name, *k, PNG);
        let Some(h) = f.outputs.get(&key(&png)) else {
            continue;
        };
        if !intact(dir, &png, h, &bounds)? {
            return Err(Error::input(format!(
                "{}: does not match its record {} (damaged since it was rendered); `lmfilm render {}` renders it again",
                dir.join(&png).display(),
                frame_record_path(name, *k).display(),
                dir.display()
            )));
        }
        pngs.push(video_mux::FramePng {
            frame: *k,
            limit: bounds.limit(&key(&png)),
            rel: png,
            hash: h.clone(),
        });
    }
    let bounds = Bounds::new(0, rec.frame_count);
    let sound = match record::read_made::<SoundRecord>(dir, Path::new(SOUND_RECORD))? {
        Some(s)
            if s.events == rec.events
                && intact(dir, Path::new(SOUNDTRACK_FILE), &s.soundtrack, &bounds)? =>
        {
            Some(s)
        }
        _ => None,
    };
    let mut want = MuxRecord {
        frames: assemble::digest(name, &frames),
        lmfilm_version: record::version(),
        mp4: String::new(),
        rate: rate.to_string(),
        soundtrack: sound.as_ref().map(|s| s.soundtrack.clone()),
        video_qp: Some(qp),
    };
    if let Some(old) = record::read_made::<MuxRecord>(dir, &record_path)? {
        let same = MuxRecord {
            mp4: old.mp4.clone(),
            ..want.clone()
        };
        // Its bytes the record's, and a player reads the film in them.
        let whole = || video::check_shape(&dir.join(&mp4), rec.frame_count, rec.dt).is_ok();
        if old == same && intact(dir, &mp4, &old.mp4, &bounds)? && whole() {
            return Ok(MuxDone {
                mp4: dir.join(mp4),
                made: false,
                groups: (0, 0),
                note: None,
            });
        }
    }
    let track = sound.map(|s| (Path::new(SOUNDTRACK_FILE), s.ears));
    let made = video_mux::mux(dir, name, (rate, qp), &pngs, ready, track).map_err(|e| match e {
        video_mux::MuxError::Io { .. } | video_mux::MuxError::Input { .. } => {
            Error::input(e.to_string())
        }
        _ => Error::other(e.to_string()),
    })?;
    let out = made.mp4;
    want.mp4 = sha256_file(&out, bounds.limit(&key(&mp4))).map_err(|e| Error::io(&out, e))?;
    let rp = dir.join(&record_path);
    record::write(&rp, &want).map_err(|e| Error::io(&rp, e))?;
    Ok(MuxDone {
        mp4: out,
        made: true,
        groups: made.groups,
        note: made.note,
    })
}

/// The PNG, the format an MP4 is made of.
const PNG: &str = ImageFormat::Png.extension();
/// A frame's record beside its images.
const RECORD_EXT: &str = "json";

/// The extensions of a frame's files: each image format's, its record's.
fn frame_extensions() -> impl Iterator<Item = &'static str> {
    ImageFormat::ALL
        .into_iter()
        .map(ImageFormat::extension)
        .chain([RECORD_EXT])
}

/// Frame `k`'s files, as paths in the folder.
fn frame_files(name: &str, k: u64) -> impl Iterator<Item = PathBuf> + '_ {
    frame_extensions().map(move |e| frame_path(name, k, e))
}

/// The first frame of the film without its PNG (`--frames` rendered
/// only some), None when every frame has one.
fn first_unrendered(dir: &Path, rec: &DeriveRecord) -> Option<u64> {
    (0..rec.frame_count).find(|&k| !dir.join(frame_path(&rec.inputs.name, k, PNG)).is_file())
}

/// Whether every frame of the derived film in `dir` has its PNG: an MP4
/// can be made.
pub fn all_rendered(dir: &Path) -> Result<bool, Error> {
    let rec = open(dir)?;
    Ok(first_unrendered(dir, &rec).is_none())
}

/// Removes, in `frames/`, the images and records of frames past the
/// film's end or of another film name (a re-run never keeps outputs made
/// from other inputs).
pub fn prune_frames(dir: &Path, rec: &DeriveRecord) -> Result<(), Error> {
    let Ok(entries) = std::fs::read_dir(dir.join(FRAMES_DIR)) else {
        return Ok(());
    };
    for e in entries.flatten() {
        let file = e.file_name().to_string_lossy().into_owned();
        let stale = parse_frame_file(&file).is_some_and(|(n, k, ext)| {
            frame_extensions().any(|e| e == ext) && (n != rec.inputs.name || k >= rec.frame_count)
        });
        if stale {
            std::fs::remove_file(e.path()).map_err(|err| Error::io(&e.path(), err))?;
        }
    }
    Ok(())
}
