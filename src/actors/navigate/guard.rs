//! The step guard (issue 54): a step of a walking actor ends before
//! anything its senses hold on the way — a surface its vision window
//! sees now in front of a point of the step, a voxel its memory holds —
//! so the eye never enters what it could have seen, whatever the speed
//! (a step of 10³⁰ m jumped through the wall it saw), the window (one
//! pixel) or the view angle (0.1°). It reads only what the actor
//! perceived: the window's depths and the memory.

use glam::Vec3;

use crate::actors::live::Living;

/// Most points of a step tested: a step longer than this many samples
/// of its spacing is tested at this many, spread over what the senses
/// can know of (the memory's cube, the vision's far distance).
const MAX_SAMPLES: usize = 4096;

impl Living {
    /// Says once what a navigator's senses cannot keep up with on its
    /// way (issue 54): a memory that is off (only this frame's window
    /// guards it), a step longer than itself (`speed`), a view that ends
    /// too near (`vision_range`), narrower than itself where it must see
    /// a wall beside its way (`fov`), or pixels so far apart there (half
    /// its size or more) that a wall's edge between two of them goes
    /// unplaced (`iVisionWinSize`). Asked every frame of a navigator but a tennis player (who looks at the
    /// ball through 9° on an open court by design). The step guard keeps
    /// it out of what it saw; what its senses never hold it may walk
    /// into, so the film says which setting and by how much.
    pub(in crate::actors) fn check_view(&mut self, dt: f32) {
        let Some(edge) = self.edge else {
            return; // said as "navigates without a vision window"
        };
        // Its size, or a memory voxel's where that is larger: nothing
        // smaller is remembered anyway.
        let voxel = self
            .memory
            .as_ref()
            .map_or(0.0, |m| m.octree().cube().voxel_edge as f32);
        let size = self.size_actor.max(voxel).max(1e-3);
        // Where it must see beside its way: past its near clip, and
        // two of its own sizes ahead.
        let ahead = self.near.max(2.0 * size);
        let angle = (self.fov as f32 / 10.0).to_radians();
        let wide = 2.0 * ahead * (angle * 0.5).tan();
        // A window's rays are evenly spread on its image plane.
        let gap = wide / edge as f32;
        if !self.memory_on {
            self.note_once(
                "memory off",
                &format!(
                    "navigates with its visual memory off (vis_mem_off): only what its window sees this frame keeps it out of walls; it stops its near clip ({}) before what it sees, but walks into what lies beside or behind its view, and plans again through what stopped it; vis_mem_on keeps it out",
                    self.near
                ),
            );
        }
        let step = self.speed * dt;
        if step > size {
            self.note_once(
                "fast walk",
                &format!(
                    "walks {step:.3} a frame (speed {} at Δt {dt}): farther than its own size ({size}: size_actor {} or the memory's voxel), it passes what its window has not yet looked at; it stops before what it sees or remembers, but a wall within its near clip ({}) it never sees; speed {:.3} or less keeps it out",
                    self.speed,
                    self.size_actor,
                    self.near,
                    size / dt
                ),
            );
        }
        if self.far < ahead {
            self.note_once(
                "short view",
                &format!(
                    "sees no farther than {} (vision_range far): nearer than the {ahead} ahead it must see beside its way (past its near clip {}, two of its sizes of {size}: size_actor {} or the memory's voxel), it walks into walls it cannot see; vision_range far {ahead} or more keeps it out",
                    self.far, self.near, self.size_actor
                ),
            );
        } else if wide < size {
            let fov = (2.0 * (size / (2.0 * ahead)).atan()).to_degrees() * 10.0;
            self.note_once(
                "narrow view",
                &format!(
                    "sees a view {wide:.3} wide {ahead} ahead (fov {} = {:.1}°, vision_range near {}): narrower than itself ({size}: size_actor {} or the memory's voxel), it cannot see a wall beside its way before it walks into it; fov {} or more keeps it out",
                    self.fov,
                    self.fov as f32 / 10.0,
                    self.near,
                    self.size_actor,
                    fov.ceil()
                ),
            );
        } else if 2.0 * gap >= size {
            // A wall's edge between two rays is placed only to within
            // their spacing: half its size, and the edge it plans past
            // may lie where its body goes (a 4-pixel window's rays 0.8
            // apart took an actor of 0.8 through a corner).
            let pixels = (2.0 * wide / size).floor() + 1.0;
            self.note_once(
                "sparse view",
                &format!(
                    "sees through a window of {edge}×{edge} pixels whose rays are {gap:.2} apart {ahead} ahead (fov {} = {:.1}°): half its own size or more ({size}: size_actor {} or the memory's voxel), it can walk into a wall's edge between two of them; iVisionWinSize {pixels} or more (or a narrower fov) keeps it out",
                    self.fov,
                    self.fov as f32 / 10.0,
                    self.size_actor
                ),
            );
        }
    }

    /// Where a step from the eye to `to` must stop, when it must: at the
    /// last tested point before the first that lies behind a surface the
    /// window sees (along that pixel's line; where the memory cannot
    /// guard it, within the near clip before it) or in a voxel the memory
    /// holds (but the eye's own), backed off by the spacing of the
    /// points. None when the whole step is free.
    pub(in crate::actors) fn step_stop(&self, to: Vec3) -> Option<Vec3> {
        let from = self.eye;
        let way = to - from;
        let length = way.length();
        if !(length.is_finite() && length > 0.0) {
            return None;
        }
        let octree = self.memory.as_ref().map(|m| m.octree());
        let edge = octree.map_or(0.1, |o| o.cube().voxel_edge as f32);
        let spacing = (edge * 0.5).clamp(1e-3, 0.1);
        // What the senses can know of lies within the memory's cube and
        // the vision's far distance.
        let known = octree
            .map(|o| {
                let c = o.cube();
                (c.max - c.min) as f32 * 3f32.sqrt()
            })
            .unwrap_or(0.0)
            .max(self.window.as_ref().map_or(0.0, |w| w.view.far));
        let tested = length.min(known + spacing);
        let n = ((tested / spacing).ceil() as usize).clamp(1, MAX_SAMPLES);
        let dir = way / length;
        let view = self
            .window
            .as_ref()
            .map(|w| (w, w.depth_view().projector()));
        let voxel_of = |p: Vec3| octree.and_then(|o| o.voxel(p.as_dvec3().to_array()));
        let held = |p: Vec3| {
            let o = octree?;
            o.get(voxel_of(p)?)
        };
        let eye_voxel = voxel_of(from);
        let eye_held = held(from).is_some();
        // How near what the window sees a step may end. A memory that
        // takes in what is seen, the eye outside what it holds, holds a
        // surface once it drops into the near clip, so the step may come
        // up to it (the tolerance covers a pixel's depths across its
        // footprint, as on a slope). Otherwise the window alone guards
        // the way: the step ends its near clip before the surface, or the
        // surface drops out of a window whose rays start at near, and the
        // next step walks through it.
        let remembers = octree.is_some() && self.memory_on && !eye_held;
        let clearance = if remembers {
            -(self.size_actor * 0.5 + spacing)
        } else {
            self.window.as_ref().map_or(0.0, |w| w.view.near.max(0.0)) + spacing
        };
        let nears_seen = |p: Vec3| {
            view.as_ref().is_some_and(|(w, project)| {
                project(p).is_some_and(|((x, y), d)| w.pixel(x, y).distance - clearance < d)
            })
        };
        // A held voxel stops the step; the eye's own, when held (a coarse
        // voxel of the ground, a fine one at a wall's face), does not.
        let blocked = |p: Vec3| held(p).is_some() && !(eye_held && voxel_of(p) == eye_voxel);
        let mut last = 0.0;
        for i in 1..=n {
            let t = tested * i as f32 / n as f32;
            let p = from + dir * t;
            if nears_seen(p) || blocked(p) {
                return Some(from + dir * (last - spacing).max(0.0));
            }
            last = t;
        }
        None
    }
}
