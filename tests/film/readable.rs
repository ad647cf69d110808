//! The readable form end to end (issue 40): every shipped scene renders
//! the same image bytes from its `.lmr` as from its `.lm`, and a film
//! run from either gives the same frames and the same soundtrack.

use std::path::{Path, PathBuf};

use crate::cli::lmfilm;
use crate::common::{fresh_dir, scene_files};

fn scenes() -> Vec<PathBuf> {
    let scenes = scene_files("lm");
    assert!(scenes.len() > 40, "{} scenes", scenes.len());
    scenes
}

fn still(scene: &Path, frame: &str, out: &Path) -> (i32, String) {
    let (code, _, err) = lmfilm(&[
        "still",
        scene.to_str().unwrap(),
        "--frame",
        frame,
        "--preset",
        "preview",
        "-o",
        out.to_str().unwrap(),
    ]);
    (code, err)
}

#[test]
fn every_scene_renders_the_same_bytes_from_its_readable_form() {
    let dir = fresh_dir("readable", "stills");
    let mut compared = 0;
    for (k, lm) in scenes().iter().enumerate() {
        let a = dir.join(format!("{k}.png"));
        let b = dir.join(format!("{k}.r.png"));
        // A later frame where the film has one (the bench stills have
        // only their first).
        let mut frame = "2";
        let (mut code, mut err) = still(lm, frame, &a);
        if err.contains("past the end") {
            frame = "0";
            (code, err) = still(lm, frame, &a);
        }
        if code != 0 && err.contains("cannot read") {
            // A file the scene names is made by a script (the forest's
            // OBJ): both forms say so alike.
            let (code, err_r) = still(&lm.with_extension("lmr"), frame, &b);
            assert!(code != 0 && err_r.contains("cannot read"), "{err_r}");
            continue;
        }
        assert_eq!(code, 0, "{}: {err}", lm.display());
        let (code, err) = still(&lm.with_extension("lmr"), frame, &b);
        assert_eq!(code, 0, "{}: {err}", lm.display());
        assert!(
            std::fs::read(&a).unwrap() == std::fs::read(&b).unwrap(),
            "{}: the readable form renders other bytes",
            lm.display()
        );
        compared += 1;
    }
    assert!(compared > 40);
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn a_film_from_the_readable_form_has_the_same_frames_and_sound() {
    let dir = fresh_dir("readable", "film");
    let scene = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/examples/airplane");
    for (ext, out) in [("lm", "a"), ("lmr", "b")] {
        let out = dir.join(out);
        let (code, _, err) = lmfilm(&[
            "run",
            &format!("{scene}.{ext}"),
            "--frames",
            "0..6",
            "--preset",
            "preview",
            "--width",
            "160",
            "--height",
            "120",
            "-o",
            out.to_str().unwrap(),
        ]);
        assert_eq!(code, 0, "{err}");
    }
    let mut names: Vec<PathBuf> = std::fs::read_dir(dir.join("a/frames"))
        .unwrap()
        .map(|e| PathBuf::from("frames").join(e.unwrap().file_name()))
        .filter(|p| p.extension().is_some_and(|x| x == "png" || x == "exr"))
        .collect();
    names.push("soundtrack.wav".into());
    names.push("soundtrack.events".into());
    assert!(names.len() >= 8, "{names:?}");
    for n in &names {
        let a = std::fs::read(dir.join("a").join(n)).unwrap();
        let b = std::fs::read(dir.join("b").join(n)).unwrap();
        assert!(a == b, "{}: differs", n.display());
    }
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn convert_goes_both_ways_from_the_command_line() {
    let dir = fresh_dir("readable", "convert");
    let lm = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/examples/parametric.lm");
    let lmr = dir.join("p.lmr");
    let (code, _, err) = lmfilm(&["convert", lm, "-o", lmr.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    assert!(err.contains("wrote"), "{err}");
    let (code, classic, err) = lmfilm(&["convert", lmr.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    assert!(
        classic.contains("[(y 3 -)p]") && classic.contains("EndProductions"),
        "{classic}"
    );
    // The same words from the thesis's spelling as from the original.
    let back = dir.join("p.lm");
    std::fs::write(&back, &classic).unwrap();
    let words = |f: &str| lmfilm(&["print", f, "--frame", "4", "--format", "full"]).1;
    assert_eq!(words(back.to_str().unwrap()), words(lm));
    // Never over its own input, however the path is written.
    let twisted = format!(
        "{}/../{}/p.lmr",
        dir.display(),
        dir.file_name().unwrap().to_str().unwrap()
    );
    let (code, _, err) = lmfilm(&["convert", lmr.to_str().unwrap(), "-o", &twisted]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("overwrite the input"), "{err}");
    std::fs::remove_dir_all(&dir).ok();
}
