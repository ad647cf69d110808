//! Resource limits of a run: how big a word, a scene, a film and an
//! image may grow before the run stops with a message (exit 2) instead
//! of exhausting memory or running without end. Each has a command-line
//! flag to raise it; docs/limits.md gives the reasons for the defaults.

use std::fmt;

/// The limits every command that reads a scene shares.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Limits {
    /// Symbols in one L-system's word (`--max-symbols`).
    pub symbols: usize,
    /// Primitives in one frame's scene: shapes and triangles of every
    /// geometry plus the instances placing them (`--max-shapes`).
    pub shapes: usize,
    /// Frames in one film (`--max-frames`).
    pub frames: u64,
    /// Pixels in one image (`--max-pixels`).
    pub pixels: u64,
    /// Voxels one actor's path search may add to its path before it
    /// gives up (Algorithm 1, `--max-plan-voxels`): bounds a plan's time
    /// and memory, and the length of the path it returns.
    pub plan_voxels: usize,
    /// Bytes the actors' visual memories may hold together
    /// (`--max-memory`).
    pub memory_bytes: u64,
}

impl Limits {
    /// Render threads a run may ask for (`--threads`): far more than any
    /// machine has cores, far fewer than the system lets one process start.
    pub const MAX_THREADS: usize = 1024;

    /// An error when a `width` × `height` image has more than `max`
    /// pixels (checked before its buffers are allocated).
    pub fn check_pixels(width: u32, height: u32, max: u64) -> Result<(), String> {
        let pixels = u64::from(width) * u64::from(height);
        if pixels > max {
            return Err(format!(
                "a {width}×{height} image has {pixels} pixels, over the limit of {max}; raise it with --max-pixels N"
            ));
        }
        Ok(())
    }
}

impl Default for Limits {
    /// Safe on a 24 GiB machine with room to spare (docs/limits.md).
    fn default() -> Self {
        Limits {
            symbols: 10_000_000,
            shapes: 10_000_000,
            frames: 1_000_000,
            pixels: 8192 * 8192,
            plan_voxels: 1 << 16,
            memory_bytes: 4 << 30,
        }
    }
}

/// A word that would grow past [`Limits::symbols`] in a step.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct LimitError {
    /// The definition file of the L-system.
    pub file: String,
    /// The frame the step was making.
    pub frame: u64,
    /// Symbols the next word would need at least.
    pub symbols: usize,
    pub max: usize,
}

impl fmt::Display for LimitError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{}: frame {}: the word reached {} symbols and would grow past the limit of {}; raise it with --max-symbols N",
            self.file, self.frame, self.symbols, self.max
        )
    }
}

impl std::error::Error for LimitError {}
