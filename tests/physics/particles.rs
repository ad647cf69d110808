//! The particle system (issue 7): `e` declares particles, `C` maps them
//! to the turtle, eq. 2.3.1 evolves them with RK4 (appendix H).

use std::path::PathBuf;
use std::process::Command;

use lmfilm::film::Film;
use lmfilm::lsys::print::Format;
use lmfilm::lsys::Source;
use lmfilm::physics::Particle;
use lmfilm::turtle::Options;

/// Δt = 0.04 s and 4 RK4 sub-steps per frame until `t_final`.
fn scene(t_final: f64, options: &str, axiom: &str, productions: &str) -> String {
    format!(
        "Camera_AnimationParameters\nnbrCalcStep_seed 4 1\nt_final_interval {t_final} 0.04\n\n\
         Options\n{options}\n\nAxiom\n{axiom}\n\nProductions\n{productions}\nEndProductions\n"
    )
}

fn film(text: &str) -> Result<Film, String> {
    Film::from_sources(&[Source::new("physics.lm", text)], None, Options::default())
        .map_err(|e| e.to_string())
}

/// Every frame's particles, as (time, table).
fn run(text: &str) -> Vec<(f64, Vec<Particle>)> {
    let mut film = film(text).unwrap();
    let mut out = Vec::new();
    while let Some(frame) = film.next_frame().unwrap() {
        let time = frame.time();
        out.push((time, film.particles().to_vec()));
    }
    out
}

/// A particle of mass 2 dropped from y = 10 with g = (0, −9.81·m, 0).
const FALL: &str =
    "f () () () (2) (0) (10) (0) e () (11) () () (0) (19.62_) (0) C () () (2) () (0) (0) (0)";

#[test]
fn free_fall_is_exact() {
    let frames = run(&scene(2.0, "", FALL, ""));
    assert_eq!(frames.len(), 51);
    for (t, ps) in &frames {
        assert_eq!(ps.len(), 1);
        let p = &ps[0];
        assert_eq!(p.mass, 2.0);
        let y = 10.0 - 9.81 * t * t / 2.0;
        assert!((p.pos.y - y).abs() < 1e-9, "t = {t}: {} ≠ {y}", p.pos.y);
        assert!((p.vel.y + 9.81 * t).abs() < 1e-9, "t = {t}: {}", p.vel.y);
        assert_eq!((p.pos.x, p.pos.z), (0.0, 0.0));
    }
}

#[test]
fn a_damped_oscillator_follows_its_closed_form() {
    // y'' = −k y − c y' with k = 4, c = 0.4, from y = 1 at rest.
    let axiom = "f () () () (2) (0) (1) (0) e () (11) () () (0) (y 4 * _ v 0.4 * -) (0) C () () (1) () (0) (0) (0)";
    let frames = run(&scene(10.0, "", axiom, ""));
    let (w0, zeta) = (2.0f64, 0.1f64);
    let wd = w0 * (1.0 - zeta * zeta).sqrt();
    for (t, ps) in &frames {
        let want = (-zeta * w0 * t).exp() * ((wd * t).cos() + zeta * w0 / wd * (wd * t).sin());
        // RK4 with h = 0.01: global error O(h⁴).
        assert!(
            (ps[0].pos.y - want).abs() < 1e-7,
            "t = {t}: {} ≠ {want}",
            ps[0].pos.y
        );
    }
}

/// The bait of code 7.1.1 fixed at the origin (eq. 7.1.8) and fishes
/// damped by −3v (eq. 7.1.9), starting at `starts`.
fn bait_and_fishes(t_final: f64, starts: &[[f64; 3]]) -> String {
    let f = |a: &str, b: &str| format!("(4 2500 3 0.005 r 2 ^ * _ ^ * - {a} {b} - *)");
    let mut axiom = format!(
        "[ e () (10) () () {} {} {} C () (1) () () (0) (0) (0) ]\n",
        f("X", "x"),
        f("Y", "y"),
        f("Z", "z")
    );
    // A negative number is written `2_`.
    let num = |v: f64| {
        if v < 0.0 {
            format!("{}_", -v)
        } else {
            v.to_string()
        }
    };
    for s in starts {
        let [x, y, z] = s.map(num);
        let repel = |a: &str, b: &str| format!("(2500 _ 3 0.005 r 2 ^ * _ ^ * {a} {b} - *)");
        axiom += &format!(
            "[ f () () () (2) ({x}) ({y}) ({z}) e () (10) () () {} {} {} e () (11) () () (u 3 * _) (v 3 * _) (w 3 * _) C () () () () (0) (0) (0) ]\n",
            repel("X", "x"),
            repel("Y", "y"),
            repel("Z", "z")
        );
    }
    scene(t_final, "", &axiom, "")
}

#[test]
fn a_fish_comes_to_rest_where_the_bait_field_vanishes() {
    let frames = run(&bait_and_fishes(20.0, &[[50.0, 0.0, 0.0]]));
    let (_, last) = frames.last().unwrap();
    let fish = &last[1];
    // 4 = 2500·3^(−0.005 r²).
    let r0 = ((2500.0f64 / 4.0).ln() / (0.005 * 3f64.ln())).sqrt();
    assert!((r0 - 34.234).abs() < 5e-4);
    assert!((fish.pos.length() - r0).abs() < 1e-6, "{}", fish.pos);
    assert!(fish.vel.length() < 1e-6, "{}", fish.vel);
    // Mass left empty by code 7.1.1 is 1; the bait does not move.
    assert_eq!(fish.mass, 1.0);
    assert_eq!(last[0].pos.length(), 0.0);
}

#[test]
fn one_or_two_threads_give_the_same_numbers() {
    let text = bait_and_fishes(
        2.0,
        &[[50.0, 0.0, 0.0], [0.0, 40.0, 10.0], [-30.0, -20.0, 5.0]],
    );
    let with = |n: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .unwrap();
        pool.install(|| run(&text))
    };
    let (a, b) = (with(1), with(2));
    assert_eq!(a, b);
    // The bait and the three fishes.
    assert_eq!(a.last().unwrap().1.len(), 4);
}

#[test]
fn exceeding_max_part_is_an_error_naming_the_limit() {
    let e = film(&scene(1.0, "MaxPart 0", FALL, "")).err().unwrap();
    assert!(e.contains("MaxPart = 0"), "{e}");
    // A production that drops a new particle every step.
    let drop =
        "X (0.04)\n1.0 X e () (11) () () (0) (9.81_) (0) C () () (1) () (0) (0) (0) EndProb\nEnd";
    let mut f = film(&scene(1.0, "MaxPart 2", "X", drop)).unwrap();
    for _ in 0..3 {
        f.next_frame().unwrap();
    }
    let e = f.next_frame().err().unwrap().to_string();
    assert!(e.contains("MaxPart = 2") && e.contains("frame 3"), "{e}");
}

#[test]
fn trace_shows_a_falling_particle() {
    let dir = std::env::temp_dir().join(format!("lmfilm_physics_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path: PathBuf = dir.join("fall.lm");
    std::fs::write(&path, scene(1.0, "", FALL, "")).unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_lmfilm"))
        .args(["trace", path.to_str().unwrap(), "--frames", "0..3"])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8(out.stdout).unwrap();
    let lines: Vec<serde_json::Value> = text
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    assert_eq!(lines.len(), 3);
    for (k, l) in lines.iter().enumerate() {
        let p = &l["particles"][0];
        let t = k as f64 * 0.04;
        assert_eq!(p["mass"], 2.0);
        let y = p["pos"][1].as_f64().unwrap();
        assert!((y - (10.0 - 9.81 * t * t / 2.0)).abs() < 1e-9, "{l}");
        assert!(
            (p["vel"][1].as_f64().unwrap() + 9.81 * t).abs() < 1e-9,
            "{l}"
        );
        assert!(p["id"].is_u64());
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `?40` (touch, 3.3): a query symbol feels the magnitude of the global
/// field, here a fixed particle's constant field of strength `s`.
fn touched(strength: &str) -> bool {
    let axiom = format!("e () (10) () () (0) ({strength}) (0) C () (1) () () (0) (0) (0) f () () () (2) (7) (1) (2) ?");
    let rule = "? (0) [(?40 4.9 -)>]\n1.0 Q EndProb\nEnd";
    let mut f = film(&scene(1.0, "", &axiom, rule)).unwrap();
    f.next_frame().unwrap();
    f.next_frame().unwrap();
    f.words(Format::Symbols)[0].contains('Q')
}

#[test]
fn a_query_symbol_feels_the_global_field() {
    assert!(touched("5"));
    assert!(!touched("4"));
}
