//! What people look at (docs/actors.md): `run` writes each actor's
//! vision window and memory display under `actors/N/`, lists them in the
//! derive record so `verify` checks them, prunes stale ones, and
//! `--inset N` puts a window into the frames' top-left corner.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use crate::common::fresh_dir;

/// A watching actor with a 32 × 32 window and a memory shown as cubes,
/// looking at a red sphere at (0, 2, 0); `frames` frames.
fn scene(dir: &Path, frames: u32, display: &str) -> PathBuf {
    let text = format!(
        "Camera_AnimationParameters
pref_pos_x1_x2_y1_y2 0 160 0 120
observer 0 4 -16
lookatPoint 0 2 0
viewAngle 450
t_final_interval {} 0.04

Options
NBR_actors 1
iVisionWinSize 0 32 8
actorNbr_automata 0 watch init 1 -20 20 0.5 obs 0 2 -12 lat 0 2 0 {display}

Axiom
f () () () (2) (0) (2) (0) m () (4) a () () () () (4)

Productions
EndProductions
",
        0.04 * f64::from(frames - 1)
    );
    let path = dir.join("watch.lm");
    std::fs::write(&path, text).unwrap();
    path
}

fn lmfilm(threads: &str, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_lmfilm"))
        .env("RAYON_NUM_THREADS", threads)
        .args(args)
        .output()
        .unwrap()
}

fn ok(out: &Output) -> String {
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// `lmfilm run SCENE -o DIR --preset preview --format png [extra…]`.
fn run(threads: &str, scene: &Path, dir: &Path, extra: &[&str]) -> String {
    let mut args = vec![
        "run",
        scene.to_str().unwrap(),
        "-o",
        dir.to_str().unwrap(),
        "--preset",
        "preview",
        "--format",
        "png",
    ];
    args.extend_from_slice(extra);
    ok(&lmfilm(threads, &args))
}

/// `lmfilm render DIR --preset preview --format png --inset 0`.
fn render_inset(dir: &Path) -> String {
    let d = dir.to_str().unwrap();
    let args = ["render", d, "--preset", "preview", "--format", "png"];
    ok(&lmfilm("2", &[&args[..], &["--inset", "0"]].concat()))
}

fn png(path: &Path) -> image::RgbImage {
    image::open(path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .to_rgb8()
}

fn actor_files(dir: &Path) -> Vec<String> {
    let mut files = Vec::new();
    for a in std::fs::read_dir(dir.join("actors")).unwrap().flatten() {
        for f in std::fs::read_dir(a.path()).unwrap().flatten() {
            files.push(format!(
                "{}/{}",
                a.file_name().to_string_lossy(),
                f.file_name().to_string_lossy()
            ));
        }
    }
    files.sort();
    files
}

#[test]
fn run_writes_each_actors_vision_and_memory() {
    let dir = fresh_dir("actor-images", "write");
    let scene = scene(&dir, 3, "mem_displ_cubes");
    let out = dir.join("film");
    let said = run("2", &scene, &out, &[]);
    assert!(said.contains("3 vision and 3 memory images"), "{said}");
    let mut want = Vec::new();
    for what in ["memory", "vision"] {
        for k in 0..3 {
            want.push(format!("0/{what}.000{k}.png"));
        }
    }
    assert_eq!(actor_files(&out), want);
    for k in 0..3 {
        // 32 pixels, scaled by 8.
        let v = png(&out.join(format!("actors/0/vision.000{k}.png")));
        assert_eq!(v.dimensions(), (256, 256));
        let [r, g, b] = v.get_pixel(128, 128).0;
        assert!(
            r > 40 && u32::from(r) > 2 * u32::from(g) && u32::from(r) > 2 * u32::from(b),
            "frame {k}: the centre sees the red sphere, got {r} {g} {b}"
        );
        // Nearest neighbour: each 8 × 8 block is one colour.
        assert_eq!(v.get_pixel(128, 128), v.get_pixel(135, 135));
        let m = png(&out.join(format!("actors/0/memory.000{k}.png")));
        assert_eq!(m.dimensions(), (256, 256));
        let lit = m.pixels().filter(|p| p.0 != [0, 0, 0]).count();
        assert!(
            lit > 100,
            "frame {k}: the memory's voxels are drawn ({lit} pixels)"
        );
    }
    ok(&lmfilm("2", &["verify", out.to_str().unwrap()]));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn actor_images_are_identical_for_any_thread_count() {
    let dir = fresh_dir("actor-images", "threads");
    let scene = scene(&dir, 2, "mem_displ_points");
    let (one, two) = (dir.join("one"), dir.join("two"));
    run("1", &scene, &one, &["--inset", "0"]);
    run("2", &scene, &two, &["--inset", "0"]);
    let files = actor_files(&one);
    assert_eq!(files.len(), 4);
    assert_eq!(files, actor_files(&two));
    for f in files
        .iter()
        .map(|f| format!("actors/{f}"))
        .chain(["frames/watch.0000.png".to_string()])
    {
        assert_eq!(
            std::fs::read(one.join(&f)).unwrap(),
            std::fs::read(two.join(&f)).unwrap(),
            "{f}"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn inset_changes_the_top_left_corner_only() {
    let dir = fresh_dir("actor-images", "inset");
    let scene = scene(&dir, 2, "mem_no_displ");
    let out = dir.join("film");
    run("2", &scene, &out, &[]);
    assert_eq!(
        actor_files(&out),
        ["0/vision.0000.png", "0/vision.0001.png"]
    );
    let frame = out.join("frames/watch.0001.png");
    let plain = png(&frame);
    let said = render_inset(&out);
    // The inset is part of the frames' record: they are made again.
    assert!(said.contains("2 of 2 frames rendered now"), "{said}");
    let inset = png(&frame);
    assert_eq!(plain.dimensions(), inset.dimensions());
    // A quarter of the height, inside a 1-pixel border.
    let corner = plain.height() / 4 + 2;
    let mut changed = 0;
    for (x, y, p) in inset.enumerate_pixels() {
        if p != plain.get_pixel(x, y) {
            assert!(x < corner && y < corner, "pixel {x},{y} changed");
            changed += 1;
        }
    }
    assert!(changed > 0);
    assert_eq!(inset.get_pixel(0, 0).0, [255, 255, 255]);
    // The same inset again: up to date.
    let said = render_inset(&out);
    assert!(said.contains("0 of 2 frames rendered now"), "{said}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn inset_of_an_actor_without_a_window_is_refused() {
    let dir = fresh_dir("actor-images", "no-window");
    let scene = scene(&dir, 1, "mem_no_displ");
    let out = dir.join("film");
    ok(&lmfilm(
        "2",
        &[
            "derive",
            scene.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
        ],
    ));
    let r = lmfilm(
        "2",
        &[
            "render",
            out.to_str().unwrap(),
            "--preset",
            "preview",
            "--inset",
            "3",
        ],
    );
    assert_eq!(r.status.code(), Some(2));
    let err = String::from_utf8_lossy(&r.stderr);
    assert!(err.contains("actor 3"), "{err}");
    assert!(!out.join("frames/watch.0000.png").exists());
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn verify_checks_the_actor_images_and_reruns_prune_them() {
    let dir = fresh_dir("actor-images", "verify");
    let scene3 = scene(&dir, 3, "mem_displ_cubes");
    let out = dir.join("film");
    let o = out.to_str().unwrap();
    run("2", &scene3, &out, &[]);
    ok(&lmfilm("2", &["verify", o]));
    let vision = out.join("actors/0/vision.0001.png");
    let bytes = std::fs::read(&vision).unwrap();
    std::fs::remove_file(&vision).unwrap();
    let r = lmfilm("2", &["verify", o]);
    assert!(!r.status.success());
    assert!(String::from_utf8_lossy(&r.stderr).contains("actors/0/vision.0001.png: missing"));
    let mut altered = bytes.clone();
    let n = altered.len();
    altered[n / 2] ^= 1;
    std::fs::write(&vision, altered).unwrap();
    let r = lmfilm("2", &["verify", o]);
    assert!(!r.status.success());
    assert!(
        String::from_utf8_lossy(&r.stderr).contains("actors/0/vision.0001.png: sha256 mismatch")
    );
    // A stray file is not an output of this film.
    std::fs::write(&vision, &bytes).unwrap();
    std::fs::write(out.join("actors/0/vision.0009.png"), &bytes).unwrap();
    let r = lmfilm("2", &["verify", o]);
    assert!(String::from_utf8_lossy(&r.stderr).contains("actors/0/vision.0009.png: not an output"));
    // A shorter film without the display keeps no image of the longer one.
    let scene2 = scene(&dir, 2, "mem_no_displ");
    run("2", &scene2, &out, &[]);
    assert_eq!(
        actor_files(&out),
        ["0/vision.0000.png", "0/vision.0001.png"]
    );
    ok(&lmfilm("2", &["verify", o]));
    let _ = std::fs::remove_dir_all(&dir);
}
