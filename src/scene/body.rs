//! Articulated bodies (issue 39): a skeleton of joints with bone
//! offsets and a rest pose, its pose as each joint's rotation, and the
//! body drawn around it as capsules (one per bone) and a head. The
//! built-in humanoid has 22 joints with the names of the public motion
//! capture libraries (Hips, Spine, …, LeftUpLeg, LeftLeg, LeftFoot), so a
//! BVH file drives it joint by joint ([`Skeleton::pose_from`]).
//!
//! Axes: y up, the figure faces +z, its left is +x.

use glam::{Affine3A, Quat, Vec3};

use super::mocap::Mocap;
use super::{Shape, ShapeKind};

/// A joint: its parent, its origin in the parent's frame at rest, and
/// the radius of the limb drawn from the parent to it.
#[derive(Debug, Clone, PartialEq)]
pub struct Joint {
    pub name: &'static str,
    pub parent: Option<usize>,
    pub offset: Vec3,
    pub radius: f32,
}

/// A skeleton: joints in order, a parent before its children.
#[derive(Debug, Clone, PartialEq)]
pub struct Skeleton {
    pub joints: Vec<Joint>,
}

/// A pose: where the root stands (its frame in the world) and each
/// joint's rotation relative to its rest orientation.
#[derive(Debug, Clone, PartialEq)]
pub struct Pose {
    pub root: Affine3A,
    pub rotations: Vec<Quat>,
}

/// The yaw rotation turning +z onto the horizontal part of `f` (the
/// identity for a vertical or zero `f`).
pub fn yaw(f: Vec3) -> Quat {
    let (x, z) = (f.x, f.z);
    if x * x + z * z < 1e-12 || !(x.is_finite() && z.is_finite()) {
        Quat::IDENTITY
    } else {
        Quat::from_rotation_y(x.atan2(z))
    }
}

/// The built-in humanoid, for a height of 1: (name, parent, offset,
/// radius). Proportions after the usual eight-heads figure.
const HUMANOID: [(&str, Option<usize>, [f32; 3], f32); 22] = [
    ("Hips", None, [0.0, 0.53, 0.0], 0.0),
    ("Spine", Some(0), [0.0, 0.07, 0.0], 0.075),
    ("Chest", Some(1), [0.0, 0.12, 0.0], 0.085),
    ("Neck", Some(2), [0.0, 0.11, 0.0], 0.05),
    ("Head", Some(3), [0.0, 0.05, 0.0], 0.025),
    ("LeftShoulder", Some(2), [0.04, 0.09, 0.0], 0.03),
    ("LeftArm", Some(5), [0.1, 0.0, 0.0], 0.035),
    ("LeftForeArm", Some(6), [0.17, 0.0, 0.0], 0.03),
    ("LeftHand", Some(7), [0.15, 0.0, 0.0], 0.025),
    ("RightShoulder", Some(2), [-0.04, 0.09, 0.0], 0.03),
    ("RightArm", Some(9), [-0.1, 0.0, 0.0], 0.035),
    ("RightForeArm", Some(10), [-0.17, 0.0, 0.0], 0.03),
    ("RightHand", Some(11), [-0.15, 0.0, 0.0], 0.025),
    ("LeftUpLeg", Some(0), [0.09, -0.02, 0.0], 0.05),
    ("LeftLeg", Some(13), [0.0, -0.245, 0.0], 0.05),
    ("LeftFoot", Some(14), [0.0, -0.235, 0.0], 0.04),
    ("LeftToe", Some(15), [0.0, -0.025, 0.1], 0.03),
    ("RightUpLeg", Some(0), [-0.09, -0.02, 0.0], 0.05),
    ("RightLeg", Some(17), [0.0, -0.245, 0.0], 0.05),
    ("RightFoot", Some(18), [0.0, -0.235, 0.0], 0.04),
    ("RightToe", Some(19), [0.0, -0.025, 0.1], 0.03),
    ("HeadTop", Some(4), [0.0, 0.12, 0.0], 0.0),
];

impl Skeleton {
    /// The built-in humanoid of `height` (from the soles to the top of
    /// the head) standing with its soles at y = 0.
    pub fn humanoid(height: f32) -> Skeleton {
        let joints = HUMANOID
            .iter()
            .map(|&(name, parent, offset, radius)| Joint {
                name,
                parent,
                offset: Vec3::from(offset) * height,
                radius: radius * height,
            })
            .collect();
        Skeleton { joints }
    }

    /// From the soles to the top of the head, standing at rest.
    pub fn height(&self) -> f32 {
        // At rest no joint turns: a joint stands at the sum of its
        // chain's offsets (parents come first).
        let mut y = Vec::with_capacity(self.joints.len());
        for j in &self.joints {
            y.push(j.parent.map_or(0.0, |p| y[p]) + j.offset.y);
        }
        y.into_iter().fold(0.0, f32::max)
    }

    /// The joint named `name`.
    pub fn joint(&self, name: &str) -> Option<usize> {
        self.joints.iter().position(|j| j.name == name)
    }

    /// The rest pose, standing at `root`.
    pub fn rest(&self, root: Affine3A) -> Pose {
        Pose {
            root,
            rotations: vec![Quat::IDENTITY; self.joints.len()],
        }
    }

    /// Each joint's frame in the world under `pose` (a joint's rotation
    /// turns its children about it).
    pub fn world(&self, pose: &Pose) -> Vec<Affine3A> {
        let mut out: Vec<Affine3A> = Vec::with_capacity(self.joints.len());
        for (k, j) in self.joints.iter().enumerate() {
            let rotation = pose.rotations.get(k).copied().unwrap_or(Quat::IDENTITY);
            let local = Affine3A::from_rotation_translation(rotation, j.offset);
            let parent = j.parent.map_or(pose.root, |p| out[p]);
            out.push(parent * local);
        }
        out
    }

    /// The body around `world` (from [`Skeleton::world`]): a capsule from
    /// each joint's parent to it, of the joint's radius, and a sphere
    /// for the head; material `material`, symbol identifiers from
    /// `symbol` on (one per joint, stable across frames).
    pub fn draw(&self, world: &[Affine3A], material: u32, symbol: u64) -> Vec<Shape> {
        let mut shapes = Vec::new();
        for (k, j) in self.joints.iter().enumerate() {
            let Some(p) = j.parent else { continue };
            let (a, b) = (world[p].translation, world[k].translation);
            let along = Vec3::from(b - a);
            let length = along.length();
            if j.radius <= 0.0 || length <= 0.0 {
                continue;
            }
            // The unit capsule lies along x: turn x onto the bone.
            let turn = Quat::from_rotation_arc(Vec3::X, along / length);
            shapes.push(Shape {
                kind: ShapeKind::Capsule {
                    length: length / j.radius,
                },
                transform: Affine3A::from_scale_rotation_translation(
                    Vec3::splat(j.radius),
                    turn,
                    a.into(),
                ),
                material,
                symbol: symbol + k as u64,
            });
        }
        // The head: an ellipsoid from the head joint to the top.
        if let (Some(head), Some(top)) = (self.joint("Head"), self.joint("HeadTop")) {
            let up = self.joints[top].offset;
            let centre = world[head].transform_point3(up * 0.5);
            let r = up.length() * 0.55;
            shapes.push(Shape {
                kind: ShapeKind::Sphere,
                transform: Affine3A::from_scale_rotation_translation(
                    Vec3::new(r * 0.85, r, r * 0.9),
                    world[head].to_scale_rotation_translation().1,
                    centre,
                ),
                material,
                symbol: symbol + self.joints.len() as u64,
            });
        }
        shapes
    }

    /// The pose of `mocap`'s frame `frame` on this skeleton: each joint
    /// takes the rotation of the file's joint of the same name (a joint
    /// the file lacks stays at rest), and the root the file's root
    /// position, scaled by the ratio of this skeleton's hip height to
    /// the file's (so a small figure takes small steps). The file's rest
    /// pose must be this skeleton's (standing, arms out): BVH rotations
    /// are relative to the file's own rest.
    pub fn pose_from(&self, mocap: &Mocap, frame: usize) -> Pose {
        let world = mocap.pose(frame);
        let rest = mocap.pose_at_rest();
        let mut rotations = vec![Quat::IDENTITY; self.joints.len()];
        for (k, j) in self.joints.iter().enumerate() {
            if let Some(m) = mocap.joints.iter().position(|mj| mj.name == j.name) {
                rotations[k] = mocap.local_rotation(frame, m);
            }
        }
        let mut root = Affine3A::IDENTITY;
        if let Some(r) = mocap.joints.iter().position(|mj| mj.parent.is_none()) {
            // The file's hip height: its root above its lowest joint or
            // end site at rest.
            let lowest = rest
                .iter()
                .zip(&mocap.joints)
                .flat_map(|(t, mj)| {
                    [
                        t.translation.y,
                        t.transform_point3(mj.end.unwrap_or(Vec3::ZERO)).y,
                    ]
                })
                .fold(f32::INFINITY, f32::min);
            let theirs = rest[r].translation.y - lowest;
            let hips = self.joints[0].offset.y;
            let scale = if theirs > 1e-6 { hips / theirs } else { 1.0 };
            let at = Vec3::from(world[r].translation) * scale;
            // The root frame carries the position; the hips' rotation is
            // the first of `rotations`.
            root = Affine3A::from_translation(at - self.joints[0].offset);
        }
        Pose { root, rotations }
    }
}
