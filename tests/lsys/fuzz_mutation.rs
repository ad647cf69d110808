//! A bounded mutation fuzz of every reader, run by CI on every change (the
//! open-ended fuzzing is `tests/fuzz/`, see docs/hostile-input.md).
//!
//! From the repository's own inputs — scenes, the flyby event log, the
//! leaf OBJ/MTL, a WAV, a snapshot derived from the gallery, a manifest,
//! a data channel and an actor trajectory —
//! a fixed number of mutated inputs per reader (byte flips, `nan`, `inf`,
//! `1e999`, huge integers, NUL and invalid UTF-8 put in place of a word,
//! truncations, duplicated and deleted lines) with a fixed seed. Each
//! reader must return Ok or Err without panicking.

use crate::common;

use std::panic::{self, AssertUnwindSafe};
use std::time::Instant;

use lmfilm::lsys::{self, Animation, NoSensors, Source};
use lmfilm::render::Settings;
use lmfilm::scene::{mtl, obj, snapshot, Scene};
use lmfilm::sound::{events::EventsFile, wav};

use crate::common::Rng;

/// Mutated inputs per reader: a few seconds for all readers in the test
/// profile on one core. `LMFILM_MUTATION_CASES` and `LMFILM_MUTATION_SEED`
/// run more cases or other ones by hand.
const CASES: usize = 10_000;

fn setting(name: &str, default: u64) -> u64 {
    std::env::var(name)
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}

fn repo(path: &str) -> Vec<u8> {
    let p = format!("{}/{path}", env!("CARGO_MANIFEST_DIR"));
    std::fs::read(&p).unwrap_or_else(|e| panic!("{p}: {e}"))
}

/// Every `.lm` file under `scenes/`, sorted, so the seeds pick the same
/// file on every machine.
fn scenes() -> Vec<Vec<u8>> {
    scene_files("lm")
}

/// Every scene file of one form (`lm`, `lmr`), read.
fn scene_files(form: &str) -> Vec<Vec<u8>> {
    common::scene_files(form)
        .iter()
        .map(|p| std::fs::read(p).unwrap())
        .collect()
}

/// What a hostile or damaged file puts where a number or a name belongs.
const TOKENS: &[&[u8]] = &[
    b"nan",
    b"NaN",
    b"inf",
    b"-inf",
    b"1e999",
    b"-1e999",
    b"1e30",
    b"1e31",
    b"1e-45",
    b"0",
    b"-0",
    b"-1",
    b"4294967296",
    b"9223372036854775807",
    b"-9223372036854775808",
    b"99999999999999999999999999",
    b"1000000000000000000",
    b"\0",
    b"\xff\xfe",
    b"\xc3",
    b"(",
    b")",
    b"/*",
    b"[",
    b"?40",
    b"\\",
    b"#",
    b"",
];

/// Start and end of the word around `at` (bytes between whitespace).
fn word_at(b: &[u8], at: usize) -> (usize, usize) {
    let ws = |c: &u8| c.is_ascii_whitespace();
    let start = b[..at].iter().rposition(ws).map_or(0, |i| i + 1);
    let end = b[at..].iter().position(ws).map_or(b.len(), |i| at + i);
    (start, end)
}

/// Line starts of `b`, plus its end.
fn lines(b: &[u8]) -> Vec<usize> {
    let mut v = vec![0];
    v.extend(
        b.iter()
            .enumerate()
            .filter(|(_, &c)| c == b'\n')
            .map(|(i, _)| i + 1),
    );
    v.push(b.len());
    v
}

/// One to three mutations of `input`.
fn mutate(input: &[u8], rng: &mut Rng) -> Vec<u8> {
    let mut b = input.to_vec();
    for _ in 0..1 + rng.below(3) {
        let at = rng.below(b.len() + 1);
        match rng.below(8) {
            0 if !b.is_empty() => {
                let i = at.min(b.len() - 1);
                b[i] ^= 1 << rng.below(8);
            }
            1 | 2 if !b.is_empty() => {
                let (s, e) = word_at(&b, at.min(b.len() - 1));
                let t = TOKENS[rng.below(TOKENS.len())];
                b.splice(s..e, t.iter().copied());
            }
            3 => {
                let t = TOKENS[rng.below(TOKENS.len())];
                b.splice(at..at, t.iter().copied());
            }
            4 => b.truncate(at),
            5 => {
                let l = lines(&b);
                let k = rng.below(l.len() - 1);
                let line = b[l[k]..l[k + 1]].to_vec();
                for _ in 0..1 + rng.below(3) {
                    b.splice(l[k]..l[k], line.iter().copied());
                }
            }
            6 => {
                let l = lines(&b);
                let k = rng.below(l.len() - 1);
                b.drain(l[k]..l[k + 1]);
            }
            _ => {
                // A raw 4-byte value: what breaks binary headers and floats.
                let v: u32 = match rng.below(6) {
                    0 => f32::NAN.to_bits(),
                    1 => f32::INFINITY.to_bits(),
                    2 => 0,
                    3 => u32::MAX,
                    4 => 1e38f32.to_bits(),
                    _ => rng.next() as u32,
                };
                let i = at.min(b.len().saturating_sub(4));
                for (k, byte) in v.to_le_bytes().iter().enumerate() {
                    if let Some(x) = b.get_mut(i + k) {
                        *x = *byte;
                    }
                }
            }
        }
    }
    b
}

/// A snapshot's payload mutated and sealed again with a right hash, so
/// the damage reaches the decoder and the validation, not the checksum.
fn mutate_snapshot(input: &[u8], rng: &mut Rng) -> Vec<u8> {
    let payload = &input[20..input.len() - 8];
    let p = mutate(payload, rng);
    let mut out = input[..12].to_vec();
    out.extend_from_slice(&(p.len() as u64).to_le_bytes());
    out.extend_from_slice(&p);
    let hash = p.iter().fold(0xcbf2_9ce4_8422_2325u64, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3)
    });
    out.extend_from_slice(&hash.to_le_bytes());
    out
}

type ReadFn = dyn Fn(&[u8]) -> bool;

/// The name of the threads that run the readers: only their panics are
/// recorded.
const FUZZ_THREAD: &str = "lmfilm-mutation";

/// A reader under test: its name, what it does with one input (true
/// when it accepted it, so the report shows how deep cases go), the
/// inputs to mutate and how.
struct Target {
    name: &'static str,
    read: Box<ReadFn>,
    corpus: Vec<Vec<u8>>,
    mutate: fn(&[u8], &mut Rng) -> Vec<u8>,
}

fn target(
    name: &'static str,
    read: impl Fn(&[u8]) -> bool + 'static,
    corpus: Vec<Vec<u8>>,
    mutate: fn(&[u8], &mut Rng) -> Vec<u8>,
) -> Target {
    Target {
        name,
        read: Box::new(read),
        corpus,
        mutate,
    }
}

fn read_scene(b: &[u8]) -> bool {
    Source::from_bytes("fuzz.lm", b.to_vec()).is_ok_and(|src| lsys::parse(&src).is_ok())
}

fn read_readable(b: &[u8]) -> bool {
    Source::from_bytes("fuzz.lmr", b.to_vec()).is_ok_and(|src| lsys::parse(&src).is_ok())
}

/// A classic file that parses is spelt readable, and that spelling
/// parses too (a converter bug panics here).
fn convert_scene(b: &[u8]) -> bool {
    let Ok(src) = Source::from_bytes("fuzz.lm", b.to_vec()) else {
        return false;
    };
    if lsys::parse(&src).is_err() {
        return false;
    }
    let Ok(readable) = lsys::readable_writer::to_readable(&src) else {
        // A spelling the readable form lacks (a condition on plain
        // values, a `"` in an automata command) is said so.
        return false;
    };
    if let Err(e) = lsys::parse(&Source::new("fuzz.lmr", readable.as_str())) {
        panic!("the readable spelling does not parse: {e}\n{readable}");
    }
    true
}

/// The scene parsed, two steps derived (its expressions evaluated) and
/// the turtle run on the result.
fn derive_scene(b: &[u8]) -> bool {
    let Ok(src) = Source::from_bytes("fuzz.lm", b.to_vec()) else {
        return false;
    };
    let Ok(mut a) = Animation::from_sources(&[src], &mut NoSensors) else {
        return false;
    };
    if a.advance_to(2, &mut NoSensors).is_err() {
        return false;
    }
    // Surfaces and motions name files beside `fuzz.lm`, which do not
    // exist.
    if a.systems
        .iter()
        .any(|s| !s.def.surfaces.is_empty() || !s.def.motions.is_empty())
    {
        return true;
    }
    common::scene(&mut a);
    true
}

fn read_events(b: &[u8]) -> bool {
    Source::from_bytes("fuzz.events", b.to_vec()).is_ok_and(|src| EventsFile::parse(src).is_ok())
}

/// The gallery's frame 5 as a snapshot.
fn gallery_snapshot() -> Vec<u8> {
    let mut a = common::load("gallery.lm");
    a.advance_to(5, &mut NoSensors).unwrap();
    let (scene, _) = common::scene(&mut a);
    let bytes = snapshot::encode(&scene);
    snapshot::decode(&bytes).expect("a derived snapshot is valid");
    bytes
}

/// A snapshot the reader accepted must render: an 8×6 image with shadows
/// and one bounce, every part of the BVH and the shading visited.
fn render_tiny(scene: Scene) -> bool {
    let settings = Settings {
        shadows: true,
        max_depth: 1,
        ..Settings::preview(8, 6)
    };
    lmfilm::render::render(std::sync::Arc::new(scene), &settings);
    true
}

/// A manifest and a derive record as a film folder holds them.
fn manifest_json() -> Vec<u8> {
    br#"{
  "dt": 0.04,
  "files": {
    "derive.json": "9d2b925351c34ae5712bc92014cfde1952935ed95ce4f090814ebed31a411377",
    "frames/film.0000.exr": "96c74fef6d2cdd9dca514e38420b44bb38163a2aaf108cd97ea2f3397dc96ca9",
    "scene/0000.snap": "7849c81eebe73d0a0302623184f47129558594d5f3fdd9e7a038e0b8825350f0"
  },
  "frame_count": 1,
  "inputs": [{"file": "leaf.obj", "sha256": "00"}],
  "lmfilm_version": "0.1.0",
  "name": "film",
  "options": {"render.spp": "16"},
  "scenes": [{"file": "film.lm", "sha256": "69f667ff40a0a240e1e25101cccde1f5068c02891ab2d946b6efa010b0ea12a2"}],
  "selection": ["0.."]
}
"#
    .to_vec()
}

fn derive_json() -> Vec<u8> {
    let inputs = r#"{"files": [], "lmfilm_version": "0.1.0", "name": "film", "options": {}, "scenes": [{"file": "film.lm", "sha256": "00"}]}"#;
    let parsed: lmfilm::production::record::Inputs = serde_json::from_str(inputs).unwrap();
    format!(
        r#"{{"dt": 0.04, "events": "00", "frame_count": 2, "inputs": {inputs}, "key": "{}",
        "selection": ["0..", "3..=4"], "snapshots": ["00", "11"], "sounds": {{"sounds/a.wav": "22"}}}}"#,
        parsed.key()
    )
    .into_bytes()
}

/// Every reader with its corpus.
fn readers() -> Vec<Target> {
    let mtl_bytes = repo("scenes/meshes/leaf.mtl");
    vec![
        target("scene", read_scene, scenes(), mutate),
        target("derive", derive_scene, scenes(), mutate),
        target("readable", read_readable, scene_files("lmr"), mutate),
        target("convert", convert_scene, scenes(), mutate),
        target(
            "events",
            read_events,
            vec![repo("scenes/examples/flyby.events")],
            mutate,
        ),
        target(
            "obj",
            move |b: &[u8]| {
                let found = |_: &str| Ok(Some(("leaf.mtl".to_string(), mtl_bytes.clone())));
                obj::parse_obj(b, 0, &found).is_ok()
            },
            vec![repo("scenes/meshes/leaf.obj")],
            mutate,
        ),
        target(
            "mtl",
            |b: &[u8]| mtl::parse(b).is_ok(),
            vec![repo("scenes/meshes/leaf.mtl")],
            mutate,
        ),
        target(
            "wav",
            |b: &[u8]| wav::decode(b).is_ok(),
            vec![repo("scenes/sounds/start.wav")],
            mutate,
        ),
        target(
            "snapshot",
            |b: &[u8]| snapshot::decode(b).is_ok_and(render_tiny),
            vec![gallery_snapshot()],
            mutate_snapshot,
        ),
        target(
            "manifest",
            |b: &[u8]| {
                let text = String::from_utf8_lossy(b);
                lmfilm::production::manifest::Manifest::parse(&text).is_ok()
            },
            vec![manifest_json()],
            mutate,
        ),
        target(
            "data channel",
            |b: &[u8]| {
                Source::from_bytes("fuzz.chan", b.to_vec())
                    .is_ok_and(|src| lmfilm::film::channels::parse(&src).is_ok())
            },
            vec![repo("scenes/actors/pulse.chan")],
            mutate,
        ),
        target(
            "trajectory",
            |b: &[u8]| {
                let scene = Source::new("fuzz.lm", "import_trace 0 fuzz.trace");
                let file = lmfilm::source::FileRef::new(&scene, 15, "fuzz.trace");
                Source::from_bytes("fuzz.trace", b.to_vec())
                    .is_ok_and(|src| lmfilm::film::tracks::parse_trace(&src, 0, &file).is_ok())
            },
            vec![repo("scenes/actors/pledge.trace")],
            mutate,
        ),
        target(
            "derive record",
            |b: &[u8]| {
                serde_json::from_slice::<lmfilm::production::record::DeriveRecord>(b)
                    .is_ok_and(|r| r.validate().is_ok())
            },
            vec![derive_json()],
            mutate,
        ),
    ]
}

#[test]
fn every_reader_survives_mutated_inputs() {
    // Panics are recorded, not printed: the report lists them with inputs.
    let panics = common::PanicPool::new(FUZZ_THREAD);
    let start = Instant::now();
    let (cases, found) = panics.pool.install(|| {
        let mut cases = 0;
        let mut found = Vec::new();
        let readers = readers();
        let cases_per_reader = setting("LMFILM_MUTATION_CASES", CASES as u64) as usize;
        let seed = setting("LMFILM_MUTATION_SEED", 0x9e37_79b9_7f4a_7c15);
        for (k, t) in readers.iter().enumerate() {
            let (name, read) = (t.name, &t.read);
            let mut rng = Rng(seed
                .wrapping_add(k as u64 + 1)
                .wrapping_mul(0x9e37_79b9_7f4a_7c15)
                | 1);
            let mut accepted = 0;
            for case in 0..cases_per_reader {
                let input = (t.mutate)(&t.corpus[case % t.corpus.len()], &mut rng);
                cases += 1;
                match panic::catch_unwind(AssertUnwindSafe(|| read(&input))) {
                    Ok(ok) => accepted += usize::from(ok),
                    Err(_) => {
                        let message = panics.last_panic();
                        found.push(format!(
                            "{name} case {case}: {message}\n  input: {:?}",
                            String::from_utf8_lossy(&input[..input.len().min(2000)])
                        ));
                    }
                }
            }
            println!("mutation: {name}: {cases_per_reader} cases, {accepted} accepted");
        }
        (cases, found)
    });
    drop(panics);
    println!(
        "mutation: {cases} cases, {} panics, {:.1} s",
        found.len(),
        start.elapsed().as_secs_f64()
    );
    assert!(found.is_empty(), "{}", found.join("\n\n"));
}
