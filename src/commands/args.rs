//! The options the commands share, each checked where clap reads it (a
//! value out of range is a usage error, exit 2, naming the option).

use std::path::PathBuf;

use clap::{Args, ValueEnum};

use crate::film::frames::FrameRange;
use crate::film::job::Formats;
use crate::lsys::Limits;
use crate::render::{Filter, Settings};
use crate::sound::{self, Attenuation, SampleFormat};

/// A number of `what` within `lo..=hi`, read from `text`.
fn within<T>(text: &str, what: &str, lo: T, hi: T) -> Result<T, String>
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

/// A finite number > 0 for `what`.
fn positive(text: &str, what: &str) -> Result<f64, String> {
    match text.trim().parse::<f64>() {
        Ok(v) if v.is_finite() && v > 0.0 => Ok(v),
        _ => Err(format!("{what} must be > 0, got {text}")),
    }
}

/// `--width` and `--height`.
pub fn side(text: &str) -> Result<u32, String> {
    within(text, "a side in pixels", 1, 32768)
}

/// `--spp`: samples per pixel.
pub fn spp(text: &str) -> Result<u32, String> {
    within(text, "--spp", 1, 65536)
}

fn threads(text: &str) -> Result<usize, String> {
    within(text, "--threads", 1, Limits::MAX_THREADS)
}

fn rate(text: &str) -> Result<u32, String> {
    within(text, "--rate", 1u32, 768_000)
}

fn speed_of_sound(text: &str) -> Result<f64, String> {
    positive(text, "--speed-of-sound (m/s)")
}

pub fn segment_width(text: &str) -> Result<f64, String> {
    positive(text, "--segment-width")
}

fn loudness(text: &str) -> Result<f64, String> {
    let v: f64 = text
        .trim()
        .parse()
        .map_err(|_| format!("--loudness must be a number of LUFS, got {text:?}"))?;
    sound::loudness::check_target(v).map_err(|e| format!("--loudness: {e}"))?;
    Ok(v)
}

/// `--time`: a time ≥ 0 in seconds.
fn time(text: &str) -> Result<f64, String> {
    match text.trim().parse::<f64>() {
        Ok(t) if t.is_finite() && t >= 0.0 => Ok(t),
        _ => Err(format!("--time must be a time ≥ 0 in seconds, got {text}")),
    }
}

/// The limits of docs/limits.md: a run that would pass one stops with a
/// message (exit 2) naming the flag that raises it.
#[derive(Args, Clone, Copy)]
pub struct LimitArgs {
    /// Most symbols in one L-system's word (56 bytes each, two words).
    #[arg(long, value_name = "N", default_value_t = Limits::default().symbols)]
    pub max_symbols: usize,
    /// Most primitives (shapes, triangles, copies) in one frame's scene.
    #[arg(long, value_name = "N", default_value_t = Limits::default().shapes)]
    pub max_shapes: usize,
    /// Most frames in one film (t_final / Δt + 1).
    #[arg(long, value_name = "N", default_value_t = Limits::default().frames)]
    pub max_frames: u64,
    /// Most pixels in one image (width × height).
    #[arg(long, value_name = "N", default_value_t = Limits::default().pixels)]
    pub max_pixels: u64,
    /// Most voxels one actor's path search adds to its path before it
    /// gives up (time and memory of a plan, length of its path).
    #[arg(long, value_name = "N", default_value_t = Limits::default().plan_voxels)]
    pub max_plan_voxels: usize,
    /// Most bytes the actors' visual memories hold together.
    #[arg(long, value_name = "BYTES", default_value_t = Limits::default().memory_bytes)]
    pub max_memory: u64,
}

impl LimitArgs {
    pub fn limits(&self) -> Limits {
        Limits {
            symbols: self.max_symbols,
            shapes: self.max_shapes,
            frames: self.max_frames,
            pixels: self.max_pixels,
            plan_voxels: self.max_plan_voxels,
            memory_bytes: self.max_memory,
        }
    }
}

/// The scene files and the frame a command works on.
#[derive(Args)]
pub struct FrameArgs {
    /// Definition files derived together as one animation.
    #[arg(required = true, value_name = "SCENE.lm")]
    pub scenes: Vec<PathBuf>,
    /// Frame number N: the words after N steps of Δt (default 0).
    #[arg(long, conflicts_with = "time")]
    pub frame: Option<u64>,
    /// Time T in seconds: the frame nearest to T.
    #[arg(long, allow_negative_numbers = true, value_parser = time)]
    pub time: Option<f64>,
    /// Let the scene run its `command_file` scripts.
    #[arg(long)]
    pub allow_commands: bool,
    #[command(flatten)]
    pub limits: LimitArgs,
}

#[derive(Clone, Copy, ValueEnum)]
pub enum PresetArg {
    Preview,
    Final,
}

#[derive(Clone, Copy, ValueEnum)]
pub enum FilterArg {
    Box,
    Gaussian,
}

impl FilterArg {
    pub fn filter(self) -> Filter {
        match self {
            FilterArg::Box => Filter::Box,
            FilterArg::Gaussian => Filter::Gaussian,
        }
    }
}

#[derive(Clone, Copy, ValueEnum)]
pub enum FormatArg {
    Png,
    Exr,
    Both,
}

#[derive(Clone, Copy, ValueEnum)]
pub enum AttenuationArg {
    Inverse,
    Thesis,
    None,
}

/// The preset's settings at `w` × `h`, with `--spp` if given (`still`,
/// `run` and `render`).
pub fn quality(preset: PresetArg, w: u32, h: u32, spp: Option<u32>) -> Settings {
    let mut s = match preset {
        PresetArg::Preview => Settings::preview(w, h),
        PresetArg::Final => Settings::final_quality(w, h),
    };
    if let Some(n) = spp {
        s.spp = n;
    }
    s
}

/// How `lmfilm sound` and `run` render the soundtrack: the fields of `sound::Settings`.
#[derive(Args)]
pub struct SoundArgs {
    /// Sample rate in Hz.
    #[arg(long, default_value_t = 48_000, value_parser = rate)]
    rate: u32,
    /// Speed of sound in m/s.
    #[arg(long, default_value_t = 343.0, value_parser = speed_of_sound)]
    speed_of_sound: f64,
    /// `inverse`: 1/max(d, 1 m); `thesis`: (1/(1 + d))² (eq. 2.4.1);
    /// `none`: delay and Doppler only.
    #[arg(long, value_enum, default_value_t = AttenuationArg::Inverse)]
    attenuation: AttenuationArg,
    /// Write 32-bit float samples instead of 16-bit PCM (no clipping).
    #[arg(long)]
    float: bool,
    /// Normalise the soundtrack to this integrated loudness in LUFS
    /// (ITU-R BS.1770-4, -70..0), keeping its true peak at or below
    /// -1 dBTP, with 5 ms fades at both ends.
    #[arg(
        long,
        value_name = "LUFS",
        default_value_t = sound::loudness::DEFAULT_TARGET,
        allow_negative_numbers = true,
        value_parser = loudness
    )]
    loudness: f64,
    /// Keep the renderer's raw levels: no loudness normalisation and
    /// no fades.
    #[arg(long, conflicts_with = "loudness")]
    no_normalize: bool,
}

impl SoundArgs {
    /// The renderer's settings.
    pub fn settings(&self) -> sound::Settings {
        sound::Settings {
            rate: self.rate,
            speed_of_sound: self.speed_of_sound,
            attenuation: match self.attenuation {
                AttenuationArg::Inverse => Attenuation::Inverse,
                AttenuationArg::Thesis => Attenuation::Thesis,
                AttenuationArg::None => Attenuation::None,
            },
            format: if self.float {
                SampleFormat::Float32
            } else {
                SampleFormat::Pcm16
            },
            loudness: (!self.no_normalize).then_some(self.loudness),
        }
    }
}

/// How frames are rendered (`run` and `render`).
#[derive(Args)]
pub struct RenderArgs {
    /// Frames to render: A..B (B excluded), A..=B, A.. or N; default all
    /// (or the scene's `rs_switch` ranges).
    #[arg(long, value_name = "A..B")]
    pub frames: Option<FrameRange>,
    /// `final` (the default): 16 samples, shadows, reflections;
    /// `preview`: 1 sample. `run` with no scene (the built-in film)
    /// renders at `final` with 3 samples per pixel unless --preset or
    /// --spp is given.
    #[arg(long, value_enum, value_name = "PRESET")]
    pub preset: Option<PresetArg>,
    /// Image width (default: the scene camera's `prefpos`).
    #[arg(long, value_parser = side)]
    pub width: Option<u32>,
    /// Image height (default: the scene camera's `prefpos`).
    #[arg(long, value_parser = side)]
    pub height: Option<u32>,
    /// Samples per pixel (overrides the preset's).
    #[arg(long, value_parser = spp)]
    pub spp: Option<u32>,
    /// `both` (the EXR master and its PNG), `png` (8-bit sRGB) or `exr`
    /// (RGBA, Z, normal, object id).
    #[arg(long, value_enum, default_value_t = FormatArg::Both)]
    pub format: FormatArg,
    /// Worker threads (default: all cores); the images do not depend on it.
    #[arg(long, value_parser = threads)]
    pub threads: Option<usize>,
    /// Put actor N's vision window (the derive folder's
    /// actors/N/vision.NNNN.png) into the frames' top-left corner.
    #[arg(long, value_name = "N")]
    pub inset: Option<usize>,
}

impl RenderArgs {
    /// The render settings (0 × 0: each snapshot camera's size) and the
    /// formats; a given size must fit `max_pixels`. `default_spp`: the
    /// samples per pixel when neither --preset nor --spp is given (the
    /// built-in film's), else the preset's.
    pub fn settings(
        &self,
        max_pixels: u64,
        default_spp: Option<u32>,
    ) -> crate::error::Result<(Settings, Formats)> {
        if let (Some(w), Some(h)) = (self.width, self.height) {
            Limits::check_pixels(w, h, max_pixels).map_err(crate::error::Error::input)?;
        }
        let (w, h) = (self.width.unwrap_or(0), self.height.unwrap_or(0));
        let spp = self.spp.or(default_spp.filter(|_| self.preset.is_none()));
        let s = quality(self.preset.unwrap_or(PresetArg::Final), w, h, spp);
        let f = match self.format {
            FormatArg::Png => Formats::Png,
            FormatArg::Exr => Formats::Exr,
            FormatArg::Both => Formats::Both,
        };
        Ok((s, f))
    }

    /// Sizes rayon's pool to `--threads` (ignored when a pool already
    /// exists: a library user calling twice).
    pub fn threads(&self) {
        if let Some(n) = self.threads {
            let _ = rayon::ThreadPoolBuilder::new()
                .num_threads(n)
                .build_global();
        }
    }
}
