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

/// Image formats a render writes (`--format`): `both` (the EXR master
/// and its PNG, the default), `png` (8-bit sRGB) or `exr` (RGBA, Z,
/// normal, object id).
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize, clap::ValueEnum,
)]
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

/// A number of `what` within `lo..=hi`, read from `text` (an option's
/// value, checked where clap reads it: out of range is a usage error).
pub fn within<T>(text: &str, what: &str, lo: T, hi: T) -> Result<T, String>
where
    T: std::str::FromStr + PartialOrd + std::fmt::Display + Copy,
{
    let n: T = text
        .trim()
        .parse()
        .map_err(|_| format!("{what} must be a number {lo}..{hi}, got {text:?}"))?;
    if n < lo || n > hi {
        return Err(format!("{what} must be {lo}..{hi}, got {n}"));
    }
    Ok(n)
}

/// `--width` and `--height`.
fn side(text: &str) -> Result<u32, String> {
    within(text, "a side in pixels", 1, 32768)
}

/// `--spp`: samples per pixel.
fn spp(text: &str) -> Result<u32, String> {
    within(text, "--spp", 1, 65536)
}

fn max_depth(text: &str) -> Result<u32, String> {
    within(text, "--max-depth", 0, 64)
}

fn light_samples(text: &str) -> Result<u32, String> {
    within(text, "--light-samples", 1, 1024)
}

fn shutter(text: &str) -> Result<f32, String> {
    match text.parse::<f32>() {
        Ok(v) if (0.0..=1.0).contains(&v) => Ok(v),
        _ => Err(format!(
            "--shutter takes a fraction 0..=1 of the frame interval, not `{text}`"
        )),
    }
}

/// `--shadows on|off`.
fn on_off() -> impl clap::builder::TypedValueParser<Value = bool> {
    use clap::builder::TypedValueParser;
    clap::builder::PossibleValuesParser::new(["on", "off"]).map(|s| s == "on")
}

/// A setting's value as its option writes it (`--shadows=on`).
trait OptionText {
    fn text(&self) -> String;
}

impl OptionText for u32 {
    fn text(&self) -> String {
        self.to_string()
    }
}

impl OptionText for f32 {
    fn text(&self) -> String {
        self.to_string()
    }
}

impl OptionText for bool {
    fn text(&self) -> String {
        (if *self { "on" } else { "off" }).to_string()
    }
}

impl OptionText for Filter {
    fn text(&self) -> String {
        self.name().to_string()
    }
}

impl OptionText for Integrator {
    fn text(&self) -> String {
        self.name().to_string()
    }
}

/// The sampling options of a render, each defined once: its field, of
/// the same name and type in the renderer's [`Settings`], in the film's
/// [`RenderChoice`] (and so in its record and `settings.json`) and in a
/// [`RenderRequest`] (the command line's `--name`, with its help and
/// value parser), and whether a `--preset` sets it. Everything that
/// copies, overlays or spells these settings is made from this list: a
/// new render option is a line here and its field in [`Settings`].
macro_rules! sampling_options {
    ($(
        $(#[doc = $doc:literal])*
        $name:ident: $ty:ty, preset $preset:literal, arg($($arg:tt)*) $(, #[$serde:meta])?;
    )*) => {
        /// Render settings, every one resolved.
        #[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
        pub struct RenderChoice {
            /// The preset the sampling settings started from.
            pub preset: Preset,
            /// Image size in pixels, and whether the user gave it (else it
            /// is the scene camera's window, followed when the scene
            /// changes it).
            pub width: u32,
            pub height: u32,
            pub size_given: bool,
            $( $(#[doc = $doc])* $(#[$serde])? pub $name: $ty, )*
            pub formats: Formats,
            /// The actor whose vision window goes into the frames' corner.
            pub inset: Option<usize>,
        }

        /// What the user asked for on the command line: `None` is "as
        /// before". Every option left out keeps the film's recorded
        /// setting (`run`, `render`, `farm slurm`), else the preset's
        /// (`still`).
        #[derive(Debug, Clone, Copy, Default, PartialEq, clap::Args)]
        #[command(next_help_heading = "Render settings")]
        pub struct RenderRequest {
            /// `final` (the default): 16 samples, shadows, 5 bounces, 4 rays
            /// per sphere light; `preview`: 1 sample, no shadows, mirrors
            /// and glass approximated by one look. `run` with no scene (the
            /// built-in film) renders at `final` with 3 samples per pixel
            /// unless --preset or --spp is given.
            #[arg(long, value_enum, value_name = "PRESET", hide_possible_values = true)]
            pub preset: Option<Preset>,
            /// Image width (default: the scene camera's window, `prefpos`;
            /// one side given keeps its aspect ratio).
            #[arg(long, value_parser = side)]
            pub width: Option<u32>,
            /// Image height (default: the scene camera's window).
            #[arg(long, value_parser = side)]
            pub height: Option<u32>,
            $( $(#[doc = $doc])* #[arg(long, $($arg)*)] pub $name: Option<$ty>, )*
            /// The image formats (`run`, `render`, `farm slurm`: `--format`).
            #[arg(skip)]
            pub formats: Option<Formats>,
            /// The inset (`--inset`); `Some(None)`: no inset.
            #[arg(skip)]
            pub inset: Option<Option<usize>>,
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
                    $( $name: s.$name, )*
                    formats: Formats::Both,
                    inset: None,
                }
            }

            /// The renderer's settings (frame 0, layers when an EXR is
            /// written).
            pub fn settings(&self) -> Settings {
                Settings {
                    width: self.width,
                    height: self.height,
                    $( $name: self.$name, )*
                    layers: self.formats != Formats::Png || self.denoise,
                    frame: 0,
                }
            }

            /// The command-line options that ask for exactly these
            /// settings (a farm's render tasks run with them).
            pub fn args(&self) -> Vec<String> {
                let mut a = vec![
                    format!("--preset={}", self.preset.name()),
                    $( format!("--{}={}", stringify!($name).replace('_', "-"), self.$name.text()), )*
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

        impl RenderRequest {
            /// The settings a preset sets, from `fresh`, the preset's.
            fn preset_over(c: &mut RenderChoice, fresh: &RenderChoice) {
                $( if $preset { c.$name = fresh.$name; } )*
            }

            /// The sampling settings the request names, over `c`.
            fn overlay(&self, c: &mut RenderChoice) {
                $( if let Some(v) = self.$name { c.$name = v; } )*
            }
        }
    };
}

sampling_options! {
    /// Samples per pixel (overrides the preset's).
    spp: u32, preset true, arg(value_parser = spp);
    /// Pixel filter (default box).
    filter: Filter, preset false, arg(value_enum);
    /// Shadow rays (overrides the preset's).
    shadows: bool, preset true, arg(value_name = "on|off", value_parser = on_off(), hide_possible_values = true);
    /// Reflection and refraction bounces (overrides the preset's).
    max_depth: u32, preset true, arg(value_name = "N", value_parser = max_depth);
    /// Shadow rays toward each sphere light (overrides the preset's).
    light_samples: u32, preset true, arg(value_name = "N", value_parser = light_samples);
    /// `whitted` (the default): Rayshade's shading, lights, ambient,
    /// mirrors and glass; `path`: path tracing, the sky lighting the
    /// scene, soft shadows, light bouncing (--max-depth bounces), depth
    /// of field from the camera's lens (docs/rendering.md).
    // A folder recorded before the choice existed was Whitted.
    integrator: Integrator, preset true, arg(value_enum), #[serde(default)];
    /// The fraction of each frame interval the shutter stays open, 0..=1
    /// (default 0.5, a film camera's 180°): the path tracer blurs what
    /// moves between a frame and the next over it; 0 freezes.
    shutter: f32, preset false, arg(value_name = "F", value_parser = shutter), #[serde(default = "default_shutter")];
    /// Denoise each frame (on|off, default off), guided by its albedo,
    /// normals and depth: the path tracer's look at few samples. The EXR
    /// keeps the colour as rendered beside it (docs/rendering.md).
    // Recorded only when on: a frame of before the choice was not.
    denoise: bool, preset true, arg(value_name = "on|off", value_parser = on_off(), hide_possible_values = true), #[serde(default, skip_serializing_if = "std::ops::Not::not")];
}

impl RenderChoice {
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
            c.preset = p;
            RenderRequest::preset_over(&mut c, &RenderChoice::of_preset(p, camera));
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
        self.overlay(&mut c);
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

/// The video's settings (`<name>.mp4`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct VideoSettings {
    /// The H.264 quantiser: 0 near lossless … 51 smallest.
    pub qp: u8,
}

impl Default for VideoSettings {
    fn default() -> VideoSettings {
        VideoSettings {
            qp: crate::production::video::DEFAULT_QP,
        }
    }
}

fn video_qp(text: &str) -> Result<u8, String> {
    within(text, "--video-qp", 0, 51)
}

/// What the user asked of the video: `None` is "as before".
#[derive(Debug, Clone, Copy, Default, PartialEq, clap::Args)]
#[command(next_help_heading = "Video settings")]
pub struct VideoRequest {
    /// The video's H.264 quantiser, 0 (near lossless, largest) to 51
    /// (smallest); default 20: the built-in film's decoded video is
    /// 43.8 dB PSNR (luma) from its frames at 3.3 Mbit/s (docs/film.md).
    #[arg(long = "video-qp", value_name = "QP", value_parser = video_qp)]
    pub qp: Option<u8>,
}

impl VideoRequest {
    /// The settings: the request over `base`, else over the defaults.
    pub fn resolve(&self, base: Option<&VideoSettings>) -> VideoSettings {
        let b = base.copied().unwrap_or_default();
        VideoSettings {
            qp: self.qp.unwrap_or(b.qp),
        }
    }
}

/// `settings.json`: the film's settings, resolved.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FilmSettings {
    pub render: Option<RenderChoice>,
    pub sound: Option<sound::SoundSettings>,
    /// A folder recorded before lmfilm made its own video has none.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub video: Option<VideoSettings>,
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
        video: None,
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
