//! The scenes a command derives: the files given, or the built-in film,
//! loaded as one [`Film`] with the user's consent to run scripts.

use std::path::{Path, PathBuf};

use crate::error::{Error, Result};
use crate::film::Film;
use crate::lsys::animation::read_source;
use crate::lsys::{Limits, Source};
use crate::production::stages::SceneText;
use crate::turtle::Options;

/// The built-in film (`lmfilm run` with no scene): the first 14 s of the
/// tennis match on its set, three files derived together (the camera
/// section, the match with the court and the referee, the landscape with
/// the moving camera).
const BUILT_IN: [(&str, &str); 3] = [
    (
        "showcase.lm",
        include_str!("../../scenes/tennis/showcase.lm"),
    ),
    ("match.lm", include_str!("../../scenes/tennis/match.lm")),
    (
        "landscape.lm",
        include_str!("../../scenes/tennis/landscape.lm"),
    ),
];

/// Samples per pixel of the built-in film when the user gives neither
/// `--preset` nor `--spp` (the `final` preset's shadows and reflections,
/// fewer samples than its 16): it renders in under 2 minutes on 2 cores.
pub const BUILT_IN_SPP: u32 = 3;

/// Loads the scene files as one film. A scene that wants to run scripts
/// (`command_file`) is refused unless the user consents
/// (`--allow-commands`), by every command alike; scripts are found in the
/// first scene's folder.
pub fn load_film(scenes: &[PathBuf], allow_commands: bool, opts: Options) -> Result<Film> {
    film_of(scenes, &read(scenes)?, allow_commands, opts)
}

/// Each scene file read once, bounded ([`read_source`]): what is parsed
/// is what the records hash.
fn read(scenes: &[PathBuf]) -> Result<Vec<Source>> {
    scenes
        .iter()
        .map(|p| read_source(p).map_err(|e| Error::input(e.to_string())))
        .collect()
}

/// The film of `sources`, read from the files `scenes`.
fn film_of(
    scenes: &[PathBuf],
    sources: &[Source],
    allow_commands: bool,
    opts: Options,
) -> Result<Film> {
    // Sounds and surfaces are found beside the first file.
    let dir = scenes.first().and_then(|p| p.parent());
    let mut film = Film::from_sources(sources, dir, opts)?;
    if let Some(what) = film.wants_commands() {
        if !allow_commands {
            return Err(Error::input(format!(
                "{what}: this scene wants to run scripts on this machine; a scene never runs anything by default. If you trust it, run again with --allow-commands"
            )));
        }
        // A bare file name's folder is the current one.
        let dir = dir.filter(|d| !d.as_os_str().is_empty());
        film.allow_commands(dir.unwrap_or(Path::new(".")));
    }
    Ok(film)
}

/// A film with what its records name it by.
pub struct Loaded {
    pub film: Film,
    /// The scene texts, as the records name them.
    pub texts: Vec<SceneText>,
    /// The film's name: its `rs_file_path_name`, else the first scene's
    /// file name (`lmfilm` for the built-in film).
    pub name: String,
}

/// The scenes given, or the built-in film when there are none.
pub fn load(scenes: &[PathBuf], allow_commands: bool, limits: Limits) -> Result<Loaded> {
    let opts = Options {
        limits,
        ..Options::default()
    };
    let (film, texts, name) = if scenes.is_empty() {
        let sources: Vec<Source> = BUILT_IN
            .iter()
            .map(|(n, t)| Source::new(format!("built-in:{n}"), *t))
            .collect();
        let film = Film::from_sources(&sources, None, opts)?;
        let texts = BUILT_IN
            .iter()
            .map(|(n, t)| SceneText {
                name: format!("built-in:{n}"),
                bytes: t.as_bytes().to_vec(),
            })
            .collect();
        (film, texts, "lmfilm".to_string())
    } else {
        let sources = read(scenes)?;
        let film = film_of(scenes, &sources, allow_commands, opts)?;
        let texts = sources
            .into_iter()
            .map(|s| SceneText {
                name: s.name,
                bytes: s.text.into_bytes(),
            })
            .collect();
        let name = scenes[0]
            .file_stem()
            .map_or("film".into(), |s| s.to_string_lossy().into_owned());
        if let Err(why) = crate::lsys::options::plain_name(&name) {
            return Err(Error::input(format!(
                "{}: the film's name `{name}` (the scene's file name) {why}; name it with rs_file_path_name",
                scenes[0].display()
            )));
        }
        (film, texts, name)
    };
    // `rs_file_path_name PATH NAME` names the frames.
    let name = film.rs_file().map_or(name, |(_, n)| n);
    Ok(Loaded { film, texts, name })
}

/// The output folder: `-o`, else the scene's `rs_file_path_name` folder,
/// else `renders/<name>/`.
pub fn output_dir(out: Option<&Path>, film: &Film, name: &str) -> PathBuf {
    out.map(Path::to_path_buf)
        .or_else(|| film.rs_file().map(|(p, _)| p))
        .unwrap_or_else(|| Path::new("renders").join(name))
}
