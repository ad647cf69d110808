//! A walking motor (issue 39; the thesis's AGENTlib bodies had one):
//! where a humanoid's feet are while its hips follow a path. Each frame
//! the motor is told where the hips are over the ground and where the
//! body faces; a foot stands where it was set down until the motor lifts
//! it, and one foot at a time steps to where it will be under its hip
//! half a stride ahead. The stride and the cadence follow the speed, a
//! body that turns without moving steps round on the spot, and a body
//! that stops brings its feet back side by side. A stance foot never
//! moves: its ankle is where it was set down until it lifts.

use glam::Vec3;

use super::body::{yaw, Skeleton};

/// A foot in the air: from where, to where, how far along (0 to 1) and
/// how fast (per second; a stance foot nearing its reach hurries it).
#[derive(Debug, Clone, Copy, PartialEq)]
struct Swing {
    foot: usize,
    from: Vec3,
    to: Vec3,
    from_toes: Vec3,
    to_toes: Vec3,
    progress: f64,
    rate: f64,
}

/// The feet of one frame: each ankle's point, where its toes point and
/// whether it is in the air (`[left, right]`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Feet {
    pub ankles: [Vec3; 2],
    pub toes: [Vec3; 2],
    pub swinging: [bool; 2],
}

/// The sizes the motor steps with, from the skeleton.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Stride {
    /// Half the distance between the hip joints: each foot's place
    /// beside the body's middle.
    pub half_width: f32,
    /// The ankle joint over the sole.
    pub ankle: f32,
    /// The farthest a stance foot may be from under its hip, along the
    /// ground, with the hips [`CROUCH`] lower than the straight legs.
    pub reach: f32,
    /// How high a swinging foot lifts.
    pub lift: f32,
}

/// How much lower than the straight-legged stance the hips walk, as a
/// fraction of the height: the knees' bend that lets a foot reach ahead
/// and behind.
pub const CROUCH: f32 = 0.025;
/// The time one step takes when walking slowly or turning, and the
/// shortest, seconds.
const SLOW_STEP: f64 = 0.4;
const QUICK_STEP: f64 = 0.12;
/// The time a step's length takes to walk at a comfortable cadence.
const CADENCE: f32 = 0.5;
/// The fastest a body turns about the vertical, radians a second: its
/// feet step round that fast (a motor holds the hips' turn to it).
pub const TURN_RATE: f32 = 3.0;
/// How far ahead, and in what steps, a standing foot's room is looked
/// for, seconds.
const LOOK_AHEAD: f64 = 1.0;
const ROOM_STEP: f64 = 0.02;
/// A foot that points this far (radians) from the body steps round.
const TURN_STEP: f32 = 0.45;

impl Stride {
    /// The stride of `skeleton` (the built-in humanoid).
    pub fn of(skeleton: &Skeleton) -> Stride {
        let height = skeleton.height();
        let j = |name: &str| skeleton.joint(name).expect("the humanoid's joints");
        let leg = skeleton.joints[j("LeftLeg")].offset.length()
            + skeleton.joints[j("LeftFoot")].offset.length();
        let rest = skeleton.rest(glam::Affine3A::IDENTITY);
        let world = skeleton.world(&rest);
        let ankle = world[j("LeftFoot")].translation.y;
        let bent = leg - CROUCH * height;
        Stride {
            half_width: world[j("LeftUpLeg")].translation.x.abs(),
            ankle,
            reach: (leg * leg - bent * bent).max(0.0).sqrt(),
            lift: 0.06 * height,
        }
    }

    /// The longest step it takes: from a reach behind to a reach ahead,
    /// with a margin.
    pub fn longest(&self) -> f32 {
        1.7 * self.reach
    }
}

/// The motor of one body, carried from frame to frame.
#[derive(Debug, Clone, PartialEq)]
pub struct Walker {
    stride: Stride,
    /// Where each foot stands (its sole's point under the ankle, on the
    /// ground) and where its toes point.
    feet: [Vec3; 2],
    toes: [Vec3; 2],
    /// Each foot's step under way: one at a time when walking, both in
    /// the air a moment when the body runs faster than steps follow.
    swings: [Option<Swing>; 2],
    /// The hips' point on the ground and the time, last frame.
    last: Option<(f64, Vec3)>,
    velocity: Vec3,
    /// The facing last frame and how fast it turns (radians a second,
    /// counter-clockwise seen from above).
    facing: Vec3,
    turning: f32,
}

/// `v` on the ground plane.
fn flat(v: Vec3) -> Vec3 {
    Vec3::new(v.x, 0.0, v.z)
}

/// The unsigned angle between two horizontal directions.
fn angle(a: Vec3, b: Vec3) -> f32 {
    let (a, b) = (flat(a).normalize_or_zero(), flat(b).normalize_or_zero());
    if a == Vec3::ZERO || b == Vec3::ZERO {
        return 0.0;
    }
    a.dot(b).clamp(-1.0, 1.0).acos()
}

impl Walker {
    /// Standing with its feet side by side about `under` (the hips'
    /// point on the ground), facing `facing`.
    pub fn new(stride: Stride, under: Vec3, facing: Vec3) -> Walker {
        let mut w = Walker {
            stride,
            feet: [Vec3::ZERO; 2],
            toes: [facing; 2],
            swings: [None; 2],
            last: None,
            velocity: Vec3::ZERO,
            facing,
            turning: 0.0,
        };
        w.feet = [0, 1].map(|f| w.home(f, under, facing));
        w
    }

    /// Standing on `soles` (each sole's point on the ground), toes along
    /// `toes`: a body whose feet something else placed until now.
    pub fn standing_on(stride: Stride, soles: [Vec3; 2], toes: [Vec3; 2]) -> Walker {
        let facing = (toes[0] + toes[1]).try_normalize().unwrap_or(Vec3::Z);
        Walker {
            feet: soles,
            toes,
            ..Walker::new(stride, soles[0].midpoint(soles[1]), facing)
        }
    }

    /// Where foot `foot` stands when the body stands at `under` facing
    /// `facing`: beside the middle, left (+x of the figure) first.
    fn home(&self, foot: usize, under: Vec3, facing: Vec3) -> Vec3 {
        let side = if foot == 0 { 1.0 } else { -1.0 };
        under + yaw(facing) * Vec3::new(side * self.stride.half_width, 0.0, 0.0)
    }

    /// The feet at `time`, the hips now over `under` (on the ground: its
    /// y is the ground's) facing `facing`. Times must not go back.
    pub fn advance(&mut self, time: f64, under: Vec3, facing: Vec3) -> Feet {
        let mut dt = 0.0;
        if let Some((t0, p0)) = self.last {
            dt = (time - t0).max(0.0);
            if flat(under - p0).length() > 2.0 * self.stride.reach {
                // A jump no leg follows (the body placed elsewhere): it
                // stands there afresh.
                *self = Walker::new(self.stride, under, facing);
            } else if dt > 1e-9 {
                let v = flat(under - p0) / dt as f32;
                // Smoothed over a few frames: a planned path's corners
                // do not throw the feet.
                self.velocity = self.velocity.lerp(v, 0.5);
                let (a, b) = (flat(self.facing), flat(facing));
                let turn = a.cross(b).y.atan2(a.dot(b));
                self.turning = self.turning + (turn / dt as f32 - self.turning) * 0.5;
            }
        }
        self.last = Some((time, under));
        self.facing = facing;
        for foot in 0..2 {
            let Some(mut s) = self.swings[foot] else {
                continue;
            };
            s.rate = s.rate.max(self.hurry(&s, under, facing));
            s.progress += dt * s.rate;
            if s.progress >= 1.0 {
                self.feet[foot] = s.to;
                self.toes[foot] = s.to_toes;
                self.swings[foot] = None;
                continue;
            }
            // The landing follows the body (the foot is in the air).
            let left = (1.0 - s.progress) / s.rate;
            (s.to, s.to_toes) = self.landing(foot, under, facing, left);
            self.swings[foot] = Some(s);
        }
        self.maybe_step(under, facing);
        // A standing foot the body has left beyond its reach this frame (a
        // start faster than any step) is lifted at once: it never slides.
        for foot in 0..2 {
            let off = flat(self.feet[foot] - self.home(foot, under, facing)).length();
            if self.swings[foot].is_none() && off > self.stride.reach {
                self.lift(foot, under, facing, QUICK_STEP);
            }
        }
        self.feet_now()
    }

    /// How long the body may go on at its present speed and turn before
    /// foot `foot`, standing, is out of its leg's reach (seconds, up to
    /// [`LOOK_AHEAD`]).
    fn room(&self, foot: usize, under: Vec3, facing: Vec3) -> f64 {
        let most = 0.97 * self.stride.reach;
        let steps = (LOOK_AHEAD / ROOM_STEP) as u32;
        for k in 1..=steps {
            let t = f64::from(k) * ROOM_STEP;
            let turned = glam::Quat::from_rotation_y(self.turning * t as f32) * facing;
            let hip = self.home(foot, under + self.velocity * t as f32, turned);
            if flat(self.feet[foot] - hip).length() > most {
                return t - ROOM_STEP;
            }
        }
        LOOK_AHEAD
    }

    /// The rate at which the swing `s` must go on to land before the
    /// other foot, standing meanwhile, is out of reach.
    fn hurry(&self, s: &Swing, under: Vec3, facing: Vec3) -> f64 {
        if self.swings[1 - s.foot].is_some() {
            return 0.0;
        }
        let time = self.room(1 - s.foot, under, facing);
        (1.0 - s.progress) / time.max(QUICK_STEP * 0.5)
    }

    /// Where foot `foot` lands `left` seconds from now: under its hip
    /// then, half a stride ahead along the body's motion.
    fn landing(&self, foot: usize, under: Vec3, facing: Vec3, left: f64) -> (Vec3, Vec3) {
        let step = self.step_length();
        let v = self.velocity;
        let ahead = v.normalize_or_zero() * (0.5 * step);
        let hip = self.home(foot, under + v * left as f32, facing);
        let mut to = hip + ahead;
        // Never beyond what the leg reaches from where the hips will be.
        let off = flat(to - hip);
        let most = 0.95 * self.stride.reach;
        if off.length() > most {
            to = hip + off.normalize() * most;
        }
        to.y = under.y;
        (to, flat(facing).normalize_or_zero())
    }

    /// The step length at the present speed: a comfortable cadence, no
    /// longer than the legs allow.
    fn step_length(&self) -> f32 {
        (self.velocity.length() * CADENCE).min(self.stride.longest())
    }

    /// Lifts the foot farthest from its place, when it is far enough
    /// and the other stands; lifts a standing foot about to be out of
    /// reach before the other lands too (a run).
    fn maybe_step(&mut self, under: Vec3, facing: Vec3) {
        let speed = self.velocity.length();
        let step = self.step_length();
        // Moving, a foot goes when it is half a step behind; standing,
        // when it is off its place by a tenth of the reach (the feet
        // come together after a stop).
        let trigger = if speed > 0.05 {
            (0.5 * step).max(0.1 * self.stride.reach)
        } else {
            0.1 * self.stride.reach
        };
        let need = |f: usize| {
            let off = flat(self.feet[f] - self.home(f, under, facing)).length() / trigger;
            let turn = angle(self.toes[f], facing) / TURN_STEP;
            off.max(turn)
        };
        let foot = match self.swings {
            [None, None] => {
                let (n0, n1) = (need(0), need(1));
                let foot = usize::from(n1 > n0);
                if n0.max(n1) < 1.0 {
                    return;
                }
                foot
            }
            [Some(s), None] | [None, Some(s)] => {
                let standing = 1 - s.foot;
                let landing = (1.0 - s.progress) / s.rate;
                if self.room(standing, under, facing) > landing + QUICK_STEP * 0.5 {
                    return;
                }
                standing
            }
            [Some(_), Some(_)] => return,
        };
        let duration = if speed > 0.05 {
            (0.8 * f64::from(step / speed)).clamp(QUICK_STEP, SLOW_STEP)
        } else {
            SLOW_STEP
        };
        self.lift(foot, under, facing, duration);
    }

    /// Starts a step of `foot` taking `duration` seconds.
    fn lift(&mut self, foot: usize, under: Vec3, facing: Vec3, duration: f64) {
        let (to, to_toes) = self.landing(foot, under, facing, duration);
        self.swings[foot] = Some(Swing {
            foot,
            from: self.feet[foot],
            to,
            from_toes: self.toes[foot],
            to_toes,
            progress: 0.0,
            rate: 1.0 / duration,
        });
    }

    /// The ankles now: a standing foot where it stands, a swinging one
    /// along a smooth arc from where it left to where it lands.
    fn feet_now(&self) -> Feet {
        let up = Vec3::Y * self.stride.ankle;
        let mut ankles = self.feet.map(|f| f + up);
        let mut toes = self.toes;
        for s in self.swings.iter().flatten() {
            let u = s.progress.clamp(0.0, 1.0) as f32;
            let smooth = u * u * (3.0 - 2.0 * u);
            let mut p = s.from.lerp(s.to, smooth);
            p.y += self.stride.lift * (std::f32::consts::PI * u).sin();
            ankles[s.foot] = p + up;
            toes[s.foot] = s.from_toes.lerp(s.to_toes, smooth);
        }
        Feet {
            ankles,
            toes,
            swinging: self.swings.map(|s| s.is_some()),
        }
    }
}
