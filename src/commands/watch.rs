//! `lmfilm watch` (issue 40, thesis 8.1.2's live preview): the still of
//! one frame, rendered again each time a scene file or a file it names
//! is saved; a scene that does not load, derive or render prints its
//! located error and is watched on.

use std::path::Path;
use std::time::{Duration, Instant, SystemTime};

use super::args::StillArgs;
use super::frame::stills;
use crate::error::Result;
use crate::production::frames::FrameRange;
use crate::render::Preset;

/// How often the files are looked at.
const POLL: Duration = Duration::from_millis(150);
/// Files up to this size are hashed, so that a save within the clock's
/// resolution that keeps the size is seen too.
const HASHED: u64 = 4 << 20;

/// What a watched file looked like: its size, time and (small files)
/// content hash; None when it cannot be read.
type Stamp = Option<(u64, Option<SystemTime>, Option<String>)>;

fn stamp(path: &Path) -> Stamp {
    let meta = std::fs::metadata(path).ok()?;
    let hash = (meta.len() <= HASHED)
        .then(|| crate::source::read_file(path, HASHED).ok())
        .flatten()
        .map(|bytes| crate::production::digest::sha256_bytes(&bytes));
    Some((meta.len(), meta.modified().ok(), hash))
}

/// `lmfilm watch`: renders the still (or the range of `frames`) at
/// once, then again after each change, until interrupted — or after
/// `count` renders.
pub fn watch(args: &StillArgs, frames: Option<&FrameRange>, count: Option<u32>) -> Result<()> {
    // A preview unless a preset is asked for: quick to look at.
    let mut still_args = args.clone();
    still_args.quality.preset.get_or_insert(Preset::Preview);
    let at = &args.at;
    let mut seen: Option<Vec<Stamp>> = None;
    let mut files = at.scenes.clone();
    let mut renders = 0;
    eprintln!(
        "watching {} (Ctrl-C stops)",
        at.scenes
            .iter()
            .map(|p| p.display().to_string())
            .collect::<Vec<_>>()
            .join(", ")
    );
    loop {
        let now: Vec<Stamp> = files.iter().map(|f| stamp(f)).collect();
        if seen.as_ref() != Some(&now) {
            let start = Instant::now();
            // The files a change of which renders again: the scenes and
            // the files their film names (surfaces, motions, channels,
            // trajectories), as the last render that loaded read them.
            let read = match stills(&still_args, frames) {
                Ok(read) => {
                    eprintln!("rendered in {:.2} s", start.elapsed().as_secs_f64());
                    read
                }
                // Printed, not fatal: the next save may fix it.
                Err(e) => {
                    eprintln!("{e}");
                    files.clone()
                }
            };
            renders += 1;
            if count.is_some_and(|n| renders >= n) {
                return Ok(());
            }
            // The files as they were when this render began to read them
            // (a save during the render renders again); files new to the
            // list as they are now.
            seen = Some(if read == files {
                now
            } else {
                read.iter().map(|f| stamp(f)).collect()
            });
            files = read;
        }
        std::thread::sleep(POLL);
    }
}
