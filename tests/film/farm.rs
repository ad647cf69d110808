//! `lmfilm farm slurm`: the chain's scripts, written with `--dry-run`,
//! run here by bash as Slurm would run them (each render task with its
//! SLURM_ARRAY_TASK_ID), make the same film as a local `run`.

use std::path::Path;
use std::process::Command;

fn lmfilm(args: &[&str]) -> (i32, String, String) {
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

/// Runs a job script with bash, as a Slurm task `task` would.
fn job(script: &Path, task: Option<u32>) {
    let mut cmd = Command::new("bash");
    cmd.arg(script);
    if let Some(k) = task {
        cmd.env("SLURM_ARRAY_TASK_ID", k.to_string());
    }
    let out = cmd.output().unwrap();
    assert!(
        out.status.success(),
        "{}: {}",
        script.display(),
        String::from_utf8_lossy(&out.stderr)
    );
}

const SCENE: &str = "Camera_AnimationParameters\nprefpos_x1_x2_y1_y2 0 64 0 48\n\
    observer 0 1 6\nlookatPoint 0 1 0\nt_final_interval 0.2 0.04\n\
    Axiom\nm () (4) A\nProductions\nA (0.04)\n1.0 F () () () () (0.3) A EndProb\nEnd\nEndProductions\n";

#[test]
fn the_chain_makes_the_film_a_local_run_makes() {
    let root = std::env::temp_dir().join(format!("lmfilm-farm-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&root);
    std::fs::create_dir_all(&root).unwrap();
    let scene = root.join("growing.lm");
    std::fs::write(&scene, SCENE).unwrap();
    let (s, farm, local) = (
        scene.to_str().unwrap(),
        root.join("farm_film"),
        root.join("local_film"),
    );
    let (code, out, err) = lmfilm(&[
        "farm",
        "slurm",
        s,
        "-o",
        farm.to_str().unwrap(),
        "--shards",
        "3",
        "--dry-run",
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("#SBATCH --array=1-3"), "{out}");
    assert!(out.contains("not submitted: --dry-run"), "{out}");
    let scripts = farm.join("farm");
    job(&scripts.join("derive.sh"), None);
    for k in [2, 1, 3] {
        job(&scripts.join("render.sh"), Some(k));
    }
    job(&scripts.join("finish.sh"), None);
    let (code, _, err) = lmfilm(&["run", s, "-o", local.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    // The same frames, byte for byte, and the same soundtrack.
    let frames = |d: &Path| {
        let mut v: Vec<(String, Vec<u8>)> = std::fs::read_dir(d.join("frames"))
            .unwrap()
            .map(|e| e.unwrap().path())
            .filter(|p| p.extension().is_some_and(|x| x == "png"))
            .map(|p| {
                (
                    p.file_name().unwrap().to_string_lossy().into_owned(),
                    std::fs::read(&p).unwrap(),
                )
            })
            .collect();
        v.sort();
        v
    };
    let (a, b) = (frames(&farm), frames(&local));
    assert_eq!(a.len(), 6);
    assert!(a == b, "the frames differ");
    let wav = |d: &Path| std::fs::read(d.join("soundtrack.wav")).unwrap();
    assert_eq!(wav(&farm), wav(&local));
    let (code, out, err) = lmfilm(&["verify", farm.to_str().unwrap()]);
    assert_eq!(code, 0, "{out}{err}");
    let _ = std::fs::remove_dir_all(&root);
}

#[test]
fn bad_requests_are_refused_with_exit_2() {
    let (code, _, err) = lmfilm(&[
        "farm",
        "slurm",
        "no/such.lm",
        "-o",
        "x",
        "--shards",
        "2",
        "--dry-run",
    ]);
    assert_eq!(code, 2);
    assert!(err.contains("no/such.lm: no such scene file"), "{err}");
    let (code, _, err) = lmfilm(&["farm", "status", "/no/such/film"]);
    assert_eq!(code, 2);
    assert!(err.contains("no chain was submitted"), "{err}");
}
