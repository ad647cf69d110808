//! The options the commands share, each checked where clap reads it (a
//! value out of range is a usage error, exit 2, naming the option).

use std::path::PathBuf;

use clap::{Args, ValueEnum};

use crate::lsys::Limits;
use crate::production::frames::FrameRange;
use crate::production::settings::{within, Formats, RenderRequest, SoundRequest};
use crate::sound::{self, Attenuation, SampleFormat};

/// A finite number > 0 for `what`.
fn positive(text: &str, what: &str) -> Result<f64, String> {
    match text.trim().parse::<f64>() {
        Ok(v) if v.is_finite() && v > 0.0 => Ok(v),
        _ => Err(format!("{what} must be > 0, got {text}")),
    }
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
    /// The options that set these limits again (a farm's jobs).
    pub fn args(&self) -> Vec<String> {
        vec![
            format!("--max-symbols={}", self.max_symbols),
            format!("--max-shapes={}", self.max_shapes),
            format!("--max-frames={}", self.max_frames),
            format!("--max-pixels={}", self.max_pixels),
            format!("--max-plan-voxels={}", self.max_plan_voxels),
            format!("--max-memory={}", self.max_memory),
        ]
    }

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

/// What a command that reads scenes may let them do, and their limits.
#[derive(Args, Clone, Copy)]
#[command(next_help_heading = "Scene and limits")]
pub struct SceneArgs {
    /// Let the scene run its `command_file` scripts.
    #[arg(long)]
    pub allow_commands: bool,
    #[command(flatten)]
    pub limits: LimitArgs,
}

impl SceneArgs {
    /// The options that ask for the same again (a farm's derive job).
    pub fn args(&self) -> Vec<String> {
        let mut a = Vec::new();
        if self.allow_commands {
            a.push("--allow-commands".to_string());
        }
        a.extend(self.limits.args());
        a
    }
}

/// `still -o`: an image path ending in .png or .exr.
pub fn image_path(text: &str) -> std::result::Result<std::path::PathBuf, String> {
    let path = std::path::PathBuf::from(text);
    match crate::render::ImageFormat::of_path(&path) {
        Some(_) => Ok(path),
        None => Err(format!(
            "{text}: the output must end in {}",
            crate::render::ImageFormat::listed()
        )),
    }
}

/// What `still` and `watch` render: a frame into an image.
#[derive(Args, Clone)]
pub struct StillArgs {
    /// The image to write: .png or .exr.
    #[arg(short, long, value_name = "OUT.png|OUT.exr", value_parser = image_path)]
    pub output: PathBuf,
    /// Diameter of the thin cylinders drawn for segments `R S`.
    #[arg(long, default_value_t = 0.05, value_parser = segment_width)]
    pub segment_width: f64,
    #[command(flatten)]
    pub at: FrameArgs,
    #[command(flatten)]
    pub quality: RenderRequest,
    /// Print where the time went: seconds to derive, build, render, encode.
    #[arg(long)]
    pub timings: bool,
}

/// The scene files and the frame a command works on.
#[derive(Args, Clone)]
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
    #[command(flatten)]
    pub scene: SceneArgs,
}

#[derive(Clone, Copy, ValueEnum)]
pub enum AttenuationArg {
    Inverse,
    Thesis,
    None,
}

#[derive(Clone, Copy, ValueEnum)]
pub enum SamplesArg {
    Pcm16,
    Float32,
}

/// `--inset`: an actor, or none.
#[derive(Clone, Copy, Debug)]
pub struct Inset(pub Option<usize>);

fn inset(text: &str) -> Result<Inset, String> {
    match text.trim() {
        "none" => Ok(Inset(None)),
        t => t
            .parse()
            .map(|a| Inset(Some(a)))
            .map_err(|_| format!("--inset takes an actor number or `none`, got {text:?}")),
    }
}

/// `--loudness`: a target in LUFS, or none (no normalisation).
#[derive(Clone, Copy, Debug)]
pub struct Loudness(pub Option<f64>);

fn loudness_or_off(text: &str) -> Result<Loudness, String> {
    match text.trim() {
        "off" => Ok(Loudness(None)),
        t => loudness(t).map(|l| Loudness(Some(l))),
    }
}

/// A film's render settings (`run`, `render`, `farm slurm`): every
/// option left out keeps the film's recorded one.
#[derive(Args, Clone, Copy)]
pub struct RenderArgs {
    #[command(flatten)]
    pub quality: RenderRequest,
    /// `both` (the EXR master and its PNG, the default), `png` (8-bit
    /// sRGB) or `exr` (RGBA, Z, normal, object id).
    #[arg(
        long,
        value_enum,
        help_heading = "Render settings",
        hide_possible_values = true
    )]
    pub format: Option<Formats>,
    /// Put actor N's vision window (the derive folder's
    /// actors/N/vision.NNNN.png) into the frames' top-left corner; `none`
    /// takes it out.
    #[arg(long, value_name = "N|none", value_parser = inset, help_heading = "Render settings")]
    pub inset: Option<Inset>,
}

impl RenderArgs {
    /// The request these options make.
    pub fn request(&self) -> RenderRequest {
        RenderRequest {
            formats: self.format,
            inset: self.inset.map(|i| i.0),
            ..self.quality
        }
    }
}

/// Which frames a process renders and with how many threads (`run`,
/// `render`).
#[derive(Args, Clone, Copy)]
pub struct WorkArgs {
    /// Frames to render: A..B (B excluded), A..=B, A.. or N; default all
    /// (or the scene's `rs_switch` ranges).
    #[arg(long, value_name = "A..B")]
    pub frames: Option<FrameRange>,
    /// Worker threads (default: all cores); the images do not depend on it.
    #[arg(long, value_parser = threads)]
    pub threads: Option<usize>,
    /// Print where the time went: seconds per stage of the frame pipeline
    /// (derive, snapshots, BVH builds, render, EXR, PNG, records).
    #[arg(long)]
    pub timings: bool,
    /// A line a frame as it is done (its number, rendered or up to date,
    /// seconds, node), for a log: a farm's render tasks write them.
    #[arg(long)]
    pub log_frames: bool,
}

impl WorkArgs {
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

/// How the soundtrack is rendered (`sound`, `run`, `farm slurm`): every
/// option left out keeps the film's recorded one, else the default.
#[derive(Args, Clone, Copy)]
#[command(next_help_heading = "Sound settings")]
pub struct SoundArgs {
    /// Sample rate in Hz (default 48000).
    #[arg(long, value_parser = rate)]
    rate: Option<u32>,
    /// Speed of sound in m/s (default 343).
    #[arg(long, value_parser = speed_of_sound)]
    speed_of_sound: Option<f64>,
    /// `inverse` (the default): 1/max(d, 1 m); `thesis`: (1/(1 + d))²
    /// (eq. 2.4.1); `none`: delay and Doppler only.
    #[arg(long, value_enum)]
    attenuation: Option<AttenuationArg>,
    /// `pcm16` (the default) or `float32` samples (no clipping).
    #[arg(long, value_enum)]
    samples: Option<SamplesArg>,
    /// The same as --samples float32.
    #[arg(long, conflicts_with = "samples")]
    float: bool,
    /// Normalise the soundtrack to this integrated loudness in LUFS
    /// (ITU-R BS.1770-4, -70..0; default -16), keeping its true peak at
    /// or below -1 dBTP, with 5 ms fades at both ends; `off` keeps the
    /// renderer's raw levels.
    #[arg(
        long,
        value_name = "LUFS|off",
        allow_negative_numbers = true,
        value_parser = loudness_or_off
    )]
    loudness: Option<Loudness>,
    /// The same as --loudness off.
    #[arg(long, conflicts_with = "loudness")]
    no_normalize: bool,
}

impl SoundArgs {
    /// The request these options make.
    pub fn request(&self) -> SoundRequest {
        let samples = match (self.samples, self.float) {
            (Some(SamplesArg::Float32), _) | (None, true) => Some(SampleFormat::Float32),
            (Some(SamplesArg::Pcm16), _) => Some(SampleFormat::Pcm16),
            (None, false) => None,
        };
        SoundRequest {
            rate: self.rate,
            speed_of_sound: self.speed_of_sound,
            attenuation: self.attenuation.map(|a| match a {
                AttenuationArg::Inverse => Attenuation::Inverse,
                AttenuationArg::Thesis => Attenuation::Thesis,
                AttenuationArg::None => Attenuation::None,
            }),
            format: samples,
            loudness: if self.no_normalize {
                Some(None)
            } else {
                self.loudness.map(|l| l.0)
            },
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::production::settings::{sound_args, Defaults, RenderChoice};
    use crate::render::{Filter, Integrator, Preset};
    use clap::Parser;

    #[derive(Parser)]
    struct Options {
        #[command(flatten)]
        render: RenderArgs,
        #[command(flatten)]
        sound: SoundArgs,
    }

    /// The options a farm's jobs get (`RenderChoice::args`, `sound_args`)
    /// ask for exactly the settings they were written from, whatever the
    /// folder recorded before: a setting the lists forgot would differ.
    #[test]
    fn the_farms_options_ask_for_the_same_settings() {
        let render = RenderChoice {
            size_given: true,
            width: 96,
            height: 72,
            spp: 5,
            filter: Filter::Gaussian,
            shadows: false,
            max_depth: 2,
            light_samples: 3,
            integrator: Integrator::Path,
            shutter: 0.25,
            formats: Formats::Png,
            inset: Some(1),
            ..RenderChoice::of_preset(Preset::Final, (64, 48))
        };
        let sound = sound::SoundSettings {
            rate: 44_100,
            speed_of_sound: 340.5,
            attenuation: Attenuation::Thesis,
            format: SampleFormat::Float32,
            loudness: None,
        };
        let words = std::iter::once("lmfilm".to_string())
            .chain(render.args())
            .chain(sound_args(&sound));
        let o = Options::try_parse_from(words).unwrap();
        let other = RenderChoice::of_preset(Preset::Preview, (320, 240));
        let camera = (64, 48);
        assert_eq!(
            o.render
                .request()
                .resolve(Some(&other), Defaults::default(), camera),
            render
        );
        assert_eq!(
            o.sound
                .request()
                .resolve(Some(&sound::SoundSettings::default())),
            sound
        );
    }
}
