//! Several L-systems derived together through time (code 2.1.1, part 0
//! and the step of part 5): one global time, one seed, one id counter.

use std::path::Path;

use super::definition::CameraParams;
use super::limits::{LimitError, Limits};
use super::parse::parse;
use super::sensors::Sensors;
use super::step::LSystem;
use crate::source::{read_file, Diagnostic, Source};

/// The L-systems of one animation and the global clock.
pub struct Animation {
    pub systems: Vec<LSystem>,
    /// Camera and animation parameters: those of the first file that has a
    /// `Camera_AnimationParameters` section.
    pub camera: CameraParams,
    /// Steps taken; the global time is `frame · Δt`.
    pub frame: u64,
    /// How far a step may grow a word (and what the film may do).
    pub limits: Limits,
    next_id: u64,
}

/// Why an animation could not be loaded.
#[derive(Debug)]
pub enum LoadError {
    /// The file could not be read (missing, a folder, a device, too large).
    Io(String, std::io::Error),
    Syntax(Diagnostic),
}

impl std::fmt::Display for LoadError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            LoadError::Io(p, e) => write!(f, "{p}: cannot read the file: {e}"),
            LoadError::Syntax(d) => d.fmt(f),
        }
    }
}

impl std::error::Error for LoadError {}

/// Largest definition file read: far beyond any hand-written scene, and
/// a bound on what a wrong path (a disk image, a device) can cost.
pub const MAX_SCENE_BYTES: u64 = 64 << 20;

/// Reads one definition file: a regular file of at most
/// [`MAX_SCENE_BYTES`], UTF-8 (else a diagnostic at the first bad byte).
pub fn read_source(path: &Path) -> Result<Source, LoadError> {
    let name = path.display().to_string();
    let bytes = read_file(path, MAX_SCENE_BYTES).map_err(|e| LoadError::Io(name.clone(), e))?;
    Source::from_bytes(name, bytes).map_err(LoadError::Syntax)
}

impl Animation {
    /// Reads and parses definition files in order.
    pub fn load<P: AsRef<Path>>(paths: &[P], sensors: &mut dyn Sensors) -> Result<Self, LoadError> {
        let sources = paths
            .iter()
            .map(|p| read_source(p.as_ref()))
            .collect::<Result<Vec<_>, _>>()?;
        Self::from_sources(&sources, sensors).map_err(LoadError::Syntax)
    }

    /// Parses the sources and derives their axioms (time 0).
    pub fn from_sources(sources: &[Source], sensors: &mut dyn Sensors) -> Result<Self, Diagnostic> {
        let defs = sources.iter().map(parse).collect::<Result<Vec<_>, _>>()?;
        let camera = defs
            .iter()
            .find(|d| d.has_camera)
            .map(|d| d.camera.clone())
            .unwrap_or_default();
        let mut next_id = 0;
        let systems = defs
            .into_iter()
            .enumerate()
            .map(|(k, d)| LSystem::new(d, k, camera.dt, camera.seed, &mut next_id, sensors))
            .collect();
        Ok(Animation {
            systems,
            camera,
            frame: 0,
            limits: Limits::default(),
            next_id,
        })
    }

    /// Global time T of the current words.
    pub fn time(&self) -> f64 {
        self.frame as f64 * self.camera.dt
    }

    /// Number of frames of the whole animation: times 0, Δt, … ≤ t_final
    /// (u64::MAX when there are more).
    pub fn frame_count(&self) -> u64 {
        ((self.camera.t_final / self.camera.dt + 1e-9).floor() as u64).saturating_add(1)
    }

    /// The frame nearest to time `t`.
    pub fn frame_at(&self, t: f64) -> u64 {
        (t / self.camera.dt).round().max(0.0) as u64
    }

    /// Steps every L-system from T to T + Δt, in file order; stops at the
    /// first word that would grow past [`Limits::symbols`].
    pub fn step(&mut self, sensors: &mut dyn Sensors) -> Result<(), LimitError> {
        let time = self.time();
        for ls in &mut self.systems {
            ls.step(
                time,
                self.frame,
                self.camera.seed,
                &mut self.next_id,
                sensors,
                self.limits.symbols,
            )
            .map_err(|symbols| LimitError {
                file: ls.def.name.clone(),
                frame: self.frame + 1,
                symbols,
                max: self.limits.symbols,
            })?;
        }
        self.frame += 1;
        Ok(())
    }

    /// Steps until the current frame is `frame`.
    pub fn advance_to(&mut self, frame: u64, sensors: &mut dyn Sensors) -> Result<(), LimitError> {
        while self.frame < frame {
            self.step(sensors)?;
        }
        Ok(())
    }
}
