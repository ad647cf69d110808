//! Bodies in a word (`D` par1 = 50–52, issue 39): the built-in humanoid
//! placed at the turtle — posed in the turtle's frame by motion capture,
//! or held by the turtle at its eyes, hand or hips and moved by its
//! motor — drawn as capsules and a head, or left undrawn for a figure
//! the word draws itself, joint by joint (`D` 51 takes the turtle to a
//! joint).

use glam::{Affine3A, Vec3, Vec3A};

use super::{placed, Interpreter};
use crate::lsys::Symbol;
use crate::scene::body::{Pose, Skeleton};
use crate::scene::motor::{Drive, Hold, Motor, DEFAULT_HEIGHT};
use crate::scene::rig::{Targets, FEET};
use crate::scene::shape::bounds;
use crate::scene::MAX_COORDINATE;

/// The humanoid's axes (x its left, y up, z forward) onto the turtle's:
/// it stands along H, as a stem grows (`+(90)` turns H up, thesis code
/// 6.2.1), faces U, and its left is −L (a right-handed turn).
const HUMANOID_TO_TURTLE: Affine3A =
    Affine3A::from_cols(Vec3A::NEG_Y, Vec3A::X, Vec3A::Z, Vec3A::ZERO);

/// `D` par1 = 50's motion −1: seated (a body held by the turtle).
const SEATED: i64 = -1;

/// A body placed by `D` par1 = 50 or 52, as its parameters give it.
struct BodyAt {
    /// par4: the motion capture (`fig_bvh`; 0 none), or [`SEATED`].
    motion: i64,
    /// par5: its height, where > 0.
    height: Option<f32>,
    /// par6: what the turtle holds (None: its frame).
    hold: Option<Hold>,
}

impl Interpreter<'_> {
    /// `D` par1 = 50 (drawn) and 52 (not drawn): a body at the turtle; its
    /// joints are where `D` par1 = 51 takes the turtle next.
    pub(in crate::turtle) fn body(&mut self, s: &Symbol, g: [f64; 3], drawn: bool) {
        let height = (g[1].is_finite() && g[1] > 0.0).then(|| g[1].min(1e3) as f32);
        let motion = if g[0].is_finite() { g[0] as i64 } else { 0 };
        let hold = match g[2] {
            1.0 => Some(Hold::Eyes),
            2.0 => Some(Hold::Hand),
            3.0 => Some(Hold::Ground),
            0.0 => None,
            h => {
                self.warn(&format!(
                    "`D` par1 = 50 holds the body by {h}, not 0 (its frame), 1 (its eyes), 2 (its right hand) or 3 (its hips over the ground): by its frame"
                ));
                None
            }
        };
        let frame = placed(&self.t, 1.0, 1.0, 1.0);
        if !frame.is_finite() {
            self.warn("`D` par1 = 50 with a turtle frame that is not finite is skipped");
            return;
        }
        let body = BodyAt {
            motion,
            height,
            hold,
        };
        let (skeleton, pose) = self.pose(&body, frame, s.id);
        let world = skeleton.world(&pose);
        if !world.iter().all(|w| w.is_finite()) {
            return self.warn("a body (`D` par1 = 50) whose pose is not finite is skipped");
        }
        if drawn {
            self.draw_body(&skeleton, &world, s.id);
        }
        self.joints = Some((skeleton, world));
    }

    /// The skeleton and pose of `body`: held by the turtle, its motor's
    /// (see [`crate::turtle::TurtleWorld::drive_body`]; a fresh motor
    /// where the world keeps none); else the built-in humanoid posed by
    /// its motion capture's frame nearest the time (the rest pose for
    /// motion 0, or a motion the Surfaces section does not declare, with
    /// a warning).
    fn pose(&mut self, body: &BodyAt, frame: Affine3A, symbol: u64) -> (Skeleton, Pose) {
        if let Some(hold) = body.hold {
            let at = Vec3::from(frame.translation);
            let heading = Vec3::from(frame.x_axis);
            let mut drive = Drive::new(hold, at, heading, self.time);
            drive.height = body.height;
            drive.seated = body.motion == SEATED;
            let (skeleton, targets) = self
                .world
                .drive_body((self.ls.index, symbol), self.actor, drive)
                .unwrap_or_else(|| {
                    let mut motor = Motor::new(&drive);
                    let targets = motor.drive(&drive);
                    (motor.skeleton().clone(), targets)
                });
            let pose = skeleton.solve(&targets);
            self.feet_beyond_reach(&skeleton, &pose, &targets);
            return (skeleton, pose);
        }
        let skeleton = Skeleton::humanoid(body.height.unwrap_or(DEFAULT_HEIGHT));
        let mut pose = skeleton.rest(Affine3A::IDENTITY);
        if body.motion != 0 {
            let lsys = self.ls.index;
            let found = self
                .motions
                .iter()
                .find(|(l, n, _)| *l == lsys && *n == body.motion);
            match found {
                Some((_, _, m)) => pose = skeleton.pose_from(m, m.frame_at(self.time)),
                None => self.warn(&format!(
                    "`D` par1 = 50 names motion {}, which the Surfaces section does not declare (`fig_bvh {} file.bvh`): the rest pose",
                    body.motion, body.motion
                )),
            }
        }
        pose.root = frame * HUMANOID_TO_TURTLE * pose.root;
        (skeleton, pose)
    }

    /// Warns (once per height) when the pose leaves a standing foot more
    /// than 2 cm from where its motor or its actor's footholds set it:
    /// the legs are too short for the steps, and the foot slides.
    fn feet_beyond_reach(&mut self, skeleton: &Skeleton, pose: &Pose, targets: &Targets) {
        let world = skeleton.world(pose);
        let short = (0..2)
            .filter(|&k| targets.standing[k])
            .filter_map(|k| {
                let at = Vec3::from(world[FEET[k]].translation);
                Some(at.distance(targets.feet[k]?))
            })
            .fold(0.0, f32::max);
        if short > 0.02 {
            self.warn(&format!(
                "a body {:.2} m tall cannot reach where its feet are set (steps or ground beyond its legs' reach): its feet slide; a taller body (`D` 50 par5) or shorter steps (`foothold_step`) keep them planted",
                skeleton.height()
            ));
        }
    }

    /// The body's capsules and head in the current material, each bone
    /// its own symbol identifier (the bone's number in the top bits), so
    /// motion blur pairs it with itself in the next frame. A body
    /// reaching beyond the scene's coordinates is skipped whole.
    fn draw_body(&mut self, skeleton: &Skeleton, world: &[Affine3A], symbol: u64) {
        let mut shapes = skeleton.draw(world, self.material, 0);
        for s in &mut shapes {
            s.symbol = symbol ^ ((s.symbol + 1) << 48);
        }
        if shapes.iter().any(|s| bounds(s).is_none()) {
            return self.warn(&format!(
                "a body (`D` par1 = 50) reaching beyond ±{MAX_COORDINATE:e} is skipped"
            ));
        }
        if self.b.count(shapes.len()) {
            for s in shapes {
                self.own(s.symbol);
                self.geometry().shapes.push(s);
            }
        }
    }

    /// `D` par1 = 51: the turtle to joint par4 (0–21, in the order of
    /// docs/symbols.md) of the body last placed, H along its bone to its
    /// first child (a joint without one: its own up), U toward its front.
    pub(in crate::turtle) fn turtle_to_joint(&mut self, g: [f64; 3]) {
        let Some((skeleton, world)) = &self.joints else {
            return self.warn("`D` par1 = 51 takes the turtle to a joint, and no body (`D` 50, 52) was placed before it: skipped");
        };
        let count = skeleton.joints.len();
        let k = g[0];
        if !(k >= 0.0 && k < count as f64 && k.fract() == 0.0) {
            return self.warn(&format!(
                "`D` par1 = 51 names joint {k}, not one of 0 to {}: skipped",
                count - 1
            ));
        }
        let k = k as usize;
        let joint = world[k];
        let at = Vec3::from(joint.translation);
        let child = skeleton.joints.iter().position(|j| j.parent == Some(k));
        let h = child
            .map(|c| Vec3::from(world[c].translation) - at)
            .and_then(Vec3::try_normalize)
            .unwrap_or_else(|| Vec3::from(joint.y_axis).normalize());
        let front = Vec3::from(joint.z_axis);
        let u = (front - h * front.dot(h))
            .try_normalize()
            .unwrap_or_else(|| h.any_orthonormal_vector());
        self.t.pos = at.as_dvec3();
        self.t.h = h.as_dvec3();
        self.t.u = u.as_dvec3();
        self.t.l = self.t.u.cross(self.t.h);
    }
}
