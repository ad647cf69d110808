//! The `lmfilm` command line: parses arguments and calls the library.

use std::io::{IsTerminal, Write};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::{Parser, Subcommand, ValueEnum};

mod film_commands;

use film_commands::{PresetArg, RenderArgs, SoundArgs};
use lmfilm::film::frames::{FrameRange, Shard};
use lmfilm::film::{job, record, Film};
use lmfilm::lsys::print::{self, Format};
use lmfilm::lsys::Limits;
use lmfilm::render::{self, Filter};
use lmfilm::scene::Scene;
use lmfilm::scene::{mesh, obj};
use lmfilm::sound;
use lmfilm::turtle::Options;

/// A deterministic film pipeline after Noser's behavioural L-systems.
///
/// A world is written as timed, parametric, conditional, stochastic,
/// context-sensitive L-systems in `.lm` definition files (see
/// docs/language.md).
#[derive(Parser)]
#[command(name = "lmfilm", version, about, long_about)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Print the word of each L-system at a frame (the thesis's PRINT option).
    ///
    /// One line per file, in the order given. Example:
    ///
    ///     lmfilm print scenes/examples/growing_tree.lm --time 1.5 --format full
    Print {
        #[command(flatten)]
        at: FrameArgs,
        /// `symbols`: symbol characters only; `full`: X(age,x,y,z,f1,f2,f3).
        #[arg(long, value_enum, default_value_t = PrintFormat::Symbols)]
        format: PrintFormat,
    },
    /// Export a frame's whole geometry as a mesh (the thesis's SM option).
    ///
    /// Writes OUT.obj and OUT.mtl: every shape tessellated at its `n`
    /// resolution, instances expanded, in world coordinates. Example:
    ///
    ///     lmfilm export scenes/examples/cours_tree3.lm --time 3 -o renders/tree.obj
    Export {
        #[command(flatten)]
        at: FrameArgs,
        /// The OBJ file to write (its .mtl is written beside it).
        #[arg(short, long, value_name = "OUT.obj")]
        output: PathBuf,
        /// Diameter of the thin cylinders drawn for segments `R S`.
        #[arg(long, default_value_t = 0.05)]
        segment_width: f64,
    },
    /// Ray-trace one frame into OUT.png or OUT.exr (the thesis's snapshots).
    ///
    /// The extension chooses the format: PNG is 8-bit sRGB; EXR holds the
    /// layers RGBA, Z (depth), N (normal) and object id. Example:
    ///
    ///     lmfilm still scenes/examples/cours_tree3.lm --time 5 -o renders/tree.png --preset preview
    Still {
        #[command(flatten)]
        at: FrameArgs,
        /// The image to write: .png or .exr.
        #[arg(short, long, value_name = "OUT.png|OUT.exr")]
        output: PathBuf,
        /// Width in pixels (default: the scene's window).
        #[arg(long)]
        width: Option<u32>,
        /// Height in pixels (default: the scene's window).
        #[arg(long)]
        height: Option<u32>,
        /// Samples per pixel (default: 1 for preview, 16 for final).
        #[arg(long)]
        spp: Option<u32>,
        /// `preview`: 1 sample, no shadows, mirrors and glass approximated
        /// by one look; `final`: all.
        #[arg(long, value_enum, default_value_t = PresetArg::Final)]
        preset: PresetArg,
        /// Pixel filter.
        #[arg(long, value_enum, default_value_t = FilterArg::Box)]
        filter: FilterArg,
        /// Diameter of the thin cylinders drawn for segments `R S`.
        #[arg(long, default_value_t = 0.05)]
        segment_width: f64,
    },
    /// Make a whole film: derive, render every frame, the soundtrack, the
    /// manifest, and an MP4 when ffmpeg is installed.
    ///
    /// With no scene, the built-in film (a tree growing in the wind, a
    /// field of flowers, an aeroplane with its Doppler sound) goes to
    /// renders/lmfilm/. A re-run redoes exactly the outputs whose inputs
    /// (scenes, the files they name, settings) changed or whose bytes were
    /// damaged; a folder of another film is refused (`--clean` empties
    /// it). Examples:
    ///
    ///     lmfilm run
    ///
    ///     lmfilm run scenes/examples/airplane.lm -o renders/plane --preset preview
    Run {
        /// Definition files derived together (none: the built-in film).
        #[arg(value_name = "SCENE.lm")]
        scenes: Vec<PathBuf>,
        /// Output folder (default renders/<first scene's name>/).
        #[arg(short, long, value_name = "DIR")]
        output: Option<PathBuf>,
        #[command(flatten)]
        render: RenderArgs,
        #[command(flatten)]
        sound: SoundArgs,
        /// Let the scene run its `command_file` scripts.
        #[arg(long)]
        allow_commands: bool,
        /// Empty the folder's lmfilm outputs first (to reuse a folder that
        /// holds another film).
        #[arg(long)]
        clean: bool,
        #[command(flatten)]
        limits: LimitArgs,
    },
    /// The simulation alone: snapshots, sound event log and manifest.
    ///
    /// Writes DIR/scene/NNNN.snap per frame, DIR/soundtrack.events and
    /// DIR/manifest.json. Example:
    ///
    ///     lmfilm derive scenes/examples/airplane.lm -o renders/plane
    Derive {
        /// Definition files derived together as one animation.
        #[arg(required = true, value_name = "SCENE.lm")]
        scenes: Vec<PathBuf>,
        /// Output folder.
        #[arg(short, long, value_name = "DIR")]
        output: PathBuf,
        /// Let the scene run its `command_file` scripts.
        #[arg(long)]
        allow_commands: bool,
        /// Empty the folder's lmfilm outputs first (to reuse a folder that
        /// holds another film).
        #[arg(long)]
        clean: bool,
        #[command(flatten)]
        limits: LimitArgs,
    },
    /// Ray-trace a derived folder's snapshots into DIR/frames/.
    ///
    /// Shard K/N takes the frames f with f mod N = K − 1, so N processes
    /// (on N machines, at the same time, over one shared folder) cover the
    /// film once; each frame writes its own record, and `sound DIR`
    /// finishes the film. A frame is skipped only when its record shows
    /// the same snapshot and settings and its files are intact. Example:
    ///
    ///     lmfilm render renders/plane --shard 1/2
    Render {
        /// A folder made by `lmfilm derive` (or `run`).
        #[arg(value_name = "DIR")]
        dir: PathBuf,
        #[command(flatten)]
        render: RenderArgs,
        /// This process's share of the frames: K/N.
        #[arg(long, value_name = "K/N")]
        shard: Option<Shard>,
        /// Most pixels in one image (width × height).
        #[arg(long, value_name = "N", default_value_t = Limits::default().pixels)]
        max_pixels: u64,
    },
    /// Frames and soundtrack of a film folder into an MP4 through ffmpeg.
    ///
    /// Writes DIR/<name>.mp4 (H.264 + AAC). Example:
    ///
    ///     lmfilm mux renders/lmfilm
    Mux {
        /// A film folder with frames/<name>.NNNN.png.
        #[arg(value_name = "DIR")]
        dir: PathBuf,
    },
    /// Check a film folder: complete, intact, made from its own inputs.
    ///
    /// The manifest against the records, every file's bytes, each frame
    /// against its snapshot, the soundtrack against its log, frames not
    /// rendered, stray files. Exit code 1, each problem named. Example:
    ///
    ///     lmfilm verify renders/lmfilm
    Verify {
        /// A film folder with its manifest.json.
        #[arg(value_name = "DIR")]
        dir: PathBuf,
    },
    /// JSON Lines on stdout, one object per frame.
    ///
    /// Each object holds the frame, its time, the particles (id, pos, vel,
    /// mass), the actors and the sound events started. Example:
    ///
    ///     lmfilm trace scenes/examples/airplane.lm --frames 0..3
    Trace {
        /// Definition files derived together as one animation.
        #[arg(required = true, value_name = "SCENE.lm")]
        scenes: Vec<PathBuf>,
        /// Frames to list: A..B (B excluded), A..=B, A.. or N.
        #[arg(long, value_name = "A..B")]
        frames: Option<FrameRange>,
        /// Let the scene run its `command_file` scripts.
        #[arg(long)]
        allow_commands: bool,
        #[command(flatten)]
        limits: LimitArgs,
    },
    /// Render a sound event log into a soundtrack WAV (thesis 2.4.3).
    ///
    /// Every microphone hears every source with the exact delay of sound
    /// travelling between their moving positions, so Doppler shifts come
    /// out right; one channel per microphone, in ascending number. A
    /// folder DIR stands for DIR/soundtrack.events → DIR/soundtrack.wav.
    /// A scene SCENE.lm is derived first and its log (the `T` symbol's
    /// events) written as soundtrack.events beside the WAV (default
    /// renders/<name>/). The format is docs/sound-events.md. Examples:
    ///
    ///     lmfilm sound scenes/examples/flyby.events -o renders/flyby.wav
    ///
    ///     lmfilm sound scenes/examples/airplane.lm
    Sound {
        /// The sound event log, a folder holding soundtrack.events, or a
        /// scene (.lm) to derive.
        #[arg(value_name = "EVENTS|DIR|SCENE.lm")]
        events: PathBuf,
        /// The WAV file to write (default: the events file's name, .wav;
        /// for a scene, renders/<name>/soundtrack.wav).
        #[arg(short, long, value_name = "OUT.wav")]
        output: Option<PathBuf>,
        /// A folder of sound files, searched after the events file's folder
        /// and before the sound library built into lmfilm.
        #[arg(long, value_name = "DIR")]
        library: Option<PathBuf>,
        #[command(flatten)]
        settings: SoundArgs,
        /// Let a scene SCENE.lm run its `command_file` scripts.
        #[arg(long)]
        allow_commands: bool,
        #[command(flatten)]
        limits: LimitArgs,
    },
}

#[derive(Clone, Copy, ValueEnum)]
enum FilterArg {
    Box,
    Gaussian,
}

/// The scene files and the frame a command works on.
#[derive(clap::Args)]
struct FrameArgs {
    /// Definition files derived together as one animation.
    #[arg(required = true, value_name = "SCENE.lm")]
    scenes: Vec<PathBuf>,
    /// Frame number N: the words after N steps of Δt (default 0).
    #[arg(long, conflicts_with = "time")]
    frame: Option<u64>,
    /// Time T in seconds: the frame nearest to T.
    #[arg(long, allow_negative_numbers = true)]
    time: Option<f64>,
    /// Let the scene run its `command_file` scripts.
    #[arg(long)]
    allow_commands: bool,
    #[command(flatten)]
    limits: LimitArgs,
}

/// The limits of docs/limits.md: a run that would pass one stops with a
/// message (exit 2) naming the flag that raises it.
#[derive(clap::Args)]
struct LimitArgs {
    /// Most symbols in one L-system's word (56 bytes each, two words).
    #[arg(long, value_name = "N", default_value_t = Limits::default().symbols)]
    max_symbols: usize,
    /// Most primitives (shapes, triangles, copies) in one frame's scene.
    #[arg(long, value_name = "N", default_value_t = Limits::default().shapes)]
    max_shapes: usize,
    /// Most frames in one film (t_final / Δt + 1).
    #[arg(long, value_name = "N", default_value_t = Limits::default().frames)]
    max_frames: u64,
    /// Most pixels in one image (width × height).
    #[arg(long, value_name = "N", default_value_t = Limits::default().pixels)]
    max_pixels: u64,
}

impl LimitArgs {
    fn limits(&self) -> Limits {
        Limits {
            symbols: self.max_symbols,
            shapes: self.max_shapes,
            frames: self.max_frames,
            pixels: self.max_pixels,
        }
    }
}

#[derive(Clone, Copy, ValueEnum)]
enum PrintFormat {
    Symbols,
    Full,
}

/// The film derived to the frame `--frame`/`--time` names, every frame
/// interpreted on the way (sound events and `?` queries included).
fn derive_to(at: &FrameArgs, opts: Options) -> Result<Film, (u8, String)> {
    let mut film = film_commands::load_film(&at.scenes, at.allow_commands, opts)?;
    let last = film.anim.frame_count() - 1;
    let dt = film.anim.camera.dt;
    let target = match (at.frame, at.time) {
        (_, Some(t)) if !t.is_finite() || t < 0.0 => {
            return Err((2, format!("--time must be a time ≥ 0 in seconds, got {t}")))
        }
        (_, Some(t)) => film.anim.frame_at(t),
        (Some(n), None) => n,
        (None, None) => 0,
    };
    // A frame past the end is not part of the film: say where it ends.
    if target > last {
        let asked = match at.time {
            Some(t) => format!("--time {t:?}"),
            None => format!("--frame {target}"),
        };
        return Err((
            2,
            format!(
                "{asked} is past the end: the film {} ends at frame {last} (time {} s); its t_final_interval sets its length",
                at.scenes[0].display(),
                last as f64 * dt
            ),
        ));
    }
    let mut progress = film_commands::Progress::new("deriving frame");
    film.advance_to(target, |k, n| progress.tick(k, n))
        .map_err(|e| (2, e))?;
    progress.done();
    Ok(film)
}

/// The scene of the film's current frame; warnings go to stderr.
fn frame_scene(film: &mut Film) -> Result<Scene, (u8, String)> {
    let (scene, messages) = film.scene().map_err(|e| (2, e))?;
    for m in messages {
        eprintln!("{m}");
    }
    Ok(scene)
}

fn export(at: &FrameArgs, output: &Path, segment_width: f64) -> Result<(), (u8, String)> {
    if !(segment_width.is_finite() && segment_width > 0.0) {
        return Err((
            2,
            format!("--segment-width must be > 0, got {segment_width}"),
        ));
    }
    let opts = Options {
        segment_width,
        limits: at.limits.limits(),
    };
    let mut film = derive_to(at, opts)?;
    let scene = frame_scene(&mut film)?;
    // Shapes become many triangles each: the count is the export's.
    let (count, max) = (mesh::expanded_count(&scene), opts.limits.shapes as u64);
    if count > max {
        return Err((
            2,
            format!(
                "{}: frame {}: the export would hold {count} triangles, over the limit of {max}; raise it with --max-shapes N",
                at.scenes[0].display(),
                film.anim.frame
            ),
        ));
    }
    if let Some(dir) = output.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).map_err(|e| {
            (
                1,
                format!("{}: cannot create the folder: {e}", dir.display()),
            )
        })?;
    }
    obj::write_obj(&scene, output)
        .map_err(|e| (1, format!("{}: cannot write: {e}", output.display())))?;
    // Say what was written, so the user finds it (and its .mtl).
    println!(
        "{}, {}",
        output.display(),
        output.with_extension("mtl").display()
    );
    Ok(())
}

#[allow(clippy::too_many_arguments)]
fn still(
    at: &FrameArgs,
    output: &Path,
    size: (Option<u32>, Option<u32>),
    spp: Option<u32>,
    preset: PresetArg,
    filter: FilterArg,
    segment_width: f64,
) -> Result<(), (u8, String)> {
    let ext = output
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    if !matches!(ext.as_deref(), Some("png") | Some("exr")) {
        return Err((
            2,
            format!("{}: the output must end in .png or .exr", output.display()),
        ));
    }
    if !(segment_width.is_finite() && segment_width > 0.0) {
        return Err((
            2,
            format!("--segment-width must be > 0, got {segment_width}"),
        ));
    }
    let limits = at.limits.limits();
    // Given sizes are checked before the derivation, the camera's after.
    if let (Some(w), Some(h)) = size {
        Limits::check_pixels(w, h, limits.pixels).map_err(|e| (2, e))?;
    }
    let opts = Options {
        segment_width,
        limits,
    };
    let mut film = derive_to(at, opts)?;
    let scene = frame_scene(&mut film)?;
    let w = size.0.unwrap_or(scene.camera.width);
    let h = size.1.unwrap_or(scene.camera.height);
    if !(1..=32768).contains(&w) || !(1..=32768).contains(&h) {
        return Err((
            2,
            format!("the image size must be 1..32768 pixels a side, got {w}×{h}"),
        ));
    }
    Limits::check_pixels(w, h, limits.pixels).map_err(|e| {
        let scene = at.scenes[0].display();
        (2, format!("{scene}: frame {}: {e}", film.anim.frame))
    })?;
    let mut settings = film_commands::quality(preset, w, h, spp)?;
    settings.filter = match filter {
        FilterArg::Box => Filter::Box,
        FilterArg::Gaussian => Filter::Gaussian,
    };
    settings.frame = film.anim.frame;
    // PNG holds colour only: no need for the layer rays.
    settings.layers = ext.as_deref() == Some("exr");
    let accel = render::Accel::new(&scene);
    let show = std::io::stderr().is_terminal();
    let img = render::render_with(&accel, &settings, &|done, rows| {
        // Every 5 % of the rows, on a terminal only.
        if show && done * 20 / rows != (done - 1) * 20 / rows {
            eprint!("\rrendering {}%", done * 100 / rows);
        }
    });
    if show {
        eprint!("\r\x1b[K");
    }
    if let Some(dir) = output.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).map_err(|e| {
            (
                1,
                format!("{}: cannot create the folder: {e}", dir.display()),
            )
        })?;
    }
    render::output::write(&img, output).map_err(|e| (1, format!("{}: {e}", output.display())))?;
    // Say what was written, so the user finds it.
    println!("{} ({w}×{h}, {} spp)", output.display(), settings.spp);
    Ok(())
}

fn print_words(at: &FrameArgs, format: PrintFormat) -> Result<(), (u8, String)> {
    let opts = Options {
        limits: at.limits.limits(),
        ..Options::default()
    };
    let mut film = derive_to(at, opts)?;
    // The turtle runs on the printed frame too, so `?` shows its position;
    // its warnings and prints are about drawing, which `print` does not.
    film.scene().map_err(|e| (2, e))?;
    let (anim, sensors) = film.parts();
    let format = match format {
        PrintFormat::Symbols => Format::Symbols,
        PrintFormat::Full => Format::Full,
    };
    let (time, seed) = (anim.time(), anim.camera.seed);
    let mut out = std::io::stdout().lock();
    for ls in &mut anim.systems {
        let line = print::word(ls, format, time, seed, sensors);
        if let Err(e) = writeln!(out, "{line}") {
            // A closed pipe (`| head`) is not an error of ours.
            if e.kind() == std::io::ErrorKind::BrokenPipe {
                return Ok(());
            }
            return Err((1, format!("cannot write to standard output: {e}")));
        }
    }
    Ok(())
}

/// Derives every frame of a scene and writes its sound event log,
/// `soundtrack.events` beside the soundtrack (default folder
/// `renders/<scene name>/`). Returns the log's and the WAV's paths.
fn scene_events(
    scene: &Path,
    output: Option<&Path>,
    allow_commands: bool,
    limits: Limits,
) -> Result<(PathBuf, PathBuf), (u8, String)> {
    let wav = output.map_or_else(
        || {
            let name = scene.file_stem().unwrap_or_default();
            Path::new("renders").join(name).join("soundtrack.wav")
        },
        Path::to_path_buf,
    );
    let events = wav.with_file_name("soundtrack.events");
    // A film folder's log and soundtrack belong to its records.
    if let Some(dir) = wav
        .parent()
        .filter(|d| d.join(record::DERIVE_RECORD).exists())
    {
        return Err((
            2,
            format!(
                "{}: this folder holds a film, whose soundtrack comes from its own records: \
                 `lmfilm sound {}` renders it; or write this scene's elsewhere with -o OUT.wav",
                dir.display(),
                dir.display()
            ),
        ));
    }
    let scenes = [scene.to_path_buf()];
    let opts = Options {
        limits,
        ..Options::default()
    };
    let mut film = film_commands::load_film(&scenes, allow_commands, opts)?;
    let mut progress = film_commands::Progress::new("deriving frame");
    let fail = |e: job::Error| (e.code, e.message);
    job::every_frame(&mut film, &mut |k, n| progress.tick(k, n), |_, _| Ok(())).map_err(fail)?;
    progress.done();
    job::write_events(&film, &events).map_err(fail)?;
    Ok((events, wav))
}

#[allow(clippy::too_many_arguments)]
fn sound(
    events: &Path,
    output: Option<&Path>,
    library: Option<&Path>,
    (args, allow_commands, limits): (&SoundArgs, bool, Limits),
) -> Result<(), (u8, String)> {
    let settings = args.settings()?;
    if events.is_dir() && output.is_none() && events.join(record::DERIVE_RECORD).exists() {
        return film_commands::sound_dir(events, &settings);
    }
    let (events, output) = if events.extension().is_some_and(|e| e == "lm") {
        scene_events(events, output, allow_commands, limits)?
    } else {
        sound::paths(events, output)
    };
    let show = std::io::stderr().is_terminal();
    let report = sound::render_file(&events, &output, &settings, library, &|done, total| {
        // Every 5 % of the tasks, on a terminal only.
        if show && done * 20 / total != (done - 1) * 20 / total {
            eprint!("\rrendering sound {}%", done * 100 / total);
        }
    });
    if show {
        eprint!("\r\x1b[K");
    }
    let report = report.map_err(|e| (e.exit_code(), e.to_string()))?;
    match report.loudness {
        Some(n) => {
            eprintln!("{}: {}", output.display(), n.summary());
            if let Some(w) = n.warning() {
                eprintln!("warning: {}: {w}", output.display());
            }
        }
        None => eprintln!("{}", output.display()),
    }
    if report.clipped > 0 {
        eprintln!(
            "warning: {}: {} samples beyond full scale were clipped; try --float or --attenuation inverse",
            output.display(),
            report.clipped
        );
    }
    Ok(())
}

/// A frame allocates and frees hundreds of megabytes (OBJ text, BVH build
/// arrays). glibc maps each big block afresh and unmaps it when freed, so
/// every reuse pays a page fault per 4 KiB (~10 % of a large frame);
/// serving big blocks from the heap and never trimming it lets freed
/// memory be reused. The peak footprint is unchanged.
#[cfg(all(target_os = "linux", target_env = "gnu"))]
fn keep_freed_memory() {
    // SAFETY: mallopt only tunes the allocator; no thread runs yet.
    unsafe {
        libc::mallopt(libc::M_MMAP_MAX, 0);
        libc::mallopt(libc::M_TRIM_THRESHOLD, i32::MAX);
    }
}

#[cfg(not(all(target_os = "linux", target_env = "gnu")))]
fn keep_freed_memory() {}

fn main() -> ExitCode {
    keep_freed_memory();
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Print { at, format } => print_words(&at, format),
        Command::Export {
            at,
            output,
            segment_width,
        } => export(&at, &output, segment_width),
        Command::Still {
            at,
            output,
            width,
            height,
            spp,
            preset,
            filter,
            segment_width,
        } => still(
            &at,
            &output,
            (width, height),
            spp,
            preset,
            filter,
            segment_width,
        ),
        Command::Run {
            scenes,
            output,
            render,
            sound,
            allow_commands,
            clean,
            limits,
        } => film_commands::run(
            &scenes,
            output.as_deref(),
            (&render, &sound),
            allow_commands,
            (clean, limits.limits()),
        ),
        Command::Derive {
            scenes,
            output,
            allow_commands,
            clean,
            limits,
        } => film_commands::derive(&scenes, &output, allow_commands, (clean, limits.limits())),
        Command::Render {
            dir,
            render,
            shard,
            max_pixels,
        } => film_commands::render(&dir, &render, shard, max_pixels),
        Command::Mux { dir } => film_commands::mux_command(&dir),
        Command::Verify { dir } => film_commands::verify(&dir),
        Command::Trace {
            scenes,
            frames,
            allow_commands,
            limits,
        } => film_commands::trace(&scenes, frames, allow_commands, limits.limits()),
        Command::Sound {
            events,
            output,
            library,
            settings,
            allow_commands,
            limits,
        } => sound(
            &events,
            output.as_deref(),
            library.as_deref(),
            (&settings, allow_commands, limits.limits()),
        ),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err((code, msg)) => {
            eprintln!("error: {msg}");
            ExitCode::from(code)
        }
    }
}
