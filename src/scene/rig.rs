//! Inverse kinematics of the built-in humanoid (issue 39): the pose that
//! puts its eyes (or its hips) at a point, its feet on given points, its
//! wrists on given points and its head toward what it looks at. Legs and
//! arms are two-bone chains solved in closed form (the knee forward, the
//! elbow down and back), so a reachable target is met exactly and an
//! unreachable one is approached along the straight limb.
//!
//! Axes as in [`super::body`]: y up, the figure faces +z, its left is +x.

use glam::{Affine3A, Mat3, Quat, Vec3};

pub use super::body::yaw;
use super::body::{Pose, Skeleton};

/// Where the body hangs from.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Anchor {
    /// Its eyes at this point: the head carries an actor's eye.
    Eyes(Vec3),
    /// Its hips joint at this point.
    Hips(Vec3),
}

/// What the pose must reach. Feet and hands are `[left, right]`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Targets {
    pub anchor: Anchor,
    /// Where the hips face (horizontal; +z when zero).
    pub facing: Vec3,
    /// Each foot's ankle joint, where it stands or swings; None hangs
    /// the leg straight down.
    pub feet: [Option<Vec3>; 2],
    /// Where each foot's toes point (horizontal; `facing` when zero).
    pub toes: [Vec3; 2],
    /// Which feet stand on the ground (bear weight): a pose that leaves
    /// one of them short of its target makes it slide.
    pub standing: [bool; 2],
    /// Each wrist; None lets the arm hang.
    pub hands: [Option<Vec3>; 2],
    /// A point the head turns to, within what a neck allows.
    pub gaze: Option<Vec3>,
    /// How far each hanging arm swings forward, radians (±1 at most).
    pub arm_swing: [f32; 2],
    /// The chest's turn about the vertical against the hips, radians
    /// (a stroke's wind-up), held to ±[`MAX_TWIST`].
    pub twist: f32,
}

impl Targets {
    /// Standing relaxed: the anchor, the facing, nothing else asked.
    pub fn standing(anchor: Anchor, facing: Vec3) -> Targets {
        Targets {
            anchor,
            facing,
            feet: [None; 2],
            toes: [Vec3::ZERO; 2],
            standing: [false; 2],
            hands: [None; 2],
            gaze: None,
            arm_swing: [0.0; 2],
            twist: 0.0,
        }
    }
}

/// Most the chest turns against the hips, and the head against the chest
/// (left or right) and up or down, radians.
pub const MAX_TWIST: f32 = 1.0;
const MAX_HEAD_YAW: f32 = 1.4;
const MAX_HEAD_PITCH: f32 = 0.9;

/// The eyes in the frame of a standing humanoid of height 1 (between
/// them, inside the head's ellipsoid, in front of the head joint).
pub const EYES: Vec3 = Vec3::new(0.0, 0.935, 0.05);

/// Where the eyes of a walking humanoid of `height` are, its hips over
/// the ground point `under` and facing `facing` (its knees bent by
/// [`crate::scene::gait::CROUCH`]).
pub fn walking_eyes(under: Vec3, facing: Vec3, height: f32) -> Vec3 {
    let crouch = crate::scene::gait::CROUCH;
    under + yaw(facing) * Vec3::new(0.0, EYES.y - crouch, EYES.z) * height
}

/// The ground point under the hips of a walking humanoid of `height`
/// whose eyes are at `eyes`, facing `facing`, on the ground at `ground`
/// (the inverse of [`walking_eyes`]).
pub fn walking_under(eyes: Vec3, facing: Vec3, height: f32, ground: f32) -> Vec3 {
    let p = eyes - yaw(facing) * Vec3::new(0.0, 0.0, EYES.z) * height;
    Vec3::new(p.x, ground, p.z)
}

/// Joints of the built-in humanoid, by their place in
/// [`Skeleton::humanoid`].
const HIPS: usize = 0;
const SPINE: usize = 1;
const CHEST: usize = 2;
const NECK: usize = 3;
const HEAD: usize = 4;
/// (upper limb joint, middle joint, end joint) of the four limbs: the
/// upper joint's rotation turns the upper bone, whose drawn capsule is
/// the middle joint's.
const LEGS: [[usize; 3]; 2] = [[13, 14, 15], [17, 18, 19]];
const ARMS: [[usize; 3]; 2] = [[6, 7, 8], [10, 11, 12]];
/// The ankle joints, left and right.
pub const FEET: [usize; 2] = [15, 19];

/// The rotation turning the orthonormal pair (`a`, `b`) onto (`c`, `d`).
fn frame_turn(a: Vec3, b: Vec3, c: Vec3, d: Vec3) -> Quat {
    let from = Mat3::from_cols(a, b, a.cross(b));
    let to = Mat3::from_cols(c, d, c.cross(d));
    Quat::from_mat3(&(to * from.transpose())).normalize()
}

/// `v` without its part along the unit `n`, normalised; `fallback`
/// (likewise made perpendicular) when `v` is along `n`.
fn perpendicular(v: Vec3, n: Vec3, fallback: Vec3) -> Vec3 {
    let p = v - n * v.dot(n);
    if p.length_squared() > 1e-10 {
        return p.normalize();
    }
    let q = fallback - n * fallback.dot(n);
    q.try_normalize()
        .unwrap_or_else(|| n.any_orthonormal_vector())
}

/// The middle joint of a two-bone chain from `root` toward `target`
/// (bones `l1`, `l2`), bent toward `pole`, the end (the target held to
/// the chain's reach) and the normal of the plane the chain bends in.
fn bend(root: Vec3, target: Vec3, l1: f32, l2: f32, pole: Vec3) -> (Vec3, Vec3, Vec3) {
    let to = target - root;
    let dir = to.try_normalize().unwrap_or(Vec3::NEG_Y);
    let d = to
        .length()
        .clamp((l1 - l2).abs() + 1e-5, (l1 + l2) * (1.0 - 1e-6));
    let end = root + dir * d;
    let a = (l1 * l1 - l2 * l2 + d * d) / (2.0 * d);
    let h = (l1 * l1 - a * a).max(0.0).sqrt();
    let side = perpendicular(pole, dir, Vec3::Z);
    (root + dir * a + side * h, end, dir.cross(side))
}

impl Skeleton {
    /// The pose meeting `t` (see [`Targets`]); for the built-in humanoid
    /// ([`Skeleton::humanoid`]) only.
    pub fn solve(&self, t: &Targets) -> Pose {
        let mut pose = self.upper_body(t);
        let facing = yaw(t.facing);
        let forward = facing * Vec3::Z;
        let down = Vec3::NEG_Y;
        for (side, [upper, middle, end]) in LEGS.into_iter().enumerate() {
            let world = self.world(&pose);
            let hip = Vec3::from(world[upper].translation);
            let (l1, l2) = self.bones(middle, end);
            let target = t.feet[side].unwrap_or(hip + down * (l1 + l2));
            self.reach(
                &mut pose,
                [upper, middle, end],
                target,
                down,
                Vec3::Z,
                forward,
            );
            // The foot level, its toes along `toes`.
            let world = self.world(&pose);
            let toes = if t.toes[side].length_squared() > 1e-12 {
                yaw(t.toes[side])
            } else {
                facing
            };
            let shin = world[middle].to_scale_rotation_translation().1;
            pose.rotations[FEET[side]] = shin.inverse() * toes;
        }
        for (side, [upper, middle, end]) in ARMS.into_iter().enumerate() {
            let world = self.world(&pose);
            let shoulder = Vec3::from(world[upper].translation);
            let (l1, l2) = self.bones(middle, end);
            // A hanging arm: down, a little out and forward.
            let out = if side == 0 { 1.0 } else { -1.0 };
            let swing = Quat::from_rotation_x(-t.arm_swing[side].clamp(-1.0, 1.0));
            let hang = facing * swing * Vec3::new(0.15 * out, -1.0, 0.08).normalize();
            let target = t.hands[side].unwrap_or(shoulder + hang * (l1 + l2) * 0.98);
            let rest = Vec3::new(out, 0.0, 0.0);
            let elbow = facing * Vec3::new(0.3 * out, -0.4, -1.0);
            self.reach(
                &mut pose,
                [upper, middle, end],
                target,
                rest,
                Vec3::NEG_Z,
                elbow,
            );
        }
        pose
    }

    /// The hips joint of the pose meeting `t`: a walking motor puts the
    /// feet about it.
    pub fn hips(&self, t: &Targets) -> Vec3 {
        self.world(&self.upper_body(t))[HIPS].translation.into()
    }

    /// The root, the spine and the head of the pose meeting `t`, the
    /// limbs at rest.
    fn upper_body(&self, t: &Targets) -> Pose {
        let height = self.height();
        let facing = yaw(t.facing);
        let mut pose = self.rest(Affine3A::from_quat(facing));
        let twist = Quat::from_rotation_y(t.twist.clamp(-MAX_TWIST, MAX_TWIST) * 0.5);
        pose.rotations[SPINE] = twist;
        pose.rotations[CHEST] = twist;
        // The anchor: the hips at a point, or the root moved so that the
        // eyes of the head looking ahead are where they must be (turning
        // to the gaze then moves them a few centimetres, within the head).
        let hips_at_rest = self.joints[HIPS].offset;
        pose.root.translation = match t.anchor {
            Anchor::Hips(p) => (p - facing * hips_at_rest).into(),
            Anchor::Eyes(p) => {
                let world = self.world(&pose);
                let eyes = world[HEAD]
                    .transform_point3(EYES * height - Vec3::new(0.0, self.head_height(), 0.0));
                (Vec3::from(pose.root.translation) + p - eyes).into()
            }
        };
        // The head toward the gaze, within the neck's turn; half of it
        // in the neck.
        if let Some(g) = t.gaze {
            let world = self.world(&pose);
            let chest = world[CHEST].to_scale_rotation_translation().1;
            let from = world[HEAD].transform_point3(Vec3::new(0.0, 0.055, 0.05) * height);
            let local = chest.inverse() * (g - from);
            if local.length_squared() > 1e-12 && local.is_finite() {
                let yaw_angle = local.x.atan2(local.z).clamp(-MAX_HEAD_YAW, MAX_HEAD_YAW);
                let flat = (local.x * local.x + local.z * local.z).sqrt();
                let pitch = (-local.y)
                    .atan2(flat)
                    .clamp(-MAX_HEAD_PITCH, MAX_HEAD_PITCH);
                let turn = Quat::from_rotation_y(yaw_angle) * Quat::from_rotation_x(pitch);
                let half = Quat::IDENTITY.slerp(turn, 0.5);
                pose.rotations[NECK] = half;
                pose.rotations[HEAD] = half.inverse() * turn;
                if let Anchor::Eyes(p) = t.anchor {
                    // The body steps under the turned head so that the
                    // eyes stay over the anchor (a look down lowers them
                    // a little, within the head).
                    let moved = p - self.eyes(&self.world(&pose));
                    pose.root.translation += glam::Vec3A::new(moved.x, 0.0, moved.z);
                }
            }
        }
        pose
    }

    /// The lengths of a limb's two bones: to its middle joint and to
    /// its end.
    fn bones(&self, middle: usize, end: usize) -> (f32, f32) {
        (
            self.joints[middle].offset.length(),
            self.joints[end].offset.length(),
        )
    }

    /// The head joint's height in a standing figure (its eyes are
    /// measured from it).
    fn head_height(&self) -> f32 {
        self.joints[..=HEAD].iter().map(|j| j.offset.y).sum()
    }

    /// Turns `upper` and `middle` so that `end` reaches `target`: `rest`
    /// is the limb's direction at rest (its pole `rest_pole` the side the
    /// middle joint bends to), `pole` the side it bends to now.
    fn reach(
        &self,
        pose: &mut Pose,
        [upper, middle, end]: [usize; 3],
        target: Vec3,
        rest: Vec3,
        rest_pole: Vec3,
        pole: Vec3,
    ) {
        let world = self.world(pose);
        let root = Vec3::from(world[upper].translation);
        let (l1, l2) = self.bones(middle, end);
        if !(target.is_finite() && l1 > 0.0 && l2 > 0.0) {
            return;
        }
        let (knee, foot, normal) = bend(root, target, l1, l2, pole);
        let d1 = (knee - root) / l1;
        let d2 = (foot - knee).try_normalize().unwrap_or(d1);
        // Each bone's pole side within the plane the limb bends in: well
        // defined even where a bone points along the pole (a seated
        // thigh, forward).
        let side = |d: Vec3| normal.cross(d).normalize();
        let upper_world = frame_turn(rest, rest_pole, d1, side(d1));
        let middle_world = frame_turn(rest, rest_pole, d2, side(d2));
        let parent = world[self.joints[upper].parent.expect("a limb has a parent")]
            .to_scale_rotation_translation()
            .1;
        pose.rotations[upper] = parent.inverse() * upper_world;
        pose.rotations[middle] = upper_world.inverse() * middle_world;
    }

    /// The world point of the eyes of a pose of this humanoid (see
    /// [`EYES`]).
    pub fn eyes(&self, world: &[Affine3A]) -> Vec3 {
        let height = self.height();
        world[HEAD].transform_point3(EYES * height - Vec3::new(0.0, self.head_height(), 0.0))
    }
}
