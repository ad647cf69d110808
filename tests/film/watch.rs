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
