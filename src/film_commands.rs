//! The film commands of DESIGN §5 — run, derive, render, mux, verify,
//! trace — as thin wrappers over `lmfilm::film`.

use std::io::{IsTerminal, Write};
use std::path::{Path, PathBuf};
use std::time::Instant;

use clap::{Args, ValueEnum};
use std::collections::BTreeMap;

use lmfilm::film::frames::{FrameRange, FrameSelection, Shard};
use lmfilm::film::job::{self, Formats, SceneText, SOUNDTRACK_FILE};
use lmfilm::film::{assemble, manifest, mux, verify, Film};
use lmfilm::lsys::{Limits, Source};
use lmfilm::render::Settings;
use lmfilm::sound::{self, Attenuation, SampleFormat};
use lmfilm::turtle::Options;

/// The built-in film (`lmfilm run` with no scene): its three files.
const BUILT_IN: [(&str, &str); 3] = [
    ("tree.lm", include_str!("../scenes/film/tree.lm")),
    ("flowers.lm", include_str!("../scenes/film/flowers.lm")),
    ("airplane.lm", include_str!("../scenes/film/airplane.lm")),
];

type Failure = (u8, String);

fn fail(e: job::Error) -> Failure {
    (e.code, e.message)
}

/// Frames done, frames per second and time left: one rewritten line on a
/// terminal, a plain line every tenth of the work otherwise (once the
/// stage has run for 2 s).
pub struct Progress {
    label: &'static str,
    terminal: bool,
    start: Instant,
    last: Instant,
}

impl Progress {
    pub fn new(label: &'static str) -> Progress {
        Progress {
            label,
            terminal: std::io::stderr().is_terminal(),
            start: Instant::now(),
            last: Instant::now(),
        }
    }

    pub fn tick(&mut self, done: u64, total: u64) {
        let now = Instant::now();
        let line = || {
            let secs = self.start.elapsed().as_secs_f64().max(1e-9);
            let rate = done as f64 / secs;
            let left = (total - done.min(total)) as f64 / rate.max(1e-9);
            format!(
                "{} {done}/{total} · {rate:.1} frames/s · {left:.0} s left",
                self.label
            )
        };
        if self.terminal {
            if now.duration_since(self.last).as_millis() >= 200 || done == total {
                self.last = now;
                eprint!("\r\x1b[K{}", line());
            }
        } else if total > 0
            && self.start.elapsed().as_secs() >= 2
            && (done * 10 / total != (done - 1) * 10 / total || done == total)
        {
            // Long work only: a quick stage stays silent in logs.
            eprintln!("{}", line());
        }
    }

    pub fn done(&self) {
        if self.terminal {
            eprintln!();
        }
    }
}

#[derive(Clone, Copy, ValueEnum)]
pub enum PresetArg {
    Preview,
    Final,
}

#[derive(Clone, Copy, ValueEnum)]
pub enum FormatArg {
    Png,
    Exr,
    Both,
}

/// How `lmfilm sound` and `run` render the soundtrack: the fields of `sound::Settings`.
#[derive(clap::Args)]
pub struct SoundArgs {
    /// Sample rate in Hz.
    #[arg(long, default_value_t = 48_000)]
    rate: u32,
    /// Speed of sound in m/s.
    #[arg(long, default_value_t = 343.0)]
    speed_of_sound: f64,
    /// `inverse`: 1/max(d, 1 m); `thesis`: (1/(1 + d))² (eq. 2.4.1);
    /// `none`: delay and Doppler only.
    #[arg(long, value_enum, default_value_t = AttenuationArg::Inverse)]
    attenuation: AttenuationArg,
    /// Write 32-bit float samples instead of 16-bit PCM (no clipping).
    #[arg(long)]
    float: bool,
    /// Normalise the soundtrack to this integrated loudness in LUFS
    /// (ITU-R BS.1770-4, -70..0), keeping its true peak at or below
    /// -1 dBTP, with 5 ms fades at both ends.
    #[arg(
        long,
        value_name = "LUFS",
        default_value_t = sound::loudness::DEFAULT_TARGET,
        allow_negative_numbers = true
    )]
    loudness: f64,
    /// Keep the renderer's raw levels: no loudness normalisation and
    /// no fades.
    #[arg(long, conflicts_with = "loudness")]
    no_normalize: bool,
}

impl SoundArgs {
    /// The renderer's settings, each option checked (exit 2 naming it).
    pub fn settings(&self) -> Result<sound::Settings, Failure> {
        let rate = self.rate;
        if !(1..=768_000).contains(&rate) {
            return Err((2, format!("--rate must be 1..768000 Hz, got {rate}")));
        }
        let speed_of_sound = self.speed_of_sound;
        if !(speed_of_sound.is_finite() && speed_of_sound > 0.0) {
            return Err((
                2,
                format!("--speed-of-sound must be > 0 m/s, got {speed_of_sound}"),
            ));
        }
        let loudness = (!self.no_normalize).then_some(self.loudness);
        if let Some(target) = loudness {
            sound::loudness::check_target(target).map_err(|e| (2, format!("--loudness: {e}")))?;
        }
        Ok(sound::Settings {
            rate,
            speed_of_sound,
            attenuation: match self.attenuation {
                AttenuationArg::Inverse => Attenuation::Inverse,
                AttenuationArg::Thesis => Attenuation::Thesis,
                AttenuationArg::None => Attenuation::None,
            },
            format: if self.float {
                SampleFormat::Float32
            } else {
                SampleFormat::Pcm16
            },
            loudness,
        })
    }
}

#[derive(Clone, Copy, ValueEnum)]
pub enum AttenuationArg {
    Inverse,
    Thesis,
    None,
}

/// The preset's settings at `w` × `h`, with `--spp` if given (`still`,
/// `run` and `render`).
pub fn quality(preset: PresetArg, w: u32, h: u32, spp: Option<u32>) -> Result<Settings, Failure> {
    let mut s = match preset {
        PresetArg::Preview => Settings::preview(w, h),
        PresetArg::Final => Settings::final_quality(w, h),
    };
    if let Some(n) = spp {
        if n == 0 || n > 65536 {
            return Err((2, format!("--spp must be 1..65536, got {n}")));
        }
        s.spp = n;
    }
    Ok(s)
}

/// How frames are rendered (`run` and `render`).
#[derive(Args)]
pub struct RenderArgs {
    /// Frames to render: A..B (B excluded), A..=B, A.. or N; default all
    /// (or the scene's `rs_switch` ranges).
    #[arg(long, value_name = "A..B")]
    frames: Option<FrameRange>,
    /// `final`: 16 samples, shadows, reflections; `preview`: 1 sample.
    #[arg(long, value_enum, default_value_t = PresetArg::Final)]
    preset: PresetArg,
    /// Image width (default: the scene camera's `prefpos`).
    #[arg(long)]
    width: Option<u32>,
    /// Image height (default: the scene camera's `prefpos`).
    #[arg(long)]
    height: Option<u32>,
    /// Samples per pixel (overrides the preset's).
    #[arg(long)]
    spp: Option<u32>,
    /// `both` (the EXR master and its PNG), `png` (8-bit sRGB) or `exr`
    /// (RGBA, Z, normal, object id).
    #[arg(long, value_enum, default_value_t = FormatArg::Both)]
    format: FormatArg,
    /// Worker threads (default: all cores); the images do not depend on it.
    #[arg(long)]
    threads: Option<usize>,
}

impl RenderArgs {
    fn settings(&self, max_pixels: u64) -> Result<(Settings, Formats), Failure> {
        for (v, what) in [(self.width, "--width"), (self.height, "--height")] {
            if v.is_some_and(|v| !(1..=32768).contains(&v)) {
                return Err((2, format!("{what} must be 1..32768 pixels")));
            }
        }
        if let (Some(w), Some(h)) = (self.width, self.height) {
            Limits::check_pixels(w, h, max_pixels).map_err(|e| (2, e))?;
        }
        // 0 × 0: the size of each snapshot's camera.
        let (w, h) = (self.width.unwrap_or(0), self.height.unwrap_or(0));
        let s = quality(self.preset, w, h, self.spp)?;
        let f = match self.format {
            FormatArg::Png => Formats::Png,
            FormatArg::Exr => Formats::Exr,
            FormatArg::Both => Formats::Both,
        };
        Ok((s, f))
    }

    fn threads(&self) -> Result<(), Failure> {
        if let Some(n) = self.threads {
            if n == 0 || n > Limits::MAX_THREADS {
                return Err((
                    2,
                    format!("--threads must be 1..{}, got {n}", Limits::MAX_THREADS),
                ));
            }
            // Ignored when a pool already exists (tests calling twice).
            let _ = rayon::ThreadPoolBuilder::new()
                .num_threads(n)
                .build_global();
        }
        Ok(())
    }
}

/// Loads the scene files as one film. A scene that wants to run scripts
/// (`command_file`) is refused unless the user consents
/// (`--allow-commands`), by every command alike; scripts are found in the
/// first scene's folder.
pub fn load_film(scenes: &[PathBuf], allow_commands: bool, opts: Options) -> Result<Film, Failure> {
    let mut film = Film::load(scenes, opts).map_err(|e| (2, e))?;
    consent(
        &mut film,
        scenes.first().map(PathBuf::as_path),
        allow_commands,
    )?;
    Ok(film)
}

/// Lets the film run its scripts with consent, refuses it without.
fn consent(film: &mut Film, first: Option<&Path>, allow: bool) -> Result<(), Failure> {
    let Some(what) = film.wants_commands() else {
        return Ok(());
    };
    if !allow {
        return Err((
            2,
            format!(
                "{what}: this scene wants to run scripts on this machine; a scene never runs anything by default. If you trust it, run again with --allow-commands"
            ),
        ));
    }
    // A bare file name's folder is the current one.
    let dir = first
        .and_then(Path::parent)
        .filter(|d| !d.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    film.allow_commands(dir);
    Ok(())
}

/// The scenes given, or the built-in film; with their names for the
/// records and the film's name.
fn load(
    scenes: &[PathBuf],
    allow_commands: bool,
    limits: Limits,
) -> Result<(Film, Vec<SceneText>, String), Failure> {
    let opts = Options {
        limits,
        ..Options::default()
    };
    let (film, texts, name) = if scenes.is_empty() {
        let sources: Vec<Source> = BUILT_IN
            .iter()
            .map(|(n, t)| Source::new(format!("built-in:{n}"), *t))
            .collect();
        let film = Film::from_sources(&sources, None, opts).map_err(|e| (2, e))?;
        let texts = BUILT_IN
            .iter()
            .map(|(n, t)| SceneText {
                name: format!("built-in:{n}"),
                bytes: t.as_bytes().to_vec(),
            })
            .collect();
        (film, texts, "lmfilm".to_string())
    } else {
        let film = load_film(scenes, allow_commands, opts)?;
        let mut texts = Vec::new();
        for p in scenes {
            let bytes = std::fs::read(p).map_err(|e| (2, format!("{}: {e}", p.display())))?;
            texts.push(SceneText {
                name: p.display().to_string(),
                bytes,
            });
        }
        let name = scenes[0]
            .file_stem()
            .map_or("film".into(), |s| s.to_string_lossy().into_owned());
        if let Err(why) = lmfilm::lsys::options::plain_name(&name) {
            return Err((
                2,
                format!(
                    "{}: the film's name `{name}` (the scene's file name) {why}; name it with rs_file_path_name",
                    scenes[0].display()
                ),
            ));
        }
        (film, texts, name)
    };
    // `rs_file_path_name PATH NAME` names the frames.
    let name = rs_file(&film).map_or(name, |(_, n)| n);
    Ok((film, texts, name))
}

/// The scene's `rs_file_path_name` (table B1): the folder and the name
/// of its ray-traced images.
fn rs_file(film: &Film) -> Option<(PathBuf, String)> {
    film.anim.systems[0]
        .def
        .options
        .iter()
        .find_map(|o| match o {
            lmfilm::lsys::options::OptionItem::RsFilePathName { path, name } => {
                Some((PathBuf::from(path), name.clone()))
            }
            _ => None,
        })
}

/// The output folder: `-o`, else the scene's `rs_file_path_name` folder,
/// else `renders/<name>/`.
fn output_dir(out: Option<&Path>, film: &Film, name: &str) -> PathBuf {
    out.map(Path::to_path_buf)
        .or_else(|| rs_file(film).map(|(p, _)| p))
        .unwrap_or_else(|| Path::new("renders").join(name))
}

/// The options that change a derivation, as its record keeps them.
fn derive_options(allow_commands: bool) -> BTreeMap<String, String> {
    BTreeMap::from([
        ("allow_commands".to_string(), allow_commands.to_string()),
        (
            "segment_width".to_string(),
            Options::default().segment_width.to_string(),
        ),
    ])
}

/// Derives the film into `dir` (nothing when its record is up to date)
/// and writes the manifest.
fn derive_into(
    film: &mut Film,
    texts: &[SceneText],
    name: &str,
    dir: &Path,
    clean: bool,
    allow: bool,
) -> Result<bool, Failure> {
    let inputs = job::inputs(film, texts, name, derive_options(allow)).map_err(fail)?;
    let mut p = Progress::new("deriving frame");
    let (_, derived) =
        job::derive(film, inputs, dir, clean, &mut |k, n| p.tick(k, n)).map_err(fail)?;
    p.done();
    assemble::finish(dir).map_err(fail)?;
    Ok(derived)
}

/// Renders the frames of `dir` that `--frames` (else the film's own
/// selection) and `shard` name; returns (rendered now, selected).
fn render_into(
    dir: &Path,
    args: &RenderArgs,
    shard: Shard,
    max_pixels: u64,
) -> Result<(u64, u64), Failure> {
    let (settings, formats) = args.settings(max_pixels)?;
    let rec = job::open(dir).map_err(fail)?;
    let selection = match args.frames {
        Some(range) => FrameSelection::range(range),
        None => FrameSelection::from_text(&rec.selection).map_err(|e| {
            (
                2,
                format!("{}: derive.json: {e}; derive the film again", dir.display()),
            )
        })?,
    };
    let frames = selection.frames(rec.frame_count, shard);
    let mut p = Progress::new("rendering frame");
    let n = job::render_frames(dir, &frames, &settings, formats, max_pixels, &mut |k, n| {
        p.tick(k, n)
    })
    .map_err(fail)?;
    p.done();
    Ok((n, frames.len() as u64))
}

/// `lmfilm run`.
pub fn run(
    scenes: &[PathBuf],
    out: Option<&Path>,
    (args, sound_args): (&RenderArgs, &SoundArgs),
    allow: bool,
    (clean, limits): (bool, Limits),
) -> Result<(), Failure> {
    args.threads()?;
    args.settings(limits.pixels)?;
    let sound_settings = sound_args.settings()?;
    let (mut film, texts, name) = load(scenes, allow, limits)?;
    let dir = output_dir(out, &film, &name);
    let derived = derive_into(&mut film, &texts, &name, &dir, clean, allow)?;
    let (rendered, selected) = render_into(&dir, args, Shard::all(), limits.pixels)?;
    let sounded = soundtrack(&dir, &sound_settings)?;
    let mp4 = if mux::ffmpeg_available() {
        Some(job::mux(&dir).map_err(fail)?)
    } else {
        None
    };
    let m = assemble::finish(&dir).map_err(fail)?;
    let now = |done: bool| if done { "made now" } else { "up to date" };
    println!(
        "{}: {} frames derived ({}), {rendered} of {selected} frames rendered now (the others up to date), {} ({}), {}",
        dir.display(),
        m.frame_count,
        now(derived),
        dir.join(SOUNDTRACK_FILE).display(),
        now(sounded),
        dir.join(manifest::MANIFEST_FILE).display()
    );
    match mp4 {
        Some((path, made)) => println!("film: {} ({})", path.display(), now(made)),
        None => println!("ffmpeg is not installed: frames and soundtrack are in {}; `lmfilm mux {}` makes the MP4 once it is", dir.display(), dir.display()),
    }
    Ok(())
}

/// `lmfilm derive`.
pub fn derive(
    scenes: &[PathBuf],
    out: &Path,
    allow: bool,
    (clean, limits): (bool, Limits),
) -> Result<(), Failure> {
    let (mut film, texts, name) = load(scenes, allow, limits)?;
    let derived = derive_into(&mut film, &texts, &name, out, clean, allow)?;
    let rec = job::open(out).map_err(fail)?;
    println!(
        "{}: {} frames {} (scene/NNNN.snap, {}, {}, {})",
        out.display(),
        rec.frame_count,
        if derived { "derived" } else { "up to date" },
        job::EVENTS_FILE,
        lmfilm::film::record::DERIVE_RECORD,
        manifest::MANIFEST_FILE
    );
    Ok(())
}

/// `lmfilm render DIR`: a shard leaves the manifest to the stage that
/// finishes the film (`sound DIR`), since shards on many machines must
/// never write one file; a whole render writes it.
pub fn render(
    dir: &Path,
    args: &RenderArgs,
    shard: Option<Shard>,
    max_pixels: u64,
) -> Result<(), Failure> {
    args.threads()?;
    let (n, selected) = render_into(dir, args, shard.unwrap_or(Shard::all()), max_pixels)?;
    println!(
        "{}: {n} of {selected} frames rendered now (the others up to date) in {}",
        dir.display(),
        dir.join(lmfilm::film::frames::FRAMES_DIR).display()
    );
    match shard {
        Some(s) => println!(
            "shard {s} done; once every shard is, finish the film with: lmfilm sound {}",
            dir.display()
        ),
        None => {
            assemble::finish(dir).map_err(fail)?;
        }
    }
    Ok(())
}

/// `lmfilm mux DIR`.
pub fn mux_command(dir: &Path) -> Result<(), Failure> {
    let (mp4, made) = job::mux(dir).map_err(fail)?;
    assemble::finish(dir).map_err(fail)?;
    println!(
        "{}{}",
        mp4.display(),
        if made { "" } else { " (up to date)" }
    );
    Ok(())
}

/// `lmfilm verify DIR`: non-zero exit and each problem named.
pub fn verify(dir: &Path) -> Result<(), Failure> {
    let report = verify::verify(dir).map_err(|e| (2, e.to_string()))?;
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
    Err((
        1,
        format!(
            "{}: {} problems ({} files listed in manifest.json)",
            dir.display(),
            report.problems.len(),
            report.checked
        ),
    ))
}

/// The folder's soundtrack (unless up to date), saying what loudness
/// normalisation did.
fn soundtrack(dir: &Path, settings: &sound::Settings) -> Result<bool, Failure> {
    let report = job::soundtrack(dir, settings).map_err(fail)?;
    if let Some(n) = report.as_ref().and_then(|r| r.loudness.as_ref()) {
        eprintln!("{}: {}", dir.join(SOUNDTRACK_FILE).display(), n.summary());
        if let Some(w) = n.warning() {
            eprintln!("warning: {w}");
        }
    }
    Ok(report.is_some())
}

/// `lmfilm sound DIR` on a film folder: the soundtrack, then the manifest
/// (the stage that finishes a film rendered in shards).
pub fn sound_dir(dir: &Path, settings: &sound::Settings) -> Result<(), Failure> {
    let made = soundtrack(dir, settings)?;
    assemble::finish(dir).map_err(fail)?;
    println!(
        "{}{}, {}",
        dir.join(SOUNDTRACK_FILE).display(),
        if made { "" } else { " (up to date)" },
        dir.join(manifest::MANIFEST_FILE).display()
    );
    Ok(())
}

/// A number for JSON, which has no NaN or infinity: those are `null`.
fn json_number(v: f64) -> String {
    if v.is_finite() {
        v.to_string()
    } else {
        "null".into()
    }
}

/// `lmfilm trace`: one JSON object per frame on stdout.
pub fn trace(
    scenes: &[PathBuf],
    frames: Option<FrameRange>,
    allow: bool,
    limits: Limits,
) -> Result<(), Failure> {
    let (mut film, _, _) = load(scenes, allow, limits)?;
    let count = film.anim.frame_count();
    let range = frames.map_or(0..count, |r| r.within(count));
    let mut out = std::io::stdout().lock();
    for k in 0..range.end {
        film.scene().map_err(|e| (2, e))?;
        if range.contains(&k) {
            let time = film.anim.time();
            let events: Vec<String> = film
                .air
                .ongoing()
                .iter()
                .filter(|e| e.start == time)
                .map(|e| {
                    format!(
                        "{{\"sound\": {}, \"source\": {}, \"pos\": [{}, {}, {}]}}",
                        e.sound, e.source, e.position.x, e.position.y, e.position.z
                    )
                })
                .collect();
            let particles: Vec<String> = film
                .particles()
                .iter()
                .filter(|p| p.is_placed())
                .map(|p| {
                    let [x, y, z] = p.pos.to_array().map(json_number);
                    let [u, v, w] = p.vel.to_array().map(json_number);
                    format!(
                        "{{\"id\": {}, \"pos\": [{x}, {y}, {z}], \"vel\": [{u}, {v}, {w}], \"mass\": {}}}",
                        p.id,
                        json_number(p.mass)
                    )
                })
                .collect();
            let line = format!(
                "{{\"frame\": {k}, \"time\": {time}, \"particles\": [{}], \"actors\": [], \"sound_events\": [{}]}}",
                particles.join(", "),
                events.join(", ")
            );
            if let Err(e) = writeln!(out, "{line}") {
                if e.kind() == std::io::ErrorKind::BrokenPipe {
                    return Ok(());
                }
                return Err((1, format!("cannot write to standard output: {e}")));
            }
        }
        if k + 1 < range.end {
            film.step().map_err(|e| (2, e))?;
        }
    }
    Ok(())
}
