//! A film's one set of settings (DESIGN §5): the render and sound
//! settings resolved once — from the command line, the folder's recorded
//! settings, the scene's own declarations (its window, the built-in
//! film's samples) and the defaults — and recorded resolved in
//! `settings.json`, so that `render DIR`, `sound DIR` and a re-run with
//! no option give the film's own bytes again.
//!
//! A request names only what the user gave; [`RenderRequest::resolve`]
//! fills the rest. A resolved setting never holds a zero meaning
//! "default".

use crate::film::names::SETTINGS_FILE;
use std::collections::BTreeMap;
use std::path::Path;

use serde::{Deserialize, Serialize};

use super::record;
use crate::error::Error;
use crate::render::{Filter, ImageFormat, Integrator, Preset, Settings};
use crate::sound;

/// Image formats a render writes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Formats {
    Png,
    Exr,
    Both,
}

impl Formats {
    /// The image formats it writes.
    pub fn formats(self) -> &'static [ImageFormat] {
        match self {
            Formats::Png => &[ImageFormat::Png],
            Formats::Exr => &[ImageFormat::Exr],
            Formats::Both => &[ImageFormat::Exr, ImageFormat::Png],
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            Formats::Png => ImageFormat::Png.extension(),
            Formats::Exr => ImageFormat::Exr.extension(),
            Formats::Both => "both",
        }
    }
}

fn default_shutter() -> f32 {
    crate::render::settings::SHUTTER
}

/// Render settings, every one resolved.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct RenderChoice {
    /// The preset the sampling settings started from.
    pub preset: Preset,
    /// Image size in pixels, and whether the user gave it (else it is
    /// the scene camera's window, followed when the scene changes it).
    pub width: u32,
    pub height: u32,
    pub size_given: bool,
    pub spp: u32,
    pub filter: Filter,
    pub shadows: bool,
    /// Reflection and refraction bounces.
    pub max_depth: u32,
    /// Shadow rays toward each sphere light.
    pub light_samples: u32,
    /// Whitted shading or path tracing (a folder recorded before the
    /// choice existed was Whitted).
    #[serde(default)]
    pub integrator: Integrator,
    /// The fraction of each frame interval the shutter is open (the
    /// path tracer's motion blur).
    #[serde(default = "default_shutter")]
    pub shutter: f32,
    pub formats: Formats,
    /// The actor whose vision window goes into the frames' corner.
    pub inset: Option<usize>,
}

impl RenderChoice {
    /// The preset's settings at the camera's size `camera`.
    pub fn of_preset(preset: Preset, camera: (u32, u32)) -> RenderChoice {
        let s = Settings::of_preset(preset, camera.0, camera.1);
        RenderChoice {
            preset,
            width: s.width,
            height: s.height,
            size_given: false,
            spp: s.spp,
            filter: s.filter,
            shadows: s.shadows,
            max_depth: s.max_depth,
            light_samples: s.light_samples,
            integrator: s.integrator,
            shutter: s.shutter,
            formats: Formats::Both,
            inset: None,
        }
    }

    /// The renderer's settings (frame 0, layers when an EXR is written).
    pub fn settings(&self) -> Settings {
        Settings {
            width: self.width,
            height: self.height,
            spp: self.spp,
            filter: self.filter,
            shadows: self.shadows,
            max_depth: self.max_depth,
            light_samples: self.light_samples,
            integrator: self.integrator,
            shutter: self.shutter,
            layers: self.formats != Formats::Png,
            frame: 0,
        }
    }

    /// The settings as a frame's record keeps them, as text: every field
    /// of the type (a field added is recorded, so a resumed run never
    /// keeps frames made with another value), but `size_given`, which
    /// says how the size was chosen, not what the image is.
    pub fn record(&self) -> BTreeMap<String, String> {
        let serde_json::Value::Object(fields) =
            serde_json::to_value(self).expect("the settings serialize")
        else {
            unreachable!("a struct serializes to an object")
        };
        fields
            .into_iter()
            .filter(|(k, _)| k != "size_given")
            .map(|(k, v)| {
                let text = match v {
                    serde_json::Value::String(s) => s,
                    serde_json::Value::Null => "none".to_string(),
                    other => other.to_string(),
                };
                (k, text)
            })
            .collect()
    }

    /// The command-line options that ask for exactly these settings (a
    /// farm's render tasks run with them).
    pub fn args(&self) -> Vec<String> {
        let mut a = vec![
            format!("--preset={}", self.preset.name()),
            format!("--spp={}", self.spp),
            format!("--filter={}", self.filter.name()),
            format!("--shadows={}", if self.shadows { "on" } else { "off" }),
            format!("--max-depth={}", self.max_depth),
            format!("--light-samples={}", self.light_samples),
            format!("--integrator={}", self.integrator.name()),
            format!("--shutter={}", self.shutter),
            format!("--format={}", self.formats.name()),
            format!(
                "--inset={}",
                self.inset.map_or("none".into(), |a| a.to_string())
            ),
        ];
        if self.size_given {
            a.push(format!("--width={}", self.width));
            a.push(format!("--height={}", self.height));
        }
        a
    }
}

/// What the user asked for on the command line: `None` is "as before".
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct RenderRequest {
    pub preset: Option<Preset>,
    pub width: Option<u32>,
    pub height: Option<u32>,
    pub spp: Option<u32>,
    pub filter: Option<Filter>,
    pub shadows: Option<bool>,
    pub max_depth: Option<u32>,
    pub light_samples: Option<u32>,
    pub integrator: Option<Integrator>,
    pub shutter: Option<f32>,
    pub formats: Option<Formats>,
    /// `Some(None)`: no inset.
    pub inset: Option<Option<usize>>,
}

/// A film's defaults where the folder records none: the final preset,
/// with the built-in film's own samples per pixel when neither a preset
/// nor a sample count is given.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Defaults {
    pub spp: Option<u32>,
}

impl RenderRequest {
    /// The settings: the request over `base` (the folder's recorded
    /// settings), else over the defaults, at the scene camera's size
    /// `camera` unless a size was given. One side given keeps the
    /// camera's aspect ratio.
    pub fn resolve(
        &self,
        base: Option<&RenderChoice>,
        defaults: Defaults,
        camera: (u32, u32),
    ) -> RenderChoice {
        let mut c = match base {
            Some(b) => *b,
            None => {
                let mut c = RenderChoice::of_preset(Preset::Final, camera);
                if self.preset.is_none() {
                    c.spp = defaults.spp.unwrap_or(c.spp);
                }
                c
            }
        };
        if let Some(p) = self.preset {
            let fresh = RenderChoice::of_preset(p, camera);
            c.preset = p;
            c.spp = fresh.spp;
            c.shadows = fresh.shadows;
            c.max_depth = fresh.max_depth;
            c.light_samples = fresh.light_samples;
            c.integrator = fresh.integrator;
        }
        if !c.size_given {
            (c.width, c.height) = camera;
        }
        let aspect = |a: u32, from: u32, to: u32| -> u32 {
            ((u64::from(a) * u64::from(to) + u64::from(from) / 2) / u64::from(from.max(1)))
                .clamp(1, u64::from(u32::MAX)) as u32
        };
        match (self.width, self.height) {
            (Some(w), Some(h)) => (c.width, c.height, c.size_given) = (w, h, true),
            (Some(w), None) => {
                (c.width, c.height, c.size_given) = (w, aspect(w, camera.0, camera.1), true)
            }
            (None, Some(h)) => {
                (c.width, c.height, c.size_given) = (aspect(h, camera.1, camera.0), h, true)
            }
            (None, None) => {}
        }
        c.spp = self.spp.unwrap_or(c.spp);
        c.filter = self.filter.unwrap_or(c.filter);
        c.shadows = self.shadows.unwrap_or(c.shadows);
        c.max_depth = self.max_depth.unwrap_or(c.max_depth);
        c.light_samples = self.light_samples.unwrap_or(c.light_samples);
        c.integrator = self.integrator.unwrap_or(c.integrator);
        c.shutter = self.shutter.unwrap_or(c.shutter);
        c.formats = self.formats.unwrap_or(c.formats);
        c.inset = self.inset.unwrap_or(c.inset);
        c
    }
}

/// What the user asked of the soundtrack: `None` is "as before".
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct SoundRequest {
    pub rate: Option<u32>,
    pub speed_of_sound: Option<f64>,
    pub attenuation: Option<sound::Attenuation>,
    pub format: Option<sound::SampleFormat>,
    /// `Some(None)`: no normalisation.
    pub loudness: Option<Option<f64>>,
}

impl SoundRequest {
    /// The settings: the request over `base`, else over the defaults.
    pub fn resolve(&self, base: Option<&sound::SoundSettings>) -> sound::SoundSettings {
        let b = base.copied().unwrap_or_default();
        sound::SoundSettings {
            rate: self.rate.unwrap_or(b.rate),
            speed_of_sound: self.speed_of_sound.unwrap_or(b.speed_of_sound),
            attenuation: self.attenuation.unwrap_or(b.attenuation),
            format: self.format.unwrap_or(b.format),
            loudness: self.loudness.unwrap_or(b.loudness),
        }
    }
}

/// The command-line options that ask for exactly the sound settings `s`.
pub fn sound_args(s: &sound::SoundSettings) -> Vec<String> {
    vec![
        format!("--rate={}", s.rate),
        format!("--speed-of-sound={}", s.speed_of_sound),
        format!("--attenuation={}", s.attenuation.name()),
        format!("--samples={}", s.format.name()),
        format!(
            "--loudness={}",
            s.loudness.map_or("off".into(), |l| l.to_string())
        ),
    ]
}

/// `settings.json`: the film's settings, resolved.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FilmSettings {
    pub render: Option<RenderChoice>,
    pub sound: Option<sound::SoundSettings>,
}

/// The folder's recorded settings (none recorded: both `None`); a
/// record that cannot be read is an error naming it.
pub fn read(dir: &Path) -> Result<FilmSettings, Error> {
    let path = dir.join(SETTINGS_FILE);
    let found = record::read::<FilmSettings>(&path).map_err(|e| {
        Error::input(format!(
            "{e}; remove it (the film's defaults apply again) or run with --clean"
        ))
    })?;
    Ok(found.unwrap_or(FilmSettings {
        render: None,
        sound: None,
    }))
}

/// Records the folder's settings (atomically).
pub fn write(dir: &Path, s: &FilmSettings) -> Result<(), Error> {
    let path = dir.join(SETTINGS_FILE);
    std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
    record::write(&path, s).map_err(|e| Error::io(&path, e))
}

/// What differs between two recorded maps, as `key old → new`.
pub fn changes(old: &BTreeMap<String, String>, new: &BTreeMap<String, String>) -> Vec<String> {
    new.iter()
        .filter_map(|(k, v)| {
            let was = old.get(k).map_or("unset", String::as_str);
            (was != v).then(|| format!("{k} {was} → {v}"))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A request resolves over the recorded settings, keeps the camera's
    /// size until a size is given, and one given side keeps the aspect.
    #[test]
    fn requests_resolve_over_the_recorded_settings() {
        let none = RenderRequest::default();
        let built_in = Defaults { spp: Some(3) };
        let c = none.resolve(None, built_in, (320, 240));
        assert_eq!(
            (c.width, c.height, c.spp, c.size_given),
            (320, 240, 3, false)
        );
        assert!(c.shadows && c.max_depth == 5);
        // A preset given replaces the built-in film's samples.
        let preview = RenderRequest {
            preset: Some(Preset::Preview),
            ..none
        };
        let p = preview.resolve(None, built_in, (320, 240));
        assert_eq!((p.spp, p.shadows), (1, false));
        // Nothing asked: the recorded settings, at the camera's new size.
        let again = none.resolve(Some(&p), Defaults::default(), (640, 480));
        assert_eq!(
            again,
            RenderChoice {
                width: 640,
                height: 480,
                ..p
            }
        );
        let w = RenderRequest {
            width: Some(160),
            ..none
        }
        .resolve(Some(&p), Defaults::default(), (320, 240));
        assert_eq!((w.width, w.height, w.size_given), (160, 120, true));
        // A given size stays when the camera changes.
        let kept = none.resolve(Some(&w), Defaults::default(), (64, 64));
        assert_eq!((kept.width, kept.height), (160, 120));
        assert!(!c.record().values().any(|v| v == "0"), "{:?}", c.record());
    }

    /// A frame's record holds every setting, as text, as the records
    /// on disk have it.
    #[test]
    fn the_record_is_every_field() {
        let c = RenderChoice {
            inset: Some(2),
            ..RenderChoice::of_preset(Preset::Final, (64, 48))
        };
        let text: Vec<String> = c.record().iter().map(|(k, v)| format!("{k}={v}")).collect();
        assert_eq!(
            text.join(" "),
            "filter=box formats=both height=48 inset=2 integrator=whitted light_samples=4 max_depth=5 preset=final shadows=true shutter=0.5 spp=16 width=64"
        );
        let none = RenderChoice::of_preset(Preset::Preview, (8, 8)).record();
        assert_eq!(none["inset"], "none");
    }

    /// The options a farm passes ask for the same settings again.
    #[test]
    fn args_name_every_setting() {
        let c = RenderChoice {
            size_given: true,
            width: 96,
            height: 72,
            inset: Some(1),
            ..RenderChoice::of_preset(Preset::Preview, (64, 48))
        };
        let a = c.args().join(" ");
        for want in [
            "--preset=preview",
            "--spp=1",
            "--width=96",
            "--height=72",
            "--inset=1",
            "--shadows=off",
        ] {
            assert!(a.contains(want), "{a}");
        }
        let s = sound_args(&sound::SoundSettings::default()).join(" ");
        assert!(
            s.contains("--rate=48000") && s.contains("--samples=pcm16"),
            "{s}"
        );
    }
}
