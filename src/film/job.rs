//! The film job in its three stages (DESIGN §1, §5), each resumable and
//! each ending with `manifest.json` rewritten from the files in the
//! output folder:
//!
//! * [`derive`]: the simulation — one snapshot per frame under `scene/`
//!   and the sound event log `soundtrack.events`;
//! * [`render_frames`]: snapshots into `frames/<name>.NNNN.png|exr`, any
//!   subset of frames (a shard), in any number of processes;
//! * [`soundtrack`]: the log into `soundtrack.wav`.
//!
//! The manifest also carries what later stages need (the film's name, Δt,
//! frame count, scenes and options), so `render DIR` and `sound DIR` need
//! nothing but the folder. Every file is written atomically and a stage
//! skips outputs that already exist: a killed job re-run ends with the
//! same bytes.

use std::collections::BTreeMap;
use std::fmt;
use std::path::{Path, PathBuf};

use super::frames::{frame_path, snapshot_path, SCENE_DIR};
use super::manifest::{self, Manifest};
use super::Film;
use crate::lsys::Limits;
use crate::render::{self, output, Settings};
use crate::scene::atomic::{remove_stale_temps, write_atomic};
use crate::scene::{snapshot, Scene};
use crate::sound;

/// The log and soundtrack names inside the folder.
pub const EVENTS_FILE: &str = "soundtrack.events";
pub const SOUNDTRACK_FILE: &str = "soundtrack.wav";

/// A failed stage: bad input (exit 2) or anything else (exit 1).
#[derive(Debug)]
pub struct Error {
    pub code: u8,
    pub message: String,
}

impl Error {
    fn input(message: impl Into<String>) -> Error {
        Error {
            code: 2,
            message: message.into(),
        }
    }

    fn other(message: impl Into<String>) -> Error {
        Error {
            code: 1,
            message: message.into(),
        }
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.message)
    }
}

impl From<manifest::Error> for Error {
    fn from(e: manifest::Error) -> Error {
        Error::other(e.to_string())
    }
}

fn io(path: &Path, e: impl fmt::Display) -> Error {
    Error::other(format!(
        "{}: {e} (is the folder writable and the disk not full?)",
        path.display()
    ))
}

/// Image formats a render writes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Formats {
    Png,
    Exr,
    Both,
}

impl Formats {
    pub fn extensions(self) -> &'static [&'static str] {
        match self {
            Formats::Png => &["png"],
            Formats::Exr => &["exr"],
            Formats::Both => &["exr", "png"],
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            Formats::Png => "png",
            Formats::Exr => "exr",
            Formats::Both => "both",
        }
    }
}

/// A scene file as the manifest names it, with its bytes.
pub struct SceneText {
    pub name: String,
    pub bytes: Vec<u8>,
}

/// Progress of a stage: `(done, total)` after each frame.
pub type Progress<'a> = &'a mut dyn FnMut(u64, u64);

/// Derives every frame of `film` into `dir`: snapshots (skipped when
/// present: derivation is deterministic) and the sound event log; then
/// the manifest, which names the film `name`.
pub fn derive(
    film: &mut Film,
    scenes: &[SceneText],
    name: &str,
    dir: &Path,
    progress: Progress,
) -> Result<Manifest, Error> {
    let frames = film.anim.frame_count();
    let scene_dir = dir.join(SCENE_DIR);
    std::fs::create_dir_all(&scene_dir).map_err(|e| io(&scene_dir, e))?;
    remove_stale_temps(&scene_dir);
    remove_stale_temps(dir);
    every_frame(film, progress, |k, scene| {
        let path = dir.join(snapshot_path(k));
        if !path.exists() {
            snapshot::write(scene, &path).map_err(|e| io(&path, e))?;
        }
        Ok(())
    })?;
    write_events(film, &dir.join(EVENTS_FILE))?;
    let mut m = Manifest::new(film.anim.camera.dt, frames);
    for s in scenes {
        m.add_scene(&s.name, &s.bytes);
    }
    m.options.insert("name".into(), name.into());
    finish(dir, m)
}

/// Derives every frame of the film from its current one (frame 0),
/// handing each frame's scene to `each`; the turtle's warnings are shown
/// once each at the end.
pub fn every_frame(
    film: &mut Film,
    progress: Progress,
    mut each: impl FnMut(u64, &Scene) -> Result<(), Error>,
) -> Result<(), Error> {
    let frames = film.anim.frame_count();
    let mut warnings = std::collections::BTreeSet::new();
    for k in 0..frames {
        let (scene, w) = film.scene().map_err(Error::input)?;
        warnings.extend(w);
        each(k, &scene)?;
        if k + 1 < frames {
            film.step().map_err(Error::input)?;
        }
        progress(k + 1, frames);
    }
    for w in warnings {
        eprintln!("{w}");
    }
    Ok(())
}

/// Writes the film's sound event log to `path`, creating its folder.
pub fn write_events(film: &Film, path: &Path) -> Result<(), Error> {
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).map_err(|e| io(dir, e))?;
    }
    write_atomic(path, sound::events::write(film.air.log()).as_bytes()).map_err(|e| io(path, e))
}

/// The manifest of a derived folder (what `render` and `sound` start
/// from), with a message that says what to do when it is missing.
pub fn open(dir: &Path) -> Result<Manifest, Error> {
    if !dir.join(manifest::MANIFEST_FILE).exists() {
        return Err(Error::input(format!(
            "{}: no manifest.json — derive the film first: lmfilm derive SCENE.lm -o {}",
            dir.display(),
            dir.display()
        )));
    }
    Ok(Manifest::read(dir)?)
}

/// The film's name as the manifest records it.
pub fn film_name(m: &Manifest) -> String {
    m.options
        .get("name")
        .cloned()
        .unwrap_or_else(|| "frame".into())
}

/// Render options recorded in the manifest: the same options give the
/// same frames, whichever process rendered them.
fn record(m: &mut Manifest, settings: &Settings, formats: Formats) {
    let o = &mut m.options;
    o.insert("render.width".into(), settings.width.to_string());
    o.insert("render.height".into(), settings.height.to_string());
    o.insert("render.spp".into(), settings.spp.to_string());
    o.insert("render.shadows".into(), settings.shadows.to_string());
    o.insert("render.max_depth".into(), settings.max_depth.to_string());
    o.insert(
        "render.light_samples".into(),
        settings.light_samples.to_string(),
    );
    o.insert("render.filter".into(), format!("{:?}", settings.filter));
    o.insert("render.formats".into(), formats.name().into());
}

/// Renders the listed frames of a derived folder with `settings` (the
/// size is the snapshot's camera's unless set); frames whose files exist
/// are skipped. Returns how many were rendered.
pub fn render_frames(
    dir: &Path,
    frames: &[u64],
    settings: &Settings,
    formats: Formats,
    max_pixels: u64,
    progress: Progress,
) -> Result<u64, Error> {
    let mut m = open(dir)?;
    let name = film_name(&m);
    let frames_dir = dir.join(super::frames::FRAMES_DIR);
    std::fs::create_dir_all(&frames_dir).map_err(|e| io(&frames_dir, e))?;
    remove_stale_temps(&frames_dir);
    let mut rendered = 0;
    for (i, &k) in frames.iter().enumerate() {
        let outs: Vec<PathBuf> = formats
            .extensions()
            .iter()
            .map(|e| dir.join(frame_path(&name, k, e)))
            .collect();
        if outs.iter().all(|p| p.exists()) {
            progress(i as u64 + 1, frames.len() as u64);
            continue;
        }
        let snap = dir.join(snapshot_path(k));
        let scene = snapshot::read(&snap).map_err(|e| {
            Error::input(format!(
                "{e} — derive the film again with this program: lmfilm derive SCENE.lm -o {}",
                dir.display()
            ))
        })?;
        let mut st = *settings;
        // 0 × 0: the camera's own size.
        if st.width == 0 || st.height == 0 {
            (st.width, st.height) = (scene.camera.width, scene.camera.height);
        }
        let refuse = |e: String| Error::input(format!("{}: {e}", snap.display()));
        Limits::check_pixels(st.width, st.height, max_pixels).map_err(refuse)?;
        render::check(&scene).map_err(refuse)?;
        st.frame = k;
        st.layers = formats != Formats::Png;
        let img = render::render(&scene, &st);
        for p in &outs {
            output::write(&img, p).map_err(|e| io(p, e))?;
        }
        rendered += 1;
        progress(i as u64 + 1, frames.len() as u64);
    }
    record(&mut m, settings, formats);
    finish(dir, m)?;
    Ok(rendered)
}

/// Renders the folder's sound event log into its soundtrack.
pub fn soundtrack(dir: &Path, settings: &sound::Settings) -> Result<(), Error> {
    let mut m = open(dir)?;
    let events = dir.join(EVENTS_FILE);
    let wav = dir.join(SOUNDTRACK_FILE);
    sound::render_file(&events, &wav, settings, None, &|_, _| {}).map_err(|e| Error {
        code: e.exit_code(),
        message: e.to_string(),
    })?;
    let o = &mut m.options;
    o.insert("sound.rate".into(), settings.rate.to_string());
    o.insert(
        "sound.speed_of_sound".into(),
        settings.speed_of_sound.to_string(),
    );
    o.insert(
        "sound.attenuation".into(),
        format!("{:?}", settings.attenuation),
    );
    o.insert("sound.format".into(), format!("{:?}", settings.format));
    finish(dir, m)?;
    Ok(())
}

/// Rewrites the manifest's file list from what the folder holds: every
/// snapshot, every frame of the film's name, the log and the soundtrack.
fn finish(dir: &Path, mut m: Manifest) -> Result<Manifest, Error> {
    let name = film_name(&m);
    m.files = BTreeMap::new();
    let mut rels = Vec::new();
    for k in 0..m.frame_count {
        rels.push(snapshot_path(k));
        for ext in ["exr", "png"] {
            rels.push(frame_path(&name, k, ext));
        }
    }
    rels.push(PathBuf::from(EVENTS_FILE));
    rels.push(PathBuf::from(SOUNDTRACK_FILE));
    for rel in rels {
        if dir.join(&rel).exists() {
            m.add_file(dir, &rel)?;
        }
    }
    m.write(dir)?;
    Ok(m)
}
