//! Articulated bodies (issue 39): the built-in humanoid's proportions,
//! bone lengths that no pose changes, capsules that meet at the joints,
//! and a BVH file driving it joint by joint.

use glam::{Affine3A, Quat, Vec3};
use lmfilm::scene::body::Skeleton;
use lmfilm::scene::mocap::Mocap;
use lmfilm::scene::ShapeKind;

/// xorshift64*, so the poses are the same on every run.
fn next(state: &mut u64) -> f32 {
    *state ^= *state >> 12;
    *state ^= *state << 25;
    *state ^= *state >> 27;
    (state.wrapping_mul(0x2545_f491_4f6c_dd1d) >> 40) as f32 / (1u64 << 24) as f32
}

#[test]
fn the_humanoid_stands_its_height_on_its_soles() {
    for height in [0.5f32, 1.8, 2.1] {
        let s = Skeleton::humanoid(height);
        assert_eq!(s.joints.len(), 22);
        let world = s.world(&s.rest(Affine3A::IDENTITY));
        let at = |name: &str| Vec3::from(world[s.joint(name).unwrap()].translation);
        assert!((at("HeadTop").y - height).abs() < 1e-5 * height);
        for toe in ["LeftToe", "RightToe"] {
            assert!(at(toe).y.abs() < 0.01 * height, "{toe} {}", at(toe));
        }
        // Left is +x, the arms out to the sides at rest.
        assert!(at("LeftHand").x > 0.35 * height && at("RightHand").x < -0.35 * height);
    }
}

#[test]
fn any_pose_keeps_the_bones_and_the_capsules_meet_at_the_joints() {
    let s = Skeleton::humanoid(1.8);
    let mut state = 0x9e37_79b9_7f4a_7c15u64;
    for _ in 0..50 {
        let mut pose = s.rest(Affine3A::from_rotation_translation(
            Quat::from_rotation_y(6.0 * next(&mut state)),
            Vec3::new(next(&mut state), 0.0, next(&mut state)) * 10.0,
        ));
        for r in &mut pose.rotations {
            let axis = Vec3::new(next(&mut state), next(&mut state), next(&mut state)) - 0.5;
            *r = Quat::from_axis_angle(axis.normalize_or(Vec3::Y), 3.0 * next(&mut state));
        }
        let world = s.world(&pose);
        for (k, j) in s.joints.iter().enumerate() {
            if let Some(p) = j.parent {
                let bone = world[k].translation.distance(world[p].translation);
                assert!((bone - j.offset.length()).abs() < 1e-5, "{}", j.name);
            }
        }
        for shape in s.draw(&world, 3, 100) {
            let ShapeKind::Capsule { length } = shape.kind else {
                continue;
            };
            let k = (shape.symbol - 100) as usize;
            let p = s.joints[k].parent.unwrap();
            let start = shape.transform.transform_point3(Vec3::ZERO);
            let end = shape
                .transform
                .transform_point3(Vec3::new(length, 0.0, 0.0));
            assert!(start.distance(world[p].translation.into()) < 1e-4);
            assert!(
                end.distance(world[k].translation.into()) < 1e-4,
                "{}",
                s.joints[k].name
            );
        }
    }
}

/// `scripts/make_mocap.py`'s file drives the humanoid: its right upper
/// arm points where the file's does, the hips stand where the file's
/// root stands (the file has no legs: its hip height is the root's).
#[test]
fn a_bvh_file_drives_the_humanoid_joint_by_joint() {
    let wave = include_str!("../../scenes/mocap/wave.bvh");
    let m = Mocap::parse(&lmfilm::source::Source::new("wave.bvh", wave)).unwrap();
    let s = Skeleton::humanoid(1.8);
    let (file_arm, file_fore) = (
        m.joints.iter().position(|j| j.name == "RightArm").unwrap(),
        m.joints
            .iter()
            .position(|j| j.name == "RightForeArm")
            .unwrap(),
    );
    for frame in [0, 7, 20, 29] {
        let theirs = m.pose(frame);
        let ours = s.world(&s.pose_from(&m, frame));
        let dir = |w: &[Affine3A], a: usize, b: usize| {
            Vec3::from(w[b].translation - w[a].translation).normalize()
        };
        let want = dir(&theirs, file_arm, file_fore);
        let got = dir(
            &ours,
            s.joint("RightArm").unwrap(),
            s.joint("RightForeArm").unwrap(),
        );
        assert!(
            got.distance(want) < 1e-5,
            "frame {frame}: {got} against {want}"
        );
        let hips = Vec3::from(ours[0].translation);
        assert!(
            hips.distance(theirs[0].translation.into()) < 1e-5,
            "frame {frame}"
        );
    }
}

/// `D` par1 = 50 in a scene: the humanoid stands along the turtle's H
/// (after `+(90)`, up), posed by the `fig_bvh` motion at the frame's
/// time; each bone keeps its symbol across frames, so motion blur finds
/// what moved; an undeclared motion is the rest pose, with a warning.
#[test]
fn a_scene_draws_bodies_posed_by_their_motion() {
    use lmfilm::render::motion::Motion;
    let text = |motion: u32| {
        format!(
            "Camera_AnimationParameters\nt_final_interval 1 0.0333333\n\
             Surfaces\nfig_bvh 1 scenes/mocap/wave.bvh\n\
             Axiom\nf () () () (2) (3) + () () () () (90) D () (50) () () ({motion}) (1.8)\n"
        )
    };
    let mut rest = crate::common::from_text(&text(0));
    let (scene, warnings) = crate::common::scene(&mut rest);
    assert!(warnings.is_empty(), "{warnings:?}");
    let shapes = &scene.geometries[0].shapes;
    assert_eq!(shapes.len(), 21, "20 limbs and a head");
    let top = shapes
        .iter()
        .map(|s| lmfilm::render::accel::shapes::bounds(s).unwrap().max.y)
        .fold(f32::MIN, f32::max);
    assert!((top - 1.8).abs() < 0.02, "the head's top at {top}");
    let mut moving = crate::common::from_text(&text(1));
    let (a, _) = crate::common::scene(&mut moving);
    moving.advance_to(10, &mut lmfilm::lsys::NoSensors).unwrap();
    let (b, _) = crate::common::scene(&mut moving);
    let motion = Motion::between(&a, &b, 1.0);
    let moved = motion.shapes[0].iter().flatten().count();
    assert!(moved >= 10, "{moved} of 21 bones move with the motion");
    let mut missing = crate::common::from_text(&text(7));
    let (_, warnings) = crate::common::scene(&mut missing);
    assert!(
        warnings.iter().any(|w| w.contains("motion 7")),
        "{warnings:?}"
    );
}

/// A body beyond the coordinates a scene may hold is skipped with a
/// warning, as any shape is; an absurd height is held to 1,000 m.
#[test]
fn a_body_out_of_bounds_is_skipped_with_a_warning() {
    let far = "Camera_AnimationParameters\nt_final_interval 1 0.04\n\
        Axiom\nf () () () (2) (10000000000000000) D () (50) () () (0) (100000000000000000000)\n";
    let mut a = crate::common::from_text(far);
    let (scene, warnings) = crate::common::scene(&mut a);
    assert!(scene.geometries[0].shapes.is_empty());
    assert!(warnings.iter().any(|w| w.contains("body")), "{warnings:?}");
}

/// A figure of the user's own (`D` 52 places a body undrawn, `D` 51
/// takes the turtle to its joints): what the word draws at a joint is
/// where the built-in body's joint is, and a capsule drawn from a joint
/// along H of the bone's length ends at the next joint.
#[test]
fn a_word_draws_its_own_figure_at_the_joints() {
    let text = "Camera_AnimationParameters\nt_final_interval 1 0.04\n\
        Axiom\nf () () () (2) (3) + () () () () (90) & () () () () (20)\n\
        D () (50) () () (0) (1.8)\n\
        D () (52) () () (0) (1.8)\n\
        [ D () (51) () () (15) m () (4) a () () () () (0.05) ]\n\
        [ D () (51) () () (13) m () (5) O () () () () (0.441) (0.05) (0.05) ]\n\
        D () (51) () () (99)\n";
    let mut a = crate::common::from_text(text);
    let (scene, warnings) = crate::common::scene(&mut a);
    assert!(
        warnings.iter().any(|w| w.contains("joint 99")),
        "{warnings:?}"
    );
    let shapes = &scene.geometries[0].shapes;
    // The built-in body's bones: the capsule ending at joint k is bone k.
    let joint = |k: u64| {
        let s = shapes.iter().find(|s| s.symbol >> 48 == k + 1).unwrap();
        let ShapeKind::Capsule { length } = s.kind else {
            panic!("bone {k}")
        };
        s.transform.transform_point3(Vec3::new(length, 0.0, 0.0))
    };
    let own = |material: u32| shapes.iter().find(|s| s.material == material).unwrap();
    let foot = own(4).transform.transform_point3(Vec3::ZERO);
    assert!(foot.distance(joint(15)) < 1e-4, "{foot} {}", joint(15));
    let thigh = own(5);
    let ShapeKind::Capsule { length } = thigh.kind else {
        panic!("a capsule")
    };
    let end = thigh
        .transform
        .transform_point3(Vec3::new(length, 0.0, 0.0));
    assert!(end.distance(joint(14)) < 1e-3, "{end} {}", joint(14));
    // 21 bones of the drawn body, one sphere, one capsule: the undrawn
    // body adds nothing.
    assert_eq!(shapes.len(), 23);
}
