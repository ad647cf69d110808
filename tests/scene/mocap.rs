//! The Biovision BVH reader (issue 39): the pose of a file made by
//! `scripts/make_mocap.py` at known frames against forward kinematics
//! written out here with rotation matrices in f64, and hostile files
//! refused with a located error.

use glam::{DVec3, Vec3};
use lmfilm::scene::mocap::Mocap;
use lmfilm::source::{Diagnostic, Source};

/// `text` read as the file `wave.bvh`.
fn parse(text: &str) -> Result<Mocap, Diagnostic> {
    Mocap::parse(&Source::new("wave.bvh", text))
}

const WAVE: &str = include_str!("../../scenes/mocap/wave.bvh");

fn rx(a: f64, v: DVec3) -> DVec3 {
    let (s, c) = a.to_radians().sin_cos();
    DVec3::new(v.x, c * v.y - s * v.z, s * v.y + c * v.z)
}

fn ry(a: f64, v: DVec3) -> DVec3 {
    let (s, c) = a.to_radians().sin_cos();
    DVec3::new(c * v.x + s * v.z, v.y, -s * v.x + c * v.z)
}

fn rz(a: f64, v: DVec3) -> DVec3 {
    let (s, c) = a.to_radians().sin_cos();
    DVec3::new(c * v.x - s * v.y, s * v.x + c * v.y, v.z)
}

/// The hand tip at frame k, as the script's docstring defines the motion.
fn hand_tip(k: f64) -> DVec3 {
    let (shoulder_z, shoulder_x, elbow_z, hips_y) = (3.0 * k, k, 2.0 * k, 3.0 * k);
    let hand = DVec3::new(-0.25, 0.0, 0.0) + DVec3::new(-0.1, 0.0, 0.0);
    let from_elbow = rz(elbow_z, hand);
    // Shoulder channels listed Z then X: R = Rz·Rx.
    let from_shoulder = rz(
        shoulder_z,
        rx(shoulder_x, DVec3::new(-0.3, 0.0, 0.0) + from_elbow),
    );
    let in_hips = DVec3::new(0.0, 0.2, 0.0) + DVec3::new(-0.2, 0.3, 0.0) + from_shoulder;
    DVec3::new(0.5 * k / 30.0, 1.0, 0.0) + ry(hips_y, in_hips)
}

#[test]
fn the_pose_at_a_frame_is_the_files_motion() {
    let m = parse(WAVE).unwrap();
    assert_eq!(m.joints.len(), 6);
    assert_eq!(m.frame_count(), 30);
    assert!((m.frame_time - 1.0 / 30.0).abs() < 1e-7);
    let wrist = m.joints.iter().position(|j| j.name == "RightHand").unwrap();
    let tip = m.joints[wrist].end.unwrap();
    for k in [0usize, 1, 10, 17, 29] {
        let pose = m.pose(k);
        let got = pose[wrist].transform_point3(tip).as_dvec3();
        let want = hand_tip(k as f64);
        assert!(got.distance(want) < 1e-5, "frame {k}: {got} against {want}");
        // Bones keep their lengths: the elbow–wrist bone is 0.25 m.
        let elbow = pose[wrist - 1].translation;
        assert!((pose[wrist].translation.distance(elbow) - 0.25).abs() < 1e-5);
    }
    // Time picks the nearest frame, held at the ends.
    assert_eq!(
        (
            m.frame_at(10.0 / 30.0 + 0.001),
            m.frame_at(-1.0),
            m.frame_at(99.0)
        ),
        (10, 0, 29)
    );
    assert_eq!(m.pose(500), m.pose(29));
    // The head's top at rest above the neck.
    let neck = m.joints.iter().position(|j| j.name == "Neck").unwrap();
    let top = m.pose(0)[neck].transform_point3(m.joints[neck].end.unwrap());
    assert!(top.distance(Vec3::new(0.0, 1.7, 0.0)) < 1e-6, "{top}");
}

#[test]
fn hostile_files_are_refused_where_they_go_wrong() {
    let refused = |text: &str| parse(text).unwrap_err();
    let motion = WAVE.find("MOTION").unwrap();
    let hierarchy = &WAVE[..motion];
    // Line and column (1-based) of each fault, shown with a caret.
    let line = WAVE[..WAVE.find("0.466667").unwrap()].matches('\n').count() + 1;
    let e = refused(&WAVE.replacen("0.466667", "nan", 1));
    assert!(e.message.contains("frame 28's value 0 (Hips"), "{e:?}");
    assert!(
        e.message.contains("must be finite") && (e.line, e.column) == (line, 1),
        "{e:?}"
    );
    assert!(
        e.to_string().contains(&format!("wave.bvh:{line}:1:")),
        "{e}"
    );
    let e = refused(&WAVE.replacen("Zrotation Xrotation\n", "Zrotation Xrotatoin\n", 1));
    assert!(e.message.contains("unknown channel `Xrotatoin`"), "{e:?}");
    let e = refused(&WAVE[..WAVE.len() - 20]);
    assert!(e.message.contains("the file ends where frame 29"), "{e:?}");
    let e = refused(&format!("{WAVE} 1.0"));
    assert!(e.message.contains("after the 30 frames"), "{e:?}");
    let e = refused(&WAVE.replacen("Frame Time: 0.03333333", "Frame Time: -1", 1));
    assert!(e.message.contains("frame time must be > 0"), "{e:?}");
    let e = refused(&WAVE.replacen("CHANNELS 1 Zrotation", "CHANNELS 9 Zrotation", 1));
    assert!(e.message.contains("0 to 6 channels"), "{e:?}");
    // A frame count far beyond the file allocates nothing for it: one
    // over a day at 100 a second is refused where it stands, a smaller
    // one where the file ends.
    let e = refused(&format!(
        "{hierarchy}MOTION\nFrames: 18446744073709551615\nFrame Time: 0.1\n1 2 3\n"
    ));
    assert!(e.message.contains("at most 8640000"), "{e:?}");
    let e = refused(&format!(
        "{hierarchy}MOTION\nFrames: 8640000\nFrame Time: 0.1\n1 2 3\n"
    ));
    assert!(e.message.contains("the file ends where"), "{e:?}");
    // Deep nesting: bounded, not a stack overflow.
    let deep = "JOINT J\n{\nOFFSET 0 1 0\nCHANNELS 0\n".repeat(5000);
    let e = refused(&format!(
        "HIERARCHY\nROOT R\n{{\nOFFSET 0 0 0\nCHANNELS 0\n{deep}"
    ));
    assert!(e.message.contains("more than 1024 joints"), "{e:?}");
    for cut in (0..WAVE.len()).step_by(97) {
        let _ = parse(&WAVE[..cut]);
    }
}

/// A skeleton without a single channel holds no value in a frame, so
/// only the announced count said how long reading looped: 10¹⁸ frames
/// looped for ever (issue 54). A count beyond a day at 100 frames a
/// second is refused where it stands; a smaller one of empty frames
/// reads at once.
#[test]
fn frames_without_channels_never_loop() {
    let file = |frames: &str| {
        format!(
            "HIERARCHY\nROOT hips\n{{\nOFFSET 0 0 0\nCHANNELS 0\nEnd Site\n{{\nOFFSET 0 1 0\n}}\n}}\nMOTION\nFrames: {frames}\nFrame Time: 0.01\n"
        )
    };
    let start = std::time::Instant::now();
    let e = parse(&file("1000000000000000000")).unwrap_err();
    assert_eq!((e.line, e.column), (12, 9), "{e}");
    assert!(e.message.contains("at most 8640000"), "{e}");
    let m = parse(&file("8640000")).unwrap();
    assert_eq!(m.frame_count(), 0);
    assert!(
        start.elapsed().as_secs() < 5,
        "reading took {:?}",
        start.elapsed()
    );
}
