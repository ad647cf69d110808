//! `lmfilm trace`: JSON Lines on stdout, one record per frame.

use std::path::PathBuf;

use super::{print_line, scenes};
use crate::error::Result;
use crate::film::trace::Record;
use crate::lsys::Limits;
use crate::production::frames::FrameRange;

/// `lmfilm trace`: the frames of `frames` (default all), each derived
/// through the frame loop like every other command's.
pub fn trace(
    scenes: &[PathBuf],
    frames: Option<FrameRange>,
    allow_commands: bool,
    limits: Limits,
) -> Result<()> {
    let mut film = scenes::load(scenes, allow_commands, limits)?.film;
    let count = film.frame_count();
    let range = frames.map_or(0..count, |r| r.within(count));
    let mut out = std::io::stdout().lock();
    if range.is_empty() {
        return Ok(());
    }
    // The warnings `derive` gives, each once, as they come.
    let mut warned = std::collections::BTreeSet::new();
    while let Some(frame) = film.next_frame()? {
        for w in frame.warnings() {
            if warned.insert(w.clone()) {
                eprintln!("{w}");
            }
        }
        let k = frame.number();
        if range.contains(&k) {
            let line = Record::of(&film).expect("a frame was handed out").to_line();
            if !print_line(&mut out, &line)? {
                return Ok(());
            }
        }
        if k + 1 >= range.end {
            break;
        }
    }
    Ok(())
}
