//! The sound library: sound numbers to file names (thesis appendix D), the
//! folders a `PLAY` file name is looked up in, and the decoded sounds a
//! log needs.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use super::events::{Event, EventLog};
use super::wav::{self, Signal};

/// Table D.1 with `.wav` for `.aiff`; 29–58 are the words of table D.2.
const DEFAULT: &[(u32, &str)] = &[
    (0, "ball_racket.wav"),
    (1, "ball_ground.wav"),
    (2, "cricket.wav"),
    (4, "frog.wav"),
    (5, "foret.wav"),
    (6, "start.wav"),
    (7, "vivaldi.wav"),
    (8, "avion.wav"),
    (9, "ball_net.wav"),
    (10, "advantage.wav"),
    (11, "all.wav"),
    (12, "deuce.wav"),
    (13, "fault.wav"),
    (14, "fifteen.wav"),
    (15, "fourty.wav"),
    (16, "game.wav"),
    (17, "let.wav"),
    (18, "love.wav"),
    (19, "server.wav"),
    (20, "striker.wav"),
    (21, "thirty.wav"),
    (22, "blue.wav"),
    (23, "green.wav"),
    (24, "out.wav"),
    (25, "service.wav"),
    (26, "left.wav"),
    (27, "right.wav"),
    (28, "wait02.wav"),
    (29, "move_right.wav"),
    (30, "move_left.wav"),
    (31, "move_up.wav"),
    (32, "move_down.wav"),
    (33, "move.wav"),
    (34, "go_back.wav"),
    (35, "turn_up.wav"),
    (36, "turn_down.wav"),
    (37, "turn_left.wav"),
    (38, "turn_right.wav"),
    (39, "faster.wav"),
    (40, "slow_down.wav"),
    (41, "turn_faster.wav"),
    (42, "turn_less.wav"),
    (43, "block.wav"),
    (44, "free_it.wav"),
    (45, "stop.wav"),
    (46, "blue.wav"),
    (47, "green.wav"),
    (48, "one.wav"),
    (49, "two.wav"),
    (50, "three.wav"),
    (51, "four.wav"),
    (52, "five.wav"),
    (53, "six.wav"),
    (54, "seven.wav"),
    (55, "eight.wav"),
    (56, "nine.wav"),
    (57, "ten.wav"),
    (58, "exit.wav"),
];

/// Sound numbers (the `T` symbol's, the audition functions') to file names.
#[derive(Debug, Clone, PartialEq)]
pub struct Library {
    files: BTreeMap<u32, String>,
}

impl Default for Library {
    /// Table D.1 / D.2 of the thesis.
    fn default() -> Self {
        Library {
            files: DEFAULT.iter().map(|&(n, f)| (n, f.to_string())).collect(),
        }
    }
}

impl Library {
    /// A library with no sound.
    pub fn empty() -> Self {
        Library {
            files: BTreeMap::new(),
        }
    }

    /// Makes sound `n` play `file` (a scene declaring its own sounds).
    pub fn set(&mut self, n: u32, file: impl Into<String>) {
        self.files.insert(n, file.into());
    }

    pub fn file_name(&self, n: u32) -> Option<&str> {
        self.files.get(&n).map(String::as_str)
    }

    /// Every (number, file name), ascending.
    pub fn iter(&self) -> impl Iterator<Item = (u32, &str)> {
        self.files.iter().map(|(&n, f)| (n, f.as_str()))
    }
}

/// Embeds `scenes/sounds/<name>` for each name, as (name, bytes).
macro_rules! embed {
    ($($name:literal),* $(,)?) => {
        &[$(($name, include_bytes!(concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/sounds/", $name)))),*]
    };
}

/// The sounds of tables D.1 and D.2, built into the program so that a copy
/// of it on a machine without the source tree (a render farm node) plays
/// them too. `scenes/sounds/` is where they come from.
const EMBEDDED: &[(&str, &[u8])] = embed![
    "advantage.wav",
    "all.wav",
    "avion.wav",
    "ball_ground.wav",
    "ball_net.wav",
    "ball_racket.wav",
    "block.wav",
    "blue.wav",
    "cricket.wav",
    "deuce.wav",
    "eight.wav",
    "exit.wav",
    "faster.wav",
    "fault.wav",
    "fifteen.wav",
    "five.wav",
    "foret.wav",
    "four.wav",
    "fourty.wav",
    "free_it.wav",
    "frog.wav",
    "game.wav",
    "go_back.wav",
    "green.wav",
    "left.wav",
    "let.wav",
    "love.wav",
    "move.wav",
    "move_down.wav",
    "move_left.wav",
    "move_right.wav",
    "move_up.wav",
    "nine.wav",
    "one.wav",
    "out.wav",
    "right.wav",
    "server.wav",
    "service.wav",
    "seven.wav",
    "six.wav",
    "slow_down.wav",
    "start.wav",
    "stop.wav",
    "striker.wav",
    "ten.wav",
    "thirty.wav",
    "three.wav",
    "turn_down.wav",
    "turn_faster.wav",
    "turn_left.wav",
    "turn_less.wav",
    "turn_right.wav",
    "turn_up.wav",
    "two.wav",
    "vivaldi.wav",
    "wait02.wav",
];

/// The folders a `PLAY` file name is looked up in, in order: the events
/// file's (or scene's) folder, then `--library`. After them comes the
/// library built into the program ([`resolve`]); nothing depends on the
/// current folder or on where the program was built.
pub fn search_path(events_dir: Option<&Path>, library: Option<&Path>) -> Vec<PathBuf> {
    events_dir
        .into_iter()
        .chain(library)
        .map(Path::to_path_buf)
        .collect()
}

/// Where a sound file was found.
#[derive(Debug, Clone, PartialEq)]
pub enum SoundOrigin {
    File(PathBuf),
    /// The built-in sound of this name.
    Embedded(&'static str, &'static [u8]),
}

impl SoundOrigin {
    /// The file decoded as a mono signal.
    pub fn read(&self) -> Result<Signal, String> {
        match self {
            SoundOrigin::File(path) => wav::read(path),
            SoundOrigin::Embedded(name, bytes) => {
                wav::decode(bytes).map_err(|e| format!("built-in {name}: {e}"))
            }
        }
    }

    /// The file's length in seconds, from its header.
    pub fn duration(&self) -> Result<f64, String> {
        match self {
            SoundOrigin::File(path) => crate::source::open_file(path, wav::MAX_WAV_BYTES)
                .map_err(|e| format!("{}: cannot read: {e}", path.display()))
                .and_then(|f| wav::duration(std::io::BufReader::new(f))),
            SoundOrigin::Embedded(_, bytes) => wav::duration(*bytes),
        }
    }
}

/// The first `dir/file` of `search` that exists, else the built-in sound
/// named `file` (an absolute `file` is taken as is). What exists is found
/// even when it is not a regular file (a folder, a device, a pipe):
/// reading it then says so, rather than play another sound of that name.
pub fn resolve(file: &str, search: &[PathBuf]) -> Option<SoundOrigin> {
    let path = Path::new(file);
    if path.is_absolute() {
        return path.exists().then(|| SoundOrigin::File(path.to_path_buf()));
    }
    search
        .iter()
        .map(|d| d.join(path))
        .find(|p| p.exists())
        .map(SoundOrigin::File)
        .or_else(|| {
            EMBEDDED
                .iter()
                .find(|(name, _)| *name == file)
                .map(|&(name, bytes)| SoundOrigin::Embedded(name, bytes))
        })
}

/// The decoded sounds of a log, by the file name its `PLAY` lines give.
#[derive(Debug, Clone, Default)]
pub struct Sounds {
    signals: BTreeMap<String, Signal>,
}

/// A sound that cannot be loaded; `play` is its `PLAY`'s index in the log.
#[derive(Debug, Clone, PartialEq)]
pub struct SoundError {
    pub play: usize,
    pub message: String,
}

impl Sounds {
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds a signal under the name `PLAY` lines use.
    pub fn insert(&mut self, file: impl Into<String>, signal: Signal) {
        self.signals.insert(file.into(), signal);
    }

    pub fn get(&self, file: &str) -> Option<&Signal> {
        self.signals.get(file)
    }

    /// Reads every file the log plays, each once, looked up in `search`.
    pub fn load(log: &EventLog, search: &[PathBuf]) -> Result<Self, SoundError> {
        let mut sounds = Sounds::new();
        let plays = log.events().filter_map(|(_, e)| match e {
            Event::Play { file, .. } => Some(file),
            _ => None,
        });
        for (play, file) in plays.enumerate() {
            if sounds.signals.contains_key(file) {
                continue;
            }
            let Some(found) = resolve(file, search) else {
                let dirs: Vec<String> = search
                    .iter()
                    .map(|d| d.display().to_string())
                    .chain(["the built-in library".to_string()])
                    .collect();
                return Err(SoundError {
                    play,
                    message: format!(
                        "sound file {file:?} not found; looked in {}; pass --library DIR",
                        dirs.join(", ")
                    ),
                });
            };
            let signal = found
                .read()
                .map_err(|message| SoundError { play, message })?;
            sounds.signals.insert(file.clone(), signal);
        }
        Ok(sounds)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_library_sound_is_built_in_and_decodes() {
        for (n, file) in Library::default().iter() {
            let found = resolve(file, &[]);
            assert!(
                matches!(found, Some(SoundOrigin::Embedded(..))),
                "sound {n}: {file}"
            );
        }
        for (name, bytes) in EMBEDDED {
            let signal = wav::decode(bytes).unwrap_or_else(|e| panic!("{name}: {e}"));
            assert!(!signal.samples.is_empty(), "{name}");
        }
        // And nothing in scenes/sounds/ is left out.
        let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/sounds");
        let mut files: Vec<String> = std::fs::read_dir(dir)
            .unwrap()
            .filter_map(|e| e.ok()?.file_name().into_string().ok())
            .filter(|f| f.ends_with(".wav"))
            .collect();
        files.sort();
        let embedded: Vec<&str> = EMBEDDED.iter().map(|(n, _)| *n).collect();
        assert_eq!(files, embedded);
    }

    #[test]
    fn a_folder_comes_before_the_built_in_library() {
        let dir = std::env::temp_dir().join(format!("lmfilm-library-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::write(dir.join("frog.wav"), b"not a wav").unwrap();
        let found = resolve("frog.wav", std::slice::from_ref(&dir));
        assert_eq!(found, Some(SoundOrigin::File(dir.join("frog.wav"))));
        assert!(found.unwrap().read().is_err());
        assert!(resolve("no_such_sound.wav", std::slice::from_ref(&dir)).is_none());
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
