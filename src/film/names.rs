//! The one registry of the names lmfilm writes in a film folder, so that
//! a name a scene chooses (`trace_actor`) never lands on one of them.

use super::actor_images::ACTORS_DIR;
use super::frames::{FRAMES_DIR, SCENE_DIR};
use super::job::{EVENTS_FILE, SOUNDTRACK_FILE};
use super::manifest::MANIFEST_FILE;
use super::record::{DERIVE_RECORD, SOUNDS_DIR, SOUND_RECORD};
use super::settings::SETTINGS_FILE;

/// The farm's scripts and logs (`lmfilm farm`), under the film folder.
pub const FARM_DIR: &str = "farm";

/// The first component of every path lmfilm writes in a film folder.
pub const OWN: [&str; 11] = [
    FRAMES_DIR,
    SCENE_DIR,
    SOUNDS_DIR,
    ACTORS_DIR,
    FARM_DIR,
    DERIVE_RECORD,
    SETTINGS_FILE,
    SOUND_RECORD,
    EVENTS_FILE,
    SOUNDTRACK_FILE,
    MANIFEST_FILE,
];

/// Whether a path whose first component is `first` (the whole path
/// `name`) is lmfilm's own: one of [`OWN`], the film's MP4 and its
/// record, or a file being written (`.tmp`).
pub fn is_own(first: &str, name: &str) -> bool {
    OWN.contains(&first)
        || name.ends_with(".mp4")
        || name.ends_with(".mp4.json")
        || name.ends_with(".tmp")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_output_is_in_the_registry() {
        assert!(is_own("actors", "actors/0/vision.0000.png"));
        assert!(is_own("farm", "farm/logs/derive.out"));
        assert!(is_own("lmfilm.mp4", "lmfilm.mp4"));
        assert!(!is_own("walk.trace", "walk.trace"));
        assert!(!is_own("traces", "traces/actor0.trace"));
    }
}
