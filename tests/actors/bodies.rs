//! Actors with bodies (issue 39), checked on what the film draws: the
//! walkers of scenes/actors/ keep each standing foot where it was set
//! down (within 2 cm) — the stepping-stone walker on the stone its plan
//! chose —, and the film's geometry is the same bytes for 1 and 2
//! threads.

use glam::{Vec2, Vec3};
use lmfilm::scene::{Scene, ShapeKind};

use super::support::film;

/// The bone of the built-in humanoid drawn as the capsule ending at
/// joint `joint` (its number in `Skeleton::humanoid`), as the turtle
/// numbers a body's bones: the joint + 1 in the symbol's top 16 bits.
fn bone_ends(scene: &Scene, joint: u64) -> Vec<Vec3> {
    scene
        .geometries
        .iter()
        .flat_map(|g| &g.shapes)
        .filter(|s| s.symbol >> 48 == joint + 1)
        .filter_map(|s| match s.kind {
            ShapeKind::Capsule { length } => {
                Some(s.transform.transform_point3(Vec3::new(length, 0.0, 0.0)))
            }
            _ => None,
        })
        .collect()
}

const LEFT_FOOT: u64 = 15;
const RIGHT_FOOT: u64 = 19;

fn read(scene: &str) -> String {
    std::fs::read_to_string(std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(scene)).unwrap()
}

/// The ends of bones `joints` (of the one body the film draws) in each
/// of the film's first `frames` frames.
fn track(f: &mut lmfilm::film::Film, frames: u64, joints: &[u64]) -> Vec<Vec<Vec3>> {
    let mut out = Vec::new();
    for _ in 0..frames {
        let Some(frame) = f.next_frame().unwrap() else {
            break;
        };
        let ends: Vec<Vec3> = joints
            .iter()
            .map(|&j| {
                let e = bone_ends(frame.scene(), j);
                assert_eq!(e.len(), 1, "one body");
                e[0]
            })
            .collect();
        out.push(ends);
    }
    out
}

/// Each ankle's contacts with the ground, from frames of `[left, right]`
/// ankles: a contact is a run of frames with the ankle at its lowest
/// height (to 3 mm); each contact's first point and the most it moved.
fn contacts_of(ankles: &[Vec<Vec3>]) -> Vec<(Vec3, f32)> {
    let low = ankles
        .iter()
        .flatten()
        .map(|a| a.y)
        .fold(f32::INFINITY, f32::min);
    let mut out = Vec::new();
    for foot in 0..2 {
        let mut contact: Option<(Vec3, f32)> = None;
        for a in ankles.iter().map(|a| a[foot]) {
            if a.y > low + 0.003 {
                out.extend(contact.take());
                continue;
            }
            let c = contact.get_or_insert((a, 0.0));
            c.1 = c.1.max(a.distance(c.0));
        }
        out.extend(contact);
    }
    out
}

/// The contacts of the ankles of the one body of `scene` over its first
/// `frames` frames (see [`contacts_of`]).
fn contacts(scene: &str, frames: u64) -> Vec<(Vec3, f32)> {
    contacts_of(&track(
        &mut film(&read(scene)),
        frames,
        &[LEFT_FOOT, RIGHT_FOOT],
    ))
}

#[test]
fn the_maze_walker_plants_its_feet() {
    let contacts = contacts("scenes/actors/walker_maze.lm", 700);
    assert!(contacts.len() > 60, "{} contacts", contacts.len());
    for (at, slid) in &contacts {
        assert!(*slid < 0.02, "the foot set down at {at} slid {slid} m");
    }
}

#[test]
fn the_stone_walker_stands_each_foot_on_a_stone() {
    let text = read("scenes/actors/walker_stones.lm");
    // The stones: `f () () () (2) (x) (y) (z)` in material 16.
    let number = |s: &str| match s.strip_suffix('_') {
        Some(n) => -n.parse::<f32>().unwrap(),
        None => s.parse().unwrap(),
    };
    let stones: Vec<Vec2> = text
        .lines()
        .filter(|l| l.starts_with("[ m () (16) $ () () (3) f () () () (2) ("))
        .map(|l| {
            let g: Vec<&str> = l.split('(').map(|g| g.split(')').next().unwrap()).collect();
            let at = g.iter().position(|g| *g == "2").unwrap();
            Vec2::new(number(g[at + 1]), number(g[at + 3]))
        })
        .collect();
    let contacts = contacts("scenes/actors/walker_stones.lm", 1050);
    assert!(contacts.len() > 40, "{} contacts", contacts.len());
    for (at, slid) in &contacts {
        assert!(*slid < 0.02, "the foot set down at {at} slid {slid} m");
        // The sole's middle under the ankle, on a stone 0.24 wide (its
        // half and a little for the sole's own size).
        let on = stones
            .iter()
            .any(|s| (s.x - at.x).abs() < 0.15 && (s.y - at.z).abs() < 0.15);
        assert!(on, "a foot stands at {at}, on no stone");
    }
}

/// The film's geometry at a frame of a walk (`lmfilm export`), the same
/// bytes for 1 and 2 threads.
#[test]
fn a_walking_body_is_the_same_for_one_and_two_threads() {
    let dir = crate::common::fresh_dir("bodies", "threads");
    let mut outputs = Vec::new();
    for threads in ["1", "2"] {
        let out = dir.join(format!("t{threads}.obj"));
        let status = std::process::Command::new(env!("CARGO_BIN_EXE_lmfilm"))
            .current_dir(env!("CARGO_MANIFEST_DIR"))
            .env("RAYON_NUM_THREADS", threads)
            .args([
                "export",
                "scenes/actors/walker_stones.lm",
                "--frame",
                "300",
                "-o",
            ])
            .arg(&out)
            .output()
            .unwrap();
        assert!(status.status.success(), "{status:?}");
        let obj = std::fs::read_to_string(&out).unwrap();
        outputs.push(obj.replace(&format!("t{threads}.mtl"), "t.mtl"));
    }
    assert!(outputs[0].lines().count() > 1000);
    assert_eq!(outputs[0], outputs[1]);
}

/// The grip of a player's racket in scenes/tennis/match.lm: a quarter
/// of the way along the handle (a capsule 0.4 long, 0.04 thick, in the
/// player's material), where its `D` 50 holds the body's right hand.
fn grips(scene: &Scene, material: u32) -> Vec<Vec3> {
    scene
        .geometries
        .iter()
        .flat_map(|g| &g.shapes)
        .filter(|s| s.material == material && s.symbol >> 48 == 0)
        .filter_map(|s| match s.kind {
            ShapeKind::Capsule { length } if (length - 10.0).abs() < 1e-3 => {
                Some(s.transform.transform_point3(Vec3::new(6.25, 0.0, 0.0)))
            }
            _ => None,
        })
        .collect()
}

const RIGHT_HAND: u64 = 12;
const HEAD: u64 = 22;

/// The match's players hold their rackets: at each stroke's impact
/// (the last frame of its hit phase, when the racket is on its planned
/// path, eq. 5.6.15–5.6.17, services included) the right wrist of the
/// body nearest each racket is on its grip within 2 cm, and nearly
/// always between strokes too (a racket high over a service's follow
/// through is beyond a 2 m player's reach); the seated referee's head
/// turns to what it looks at.
#[test]
fn the_players_hold_their_rackets_and_the_referee_follows_the_ball() {
    let mut f = film(&read("scenes/tennis/match.lm"));
    let (mut held, mut frames, mut impacts) = (0, 0, 0);
    let mut turned = Vec::new();
    let mut hitting = [false; 2];
    let mut last: [Option<f32>; 2] = [None; 2];
    for _ in 0..900 {
        let Some(frame) = f.next_frame().unwrap() else {
            break;
        };
        let s = frame.scene().clone();
        let number = frame.number();
        let wrists = bone_ends(&s, RIGHT_HAND);
        assert_eq!(wrists.len(), 3, "two players and the referee");
        for (p, material) in [11, 12].into_iter().enumerate() {
            let grip = grips(&s, material);
            assert_eq!(grip.len(), 1, "one handle in material {material}");
            let d = wrists
                .iter()
                .map(|w| w.distance(grip[0]))
                .fold(f32::INFINITY, f32::min);
            frames += 1;
            held += usize::from(d < 0.02);
            // The frame a hit phase ends follows the impact.
            let now = f.living()[p].tennis.state == 13;
            if hitting[p] && !now {
                let at = last[p].unwrap();
                assert!(
                    at < 0.02,
                    "frame {number}: player {p}'s hand {at} m off its grip at the impact"
                );
                impacts += 1;
            }
            hitting[p] = now;
            last[p] = Some(d);
        }
        // The referee's head: its ellipsoid's forward axis.
        let referee = &f.living()[2];
        let head = s
            .geometries
            .iter()
            .flat_map(|g| &g.shapes)
            .find(|sh| sh.symbol >> 48 == HEAD + 1 && sh.material == 15)
            .expect("the referee's head");
        let forward = Vec3::from(head.transform.z_axis).normalize();
        let look = (referee.look_at - referee.eye).normalize();
        turned.push(forward.angle_between(look));
    }
    assert!(impacts >= 6, "{impacts} impacts");
    assert!(
        held * 100 >= frames * 97,
        "the hand on its grip in {held} of {frames} frames"
    );
    turned.sort_by(f32::total_cmp);
    let median = turned[turned.len() / 2];
    assert!(
        median < 0.2,
        "the referee's head is {median} rad off its gaze (median)"
    );
}

/// An imported trajectory drives a body (`$` par2 = 5, `import_trace`):
/// held by its eyes at the trajectory's point (1 m up: a child of 1.1 m),
/// it walks the path `pledge.lm` recorded with its feet planted.
#[test]
fn an_imported_trajectory_walks_a_body() {
    let dir = crate::common::fresh_dir("bodies", "trace");
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    std::fs::copy(
        root.join("scenes/actors/pledge.trace"),
        dir.join("pledge.trace"),
    )
    .unwrap();
    let scene = dir.join("walk.lm");
    std::fs::write(
        &scene,
        "Camera_AnimationParameters\nt_final_interval 12 0.04\n\
         Options\nimport_trace 0 pledge.trace\n\
         Axiom\n[ $ () () (5) (0) m () (14) D () (50) () () (0) () (1) ]\n",
    )
    .unwrap();
    let mut f = lmfilm::film::Film::load(&[&scene], lmfilm::turtle::Options::default()).unwrap();
    // The ankles, and the spine joint (where the body is).
    let frames = track(&mut f, u64::MAX, &[LEFT_FOOT, RIGHT_FOOT, 1]);
    let travelled: f32 = frames
        .windows(2)
        .map(|w| Vec3::new(w[1][2].x - w[0][2].x, 0.0, w[1][2].z - w[0][2].z).length())
        .sum();
    let contacts = contacts_of(&frames);
    for (at, slid) in &contacts {
        assert!(*slid < 0.02, "the foot set down at {at} slid {slid} m");
    }
    let steps = contacts.len();
    assert!(travelled > 5.0, "the body went {travelled} m");
    assert!(steps > 10, "{steps} steps");
}

/// A body whose legs cannot span its steps says so: the cube of
/// scenes/actors/footholds.lm, whose eye is 0.7 up, given a body (0.77 m
/// tall) for stones 0.62 apart.
#[test]
fn a_body_too_short_for_its_steps_says_so() {
    let text = read("scenes/actors/footholds.lm").replace(
        "[ M () (7) () (0)\n",
        "[ M () (7) () (0) D () (50) () () (0) () (1)\n",
    );
    assert!(text.contains("D () (50)"));
    let mut f = film(&text);
    let mut said = Vec::new();
    for _ in 0..300 {
        let Some(frame) = f.next_frame().unwrap() else {
            break;
        };
        said.extend(frame.warnings().iter().cloned());
    }
    assert!(
        said.iter()
            .any(|w| w.contains("cannot reach where its feet are set")),
        "{said:?}"
    );
}
