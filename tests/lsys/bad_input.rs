//! Malformed definition files: every mistake names file:line:column with
//! the line and a caret, exits with code 2, and never panics.

use lmfilm::lsys::{parse, Diagnostic, Source};
use proptest::prelude::*;
use proptest::strategy::ValueTree;

fn error(text: &str) -> Diagnostic {
    match parse(&Source::new("bad.lm", text)) {
        Ok(_) => panic!("expected an error for:\n{text}"),
        Err(e) => e,
    }
}

fn check(text: &str, line: usize, column: usize, words: &str) {
    let e = error(text);
    assert_eq!((e.line, e.column), (line, column), "{e}");
    assert!(e.message.contains(words), "`{words}` not in: {e}");
    let shown = e.to_string();
    assert!(
        shown.starts_with(&format!("bad.lm:{line}:{column}: ")),
        "{shown}"
    );
    assert!(shown.ends_with('^'), "{shown}");
}

#[test]
fn unclosed_group() {
    check("Axiom\nF () (x2*\nG\n", 2, 6, "unclosed group");
}

#[test]
fn unknown_operator() {
    check(
        "Axiom\nF (x @ 2)\n",
        2,
        6,
        "unknown operator or parameter `@`",
    );
    check("Axiom\nF (-2)\n", 2, 4, "2_");
}

#[test]
fn stack_underflow() {
    check("Axiom\nF () (x+)\n", 2, 8, "stack underflow");
    check("Axiom\nF () (x 2)\n", 2, 7, "leaves 2 values");
}

#[test]
fn missing_end() {
    check(
        "Axiom\nA\nProductions\nA (1)\n1.0 B EndProb\nB (1)\n1.0 C EndProb\nEnd\nEndProductions\n",
        6,
        1,
        "expected a probability",
    );
    check(
        "Axiom\nA\nProductions\nA (1)\n1.0 B EndProb\nEndProductions\n",
        4,
        1,
        "missing `End`",
    );
    check(
        "Axiom\nA\nProductions\nA (1)\n1.0 B\nEnd\nEndProductions\n",
        6,
        1,
        "missing `EndProb`",
    );
    check(
        "Axiom\nA\nProductions\nA (1)\n1.0 B EndProb\nEnd\n",
        7,
        1,
        "missing `EndProductions`",
    );
}

#[test]
fn sections_and_keywords() {
    check("Axiom\nA\nConstants\na 1 2\n", 3, 1, "out of order");
    check(
        "Camera_AnimationParameters\nobserver 0 0\nAxiom\n",
        3,
        1,
        "a number",
    );
    check(
        "Camera_AnimationParameters\nzoom 2\n",
        2,
        1,
        "unknown keyword `zoom`",
    );
    check("Options\nMaxParticles 4\n", 2, 1, "unknown option");
    check("Axioms\nA\n", 1, 1, "expected a section name");
    check("/* open\nAxiom\nA\n", 1, 1, "unclosed comment");
    check("Constants\nt 1 2\n", 2, 1, "not a Constants function");
    check("Axiom\nF (a)\n", 2, 4, "not defined in the Constants");
    check(
        "Camera_AnimationParameters\nt_final_interval 1 0\n",
        2,
        20,
        "Δt must be > 0",
    );
    check(
        "Splines\ntime_spline 0 2 1 1 0 0 1 1 5 5\n",
        2,
        29,
        "end marker",
    );
}

#[test]
fn productions() {
    check(
        "Axiom\nA\nProductions\nA (1) (x)\n1 B EndProb\nEnd\nEndProductions\n",
        4,
        8,
        "condition is written",
    );
    check(
        "Axiom\nA\nProductions\nA (1) [(x)?]\n1 B EndProb\nEnd\nEndProductions\n",
        4,
        11,
        "predicate",
    );
    check(
        "Axiom\nA\nProductions\nA (1) () (AB)\n1 B EndProb\nEnd\nEndProductions\n",
        4,
        11,
        "a context is one symbol",
    );
    check(
        "Axiom\nA\nProductions\nA\n1 B EndProb\nEnd\nEndProductions\n",
        4,
        2,
        "maximal age",
    );
    check(
        "Axiom\nA\nProductions\nA (1)\n0 B EndProb\nEnd\nEndProductions\n",
        4,
        1,
        "probability > 0",
    );
    check("Axiom\nF ()()()()()()()()\n", 2, 17, "more than 7 groups");
}

#[test]
fn cli_reports_and_exits_with_2() {
    let dir = std::env::temp_dir().join(format!("lmfilm-bad-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("bad.lm");
    std::fs::write(&file, "Axiom\nF () (x+)\n").unwrap();
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_lmfilm"))
        .args(["print", file.to_str().unwrap()])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("bad.lm:2:8: stack underflow"), "{err}");
    assert!(err.contains("  F () (x+)\n"), "{err}");
    let missing = std::process::Command::new(env!("CARGO_BIN_EXE_lmfilm"))
        .args(["print", dir.join("none.lm").to_str().unwrap()])
        .output()
        .unwrap();
    assert_eq!(missing.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&missing.stderr).contains("cannot read the file"));
    std::fs::remove_dir_all(&dir).ok();
}

/// Pieces that definition files are made of, to build random near-files.
const PIECES: &[&str] = &[
    "Camera_AnimationParameters\n",
    "t_final_interval 3 1\n",
    "nbrCalcStep_seed 4 9\n",
    "Options\n",
    "fConst 5 1 2 3 4\n",
    "Splines\n",
    "time_spline 0 2 1 1 0 0 1 1 1e30 1e30\n",
    "Constants\n",
    "a 1 2\n",
    "P 1 2 3\n",
    "Axiom\n",
    "Productions\n",
    "EndProductions\n",
    "End\n",
    "EndProb\n",
    "1.0 ",
    "0.5 ",
    "(1) ",
    "() ",
    "[(x)>] ",
    "[(x1-)<] & ",
    "(A) ",
    "F",
    "A",
    "B",
    "[",
    "]",
    "]()(1_)",
    "]()(100)",
    "e()(10)()()(x)",
    "+()()()()(90)",
    "(x2*)",
    "(xy+)",
    "(t T + ?08)",
    "(! 1 #)",
    "(a P * ?12 +)",
    "(5 3< 5> ?44 +)",
    "(?40 ?30 ?60 + +)",
    "(?41)",
    "(x 0 /)",
    "(x 10 ^ 1000 ^)",
    "/* c */",
    "(",
    ")",
    "?",
    "@",
    "é",
    " ",
    "\n",
];

/// Well-formed symbols, to fill the skeleton below.
const SYMBOLS: &[&str] = &[
    "F",
    "A",
    "B",
    " [",
    "] ",
    "]()(1_)",
    "]()(100)",
    "e()(10)()()(x)",
    "+()()()()(90)",
    "A()(x2*)",
    "B()(xy+)(z)",
    "F()(t T + ?08)",
    "A()(! 1 #)",
    "B()(a P * ?12 +)",
    "A()(5 3< 5> ?44 +)",
    "F()(?40 ?30 ?60 + +)",
    "A()()()()(?41)",
    "B()(x 0 /)",
    "F()(x 10 ^ 1000 ^)",
    "[()(1)",
    "]()(1)",
];

fn near_file() -> impl Strategy<Value = String> {
    let pieces = || prop::collection::vec(prop::sample::select(PIECES), 0..40);
    let symbols = || prop::collection::vec(prop::sample::select(SYMBOLS), 0..12);
    prop_oneof![
        pieces().prop_map(|v| v.concat()),
        // A valid skeleton with random axiom and productions, so that
        // many cases get through the parser and are derived.
        (symbols(), symbols(), symbols(), prop::sample::select(&["", "[(x)>]", "() (A)", "() () (B)"][..]))
            .prop_map(|(a, p, q, cond)| format!(
                "Camera_AnimationParameters\nt_final_interval 3 1\nConstants\na 1 2\nP 1 2 3\nAxiom\nA{}\nProductions\nA (1) {cond}\n0.5 {} EndProb 0.5 {} EndProb End\nB (1)\n1 AB EndProb End\nEndProductions\n",
                a.concat(),
                p.concat(),
                q.concat()
            )),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(3000))]

    /// Any text: parsing returns a definition or a located error, and a
    /// parsed definition derives without panicking.
    #[test]
    fn parser_and_evaluator_never_panic(text in near_file()) {
        let src = Source::new("fuzz.lm", text);
        if let Ok(anim) = lmfilm::lsys::Animation::from_sources(std::slice::from_ref(&src), &mut lmfilm::lsys::NoSensors) {
            let mut anim = anim;
            for _ in 0..4 {
                if anim.systems[0].word().len() > 20_000 { break; }
                anim.step(&mut lmfilm::lsys::NoSensors).unwrap();
            }
            let (t, seed) = (anim.time(), anim.camera.seed);
            let _ = lmfilm::lsys::print::word(&mut anim.systems[0], lmfilm::lsys::print::Format::Full, t, seed, &mut lmfilm::lsys::NoSensors);
        } else if let Err(e) = parse(&src) {
            prop_assert!(e.line >= 1 && e.column >= 1);
            prop_assert!(!e.message.is_empty());
        }
    }

    /// Arbitrary bytes in an expression group.
    #[test]
    fn expressions_never_panic(expr in "[-+*/^%~<|_$&:\">!#'?0-9.xyztTXYZuvwr ]{0,24}") {
        let text = format!("Camera_AnimationParameters\nt_final_interval 3 1\nAxiom\nA ({expr}) ({expr}) () () ({expr})\nProductions\nA (1) [({expr})>]\n1 B ({expr}) EndProb\nEnd\nEndProductions\n");
        if let Ok(mut anim) = lmfilm::lsys::Animation::from_sources(&[Source::new("e.lm", text)], &mut lmfilm::lsys::NoSensors) {
            anim.step(&mut lmfilm::lsys::NoSensors).unwrap();
            let (t, seed) = (anim.time(), anim.camera.seed);
            let _ = lmfilm::lsys::print::word(&mut anim.systems[0], lmfilm::lsys::print::Format::Full, t, seed, &mut lmfilm::lsys::NoSensors);
        }
    }
}

#[test]
fn fuzzing_reaches_the_deriver() {
    // Runs the property on its own and checks that a fair share of the
    // generated files parse, so the derivation path is exercised too.
    let mut runner = proptest::test_runner::TestRunner::deterministic();
    let mut ok = 0;
    for _ in 0..500 {
        let text = near_file().new_tree(&mut runner).unwrap().current();
        ok += usize::from(parse(&Source::new("f.lm", text)).is_ok());
    }
    assert!(ok > 25, "only {ok} of 500 generated files parse");
}

#[test]
fn export_reports_bad_options_and_missing_surfaces() {
    let dir = std::env::temp_dir().join(format!("lmfilm-exp-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("s.lm");
    std::fs::write(
        &file,
        "Surfaces\nfig_obj 1 nowhere.obj\nAxiom\nB () (1) () () (1) (1) (1)\n",
    )
    .unwrap();
    let run = |args: &[&str]| {
        std::process::Command::new(env!("CARGO_BIN_EXE_lmfilm"))
            .arg("export")
            .arg(&file)
            .args(args)
            .output()
            .unwrap()
    };
    let out = run(&[
        "-o",
        dir.join("x.obj").to_str().unwrap(),
        "--segment-width",
        "0",
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("--segment-width must be > 0"));
    let out = run(&["-o", dir.join("x.obj").to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    // The error points at the line that names the file.
    assert!(
        err.contains("s.lm:2:11: surface 1: ") && err.contains("nowhere.obj"),
        "{err}"
    );
    assert!(
        err.contains("  fig_obj 1 nowhere.obj\n            ^"),
        "{err}"
    );
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn near_miss_keywords_are_named() {
    let prods = "Axiom\nF\nProductions\nF (1) 1 F F EndProb\nEnd\n";
    check(
        &format!("{prods}EndProduction\n"),
        6,
        1,
        "`EndProduction` is not a keyword; did you mean `EndProductions`?",
    );
    check(
        "Axiom\nF\nProductons\nF (1) 1 F EndProb\nEnd\nEndProductions\n",
        3,
        1,
        "did you mean `Productions`?",
    );
    check(
        "Axiom\nF\nProductions\nF (1) 1 F F EndPorb\nEnd\nEndProductions\n",
        4,
        13,
        "did you mean `EndProb`?",
    );
    check(
        "Options\nMaxpart 10\nAxiom\nF\n",
        2,
        1,
        "did you mean `MaxPart`?",
    );
    check("Axoim\nF\n", 1, 1, "did you mean `Axiom`?");
    check(
        "Camera_AnimationParameters\nviewangle 450\n",
        2,
        1,
        "did you mean `viewAngle`?",
    );
}

/// `nan`, `inf`, `1e999`, numbers beyond 1e30 and integers beyond i64
/// are located errors wherever a number is read.
#[test]
fn non_finite_and_absurd_numbers() {
    check(
        "Camera_AnimationParameters\nnear 1e999\n",
        2,
        6,
        "`1e999` is not a finite number",
    );
    check(
        "Camera_AnimationParameters\nfar -1e999\n",
        2,
        5,
        "not a finite number",
    );
    check("Camera_AnimationParameters\nfar 1e31\n", 2, 5, "too large");
    check(
        "Camera_AnimationParameters\nobserver 0 1e19 0\n",
        2,
        12,
        "observer position must be within ±1e18",
    );
    check(
        "Camera_AnimationParameters\ntwist nan\n",
        2,
        7,
        "found `nan`",
    );
    check(
        "Camera_AnimationParameters\nobserver 0 inf 0\n",
        2,
        12,
        "found `inf`",
    );
    check("Constants\na 1 1e999\n", 2, 5, "not a finite number");
    check(
        "Constants\na 1 nan\n",
        2,
        5,
        "coefficient 2 of `a` (it takes 2)",
    );
    check("Constants\nE 1 2\nAxiom\n", 3, 1, "found `Axiom`");
    check("Options\nfConst 1 2 1e400\n", 2, 12, "not a finite number");
    check(
        "Splines\ntime_spline 0 1 1 1 0 1e999 1e30 1e30\n",
        2,
        23,
        "not a finite number",
    );
    // An expression literal of 400 digits overflows to infinity.
    check(
        &format!("Axiom\nF ({})\n", "9".repeat(400)),
        2,
        4,
        "at most 1e30",
    );
    check(
        "Options\nMaxPart 1000000000000000000\n",
        2,
        9,
        "maximal number of particles must be 0..=10000000",
    );
    check("Options\nMaxPart 1e18\n", 2, 9, "not an integer");
    check(
        "Options\nMaxPart 99999999999999999999\n",
        2,
        9,
        "an integer too large to hold",
    );
    check(
        "RepetitionParameters\nstartp_sidel_nbr_dist 0 1 1000000000000 0\n",
        2,
        27,
        "number of objects must be 0..=1000000",
    );
    check(
        "RepetitionParameters\nscale 0\n",
        2,
        7,
        "scale must be 1e-6..=1e6",
    );
    // A window of i64 extremes overflowed when its width was taken.
    check(
        "Camera_AnimationParameters\npref_pos_x1_x2_y1_y2 -9223372036854775808 9223372036854775807 0 1\n",
        2,
        22,
        "window coordinate must be",
    );
    check(
        "Options\nNbrChannels_listOfNames 1000000000000 a\n",
        2,
        25,
        "number of channels must be",
    );
}

/// A scene that is not UTF-8 names the first bad byte; a folder or a
/// device is refused before it is read.
#[test]
fn unreadable_scene_files_are_located() {
    use lmfilm::lsys::{Animation, LoadError, NoSensors};
    let dir = std::env::temp_dir().join(format!("lmfilm-utf8-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("latin1.lm");
    std::fs::write(&file, b"Axiom\n/* caf\xe9 */ F\n").unwrap();
    let Err(LoadError::Syntax(e)) = Animation::load(&[&file], &mut NoSensors) else {
        panic!("expected a located error");
    };
    assert_eq!((e.line, e.column), (2, 7), "{e}");
    assert!(
        e.message.contains("0xe9") && e.message.contains("UTF-8"),
        "{e}"
    );
    for (path, why) in [
        (dir.clone(), "is a folder"),
        ("/dev/zero".into(), "not a regular file"),
    ] {
        let Err(e) = Animation::load(&[&path], &mut NoSensors) else {
            panic!("{} was read", path.display());
        };
        assert!(e.to_string().contains(why), "{e}");
    }
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_lmfilm"))
        .args(["print", file.to_str().unwrap()])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("latin1.lm:2:7: byte 0xe9"), "{err}");
    std::fs::remove_dir_all(&dir).ok();
}

/// A `sound_file` that does not exist is reported at its scene line.
#[test]
fn missing_sound_file_points_at_the_scene_line() {
    let dir = std::env::temp_dir().join(format!("lmfilm-sf-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("s.lm");
    std::fs::write(&file, "Options\nsound_file 3 nowhere.wav\nAxiom\nF\n").unwrap();
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_lmfilm"))
        .args(["print", file.to_str().unwrap()])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("s.lm:2:14: sound file \"nowhere.wav\" not found"),
        "{err}"
    );
    assert!(
        err.contains("  sound_file 3 nowhere.wav\n               ^"),
        "{err}"
    );
    std::fs::remove_dir_all(&dir).ok();
}

/// A `command_file` script that is not a file (missing, a folder) is
/// reported at the scene line that names it when `E` would run it.
#[test]
fn script_that_is_not_a_file_points_at_the_scene_line() {
    let dir = std::env::temp_dir().join(format!("lmfilm-cf-{}", std::process::id()));
    std::fs::create_dir_all(dir.join("folder.sh")).unwrap();
    let file = dir.join("e.lm");
    for script in ["nowhere.sh", "folder.sh"] {
        std::fs::write(
            &file,
            format!("Camera_AnimationParameters\nt_final_interval 0.04 0.04\nOptions\ncommand_file 1 {script} a b\nAxiom\nE () (1) (1)\n"),
        )
        .unwrap();
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_lmfilm"))
            .args(["derive", file.to_str().unwrap(), "-o"])
            .arg(dir.join("out"))
            .arg("--allow-commands")
            .output()
            .unwrap();
        assert_eq!(out.status.code(), Some(2));
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(
            err.contains("e.lm:4:16: script ") && err.contains("is not a file"),
            "{err}"
        );
        assert!(
            err.contains(&format!(
                "  command_file 1 {script} a b\n                 ^"
            )),
            "{err}"
        );
    }
    std::fs::remove_dir_all(&dir).ok();
}
