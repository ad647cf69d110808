//! Imported and exported data (thesis 6.3.3): data channels read by
//! `?50`, actor trajectories written by `I` (`trace_actor`) into the
//! output folder and followed by `$` par2 = 5 (`import_trace`).

use crate::common;

use std::path::{Path, PathBuf};

use super::records::{fails, ok, s, write};

fn temp(name: &str) -> PathBuf {
    common::fresh_dir("tracks", name)
}

/// A 0.2 s film (6 frames, Δt = 0.04) with `options` and `axiom`.
fn scene(options: &str, axiom: &str) -> String {
    format!(
        "Camera_AnimationParameters\nprefpos_x1_x2_y1_y2 0 32 0 18\nobserver 0 2 20\n\
         lookatPoint 0 2 0\nviewAngle 500\nt_final_interval 0.2 0.04\n\
         Options\n{options}\nAxiom\n{axiom}\nProductions\nEndProductions\n"
    )
}

/// The centre of the bounding box of an exported OBJ's vertices.
fn centre(obj: &Path) -> [f64; 3] {
    let text = std::fs::read_to_string(obj).unwrap();
    let (mut lo, mut hi) = ([f64::MAX; 3], [f64::MIN; 3]);
    for line in text.lines().filter(|l| l.starts_with("v ")) {
        for (k, w) in line.split_whitespace().skip(1).take(3).enumerate() {
            let v: f64 = w.parse().unwrap();
            lo[k] = lo[k].min(v);
            hi[k] = hi[k].max(v);
        }
    }
    [0, 1, 2].map(|k| (lo[k] + hi[k]) / 2.0)
}

fn near(a: [f64; 3], b: [f64; 3]) -> bool {
    (0..3).all(|k| (a[k] - b[k]).abs() < 1e-4)
}

/// The sphere the turtle draws on actor 0's imported trajectory, at
/// frame `frame` of `scene`.
fn sphere_at(scene: &str, dir: &Path, frame: u64) -> [f64; 3] {
    let obj = dir.join(format!("frame{frame}.obj"));
    let f = frame.to_string();
    ok(&["export", scene, "--frame", &f, "-o", s(&obj)]);
    centre(&obj)
}

const FOLLOW: &str = "$ () () (5) (0) a () () () () (0.1)";

#[test]
fn channels_are_interpolated_between_samples_and_clamped() {
    let dir = temp("channels");
    write(&dir, "a.chan", "0.08 3\n1 3\n-1\n");
    write(&dir, "b.chan", "1 1 7\n");
    let film = write(
        &dir,
        "film.lm",
        &scene(
            "NbrChannels_listOfNames 2 a.chan b.chan",
            "a () () () () (0 T ?50) (1 T ?50)",
        ),
    );
    let at = |t: &str| ok(&["print", &film, "--time", t, "--format", "full"]);
    // Channel 0 is the first name: samples 1, 3, −1 every 0.08 s.
    assert!(at("0").contains("a(0,0,0,0,1,7,0)"), "{}", at("0"));
    assert!(at("0.04").contains(",2,7,0)"), "{}", at("0.04"));
    assert!(at("0.12").contains(",1,7,0)"), "{}", at("0.12"));
    assert!(at("0.2").contains(",-1,7,0)"), "{}", at("0.2"));

    // A production condition reads the channel too: `a` becomes `b`
    // once channel 0 (3, 3, 0 every 0.08 s) is below 2 (after 0.08 s).
    write(&dir, "c.chan", "0.08 3 3 3 0");
    let cond = write(
        &dir,
        "cond.lm",
        &scene("NbrChannels_listOfNames 1 c.chan", "a ()").replace(
            "EndProductions",
            "a (0) [(0 T ?50 2 ~)=]\n1.0 b EndProb\nEnd\nEndProductions",
        ),
    );
    let words = |f: &str| ok(&["print", &cond, "--frame", f]);
    assert!(words("1").contains('a'), "{}", words("1"));
    assert!(words("4").contains('b'), "{}", words("4"));

    // A channel the film does not declare stops the frame.
    let bad = write(
        &dir,
        "bad.lm",
        &scene(
            "NbrChannels_listOfNames 1 a.chan",
            "a () () () () (3 T ?50)",
        ),
    );
    let err = fails(&["print", &bad, "--frame", "1", "--format", "full"], 2);
    assert!(err.contains("data channel 3"), "{err}");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn i_writes_one_record_per_frame_into_the_folder_and_verify_checks_it() {
    let root = temp("export");
    let options = "NBR_actors 1\nactorNbr_automata 0 0 9 obs 1.1 0.3 -2.7 lat 0 0 0\n\
                   trace_actor 0 out/a.trace";
    // Two `I` in a frame still write one record.
    let film = write(&root, "film.lm", &scene(options, "I I a () () () () (1)"));
    let dir = root.join("dir");
    ok(&["run", &film, "-o", s(&dir), "--preset", "preview"]);
    let text = std::fs::read_to_string(dir.join("out/a.trace")).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines.len(), 6, "{text}");
    assert_eq!(lines[0], "Actor 0 0 0 1.1 0.3 -2.7");
    assert_eq!(lines[1], "Actor 0 0 0.04 1.1 0.3 -2.7");
    ok(&["verify", s(&dir)]);
    let derive = std::fs::read_to_string(dir.join("derive.json")).unwrap();
    assert!(derive.contains("out/a.trace"), "{derive}");

    // A record listing a file twice (as a trajectory and as an actor
    // image, issue 43) is not intact.
    let mut twice: serde_json::Value = serde_json::from_str(&derive).unwrap();
    twice["actors"]["out/a.trace"] = serde_json::json!("0");
    std::fs::write(dir.join("derive.json"), twice.to_string()).unwrap();
    let err = fails(&["verify", s(&dir)], 1);
    assert!(err.contains("listed twice"), "{err}");
    std::fs::write(dir.join("derive.json"), &derive).unwrap();

    // Altered: verify says which file.
    std::fs::write(dir.join("out/a.trace"), "Actor 0 0 0 9 9 9\n").unwrap();
    let err = fails(&["verify", s(&dir)], 1);
    assert!(err.contains("out/a.trace"), "{err}");

    // A re-run writes it again; a renamed trace file prunes the old one.
    ok(&["derive", &film, "-o", s(&dir)]);
    assert_eq!(
        std::fs::read_to_string(dir.join("out/a.trace")).unwrap(),
        text
    );
    write(
        &root,
        "film.lm",
        &scene(&options.replace("out/a", "b"), "I"),
    );
    ok(&["derive", &film, "-o", s(&dir)]);
    assert!(!dir.join("out/a.trace").exists());
    assert_eq!(std::fs::read_to_string(dir.join("b.trace")).unwrap(), text);

    // Commands without an output folder write nothing.
    ok(&["print", &film, "--frame", "2"]);
    std::fs::remove_dir_all(&root).unwrap();
}

#[test]
fn an_imported_trajectory_places_the_turtle_and_an_export_reads_back() {
    let root = temp("import");
    // Actor 0 goes along x, then along z, then stays; actor 1 is ignored.
    write(
        &root,
        "hand.trace",
        "Actor 0 0 0 0 0 0\nActor 1 5 0 100 100 100\nActor 0 0 0.08 4 0 0\n\n\
         Actor 0 3 0.16 4 0 8\n",
    );
    let film = write(
        &root,
        "follow.lm",
        &scene("import_trace 0 hand.trace", FOLLOW),
    );
    assert!(near(sphere_at(&film, &root, 0), [0.0, 0.0, 0.0]));
    assert!(near(sphere_at(&film, &root, 1), [2.0, 0.0, 0.0]));
    assert!(near(sphere_at(&film, &root, 3), [4.0, 0.0, 4.0]));
    assert!(near(sphere_at(&film, &root, 5), [4.0, 0.0, 8.0]));

    // Round trip: actor 0 walks 0.5 along +z each frame ([M f g]); its
    // records, written by `I`, imported again, put the turtle where it was.
    let options = "NBR_actors 1\nactorNbr_automata 0 0 9 obs 1.1 0.3 -2.7 lat 1.1 0.3 0\n\
                   trace_actor 0 a.trace";
    let walk = "[ M () (7) () (0) f () () () () (0.5) g () (0) ] I";
    let export = write(&root, "export.lm", &scene(options, walk));
    let dir = root.join("dir");
    ok(&["derive", &export, "-o", s(&dir)]);
    std::fs::copy(dir.join("a.trace"), root.join("a.trace")).unwrap();
    let again = write(&root, "again.lm", &scene("import_trace 0 a.trace", FOLLOW));
    for k in [0u8, 2, 5] {
        let at = sphere_at(&again, &root, u64::from(k));
        let eye = [1.1f32, 0.3, -2.7 + 0.5 * f32::from(k + 1)].map(f64::from);
        assert!(near(at, eye), "frame {k}: {at:?} {eye:?}");
    }
    std::fs::remove_dir_all(&root).unwrap();
}

#[test]
fn bad_channel_and_trace_files_are_located() {
    let root = temp("bad");
    let check = |options: &str, file: &str, text: &str, at: &str| {
        write(&root, file, text);
        let film = write(&root, "film.lm", &scene(options, "F"));
        let err = fails(&["print", &film], 2);
        assert!(err.contains(at), "{at}: {err}");
        assert!(err.contains('^'), "{err}");
    };
    let chan = "NbrChannels_listOfNames 1 c.chan";
    check(chan, "c.chan", "0.1 3\n1 2\n", "c.chan:3:1:");
    check(chan, "c.chan", "0.1 2\n1 x\n", "c.chan:2:3:");
    check(chan, "c.chan", "-1 1 1\n", "c.chan:1:1:");
    check(chan, "c.chan", "0.1 2 1 2 3\n", "c.chan:1:11:");
    // Missing: located where the scene names it.
    check(
        "NbrChannels_listOfNames 1 none.chan",
        "c.chan",
        "",
        "film.lm:8:27:",
    );
    let trace = "import_trace 0 t.trace";
    check(trace, "t.trace", "Actor 0 0 x 0 0 0\n", "t.trace:1:11:");
    check(trace, "t.trace", "Actor 0 0 0 0 0\n", "t.trace:1:16:");
    check(trace, "t.trace", "Actor 1 0 0 0 0 0\n", "film.lm:8:16:");
    check("import_trace 0 none.trace", "t.trace", "", "film.lm:8:16:");
    std::fs::remove_dir_all(&root).unwrap();
}

#[test]
fn a_trace_file_outside_the_folder_is_refused() {
    let root = temp("outside");
    let dir = root.join("dir");
    for (name, why) in [
        ("../x", "not a relative path inside the output folder"),
        (
            "/tmp/x.trace",
            "not a relative path inside the output folder",
        ),
        ("manifest.json", "lmfilm's own outputs"),
        // Issue 43: the actors' images and the farm's folder were not
        // in the list (a trace over actors/0/vision.0000.png replaced
        // the image and verify called the folder intact).
        ("actors", "lmfilm's own outputs"),
        ("actors/0/vision.0000.png", "lmfilm's own outputs"),
        ("farm/logs/x", "lmfilm's own outputs"),
        ("soundtrack.json", "lmfilm's own outputs"),
    ] {
        let options = format!("NBR_actors 1\ntrace_actor 0 {name}");
        let film = write(&root, "film.lm", &scene(&options, "I"));
        let err = fails(&["derive", &film, "-o", s(&dir)], 2);
        assert!(err.contains("film.lm:9:15:"), "{err}");
        assert!(err.contains(why), "{err}");
    }
    // An actor the film does not have.
    let film = write(&root, "film.lm", &scene("trace_actor 0 a.trace", "I"));
    let err = fails(&["derive", &film, "-o", s(&dir)], 2);
    assert!(
        err.contains("film.lm:8:15:") && err.contains("NBR_actors"),
        "{err}"
    );
    assert!(!root.join("x").exists());
    std::fs::remove_dir_all(&root).unwrap();
}

/// Trace names that failed only once the film had derived, without a
/// location, or were written through a link out of the folder (issue
/// 54): each is now refused before deriving, at the scene's line, and
/// nothing is written outside the folder.
#[test]
fn a_trace_file_that_cannot_be_written_is_refused_before_deriving() {
    let root = temp("unwritable");
    let dir = root.join("dir");
    let outside = root.join("outside");
    std::fs::create_dir_all(dir.join("made")).unwrap();
    std::fs::create_dir_all(&outside).unwrap();
    std::os::unix::fs::symlink(&outside, dir.join("out")).unwrap();
    std::os::unix::fs::symlink(outside.join("t.trace"), dir.join("linked.trace")).unwrap();
    std::fs::write(dir.join("plain"), "a file").unwrap();
    let long = "x".repeat(300);
    for (options, why) in [
        ("trace_actor 0 out/a.trace".to_string(), "is a link"),
        ("trace_actor 0 linked.trace".to_string(), "is a link"),
        (
            "trace_actor 0 plain/a.trace".to_string(),
            "is a file, where the trace's path needs a folder",
        ),
        (
            "trace_actor 0 made".to_string(),
            "is a folder or a special file",
        ),
        ("trace_actor 0 sub/".to_string(), "names a folder"),
        (
            format!("trace_actor 0 {long}"),
            "a file system takes at most 255",
        ),
        (
            "trace_actor 0 a\ntrace_actor 0 a/b.trace".to_string(),
            "one would be a folder of the other",
        ),
    ] {
        let film = write(
            &root,
            "film.lm",
            &scene(&format!("NBR_actors 1\n{options}"), "I"),
        );
        let err = fails(&["derive", &film, "-o", s(&dir)], 2);
        assert!(
            err.contains("film.lm:") && err.contains(":15:"),
            "{options}: {err}"
        );
        assert!(err.contains(why), "{options}: {err}");
        assert!(
            !dir.join("derive.json").exists(),
            "{options}: derived before refusing"
        );
    }
    assert!(
        std::fs::read_dir(&outside).unwrap().next().is_none(),
        "written outside the folder"
    );
    std::fs::remove_dir_all(&root).unwrap();
}
