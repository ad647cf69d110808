//! The film commands of DESIGN §5: run, derive, render, mux, verify and
//! `sound DIR`, over the stages of [`crate::production::stages`].

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use super::args::{RenderArgs, SceneArgs, SoundArgs, WorkArgs};
use super::scenes::{self, Loaded};
use super::{FrameLog, Progress};
use crate::error::{Error, Result};
use crate::film::names::{
    self, ACTORS_DIR, DERIVE_RECORD, EVENTS_FILE, FRAMES_DIR, SOUNDTRACK_FILE,
};
use crate::lsys::Limits;
use crate::production::frames::{FrameRange, FrameSelection, Shard};
use crate::production::mux::FrameRate;
use crate::production::settings::{
    self, Defaults, RenderChoice, RenderRequest, SoundRequest, VideoRequest, VideoSettings,
};
use crate::production::timings::Timings;
use crate::production::video_groups::GroupTap;
use crate::production::{assemble, pipeline, record, stages, verify};
use crate::render::Integrator;
use crate::sound;
use crate::turtle::Options;

/// The options that change a derivation, as its record keeps them
/// (`actor_images`: what the derivation writes of its actors, so a
/// folder derived before they were written is derived again).
fn derive_options(allow_commands: bool) -> BTreeMap<String, String> {
    BTreeMap::from([
        ("actor_images".to_string(), "vision+memory png".to_string()),
        ("allow_commands".to_string(), allow_commands.to_string()),
        (
            "segment_width".to_string(),
            Options::default().segment_width.to_string(),
        ),
    ])
}

/// Derives the film into `dir` (nothing when its record is up to date)
/// and writes the manifest; returns whether it derived.
fn derive_into(
    loaded: &mut Loaded,
    dir: &Path,
    (clean, allow): (bool, bool),
    timings: &Timings,
) -> Result<bool> {
    let Loaded { film, texts, name } = loaded;
    let inputs = stages::inputs(film, texts, name, derive_options(allow))?;
    let mut p = Progress::new("deriving frame");
    let tick = &mut |k, n| p.tick(k, n);
    let (_, derived) = stages::derive(film, inputs, dir, clean, tick, timings)?;
    p.done();
    assemble::finish(dir)?;
    Ok(derived)
}

/// The film's render settings in `dir`: `request` over the folder's
/// recorded settings, else the defaults, at the scene camera's size
/// `camera` (`window_of` says where it was read, for a size over the
/// limit); recorded when new. `partial` names a selection that is not
/// the whole film (`--frames`, `--shard`): an option that changes the
/// recorded settings is then refused, since the folder would hold frames
/// of two settings.
pub(crate) fn resolve_render(
    dir: &Path,
    request: &RenderRequest,
    defaults: Defaults,
    (camera, window_of): ((u32, u32), &str),
    partial: Option<String>,
    max_pixels: u64,
) -> Result<RenderChoice> {
    let mut recorded = settings::read(dir)?;
    let choice = request.resolve(recorded.render.as_ref(), defaults, camera);
    Limits::check_pixels(choice.width, choice.height, max_pixels).map_err(|e| {
        let whose = if choice.size_given {
            "the settings (--width, --height, settings.json)"
        } else {
            window_of
        };
        Error::input(format!("{whose}: the camera's window: {e}"))
    })?;
    if let Some(old) = &recorded.render {
        // What the options change, beside what the scene's window does.
        let kept = RenderRequest::default().resolve(Some(old), defaults, camera);
        let changed = settings::changes(&kept.record(), &choice.record());
        if !changed.is_empty() {
            if let Some(part) = partial {
                return Err(Error::input(format!(
                    "{}: the options change the film's settings ({}; recorded in {}): rendering {part} alone would leave frames of two settings in one folder. Render every frame with them (no --frames, no --shard), or give no render option to keep the film's",
                    dir.display(),
                    changed.join(", "),
                    names::SETTINGS_FILE
                )));
            }
            eprintln!(
                "{}: new render settings ({}): every frame is rendered again",
                dir.display(),
                changed.join(", ")
            );
        }
    }
    if recorded.render != Some(choice) {
        recorded.render = Some(choice);
        settings::write(dir, &recorded)?;
    }
    Ok(choice)
}

/// The film's sound settings in `dir`: `request` over the recorded
/// ones, else the defaults; recorded when new.
pub(crate) fn resolve_sound(dir: &Path, request: &SoundRequest) -> Result<sound::SoundSettings> {
    resolve_recorded(dir, |s| &mut s.sound, |old| request.resolve(old))
}

/// One of the film's settings in `dir` (the `field` of settings.json):
/// `choose` over the recorded value; recorded when new.
fn resolve_recorded<T: Copy + PartialEq>(
    dir: &Path,
    field: fn(&mut settings::FilmSettings) -> &mut Option<T>,
    choose: impl FnOnce(Option<&T>) -> T,
) -> Result<T> {
    let mut recorded = settings::read(dir)?;
    let slot = field(&mut recorded);
    let chosen = choose(slot.as_ref());
    if *slot != Some(chosen) {
        *slot = Some(chosen);
        settings::write(dir, &recorded)?;
    }
    Ok(chosen)
}

/// Renders the frames of `dir` that `frames` (else the film's own
/// selection) and `shard` name with `choice`; returns (rendered now,
/// selected).
fn render_into(
    dir: &Path,
    choice: &RenderChoice,
    (frames, shard): (Option<FrameRange>, Shard),
    max_pixels: u64,
    (timings, log_frames): (&Timings, bool),
    video: Option<&GroupTap>,
) -> Result<(u64, u64)> {
    let rec = record::open(dir)?;
    let selection = match frames {
        Some(range) => FrameSelection::range(range),
        None => FrameSelection::from_text(&rec.selection).map_err(|e| {
            Error::input(format!(
                "{}: derive.json: {e}; derive the film again",
                dir.display()
            ))
        })?,
    };
    let frames = selection.frames(rec.frame_count, shard);
    let mut p = FrameLog::new(log_frames);
    let tick = &mut |d| p.frame(d);
    let n = stages::render_frames(dir, &frames, choice, max_pixels, (tick, timings), video)?;
    p.done();
    Ok((n, frames.len() as u64))
}

/// Which part of the film `frames` and `shard` select, when not all.
fn partial(frames: Option<FrameRange>, shard: Option<Shard>) -> Option<String> {
    match (frames, shard) {
        (Some(f), _) => Some(format!("frames {f}")),
        (None, Some(s)) => Some(format!("shard {s}")),
        (None, None) => None,
    }
}

/// What the derivation wrote of its actors, for the summaries: `N
/// vision and M memory images in DIR/actors/` and the trajectories `I`
/// wrote, one line each (none without any).
fn actor_summary(dir: &Path) -> Result<Vec<String>> {
    let rec = record::open(dir)?;
    let count = |what: &str| {
        rec.actors
            .keys()
            .filter(|f| f.rsplit('/').next().is_some_and(|n| n.starts_with(what)))
            .count()
    };
    let (vision, memory) = (count("vision."), count("memory."));
    let mut lines = Vec::new();
    if vision + memory > 0 {
        lines.push(format!(
            "actors: {vision} vision and {memory} memory images in {} (N/vision.NNNN.png, N/memory.NNNN.png)",
            dir.join(ACTORS_DIR).display()
        ));
    }
    for file in rec.tracks.keys() {
        lines.push(format!("actor trajectory: {}", dir.join(file).display()));
    }
    Ok(lines)
}

/// What `run` and `derive` start from.
pub struct FilmArgs<'a> {
    /// The scene files (none: the built-in film).
    pub scenes: &'a [PathBuf],
    pub allow_commands: bool,
    /// Empty the folder's lmfilm outputs first.
    pub clean: bool,
    pub limits: Limits,
}

impl<'a> FilmArgs<'a> {
    pub fn new(scenes: &'a [PathBuf], scene: &SceneArgs, clean: bool) -> Self {
        FilmArgs {
            scenes,
            allow_commands: scene.allow_commands,
            clean,
            limits: scene.limits.limits(),
        }
    }
}

/// The film's defaults: the built-in film's own sampling (docs/film.md,
/// "The built-in film").
pub fn defaults(scenes: &[PathBuf]) -> Defaults {
    Defaults {
        spp: scenes.is_empty().then_some(scenes::BUILT_IN_SPP),
    }
}

/// `lmfilm run`: derive, render, soundtrack, MP4 and the manifest, with the film's settings: the options given over those the
/// folder recorded.
pub fn run(
    film: &FilmArgs,
    out: Option<&Path>,
    args: &RenderArgs,
    work: &WorkArgs,
    sound_args: &SoundArgs,
    video: &VideoRequest,
) -> Result<()> {
    work.threads();
    let timings = Timings::start();
    let request = args.request();
    if let (Some(w), Some(h)) = (request.width, request.height) {
        Limits::check_pixels(w, h, film.limits.pixels).map_err(Error::input)?;
    }
    let mut loaded = scenes::load(film.scenes, film.allow_commands, film.limits)?;
    let dir = scenes::output_dir(out, &loaded.film, &loaded.name);
    let camera = loaded.film.window();
    let first = film
        .scenes
        .first()
        .map_or("the built-in film".to_string(), |p| p.display().to_string());
    let Loaded {
        film: f,
        texts,
        name,
    } = &mut loaded;
    let inputs = stages::inputs(f, texts, name, derive_options(film.allow_commands))?;
    // The folder is claimed (emptied with --clean) before the settings
    // are recorded in it.
    stages::claim(&dir, &inputs, film.clean)?;
    let choice = resolve_render(
        &dir,
        &request,
        defaults(film.scenes),
        (camera, &first),
        partial(work.frames, None),
        film.limits.pixels,
    )?;
    let sound_settings = resolve_sound(&dir, &sound_args.request())?;
    let video = resolve_video(&dir, video)?;
    let selection = match work.frames {
        Some(range) => FrameSelection::range(range),
        None => FrameSelection::resolve(None, f.rs_switch()),
    };
    let frames = selection.frames(f.frame_count(), Shard::all());
    let max_pixels = film.limits.pixels;
    // The video's groups encoded as the frames are written; the mux
    // encodes the rest (a film whose Δt makes no frame rate has none).
    let tap = FrameRate::from_dt(f.dt())
        .ok()
        .map(|rate| GroupTap::new(rate.fps(), video.qp, f.frame_count()));
    let (derived, streamed) = if stages::streams(&choice) {
        let mut p = FrameLog::new(work.log_frames);
        let streamed = pipeline::derive_rendering(
            f,
            inputs,
            &dir,
            (&choice, &frames, max_pixels),
            &timings,
            &mut |d| p.frame(d),
            tap.as_ref(),
        )?;
        p.done();
        streamed
    } else {
        let mut p = Progress::new("deriving frame");
        let tick = &mut |k, n| p.tick(k, n);
        let (_, derived) =
            stages::derive_announcing(f, inputs, &dir, tick, &timings, &mut |_, _| Ok(()))?;
        p.done();
        (derived, None)
    };
    assemble::finish(&dir)?;
    let (rendered, selected) = match streamed {
        Some(n) => (n, frames.len() as u64),
        None => render_into(
            &dir,
            &choice,
            (work.frames, Shard::all()),
            max_pixels,
            (&timings, work.log_frames),
            tap.as_ref(),
        )?,
    };
    let sounded = soundtrack(&dir, &sound_settings)?;
    let complete = stages::all_rendered(&dir)?;
    let ready = tap.map(GroupTap::groups).unwrap_or_default();
    let mp4 = if complete {
        Some(stages::mux(&dir, video.qp, &ready)?)
    } else {
        None
    };
    let m = assemble::finish(&dir)?;
    let now = |done: bool| if done { "made now" } else { "up to date" };
    println!(
        "{}: {} frames derived ({}), {rendered} of {selected} frames rendered now (the others up to date), {} ({}), {}",
        dir.display(),
        m.frame_count,
        now(derived),
        dir.join(SOUNDTRACK_FILE).display(),
        now(sounded),
        dir.join(names::MANIFEST_FILE).display()
    );
    println!("settings: {}", describe(&choice));
    for line in actor_summary(&dir)? {
        println!("{line}");
    }
    if let Some(a) = choice.inset {
        println!(
            "the frames show actor {a}'s vision window in their top-left corner (--inset {a})"
        );
    }
    if work.timings {
        eprint!("{}", timings.report());
    }
    match mp4 {
        Some(done) => {
            println!("film: {} ({})", done.mp4.display(), now(done.made));
            if done.made {
                println!("{}", groups_line(done.groups));
            }
            if let Some(note) = done.note {
                println!("note: {note}");
            }
        }
        None => println!("no MP4: only some frames are rendered (`lmfilm render {}` renders the rest, then `lmfilm mux {}`)", dir.display(), dir.display()),
    }
    Ok(())
}

/// `lmfilm derive`.
pub fn derive(film: &FilmArgs, out: &Path, show_timings: bool) -> Result<()> {
    let timings = Timings::start();
    let mut loaded = scenes::load(film.scenes, film.allow_commands, film.limits)?;
    let flags = (film.clean, film.allow_commands);
    let derived = derive_into(&mut loaded, out, flags, &timings)?;
    if show_timings {
        eprint!("{}", timings.report());
    }
    let rec = record::open(out)?;
    println!(
        "{}: {} frames {} (scene/NNNN.snap, {EVENTS_FILE}, {DERIVE_RECORD}, {})",
        out.display(),
        rec.frame_count,
        if derived { "derived" } else { "up to date" },
        names::MANIFEST_FILE
    );
    for line in actor_summary(out)? {
        println!("{line}");
    }
    Ok(())
}

/// The settings as the summaries say them.
fn describe(c: &RenderChoice) -> String {
    let look = match c.integrator {
        Integrator::Whitted => format!("shadows {}", if c.shadows { "on" } else { "off" }),
        Integrator::Path => format!("path traced, shutter {}", c.shutter),
    };
    format!(
        "{}×{}, {} spp, preset {}, {look}, {} bounces, filter {}, formats {} ({})",
        c.width,
        c.height,
        c.spp,
        c.preset.name(),
        c.max_depth,
        c.filter.name(),
        c.formats.name(),
        names::SETTINGS_FILE
    )
}

/// `lmfilm render DIR`: the folder's recorded settings with the options
/// given over them. A shard leaves the manifest to the stage that
/// finishes the film (`sound DIR`), since shards on many machines must
/// never write one file; a whole render writes it.
pub fn render(
    dir: &Path,
    args: &RenderArgs,
    work: &WorkArgs,
    shard: Option<Shard>,
    max_pixels: u64,
) -> Result<()> {
    work.threads();
    let request = args.request();
    if let (Some(w), Some(h)) = (request.width, request.height) {
        Limits::check_pixels(w, h, max_pixels).map_err(Error::input)?;
    }
    let camera = stages::camera_size(dir)?;
    if shard.is_none() {
        // It finishes the film: refused before a frame is rendered.
        stages::check_finishing(dir)?;
    }
    let first = dir.join(crate::film::names::snapshot_path(0));
    let choice = resolve_render(
        dir,
        &request,
        Defaults::default(),
        (camera, &first.display().to_string()),
        partial(work.frames, shard),
        max_pixels,
    )?;
    let timings = Timings::start();
    let selection = (work.frames, shard.unwrap_or(Shard::all()));
    let (n, selected) = render_into(
        dir,
        &choice,
        selection,
        max_pixels,
        (&timings, work.log_frames),
        None,
    )?;
    if work.timings {
        eprint!("{}", timings.report());
    }
    println!(
        "{}: {n} of {selected} frames rendered now (the others up to date) in {}; settings: {}",
        dir.display(),
        dir.join(FRAMES_DIR).display(),
        describe(&choice)
    );
    if let Some(a) = choice.inset {
        println!(
            "the frames show actor {a}'s vision window in their top-left corner (--inset {a})"
        );
    }
    match shard {
        Some(s) => println!(
            "shard {s} done; once every shard is, finish the film with: lmfilm sound {}",
            dir.display()
        ),
        None => {
            assemble::finish(dir)?;
        }
    }
    Ok(())
}

/// How the video's groups of pictures were made, for the user.
fn groups_line((ready, total): (usize, usize)) -> String {
    format!("video: {ready} of {total} groups of pictures encoded while the frames rendered, the others from the PNG frames")
}

/// `lmfilm mux DIR`.
pub fn mux(dir: &Path, video: &VideoRequest) -> Result<()> {
    stages::check_finishing(dir)?;
    let video = resolve_video(dir, video)?;
    let done = stages::mux(dir, video.qp, &[])?;
    assemble::finish(dir)?;
    println!(
        "{}{}",
        done.mp4.display(),
        if done.made { "" } else { " (up to date)" }
    );
    if let Some(note) = done.note {
        println!("note: {note}");
    }
    Ok(())
}

/// The film's video settings in `dir`: `request` over the recorded
/// ones, else the defaults; recorded when new.
pub(crate) fn resolve_video(dir: &Path, request: &VideoRequest) -> Result<VideoSettings> {
    resolve_recorded(dir, |s| &mut s.video, |old| request.resolve(old))
}

/// `lmfilm verify DIR`: each problem named, and an error (exit 1) when
/// there is one.
pub fn verify(dir: &Path) -> Result<()> {
    let report = verify::verify(dir).map_err(|e| Error::input(e.to_string()))?;
    if report.is_ok() {
        println!(
            "{}: complete and intact: {} files match manifest.json and their records",
            dir.display(),
            report.checked
        );
        return Ok(());
    }
    for p in &report.problems {
        eprintln!("{}: {p}", dir.display());
    }
    Err(Error::other(format!(
        "{}: {} problems ({} files listed in manifest.json)",
        dir.display(),
        report.problems.len(),
        report.checked
    )))
}

/// The folder's soundtrack (unless up to date), saying what loudness
/// normalisation did.
fn soundtrack(dir: &Path, settings: &sound::SoundSettings) -> Result<bool> {
    let report = stages::soundtrack(dir, settings)?;
    if let Some(n) = report.as_ref().and_then(|r| r.loudness.as_ref()) {
        eprintln!("{}: {}", dir.join(SOUNDTRACK_FILE).display(), n.summary());
        if let Some(w) = n.warning() {
            eprintln!("warning: {w}");
        }
    }
    if let Some(a) = report.as_ref().and_then(|r| r.ambix.as_ref()) {
        ambix_said(a);
    }
    Ok(report.is_some())
}

/// `lmfilm sound DIR` on a film folder: the soundtrack with the folder's
/// recorded settings and the options given over them, then the manifest
/// (the stage that finishes a film rendered in shards).
pub fn sound_dir(dir: &Path, request: &SoundRequest) -> Result<()> {
    stages::check_finishing(dir)?;
    let settings = resolve_sound(dir, request)?;
    let made = soundtrack(dir, &settings)?;
    assemble::finish(dir)?;
    println!(
        "{}{}, {}",
        dir.join(SOUNDTRACK_FILE).display(),
        if made { "" } else { " (up to date)" },
        dir.join(names::MANIFEST_FILE).display()
    );
    Ok(())
}

/// What the ambisonic master is and what its normalisation did.
pub fn ambix_said(a: &sound::AmbixReport) {
    let level = a.loudness.map_or("levels as rendered".into(), |n| {
        format!("W: {}", n.summary())
    });
    eprintln!(
        "{}: the ambisonic master (AmbiX: W Y Z X, SN3D), {level}",
        a.path.display()
    );
    if a.clipped > 0 {
        eprintln!(
            "warning: {}: {} samples beyond full scale were clipped; try --float",
            a.path.display(),
            a.clipped
        );
    }
}
