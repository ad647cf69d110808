//! Actors as they live through a film: where each one's eye is and looks,
//! its last vision window and its visual memory. The frame loop's sense
//! step (DESIGN §1 step 3) makes every actor with a vision window see
//! into the frame's BVH, in parallel, and remember what it saw.

use glam::{DVec3, Vec3};
use rayon::prelude::*;

use super::memory::{Forgetting, VisualMemory};
use super::octree::Cube;
use super::vision::{self, View, Window};
use super::{Actor, Table};
use crate::lsys::automata::AutomataCommand;
use crate::render::Accel;

/// The view angle before any `fov` command: 60°, in tenths of a degree.
const DEFAULT_FOV: i64 = 600;

/// One actor's body, eye and memory.
pub struct Living {
    pub id: usize,
    pub eye: Vec3,
    pub look_at: Vec3,
    /// View angle in tenths of a degree (`fov`).
    pub fov: i64,
    /// Clipping range of the vision window (`vision_range near far`).
    pub near: f32,
    pub far: f32,
    /// Edge of the vision window, when the actor has one.
    pub edge: Option<u32>,
    /// The visual memory, when `init` declared its cube and it is on.
    pub memory: Option<VisualMemory>,
    /// What the actor saw at the last sense step.
    pub window: Option<Window>,
}

impl Living {
    /// The actor as the commands of its first automata set it up.
    pub fn new(actor: &Actor) -> Living {
        let mut me = Living {
            id: actor.id(),
            eye: Vec3::ZERO,
            look_at: Vec3::Z,
            fov: DEFAULT_FOV,
            near: 0.01,
            far: 1e6,
            edge: actor.vision().map(|v| v.edge),
            memory: None,
            window: None,
        };
        let commands = actor.automata().first().map(|e| e.commands.as_slice());
        let mut memory_on = true;
        let mut range = f32::INFINITY;
        let mut cube = None;
        for c in commands.unwrap_or_default() {
            match c.command {
                AutomataCommand::Obs(p) => me.eye = DVec3::from_array(p).as_vec3(),
                AutomataCommand::Lat(p) => me.look_at = DVec3::from_array(p).as_vec3(),
                AutomataCommand::Fov(f) => me.fov = f,
                AutomataCommand::VisionRange {
                    near,
                    far,
                    memory_range,
                } => {
                    (me.near, me.far) = (near as f32, far as f32);
                    if memory_range > 0.0 {
                        range = memory_range as f32;
                    }
                }
                AutomataCommand::Init {
                    min,
                    max,
                    voxel_edge,
                    ..
                } => cube = Some(Cube::new(min, max, voxel_edge)),
                AutomataCommand::VisMemOn => memory_on = true,
                AutomataCommand::VisMemOff => memory_on = false,
                _ => {}
            }
        }
        if let (Some(cube), true) = (cube, memory_on && me.edge.is_some()) {
            let rule = Forgetting {
                range,
                ..Forgetting::thesis(cube.voxel_edge)
            };
            me.memory = Some(VisualMemory::new(cube, rule));
        }
        me
    }

    /// Sees into `accel` and remembers what it saw, at `frame`.
    fn sense(&mut self, accel: &Accel, frame: u64) {
        let Some(edge) = self.edge else { return };
        let view = View::new(self.eye, self.look_at, self.fov, self.near, self.far);
        let window = vision::see(accel, &view, edge);
        if let Some(memory) = &mut self.memory {
            let stamp = u32::try_from(frame).unwrap_or(u32::MAX);
            memory.integrate(&window.depth_view(), stamp);
        }
        self.window = Some(window);
    }
}

/// Every actor of the table, as it stands before the first frame.
pub fn living(table: &Table) -> Vec<Living> {
    table.actors().iter().map(Living::new).collect()
}

/// The sense step: every actor sees, in parallel; each writes only its
/// own window and memory, so the result does not depend on threads.
pub fn sense(actors: &mut [Living], accel: &Accel, frame: u64) {
    actors.par_iter_mut().for_each(|a| a.sense(accel, frame));
}
