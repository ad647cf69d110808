//! The `lmfilm` command line: parses arguments and calls the library's
//! commands (`lmfilm::commands`).

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Parser, Subcommand, ValueEnum};

use lmfilm::commands::args::{
    segment_width, FrameArgs, RenderArgs, SceneArgs, SoundArgs, StillArgs, WorkArgs,
};
use lmfilm::commands::film::FilmArgs;
use lmfilm::commands::sound::SoundInput;
use lmfilm::commands::{self, trace::trace};
use lmfilm::lsys::Limits;
use lmfilm::production::frames::{FrameRange, Shard};
use lmfilm::production::settings::VideoRequest;
use lmfilm::render::accel::tri4::{Simd, SIMD_VAR};

/// A deterministic film pipeline after Noser's behavioural L-systems.
///
/// A world is written as timed, parametric, conditional, stochastic,
/// context-sensitive L-systems in `.lm` definition files (see
/// docs/language.md).
#[derive(Parser)]
#[command(name = "lmfilm", version, about, long_about, after_long_help = ENVIRONMENT)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

/// What `--help` says of the environment.
const ENVIRONMENT: &str = "Environment:
  RAYON_NUM_THREADS  threads (the bytes are the same for any count)
  LMFILM_SIMD        baseline, avx or avx512: the widest SIMD path the ray tracer may
                     take (default: the widest this CPU has). Every path gives the same
                     bytes; a farm checks its machines against each other so:
                     LMFILM_SIMD=baseline lmfilm still scenes/examples/gallery.lm -o renders/base.png";

#[derive(Subcommand)]
enum Command {
    /// Print the word of each L-system at a frame (the thesis's PRINT option).
    ///
    /// One line per file, in the order given. Example:
    ///
    ///     lmfilm print scenes/examples/growing_tree.lm --time 1.5 --format full
    Print {
        /// `symbols`: symbol characters only; `full`: X(age,x,y,z,f1,f2,f3).
        #[arg(long, value_enum, default_value_t = PrintFormat::Symbols)]
        format: PrintFormat,
        #[command(flatten)]
        at: FrameArgs,
    },
    /// Spell a definition file in the other form: classic (.lm) to
    /// readable (.lmr), or readable to classic.
    ///
    /// Both forms parse into the same definition, so the film, its frames
    /// and its sound are the same bytes; comments and line breaks are
    /// kept. Without -o the result is printed. Example:
    ///
    ///     lmfilm convert scenes/examples/parametric.lm -o renders/parametric.lmr
    Convert {
        /// The file to convert: .lm or .lmr.
        #[arg(value_name = "FILE")]
        input: PathBuf,
        /// Where to write the other spelling (default: print it).
        #[arg(short, long, value_name = "OUT")]
        output: Option<PathBuf>,
    },
    /// Serve editors: a language server for .lm and .lmr files over stdio.
    ///
    /// Diagnostics as you type, hover that says what a symbol, function
    /// or parameter means, completion of names, go-to-definition of a
    /// symbol's rules. Point an editor's LSP client at it, e.g. for Neovim:
    ///
    ///     vim.lsp.start({ name = "lmfilm", cmd = { "lmfilm", "lsp" } })
    Lsp,
    /// Export a frame's whole geometry as a mesh (the thesis's SM option).
    ///
    /// Writes OUT.obj and OUT.mtl: every shape tessellated at its `n`
    /// resolution, instances expanded, in world coordinates. Example:
    ///
    ///     lmfilm export scenes/examples/cours_tree3.lm --time 3 -o renders/tree.obj
    Export {
        /// The OBJ file to write (its .mtl is written beside it).
        #[arg(short, long, value_name = "OUT.obj")]
        output: PathBuf,
        /// Diameter of the thin cylinders drawn for segments `R S`.
        #[arg(long, default_value_t = 0.05, value_parser = segment_width)]
        segment_width: f64,
        #[command(flatten)]
        at: FrameArgs,
    },
    /// Ray-trace one frame into OUT.png or OUT.exr (the thesis's snapshots).
    ///
    /// The extension chooses the format: PNG is 8-bit sRGB; EXR holds the
    /// layers RGBA, Z (depth), N (normal) and object id. Example:
    ///
    ///     lmfilm still scenes/examples/cours_tree3.lm --time 5 -o renders/tree.png --preset preview
    Still {
        #[command(flatten)]
        still: StillArgs,
    },
    /// Watch scene files and render a preview still of one frame each
    /// time one of them (or a file it names) is saved: a live preview
    /// beside an editor. Errors are printed, not fatal; Ctrl-C stops.
    ///
    /// The preview preset unless --preset is given. Example:
    ///
    ///     lmfilm watch scenes/examples/cours_tree3.lm --time 5 -o renders/preview.png
    ///
    ///     lmfilm watch scenes/examples/first.lmr --frames 90..=100 -o renders/first.png
    Watch {
        /// Stop after this many renders (for scripts; default: never).
        #[arg(long, value_name = "N")]
        count: Option<u32>,
        /// A short range instead of one frame: A..B (B excluded) or
        /// A..=B, written OUT.NNNN.png.
        #[arg(long, value_name = "A..B", conflicts_with_all = ["frame", "time"])]
        frames: Option<FrameRange>,
        #[command(flatten)]
        still: StillArgs,
    },
    /// Make a whole film: derive, render every frame, the soundtrack, the
    /// video (DIR/<name>.mp4, H.264 and Opus, made by lmfilm) and the
    /// manifest.
    ///
    /// With no scene, the built-in film goes to renders/lmfilm/: 14 s of
    /// the tennis match (two players, the ball, the referee calling the
    /// score) on its set, the camera circling down from over the trees to
    /// behind the referee, rendered at the final preset with 3 samples
    /// per pixel unless --preset or --spp is given. The former built-in
    /// film (a tree growing in the wind, a field of flowers, an aeroplane
    /// with its Doppler sound) is the second example. A re-run redoes
    /// exactly the outputs whose inputs (scenes, the files they name,
    /// settings) changed or whose bytes were damaged; a folder of another
    /// film is refused (`--clean` empties it). Examples:
    ///
    ///     lmfilm run
    ///
    ///     lmfilm run scenes/film/tree.lm scenes/film/flowers.lm scenes/film/airplane.lm
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
        work: WorkArgs,
        /// Empty the folder's lmfilm outputs first (to reuse a folder that
        /// holds another film).
        #[arg(long)]
        clean: bool,
        #[command(flatten)]
        render: RenderArgs,
        #[command(flatten)]
        sound: SoundArgs,
        #[command(flatten)]
        video: VideoRequest,
        #[command(flatten)]
        scene: SceneArgs,
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
        /// Empty the folder's lmfilm outputs first (to reuse a folder that
        /// holds another film).
        #[arg(long)]
        clean: bool,
        /// Print where the time went: the frame loop, each actor's
        /// vision, snapshots, actor images.
        #[arg(long)]
        timings: bool,
        #[command(flatten)]
        scene: SceneArgs,
    },
    /// Ray-trace a derived folder's snapshots into DIR/frames/.
    ///
    /// With the film's settings (DIR/settings.json, as `run` or `farm
    /// slurm` recorded them), the options given over them: with none, a
    /// re-render gives the same bytes as before. An option that changes
    /// them renders every frame again, and is refused with --frames or
    /// --shard (a folder never holds frames of two settings). Shard K/N
    /// takes the frames f with f mod N = K − 1, so N processes (on N
    /// machines, at the same time, over one shared folder) cover the film
    /// once; each frame writes its own record, and `sound DIR` finishes
    /// the film. A frame is skipped only when its record shows the same
    /// snapshot and settings and its files are intact. Examples:
    ///
    ///     lmfilm render renders/plane --frames 3..5
    ///
    ///     lmfilm render renders/plane --shard 1/2
    Render {
        /// A folder made by `lmfilm derive` (or `run`).
        #[arg(value_name = "DIR")]
        dir: PathBuf,
        #[command(flatten)]
        work: WorkArgs,
        /// This process's share of the frames: K/N.
        #[arg(long, value_name = "K/N")]
        shard: Option<Shard>,
        /// Most pixels in one image (width × height).
        #[arg(long, value_name = "N", default_value_t = Limits::default().pixels)]
        max_pixels: u64,
        #[command(flatten)]
        render: RenderArgs,
    },
    /// Frames and soundtrack of a film folder into its video.
    ///
    /// Writes DIR/<name>.mp4 (H.264 and Opus, made by lmfilm itself: no
    /// ffmpeg needed) from the PNG frames and soundtrack.wav. Example:
    ///
    ///     lmfilm mux renders/lmfilm
    Mux {
        /// A film folder with frames/<name>.NNNN.png.
        #[arg(value_name = "DIR")]
        dir: PathBuf,
        #[command(flatten)]
        video: VideoRequest,
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
    /// A film on a render farm: a Slurm job chain (docs/farm.md).
    #[command(subcommand)]
    Farm(FarmCommand),
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
        #[command(flatten)]
        scene: SceneArgs,
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
        #[command(flatten)]
        scene: SceneArgs,
    },
}

#[derive(Clone, Copy, ValueEnum)]
enum PrintFormat {
    Symbols,
    Full,
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

/// The render-farm commands.
#[derive(Subcommand)]
enum FarmCommand {
    /// Write the film's Slurm job chain into DIR/farm/ and submit it.
    ///
    /// One derive job, an array of N render tasks (task i renders shard
    /// i/N), one finishing job (the frames a shard left, soundtrack,
    /// manifest, MP4 when ffmpeg exists, verify). A job that fails goes
    /// again to another node (3 attempts; a node that failed 2 jobs is
    /// left behind). Every value a script holds is checked first: Slurm
    /// names, times and sizes in their forms, paths in UTF-8 without
    /// control characters. The film's settings (render, sound, limits, consent to
    /// scripts) are resolved here, recorded in DIR/settings.json and
    /// passed to every job. DIR must be a folder every node shares; the
    /// jobs run this lmfilm by its absolute path. Submitting again
    /// resumes: only what is missing is redone. Example:
    ///
    ///     lmfilm farm slurm scenes/tennis/match.lm -o /shared/match --shards 8 --preset preview --width 480 --dry-run
    Slurm(Box<commands::farm::SlurmArgs>),
    /// Frames done of the total with a bar, the time left, the last
    /// frame rendered (the image where the terminal shows images, else a
    /// text preview), the chain's jobs as Slurm accounts for them, and
    /// the nodes that failed with their logs' last words.
    ///
    ///     lmfilm farm status /shared/match --watch
    Status(commands::farm::StatusArgs),
}

fn main() -> ExitCode {
    keep_freed_memory();
    let cli = Cli::parse();
    // Empty is unset.
    if let Some(v) = std::env::var_os(SIMD_VAR).filter(|v| !v.is_empty()) {
        if v.to_str().and_then(Simd::parse).is_none() {
            let names: Vec<_> = Simd::ALL.iter().map(|s| s.name()).collect();
            eprintln!(
                "error: {SIMD_VAR}={v:?}: expected one of {}",
                names.join(", ")
            );
            return ExitCode::from(2);
        }
    }
    let result = match cli.command {
        Command::Print { at, format } => {
            commands::frame::print(&at, matches!(format, PrintFormat::Full))
        }
        Command::Convert { input, output } => commands::convert::convert(&input, output.as_deref()),
        Command::Lsp => commands::lsp::lsp(),
        Command::Export {
            at,
            output,
            segment_width,
        } => commands::frame::export(&at, &output, segment_width),
        Command::Still { still } => commands::frame::still(&still).map(|_| ()),
        Command::Watch {
            still,
            count,
            frames,
        } => commands::watch::watch(&still, frames.as_ref(), count),
        Command::Run {
            scenes,
            output,
            work,
            clean,
            render,
            sound,
            video,
            scene,
        } => {
            let film = FilmArgs::new(&scenes, &scene, clean);
            commands::film::run(&film, output.as_deref(), &render, &work, &sound, &video)
        }
        Command::Derive {
            scenes,
            output,
            clean,
            timings,
            scene,
        } => commands::film::derive(&FilmArgs::new(&scenes, &scene, clean), &output, timings),
        Command::Farm(FarmCommand::Slurm(args)) => commands::farm::slurm(&args),
        Command::Farm(FarmCommand::Status(args)) => commands::farm::status(&args),
        Command::Render {
            dir,
            work,
            render,
            shard,
            max_pixels,
        } => commands::film::render(&dir, &render, &work, shard, max_pixels),
        Command::Mux { dir, video } => commands::film::mux(&dir, &video),
        Command::Verify { dir } => commands::film::verify(&dir),
        Command::Trace {
            scenes,
            frames,
            scene,
        } => trace(&scenes, frames, scene.allow_commands, scene.limits.limits()),
        Command::Sound {
            events,
            output,
            library,
            settings,
            scene,
        } => {
            let input = SoundInput {
                events: &events,
                output: output.as_deref(),
                library: library.as_deref(),
                allow_commands: scene.allow_commands,
                limits: scene.limits.limits(),
            };
            commands::sound::sound(&input, &settings)
        }
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(e.exit_code())
        }
    }
}

#[cfg(test)]
mod tests {
    use clap::CommandFactory;

    /// clap's own checks of the whole command line (unique names and
    /// groups, valid defaults), which otherwise run only when a test
    /// happens to parse that subcommand. They need debug assertions, as
    /// `make test` builds; in a release build they do nothing.
    #[test]
    fn the_command_line_is_well_formed() {
        super::Cli::command().debug_assert();
    }
}
