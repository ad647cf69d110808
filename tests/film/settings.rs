//! One set of film settings (issue 37): resolved once, recorded resolved
//! in `settings.json`, and taken again by `render DIR`, `sound DIR` and a
//! re-run with no option; an option that changes them re-renders every
//! frame or is refused, never leaving frames of two settings.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use crate::cli::lmfilm;

const SCENE: &str = "Camera_AnimationParameters\nprefpos_x1_x2_y1_y2 0 64 0 48\n\
    observer 0 1 6\nlookatPoint 0 1 0\nt_final_interval 0.2 0.04\n\
    Axiom\nm () (4) A\nProductions\nA (0.04)\n1.0 F () () () () (0.3) A EndProb\nEnd\nEndProductions\n";

/// A fresh folder with the scene in it.
fn root(test: &str) -> (PathBuf, String) {
    let root = std::env::temp_dir().join(format!("lmfilm-settings-{test}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&root);
    std::fs::create_dir_all(&root).unwrap();
    let scene = root.join("growing.lm");
    std::fs::write(&scene, SCENE).unwrap();
    (root, scene.to_str().unwrap().to_string())
}

/// Every file of `frames/`: name → bytes.
fn frames(dir: &Path) -> BTreeMap<String, Vec<u8>> {
    std::fs::read_dir(dir.join("frames"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .map(|p| {
            let name = p.file_name().unwrap().to_string_lossy().into_owned();
            (name, std::fs::read(&p).unwrap())
        })
        .collect()
}

fn ok(args: &[&str]) -> String {
    let (code, out, err) = lmfilm(args);
    assert_eq!(code, 0, "{args:?}: {out}{err}");
    out + &err
}

/// The first example: a film rendered with its own settings,
/// three frames deleted, `render DIR --frames` with no option renders
/// them again with the film's settings, byte for byte; the record holds
/// resolved values only.
#[test]
fn a_re_render_of_deleted_frames_gives_the_same_bytes() {
    let (root, scene) = root("rerender");
    let a = root.join("A");
    let dir = a.to_str().unwrap();
    ok(&[
        "run", &scene, "-o", dir, "--preset", "preview", "--spp", "2",
    ]);
    let before = frames(&a);
    for k in [3, 4, 5] {
        for ext in ["png", "exr", "json"] {
            std::fs::remove_file(a.join(format!("frames/growing.000{k}.{ext}"))).unwrap();
        }
    }
    let out = ok(&["render", dir, "--frames", "3..6"]);
    assert!(out.contains("3 of 3 frames rendered now"), "{out}");
    assert!(frames(&a) == before, "the re-rendered frames differ");
    ok(&["verify", dir]);
    let settings = std::fs::read_to_string(a.join("settings.json")).unwrap();
    for want in [
        "\"width\": 64",
        "\"height\": 48",
        "\"spp\": 2",
        "\"preset\": \"preview\"",
    ] {
        assert!(settings.contains(want), "{settings}");
    }
    let record = std::fs::read_to_string(a.join("frames/growing.0003.json")).unwrap();
    for unresolved in ["\"width\": \"0\"", "\"height\": \"0\"", "\"spp\": \"0\""] {
        assert!(
            !record.contains(unresolved),
            "a zero meaning default: {record}"
        );
    }
    // `run` again with no option keeps the film's settings: nothing to do.
    let out = ok(&["run", &scene, "-o", dir]);
    assert!(out.contains("0 of 6 frames rendered now"), "{out}");
    assert!(out.contains("64×48, 2 spp, preset preview"), "{out}");
    let _ = std::fs::remove_dir_all(&root);
}

/// An option that changes the film's settings on a part of the film is
/// refused, naming the option and the way out; on the whole film it is
/// the new setting and every frame is rendered again with it.
#[test]
fn a_changed_option_re_renders_every_frame_or_is_refused() {
    let (root, scene) = root("changed");
    let a = root.join("A");
    let dir = a.to_str().unwrap();
    ok(&["run", &scene, "-o", dir, "--preset", "preview"]);
    let (code, _, err) = lmfilm(&["render", dir, "--frames", "3..5", "--spp", "4"]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("spp 1 → 4") && err.contains("--frames"),
        "{err}"
    );
    let (code, _, err) = lmfilm(&["render", dir, "--shard", "1/2", "--width", "32"]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("width 64 → 32") && err.contains("height 48 → 24"),
        "{err}"
    );
    let out = ok(&["render", dir, "--spp", "4"]);
    assert!(out.contains("6 of 6 frames rendered now"), "{out}");
    assert!(out.contains("spp 1 → 4"), "{out}");
    for k in 0..6 {
        let r = std::fs::read_to_string(a.join(format!("frames/growing.000{k}.json"))).unwrap();
        assert!(r.contains("\"spp\": \"4\""), "{r}");
    }
    ok(&["verify", dir]);
    // The soundtrack keeps its settings the same way.
    ok(&["sound", dir, "--loudness", "off"]);
    let out = ok(&["sound", dir]);
    assert!(out.contains("(up to date)"), "{out}");
    let _ = std::fs::remove_dir_all(&root);
}

/// Each option group shows once per command.
#[test]
fn every_command_shows_its_options_once() {
    for (cmd, options) in [
        (
            vec!["run"],
            vec![
                "--spp",
                "--preset",
                "--rate",
                "--loudness",
                "--max-plan-voxels",
                "--allow-commands",
            ],
        ),
        (
            vec!["render"],
            vec!["--spp", "--filter", "--max-depth", "--shadows", "--inset"],
        ),
        (vec!["still"], vec!["--spp", "--filter", "--light-samples"]),
        (
            vec!["farm", "slurm"],
            vec![
                "--spp",
                "--preset",
                "--width",
                "--format",
                "--inset",
                "--rate",
                "--allow-commands",
                "--max-symbols",
            ],
        ),
        (vec!["sound"], vec!["--rate", "--samples", "--loudness"]),
    ] {
        let mut args = cmd.clone();
        args.push("--help");
        let help = ok(&args);
        for o in options {
            let shown = help
                .lines()
                .filter(|l| {
                    l.trim_start()
                        .strip_prefix(o)
                        .is_some_and(|rest| rest.is_empty() || rest.starts_with([' ', '=']))
                })
                .count();
            assert_eq!(shown, 1, "{cmd:?} --help shows {o} {shown} times:\n{help}");
        }
    }
}
