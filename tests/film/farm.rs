//! `lmfilm farm slurm`: the chain's scripts, written with `--dry-run`,
//! run here by bash as Slurm would run them (each render task with its
//! SLURM_ARRAY_TASK_ID), make the same film as a local `run`; hostile
//! values are refused or written as the one value they are; on a real
//! two-node Slurm (scripts/slurm_up.sh), a cancelled task is finished by
//! the finishing job and a broken node is left behind.

use std::path::Path;
use std::process::Command;

use crate::cli::lmfilm;
use crate::common::fresh_dir;

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
    let root = fresh_dir("farm", "chain");
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
    assert!(out.contains("#!/bin/bash -p\n"), "{out}");
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

/// Strings a user (or a web form in front of `farm slurm`) might type,
/// each trying to make a script run something else: `touch MARK` where
/// the shell would run it, a second `#SBATCH` option where sbatch would
/// read it.
fn hostile() -> Vec<String> {
    let mut h: Vec<String> = [
        "x; touch MARK",
        "$(touch MARK)",
        "`touch MARK`",
        "x\ntouch MARK",
        "x\n#SBATCH --export=LD_PRELOAD=MARK",
        "x\" --export=\"LD_PRELOAD=MARK",
        "x' ; touch MARK ; '",
        "x --chdir=MARK",
        "100%j %% %",
        "back\\slash",
        "-x",
        "x\rtouch MARK",
        "x\ttab",
        "ünïcödé",
        "@BIN@ @DIR@",
        "${IFS}touch${IFS}MARK",
        "'\"'\"'",
        "#comment",
        "a|touch MARK&",
        "x\u{85}y",
    ]
    .iter()
    .map(|s| s.to_string())
    .collect();
    h.push("a".repeat(300));
    h
}

/// An #SBATCH line's words as sbatch reads them: split at blanks outside
/// double quotes, `\"` and `\\` as the characters, `#` outside quotes
/// ending the line (as seen with sbatch 22.05).
fn sbatch_words(line: &str) -> Vec<String> {
    let mut words = Vec::new();
    let mut chars = line.chars().peekable();
    loop {
        while chars.peek().is_some_and(|c| c.is_whitespace()) {
            chars.next();
        }
        match chars.peek() {
            None | Some('#') => return words,
            _ => {}
        }
        let (mut word, mut quoted) = (String::new(), false);
        while let Some(&c) = chars.peek() {
            if !quoted && c.is_whitespace() {
                break;
            }
            chars.next();
            match c {
                '"' => quoted = !quoted,
                '\\' if quoted => word.extend(chars.next()),
                c => word.push(c),
            }
        }
        words.push(word);
    }
}

/// Every value a script holds, hostile, is refused at the command line
/// (exit 2, naming the option and the character) or written so that
/// bash and sbatch read it as the one value it is: the scripts, run by
/// bash with stubs for lmfilm and Slurm's commands, run the stub with
/// exactly the intended words and nothing else, and each `#SBATCH` line
/// holds one option.
#[test]
fn hostile_values_are_refused_or_written_as_one_value() {
    let root = fresh_dir("farm", "hostile");
    let (stubs, work) = (root.join("stubs"), root.join("work"));
    std::fs::create_dir_all(&stubs).unwrap();
    std::fs::create_dir_all(&work).unwrap();
    let calls = root.join("calls");
    // The stub lmfilm writes its words, NUL-separated, one call a line;
    // Slurm's commands note that they were called and fail.
    let stub = |path: &Path, body: &str| {
        std::fs::write(path, format!("#!/bin/bash\n{body}\n")).unwrap();
        use std::os::unix::fs::PermissionsExt;
        std::fs::set_permissions(path, std::fs::Permissions::from_mode(0o755)).unwrap();
    };
    let log = calls.to_str().unwrap().to_string();
    let lmfilm_stub = |path: &Path| {
        stub(
            path,
            &format!("printf '%s\\0' lmfilm \"$@\" >>'{log}'; printf '\\n' >>'{log}'"),
        )
    };
    for cmd in ["sbatch", "scontrol", "squeue", "sacct", "touch"] {
        stub(
            &stubs.join(cmd),
            &format!("printf '%s\\0' {cmd} \"$@\" >>'{log}'; printf '\\n' >>'{log}'; exit 1"),
        );
    }
    let scene_ok = root.join("growing.lm");
    std::fs::write(&scene_ok, SCENE).unwrap();
    let plain_bin = root.join("bin").join("lmfilm");
    std::fs::create_dir_all(plain_bin.parent().unwrap()).unwrap();
    lmfilm_stub(&plain_bin);
    let base = |dir: &Path, scene: &Path, bin: &Path| -> Vec<String> {
        [
            "farm",
            "slurm",
            scene.to_str().unwrap(),
            "-o",
            dir.to_str().unwrap(),
            "--shards",
            "2",
            "--dry-run",
            "--lmfilm",
            bin.to_str().unwrap(),
            "--preset",
            "preview",
            "--width",
            "32",
            "--height",
            "24",
        ]
        .iter()
        .map(|s| s.to_string())
        .collect()
    };
    let run = |args: &[String]| {
        let a: Vec<&str> = args.iter().map(String::as_str).collect();
        lmfilm(&a)
    };
    let mut checked = (0, 0);
    for (k, h) in hostile().iter().enumerate() {
        // The options sbatch reads: each refused, naming itself.
        for option in ["--partition", "--account", "--time", "--mem"] {
            let mut args = base(&root.join(format!("opt{k}")), &scene_ok, &plain_bin);
            args.push(format!("{option}={h}"));
            let (code, out, err) = run(&args);
            assert_eq!(code, 2, "{option} {h:?} was accepted: {out}{err}");
            assert!(err.contains(option), "{option} {h:?}: {err}");
            checked.0 += 1;
        }
        // The paths: the film folder, the binary, a scene.
        let name = h.replace('/', "_");
        let dir = root.join(format!("film {k} {name}"));
        let bin = root.join(format!("bin {k} {name}")).join("lmfilm");
        let scene = root.join(format!("scene {k} {name}.lm"));
        let _ = std::fs::create_dir_all(bin.parent().unwrap());
        if std::fs::write(&scene, SCENE).is_err() {
            continue; // a name this file system refuses
        }
        lmfilm_stub(&bin);
        let (code, out, err) = run(&base(&dir, &scene, &bin));
        if code != 0 {
            assert_eq!(code, 2, "{h:?}: {out}{err}");
            let named = ["-o/--output", "--lmfilm", "SCENE"]
                .iter()
                .any(|o| err.contains(o));
            assert!(
                named && err.contains("U+"),
                "{h:?}: the refusal names no option and character: {err}"
            );
            assert!(
                h.chars().any(|c| c.is_control() || c == '\\'),
                "{h:?} was refused though it can be written safely: {err}"
            );
            checked.0 += 1;
            continue;
        }
        let farm = dir.join("farm");
        for script in ["derive.sh", "render.sh", "finish.sh"] {
            let text = std::fs::read_to_string(farm.join(script)).unwrap();
            let mut lines = text.lines();
            assert_eq!(lines.next(), Some("#!/bin/bash -p"));
            for line in lines.take_while(|l| l.starts_with("#SBATCH")) {
                let words = sbatch_words(&line["#SBATCH".len()..]);
                assert_eq!(words.len(), 1, "{h:?}: {line:?} reads as {words:?}");
                if let Some(v) = words[0].strip_prefix("--output=") {
                    let want = format!("{}/farm/logs/", dir.to_str().unwrap().replace('%', "%%"));
                    assert!(v.starts_with(&want), "{h:?}: {v:?}");
                }
            }
        }
        let _ = std::fs::remove_file(&calls);
        for (script, task) in [
            ("derive.sh", None),
            ("render.sh", Some("1")),
            ("finish.sh", None),
        ] {
            let mut cmd = Command::new("bash");
            cmd.arg(farm.join(script))
                .current_dir(&work)
                .env("PATH", format!("{}:/usr/bin:/bin", stubs.display()))
                .env_remove("SLURM_JOB_ID");
            if let Some(t) = task {
                cmd.env("SLURM_ARRAY_TASK_ID", t);
            }
            let out = cmd.output().unwrap();
            assert!(
                out.status.success(),
                "{h:?} {script}: {}",
                String::from_utf8_lossy(&out.stderr)
            );
        }
        assert!(
            std::fs::read_dir(&work).unwrap().next().is_none(),
            "{h:?}: something ran in the scripts' folder"
        );
        let text = std::fs::read(&calls).unwrap();
        let got: Vec<Vec<String>> = text
            .split(|&b| b == b'\n')
            .filter(|l| !l.is_empty())
            .map(|l| {
                l.split(|&b| b == 0)
                    .filter(|w| !w.is_empty())
                    .map(|w| String::from_utf8_lossy(w).into_owned())
                    .collect()
            })
            .collect();
        let (d, s) = (
            dir.to_str().unwrap().to_string(),
            scene.to_str().unwrap().to_string(),
        );
        let programs: Vec<(&str, &str, &str)> = got
            .iter()
            .map(|c| {
                (
                    c[0].as_str(),
                    c[1].as_str(),
                    c.get(2).map_or("", String::as_str),
                )
            })
            .collect();
        let want = vec![
            ("lmfilm", "derive", s.as_str()),
            ("lmfilm", "render", d.as_str()),
            ("lmfilm", "render", d.as_str()),
            ("lmfilm", "sound", d.as_str()),
            ("lmfilm", "mux", d.as_str()),
            ("lmfilm", "verify", d.as_str()),
        ];
        assert_eq!(programs, want, "{h:?}");
        assert_eq!(&got[0][3..5], ["-o", d.as_str()], "{h:?}");
        assert_eq!(&got[1][3..6], ["--shard", "1/2", "--log-frames"], "{h:?}");
        checked.1 += 1;
    }
    println!(
        "hostile values: {} refused, {} written safely and run",
        checked.0, checked.1
    );
    assert!(checked.1 >= 10, "too few cases ran: {checked:?}");
    let _ = std::fs::remove_dir_all(&root);
}

/// Slurm refuses a chain it cannot hold before it is submitted: more
/// shards than its MaxArraySize, a partition it has not, a time beyond
/// the partition's MaxTime (the test cluster's `short` partition allows
/// 10 minutes).
#[test]
fn slurms_limits_are_said_before_submitting() {
    if !slurm_is_up("slurms_limits_are_said_before_submitting") {
        return;
    }
    let root = fresh_dir("farm", "limits");
    let scene = root.join("growing.lm");
    std::fs::write(&scene, SCENE).unwrap();
    let dir = root.join("film");
    let try_with = |extra: &[&str]| {
        let mut args = vec![
            "farm",
            "slurm",
            scene.to_str().unwrap(),
            "-o",
            dir.to_str().unwrap(),
            "--dry-run",
        ];
        args.extend(extra);
        lmfilm(&args)
    };
    let (code, _, err) = try_with(&["--shards", "5000"]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("MaxArraySize"), "{err}");
    let (code, _, err) = try_with(&["--shards", "2", "--partition", "nosuch"]);
    assert_eq!(code, 2);
    assert!(err.contains("no such partition"), "{err}");
    let (code, _, err) = try_with(&["--shards", "2", "--partition", "short", "--time", "1:00:00"]);
    assert_eq!(code, 2);
    assert!(err.contains("MaxTime"), "{err}");
    assert!(!dir.join("farm").exists(), "a refused chain wrote scripts");
    let (code, out, err) = try_with(&["--shards", "2", "--partition", "short", "--time", "5"]);
    assert_eq!(code, 0, "{out}{err}");
    let _ = std::fs::remove_dir_all(&root);
}

/// Whether the two Slurm nodes of scripts/slurm_up.sh are up here; when
/// not, the test says so and skips — but not on CI, where `.ci/run`
/// starts them: there it fails.
fn slurm_is_up(test: &str) -> bool {
    let up = Command::new("sinfo")
        .args(["-h", "-N", "-o", "%N %T"])
        .output()
        .is_ok_and(|o| {
            let text = String::from_utf8_lossy(&o.stdout);
            o.status.success()
                && text
                    .lines()
                    .filter(|l| !l.contains("down") && !l.contains("drain"))
                    .count()
                    >= 2
        });
    if !up {
        assert!(
            std::env::var("CI").as_deref() != Ok("true"),
            "{test}: no two-node Slurm is up, and on CI .ci/run starts one (scripts/slurm_up.sh)"
        );
        println!("{test}: SKIPPED — no two-node Slurm is up here (scripts/slurm_up.sh starts one)");
    }
    up
}

/// Every job of the chain in `dir`: the first three and the later ones.
fn chain_jobs(dir: &Path) -> Vec<String> {
    let farm = dir.join("farm");
    let mut ids: Vec<String> = std::fs::read_to_string(farm.join("jobs.txt"))
        .unwrap_or_default()
        .lines()
        .filter_map(|l| l.split_whitespace().nth(1).map(str::to_string))
        .collect();
    if let Ok(r) = std::fs::read_dir(farm.join("retries")) {
        ids.extend(r.filter_map(|e| {
            let name = e.ok()?.file_name().into_string().ok()?;
            Some(name.rsplit_once('@')?.1.to_string())
        }));
    }
    ids
}

/// Waits until no job of the chain in `dir` is queued (at most 5
/// minutes), later jobs included.
fn wait_for_chain(dir: &Path) {
    for _ in 0..300 {
        let out = Command::new("squeue")
            .args(["-h", "-o", "%F"])
            .output()
            .unwrap();
        let queued = String::from_utf8_lossy(&out.stdout).to_string();
        let ids = chain_jobs(dir);
        if out.status.success() && !ids.iter().any(|id| queued.lines().any(|q| q.trim() == id)) {
            return;
        }
        std::thread::sleep(std::time::Duration::from_secs(1));
    }
    panic!(
        "the chain in {} did not end within 5 minutes",
        dir.display()
    );
}

/// Submits the chain of `scene` into `dir` with `extra` options; returns
/// its job ids.
fn submit(scene: &str, dir: &Path, extra: &[&str]) -> Vec<String> {
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
        .chain(extra.iter().copied())
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

/// The frames and soundtrack of two folders are the same bytes.
fn same_film(a: &Path, b: &Path) {
    for f in [
        "soundtrack.wav",
        "frames/growing.0003.png",
        "frames/growing.0005.exr",
    ] {
        let (x, y) = (
            std::fs::read(a.join(f)).unwrap(),
            std::fs::read(b.join(f)).unwrap(),
        );
        assert!(x == y, "{f} differs");
    }
}

/// A real Slurm runs the chain; a render task cancelled before it runs
/// leaves its frames to the finishing job, which renders them: the film
/// completes, equal to a local run's; submitted again, the chain redoes
/// nothing and `farm status --watch` returns once it has ended.
#[test]
fn on_slurm_a_cancelled_task_is_finished_and_a_resubmission_resumes() {
    if !slurm_is_up("on_slurm_a_cancelled_task_is_finished_and_a_resubmission_resumes") {
        return;
    }
    let root = fresh_dir("slurm", "chain");
    let scene = root.join("growing.lm");
    std::fs::write(&scene, SCENE).unwrap();
    let s = scene.to_str().unwrap();
    let (film, local) = (root.join("film"), root.join("local"));
    let ids = submit(s, &film, &[]);
    // The render tasks wait for the derivation: task 2 is still pending.
    let task = format!("{}_2", ids[1]);
    assert!(Command::new("scancel")
        .arg(&task)
        .status()
        .unwrap()
        .success());
    wait_for_chain(&film);
    let (code, out, err) = lmfilm(&["verify", film.to_str().unwrap()]);
    assert_eq!(code, 0, "{out}{err}");
    let finish_logs: String = std::fs::read_dir(film.join("farm/logs"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| {
            p.file_name()
                .unwrap()
                .to_string_lossy()
                .starts_with("finish-")
        })
        .map(|p| std::fs::read_to_string(p).unwrap())
        .collect();
    // Shard 2 of 3 holds frames 1 and 4: the finish rendered them (unless
    // the task had already run when it was cancelled).
    let ran = film.join(format!("farm/logs/render-{task}.out")).exists();
    assert!(
        ran || finish_logs.contains("frame 1 (2/6): rendered"),
        "{finish_logs}"
    );
    assert!(
        finish_logs.contains("frame 0 (1/6): up to date"),
        "{finish_logs}"
    );
    let (code, _, err) = run_locally(s, &local);
    assert_eq!(code, 0, "{err}");
    same_film(&film, &local);
    // Submitted again: every stage finds its work done.
    let before = std::fs::read(film.join("frames/growing.0002.png")).unwrap();
    submit(s, &film, &[]);
    wait_for_chain(&film);
    let (code, out, err) = lmfilm(&["verify", film.to_str().unwrap()]);
    assert_eq!(code, 0, "{out}{err}");
    assert_eq!(
        std::fs::read(film.join("frames/growing.0002.png")).unwrap(),
        before
    );
    let (code, out, err) = lmfilm(&["farm", "status", film.to_str().unwrap(), "--watch", "1"]);
    assert_eq!(code, 0, "{err}");
    assert!(
        out.contains("6/6 rendered") && out.contains("film: finished"),
        "{out}"
    );
    assert!(out.contains("last frame: "), "{out}");
    let _ = std::fs::remove_dir_all(&root);
}

/// Two nodes, one broken (its lmfilm fails every task: here a wrapper
/// that exits 1 on it), the film folder's name hostile to the scripts:
/// every job that lands on the broken node goes again to the other, the
/// film completes and verifies, equal to a local run's, and `farm
/// status` names the broken node, its failures and their log lines.
#[test]
fn on_two_nodes_a_broken_node_is_left_behind() {
    if !slurm_is_up("on_two_nodes_a_broken_node_is_left_behind") {
        return;
    }
    let root = fresh_dir("slurm", "bad");
    let scene = root.join("growing.lm");
    std::fs::write(&scene, SCENE).unwrap();
    let s = scene.to_str().unwrap();
    let out = Command::new("sinfo")
        .args(["-h", "-N", "-o", "%N"])
        .output()
        .unwrap();
    let nodes = String::from_utf8_lossy(&out.stdout).to_string();
    let bad = nodes.lines().next().unwrap().trim().to_string();
    let wrapper = root.join("lmfilm");
    std::fs::write(
        &wrapper,
        format!(
            "#!/bin/bash\nif [ \"${{SLURMD_NODENAME:-}}\" = {bad} ]; then echo \"lmfilm: cannot run on this node\" >&2; exit 1; fi\nexec '{}' \"$@\"\n",
            env!("CARGO_BIN_EXE_lmfilm")
        ),
    )
    .unwrap();
    use std::os::unix::fs::PermissionsExt;
    std::fs::set_permissions(&wrapper, std::fs::Permissions::from_mode(0o755)).unwrap();
    let film = root.join("film \"it's\" 100% $(touch x) `y`");
    submit(s, &film, &["--lmfilm", wrapper.to_str().unwrap()]);
    wait_for_chain(&film);
    let (code, out, err) = lmfilm(&["verify", film.to_str().unwrap()]);
    assert_eq!(code, 0, "{out}{err}");
    let local = root.join("local");
    let (code, _, err) = run_locally(s, &local);
    assert_eq!(code, 0, "{err}");
    same_film(&film, &local);
    // The logs are where the scripts put them, in the hostile folder.
    let logs: Vec<String> = std::fs::read_dir(film.join("farm/logs"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert!(logs.iter().any(|l| l.starts_with("render-")), "{logs:?}");
    let failed: Vec<String> = std::fs::read_dir(film.join("farm/failed"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert!(!failed.is_empty(), "no job landed on {bad}");
    assert!(
        failed.iter().all(|f| f.contains(&format!("@{bad}@"))),
        "{failed:?}"
    );
    let (code, out, err) = lmfilm(&["farm", "status", film.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("film: finished"), "{out}");
    assert!(
        out.contains("nodes that failed:") && out.contains(&format!("  {bad}: ")),
        "{out}"
    );
    assert!(out.contains("lmfilm: cannot run on this node"), "{out}");
    let _ = std::fs::remove_dir_all(&root);
}

/// `farm status` over a folder whose files are hostile: each file it
/// reads (the chain's job ids, a failure's note, a job's log, the last
/// frame's record and PNG) made a link to an endless device, a pipe and
/// a folder in turn. It answers within seconds every time — refusing,
/// naming the file, when the job ids cannot be read, else saying what it
/// could not read — and changes nothing in the folder.
#[test]
fn farm_status_never_waits_on_a_hostile_file() {
    let root = fresh_dir("farm", "hostile-status");
    let scene = root.join("growing.lm");
    std::fs::write(&scene, SCENE).unwrap();
    let film = root.join("film");
    let (code, _, err) = run_locally(scene.to_str().unwrap(), &film);
    assert_eq!(code, 0, "{err}");
    let farm = film.join("farm");
    std::fs::create_dir_all(farm.join("failed")).unwrap();
    std::fs::create_dir_all(farm.join("logs")).unwrap();
    let log = farm.join("logs/render-3_1.out");
    std::fs::write(&log, "lmfilm-render: shard 1/3\nerror: disk full\n").unwrap();
    std::fs::write(farm.join("jobs.txt"), "derive 2\nrender 3\nfinish 4\n").unwrap();
    let note = farm.join("failed/render-1@node1@5");
    std::fs::write(&note, format!("exit 1\nlog {}\n", log.display())).unwrap();
    // The newest record is the last frame's: the one status previews.
    let newest = (0..6)
        .map(|k| film.join(format!("frames/growing.{k:04}.json")))
        .max_by_key(|p| std::fs::metadata(p).unwrap().modified().unwrap())
        .unwrap();
    let png = newest.with_extension("png");
    let f = film.to_str().unwrap();
    let status = || crate::limits::lmfilm(&["farm", "status", f], 20);
    let (code, out, err) = lmfilm(&["farm", "status", f]);
    assert_eq!(code, 0, "{err}");
    assert!(
        out.contains("error: disk full") && out.contains("  node1: 1 failed job"),
        "{out}"
    );
    let snapshot = |d: &Path| -> Vec<(std::path::PathBuf, Vec<u8>)> {
        let mut v = Vec::new();
        for sub in ["frames", "scene"] {
            for e in std::fs::read_dir(d.join(sub)).unwrap() {
                let p = e.unwrap().path();
                if p.is_file() {
                    v.push((p.clone(), std::fs::read(&p).unwrap()));
                }
            }
        }
        v.sort();
        v
    };
    for file in [
        farm.join("jobs.txt"),
        note.clone(),
        log.clone(),
        newest.clone(),
        png.clone(),
    ] {
        let kept = std::fs::read(&file).unwrap();
        let before: Vec<_> = snapshot(&film)
            .into_iter()
            .filter(|(p, _)| *p != file)
            .collect();
        for kind in ["device", "pipe", "folder"] {
            std::fs::remove_file(&file).unwrap();
            match kind {
                "device" => std::os::unix::fs::symlink("/dev/zero", &file).unwrap(),
                "pipe" => assert!(Command::new("mkfifo")
                    .arg(&file)
                    .status()
                    .unwrap()
                    .success()),
                _ => std::fs::create_dir(&file).unwrap(),
            }
            let (code, err) = status();
            if file.ends_with("jobs.txt") {
                assert_eq!(code, 2, "{kind}: {err}");
                assert!(err.contains("jobs.txt"), "{kind}: {err}");
            } else {
                assert_eq!(code, 0, "{kind} {}: {err}", file.display());
            }
            match kind {
                "folder" => std::fs::remove_dir(&file).unwrap(),
                _ => std::fs::remove_file(&file).unwrap(),
            }
            std::fs::write(&file, &kept).unwrap();
            let after: Vec<_> = snapshot(&film)
                .into_iter()
                .filter(|(p, _)| *p != file)
                .collect();
            assert!(
                before == after,
                "{kind} {}: the folder changed",
                file.display()
            );
        }
    }
    let _ = std::fs::remove_dir_all(&root);
}
