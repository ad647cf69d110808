//! The actor symbols and sensor functions through the frame loop (thesis
//! C.5, table B5, code 5.10.2): `M` makes an actor current for the
//! symbols of its branch, whose conditions read that actor's percepts;
//! `g` maps the turtle back; `M` 14/15 place the memory display.

use lmfilm::actors::live;
use lmfilm::film::trace::Record;
use lmfilm::film::Film;
use lmfilm::lsys::print::Format;
use lmfilm::lsys::Source;
use lmfilm::turtle::Options;

use super::support::{film, same_for_one_and_two_threads, scene, trace_bytes};

/// A wall 20 × 20 whose face toward −z is the plane z = 9.5.
const WALL: &str = "[ f () () () (2) (10_) (0) (10) c () () () () (20) (20) (1) ]";

/// x becomes y once the condition holds.
fn x_to_y(condition: &str) -> String {
    format!("x (0) {condition}\n1.0 y EndProb\nEnd\n")
}

#[test]
fn a_branch_reads_the_actor_its_m_made_current() {
    // Actor 0 faces the wall 9.5 away, actor 1 faces away from it.
    let options = "NBR_actors 2\niVisionWinSize 0 8 4\niVisionWinSize 1 8 4\n\
        actorNbr_automata 0 watch obs 0 0 0 lat 0 0 1\n\
        actorNbr_automata 1 watch obs 0 0 0 lat 0 0 -1";
    let axiom = format!("{WALL} [ M () (7) () (0) x ] [ M () (7) () (1) x ] x");
    let mut f = film(&scene(0.08, options, &axiom, &x_to_y("[(?30 10 -)<]")));
    f.seek(1, |_, _| {}).unwrap();
    // Outside any M branch the current actor is the last M's: actor 1.
    assert_eq!(f.words(Format::Symbols), ["[fc][My][Mx]x"]);
}

#[test]
fn a_walking_actor_sees_the_wall_come_closer() {
    // [M f x g]: each frame the actor steps 0.5 toward the wall; x turns
    // into y at the first step whose last reading of ?30 is under 3:
    // frame 13's (eye at z = 7, 2.5 from the face), not frame 12's (3.0).
    let options = "NBR_actors 1\niVisionWinSize 0 16 8\n\
        actorNbr_automata 0 watch obs 0 2 0 lat 0 2 1";
    let axiom = format!("{WALL} [ M () (7) () (0) f () () () () (0.5) x g () (0) ]");
    let mut f = film(&scene(0.8, options, &axiom, &x_to_y("[(?30 3 -)<]")));
    f.seek(13, |_, _| {}).unwrap();
    assert_eq!(f.words(Format::Symbols), ["[fc][Mfxg]"]);
    let eye = f.living()[0].eye;
    assert_eq!(eye.to_array(), [0.0, 2.0, 7.0]);
    let centre = f.living()[0].window.as_ref().unwrap().centre_distance();
    assert!((centre - 2.5).abs() < 1e-4, "{centre}");
    f.next_frame().unwrap();
    assert_eq!(f.words(Format::Symbols), ["[fc][Mfyg]"]);
}

#[test]
fn obstacle_side_drives_the_choice_of_a_production() {
    // A post left of the view axis (+x is left looking along +z), then
    // one right of it: ?31 picks the production.
    for (x, expect) in [("0.5", "l"), ("0.5_", "r")] {
        let options = "NBR_actors 1\niVisionWinSize 0 32 8\n\
            actorNbr_automata 0 watch obs 0 1 0 lat 0 1 1 dist_coll 4 size_actor 2";
        let axiom = format!(
            "[ f () () () (2) ({x}) (0) (2) + () () () () (90) c () () () () (3) (0.4) (0.4) ] \
             [ M () (7) () (0) x ]"
        );
        let prods = "x (0) [(?31 1 +)=]\n1.0 l EndProb\nEnd\n\
                     x (0) [(?31 1 -)=]\n1.0 r EndProb\nEnd\n";
        let mut f = film(&scene(0.08, options, &axiom, prods));
        f.seek(1, |_, _| {}).unwrap();
        assert_eq!(f.words(Format::Symbols), [format!("[f+c][M{expect}]")]);
    }
}

#[test]
fn g_maps_the_turtle_to_the_actor() {
    let options = "NBR_actors 1\nactorNbr_automata 0 watch obs 0 0 0 lat 0 0 1";
    // g 0: eye at the turtle, looking along H (the default H is +x).
    let mut f = film(&scene(
        0.04,
        options,
        "f () () () (2) (1) (2) (3) g () (0)",
        "",
    ));
    f.next_frame().unwrap();
    let a = &f.living()[0];
    assert_eq!(
        (a.eye.to_array(), a.look_at.to_array()),
        ([1.0, 2.0, 3.0], [2.0, 2.0, 3.0])
    );
    // g 2: the same with the height par4, looking in the horizontal plane.
    let axiom = "f () () () (2) (1) (2) (3) + () () () () (30) g () (2) () () (5)";
    let mut f = film(&scene(0.04, options, axiom, ""));
    f.next_frame().unwrap();
    let a = &f.living()[0];
    assert_eq!(a.eye.to_array(), [1.0, 5.0, 3.0]);
    assert!(
        (a.look_at - a.eye).abs_diff_eq(glam::Vec3::X, 1e-6),
        "{}",
        a.look_at
    );
    // g 1: the local goal at the turtle; it is the goal the trace lists.
    let mut f = film(&scene(
        0.04,
        options,
        "f () () () (2) (4) (0) (5) g () (1)",
        "",
    ));
    f.next_frame().unwrap();
    let r = Record::of(&f).unwrap();
    assert_eq!(r.actors[0].goal, Some([4.0, 0.0, 5.0]));
}

#[test]
fn m_puts_the_turtle_at_the_actor_looking_where_it_looks() {
    // M then a box of length 2 along H: it lies from the eye toward the
    // look-at point.
    let options = "NBR_actors 1\nactorNbr_automata 0 watch obs 1 2 3 lat 1 2 9";
    let mut f = film(&scene(
        0.04,
        options,
        "M () (7) () (0) c () () () () (2) (0.2) (0.2)",
        "",
    ));
    let frame = f.next_frame().unwrap().unwrap();
    let shapes = &frame.scene().geometries[0].shapes;
    assert_eq!(shapes.len(), 1);
    let t = shapes[0].transform;
    assert!(t
        .translation
        .abs_diff_eq(glam::Vec3A::new(1.0, 2.0, 3.0), 1e-6));
    assert!(t
        .matrix3
        .x_axis
        .abs_diff_eq(glam::Vec3A::new(0.0, 0.0, 2.0), 1e-6));
    // Its up (U) stays vertical.
    assert!(t
        .matrix3
        .z_axis
        .abs_diff_eq(glam::Vec3A::new(0.0, 0.2, 0.0), 1e-6));
}

#[test]
fn m_14_and_15_place_the_memory_display() {
    let options = "NBR_actors 1\nactorNbr_automata 0 watch mem_displ_points";
    let axiom =
        "f () () () (2) (0) (9) (5_) M () (14) () (0) f () () () (2) (1) (0) (0) M () (15) () (0)";
    let mut f = film(&scene(0.04, options, axiom, ""));
    f.next_frame().unwrap();
    let d = f.living()[0].display;
    assert_eq!(d.eye.map(|v| v.to_array()), Some([0.0, 9.0, -5.0]));
    assert_eq!(d.look_at.map(|v| v.to_array()), Some([1.0, 0.0, 0.0]));
}

#[test]
fn an_actor_that_does_not_exist_is_warned_of() {
    let options = "NBR_actors 1\nactorNbr_automata 0 watch";
    let mut f = film(&scene(0.04, options, "M () (7) () (3) g () (0)", ""));
    let frame = f.next_frame().unwrap().unwrap();
    let w = frame.warnings().join("\n");
    assert!(w.contains("`M` names actor 3"), "{w}");
    // Without actors, g is warned of too.
    let mut f = film(&scene(0.04, "", "g () (0)", ""));
    let w = f.next_frame().unwrap().unwrap().warnings().join("\n");
    assert!(w.contains("the scene has none"), "{w}");
}

#[test]
fn goal_functions_read_the_actors_goals() {
    // The eye at the origin looking along +z; goal (0 0 5) ahead, 5 away.
    let options = "NBR_actors 1\nactorNbr_automata 0 watch obs 0 0 0 lat 0 0 1 \
        goal 0 0 5 eps_arrived 6 eps_look_at 0.9";
    let prods = "a (0) [(?32)>]\n1.0 A EndProb\nEnd\n\
                 b (0) [(?33)>]\n1.0 B EndProb\nEnd\n\
                 c (0) [(?39)>]\n1.0 C EndProb\nEnd\n";
    let mut f = film(&scene(0.08, options, "a b c", prods));
    f.seek(1, |_, _| {}).unwrap();
    assert_eq!(f.words(Format::Symbols), ["ABC"]);
    // A local goal behind, and a threshold too small to have arrived.
    let options = "NBR_actors 1\nactorNbr_automata 0 watch obs 0 0 0 lat 0 0 1 \
        goal 0 0 5 local_goal 0 0 0 -5 eps_arrived 1";
    let mut f = film(&scene(0.08, options, "a b c", prods));
    f.seek(1, |_, _| {}).unwrap();
    assert_eq!(f.words(Format::Symbols), ["abc"]);
}

/// An actor looking at a ball of material 10 (the thing of interest 0)
/// of radius 1 (`a` takes the diameter) centred at (0, 1, 8).
const BALL: &str = "[ f () () () (2) (0) (1) (8) m () (10) a () () () () (2) ]";

#[test]
fn the_thing_of_interest_is_found_and_located() {
    let options = "NBR_actors 1\niVisionWinSize 0 64 16\n\
        actorNbr_automata 0 watch obs 0 1 0 lat 0 1 8 fov 300 interest 1 0";
    let prods = "x (0) [(?36)>]\n1.0 X EndProb\nEnd\n";
    let mut f = film(&scene(0.08, options, &format!("{BALL} x"), prods));
    f.seek(1, |_, _| {}).unwrap();
    assert_eq!(f.words(Format::Symbols), ["[fma]X"]);
    let r = Record::of(&f).unwrap();
    let a = &r.actors[0];
    assert!(a.found && a.pixels > 100, "{a:?}");
    // The mean of the visible half's points: on the axis, in front of the
    // centre by about 2/3 of the radius.
    let p = a.position.unwrap();
    assert!(p[0].abs() < 0.05 && (p[1] - 1.0).abs() < 0.05, "{p:?}");
    assert!(p[2] > 7.0 && p[2] < 7.5, "{p:?}");
    // Off: not found.
    let off = options.replace("interest 1 0", "interest 0 0");
    let mut f = film(&scene(0.08, &off, &format!("{BALL} x"), prods));
    f.seek(1, |_, _| {}).unwrap();
    assert_eq!(f.words(Format::Symbols), ["[fma]x"]);
}

#[test]
fn rgb_interest_sets_local_goal_1() {
    // Material 10 is the ball, diffuse (0.8, 0.4, 0.2): its shaded pixels
    // have that hue.
    let options = "NBR_actors 1\niVisionWinSize 0 32 16\n\
        actorNbr_automata 0 watch obs 0 1 0 lat 0 1 8 fov 300 rgb_interest 204 102 51 1";
    let prods = "x (0) [(?38)>]\n1.0 X EndProb\nEnd\n";
    let mut f = film(&scene(0.08, options, &format!("{BALL} x"), prods));
    f.seek(1, |_, _| {}).unwrap();
    assert_eq!(f.words(Format::Symbols), ["[fma]X"]);
    let goal = f.living()[0].local_goals[&1];
    assert!(
        (goal - glam::Vec3::new(0.0, 1.0, 7.3)).length() < 0.3,
        "{goal}"
    );
}

#[test]
fn trace_is_the_same_for_one_and_two_threads() {
    same_for_one_and_two_threads(
        "scenes/actors/flower_room.lm",
        &["--frames", "0..12"],
        "\"memory_voxels\": ",
    );
}

#[test]
fn a_cut_branch_gives_back_the_actor_before_it() {
    // Actor 0 sees the wall, actor 1 does not. The cut removes the branch
    // in which M made actor 0 current; the x after it reads actor 1 again.
    let options = "NBR_actors 2\niVisionWinSize 0 8 4\niVisionWinSize 1 8 4\n\
        actorNbr_automata 0 watch obs 0 0 0 lat 0 0 1\n\
        actorNbr_automata 1 watch obs 0 0 0 lat 0 0 -1";
    let axiom = format!("{WALL} M () (7) () (1) [ M () (7) () (0) k ] x");
    let prods = format!(
        "k (0)\n1.0 ] () (1_) w EndProb\nEnd\n{}",
        x_to_y("[(?30 10 -)<]")
    );
    let mut f = film(&scene(0.08, options, &axiom, &prods));
    f.seek(1, |_, _| {}).unwrap();
    assert_eq!(f.words(Format::Symbols), ["[fc]Mwx"]);
}

#[test]
fn every_actor_scene_runs() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/actors");
    let mut scenes: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "lm"))
        .collect();
    scenes.sort();
    assert!(scenes.len() >= 4, "{scenes:?}");
    for scene in scenes {
        let out = trace_bytes(scene.to_str().unwrap(), &["--frames", "0..3"], None);
        assert_eq!(out.iter().filter(|&&b| b == b'\n').count(), 3);
    }
}

#[test]
fn vision_and_memory_are_bounded() {
    // Five windows of 1024 × 1024 are more than the actors may cast.
    let windows: String = (0..5)
        .map(|a| format!("iVisionWinSize {a} 1024 4\n"))
        .collect();
    let text = scene(0.04, &format!("NBR_actors 5\n{windows}"), "F", "");
    let e = Film::from_sources(&[Source::new("big.lm", &text)], None, Options::default())
        .err()
        .unwrap()
        .to_string();
    assert!(e.contains("big.lm:9:18:") && e.contains("4194304"), "{e}");
    // A memory past its budget names the actor and what to change.
    let options = "NBR_actors 1\niVisionWinSize 0 16 4\n\
        actorNbr_automata 0 watch init 1 -20 20 0.1 obs 0 2 0 lat 0 2 1";
    let mut f = film(&scene(0.04, options, WALL, ""));
    f.next_frame().unwrap();
    let e = live::check_memory(f.living(), 1000).unwrap_err();
    assert!(
        e.contains("actor 0's holds") && e.contains("larger voxel edge"),
        "{e}"
    );
    assert!(live::check_memory(f.living(), 1 << 30).is_ok());
}
