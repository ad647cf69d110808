//! `lmfilm farm slurm`: the chain's scripts, written with `--dry-run`,
//! run here by bash as Slurm would run them (each render task with its
//! SLURM_ARRAY_TASK_ID), make the same film as a local `run`.

use std::path::Path;
use std::process::Command;

use crate::cli::lmfilm;

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

/// The film's settings a chain is submitted with, and a local run too.
const SETTINGS: [&str; 8] = [
    "--preset",
    "preview",
    "--width",
    "96",
    "--height",
    "72",
    "--loudness",
    "-20",
];

/// `lmfilm run SCENE -o DIR` with [`SETTINGS`].
fn run_locally(scene: &str, dir: &Path) -> (i32, String, String) {
    let mut args = vec!["run", scene, "-o", dir.to_str().unwrap()];
    args.extend(SETTINGS);
    lmfilm(&args)
}

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
    let (code, out, err) = lmfilm(
        &[
            "farm",
            "slurm",
            s,
            "-o",
            farm.to_str().unwrap(),
            "--shards",
            "3",
            "--dry-run",
        ]
        .into_iter()
        .chain(SETTINGS.iter().copied())
        .collect::<Vec<_>>(),
    );
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("#SBATCH --array=1-3"), "{out}");
    assert!(
        out.contains("'--preset=preview'") && out.contains("'--width=96'"),
        "{out}"
    );
    assert!(out.contains("'--loudness=-20'"), "{out}");
    assert!(out.contains("not submitted: --dry-run"), "{out}");
    let scripts = farm.join("farm");
    job(&scripts.join("derive.sh"), None);
    for k in [2, 1, 3] {
        job(&scripts.join("render.sh"), Some(k));
    }
    job(&scripts.join("finish.sh"), None);
    let (code, _, err) = run_locally(s, &local);
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
    let record = std::fs::read_to_string(farm.join("frames/growing.0002.json")).unwrap();
    assert!(
        record.contains("\"width\": \"96\"") && record.contains("\"preset\": \"preview\""),
        "{record}"
    );
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

/// Whether a Slurm node is up here (scripts/slurm_up.sh starts one);
/// when not, the test says so and skips.
fn slurm_is_up(test: &str) -> bool {
    let up = Command::new("sinfo")
        .args(["-h", "-o", "%T"])
        .output()
        .is_ok_and(|o| o.status.success() && String::from_utf8_lossy(&o.stdout).contains("idle"));
    if !up {
        println!("{test}: SKIPPED — no Slurm node is up here (scripts/slurm_up.sh starts one)");
    }
    up
}

/// Waits until none of the jobs is queued any more (at most 5 minutes).
fn wait_for(ids: &[String]) {
    for _ in 0..300 {
        let out = Command::new("squeue")
            .args(["-h", "-o", "%i", "-j", &ids.join(",")])
            .output()
            .unwrap();
        if String::from_utf8_lossy(&out.stdout).trim().is_empty() {
            return;
        }
        std::thread::sleep(std::time::Duration::from_secs(1));
    }
    panic!("the chain {ids:?} did not end within 5 minutes");
}

/// Submits the chain of `scene` into `dir`; returns its job ids.
fn submit(scene: &str, dir: &Path) -> Vec<String> {
    let (code, out, err) = lmfilm(
        &[
            "farm",
            "slurm",
            scene,
            "-o",
            dir.to_str().unwrap(),
            "--shards",
            "3",
        ]
        .into_iter()
        .chain(SETTINGS.iter().copied())
        .collect::<Vec<_>>(),
    );
    assert_eq!(code, 0, "{out}{err}");
    let ids: Vec<String> = out
        .lines()
        .filter_map(|l| l.split("job ").nth(1))
        .map(|r| r.split_whitespace().next().unwrap().to_string())
        .collect();
    assert_eq!(ids.len(), 3, "{out}");
    ids
}

/// A real Slurm runs the chain; a render task cancelled before it runs
/// keeps the chain from finishing (the folder is incomplete, never
/// reported complete), and submitting again completes the same film.
#[test]
fn on_slurm_the_chain_finishes_resumes_and_matches_a_local_run() {
    if !slurm_is_up("on_slurm_the_chain_finishes_resumes_and_matches_a_local_run") {
        return;
    }
    let root = std::env::temp_dir().join(format!("lmfilm-slurm-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&root);
    std::fs::create_dir_all(&root).unwrap();
    let scene = root.join("growing.lm");
    std::fs::write(&scene, SCENE).unwrap();
    let s = scene.to_str().unwrap();
    let (film, local) = (root.join("film"), root.join("local"));
    // The chain held, a render task cancelled, then released.
    let ids = submit(s, &film);
    let task = format!("{}_2", ids[1]);
    assert!(Command::new("scancel")
        .arg(&task)
        .status()
        .unwrap()
        .success());
    // The finishing job can never run now: Slurm keeps it pending.
    std::thread::sleep(std::time::Duration::from_secs(3));
    Command::new("scancel").arg(&ids[2]).status().unwrap();
    wait_for(&ids);
    assert!(
        !film.join("soundtrack.wav").exists(),
        "a cancelled chain finished"
    );
    let (code, out, _) = lmfilm(&["verify", film.to_str().unwrap()]);
    assert_ne!(code, 0, "a cancelled chain verified: {out}");
    // Submitted again, it completes.
    let ids = submit(s, &film);
    wait_for(&ids);
    let (code, out, err) = lmfilm(&["verify", film.to_str().unwrap()]);
    assert_eq!(code, 0, "{out}{err}");
    let (code, out, err) = lmfilm(&["farm", "status", film.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    assert!(
        out.contains("6/6 rendered") && out.contains("film: finished"),
        "{out}"
    );
    let (code, _, err) = run_locally(s, &local);
    assert_eq!(code, 0, "{err}");
    for f in [
        "soundtrack.wav",
        "frames/growing.0003.png",
        "frames/growing.0005.exr",
    ] {
        let (a, b) = (
            std::fs::read(film.join(f)).unwrap(),
            std::fs::read(local.join(f)).unwrap(),
        );
        assert!(a == b, "{f} differs");
    }
    let _ = std::fs::remove_dir_all(&root);
}
