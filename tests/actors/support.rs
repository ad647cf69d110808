//! What the actor tests share: a film from a scene text, the text of a
//! small scene, and `lmfilm trace` run on a scene of the repository.

use std::process::Command;

use lmfilm::film::Film;
use lmfilm::lsys::Source;
use lmfilm::turtle::Options;

/// A number as the scene language writes it: `1.5_` for −1.5, in the
/// digits of its own type.
pub fn written(v: impl std::fmt::Display) -> String {
    let s = v.to_string();
    match s.strip_prefix('-') {
        Some(magnitude) => format!("{magnitude}_"),
        None => s,
    }
}

/// The film of one scene text.
pub fn film(text: &str) -> Film {
    Film::from_sources(&[Source::new("actors.lm", text)], None, Options::default()).unwrap()
}

/// A scene of `seconds` (Δt = 0.04) with these options, axiom and
/// productions.
pub fn scene(seconds: f64, options: &str, axiom: &str, productions: &str) -> String {
    format!(
        "Camera_AnimationParameters\nt_final_interval {seconds} 0.04\n\
         Options\n{options}\nAxiom\n{axiom}\nProductions\n{productions}EndProductions\n"
    )
}

/// What `lmfilm trace SCENE ARGS…` prints, run from the repository with
/// `threads` rayon threads (None: the default); it must succeed.
pub fn trace_bytes(scene: &str, args: &[&str], threads: Option<&str>) -> Vec<u8> {
    let mut c = Command::new(env!("CARGO_BIN_EXE_lmfilm"));
    c.arg("trace").arg(scene).args(args);
    c.current_dir(env!("CARGO_MANIFEST_DIR"));
    if let Some(n) = threads {
        c.env("RAYON_NUM_THREADS", n);
    }
    let out = c.output().unwrap();
    assert!(
        out.status.success(),
        "{scene}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    out.stdout
}

/// `lmfilm trace SCENE ARGS…` prints the same bytes with 1 and 2 rayon
/// threads, and what it prints holds `marker` (it traced what it should).
pub fn same_for_one_and_two_threads(scene: &str, args: &[&str], marker: &str) {
    let one = trace_bytes(scene, args, Some("1"));
    assert!(String::from_utf8_lossy(&one).contains(marker), "{scene}");
    assert_eq!(one, trace_bytes(scene, args, Some("2")), "{scene}");
}

/// The JSON lines `lmfilm trace` writes for a scene of the repository.
pub fn trace(scene: &str) -> Vec<serde_json::Value> {
    String::from_utf8(trace_bytes(scene, &[], None))
        .unwrap()
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect()
}
