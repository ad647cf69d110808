//! Outputs a user can trust (issue 11 §1, §2, §4): every output records
//! what made it, a re-run redoes exactly what changed, a folder of another
//! film is refused, `verify` checks the whole chain, shards on several
//! hosts write their own records, and nothing is written outside the
//! output folder.

use crate::common;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// A 0.4 s film (11 frames): a sphere in front of the camera, a sound at frame 0.
const SCENE: &str = "Camera_AnimationParameters
prefpos_x1_x2_y1_y2 0 32 0 18
observer 0 2 20
lookatPoint 0 2 0
viewAngle 500
t_final_interval 0.4 0.04
Axiom
m () (1) S () () () () (2) T () (1) () () (6) (1)
";

fn temp(name: &str) -> PathBuf {
    common::fresh_dir("records", name)
}

fn lmfilm_env(args: &[&str], env: &[(&str, &str)]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_lmfilm"))
        .args(args)
        .envs(env.iter().copied())
        .output()
        .unwrap()
}

fn lmfilm(args: &[&str]) -> Output {
    lmfilm_env(args, &[])
}

pub(crate) fn ok(args: &[&str]) -> String {
    let out = lmfilm(args);
    assert!(
        out.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout).into_owned()
}

pub(crate) fn fails(args: &[&str], code: i32) -> String {
    let out = lmfilm(args);
    assert_eq!(
        out.status.code(),
        Some(code),
        "{args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stderr).into_owned()
}

pub(crate) fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

pub(crate) fn write(dir: &Path, name: &str, text: &str) -> String {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    s(&p).to_string()
}

fn sha256_hex(bytes: &[u8]) -> String {
    lmfilm::production::digest::sha256_bytes(bytes)
}

fn read(p: &Path) -> Vec<u8> {
    std::fs::read(p).unwrap()
}

/// `run` with the small preview settings the tests use.
fn run(scene: &[&str], dir: &Path, extra: &[&str]) -> String {
    let mut args = vec!["run"];
    args.extend_from_slice(scene);
    args.extend_from_slice(&["-o", s(dir), "--preset", "preview"]);
    args.extend_from_slice(extra);
    ok(&args)
}

/// How many frames the run's summary says it rendered now.
fn rendered_now(summary: &str) -> u64 {
    let at = summary.find(" of ").unwrap();
    let start = summary[..at].rfind(' ').unwrap() + 1;
    summary[start..at].parse().unwrap()
}

#[test]
fn a_folder_of_another_film_is_refused_until_cleaned() {
    let root = temp("other-film");
    let tree = write(&root, "tree.lm", SCENE);
    let ball = write(&root, "ball.lm", &SCENE.replace("(2) T", "(1) T"));
    let plane = write(&root, "plane.lm", &SCENE.replace("(2) T", "(3) T"));
    let dir = root.join("out");
    run(&[&tree, &ball], &dir, &[]);
    let err = fails(
        &["run", &tree, &plane, "-o", s(&dir), "--preset", "preview"],
        2,
    );
    assert!(err.contains(s(&dir)), "{err}");
    assert!(err.contains("ball.lm") && err.contains("plane.lm"), "{err}");
    assert!(err.contains("-o") && err.contains("--clean"), "{err}");
    // Nothing of the first film was touched.
    ok(&["verify", s(&dir)]);
    run(&[&tree, &plane], &dir, &["--clean"]);
    ok(&["verify", s(&dir)]);
    let m = std::fs::read_to_string(dir.join("manifest.json")).unwrap();
    assert!(m.contains("plane.lm") && !m.contains("ball.lm"), "{m}");
    std::fs::remove_dir_all(&root).unwrap();
}

#[test]
fn a_rerun_redoes_exactly_what_changed() {
    let root = temp("rerun");
    let scene = write(&root, "film.lm", SCENE);
    let dir = root.join("out");
    let first = run(&[&scene], &dir, &[]);
    assert_eq!(rendered_now(&first), 11, "{first}");
    assert_eq!(rendered_now(&run(&[&scene], &dir, &[])), 0);
    let frame = dir.join("frames/film.0003.png");
    let before = read(&frame);

    // The final preset after the preview: every frame again.
    let out = ok(&["run", &scene, "-o", s(&dir), "--spp", "2"]);
    assert_eq!(rendered_now(&out), 11, "{out}");
    assert_ne!(read(&frame), before);

    // A damaged frame is made again, not re-hashed into the manifest.
    let mut bytes = read(&frame);
    let last = bytes.len() - 20;
    bytes[last] ^= 0xff;
    std::fs::write(&frame, &bytes).unwrap();
    let err = fails(&["verify", s(&dir)], 1);
    assert!(err.contains("frames/film.0003.png"), "{err}");
    let out = ok(&["run", &scene, "-o", s(&dir), "--spp", "2"]);
    assert_eq!(rendered_now(&out), 1, "{out}");
    ok(&["verify", s(&dir)]);

    // A moved camera: derived and rendered again.
    let before = read(&frame);
    write(
        &root,
        "film.lm",
        &SCENE.replace("observer 0 2 20", "observer 3 2 20"),
    );
    let out = ok(&["run", &scene, "-o", s(&dir), "--spp", "2"]);
    assert_eq!(rendered_now(&out), 11, "{out}");
    assert_ne!(read(&frame), before);
    ok(&["verify", s(&dir)]);

    // A shorter film: the frames past its end go.
    write(&root, "film.lm", &SCENE.replace("0.4 0.04", "0.2 0.04"));
    ok(&["run", &scene, "-o", s(&dir), "--spp", "2"]);
    assert!(!dir.join("frames/film.0007.png").exists());
    assert!(!dir.join("scene/0007.snap").exists());
    ok(&["verify", s(&dir)]);
    std::fs::remove_dir_all(&root).unwrap();
}

#[test]
fn a_referenced_file_is_an_input() {
    let root = temp("inputs");
    std::fs::write(root.join("tri.obj"), "v 0 0 0\nv 4 0 0\nv 0 4 0\nf 1 2 3\n").unwrap();
    let scene = write(
        &root,
        "obj.lm",
        &SCENE
            .replace("Axiom", "Surfaces\nfig_obj 1 tri.obj\nAxiom")
            .replace("S () () () () (2)", "B () (1) () () (1)"),
    );
    let dir = root.join("out");
    run(&[&scene], &dir, &[]);
    let derive = std::fs::read_to_string(dir.join("derive.json")).unwrap();
    assert!(derive.contains("tri.obj"), "{derive}");
    assert_eq!(rendered_now(&run(&[&scene], &dir, &[])), 0);
    std::fs::write(root.join("tri.obj"), "v 0 0 0\nv 8 0 0\nv 0 8 0\nf 1 2 3\n").unwrap();
    assert_eq!(rendered_now(&run(&[&scene], &dir, &[])), 11);
    std::fs::remove_dir_all(&root).unwrap();
}

#[test]
fn verify_checks_the_whole_chain() {
    let root = temp("verify");
    let scene = write(&root, "film.lm", SCENE);
    let dir = root.join("out");
    run(&[&scene], &dir, &[]);
    let good = ok(&["verify", s(&dir)]);
    assert!(good.contains("complete and intact"), "{good}");

    // Stray files in frames/ and scene/, a frame past the film's end.
    std::fs::write(dir.join("frames/notes.txt"), "x").unwrap();
    std::fs::write(dir.join("scene/0099.snap"), "x").unwrap();
    std::fs::copy(
        dir.join("frames/film.0001.png"),
        dir.join("frames/film.0011.png"),
    )
    .unwrap();
    let err = fails(&["verify", s(&dir)], 1);
    for f in [
        "frames/notes.txt",
        "scene/0099.snap",
        "frames/film.0011.png",
    ] {
        assert!(err.contains(f), "{f}: {err}");
    }
    for f in [
        "frames/notes.txt",
        "scene/0099.snap",
        "frames/film.0011.png",
    ] {
        std::fs::remove_file(dir.join(f)).unwrap();
    }
    ok(&["verify", s(&dir)]);

    // An edited manifest: a changed Δt, a deleted entry.
    let path = dir.join("manifest.json");
    let text = std::fs::read_to_string(&path).unwrap();
    std::fs::write(&path, text.replace("\"dt\": 0.04", "\"dt\": 0.05")).unwrap();
    let err = fails(&["verify", s(&dir)], 1);
    assert!(err.contains("`dt`"), "{err}");
    let mut json: serde_json::Value = serde_json::from_str(&text).unwrap();
    json["files"]
        .as_object_mut()
        .unwrap()
        .remove("frames/film.0004.exr");
    std::fs::write(&path, serde_json::to_string_pretty(&json).unwrap()).unwrap();
    let err = fails(&["verify", s(&dir)], 1);
    assert!(err.contains("frames/film.0004.exr"), "{err}");
    std::fs::write(&path, &text).unwrap();
    ok(&["verify", s(&dir)]);

    // A frame's record edited to claim another snapshot.
    let rec = dir.join("frames/film.0002.json");
    let rtext = std::fs::read_to_string(&rec).unwrap();
    let mut r: serde_json::Value = serde_json::from_str(&rtext).unwrap();
    r["snapshot"] = "00".into();
    std::fs::write(&rec, serde_json::to_string(&r).unwrap()).unwrap();
    let err = fails(&["verify", s(&dir)], 1);
    assert!(err.contains("frames/film.0002"), "{err}");
    std::fs::write(&rec, rtext).unwrap();

    // A missing frame: the film is incomplete.
    for ext in ["png", "exr", "json"] {
        std::fs::remove_file(dir.join(format!("frames/film.0006.{ext}"))).unwrap();
    }
    let err = fails(&["verify", s(&dir)], 1);
    assert!(err.contains("frames/film.0006.png"), "{err}");
    ok(&["render", s(&dir), "--preset", "preview"]);
    ok(&["verify", s(&dir)]);

    // Derived again from a changed scene but not rendered: the frames
    // and the soundtrack are stale, and verify says so.
    write(&root, "film.lm", &SCENE.replace("(2) T", "(3) T"));
    ok(&["derive", &scene, "-o", s(&dir)]);
    let err = fails(&["verify", s(&dir)], 1);
    assert!(err.contains("another snapshot"), "{err}");
    assert!(err.contains("soundtrack.wav"), "{err}");
    std::fs::remove_dir_all(&root).unwrap();
}

/// Two shards at the same time on two "hosts" over one folder, then the
/// finishing step: the same manifest as one `run`.
#[test]
fn concurrent_shards_on_two_hosts_give_the_run_manifest() {
    let root = temp("shards");
    let scene = write(&root, "film.lm", SCENE);
    let (whole, split) = (root.join("whole"), root.join("split"));
    run(&[&scene], &whole, &[]);
    ok(&["derive", &scene, "-o", s(&split)]);
    // A half-written frame of another host, which must survive.
    let theirs = split.join("frames/film.0001.png.~other-host~1~0.tmp");
    std::fs::create_dir_all(split.join("frames")).unwrap();
    std::fs::write(&theirs, "half").unwrap();
    let spawn = |k: &str, host: &str| {
        Command::new(env!("CARGO_BIN_EXE_lmfilm"))
            .args(["render", s(&split), "--preset", "preview", "--shard", k])
            .env("LMFILM_HOST", host)
            .output()
    };
    let (a, b) = std::thread::scope(|t| {
        let a = t.spawn(|| spawn("1/2", "node-a"));
        let b = t.spawn(|| spawn("2/2", "node-b"));
        (a.join().unwrap().unwrap(), b.join().unwrap().unwrap())
    });
    assert!(a.status.success() && b.status.success());
    assert!(theirs.exists(), "another host's temporary file was removed");
    std::fs::remove_file(&theirs).unwrap();
    // No shard wrote the manifest: it still lists no frame.
    let m = std::fs::read_to_string(split.join("manifest.json")).unwrap();
    assert!(!m.contains("frames/"), "{m}");
    ok(&["sound", s(&split)]);
    ok(&["mux", s(&split)]);
    assert_eq!(
        read(&whole.join("manifest.json")),
        read(&split.join("manifest.json"))
    );
    ok(&["verify", s(&split)]);
    std::fs::remove_dir_all(&root).unwrap();
}

#[test]
fn outputs_stay_in_their_folder() {
    let root = temp("escape");
    let inner = root.join("a/b");
    std::fs::create_dir_all(&inner).unwrap();
    let scene = write(
        &inner,
        "esc.lm",
        &SCENE.replace(
            "Axiom",
            "Options\nrs_file_path_name out ../../ESCAPED\nAxiom",
        ),
    );
    let err = fails(&["run", &scene, "-o", s(&inner.join("out"))], 2);
    assert!(
        err.contains("esc.lm:") && err.contains("../../ESCAPED"),
        "{err}"
    );
    assert!(err.contains('^'), "located with a caret: {err}");
    assert!(!inner.join("out").exists(), "nothing is written");
    let scene = write(
        &inner,
        "abs.lm",
        &SCENE.replace("Axiom", "Options\nrs_file_path_name out /tmp/ABS\nAxiom"),
    );
    fails(&["derive", &scene, "-o", s(&inner.join("out"))], 2);

    // A derive record whose name leaves the folder is refused by render.
    let plain = write(&inner, "plain.lm", SCENE);
    let dir = inner.join("ok");
    ok(&["derive", &plain, "-o", s(&dir)]);
    let rec = dir.join("derive.json");
    let text = std::fs::read_to_string(&rec).unwrap();
    std::fs::write(
        &rec,
        text.replace("\"name\": \"plain\"", "\"name\": \"../../X\""),
    )
    .unwrap();
    let err = fails(&["render", s(&dir)], 2);
    assert!(err.contains("derive.json"), "{err}");
    let written: Vec<_> = std::fs::read_dir(&root)
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(written, [std::ffi::OsString::from("a")], "nothing outside");
    assert!(!inner.join("X.0000.png").exists());
    std::fs::remove_dir_all(&root).unwrap();
}

/// Every command that reads a scene refuses its scripts without consent,
/// with the same message naming the flag.
#[test]
fn every_command_asks_consent_for_scripts() {
    let root = temp("consent");
    let scene = write(
        &root,
        "cmd.lm",
        &SCENE.replace("Axiom", "Options\ncommand_file 1 touch.sh a b\nAxiom"),
    );
    let png = root.join("x.png");
    let obj = root.join("x.obj");
    let wav = root.join("x.wav");
    let out = root.join("o");
    let commands: [Vec<&str>; 7] = [
        vec!["print", &scene],
        vec!["export", &scene, "-o", s(&obj)],
        vec!["still", &scene, "-o", s(&png)],
        vec!["sound", &scene, "-o", s(&wav)],
        vec!["trace", &scene],
        vec!["derive", &scene, "-o", s(&out)],
        vec!["run", &scene, "-o", s(&out)],
    ];
    for args in &commands {
        let err = fails(args, 2);
        assert!(err.contains("--allow-commands"), "{args:?}: {err}");
        let mut allowed = args.clone();
        allowed.push("--allow-commands");
        ok(&allowed);
    }
    std::fs::remove_dir_all(&root).unwrap();
}

/// A scene named by its bare file name runs its scripts from its folder.
#[cfg(unix)]
#[test]
fn a_bare_scene_name_finds_its_scripts() {
    use std::os::unix::fs::PermissionsExt;
    let root = temp("bare");
    let script = root.join("log.sh");
    std::fs::write(&script, "#!/bin/sh\necho \"$1\" >> calls.txt\n").unwrap();
    std::fs::set_permissions(&script, std::fs::Permissions::from_mode(0o755)).unwrap();
    std::fs::write(
        root.join("cmd.lm"),
        "Camera_AnimationParameters\nt_final_interval 0.04 0.04\nOptions\ncommand_file 1 log.sh a b\nAxiom\nE () (1) (1) () (4) (5) (6)\n",
    )
    .unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_lmfilm"))
        .args(["derive", "cmd.lm", "-o", "out", "--allow-commands"])
        .current_dir(&root)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_eq!(
        std::fs::read_to_string(root.join("calls.txt")).unwrap(),
        "0\n1\n"
    );
    std::fs::remove_dir_all(&root).unwrap();
}

/// The MP4 records its frames and soundtrack: made once, remade when a
/// frame changes, and a damaged MP4 is named by verify.
#[test]
fn the_mp4_is_made_from_its_frames_and_soundtrack() {
    let root = temp("mp4");
    let scene = write(&root, "film.lm", SCENE);
    let dir = root.join("out");
    let out = run(&[&scene], &dir, &[]);
    assert!(out.contains("film.mp4 (made now)"), "{out}");
    let record = std::fs::read_to_string(dir.join("film.mp4.json")).unwrap();
    assert!(record.contains("\"soundtrack\": \""), "{record}");
    let out = run(&[&scene], &dir, &[]);
    assert!(out.contains("film.mp4 (up to date)"), "{out}");
    let mp4 = dir.join("film.mp4");
    let mut bytes = read(&mp4);
    let mid = bytes.len() / 2;
    bytes[mid] ^= 0xff;
    std::fs::write(&mp4, &bytes).unwrap();
    let err = fails(&["verify", s(&dir)], 1);
    assert!(err.contains("film.mp4"), "{err}");
    let out = run(&[&scene], &dir, &[]);
    assert!(out.contains("film.mp4 (made now)"), "{out}");
    ok(&["verify", s(&dir)]);
    // A truncated MP4 (a copy cut short) is named too, and made again.
    let whole = read(&mp4);
    std::fs::write(&mp4, &whole[..whole.len() / 3]).unwrap();
    let err = fails(&["verify", s(&dir)], 1);
    assert!(err.contains("film.mp4"), "{err}");
    ok(&["mux", s(&dir)]);
    assert_eq!(read(&mp4), whole, "made again, the same bytes");
    // An MP4 whose record names its bytes but which is not the film's:
    // a shorter film's video, its hash written into the record (a muxer
    // that lost frames would leave that). verify reads the MP4 back as a
    // player does and names the count and the length.
    let short = root.join("short");
    let shorter = write(&root, "short.lm", &SCENE.replace("0.4 0.04", "0.2 0.04"));
    run(&[&shorter], &short, &[]);
    let other = read(&short.join("short.mp4"));
    std::fs::write(&mp4, &other).unwrap();
    let record = dir.join("film.mp4.json");
    let text = std::fs::read_to_string(&record).unwrap();
    let old_hash = sha256_hex(&whole);
    assert!(text.contains(&old_hash), "{text}");
    std::fs::write(&record, text.replace(&old_hash, &sha256_hex(&other))).unwrap();
    ok(&["sound", s(&dir)]); // the manifest assembled again from the records
    let err = fails(&["verify", s(&dir)], 1);
    assert!(
        err.contains("film.mp4: holds 6 pictures, the film 11 frames"),
        "{err}"
    );
    ok(&["mux", s(&dir)]);
    ok(&["verify", s(&dir)]);
    // New frames: the old MP4 no longer matches them.
    ok(&["render", s(&dir), "--spp", "2"]);
    let err = fails(&["verify", s(&dir)], 1);
    assert!(err.contains("film.mp4: made from other frames"), "{err}");
    ok(&["mux", s(&dir)]);
    ok(&["verify", s(&dir)]);
    std::fs::remove_dir_all(&root).unwrap();
}

/// A scene with ears and an ambisonic microphone (the aeroplane, cut
/// short): the film's MP4 takes the ears as its stereo, the ambisonic
/// master `soundtrack.ambix.wav` (4 channels, no loudspeaker positions)
/// is listed in the manifest and checked by verify, remade by `sound`
/// when damaged, and removed when the scene no longer asks for it.
#[test]
fn the_ambisonic_master_is_one_of_the_film_s_files() {
    let root = temp("ambix");
    let airplane = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/examples/airplane.lm");
    let text = std::fs::read_to_string(airplane)
        .unwrap()
        .replace("t_final_interval 6 0.04", "t_final_interval 1.2 0.04");
    let scene = write(&root, "air.lm", &text);
    let dir = root.join("out");
    let out = lmfilm(&["run", &scene, "-o", s(&dir), "--preset", "preview"]);
    let said = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{said}");
    assert!(
        said.contains(
            "soundtrack.ambix.wav: the ambisonic master (AmbiX: W Y Z X, SN3D), W: -16.0 LUFS"
        ),
        "{said}"
    );
    let master = dir.join("soundtrack.ambix.wav");
    let bytes = read(&master);
    assert_eq!(&bytes[40..44], &[0; 4], "no loudspeaker positions");
    let wav = hound::WavReader::open(&master).unwrap();
    assert_eq!(wav.spec().channels, 4);
    assert_eq!(wav.duration(), 31 * 1920, "as long as the soundtrack");
    let movie = crate::mp4::Movie::read(&read(&dir.join("air.mp4")));
    assert_eq!(
        movie.track(b"soun").channels,
        2,
        "the ears, of three microphones"
    );
    let manifest = std::fs::read_to_string(dir.join("manifest.json")).unwrap();
    assert!(manifest.contains("soundtrack.ambix.wav"), "{manifest}");
    ok(&["verify", s(&dir)]);
    let mut damaged = bytes.clone();
    let mid = damaged.len() / 2;
    damaged[mid] ^= 0x55;
    std::fs::write(&master, &damaged).unwrap();
    let err = fails(&["verify", s(&dir)], 1);
    assert!(err.contains("soundtrack.ambix.wav"), "{err}");
    ok(&["sound", s(&dir)]);
    assert_eq!(read(&master), bytes, "made again, the same bytes");
    ok(&["verify", s(&dir)]);
    // Without INIT_ambix: no master, none left behind.
    write(&root, "air.lm", &text.replace(" INIT_ambix 2", ""));
    run(&[&scene], &dir, &[]);
    assert!(!master.exists(), "a master of other inputs was kept");
    let manifest = std::fs::read_to_string(dir.join("manifest.json")).unwrap();
    assert!(!manifest.contains("soundtrack.ambix.wav"), "{manifest}");
    ok(&["verify", s(&dir)]);
    std::fs::remove_dir_all(&root).unwrap();
}

/// A scene's own sound file is copied into the folder at derive, so the
/// finishing stage renders the soundtrack without the scene's folder.
#[test]
fn the_folder_carries_the_scenes_own_sounds() {
    let root = temp("own-sound");
    let scenes = root.join("scenes");
    std::fs::create_dir_all(&scenes).unwrap();
    let wav = format!("{}/scenes/sounds/frog.wav", env!("CARGO_MANIFEST_DIR"));
    std::fs::copy(&wav, scenes.join("mine.wav")).unwrap();
    let scene = write(
        &scenes,
        "own.lm",
        &SCENE.replace("Axiom", "Options\nsound_file 6 mine.wav\nAxiom"),
    );
    let dir = root.join("out");
    ok(&["derive", &scene, "-o", s(&dir)]);
    assert!(dir.join("sounds/mine.wav").exists());
    std::fs::remove_dir_all(&scenes).unwrap();
    ok(&["render", s(&dir), "--preset", "preview"]);
    ok(&["sound", s(&dir)]);
    let samples: Vec<i16> = hound::WavReader::open(dir.join("soundtrack.wav"))
        .unwrap()
        .into_samples()
        .map(Result::unwrap)
        .collect();
    assert!(
        samples.iter().any(|&v| v != 0),
        "the scene's own sound is heard"
    );
    ok(&["verify", s(&dir)]);
    // The copy is an output of the folder, checked like the others.
    let m = std::fs::read_to_string(dir.join("manifest.json")).unwrap();
    assert!(m.contains("sounds/mine.wav"), "{m}");
    std::fs::remove_dir_all(&root).unwrap();
}

/// `sound SCENE.lm` never writes into a film's folder, whose log and
/// soundtrack belong to its records.
#[test]
fn sound_of_a_scene_leaves_a_film_folder_alone() {
    let root = temp("sound-scene");
    let scene = write(&root, "film.lm", SCENE);
    let dir = root.join("out");
    run(&[&scene], &dir, &[]);
    let wav = dir.join("soundtrack.wav");
    let before = read(&wav);
    let err = fails(&["sound", &scene, "-o", s(&wav), "--loudness", "-20"], 2);
    assert!(
        err.contains("holds a film") && err.contains("lmfilm sound"),
        "{err}"
    );
    assert_eq!(read(&wav), before);
    ok(&["verify", s(&dir)]);
    ok(&["sound", &scene, "-o", s(&root.join("elsewhere/x.wav"))]);
    std::fs::remove_dir_all(&root).unwrap();
}
