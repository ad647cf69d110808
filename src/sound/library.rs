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

/// The folders a `PLAY` file name is looked up in, in order: the events
/// file's folder, `--library`, `scenes/sounds/` under the current folder,
/// and the `scenes/sounds/` this program was built with.
pub fn search_path(events_dir: Option<&Path>, library: Option<&Path>) -> Vec<PathBuf> {
    let mut dirs: Vec<PathBuf> = Vec::new();
    dirs.extend(events_dir.map(Path::to_path_buf));
    dirs.extend(library.map(Path::to_path_buf));
    dirs.push(PathBuf::from("scenes/sounds"));
    dirs.push(PathBuf::from(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/scenes/sounds"
    )));
    dirs
}

/// The first `dir/file` that exists (an absolute `file` is taken as is).
pub fn resolve(file: &str, search: &[PathBuf]) -> Option<PathBuf> {
    let file = Path::new(file);
    if file.is_absolute() {
        return file.is_file().then(|| file.to_path_buf());
    }
    search.iter().map(|d| d.join(file)).find(|p| p.is_file())
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
            let Some(path) = resolve(file, search) else {
                let dirs: Vec<String> = search.iter().map(|d| d.display().to_string()).collect();
                return Err(SoundError {
                    play,
                    message: format!(
                        "sound file {file:?} not found; looked in {}; pass --library DIR",
                        dirs.join(", ")
                    ),
                });
            };
            let signal = wav::read(&path).map_err(|message| SoundError { play, message })?;
            sounds.signals.insert(file.clone(), signal);
        }
        Ok(sounds)
    }
}
