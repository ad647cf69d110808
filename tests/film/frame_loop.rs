//! The one frame loop (issue 12): every frame handed out once and in
//! order, its scene and BVH shared, the sensors reading what the last
//! frame left, one error type with its exit codes, trace records.

use std::os::unix::fs::PermissionsExt;
use std::path::Path;
use std::process::Command;
use std::sync::Arc;

use lmfilm::error::Kind;
use lmfilm::film::trace::Record;
use lmfilm::film::Film;
use lmfilm::lsys::print::Format;
use lmfilm::lsys::Source;
use lmfilm::turtle::Options;

use crate::common;

fn film(text: &str) -> Film {
    Film::from_sources(&[Source::new("loop.lm", text)], None, Options::default()).unwrap()
}

const GROW: &str = "Camera_AnimationParameters\nt_final_interval 0.2 0.04\n\
    Axiom\nA\nProductions\nA (0.04)\n1.0 F A EndProb\nEnd\nEndProductions\n";

#[test]
fn frames_come_once_each_in_order_then_none() {
    let mut f = film(GROW);
    let mut seen = Vec::new();
    while let Some(frame) = f.next_frame().unwrap() {
        assert_eq!(frame.time(), frame.number() as f64 * 0.04);
        seen.push(frame.number());
    }
    assert_eq!(seen, [0, 1, 2, 3, 4, 5]);
    // Past the end the loop stays put: no step beyond the last frame.
    assert!(f.next_frame().unwrap().is_none());
    assert_eq!(f.frame().unwrap().number(), 5);
    // Each frame's word grew by one F (the step ran between frames).
    assert_eq!(f.words(Format::Symbols), ["FFFFFA"]);
}

#[test]
fn seek_interprets_the_frame_and_refuses_past_the_end() {
    let mut f = film(GROW);
    let mut ticks = Vec::new();
    let frame = f.seek(3, |k, n| ticks.push((k, n))).unwrap();
    assert_eq!(frame.number(), 3);
    assert_eq!(ticks, [(1, 3), (2, 3), (3, 3)]);
    let e = film(GROW).seek(9, |_, _| {}).err().unwrap();
    assert_eq!(e.kind(), Kind::Input);
    assert!(
        e.to_string().contains("past the film's end (frame 5)"),
        "{e}"
    );
}

#[test]
fn vision_and_the_camera_share_one_scene_and_one_bvh() {
    let mut f = film(GROW);
    let frame = f.seek(2, |_, _| {}).unwrap();
    let accel = frame.accel();
    assert!(Arc::ptr_eq(&accel.scene, frame.scene()));
    assert!(std::ptr::eq(accel, frame.accel()), "built once");
}

/// The width along x of the frame's widest shape.
fn widest(f: &Film) -> f32 {
    let scene = f.frame().unwrap().scene();
    let mut w = 0.0f32;
    for g in &scene.geometries {
        for s in &g.shapes {
            if let Some(b) = lmfilm::render::accel::shapes::bounds(s) {
                w = w.max(b.max.x - b.min.x);
            }
        }
    }
    w
}

/// Expressions read the sensors' last reading, not the live world: at
/// frame 1 `C` has moved the particle (a field of strength 5 and reach 1)
/// from the origin to x = 4 before the sphere that follows is
/// interpreted, yet the sphere's diameter `?40 + 0.1` (felt at the
/// origin) still has frame 0's reading, 5; at frame 2 the reading is 0.
#[test]
fn expressions_read_the_sensors_last_reading() {
    let text = "Camera_AnimationParameters\nt_final_interval 0.08 0.04\n\
        Axiom\ne () (10) (1) () (0) (5) (0) C () (1) () () (T 100 *) (0) (0) \
        a () () () () (?40 0.1 +)\nProductions\nEndProductions\n";
    let mut f = film(text);
    let mut widths = Vec::new();
    while f.next_frame().unwrap().is_some() {
        widths.push(widest(&f));
    }
    // Frame 0: nothing read yet.
    let near = |w: f32, d: f32| (w - d).abs() < 1e-3;
    assert!(
        near(widths[0], 0.1) && near(widths[1], 5.1) && near(widths[2], 0.1),
        "{widths:?}"
    );
}

#[test]
fn trace_records_are_json_with_a_place_for_each_actor() {
    let text = "Camera_AnimationParameters\nt_final_interval 0.04 0.04\n\
        Options\nNBR_actors 2\niVisionWinSize 0 16 8\n\
        actorNbr_automata 0 0 9 init 10 -20 300 2.0 obs 0 0 50 lat 0 0 0\n\
        actorNbr_automata 1 observe\n\
        Axiom\nT () (1) () () (0) (3) F\nProductions\nEndProductions\n";
    let mut f = film(text);
    f.next_frame().unwrap();
    let line = Record::of(&f).unwrap().to_line();
    let json: serde_json::Value = serde_json::from_str(&line).unwrap();
    assert_eq!(json["frame"], 0);
    let actors = json["actors"].as_array().unwrap();
    assert_eq!(actors.len(), 2);
    assert_eq!(actors[0]["id"], 0);
    assert_eq!(actors[0]["automata"], "watch");
    assert_eq!(actors[1]["automata"], "observe");
    // The trace's own spacing, as it has always been written.
    assert!(
        line.starts_with("{\"frame\": 0, \"time\": 0, \"particles\": []"),
        "{line}"
    );
}

fn lmfilm(args: &[&str], dir: &Path) -> (i32, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_lmfilm"))
        .args(args)
        .current_dir(dir)
        .output()
        .unwrap();
    (
        out.status.code().unwrap(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// One error type, one mapping: the scene's fault is exit 2 with its
/// location; a script that fails is not the input's fault (exit 1).
#[test]
fn exit_codes_say_whose_fault_it_is() {
    let dir = common::fresh_dir("frame-loop", "exit");
    let script = dir.join("fail.sh");
    std::fs::write(&script, "#!/bin/sh\nexit 3\n").unwrap();
    std::fs::set_permissions(&script, std::fs::Permissions::from_mode(0o755)).unwrap();
    std::fs::write(
        dir.join("e.lm"),
        "Camera_AnimationParameters\nt_final_interval 0.04 0.04\nOptions\ncommand_file 1 fail.sh a b\nAxiom\nE () (1) (1) () (4) (5) (6)\n",
    )
    .unwrap();
    let (code, err) = lmfilm(&["print", "e.lm", "--allow-commands"], &dir);
    assert_eq!(code, 1, "{err}");
    assert!(
        err.contains("frame 0: script fail.sh (command_file 1) failed"),
        "{err}"
    );
    std::fs::write(dir.join("bad.lm"), "Axiom\nF (\n").unwrap();
    let (code, err) = lmfilm(&["print", "bad.lm"], &dir);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("bad.lm:2:"), "{err}");
    // Options are checked where clap reads them: usage, exit 2.
    for (args, needle) in [
        (
            &["still", "e.lm", "-o", "x.jpg"][..],
            "must end in .png or .exr",
        ),
        (
            &["still", "e.lm", "-o", "x.png", "--spp", "0"],
            "--spp must be 1..65536",
        ),
        (
            &["print", "e.lm", "--time", "-1"],
            "--time must be a time ≥ 0",
        ),
        (
            &["sound", "e.lm", "--rate", "0"],
            "--rate must be 1..768000",
        ),
    ] {
        let (code, err) = lmfilm(args, &dir);
        assert_eq!(code, 2, "{args:?}: {err}");
        assert!(err.contains(needle), "{args:?}: {err}");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The sense step: an actor with a vision window sees into the frame's
/// BVH and its visual memory fills; with `vis_mem_off` it remembers
/// nothing; an actor without a window sees nothing.
#[test]
fn watching_actors_remember_what_they_see() {
    let scene = |extra: &str| {
        format!(
            "Camera_AnimationParameters\nt_final_interval 0.04 0.04\n\
             Options\nNBR_actors 2\niVisionWinSize 0 32 8\n\
             actorNbr_automata 0 watch init 10 -20 300 2.0 obs 0 0 -10 lat 0 0 0 {extra}\n\
             actorNbr_automata 1 watch init 10 -20 300 2.0 obs 0 0 -10 lat 0 0 0\n\
             Axiom\na () () () () (4)\nProductions\nEndProductions\n"
        )
    };
    let voxels = |text: &str| {
        let mut f = film(text);
        f.next_frame().unwrap();
        let r = Record::of(&f).unwrap();
        (r.actors[0].memory_voxels, r.actors[1].memory_voxels)
    };
    let (seen, blind) = voxels(&scene(""));
    assert!(seen >= 4, "the sphere's visible side: {seen} voxels");
    assert_eq!(blind, 0, "actor 1 has no vision window");
    assert_eq!(voxels(&scene("vis_mem_off")).0, 0);
    let mut f = film(&scene(""));
    f.next_frame().unwrap();
    let window = f.living()[0].window.as_ref().unwrap();
    assert!((window.centre - 8.0).abs() < 1e-4, "?30: {}", window.centre);
}
