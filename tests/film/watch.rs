//! `lmfilm watch` (issue 40): a preview still rendered at once, again
//! when the scene is saved, an error printed (not fatal) when a save
//! breaks it, and again when the next save mends it.

use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// A one-sphere scene of colour `material`; `broken` adds a line the
/// parser refuses.
fn scene(material: u32, broken: bool) -> String {
    format!(
        "Camera_AnimationParameters\npref_pos_x1_x2_y1_y2 0 48 0 32\nobserver 0 0 -5\nlookatPoint 0 0 0\nt_final_interval 1 0.04\n\
         Axiom\nm () ({material}) a () () () () (1)\n{}",
        if broken { "Productions\nF (0\n" } else { "" }
    )
}

/// Waits until `path` holds bytes other than `old` (at most 60 s).
fn changed(path: &Path, old: &[u8]) -> Vec<u8> {
    let start = Instant::now();
    loop {
        if let Ok(bytes) = std::fs::read(path) {
            if !bytes.is_empty() && bytes != old {
                return bytes;
            }
        }
        assert!(
            start.elapsed() < Duration::from_secs(60),
            "{} never changed",
            path.display()
        );
        std::thread::sleep(Duration::from_millis(50));
    }
}

#[test]
fn watch_renders_again_on_each_save_and_survives_a_broken_one() {
    let dir = crate::common::fresh_dir("watch", "saves");
    let (lm, png) = (dir.join("w.lm"), dir.join("w.png"));
    std::fs::write(&lm, scene(4, false)).unwrap();
    let child = Command::new(env!("CARGO_BIN_EXE_lmfilm"))
        .args([
            "watch",
            lm.to_str().unwrap(),
            "-o",
            png.to_str().unwrap(),
            "--count",
            "3",
        ])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let red = changed(&png, &[]);
    // A save the parser refuses: the error is printed, the image kept.
    std::thread::sleep(Duration::from_millis(300));
    std::fs::write(&lm, scene(4, true)).unwrap();
    std::thread::sleep(Duration::from_millis(1500));
    assert_eq!(std::fs::read(&png).unwrap(), red);
    // Mended, another colour: rendered again.
    std::fs::write(&lm, scene(3, false)).unwrap();
    let blue = changed(&png, &red);
    assert_ne!(blue, red);
    let out = child.wait_with_output().unwrap();
    assert!(out.status.success(), "{out:?}");
    let err = String::from_utf8_lossy(&out.stderr);
    // The broken save's error, located with its line and caret.
    assert!(err.contains("w.lm:") && err.contains('^'), "{err}");
    assert_eq!(err.matches("rendered in").count(), 2, "{err}");
}

#[test]
fn watch_renders_a_short_range_as_numbered_frames() {
    let dir = crate::common::fresh_dir("watch", "range");
    let scene = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/examples/first.lmr");
    let out = dir.join("first.png");
    let (code, _, err) = crate::cli::lmfilm(&[
        "watch",
        scene,
        "--frames",
        "24..=26",
        "--count",
        "1",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    // Each frame as `still` renders it alone.
    for n in 24..=26 {
        let single = dir.join(format!("single{n}.png"));
        let (code, _, err) = crate::cli::lmfilm(&[
            "still",
            scene,
            "--frame",
            &n.to_string(),
            "--preset",
            "preview",
            "-o",
            single.to_str().unwrap(),
        ]);
        assert_eq!(code, 0, "{err}");
        let ranged = std::fs::read(dir.join(format!("first.{n:04}.png"))).unwrap();
        assert!(
            ranged == std::fs::read(&single).unwrap(),
            "frame {n} differs"
        );
    }
    assert!(!dir.join("first.0027.png").exists());
    std::fs::remove_dir_all(&dir).ok();
}
