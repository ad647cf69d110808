//! The files of a film folder as the stages read them (issue 53,
//! docs/hostile-input.md "A film folder's files"): each file's bound in
//! bytes, read only as a regular file (`source::open_file`: a folder, a
//! device such as `/dev/zero` or a named pipe is refused, never waited
//! on), and the way out, named in the error, when one cannot be read.

use std::io;
use std::path::Path;

use crate::error::Error;
use crate::film::names::{
    self, ACTORS_DIR, AMBIX_FILE, DERIVE_RECORD, EVENTS_FILE, FRAMES_DIR, MANIFEST_FILE, SCENE_DIR,
    SETTINGS_FILE, SOUNDS_DIR, SOUNDTRACK_FILE, SOUND_RECORD,
};
use crate::lsys::Limits;
use crate::render::output;
use crate::scene::snapshot::MAX_SNAPSHOT_BYTES;
use crate::sound::wav::{MAX_SOUNDTRACK_BYTES, MAX_WAV_BYTES};
use crate::sound::MAX_EVENTS_BYTES;
use crate::source::{refused, Refused};

/// Largest record read (`derive.json`, `settings.json`, a frame's, the
/// soundtrack's, the MP4's): a derive record of a long film is the
/// biggest, ~70 bytes a frame.
pub const MAX_RECORD: u64 = 256 << 20;

/// Largest `manifest.json` read: ~110 bytes a listed file, four files a
/// frame (snapshot, EXR, PNG, record), so a film of the default
/// `--max-frames` (10⁶) lists ~450 MB.
pub const MAX_MANIFEST: u64 = 1 << 30;

/// Largest trajectory a scene writes (`trace_actor`) that is read back
/// to hash it: a line a frame, as the event log.
pub const MAX_TRACK_BYTES: u64 = MAX_EVENTS_BYTES;

/// The bounds of one film folder's files.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Bounds {
    /// Bytes of one image (a frame's EXR or PNG, an actor's image).
    image: u64,
    /// Frames of the film (an MP4 holds them all).
    frames: u64,
}

impl Bounds {
    /// The bounds of a film of `frames` frames whose images have at most
    /// `pixels` pixels, and never fewer than the default `--max-pixels`:
    /// a bound only refuses what the film cannot have made.
    pub fn new(pixels: u64, frames: u64) -> Bounds {
        let pixels = pixels.max(Limits::default().pixels);
        Bounds {
            image: output::max_file_bytes(pixels),
            frames,
        }
    }

    /// The bounds of a film whose frames were rendered with the settings
    /// `render` (as a frame's record or the manifest keeps them: `width`,
    /// `height`), of `frames` frames.
    pub fn of_settings<'a>(
        render: impl Iterator<Item = (&'a str, &'a str)>,
        frames: u64,
    ) -> Bounds {
        let (mut width, mut height) = (0u64, 0u64);
        for (k, v) in render {
            match k {
                "width" => width = v.parse().unwrap_or(0),
                "height" => height = v.parse().unwrap_or(0),
                _ => {}
            }
        }
        Bounds::new(width.saturating_mul(height), frames)
    }

    /// The most bytes read of the folder's file `rel` (`/` separators,
    /// as the records key it).
    pub fn limit(&self, rel: &str) -> u64 {
        let under = |dir: &str| under(rel, dir);
        if rel == MANIFEST_FILE {
            MAX_MANIFEST
        } else if rel == EVENTS_FILE {
            MAX_EVENTS_BYTES
        } else if rel == SOUNDTRACK_FILE || rel == AMBIX_FILE {
            MAX_SOUNDTRACK_BYTES
        } else if under(SCENE_DIR) {
            MAX_SNAPSHOT_BYTES
        } else if under(SOUNDS_DIR) {
            MAX_WAV_BYTES
        } else if rel.ends_with(".json") {
            MAX_RECORD
        } else if under(FRAMES_DIR) || under(ACTORS_DIR) {
            self.image
        } else if rel.ends_with(".mp4") {
            // Never more than its frames as images and its soundtrack.
            self.frames
                .saturating_mul(self.image)
                .saturating_add(MAX_SOUNDTRACK_BYTES)
        } else {
            MAX_TRACK_BYTES
        }
    }
}

/// Whether the folder's file `rel` lies under its folder `dir`.
fn under(rel: &str, dir: &str) -> bool {
    rel.strip_prefix(dir)
        .is_some_and(|rest| rest.starts_with('/'))
}

/// What the user does about the folder's file `rel` that cannot be read
/// (a folder, a device, a pipe, too large): remove it and run the command
/// that makes it again.
pub fn way_out(dir: &Path, rel: &str) -> String {
    let d = dir.display();
    let again = |command: &str| format!("remove it and run `{command}` again");
    let under = |sub: &str| under(rel, sub);
    if rel == SETTINGS_FILE {
        "remove it (the film's defaults apply again) or run with --clean".into()
    } else if rel == MANIFEST_FILE {
        format!("remove it; `lmfilm sound {d}` writes it again from the records")
    } else if rel == SOUNDTRACK_FILE || rel == AMBIX_FILE || rel == SOUND_RECORD {
        again(&format!("lmfilm sound {d}"))
    } else if rel.ends_with(".mp4") || rel.ends_with(".mp4.json") {
        again(&format!("lmfilm mux {d}"))
    } else if under(FRAMES_DIR) {
        again(&format!("lmfilm render {d}"))
    } else {
        // derive.json, snapshots, the event log, the sounds, the actors'
        // images, the trajectories: the derivation's.
        again(&format!("lmfilm derive SCENE.lm -o {d}"))
    }
}

/// The input error (exit 2) for the folder's file `rel` that could not be
/// read: the file, what it is (`e`) and the way out.
pub fn unreadable(dir: &Path, rel: &str, e: &io::Error) -> Error {
    Error::input(format!(
        "{}: {e}; {}",
        dir.join(rel).display(),
        way_out(dir, rel)
    ))
}

/// Refuses the folder's file `rel` when something else than a regular
/// file stands there (a folder, a device, a pipe, a socket): a stage
/// never reads it, nor replaces what it did not write. Only its metadata
/// is read, so a pipe is never opened. A missing file is no error.
pub fn check_kind(dir: &Path, rel: &str) -> Result<(), Error> {
    let Ok(meta) = std::fs::metadata(dir.join(rel)) else {
        return Ok(());
    };
    match Refused::of_kind(meta.file_type()) {
        Some(what) => Err(unreadable(dir, rel, &what.into())),
        None => Ok(()),
    }
}

/// Whether `e` says the file is something else than a regular file (a
/// folder, a device, a pipe), not merely missing, damaged or too large.
pub fn not_a_file(e: &io::Error) -> bool {
    refused(e).is_some_and(|r| r.not_a_file())
}

/// The folder's records, at its root and beside the frames, that
/// `finish` reads to assemble the manifest, and the manifest it writes.
pub fn finishing(name: &str, frames: u64) -> Vec<String> {
    let mut rels: Vec<String> = [DERIVE_RECORD, SETTINGS_FILE, SOUND_RECORD, MANIFEST_FILE]
        .map(String::from)
        .into();
    rels.push(names::key(&names::mp4_paths(name).1));
    rels.extend((0..frames).map(|k| names::key(&names::frame_record_path(name, k))));
    rels
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_file_has_its_bound_and_way_out() {
        let b = Bounds::new(0, 10);
        let image = output::max_file_bytes(Limits::default().pixels);
        assert_eq!(b.limit("derive.json"), MAX_RECORD);
        assert_eq!(b.limit("frames/f.0001.json"), MAX_RECORD);
        assert_eq!(b.limit("f.mp4.json"), MAX_RECORD);
        assert_eq!(b.limit("manifest.json"), MAX_MANIFEST);
        assert_eq!(b.limit("scene/0001.snap"), MAX_SNAPSHOT_BYTES);
        assert_eq!(b.limit("sounds/frog.wav"), MAX_WAV_BYTES);
        assert_eq!(b.limit("soundtrack.events"), MAX_EVENTS_BYTES);
        assert_eq!(b.limit("soundtrack.wav"), MAX_SOUNDTRACK_BYTES);
        assert_eq!(b.limit("frames/f.0001.exr"), image);
        assert_eq!(b.limit("actors/0/vision.0001.png"), image);
        assert_eq!(b.limit("f.mp4"), 10 * image + MAX_SOUNDTRACK_BYTES);
        assert_eq!(b.limit("traces/walk.trace"), MAX_TRACK_BYTES);
        let big = Bounds::of_settings([("height", "20000"), ("width", "20000")].into_iter(), 1);
        assert_eq!(
            big.limit("frames/f.0000.png"),
            output::max_file_bytes(400_000_000)
        );
        let d = Path::new("out");
        assert!(way_out(d, "frames/f.0001.png").contains("lmfilm render out"));
        assert!(way_out(d, "scene/0001.snap").contains("lmfilm derive SCENE.lm -o out"));
        assert!(way_out(d, "soundtrack.wav").contains("lmfilm sound out"));
        assert!(way_out(d, "f.mp4").contains("lmfilm mux out"));
    }
}
