//! What a render is asked for: size, samples, filter, shadows and
//! bounces, and the two presets (`preview`, `final`).

use serde::{Deserialize, Serialize};

/// How pixel samples are weighted.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, clap::ValueEnum)]
#[serde(rename_all = "lowercase")]
pub enum Filter {
    Box,
    /// Weights exp(−r²/2σ²), σ = 0.5 pixel, over the samples of the pixel.
    Gaussian,
}

impl Filter {
    /// The name the command line and the records use.
    pub fn name(self) -> &'static str {
        match self {
            Filter::Box => "box",
            Filter::Gaussian => "gaussian",
        }
    }
}

/// How a pixel's light is computed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize, clap::ValueEnum)]
#[serde(rename_all = "lowercase")]
pub enum Integrator {
    /// Rayshade's Whitted shading: lights, hard or sphere-sampled
    /// shadows, an ambient term, mirrors and glass traced.
    #[default]
    Whitted,
    /// Unidirectional path tracing with next-event estimation and
    /// multiple importance sampling, the sky as a light, a thin lens.
    Path,
}

impl Integrator {
    /// The name the command line and the records use.
    pub fn name(self) -> &'static str {
        match self {
            Integrator::Whitted => "whitted",
            Integrator::Path => "path",
        }
    }
}

/// The film camera's 180° shutter: open half of each frame interval.
pub const SHUTTER: f32 = 0.5;

/// The two starting points of a render's sampling settings.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, clap::ValueEnum)]
#[serde(rename_all = "lowercase")]
pub enum Preset {
    Preview,
    Final,
}

impl Preset {
    /// The name the command line and the records use.
    pub fn name(self) -> &'static str {
        match self {
            Preset::Preview => "preview",
            Preset::Final => "final",
        }
    }
}

/// What a render does.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Settings {
    pub width: u32,
    pub height: u32,
    /// Samples per pixel.
    pub spp: u32,
    pub filter: Filter,
    pub shadows: bool,
    /// Reflection and refraction bounces (Whitted); bounces of a path
    /// (path: 0 is direct light only).
    pub max_depth: u32,
    /// Shadow rays toward each sphere light (soft shadows).
    pub light_samples: u32,
    pub integrator: Integrator,
    /// The fraction of the frame interval the shutter stays open (the
    /// path tracer's motion blur; 0 freezes the frame).
    pub shutter: f32,
    /// Whether the frame is denoised (`render::denoise`), guided by its
    /// layers (which it then computes whatever the format).
    pub denoise: bool,
    /// Whether the depth, normal and object id layers are wanted (EXR):
    /// they cost one more ray through each pixel centre.
    pub layers: bool,
    /// Frame number, part of the sample key.
    pub frame: u64,
}

impl Settings {
    /// Whether a frame blurs what moves toward the next frame (the path
    /// tracer with the shutter open), so it needs the next frame's scene.
    pub fn blurs(&self) -> bool {
        self.integrator == Integrator::Path && self.shutter > 0.0
    }

    /// The preset's settings at `width` × `height`.
    pub fn of_preset(preset: Preset, width: u32, height: u32) -> Self {
        match preset {
            Preset::Preview => Settings::preview(width, height),
            Preset::Final => Settings::final_quality(width, height),
        }
    }

    /// `preview`: one sample, no shadows, no traced bounces (mirrors and
    /// glass get a one-look approximation, see `shade::preview_bounce`).
    pub fn preview(width: u32, height: u32) -> Self {
        Settings {
            width,
            height,
            spp: 1,
            filter: Filter::Box,
            shadows: false,
            max_depth: 0,
            light_samples: 1,
            integrator: Integrator::Whitted,
            shutter: SHUTTER,
            denoise: false,
            layers: true,
            frame: 0,
        }
    }

    /// `final`: 16 samples, shadows (4 rays per sphere light), 5 bounces.
    pub fn final_quality(width: u32, height: u32) -> Self {
        Settings {
            width,
            height,
            spp: 16,
            filter: Filter::Box,
            shadows: true,
            max_depth: 5,
            light_samples: 4,
            integrator: Integrator::Whitted,
            shutter: SHUTTER,
            denoise: false,
            layers: true,
            frame: 0,
        }
    }
}
