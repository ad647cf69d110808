//! Issue 53: a shared folder can hang every command. Each file of a
//! finished film folder is replaced in turn by a link to `/dev/zero`, a
//! named pipe (FIFO) and a folder, and `render`, `verify`, `sound` and
//! `mux` run on it under a time guard: each ends, refuses what it reads
//! (exit 2, naming the file and the way out; `verify` reports it, exit 1)
//! or leaves alone what it does not read, and never touches another file
//! of the folder, nor replaces what stands in the file's place.

use std::collections::BTreeMap;
use std::os::unix::fs::FileTypeExt;
use std::path::{Path, PathBuf};
use std::time::Instant;

use crate::common::fresh_dir;

/// A 3-frame film at 32 × 24: a sphere, an actor with a vision window
/// (`actors/0/vision.NNNN.png`), a sound of the scene's own folder
/// (copied into `sounds/`) played at frame 0.
const SCENE: &str = "Camera_AnimationParameters
prefpos_x1_x2_y1_y2 0 32 0 24
observer 0 4 -16
lookatPoint 0 2 0
viewAngle 450
t_final_interval 0.08 0.04

Options
sound_file 6 mine.wav
NBR_actors 1
iVisionWinSize 0 8 8
actorNbr_automata 0 watch init 1 -20 20 0.5 obs 0 2 -12 lat 0 2 0

Axiom
m () (1) S () () () () (2) T () (1) () () (6) (1) f () () () (2) (0) (2) (0) m () (4) a () () () () (4)
";

/// The longest a command may take on this tiny folder, in seconds,
/// before it counts as hung (killed, and the test fails).
const GUARD: u64 = 20;

/// Runs `lmfilm args` under the time guard: exit code and stderr.
fn lmfilm(args: &[&str]) -> (i32, String) {
    crate::limits::lmfilm(args, GUARD)
}

/// What stands in the place of a file of the folder.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Odd {
    /// A link to `/dev/zero`: a device that never ends.
    DevZero,
    /// A named pipe nothing writes to.
    Fifo,
    /// An empty folder.
    Folder,
}

impl Odd {
    fn make(self, path: &Path) {
        std::fs::remove_file(path).unwrap();
        match self {
            Odd::DevZero => std::os::unix::fs::symlink("/dev/zero", path).unwrap(),
            Odd::Fifo => {
                let name = std::ffi::CString::new(path.to_str().unwrap()).unwrap();
                // SAFETY: a valid NUL-terminated path.
                assert_eq!(unsafe { libc::mkfifo(name.as_ptr(), 0o600) }, 0);
            }
            Odd::Folder => std::fs::create_dir(path).unwrap(),
        }
    }

    /// Whether `path` is still what [`Odd::make`] put there.
    fn stands(self, path: &Path) -> bool {
        let Ok(meta) = std::fs::symlink_metadata(path) else {
            return false;
        };
        match self {
            Odd::DevZero => {
                meta.file_type().is_symlink()
                    && std::fs::read_link(path).is_ok_and(|t| t == Path::new("/dev/zero"))
            }
            Odd::Fifo => meta.file_type().is_fifo(),
            Odd::Folder => meta.is_dir() && std::fs::read_dir(path).unwrap().next().is_none(),
        }
    }

    /// The words the refusal says it with.
    fn said(self) -> &'static str {
        match self {
            Odd::DevZero => "is a device",
            Odd::Fifo => "is a named pipe",
            Odd::Folder => "is a folder",
        }
    }

    fn undo(self, path: &Path, bytes: &[u8]) {
        match self {
            Odd::Folder => std::fs::remove_dir(path).unwrap(),
            _ => std::fs::remove_file(path).unwrap(),
        }
        std::fs::write(path, bytes).unwrap();
    }
}

/// Every regular file under `dir` but `skip`, relative to it, with its
/// bytes.
fn files(dir: &Path, skip: &str) -> BTreeMap<String, Vec<u8>> {
    let mut out = BTreeMap::new();
    let mut dirs = vec![PathBuf::new()];
    while let Some(sub) = dirs.pop() {
        for e in std::fs::read_dir(dir.join(&sub)).unwrap().flatten() {
            let rel = sub.join(e.file_name());
            let kind = e.file_type().unwrap();
            if rel == Path::new(skip) {
                continue;
            } else if kind.is_dir() {
                dirs.push(rel);
            } else {
                assert!(kind.is_file(), "{}: not a file", rel.display());
                let key = rel.to_str().unwrap().to_string();
                out.insert(key, std::fs::read(dir.join(&rel)).unwrap());
            }
        }
    }
    out
}

/// The files that differ between `a` and `b`: added, removed or changed.
fn differ(a: &BTreeMap<String, Vec<u8>>, b: &BTreeMap<String, Vec<u8>>) -> Vec<String> {
    let mut keys: Vec<&String> = a.keys().chain(b.keys()).collect();
    keys.sort();
    keys.dedup();
    keys.into_iter()
        .filter(|k| a.get(*k) != b.get(*k))
        .cloned()
        .collect()
}

/// The exit code a command gives when the folder's file `rel` is not a
/// regular file: 2 where it reads or writes it (refused before anything
/// is written), verify's 1 for a problem (2 when it is the manifest it
/// starts from), else what it gives on an intact folder (`intact`).
fn expected(command: &str, rel: &str, name: &str, intact: i32) -> i32 {
    let record = rel.ends_with(".json");
    let frame = |ext: &str| rel.starts_with("frames/") && rel.ends_with(ext);
    let finishing = record || rel == "manifest.json";
    let sound =
        ["soundtrack.events", "soundtrack.wav"].contains(&rel) || rel.starts_with("sounds/");
    let mp4 = rel == format!("{name}.mp4");
    let reads = match command {
        "verify" => return if rel == "manifest.json" { 2 } else { 1 },
        "render" => finishing || rel.starts_with("scene/") || rel.starts_with("frames/"),
        "sound" => finishing || sound,
        "mux" => finishing || frame(".png") || rel == "soundtrack.wav" || mp4,
        _ => unreachable!(),
    };
    if reads {
        2
    } else {
        intact
    }
}

#[test]
fn no_command_waits_on_a_file_without_end() {
    let started = Instant::now();
    let root = fresh_dir("hostile-folders", "every-file");
    let scenes = root.join("scenes");
    std::fs::create_dir_all(&scenes).unwrap();
    let wav = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/sounds/frog.wav");
    std::fs::copy(wav, scenes.join("mine.wav")).unwrap();
    let scene = scenes.join("film.lm");
    std::fs::write(&scene, SCENE).unwrap();
    let dir = root.join("out");
    let d = dir.to_str().unwrap();
    let made = &[
        "run",
        scene.to_str().unwrap(),
        "-o",
        d,
        "--preset",
        "preview",
        "--width",
        "32",
        "--height",
        "24",
    ];
    let (code, err) = lmfilm(made);
    assert_eq!(code, 0, "{err}");
    let pristine = files(&dir, "");
    for want in [
        "derive.json",
        "settings.json",
        "manifest.json",
        "soundtrack.events",
        "soundtrack.wav",
        "soundtrack.json",
        "scene/0002.snap",
        "frames/film.0002.exr",
        "frames/film.0002.png",
        "frames/film.0002.json",
        "actors/0/vision.0002.png",
        "sounds/mine.wav",
    ] {
        assert!(pristine.contains_key(want), "{want}: {:?}", pristine.keys());
    }
    // On the intact folder: everything is up to date.
    let mut intact = BTreeMap::new();
    for command in ["render", "verify", "sound", "mux"] {
        let (code, err) = lmfilm(&[command, d]);
        assert_eq!(code, 0, "{command} on the intact folder: {err}");
        let changed = differ(&files(&dir, ""), &pristine);
        assert!(
            changed.is_empty(),
            "{command} on the intact folder changed {changed:?}"
        );
        intact.insert(command, code);
    }
    let mut runs = 0;
    for (rel, bytes) in &pristine {
        let path = dir.join(rel);
        let mut others = pristine.clone();
        others.remove(rel);
        for odd in [Odd::DevZero, Odd::Fifo, Odd::Folder] {
            odd.make(&path);
            for command in ["render", "verify", "sound", "mux"] {
                let case = format!("{command} with {rel} as {odd:?}");
                let (code, err) = lmfilm(&[command, d]);
                runs += 1;
                let want = expected(command, rel, "film", intact[command]);
                assert_eq!(code, want, "{case}: {err}");
                if code == 2 || command == "verify" {
                    assert!(err.contains(rel.as_str()), "{case}: names the file: {err}");
                    assert!(err.contains(odd.said()), "{case}: says what it is: {err}");
                    assert!(err.contains("remove it"), "{case}: says the way out: {err}");
                }
                assert!(odd.stands(&path), "{case}: {rel} was replaced");
                let changed = differ(&files(&dir, rel), &others);
                assert!(changed.is_empty(), "{case}: changed {changed:?}");
            }
            odd.undo(&path, bytes);
        }
    }
    assert!(differ(&files(&dir, ""), &pristine).is_empty());
    // A PNG damaged since its render is never put in the video.
    let png = dir.join("frames/film.0001.png");
    std::fs::write(&png, b"not the frame").unwrap();
    let (code, err) = lmfilm(&["mux", d]);
    assert_eq!(code, 2, "mux with a damaged PNG: {err}");
    assert!(
        err.contains("film.0001.png: does not match its record"),
        "{err}"
    );
    std::fs::write(&png, &pristine["frames/film.0001.png"]).unwrap();
    // An event log given by its name (a folder stands for the
    // `soundtrack.events` in it), and a scene, that never end.
    for odd in [Odd::DevZero, Odd::Fifo, Odd::Folder] {
        let events = root.join("odd.events");
        std::fs::write(&events, b"").unwrap();
        odd.make(&events);
        let wav = root.join("odd.wav");
        let (code, err) = lmfilm(&[
            "sound",
            events.to_str().unwrap(),
            "-o",
            wav.to_str().unwrap(),
        ]);
        let case = format!("sound with the event log as {odd:?}");
        assert_eq!(code, 2, "{case}: {err}");
        let said = match odd {
            Odd::Folder => "soundtrack.events: cannot read",
            _ => odd.said(),
        };
        assert!(
            err.contains("odd.events") && err.contains(said),
            "{case}: {err}"
        );
        assert!(odd.stands(&events) && !wav.exists(), "{case}");
        odd.undo(&events, b"");
        let lm = root.join("odd.lm");
        std::fs::write(&lm, b"").unwrap();
        odd.make(&lm);
        let out = root.join("odd-film");
        let (code, err) = lmfilm(&["run", lm.to_str().unwrap(), "-o", out.to_str().unwrap()]);
        let case = format!("run with the scene as {odd:?}");
        assert_eq!(code, 2, "{case}: {err}");
        assert!(
            err.contains("odd.lm") && err.contains(odd.said()),
            "{case}: {err}"
        );
        assert!(odd.stands(&lm) && !out.exists(), "{case}");
        odd.undo(&lm, b"");
    }
    eprintln!(
        "{runs} commands on {} files in {:.1} s",
        pristine.len(),
        started.elapsed().as_secs_f64()
    );
    std::fs::remove_dir_all(&root).unwrap();
}
