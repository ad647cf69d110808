//! `lmfilm sound`: a sound event log, a film folder or a scene into a
//! soundtrack WAV.

use std::path::{Path, PathBuf};

use super::args::SoundArgs;
use super::{film, scenes, Percent, Progress};
use crate::error::{Error, Result};
use crate::film::names::DERIVE_RECORD;
use crate::lsys::Limits;
use crate::production::stages;
use crate::sound;
use crate::turtle::Options;

/// Derives every frame of a scene through the frame loop and writes its
/// sound event log, `soundtrack.events` beside the soundtrack (default
/// folder `renders/<scene name>/`). Returns the log's and the WAV's paths.
fn scene_events(
    scene: &Path,
    output: Option<&Path>,
    allow_commands: bool,
    limits: Limits,
) -> Result<(PathBuf, PathBuf)> {
    let wav = output.map_or_else(
        || {
            let name = scene.file_stem().unwrap_or_default();
            Path::new("renders").join(name).join("soundtrack.wav")
        },
        Path::to_path_buf,
    );
    let events = wav.with_file_name("soundtrack.events");
    // A film folder's log and soundtrack belong to its records.
    if let Some(dir) = wav.parent().filter(|d| d.join(DERIVE_RECORD).exists()) {
        return Err(Error::input(format!(
            "{}: this folder holds a film, whose soundtrack comes from its own records: \
             `lmfilm sound {}` renders it; or write this scene's elsewhere with -o OUT.wav",
            dir.display(),
            dir.display()
        )));
    }
    let scenes = [scene.to_path_buf()];
    let opts = Options {
        limits,
        ..Options::default()
    };
    let mut film = scenes::load_film(&scenes, allow_commands, opts)?;
    let mut progress = Progress::new("deriving frame");
    stages::every_frame(&mut film, &mut |k, n| progress.tick(k, n), |_, _| Ok(()))?;
    progress.done();
    stages::write_events(&film, &events)?;
    Ok((events, wav))
}

/// What `lmfilm sound` reads beside its settings.
pub struct SoundInput<'a> {
    /// The events file, a film folder or a scene (`.lm`).
    pub events: &'a Path,
    pub output: Option<&'a Path>,
    /// A folder of sound files searched before the built-in library.
    pub library: Option<&'a Path>,
    pub allow_commands: bool,
    pub limits: Limits,
}

/// `lmfilm sound`.
pub fn sound(input: &SoundInput, args: &SoundArgs) -> Result<()> {
    let request = args.request();
    let (events, output) = (input.events, input.output);
    if events.is_dir() && output.is_none() && events.join(DERIVE_RECORD).exists() {
        return film::sound_dir(events, &request);
    }
    let settings = request.resolve(None);
    let (events, output) = if events.extension().is_some_and(|e| e == "lm") {
        scene_events(events, output, input.allow_commands, input.limits)?
    } else {
        sound::paths(events, output)
    };
    let percent = Percent::new("rendering sound");
    let report = sound::render_file(
        &events,
        &output,
        &settings,
        input.library,
        &|done, total| percent.tick(done as u64, total as u64),
    );
    percent.done();
    let report = report?;
    match report.loudness {
        Some(n) => {
            eprintln!("{}: {}", output.display(), n.summary());
            if let Some(w) = n.warning() {
                eprintln!("warning: {}: {w}", output.display());
            }
        }
        None => eprintln!("{}", output.display()),
    }
    if let Some(a) = &report.ambix {
        film::ambix_said(a);
    }
    if report.clipped > 0 {
        eprintln!(
            "warning: {}: {} samples beyond full scale were clipped; try --float or --attenuation inverse",
            output.display(),
            report.clipped
        );
    }
    Ok(())
}
