//! The `lmfilm` command line: parses arguments and calls the library.

use std::io::{IsTerminal, Write};
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::{Duration, Instant};

use clap::{Parser, Subcommand, ValueEnum};
use lmfilm::lsys::print::{self, Format};
use lmfilm::lsys::{Animation, NoSensors};

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
        /// Definition files derived together as one animation.
        #[arg(required = true, value_name = "SCENE.lm")]
        scenes: Vec<PathBuf>,
        /// Frame number N: the word after N steps of Δt (default 0).
        #[arg(long, conflicts_with = "time")]
        frame: Option<u64>,
        /// Time T in seconds: the frame nearest to T.
        #[arg(long, allow_negative_numbers = true)]
        time: Option<f64>,
        /// `symbols`: symbol characters only; `full`: X(age,x,y,z,f1,f2,f3).
        #[arg(long, value_enum, default_value_t = PrintFormat::Symbols)]
        format: PrintFormat,
    },
}

#[derive(Clone, Copy, ValueEnum)]
enum PrintFormat {
    Symbols,
    Full,
}

/// Shows `frame k/N` on a terminal while long derivations run.
struct Progress {
    enabled: bool,
    last: Instant,
}

impl Progress {
    fn new() -> Self {
        Progress {
            enabled: std::io::stderr().is_terminal(),
            last: Instant::now(),
        }
    }

    fn tick(&mut self, k: u64, n: u64) {
        if self.enabled && self.last.elapsed() > Duration::from_millis(250) {
            self.last = Instant::now();
            eprint!("\rderiving frame {k}/{n}");
        }
    }

    fn done(&self) {
        if self.enabled {
            eprint!("\r\x1b[K");
        }
    }
}

fn print_words(
    scenes: &[PathBuf],
    frame: Option<u64>,
    time: Option<f64>,
    format: PrintFormat,
) -> Result<(), (u8, String)> {
    let mut sensors = NoSensors;
    let mut anim = Animation::load(scenes, &mut sensors).map_err(|e| (2, e.to_string()))?;
    let target = match (frame, time) {
        (_, Some(t)) if !t.is_finite() || t < 0.0 => {
            return Err((2, format!("--time must be a time ≥ 0 in seconds, got {t}")))
        }
        (_, Some(t)) => anim.frame_at(t),
        (Some(n), None) => n,
        (None, None) => 0,
    };
    let mut progress = Progress::new();
    while anim.frame < target {
        anim.step(&mut sensors);
        progress.tick(anim.frame, target);
    }
    progress.done();
    let format = match format {
        PrintFormat::Symbols => Format::Symbols,
        PrintFormat::Full => Format::Full,
    };
    let (time, seed) = (anim.time(), anim.camera.seed);
    let mut out = std::io::stdout().lock();
    for ls in &mut anim.systems {
        let line = print::word(ls, format, time, seed, &mut sensors);
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

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Print {
            scenes,
            frame,
            time,
            format,
        } => print_words(&scenes, frame, time, format),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err((code, msg)) => {
            eprintln!("error: {msg}");
            ExitCode::from(code)
        }
    }
}
