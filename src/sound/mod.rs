//! Sound (thesis ch. 2.4, table B7, appendix D): the event log written
//! during an animation, the sound library, and the Doppler renderer that
//! turns a log into a soundtrack with one channel per microphone.

pub mod air;
pub mod events;
pub mod library;
pub mod limiter;
pub mod loudness;
pub mod render;
pub mod trajectory;
pub mod wav;

use std::path::{Path, PathBuf};

pub use events::{Event, EventLog, EventsFile, LogError, TimedEvents};
pub use library::{Library, Sounds};
pub use render::{render, Attenuation, SoundSettings, Soundtrack};
pub use wav::{SampleFormat, Signal};

use crate::atomic::write_atomic;
use crate::error::Error;
use crate::source::read_file;
use crate::source::Source;

/// The events file and soundtrack `lmfilm sound ARG [-o OUT]` means: a
/// folder stands for its `soundtrack.events`; the soundtrack goes beside
/// the events file with the extension `.wav` unless `output` is given.
pub fn paths(arg: &Path, output: Option<&Path>) -> (PathBuf, PathBuf) {
    let events = if arg.is_dir() {
        arg.join("soundtrack.events")
    } else {
        arg.to_path_buf()
    };
    let wav = output.map_or_else(|| events.with_extension("wav"), Path::to_path_buf);
    (events, wav)
}

/// What [`render_file`] wrote.
#[derive(Debug, Clone, PartialEq)]
pub struct SoundtrackReport {
    pub channels: usize,
    pub samples: usize,
    pub rate: u32,
    /// 16-bit samples beyond [-1, 1], clamped.
    pub clipped: u64,
    /// What loudness normalisation did (`None`: it was off).
    pub loudness: Option<loudness::Normalization>,
    /// The channels of the listener's left and right ears.
    pub ears: Option<(usize, usize)>,
    /// The ambisonic master written ([`ambix_path`]), its clipped samples
    /// and what its normalisation did.
    pub ambix: Option<AmbixReport>,
}

/// The ambisonic master [`render_file`] wrote.
#[derive(Debug, Clone, PartialEq)]
pub struct AmbixReport {
    pub path: PathBuf,
    pub clipped: u64,
    pub loudness: Option<loudness::Normalization>,
}

/// Where the ambisonic master of the soundtrack `wav` goes: beside it,
/// `NAME.ambix.wav` (the folder's `soundtrack.ambix.wav`).
pub fn ambix_path(wav: &Path) -> PathBuf {
    let stem = wav.file_stem().unwrap_or_default().to_string_lossy();
    wav.with_file_name(format!("{stem}.ambix.wav"))
}

/// Largest sound event log read: a bound on what a wrong path costs.
pub const MAX_EVENTS_BYTES: u64 = 1 << 30;

/// Renders the events file `events` into the WAV file `output` (written
/// atomically), looking sounds up as [`library::search_path`] says.
pub fn render_file(
    events: &Path,
    output: &Path,
    settings: &SoundSettings,
    library: Option<&Path>,
    progress: &(dyn Fn(usize, usize) + Sync),
) -> Result<SoundtrackReport, Error> {
    let bytes = read_file(events, MAX_EVENTS_BYTES)
        .map_err(|e| Error::input(format!("{}: cannot read: {e}", events.display())))?;
    let file = EventsFile::parse(Source::from_bytes(events.display().to_string(), bytes)?)?;
    let search = library::search_path(events.parent(), library);
    let sounds =
        Sounds::load(&file.log, &search).map_err(|e| file.play_error(e.play, e.message))?;
    let track = render::render_with(&file.log, &sounds, settings, progress)?;
    let (bytes, clipped) =
        wav::encode(&track.channels, track.rate, settings.format).map_err(Error::other)?;
    if let Some(dir) = output.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).map_err(|e| {
            Error::other(format!("{}: cannot create the folder: {e}", dir.display()))
        })?;
    }
    let ambix = match &track.ambix {
        Some(a) => {
            let (bytes, clipped) =
                wav::encode(&a.channels, track.rate, settings.format).map_err(Error::other)?;
            let path = ambix_path(output);
            write_atomic(&path, &bytes).map_err(|e| Error::other(e.to_string()))?;
            Some(AmbixReport {
                path,
                clipped,
                loudness: a.loudness,
            })
        }
        None => None,
    };
    write_atomic(output, &bytes).map_err(|e| Error::other(e.to_string()))?;
    Ok(SoundtrackReport {
        channels: track.channels.len(),
        samples: track.channels.first().map_or(0, Vec::len),
        rate: track.rate,
        clipped,
        loudness: track.loudness,
        ears: track.ears,
        ambix,
    })
}
