//! What each command of the command line does (DESIGN §5), with its
//! options as clap reads them; `src/main.rs` only parses and dispatches.
//! Every command returns the one [`crate::error::Error`].

pub mod args;
pub mod convert;
pub mod farm;
pub mod film;
pub mod frame;
pub mod lsp;
pub mod scenes;
pub mod sound;
pub mod trace;
pub mod watch;

use std::io::{IsTerminal, Write};
use std::time::Instant;

use crate::error::{Error, Result};

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

/// A render's frames as they are done: the progress line, and with
/// `--log-frames` one line a frame — its number, whether it was rendered
/// or up to date, its seconds and the node — for a farm task's log.
pub struct FrameLog {
    progress: Progress,
    /// The node the lines name (Slurm's name for it, else the host's).
    node: Option<String>,
}

impl FrameLog {
    pub fn new(log_frames: bool) -> FrameLog {
        let node = log_frames.then(|| {
            std::env::var("SLURMD_NODENAME")
                .ok()
                .filter(|n| !n.is_empty())
                .unwrap_or_else(|| crate::atomic::host_name().to_string())
        });
        FrameLog {
            progress: Progress::new("rendering frame"),
            node,
        }
    }

    pub fn frame(&mut self, d: crate::production::stages::FrameDone) {
        self.progress.tick(d.done, d.total);
        if let Some(node) = &self.node {
            let what = if d.made { "rendered" } else { "up to date" };
            eprintln!(
                "frame {} ({}/{}): {what} in {:.2} s on {node}",
                d.frame, d.done, d.total, d.seconds
            );
        }
    }

    pub fn done(&self) {
        self.progress.done();
    }
}

/// A percentage on one rewritten line of a terminal, every 5 % of the
/// work (rows of an image, tasks of a soundtrack); silent elsewhere.
pub struct Percent {
    label: &'static str,
    show: bool,
}

impl Percent {
    pub fn new(label: &'static str) -> Percent {
        Percent {
            label,
            show: std::io::stderr().is_terminal(),
        }
    }

    pub fn tick<T: Into<u64>>(&self, done: T, total: T) {
        let (done, total) = (done.into(), total.into());
        if self.show && total > 0 && done * 20 / total != (done - 1) * 20 / total {
            eprint!("\r{} {}%", self.label, done * 100 / total);
        }
    }

    pub fn done(&self) {
        if self.show {
            eprint!("\r\x1b[K");
        }
    }
}

/// Writes `line` to standard output; false when the reader has gone (a
/// closed pipe, `| head`), which is not an error of ours.
pub fn print_line(out: &mut impl Write, line: &str) -> Result<bool> {
    match writeln!(out, "{line}") {
        Ok(()) => Ok(true),
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => Ok(false),
        Err(e) => Err(Error::other(format!(
            "cannot write to standard output: {e}"
        ))),
    }
}

/// Creates the folder `path` will be written in.
pub fn create_parent(path: &std::path::Path) -> Result<()> {
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).map_err(|e| {
            Error::other(format!("{}: cannot create the folder: {e}", dir.display()))
        })?;
    }
    Ok(())
}
