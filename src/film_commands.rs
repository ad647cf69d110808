//! The film commands of DESIGN §5 — run, derive, render, mux, verify,
//! trace — as thin wrappers over `lmfilm::film`.

use std::io::{IsTerminal, Write};
use std::path::{Path, PathBuf};
use std::time::Instant;

use clap::{Args, ValueEnum};
use lmfilm::film::frames::{frame_pattern, rs_switch, FrameRange, FrameSelection, Shard};
use lmfilm::film::job::{self, Formats, SceneText, SOUNDTRACK_FILE};
use lmfilm::film::{manifest, mux, Film};
use lmfilm::lsys::{Limits, Source};
use lmfilm::render::Settings;
use lmfilm::sound;
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
    /// `png` (8-bit sRGB), `exr` (RGBA, Z, normal, object id) or `both`.
    #[arg(long, value_enum, default_value_t = FormatArg::Png)]
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

/// The scenes given, or the built-in film; with their names for the
/// manifest and the film's name.
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
        let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/film");
        let film = Film::from_sources(&sources, Some(&dir), opts).map_err(|e| (2, e))?;
        let texts = BUILT_IN
            .iter()
            .map(|(n, t)| SceneText {
                name: format!("built-in:{n}"),
                bytes: t.as_bytes().to_vec(),
            })
            .collect();
        (film, texts, "lmfilm".to_string())
    } else {
        let film = Film::load(scenes, opts).map_err(|e| (2, e))?;
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
        (film, texts, name)
    };
    // `rs_file_path_name PATH NAME` names the frames.
    let name = rs_file(&film).map_or(name, |(_, n)| n);
    let mut film = film;
    if let Some(what) = film.wants_commands() {
        if allow_commands {
            let dir = scenes
                .first()
                .and_then(|p| p.parent())
                .unwrap_or(Path::new("."));
            film.allow_commands(dir);
        } else {
            return Err((
                2,
                format!(
                    "{what}: this scene wants to run scripts on this machine; a scene never runs anything by default. If you trust it, run again with --allow-commands"
                ),
            ));
        }
    }
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

fn derive_into(
    film: &mut Film,
    texts: &[SceneText],
    name: &str,
    dir: &Path,
) -> Result<(), Failure> {
    let mut p = Progress::new("deriving frame");
    job::derive(film, texts, name, dir, &mut |k, n| p.tick(k, n)).map_err(fail)?;
    p.done();
    Ok(())
}

fn render_into(
    dir: &Path,
    args: &RenderArgs,
    shard: Shard,
    rs: Option<Vec<i64>>,
    max_pixels: u64,
) -> Result<u64, Failure> {
    let (settings, formats) = args.settings(max_pixels)?;
    let m = job::open(dir).map_err(fail)?;
    let selection = FrameSelection::resolve(args.frames, rs.as_deref());
    let frames = selection.frames(m.frame_count, shard);
    let mut p = Progress::new("rendering frame");
    let n = job::render_frames(dir, &frames, &settings, formats, max_pixels, &mut |k, n| {
        p.tick(k, n)
    })
    .map_err(fail)?;
    p.done();
    Ok(n)
}

/// `lmfilm run`.
pub fn run(
    scenes: &[PathBuf],
    out: Option<&Path>,
    args: &RenderArgs,
    allow: bool,
    limits: Limits,
) -> Result<(), Failure> {
    args.threads()?;
    args.settings(limits.pixels)?;
    let (mut film, texts, name) = load(scenes, allow, limits)?;
    let rs = rs_switch(&film.anim.systems[0].def.options).map(<[i64]>::to_vec);
    let dir = output_dir(out, &film, &name);
    derive_into(&mut film, &texts, &name, &dir)?;
    let rendered = render_into(&dir, args, Shard::all(), rs, limits.pixels)?;
    job::soundtrack(&dir, &sound::Settings::default()).map_err(fail)?;
    let m = job::open(&dir).map_err(fail)?;
    println!(
        "{}: {} frames ({rendered} rendered now), soundtrack {}",
        dir.display(),
        m.frame_count,
        dir.join(SOUNDTRACK_FILE).display()
    );
    if mux::ffmpeg_available() {
        let mp4 = mux_dir(&dir)?;
        println!("film: {}", mp4.display());
    } else {
        println!("ffmpeg is not installed: frames and soundtrack are in {}; `lmfilm mux {}` makes the MP4 once it is", dir.display(), dir.display());
    }
    Ok(())
}

/// `lmfilm derive`.
pub fn derive(scenes: &[PathBuf], out: &Path, allow: bool, limits: Limits) -> Result<(), Failure> {
    let (mut film, texts, name) = load(scenes, allow, limits)?;
    derive_into(&mut film, &texts, &name, out)?;
    println!(
        "{}: {} frames derived",
        out.display(),
        film.anim.frame_count()
    );
    Ok(())
}

/// `lmfilm render DIR`.
pub fn render(
    dir: &Path,
    args: &RenderArgs,
    shard: Option<Shard>,
    max_pixels: u64,
) -> Result<(), Failure> {
    args.threads()?;
    let n = render_into(dir, args, shard.unwrap_or(Shard::all()), None, max_pixels)?;
    println!("{}: {n} frames rendered", dir.display());
    Ok(())
}

fn mux_dir(dir: &Path) -> Result<PathBuf, Failure> {
    let m = job::open(dir).map_err(fail)?;
    let name = job::film_name(&m);
    let rate = mux::FrameRate::from_dt(m.dt).map_err(|e| (2, e.to_string()))?;
    let track = dir.join(SOUNDTRACK_FILE);
    let track = track.exists().then_some(Path::new(SOUNDTRACK_FILE));
    mux::mux(dir, &name, rate, &frame_pattern(&name, "png"), track).map_err(|e| (1, e.to_string()))
}

/// `lmfilm mux DIR`.
pub fn mux_command(dir: &Path) -> Result<(), Failure> {
    let mp4 = mux_dir(dir)?;
    println!("{}", mp4.display());
    Ok(())
}

/// `lmfilm verify DIR`: non-zero exit and each bad file named.
pub fn verify(dir: &Path) -> Result<(), Failure> {
    let report = manifest::verify(dir).map_err(|e| (2, e.to_string()))?;
    if report.is_ok() {
        println!(
            "{}: {} files match manifest.json",
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
            "{}: {} of {} files do not match manifest.json",
            dir.display(),
            report.problems.len(),
            report.checked
        ),
    ))
}

/// `lmfilm sound DIR` on a film folder: the soundtrack, then the manifest.
pub fn sound_dir(dir: &Path, settings: &sound::Settings) -> Result<(), Failure> {
    job::soundtrack(dir, settings).map_err(fail)?;
    println!("{}", dir.join(SOUNDTRACK_FILE).display());
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
    limits: Limits,
) -> Result<(), Failure> {
    let (mut film, _, _) = load(scenes, false, limits)?;
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
