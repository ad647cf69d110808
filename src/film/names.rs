//! The names lmfilm writes in a film folder (DESIGN §5), in one place:
//! the folders and files of every stage, the numbered paths of the
//! frames and snapshots, and the registry that keeps a name a scene
//! chooses (`trace_actor`) off them.

use std::path::{Path, PathBuf};

/// Folder of the rendered images, inside the output folder.
pub const FRAMES_DIR: &str = "frames";

/// Folder of the scene snapshots, inside the output folder.
pub const SCENE_DIR: &str = "scene";

/// A frame number as it appears in file names: zero-padded to 4 digits,
/// more digits from frame 10000 on.
pub fn frame_number(frame: u64) -> String {
    format!("{frame:04}")
}

/// `frames/<name>.NNNN.<ext>`, relative to the output folder.
pub fn frame_path(name: &str, frame: u64, ext: &str) -> PathBuf {
    PathBuf::from(FRAMES_DIR).join(format!("{name}.{}.{ext}", frame_number(frame)))
}

/// `scene/NNNN.snap`, relative to the output folder.
pub fn snapshot_path(frame: u64) -> PathBuf {
    PathBuf::from(SCENE_DIR).join(format!("{}.snap", frame_number(frame)))
}

/// The derivation's record, at the folder's root.
pub const DERIVE_RECORD: &str = "derive.json";

/// The soundtrack's record, at the folder's root.
pub const SOUND_RECORD: &str = "soundtrack.json";

/// The folder of the scene's own sound files, inside the output folder.
pub const SOUNDS_DIR: &str = "sounds";

/// `frames/<name>.NNNN.json`, relative to the output folder.
pub fn frame_record_path(name: &str, frame: u64) -> PathBuf {
    frame_path(name, frame, "json")
}

/// `<name>.mp4` and `<name>.mp4.json`, relative to the output folder.
pub fn mp4_paths(name: &str) -> (PathBuf, PathBuf) {
    (
        PathBuf::from(format!("{name}.mp4")),
        PathBuf::from(format!("{name}.mp4.json")),
    )
}

/// The names a frame of any film may have in `frames/`: `(name, frame,
/// extension)` when `file` looks like `<name>.NNNN.<ext>`.
pub fn parse_frame_file(file: &str) -> Option<(&str, u64, &str)> {
    let (rest, ext) = file.rsplit_once('.')?;
    let (name, number) = rest.rsplit_once('.')?;
    if number.len() < 4 || !number.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    Some((name, number.parse().ok()?, ext))
}

/// The log and soundtrack names inside the folder.
pub const EVENTS_FILE: &str = "soundtrack.events";

pub const SOUNDTRACK_FILE: &str = "soundtrack.wav";

/// The ambisonic master (`INIT_ambix`), beside the soundtrack.
pub const AMBIX_FILE: &str = "soundtrack.ambix.wav";

/// `rel` as the records and the manifest key it: `/` separators.
pub fn key(rel: &Path) -> String {
    rel.iter()
        .map(|c| c.to_string_lossy())
        .collect::<Vec<_>>()
        .join("/")
}

/// The manifest's file name inside the output folder.
pub const MANIFEST_FILE: &str = "manifest.json";

/// Folder of the actors' images, inside the output folder.
pub const ACTORS_DIR: &str = "actors";

/// The folder's settings record.
pub const SETTINGS_FILE: &str = "settings.json";

/// The farm's scripts and logs (`lmfilm farm`), under the film folder.
pub const FARM_DIR: &str = "farm";

/// The first component of every path lmfilm writes in a film folder.
pub const OWN: [&str; 12] = [
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
    AMBIX_FILE,
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
    fn frame_files_parse_back() {
        assert_eq!(
            parse_frame_file("my.film.0012.png"),
            Some(("my.film", 12, "png"))
        );
        assert_eq!(parse_frame_file("a.12345.json"), Some(("a", 12345, "json")));
        assert_eq!(parse_frame_file("a.12.png"), None);
        assert_eq!(parse_frame_file("notes.txt"), None);
    }

    #[test]
    fn every_output_is_in_the_registry() {
        assert!(is_own("actors", "actors/0/vision.0000.png"));
        assert!(is_own("farm", "farm/logs/derive.out"));
        assert!(is_own("lmfilm.mp4", "lmfilm.mp4"));
        assert!(!is_own("walk.trace", "walk.trace"));
        assert!(!is_own("traces", "traces/actor0.trace"));
    }
}
