//! The motor of a body held by the turtle (issue 39): from where the
//! turtle holds it each frame — its eyes (an actor's camera), its right
//! hand (a racket's grip) or its hips' point on the ground (a path, a
//! trajectory) — and what its actor gives it (the gaze, the body's
//! direction, the footholds its feet stand on), the pose of the frame.
//! It keeps what a body carries from frame to frame: its walking motor
//! ([`Walker`]), where its hips face and, when a hand leads, where they
//! stand. A film keeps one motor per body; a fresh motor gives the pose
//! of a body that has just appeared.

use glam::{Quat, Vec3};

use super::body::Skeleton;
use super::gait::{Feet, Stride, Walker, CROUCH, TURN_RATE};
use super::rig::{yaw, Anchor, Targets, EYES, MAX_TWIST};

/// Which point of the body the turtle holds (`D` par1 = 50, par6).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Hold {
    /// Its eyes at the turtle: it walks below them.
    Eyes,
    /// Its right wrist at the turtle: it follows what it holds.
    Hand,
    /// Its hips over the turtle's point, which is on the ground.
    Ground,
}

/// What drives a body this frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Drive {
    pub hold: Hold,
    /// The turtle's point and heading (H).
    pub at: Vec3,
    pub heading: Vec3,
    pub time: f64,
    /// Its height; None sizes a body held by its eyes so that it stands
    /// them over the ground (1.8 otherwise).
    pub height: Option<f32>,
    /// Seated (its legs forward and down, its hips where they are).
    pub seated: bool,
    /// From its actor: what it looks at, the ground it walks on, where
    /// its body faces (else the gaze's, else the turtle's heading) and,
    /// walking on footholds, its soles' points now and which are in the
    /// air.
    pub gaze: Option<Vec3>,
    pub ground: f32,
    pub facing: Option<Vec3>,
    pub soles: Option<([Vec3; 2], [bool; 2])>,
}

impl Drive {
    /// Held at `at`, heading `heading`, at time `time`; nothing more known.
    pub fn new(hold: Hold, at: Vec3, heading: Vec3, time: f64) -> Drive {
        Drive {
            hold,
            at,
            heading,
            time,
            height: None,
            seated: false,
            gaze: None,
            ground: 0.0,
            facing: None,
            soles: None,
        }
    }
}

/// The default height of a body, metres.
pub const DEFAULT_HEIGHT: f32 = 1.8;
/// The height range a body may take.
const HEIGHTS: std::ops::RangeInclusive<f32> = 0.05..=1000.0;
/// Where the right wrist is, seen from above, against the hips in a
/// ready stance (for a height of 1: right and a little forward, the arm
/// hanging forward within reach).
const GRIP: Vec3 = Vec3::new(-0.17, 0.0, 0.1);
/// How quickly hips led by a hand follow it (seconds to close most of
/// the way), how low they may crouch for a low hand and how high they
/// may rise for a high one, off the ground (of the height).
const FOLLOW: f32 = 0.2;
const MOST_CROUCH: f32 = 0.2;
const MOST_RISE: f32 = 0.35;

/// A body's motor, from frame to frame.
#[derive(Debug, Clone, PartialEq)]
pub struct Motor {
    skeleton: Skeleton,
    /// The skeleton's stride (what the walking motor steps with).
    stride: Stride,
    walker: Option<Walker>,
    /// Where its soles stood last frame, when its actor placed them.
    soles: Option<[Vec3; 2]>,
    facing: Vec3,
    /// The hips' point on the ground and how much lower than walking they
    /// crouch, when a hand leads.
    led: Option<(Vec3, f32)>,
    time: f64,
}

/// The horizontal part of `v`, normalised; None when vertical or zero.
fn level(v: Vec3) -> Option<Vec3> {
    Vec3::new(v.x, 0.0, v.z).try_normalize()
}

impl Motor {
    /// The motor of a body first driven by `d`.
    pub fn new(d: &Drive) -> Motor {
        let height = match (d.height, d.hold) {
            (Some(h), _) => h,
            (None, Hold::Eyes) if !d.seated => (d.at.y - d.ground) / (EYES.y - CROUCH),
            _ => DEFAULT_HEIGHT,
        };
        let height = if height.is_finite() {
            height.clamp(*HEIGHTS.start(), *HEIGHTS.end())
        } else {
            DEFAULT_HEIGHT
        };
        let skeleton = Skeleton::humanoid(height);
        Motor {
            stride: Stride::of(&skeleton),
            skeleton,
            walker: None,
            soles: None,
            facing: Self::wanted_facing(d, d.at).unwrap_or(Vec3::Z),
            led: None,
            time: d.time,
        }
    }

    /// The time it was last driven at.
    pub fn time(&self) -> f64 {
        self.time
    }

    /// The skeleton it moves.
    pub fn skeleton(&self) -> &Skeleton {
        &self.skeleton
    }

    /// Where the body would face: its actor's body direction, else
    /// toward what it looks at from `from`, else the turtle's heading.
    fn wanted_facing(d: &Drive, from: Vec3) -> Option<Vec3> {
        d.facing
            .and_then(level)
            .or_else(|| d.gaze.and_then(|g| level(g - from)))
            .or_else(|| level(d.heading))
    }

    /// The pose targets of the frame `d` drives (times must not go back).
    pub fn drive(&mut self, d: &Drive) -> Targets {
        let dt = (d.time - self.time).max(0.0) as f32;
        self.time = d.time;
        let height = self.skeleton.height();
        let from = self.led.map_or(d.at, |(p, _)| p);
        // Seated, the hips keep facing where they first faced.
        let want = Self::wanted_facing(d, from).filter(|_| !d.seated);
        if let Some(want) = want {
            // The hips turn toward it, no faster than the feet follow.
            let (a, b) = (self.facing, want);
            let angle = a.cross(b).y.atan2(a.dot(b));
            let most = TURN_RATE * dt;
            let turn = if self.walker.is_none() {
                angle
            } else {
                angle.clamp(-most, most)
            };
            self.facing = (Quat::from_rotation_y(turn) * a).normalize();
        }
        let mut t = Targets::standing(Anchor::Eyes(d.at), self.facing);
        t.gaze = d.gaze;
        match d.hold {
            Hold::Eyes => {}
            Hold::Ground => {
                let hips = self.skeleton.joints[0].offset.y - CROUCH * height;
                t.anchor = Anchor::Hips(Vec3::new(d.at.x, d.at.y + hips, d.at.z));
            }
            Hold::Hand => self.lead(d, &mut t, dt),
        }
        let hips = self.skeleton.hips(&t);
        if d.seated {
            // Thighs forward, shins down: the feet under the knees.
            let turn = yaw(self.facing);
            let thigh = self.skeleton.joints[14].offset.length();
            let shin = self.skeleton.joints[15].offset.length();
            let width = self.skeleton.joints[13].offset.x;
            t.feet = [1.0, -1.0].map(|side| {
                Some(hips + turn * Vec3::new(side * width, -0.02 * height - shin, thigh))
            });
            return t;
        }
        let under = Vec3::new(hips.x, d.ground, hips.z);
        let feet = match d.soles {
            Some((soles, swinging)) => {
                self.walker = None;
                self.soles = Some(soles);
                Feet {
                    ankles: soles.map(|s| s + Vec3::Y * self.stride.ankle),
                    toes: [self.facing; 2],
                    swinging,
                }
            }
            None => {
                // The motor takes over from where the feet stand.
                let soles = self.soles.take();
                let (stride, facing) = (self.stride, self.facing);
                let walker = self.walker.get_or_insert_with(|| match soles {
                    Some(soles) => Walker::standing_on(stride, soles, [facing; 2]),
                    None => Walker::new(stride, under, facing),
                });
                walker.advance(d.time, under, self.facing)
            }
        };
        // A hand that lifts the hips off the ground lifts the feet too
        // (a jump).
        let jump = self.led.map_or(0.0, |(_, crouch)| (-crouch).max(0.0));
        t.feet = feet.ankles.map(|a| Some(a + Vec3::Y * jump));
        t.toes = feet.toes;
        t.standing = feet.swinging.map(|s| !s && jump == 0.0);
        // The arms swing against the legs: each forward as the other
        // side's foot is.
        let reach = self.stride.reach.max(1e-6);
        let ahead = |f: usize| (feet.ankles[f] - hips).dot(yaw(self.facing) * Vec3::Z) / reach;
        t.arm_swing = [0.35 * ahead(1), 0.35 * ahead(0)];
        t
    }

    /// A right hand held at `d.at` leads the hips: they follow it to a
    /// ready stance beside it, lower, higher (a jump) or nearer when it
    /// would be out of the arm's reach, and the chest turns toward it.
    fn lead(&mut self, d: &Drive, t: &mut Targets, dt: f32) {
        let s = &self.skeleton;
        let height = s.height();
        let turn = yaw(self.facing);
        let mut wanted = d.at - turn * GRIP * height;
        wanted.y = d.ground;
        let (mut under, mut crouch) = self.led.unwrap_or((wanted, 0.0));
        let k = if dt > 0.0 {
            1.0 - (-dt / FOLLOW).exp()
        } else {
            0.0
        };
        under += (wanted - under) * k;
        under.y = d.ground;
        // Back up (or down) when the hand no longer needs it.
        crouch *= 1.0 - k;
        let walking = s.joints[0].offset.y - CROUCH * height;
        let arm = (s.joints[11].offset.length() + s.joints[12].offset.length()) * 0.97;
        for _ in 0..6 {
            t.anchor = Anchor::Hips(under + Vec3::Y * (walking - crouch));
            t.twist = self.twist(d.at, under);
            let world = s.world(&s.solve(t));
            let shoulder = Vec3::from(world[10].translation);
            let gap = d.at - shoulder;
            if gap.length() <= arm {
                break;
            }
            // Nearer along the ground while that is enough; higher or
            // lower first when the hand is beyond reach above or below.
            let level = Vec3::new(gap.x, 0.0, gap.z);
            let room = arm * arm - gap.y * gap.y;
            if room > (0.3 * arm).powi(2) {
                let go = level.length() - room.sqrt();
                under += level.normalize_or_zero() * go;
            } else {
                let want = gap.y.signum() * 0.9 * arm;
                crouch = (crouch - (gap.y - want)).clamp(-MOST_RISE * height, MOST_CROUCH * height);
            }
        }
        self.led = Some((under, crouch));
        t.anchor = Anchor::Hips(under + Vec3::Y * (walking - crouch));
        t.twist = self.twist(d.at, under);
        t.hands[1] = Some(d.at);
    }

    /// The chest's turn that brings the right shoulder round toward a
    /// hand at `hand`, the hips over `under`.
    fn twist(&self, hand: Vec3, under: Vec3) -> f32 {
        let local = yaw(self.facing).inverse() * (hand - under);
        let now = local.x.atan2(local.z);
        let ready = GRIP.x.atan2(GRIP.z);
        let turn = (now - ready + std::f32::consts::PI).rem_euclid(std::f32::consts::TAU)
            - std::f32::consts::PI;
        turn.clamp(-MAX_TWIST, MAX_TWIST)
    }
}
