//! One frame of a film as the frame loop hands it out: its number, its
//! time, its scene and the scene's acceleration structure, which vision
//! and the camera share.

use std::sync::{Arc, OnceLock};

use crate::render::Accel;
use crate::scene::Scene;

/// Frame `number` at time `number · Δt`, interpreted.
pub struct Frame {
    number: u64,
    time: f64,
    scene: Arc<Scene>,
    /// Built on first use (DESIGN §1 step 2): a derivation that only
    /// writes snapshots never needs it.
    accel: OnceLock<Accel>,
    warnings: Vec<String>,
}

impl Frame {
    pub(super) fn new(number: u64, time: f64, scene: Scene, warnings: Vec<String>) -> Frame {
        Frame {
            number,
            time,
            scene: Arc::new(scene),
            accel: OnceLock::new(),
            warnings,
        }
    }

    pub fn number(&self) -> u64 {
        self.number
    }

    pub fn time(&self) -> f64 {
        self.time
    }

    pub fn scene(&self) -> &Arc<Scene> {
        &self.scene
    }

    /// The scene's BVH, built once for everything that casts rays into
    /// this frame.
    pub fn accel(&self) -> &Accel {
        self.accel
            .get_or_init(|| Accel::new(Arc::clone(&self.scene)))
    }

    /// More warnings about this frame (the sound handler's, at its end).
    pub(super) fn warn(&mut self, more: Vec<String>) {
        self.warnings.extend(more);
    }

    /// The turtle's and the sound handler's warnings about this frame.
    pub fn warnings(&self) -> &[String] {
        &self.warnings
    }
}
