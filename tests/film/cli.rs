//! The command line end to end on real scenes.

use std::process::Command;

/// Runs lmfilm with `args`: exit code, stdout, stderr.
pub(crate) fn lmfilm(args: &[&str]) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_lmfilm"))
        .args(args)
        .output()
        .unwrap();
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn query_positions_feed_back_into_the_derivation() {
    // A walker moves 1 per frame through its persistent state table; its
    // query symbol is replaced by T once the turtle has passed x = 2.5.
    let dir = std::env::temp_dir().join(format!("lmfilm-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("walker.lm");
    std::fs::write(
        &file,
        "Camera_AnimationParameters\nt_final_interval 10 1\nAxiom\n[ ] () (1) (1) f () () () () (1) [ () (1) (1) ? ]\n\
         Productions\n? (0) [(x 2.5 -)>]\n1 T EndProb\nEnd\nEndProductions\n",
    )
    .unwrap();
    let f = file.to_str().unwrap();
    let (code, out, err) = lmfilm(&["print", f, "--frame", "2", "--format", "full"]);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("?(2,3,0,0,0,0,0)"), "{out}");
    let (_, out, _) = lmfilm(&["print", f, "--frame", "4"]);
    assert_eq!(out, "[]f[T]\n");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn help_lists_every_command_with_an_example() {
    let (code, out, _) = lmfilm(&["--help"]);
    assert_eq!(code, 0);
    for cmd in ["print", "export", "still", "watch"] {
        assert!(out.contains(cmd), "{out}");
        let (_, sub, _) = lmfilm(&[cmd, "--help"]);
        assert!(sub.contains(&format!("lmfilm {cmd} scenes/")), "{sub}");
    }
}

#[test]
fn help_shows_each_example_on_its_own_line() {
    for cmd in ["run", "sound", "derive", "still", "export"] {
        let (code, sub, _) = lmfilm(&[cmd, "--help"]);
        assert_eq!(code, 0);
        for line in sub.lines() {
            assert!(line.matches("lmfilm ").count() <= 1, "{cmd}: {line}");
        }
    }
    let (_, run, _) = lmfilm(&["run", "--help"]);
    assert!(
        run.contains("Usage: lmfilm run [OPTIONS] [SCENE.lm]..."),
        "{run}"
    );
    assert!(run.lines().any(|l| l.trim() == "lmfilm run"), "{run}");
}

#[test]
fn export_writes_obj_and_mtl() {
    let dir = std::env::temp_dir().join(format!("lmfilm-cli-exp-{}", std::process::id()));
    let out = dir.join("sub/tree.obj");
    let scene = format!(
        "{}/scenes/examples/growing_tree_drawn.lm",
        env!("CARGO_MANIFEST_DIR")
    );
    let (code, said, err) = lmfilm(&[
        "export",
        &scene,
        "--time",
        "1.5",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    // It says what it wrote.
    let mtl = dir.join("sub/tree.mtl");
    assert_eq!(said, format!("{}, {}\n", out.display(), mtl.display()));
    let obj = std::fs::read_to_string(&out).unwrap();
    assert!(obj.contains("mtllib tree.mtl"));
    assert!(dir.join("sub/tree.mtl").exists());
    // Three segments: the trunk reaches y = 6.5.
    let top = obj
        .lines()
        .filter_map(|l| l.strip_prefix("v "))
        .map(|v| v.split_whitespace().nth(1).unwrap().parse::<f64>().unwrap())
        .fold(f64::MIN, f64::max);
    assert!((top - 6.525).abs() < 0.01, "{top}");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn still_writes_png_and_exr_identically_for_any_thread_count() {
    let dir = std::env::temp_dir().join(format!("lmfilm-cli-still-{}", std::process::id()));
    let scene = format!("{}/scenes/examples/gallery.lm", env!("CARGO_MANIFEST_DIR"));
    let mut exr = Vec::new();
    for threads in ["1", "2"] {
        for ext in ["png", "exr"] {
            let out = dir.join(format!("g{threads}.{ext}"));
            let st = Command::new(env!("CARGO_BIN_EXE_lmfilm"))
                .env("RAYON_NUM_THREADS", threads)
                .args([
                    "still",
                    &scene,
                    "--width",
                    "80",
                    "--height",
                    "45",
                    "--spp",
                    "2",
                    "-o",
                    out.to_str().unwrap(),
                ])
                .status()
                .unwrap();
            assert!(st.success());
        }
        exr.push(std::fs::read(dir.join(format!("g{threads}.exr"))).unwrap());
        assert_eq!(
            std::fs::read(dir.join("g1.png")).unwrap(),
            std::fs::read(dir.join(format!("g{threads}.png"))).unwrap()
        );
    }
    assert_eq!(exr[0], exr[1], "EXR bytes identical for 1 and 2 threads");
    let img = lmfilm::render::output::read_exr_layers(&dir.join("g1.exr")).unwrap();
    assert_eq!((img.width, img.height), (80, 45));
    assert!(img.depth.iter().any(|d| d.is_finite()) && img.object.iter().any(|&o| o != u32::MAX));
    // It says what it wrote.
    let small = dir.join("small.png");
    let (code, said, err) = lmfilm(&[
        "still",
        &scene,
        "--width",
        "8",
        "--height",
        "6",
        "--preset",
        "preview",
        "-o",
        small.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    assert_eq!(said, format!("{} (8×6, 1 spp)\n", small.display()));
    let (code, _, err) = lmfilm(&["still", &scene, "-o", dir.join("x.jpg").to_str().unwrap()]);
    assert_eq!(code, 2);
    assert!(err.contains(".png or .exr"), "{err}");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn turtle_warnings_are_located_said_once_and_only_when_drawing() {
    let dir = std::env::temp_dir().join(format!("lmfilm-cli-warn-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("flat.lm");
    // Every step adds a cube of negative size made by the production's
    // text at line 7, column 5.
    std::fs::write(
        &file,
        "Camera_AnimationParameters\nt_final_interval 0.2 0.04\nAxiom\nF\nProductions\nF (0)\n1.0 c () () () () (1_) (1) (1) F EndProb\nEnd\nEndProductions\n",
    )
    .unwrap();
    let f = file.to_str().unwrap();
    let warnings = |err: &str| -> Vec<String> {
        err.lines()
            .filter(|l| l.contains("warning"))
            .map(str::to_string)
            .collect()
    };
    let want = format!("{f}:7:5: warning: `c` with a size < 0 or not a number is skipped");
    let obj = dir.join("x.obj");
    let (code, _, err) = lmfilm(&["export", f, "--frame", "3", "-o", obj.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    assert_eq!(warnings(&err), std::slice::from_ref(&want), "{err}");
    let out = dir.join("film");
    let (code, _, err) = lmfilm(&["derive", f, "-o", out.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    assert_eq!(warnings(&err), [want], "once for the whole film: {err}");
    // `print` draws nothing, so it warns of nothing drawn.
    let (code, _, err) = lmfilm(&["print", f, "--frame", "3"]);
    assert_eq!(code, 0, "{err}");
    assert!(warnings(&err).is_empty(), "{err}");
    std::fs::remove_dir_all(&dir).ok();
}
