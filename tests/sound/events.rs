//! The sound event log (table B7): reader, writer, builder, bad input, and
//! the sound library's numbering (appendix D).

use glam::DVec3;
use lmfilm::sound::events::{parse, write, Event};
use lmfilm::sound::{EventLog, Library};
use proptest::prelude::*;

fn sample_log() -> EventLog {
    let mut log = EventLog::new();
    log.declare_mic(0, [-0.09, 1.7, 0.0]).unwrap();
    log.declare_mic(1, [0.09, 1.7, 0.0]).unwrap();
    log.declare_source(3, [0.1, 0.2, 0.3]).unwrap();
    log.declare_constant_source(7, DVec3::new(5.0, 0.0, -1e-7))
        .unwrap();
    log.push(Event::Ears { left: 0, right: 1 }).unwrap();
    log.push(Event::DistMatrix).unwrap();
    log.frame(0.0).unwrap();
    log.play(7, "cricket.wav").unwrap();
    log.frame(0.04).unwrap();
    log.source_position(3, [1.0 / 3.0, 2.5, -7.25]).unwrap();
    log.mic_position(1, [0.1, 1.7, 1e21]).unwrap();
    log.push(Event::SourceOrientation {
        n: 3,
        orientation: DVec3::new(0.0, 1.0, 0.0),
    })
    .unwrap();
    log.push(Event::MicOrientation {
        n: 0,
        orientation: DVec3::new(1.0, 0.0, 0.0),
    })
    .unwrap();
    log.play(3, "ball_racket.wav").unwrap();
    // A source that appears in the middle of the film.
    log.declare_source(9, [0.0, 0.0, 0.0]).unwrap();
    log.frame(0.08).unwrap();
    log.source_position(9, [0.5, 0.0, 0.0]).unwrap();
    log
}

#[test]
fn writer_output_reads_back_identically() {
    let log = sample_log();
    let text = write(&log);
    let back = parse(&text, "a.events").unwrap_or_else(|e| panic!("{e}\n{text}"));
    assert_eq!(back, log);
    assert_eq!(write(&back), text);
    assert!(text.starts_with("INIT_mic 0 -0.09 1.7 0 0 0 0\n"), "{text}");
    assert!(
        text.contains("\nTIME 0.04\nSP 3 0.3333333333333333 2.5 -7.25\n"),
        "{text}"
    );
    assert!(text.contains("\nPLAY 3 ball_racket.wav\n"), "{text}");
}

#[test]
fn reads_comments_blank_lines_time_spelling_and_any_case() {
    let text = "# a log\n\nINIT_mic 0 0 0 0 0 0 0\n  CONST_S 1 343 0 0 0 0 0   # a wall\n\
                INIT_dist_matrix\nTime 0\r\n  play 1 start.wav\nTIME 1e-1 # comment\n";
    let log = parse(text, "b.events").unwrap();
    assert_eq!(log.frames().len(), 2);
    assert_eq!(log.frames()[1].time, 0.1);
    assert_eq!(
        log.frames()[0].events,
        vec![Event::Play {
            n: 1,
            file: "start.wav".into()
        }]
    );
    assert_eq!(log.init().len(), 3);
    assert_eq!(log.mic_numbers(), vec![0]);
    assert!((log.duration() - 0.2).abs() < 1e-15);
}

/// The error for `text`, which must be `file:line:column: …` containing `needle`.
fn error(text: &str, line: usize, column: usize, needle: &str) {
    let e = parse(text, "bad.events").expect_err(text);
    let shown = e.to_string();
    assert_eq!((e.line, e.column), (line, column), "{shown}");
    assert!(
        shown.starts_with(&format!("bad.events:{line}:{column}: ")),
        "{shown}"
    );
    assert!(shown.contains(needle), "{shown}");
}

const HEAD: &str = "INIT_mic 0 0 0 0 0 0 0\nINIT_source 1 0 0 0 0 0 0\nTIME 0\n";

/// `INIT_ears` (lmfilm's) is refused where it names a microphone not
/// declared, one already an ear, the same one twice, or comes after the
/// first `TIME`; each at the number at fault.
#[test]
fn ears_are_two_declared_microphones_before_the_first_time() {
    let mics = "INIT_mic 0 0 0 0 0 0 0\nINIT_mic 1 1 0 0 0 0 0\nINIT_mic 2 2 0 0 0 0 0\n";
    error(
        &format!("{mics}INIT_ears 0 7\n"),
        4,
        13,
        "microphone 7 is not declared",
    );
    error(
        &format!("{mics}INIT_ears 1 1\n"),
        4,
        13,
        "cannot be both ears",
    );
    error(
        &format!("{mics}INIT_ears 0 1\nINIT_ears 2 1\n"),
        5,
        13,
        "microphone 1 is already an ear",
    );
    error(
        &format!("{mics}TIME 0\nINIT_ears 0 1\n"),
        5,
        1,
        "INIT_ears after the first TIME line",
    );
    let log = parse(&format!("{mics}INIT_ears 0 1\nTIME 0\n"), "ok.events").unwrap();
    assert!(log.init().contains(&Event::Ears { left: 0, right: 1 }));
}

/// `INIT_ambix` (lmfilm's) names one declared microphone, not an ear,
/// before the first `TIME`, once; an ear cannot be the ambisonic one.
#[test]
fn the_ambisonic_microphone_is_one_declared_microphone_not_an_ear() {
    let mics = "INIT_mic 0 0 0 0 0 0 0\nINIT_mic 1 1 0 0 0 0 0\nINIT_mic 2 2 0 0 0 0 0\n";
    error(
        &format!("{mics}INIT_ambix 7\n"),
        4,
        12,
        "INIT_ambix: microphone 7 is not declared",
    );
    error(
        &format!("{mics}INIT_ambix 2\nINIT_ambix 1\n"),
        5,
        12,
        "microphone 2 already makes the ambisonic master",
    );
    error(
        &format!("{mics}INIT_ears 0 1\nINIT_ambix 1\n"),
        5,
        12,
        "microphone 1 is an ear",
    );
    error(
        &format!("{mics}INIT_ambix 1\nINIT_ears 0 1\n"),
        5,
        13,
        "microphone 1 makes the ambisonic master",
    );
    error(
        &format!("{mics}TIME 0\nINIT_ambix 1\n"),
        5,
        1,
        "INIT_ambix after the first TIME line",
    );
    error(
        &format!("{mics}INIT_ambix\n"),
        4,
        1,
        "INIT_ambix takes 1 argument",
    );
    let text = format!("{mics}INIT_ambix 2\nTIME 0\nMO 2 0 0 -1\n");
    let log = parse(&text, "ok.events").unwrap();
    assert_eq!(log.ambix(), Some(2));
    assert_eq!(write(&log), text, "written back as read");
}

#[test]
fn bad_input_names_file_line_and_column() {
    error(
        &format!("{HEAD}XP 1 2 3 4\n"),
        4,
        1,
        "unknown keyword \"XP\"",
    );
    error(
        &format!("{HEAD}SP 1 2 x3 4\n"),
        4,
        8,
        "\"x3\" is not a finite number",
    );
    error(
        &format!("{HEAD}SP 1 2 inf 4\n"),
        4,
        8,
        "not a finite number",
    );
    error(
        &format!("{HEAD}SP 1 2 NaN 4\n"),
        4,
        8,
        "not a finite number",
    );
    error(
        &format!("{HEAD}SP 1 2 3\n"),
        4,
        1,
        "SP takes 4 arguments (SP n x y z), got 3",
    );
    error(&format!("{HEAD}SP 1 2 3 4 5\n"), 4, 12, "got 5");
    error(&format!("{HEAD}TIME\n"), 4, 1, "TIME takes 1 argument");
    error(
        &format!("{HEAD}SP 2 0 0 0\n"),
        4,
        4,
        "source 2 is not declared",
    );
    error(
        &format!("{HEAD}PLAY 5 a.wav\n"),
        4,
        6,
        "source 5 is not declared",
    );
    error(
        &format!("{HEAD}MP 1 0 0 0\n"),
        4,
        4,
        "microphone 1 is not declared",
    );
    error(
        &format!("{HEAD}MO 4 0 0 0\n"),
        4,
        4,
        "microphone 4 is not declared",
    );
    error(
        &format!("{HEAD}SP -1 0 0 0\n"),
        4,
        4,
        "not a source or microphone number",
    );
    error(
        &format!("{HEAD}SP 1.0 0 0 0\n"),
        4,
        4,
        "not a source or microphone number",
    );
    error(
        &format!("{HEAD}TIME 0.5\nTIME 0.25\n"),
        5,
        6,
        "does not come after the previous TIME 0.5",
    );
    error(&format!("{HEAD}TIME 0\n"), 4, 6, "does not come after");
    error("TIME -1\n", 1, 6, "TIME must be a time ≥ 0");
    error("TIME 1e300\n", 1, 6, "≤ 3.2e7 seconds");
    error("INIT_mic 0 0 1e31 0 0 0 0\n", 1, 14, "within ±1e30");
    error("INIT_mic 0 0 0 0 0 0 1e999\n", 1, 22, "not a finite number");
    error(
        "INIT_source 1 0 0 0 0 0 0\nSP 1 0 0 0\n",
        2,
        1,
        "before the first TIME",
    );
    error(
        "INIT_source 1 0 0 0 0 0 0\nPLAY 1 a.wav\n",
        2,
        1,
        "before the first TIME",
    );
    error(
        "CONST_S 1 0 0 0 0 0 0\nTIME 0\nSP 1 1 0 0\n",
        3,
        4,
        "constant (CONST_S)",
    );
    error(
        &format!("{HEAD}INIT_source 1 0 0 0 0 0 0\n"),
        4,
        13,
        "declared twice",
    );
    error(
        &format!("{HEAD}INIT_mic 0 0 0 0 0 0 0\n"),
        4,
        10,
        "declared twice",
    );
    // The line and a caret under the column.
    let e = parse(&format!("{HEAD}SP 1 2 x3 4\n"), "bad.events").unwrap_err();
    assert!(e.to_string().ends_with("  SP 1 2 x3 4\n         ^"), "{e}");
}

#[test]
fn builder_refuses_what_the_reader_refuses() {
    let mut log = EventLog::new();
    assert!(log.source_position(0, [0.0, 0.0, 0.0]).is_err());
    log.declare_source(0, [0.0, 0.0, 0.0]).unwrap();
    assert!(log.play(0, "a.wav").is_err(), "PLAY before TIME");
    log.frame(1.0).unwrap();
    assert!(log.frame(f64::NAN).is_err());
    assert!(log.frame(0.5).is_err());
    assert!(log.source_position(0, [f64::INFINITY, 0.0, 0.0]).is_err());
    assert!(log.play(0, "two words.wav").is_err());
    assert!(log.play(0, "#x.wav").is_err());
    assert!(log.play(0, "").is_err());
    assert!(log.declare_mic(0, [f64::NAN, 0.0, 0.0]).is_err());
    assert!(log.mic_position(3, [0.0, 0.0, 0.0]).is_err());
    // Refused events leave no trace.
    assert_eq!(write(&log), "INIT_source 0 0 0 0 0 0 0\nTIME 1\n");
}

#[test]
fn duration_is_last_time_plus_one_frame_interval() {
    let mut log = EventLog::new();
    assert_eq!(log.duration(), 0.0);
    log.frame(2.0).unwrap();
    assert_eq!(log.duration(), 2.04, "one frame: the thesis's 1/25 s");
    log.frame(2.5).unwrap();
    assert_eq!(log.frame_interval(), 0.5);
    assert_eq!(log.duration(), 3.0);
}

#[test]
fn library_default_is_table_d1_and_d2() {
    let lib = Library::default();
    assert_eq!(lib.file_name(0), Some("ball_racket.wav"));
    assert_eq!(lib.file_name(3), None, "table D.1 has no 3");
    assert_eq!(lib.file_name(8), Some("avion.wav"));
    assert_eq!(lib.file_name(15), Some("fourty.wav"));
    assert_eq!(lib.file_name(28), Some("wait02.wav"));
    assert_eq!(lib.file_name(29), Some("move_right.wav"));
    assert_eq!(lib.file_name(44), Some("free_it.wav"));
    assert_eq!(lib.file_name(58), Some("exit.wav"));
    assert_eq!(lib.file_name(59), None);
    assert_eq!(lib.iter().count(), 58);
    let mut own = Library::empty();
    own.set(3, "bell.wav");
    assert_eq!(own.file_name(3), Some("bell.wav"));
    assert_eq!(own.file_name(0), None);
}

proptest! {
    #[test]
    fn any_numbers_within_the_bounds_round_trip(
        // Positions are finite and within ±1e30 (events::MAX_VALUE).
        xs in prop::collection::vec((prop::num::f64::NORMAL | prop::num::f64::SUBNORMAL | prop::num::f64::ZERO).prop_map(|x| x % 1e30), 9),
        dt in 1e-9f64..10.0,
        n in any::<u32>(),
    ) {
        let mut log = EventLog::new();
        log.declare_source(n, [xs[0], xs[1], xs[2]]).unwrap();
        log.declare_mic(n, [xs[3], xs[4], xs[5]]).unwrap();
        log.frame(dt).unwrap();
        log.source_position(n, [xs[6], xs[7], xs[8]]).unwrap();
        log.frame(dt * 3.0).unwrap();
        log.mic_position(n, [xs[8], xs[7], xs[6]]).unwrap();
        let text = write(&log);
        prop_assert_eq!(parse(&text, "p.events").unwrap(), log);
    }

    #[test]
    fn garbage_never_panics(text in "[A-Za-z_#0-9 .\\-\\n]{0,200}") {
        let _ = parse(&text, "g.events");
    }
}
