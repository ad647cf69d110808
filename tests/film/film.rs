//! The film driver end to end (issue 6): run, derive, render shards,
//! sound, verify, resume after a kill, thread-count independence.

use crate::common;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::time::{Duration, Instant};

const SCENE: &str = "/* a short film for the tests: 1 s, a box flying past with its sound */
Camera_AnimationParameters
prefpos_x1_x2_y1_y2 0 64 0 36
observer 0 2 20
lookatPoint 0 2 0
viewAngle 500
t_final_interval 1.0 0.04
Axiom
D () (15) m () (1) D () (2) () () (0)
[ f () () () (2) (T 20 * 10 -) (3) (0) T () (1) () () (6) (1) m () (4) c () () () () (2) (1) (1) ]
Productions
T (0)
1.0 T () (2) () () (1) EndProb
End
EndProductions
";

fn temp(name: &str) -> PathBuf {
    common::fresh_dir("film", name)
}

fn lmfilm(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_lmfilm"))
        .args(args)
        .output()
        .unwrap()
}

fn ok(args: &[&str]) -> Output {
    let out = lmfilm(args);
    assert!(
        out.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    out
}

fn scene_in(dir: &Path) -> String {
    let p = dir.join("flight.lm");
    std::fs::write(&p, SCENE).unwrap();
    p.to_str().unwrap().to_string()
}

fn manifest(dir: &Path) -> String {
    std::fs::read_to_string(dir.join("manifest.json")).unwrap()
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

#[test]
fn any_thread_count_and_any_shard_split_give_the_same_film() {
    let root = temp("same");
    let scene = scene_in(&root);
    let (one, two, split) = (root.join("one"), root.join("two"), root.join("split"));
    let said = ok(&["run", &scene, "-o", s(&one), "--threads", "1"]);
    ok(&["run", &scene, "-o", s(&two), "--threads", "2"]);
    assert_eq!(manifest(&one), manifest(&two));
    // The video encoded while the frames rendered, every group of it;
    // the split film's `mux` below encodes it from the PNGs.
    let said = String::from_utf8_lossy(&said.stdout).to_string();
    let groups = said
        .lines()
        .find_map(|l| l.strip_prefix("video: "))
        .unwrap_or_else(|| panic!("{said}"));
    let words: Vec<&str> = groups.split(' ').collect();
    assert_eq!((words[0], words[1]), (words[2], "of"), "{said}");
    assert!(words[0].parse::<u32>().unwrap() > 0, "{said}");
    // derive + two shards (in any order) + sound = run.
    ok(&["derive", &scene, "-o", s(&split)]);
    ok(&["render", s(&split), "--shard", "2/2"]);
    ok(&["render", s(&split), "--shard", "1/2"]);
    ok(&["sound", s(&split)]);
    ok(&["mux", s(&split)]);
    // The same bytes, the video's included, at 1 and 2 threads and split
    // in shards.
    assert_eq!(manifest(&one), manifest(&split));
    assert!(manifest(&one).contains("flight.mp4"));
    let m = manifest(&one);
    // The EXR master, its PNG and the frame's record.
    assert_eq!(m.matches("frames/flight.").count(), 3 * 26, "{m}");
    assert_eq!(m.matches("scene/").count(), 26);
    assert!(m.contains("soundtrack.wav") && m.contains("soundtrack.events"));
    // frames × Δt × rate samples, one channel (the camera's microphone).
    let wav = hound::WavReader::open(one.join("soundtrack.wav")).unwrap();
    assert_eq!(wav.duration(), 26 * 1920);
    ok(&["verify", s(&one)]);
    // run ends with the MP4, made without ffmpeg.
    assert!(one.join("flight.mp4").exists());
    std::fs::remove_dir_all(&root).unwrap();
}

/// A denoised film (issue 57): the same bytes at 1 and 2 threads and in
/// shards; its frames' records say so (a film not denoised records
/// nothing new); its EXR masters keep the colour as rendered and the
/// albedo beside the denoised colour.
#[test]
fn a_denoised_film_is_the_same_for_any_split() {
    let root = temp("denoised");
    let scene = scene_in(&root);
    let (one, two, split) = (root.join("one"), root.join("two"), root.join("split"));
    let look = ["--integrator", "path", "--spp", "2", "--denoise", "on"];
    fn with<'a>(args: &[&'a str], look: &[&'a str]) -> Vec<&'a str> {
        [args, look].concat()
    }
    ok(&with(
        &["run", &scene, "-o", s(&one), "--threads", "1"],
        &look,
    ));
    ok(&with(
        &["run", &scene, "-o", s(&two), "--threads", "2"],
        &look,
    ));
    assert_eq!(manifest(&one), manifest(&two));
    ok(&["derive", &scene, "-o", s(&split)]);
    ok(&with(&["render", s(&split), "--shard", "2/2"], &look));
    ok(&with(&["render", s(&split), "--shard", "1/2"], &look));
    ok(&["sound", s(&split)]);
    ok(&["mux", s(&split)]);
    assert_eq!(manifest(&one), manifest(&split));
    let record = std::fs::read_to_string(one.join("frames/flight.0003.json")).unwrap();
    assert!(record.contains("\"denoise\": \"true\""), "{record}");
    let exr = lmfilm::render::output::read_exr_layers(&one.join("frames/flight.0003.exr")).unwrap();
    let noisy = exr.noisy.expect("the colour as rendered");
    assert_ne!(noisy, exr.rgba, "denoised");
    assert!(exr.albedo.iter().any(|a| *a != [1.0; 3]), "the albedo");
    ok(&["verify", s(&one)]);
    // Without the denoiser, nothing of it in the records.
    let plain = root.join("plain");
    ok(&["run", &scene, "-o", s(&plain), "--preset", "preview"]);
    let record = std::fs::read_to_string(plain.join("frames/flight.0003.json")).unwrap();
    assert!(!record.contains("denoise"), "{record}");
    std::fs::remove_dir_all(&root).unwrap();
}

/// `--timings` says where the time went (issue 45): each stage of the
/// pipeline, and under the frame loop each actor's vision; `derive`
/// gives its own part.
#[test]
fn timings_name_every_stage_and_each_actor_s_vision() {
    let root = temp("timings");
    let scene = format!(
        "{}/scenes/actors/flower_room.lm",
        env!("CARGO_MANIFEST_DIR")
    );
    let stderr = |out: Output| String::from_utf8_lossy(&out.stderr).to_string();
    let dir = root.join("film");
    let run = ok(&[
        "run",
        &scene,
        "-o",
        s(&dir),
        "--frames",
        "0..2",
        "--timings",
    ]);
    let said = stderr(run);
    for stage in [
        "derive (frame loop)",
        "actor 0's vision",
        "actor images",
        "render",
        "encode EXR",
        "encode PNG",
        "hash and record",
    ] {
        assert!(said.contains(stage), "{stage}: {said}");
    }
    let derived = ok(&[
        "derive",
        &scene,
        "-o",
        s(&root.join("derived")),
        "--timings",
    ]);
    let said = stderr(derived);
    assert!(
        said.contains("actor 0's vision") && !said.contains("render"),
        "{said}"
    );
    std::fs::remove_dir_all(&root).unwrap();
}

#[test]
fn a_killed_run_resumes_to_the_same_bytes() {
    let root = temp("kill");
    let scene = scene_in(&root);
    let (clean, killed) = (root.join("clean"), root.join("killed"));
    let big = ["--width", "320", "--height", "180"];
    ok(&[&["run", &scene, "-o", s(&clean)], &big[..]].concat());
    let mut child = Command::new(env!("CARGO_BIN_EXE_lmfilm"))
        .args([&["run", &scene, "-o", s(&killed)], &big[..]].concat())
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    // Kill it once a few frames are on disk (or when it is done).
    let start = Instant::now();
    loop {
        let n = std::fs::read_dir(killed.join("frames")).map_or(0, |d| d.count());
        if n >= 3 || start.elapsed() > Duration::from_secs(60) {
            break;
        }
        if child.try_wait().unwrap().is_some() {
            break;
        }
        std::thread::sleep(Duration::from_millis(5));
    }
    child.kill().ok(); // SIGKILL
    child.wait().unwrap();
    ok(&[&["run", &scene, "-o", s(&killed)], &big[..]].concat());
    assert_eq!(manifest(&clean), manifest(&killed));
    // No temporary files are left behind.
    for d in ["frames", "scene"] {
        for e in std::fs::read_dir(killed.join(d)).unwrap() {
            let name = e.unwrap().file_name().into_string().unwrap();
            let ours = [".png", ".exr", ".json", ".snap"];
            assert!(ours.iter().any(|e| name.ends_with(e)), "{name}");
        }
    }
    std::fs::remove_dir_all(&root).unwrap();
}

#[test]
fn verify_names_a_flipped_byte_and_a_missing_frame() {
    let root = temp("verify");
    let scene = scene_in(&root);
    let dir = root.join("film");
    ok(&["run", &scene, "-o", s(&dir), "--preset", "preview"]);
    let frame = dir.join("frames/flight.0003.png");
    let mut bytes = std::fs::read(&frame).unwrap();
    let k = bytes.len() / 2;
    bytes[k] ^= 1;
    std::fs::write(&frame, bytes).unwrap();
    std::fs::remove_file(dir.join("frames/flight.0007.png")).unwrap();
    let out = lmfilm(&["verify", s(&dir)]);
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("flight.0003.png") && err.contains("flight.0007.png"),
        "{err}"
    );
    std::fs::remove_dir_all(&root).unwrap();
}

#[test]
fn bad_input_says_what_to_do() {
    let root = temp("bad");
    let scene = scene_in(&root);
    // A missing scene.
    let out = lmfilm(&["run", s(&root.join("nope.lm")), "-o", s(&root.join("x"))]);
    assert_eq!(out.status.code(), Some(2));
    // A folder that was never derived.
    let out = lmfilm(&["render", s(&root)]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("lmfilm derive"));
    // A snapshot from another program version.
    let dir = root.join("film");
    ok(&["derive", &scene, "-o", s(&dir)]);
    let snap = dir.join("scene/0002.snap");
    let mut bytes = std::fs::read(&snap).unwrap();
    bytes[8] = bytes[8].wrapping_add(1); // the version field after the magic
    std::fs::write(&snap, bytes).unwrap();
    let out = lmfilm(&["render", s(&dir), "--frames", "2..3"]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("0002.snap") && err.contains("lmfilm derive"),
        "{err}"
    );
    // An MP4 needs every frame: `run --frames` says it made none, `mux`
    // refuses a folder with frames still to render.
    let part = root.join("part");
    let out = ok(&[
        "run",
        &scene,
        "-o",
        s(&part),
        "--frames",
        "1..2",
        "--preset",
        "preview",
    ]);
    let said = String::from_utf8_lossy(&out.stdout);
    assert!(
        said.contains("no MP4") && !part.join("film.mp4").exists(),
        "{said}"
    );
    let out = lmfilm(&["mux", s(&part)]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("frame 0 has no image"));
    // Bad ranges and shards.
    for bad in [["--frames", "3..1"], ["--shard", "3/2"]] {
        let out = lmfilm(&[&["render", s(&dir)], &bad[..]].concat());
        assert_eq!(out.status.code(), Some(2), "{bad:?}");
    }
    // A scene that declares a script does not run without consent.
    let cmd = root.join("cmd.lm");
    std::fs::write(
        &cmd,
        SCENE.replace("Axiom", "Options\ncommand_file 1 touch.sh a b\nAxiom"),
    )
    .unwrap();
    let out = lmfilm(&["derive", s(&cmd), "-o", s(&root.join("c"))]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("--allow-commands"));
    std::fs::remove_dir_all(&root).unwrap();
}

#[test]
fn trace_lists_each_frame_as_json() {
    let root = temp("trace");
    let scene = scene_in(&root);
    let out = ok(&["trace", &scene, "--frames", "0..3"]);
    let text = String::from_utf8(out.stdout).unwrap();
    let lines: Vec<serde_json::Value> = text
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    assert_eq!(lines.len(), 3);
    assert_eq!(lines[1]["frame"], 1);
    assert_eq!(lines[1]["time"], 0.04);
    assert_eq!(lines[0]["sound_events"][0]["sound"], 6);
    assert_eq!(lines[0]["sound_events"][0]["pos"][0], -10.0);
    assert!(lines[1]["sound_events"].as_array().unwrap().is_empty());
    std::fs::remove_dir_all(&root).unwrap();
}

/// With consent, `E` runs its script each frame with the thesis's
/// arguments: frame number, the two declared words, three integers.
#[cfg(unix)]
#[test]
fn allowed_scripts_run_with_the_frame_number() {
    use std::os::unix::fs::PermissionsExt;
    let root = temp("script");
    let script = root.join("log.sh");
    std::fs::write(&script, "#!/bin/sh\necho \"$@\" >> calls.txt\n").unwrap();
    std::fs::set_permissions(&script, std::fs::Permissions::from_mode(0o755)).unwrap();
    let scene = root.join("e.lm");
    std::fs::write(
        &scene,
        "Camera_AnimationParameters\nt_final_interval 0.12 0.04\nOptions\ncommand_file 1 log.sh tape one\nAxiom\nE () (1) (1) () (4) (5.7) (6)\n",
    )
    .unwrap();
    ok(&[
        "derive",
        s(&scene),
        "-o",
        s(&root.join("out")),
        "--allow-commands",
    ]);
    let calls = std::fs::read_to_string(root.join("calls.txt")).unwrap();
    assert_eq!(
        calls,
        "0 tape one 4 5 6\n1 tape one 4 5 6\n2 tape one 4 5 6\n3 tape one 4 5 6\n"
    );
    std::fs::remove_dir_all(&root).unwrap();
}

/// `rs_file_path_name` names the folder and the frames, `rs_switch` picks
/// the frames to ray-trace; the command line overrides both.
#[test]
fn rs_options_choose_folder_name_and_frames() {
    let root = temp("rs");
    let out = root.join("shots");
    let scene = root.join("rs.lm");
    std::fs::write(
        &scene,
        SCENE.replace(
            "Axiom",
            &format!(
                "Options\nrs_file_path_name {} shot\nrs_switch 2 4\nAxiom",
                out.display()
            ),
        ),
    )
    .unwrap();
    ok(&["run", s(&scene), "--preset", "preview"]);
    let mut frames: Vec<String> = std::fs::read_dir(out.join("frames"))
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .collect();
    frames.sort();
    let want: Vec<String> = (2..=4)
        .flat_map(|k| ["exr", "json", "png"].map(|e| format!("shot.{k:04}.{e}")))
        .collect();
    assert_eq!(frames, want);
    // Every frame is still derived: 26 snapshots, the whole soundtrack.
    assert_eq!(std::fs::read_dir(out.join("scene")).unwrap().count(), 26);
    let other = root.join("other");
    ok(&[
        "run",
        s(&scene),
        "--preset",
        "preview",
        "-o",
        s(&other),
        "--frames",
        "0..=1",
    ]);
    assert!(other.join("frames/shot.0000.png").exists());
    assert_eq!(
        std::fs::read_dir(other.join("frames")).unwrap().count(),
        2 * 3
    );
    std::fs::remove_dir_all(&root).unwrap();
}
