//! Bodies that reach and walk (issue 39): the humanoid's inverse
//! kinematics meets what it is asked within reach, and the walking motor
//! plants its feet — on generated paths of random turns, speeds, stops
//! and turns on the spot, for several heights and frame rates, no stance
//! ankle of the drawn body moves more than 2 cm.

use glam::{Affine3A, Quat, Vec3};
use lmfilm::scene::body::Skeleton;
use lmfilm::scene::gait::{Stride, Walker};
use lmfilm::scene::rig::{walking_eyes, walking_under, Anchor, Targets};

/// xorshift64*, so the cases are the same on every run.
fn next(state: &mut u64) -> f32 {
    *state ^= *state >> 12;
    *state ^= *state << 25;
    *state ^= *state >> 27;
    (state.wrapping_mul(0x2545_f491_4f6c_dd1d) >> 40) as f32 / (1u64 << 24) as f32
}

fn joint(s: &Skeleton, world: &[Affine3A], name: &str) -> Vec3 {
    world[s.joint(name).unwrap()].translation.into()
}

fn bones_keep_their_length(s: &Skeleton, world: &[Affine3A]) {
    for (k, j) in s.joints.iter().enumerate() {
        if let Some(p) = j.parent {
            let bone = world[k].translation.distance(world[p].translation);
            assert!(
                (bone - j.offset.length()).abs() < 1e-4 * s.height(),
                "{}",
                j.name
            );
        }
    }
}

/// Targets drawn inside each limb's reach are met within 0.1 mm, the
/// eyes stand at their anchor, the bones keep their lengths.
#[test]
fn the_humanoid_reaches_what_is_within_reach() {
    let mut state = 0x1234_5678_9abc_def1u64;
    for case in 0..200 {
        let height = 1.0 + next(&mut state);
        let s = Skeleton::humanoid(height);
        let under = Vec3::new(next(&mut state) * 10.0, 0.0, next(&mut state));
        let facing = Quat::from_rotation_y(6.3 * next(&mut state)) * Vec3::Z;
        let eyes = walking_eyes(under, facing, height);
        assert!(walking_under(eyes, facing, height, 0.0).distance(under) < 1e-5);
        let stride = Stride::of(&s);
        let mut t = Targets::standing(Anchor::Eyes(eyes), facing);
        t.gaze = Some(eyes + Vec3::new(next(&mut state), next(&mut state), next(&mut state)) * 5.0);
        // Feet anywhere within 0.9 of the reach from under their hips
        // (the head's turn moves the hips a little).
        let hips = s.hips(&t);
        let walker = Walker::new(stride, Vec3::new(hips.x, 0.0, hips.z), facing);
        let feet = walker_feet(&walker);
        let jitter = |state: &mut u64| {
            let a = 6.3 * next(state);
            Vec3::new(a.cos(), 0.0, a.sin()) * 0.9 * stride.reach * next(state)
        };
        t.feet = [
            Some(feet[0] + jitter(&mut state)),
            Some(feet[1] + jitter(&mut state)),
        ];
        // A hand anywhere within 0.9 of the arm's length of its shoulder.
        let shoulder = joint(&s, &s.world(&s.solve(&t)), "RightArm");
        let arm = 0.32 * height;
        let dir = Vec3::new(
            next(&mut state) - 0.5,
            next(&mut state) - 0.5,
            next(&mut state) - 0.5,
        );
        let hand = shoulder + dir.normalize_or(Vec3::Z) * arm * 0.9 * next(&mut state).max(0.2);
        t.hands[1] = Some(hand);
        let world = s.world(&s.solve(&t));
        bones_keep_their_length(&s, &world);
        // The head turned to the gaze carries the eyes a little: the
        // anchor (an actor's camera) stays inside the drawn head.
        let head = s.draw(&world, 0, 0).pop().unwrap();
        let inside = head.transform.inverse().transform_point3(eyes).length();
        assert!(
            inside < 1.0,
            "case {case}: the anchor at {inside} of the head's radius"
        );
        let ahead = s.world(&s.solve(&Targets { gaze: None, ..t }));
        assert!(s.eyes(&ahead).distance(eyes) < 1e-4 * height, "case {case}");
        for (name, want) in [
            ("LeftFoot", t.feet[0]),
            ("RightFoot", t.feet[1]),
            ("RightHand", Some(hand)),
        ] {
            let got = joint(&s, &world, name);
            assert!(
                got.distance(want.unwrap()) < 1e-4,
                "case {case}: {name} {got} against {want:?}"
            );
        }
    }
}

/// The ankles of a walker standing still, from its first frame.
fn walker_feet(w: &Walker) -> [Vec3; 2] {
    w.clone().advance(0.0, Vec3::ZERO, Vec3::Z).ankles
}

/// The fastest a body turns, radians a second (a film's motor turns
/// no faster: docs/actors.md).
const TURN_RATE: f32 = lmfilm::scene::gait::TURN_RATE;

/// One generated path: way points joined at random speeds, with stops
/// and turns on the spot; the hips' ground point and facing at time t.
struct Path {
    /// (time, point, facing) keys, linearly joined.
    keys: Vec<(f64, Vec3, Vec3)>,
}

impl Path {
    fn random(state: &mut u64, height: f32) -> Path {
        let mut keys = vec![(0.0, Vec3::ZERO, Vec3::Z)];
        let (mut t, mut at, mut facing) = (0.0f64, Vec3::ZERO, Vec3::Z);
        for _ in 0..8 {
            match (next(state) * 4.0) as u32 {
                // Stand still a while.
                0 => t += 0.3 + f64::from(next(state)),
                // Turn on the spot, by up to 180°.
                1 => {
                    let turn = (next(state) - 0.5) * std::f32::consts::TAU;
                    facing = Quat::from_rotation_y(turn) * facing;
                    t += f64::from(turn.abs() / TURN_RATE) + 0.1;
                }
                // Walk somewhere, 0.3–1.4 m/s for a 1.8 m body.
                _ => {
                    let a = 6.3 * next(state);
                    let d = Vec3::new(a.cos(), 0.0, a.sin()) * (1.0 + 3.0 * next(state));
                    let speed = (0.3 + 1.1 * next(state)) * height / 1.8;
                    // Turn toward it first, at up to TURN_RATE.
                    let turn = facing.angle_between(d.normalize());
                    facing = d.normalize();
                    t += f64::from(turn / TURN_RATE) + 0.05;
                    keys.push((t, at, facing));
                    t += f64::from(d.length() / speed);
                    at += d;
                }
            }
            keys.push((t, at, facing));
        }
        Path { keys }
    }

    fn end(&self) -> f64 {
        self.keys.last().unwrap().0 + 1.0
    }

    fn at(&self, t: f64) -> (Vec3, Vec3) {
        for w in self.keys.windows(2) {
            let ((t0, p0, f0), (t1, p1, f1)) = (w[0], w[1]);
            if t <= t1 {
                let u = if t1 > t0 {
                    ((t - t0) / (t1 - t0)) as f32
                } else {
                    1.0
                };
                let f = f0.slerp(f1, u.clamp(0.0, 1.0));
                return (p0.lerp(p1, u.clamp(0.0, 1.0)), f);
            }
        }
        let (_, p, f) = *self.keys.last().unwrap();
        (p, f)
    }
}

#[test]
fn stance_feet_stay_planted_on_generated_paths() {
    let mut state = 0x0dd_ba11_cafe_f00du64;
    let mut steps = 0;
    for case in 0..100 {
        let height = 1.2 + 0.8 * next(&mut state);
        let dt = [1.0 / 24.0, 0.04, 1.0 / 30.0, 1.0 / 60.0][case % 4];
        let s = Skeleton::humanoid(height);
        let stride = Stride::of(&s);
        let path = Path::random(&mut state, height);
        let (p, f) = path.at(0.0);
        let mut walker = Walker::new(stride, p, f);
        // Where each ankle was set down, while it stands.
        let mut planted: [Option<Vec3>; 2] = [None; 2];
        let mut frame = 0u32;
        loop {
            let t = f64::from(frame) * dt;
            if t > path.end() {
                break;
            }
            let (under, facing) = path.at(t);
            let feet = walker.advance(t, under, facing);
            let eyes = walking_eyes(under, facing, height);
            let mut targets = Targets::standing(Anchor::Eyes(eyes), facing);
            targets.feet = feet.ankles.map(Some);
            targets.toes = feet.toes;
            let world = s.world(&s.solve(&targets));
            bones_keep_their_length(&s, &world);
            for (foot, name) in ["LeftFoot", "RightFoot"].into_iter().enumerate() {
                let ankle = joint(&s, &world, name);
                if feet.swinging[foot] {
                    planted[foot] = None;
                    continue;
                }
                match planted[foot] {
                    None => {
                        planted[foot] = Some(ankle);
                        steps += 1;
                    }
                    Some(p) => assert!(
                        ankle.distance(p) < 0.02,
                        "case {case} (height {height}, dt {dt}) t {t:.3}: the stance {name} slid {} m; {feet:?} hip {} reach {}",
                        ankle.distance(p), joint(&s, &world, ["LeftUpLeg", "RightUpLeg"][foot]), stride.reach
                    ),
                }
            }
            frame += 1;
        }
        // It ends standing, feet beside each other under the hips.
        let (under, facing) = path.at(path.end());
        walker.advance(path.end() + 2.0, under, facing);
        let feet = walker
            .advance(path.end() + 3.0, under, facing)
            .ankles
            .map(|a| a - Vec3::Y * stride.ankle);
        for (k, a) in feet.into_iter().enumerate() {
            let side = if k == 0 { 1.0 } else { -1.0 };
            let home = under + lmfilm::scene::rig::yaw(facing) * Vec3::X * side * stride.half_width;
            assert!(
                a.distance(home) < 0.15 * stride.reach + 1e-3,
                "case {case}: foot {k} at {a}, its place {home}"
            );
        }
    }
    assert!(steps > 400, "{steps} steps in all");
}

/// Feet and hands anywhere within the limb's reach of its root — ahead
/// along the knee's pole (a seated thigh), sideways, behind, above — are
/// met: the limb's frame is taken in the plane it bends in, never from a
/// pole along the bone.
#[test]
fn limbs_reach_in_every_direction_including_along_their_pole() {
    use lmfilm::scene::motor::{Drive, Hold, Motor};
    let mut state = 0x5eed_u64;
    // The seated referee's case: the thigh straight ahead, as the pole.
    let mut d = Drive::new(Hold::Eyes, Vec3::new(0.0, 3.0, -7.0), Vec3::Z, 0.0);
    d.height = Some(1.9);
    d.seated = true;
    d.gaze = Some(Vec3::ZERO);
    let t = Motor::new(&d).drive(&d);
    let s = Skeleton::humanoid(1.9);
    let world = s.world(&s.solve(&t));
    for (name, want) in [("LeftFoot", t.feet[0]), ("RightFoot", t.feet[1])] {
        let got = joint(&s, &world, name);
        assert!(got.distance(want.unwrap()) < 1e-4, "{name} {got} {want:?}");
    }
    for case in 0..300 {
        let s = Skeleton::humanoid(1.0 + next(&mut state));
        let facing = Quat::from_rotation_y(6.3 * next(&mut state)) * Vec3::Z;
        let mut t = Targets::standing(Anchor::Hips(Vec3::new(0.0, 1.0, 0.0)), facing);
        let rest = s.world(&s.solve(&t));
        let mut wants = Vec::new();
        for (root, end, reach, slot) in [
            ("LeftUpLeg", "LeftFoot", 0.48, 0),
            ("RightUpLeg", "RightFoot", 0.48, 1),
            ("LeftArm", "LeftHand", 0.32, 2),
            ("RightArm", "RightHand", 0.32, 3),
        ] {
            // Along the pole itself in one case of four.
            let dir = if case % 4 == 0 {
                facing
            } else {
                Vec3::new(
                    next(&mut state) - 0.5,
                    next(&mut state) - 0.5,
                    next(&mut state) - 0.5,
                )
                .normalize_or(Vec3::Z)
            };
            let length = reach * s.height() * (0.2 + 0.75 * next(&mut state));
            let want = joint(&s, &rest, root) + dir * length;
            match slot {
                0 | 1 => t.feet[slot] = Some(want),
                _ => t.hands[slot - 2] = Some(want),
            }
            wants.push((end, want));
        }
        let world = s.world(&s.solve(&t));
        bones_keep_their_length(&s, &world);
        for (end, want) in wants {
            let got = joint(&s, &world, end);
            assert!(
                got.distance(want) < 1e-3 * s.height(),
                "case {case}: {end} {got} against {want}"
            );
        }
    }
}
