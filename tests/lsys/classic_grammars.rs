//! Classic L-systems of seeds/002 and seeds/003 with their known strings.

use crate::common::*;
use lmfilm::lsys::{Animation, NoSensors, Sensors, Source, Who};

/// A naive parallel rewriter: the reference for context-free grammars.
fn rewrite(axiom: &str, rules: &[(char, &str)], n: usize) -> String {
    let mut w = axiom.to_string();
    for _ in 0..n {
        w = w
            .chars()
            .map(|c| {
                rules
                    .iter()
                    .find(|r| r.0 == c)
                    .map_or(c.to_string(), |r| r.1.to_string())
            })
            .collect();
    }
    w
}

#[test]
fn bracketed_plant_matches_reference_and_lengths() {
    let mut a = load("bracketed_plant.lm");
    let lengths = [1, 11, 61, 311, 1561, 7811];
    for (n, len) in lengths.iter().enumerate() {
        let w = at_frame(&mut a, n as u64);
        assert_eq!(w.len(), *len, "generation {n}");
        assert_eq!(w, rewrite("F", &[('F', "F[+F]F[-F]F")], n));
    }
}

#[test]
fn node_rewriting_matches_reference() {
    let mut a = load("node_rewriting.lm");
    for n in 0..=7 {
        let w = at_frame(&mut a, n);
        let r = rewrite("X", &[('X', "F[+X]F[-X]+X"), ('F', "FF")], n as usize);
        assert_eq!(w, r, "generation {n}");
    }
}

#[test]
fn context_sensitive_signal_propagates() {
    let mut a = load("context_signal.lm");
    for k in 0..9 {
        let expected: String = (0..9).map(|i| if i == k { 'b' } else { 'a' }).collect();
        assert_eq!(at_frame(&mut a, k as u64), expected);
    }
}

#[test]
fn right_context_in_branches() {
    let mut a = load("context_branch.lm");
    let seq = ["S", "FAT", "F[+FBF]F", "F[+F[-FAF]F]F", "F[+F[-FFF]F]F"];
    for (n, s) in seq.iter().enumerate() {
        assert_eq!(at_frame(&mut a, n as u64), *s);
    }
}

#[test]
fn parametric_sequence() {
    let mut a = load("parametric.lm");
    let expected: [&[(char, f64, f64)]; 6] = [
        &[('B', 2.0, 0.0), ('A', 4.0, 4.0)],
        &[('B', 1.0, 0.0), ('B', 4.0, 0.0), ('A', 1.0, 0.0)],
        &[('B', 0.0, 0.0), ('B', 3.0, 0.0), ('A', 2.0, 1.0)],
        &[('C', 0.0, 0.0), ('B', 2.0, 0.0), ('A', 4.0, 3.0)],
        &[('C', 0.0, 0.0), ('B', 1.0, 0.0), ('A', 8.0, 7.0)],
        &[
            ('C', 0.0, 0.0),
            ('B', 0.0, 0.0),
            ('B', 8.0, 0.0),
            ('A', 8.0 / 7.0, 0.0),
        ],
    ];
    for (n, want) in expected.iter().enumerate() {
        a.advance_to(n as u64, &mut NoSensors).unwrap();
        let got: Vec<(char, f64, f64)> = a.systems[0]
            .word()
            .iter()
            .map(|s| (s.ch as char, s.par[0], s.par[1]))
            .collect();
        assert_eq!(got.len(), want.len(), "step {n}: {got:?}");
        for (g, w) in got.iter().zip(want.iter()) {
            assert_eq!(g.0, w.0, "step {n}");
            assert!(
                (g.1 - w.1).abs() < 1e-12 && (g.2 - w.2).abs() < 1e-12,
                "step {n}: {got:?}"
            );
        }
    }
    assert!(full(&mut a).ends_with("A(0,1.142857,0,0,0,0,0)"));
}

#[test]
fn timed_sequence_with_ages() {
    let mut a = load("timed.lm");
    let ages = |a: &mut Animation| -> Vec<(char, f64)> {
        let dt = a.systems[0].dt;
        a.systems[0]
            .word()
            .iter()
            .filter(|s| s.ch.is_ascii_alphabetic())
            .map(|s| (s.ch as char, s.age(dt)))
            .collect()
    };
    for t in 0..4 {
        a.advance_to(t, &mut NoSensors).unwrap();
        assert_eq!(ages(&mut a), [('A', t as f64)]);
    }
    a.advance_to(4, &mut NoSensors).unwrap();
    assert_eq!(ages(&mut a), [('S', 0.0), ('B', 0.0), ('S', 0.0)]);
    a.advance_to(7, &mut NoSensors).unwrap();
    assert_eq!(ages(&mut a), [('S', 3.0), ('S', 0.0), ('S', 3.0)]);
    assert_eq!(symbols(&mut a), "S[+S]S");
}

#[test]
fn pruning_cut_symbols() {
    let mut a = load("pruning.lm");
    assert_eq!(at_frame(&mut a, 1), "F[+FK][-GGGPGG]F[+GQG]G");
    assert_eq!(at_frame(&mut a, 2), "F[+FK][-GGG]FRG");
}

#[test]
fn cut_at_top_level_and_nested_branches() {
    // ](1_) with no enclosing branch replaces the whole word.
    let mut a = from_text("Camera_AnimationParameters\nt_final_interval 9 1\nAxiom\nAB[C]D\nProductions\nD (1)\n1.0 ]()(1_) E EndProb\nEnd\nEndProductions\n");
    assert_eq!(at_frame(&mut a, 1), "E");
    // ](100) at top level removes everything after the replaced symbol.
    let mut a = from_text("Camera_AnimationParameters\nt_final_interval 9 1\nAxiom\nAB[C]D\nProductions\nB (1)\n1.0 ]()(100) E EndProb\nEnd\nEndProductions\n");
    assert_eq!(at_frame(&mut a, 1), "AE");
    // The branch cut removes sub-branches and symbols rewritten earlier in
    // the same step; identifiers stay unique and increasing.
    let mut a = from_text(
        "Camera_AnimationParameters\nt_final_interval 9 1\nAxiom\nA[B[C]DX]E\nProductions\nB (1)\n1.0 BB EndProb\nEnd\nX (1)\n1.0 Y]()(1_) EndProb\nEnd\nEndProductions\n",
    );
    assert_eq!(at_frame(&mut a, 1), "AYE");
    let ids: Vec<u64> = a.systems[0].word().iter().map(|s| s.id).collect();
    assert!(ids[1] > ids[0] && ids[1] > ids[2], "{ids:?}");
}

#[test]
fn stochastic_same_seed_same_word_other_seed_other_word() {
    let word = |seed: u64| {
        let text = std::fs::read_to_string(example("stochastic.lm"))
            .unwrap()
            .replace("1997", &seed.to_string());
        let mut a = from_text(&text);
        at_frame(&mut a, 6)
    };
    assert_eq!(word(1997), word(1997));
    let w = word(1997);
    assert!((1..40).map(word).any(|v| v != w));
}

#[test]
fn stochastic_frequencies_within_bounds() {
    // 4000 symbols choose among parts of weight 2 and 6: normalised to
    // 0.25 / 0.75. Binomial sd = sqrt(4000·0.25·0.75) ≈ 27.4; allow 5 sd.
    let axiom = "A".repeat(4000);
    let text = format!(
        "Camera_AnimationParameters\nnbrCalcStep_seed 4 7\nt_final_interval 9 1\nAxiom\n{axiom}\nProductions\nA (1)\n2 B EndProb\n6 C EndProb\nEnd\nEndProductions\n"
    );
    let mut a = from_text(&text);
    let w = at_frame(&mut a, 1);
    let b = w.matches('B').count() as f64;
    assert!((b - 1000.0).abs() < 5.0 * 27.4, "B = {b}");
    assert_eq!(w.len(), 4000);
}

#[test]
fn random_numbers_keyed_per_symbol_and_step() {
    // Growth `!` is fixed for a symbol's life; parameter `!` is drawn once.
    let mut a = from_text(
        "Camera_AnimationParameters\nt_final_interval 10 1\nAxiom\nA () (!) () () (!)\nProductions\nEndProductions\n",
    );
    let g0 = full(&mut a);
    a.advance_to(3, &mut NoSensors).unwrap();
    let g3 = full(&mut a);
    assert_eq!(
        g0.split(',').skip(1).collect::<Vec<_>>(),
        g3.split(',').skip(1).collect::<Vec<_>>()
    );
    // A condition with `!` is redrawn each step: `! 0.5 -` > 0 fires on
    // some step, not necessarily the first, for some of 50 symbols.
    let axiom = "A".repeat(50);
    let mut a = from_text(&format!(
        "Camera_AnimationParameters\nt_final_interval 10 1\nAxiom\n{axiom}\nProductions\nA (1) [(!0.5-)>]\n1.0 B EndProb\nEnd\nEndProductions\n"
    ));
    let first = at_frame(&mut a, 1).matches('B').count();
    let later = at_frame(&mut a, 6).matches('B').count();
    assert!(first > 5 && first < 45, "{first}");
    assert!(later > first, "{first} {later}");
}

#[test]
fn ephemeral_symbols_never_enter_the_word() {
    let mut a = from_text(
        "Axiom\nF e () (10) () () (x) C\nProductions\nG (1)\n1.0 e () (11) () () (3u*_) C EndProb\nEnd\nEndProductions\n",
    );
    assert_eq!(symbols(&mut a), "FC");
    let ev = a.systems[0].events();
    assert_eq!(ev.len(), 1);
    assert_eq!((ev[0].position, ev[0].par[0]), (1, 10.0));
    // e with par1 = 0 carries a behaviour command string as text (C.6):
    // [actor] automata commands.
    let a = from_text("Axiom\ne () (0) () () (0 watch goal 1 2 3) A\n");
    let ev = &a.systems[0].events()[0];
    let script = a.systems[0].def.growth[ev.growth as usize]
        .script
        .clone()
        .unwrap();
    assert_eq!(script.actor.map(|a| a.value), Some(0));
    assert_eq!(script.automata.value.name(), "watch");
    assert_eq!(script.commands.len(), 1);
    // An empty par1 is 0 too; without the actor, the automata alone.
    let a = from_text("Axiom\ne () () () () (2 reset_goal) A\n");
    let ev = &a.systems[0].events()[0];
    let script = a.systems[0].def.growth[ev.growth as usize]
        .script
        .clone()
        .unwrap();
    assert!(script.actor.is_none());
    assert_eq!(script.automata.value.name(), "observe");
    // What is not a command is refused where it stands.
    let e = lmfilm::lsys::parse(&lmfilm::lsys::Source::new(
        "e.lm",
        "Axiom\ne () (0) () () (observe goal 1 2 3 fly) A\n",
    ))
    .unwrap_err();
    assert_eq!((e.line, e.column), (2, 36), "{e}");
}

#[test]
fn state_table_brackets_are_not_branches_for_context() {
    // `[(1)` saves a turtle state: it neither opens a branch nor blocks
    // the context; `B` sees `A` on its left.
    let mut a = from_text(
        "Camera_AnimationParameters\nt_final_interval 9 1\nAxiom\nA [ () (1) B\nProductions\nB (1) () (A) ()\n1.0 C EndProb\nEnd\nEndProductions\n",
    );
    assert_eq!(at_frame(&mut a, 1), "A[C");
}

#[test]
fn several_files_each_with_its_own_word() {
    let one = Source::new("one.lm", "Camera_AnimationParameters\nt_final_interval 5 1\nAxiom\nA\nProductions\nA (1)\n1.0 AB EndProb\nEnd\nEndProductions\n");
    let two = Source::new(
        "two.lm",
        "Axiom\nX\nProductions\nX (2)\n1.0 YY EndProb\nEnd\nEndProductions\n",
    );
    let mut a = Animation::from_sources(&[one, two], &mut NoSensors).unwrap();
    a.advance_to(2, &mut NoSensors).unwrap();
    let words: Vec<String> = a
        .systems
        .iter()
        .map(|l| l.word().iter().map(|s| s.ch as char).collect())
        .collect();
    assert_eq!(words, ["ABB", "YY"]);
    let mut ids: Vec<u64> = a
        .systems
        .iter()
        .flat_map(|l| l.word().iter().map(|s| s.id))
        .collect();
    ids.sort_unstable();
    ids.dedup();
    assert_eq!(ids.len(), 5, "identifiers are unique across files");
}

#[test]
fn sensors_answer_special_functions() {
    struct Field;
    impl Sensors for Field {
        fn force(&mut self, p: [f64; 3]) -> f64 {
            p[0]
        }
        fn sounds_playing(&mut self) -> f64 {
            2.0
        }
    }
    let text = "Axiom\n? () (3) ? () (0.5) S\nProductions\n? (0) [(?40 1-)>]\n1.0 T EndProb\nEnd\nS (0) [(?60 2-)=]\n1.0 H EndProb\nEnd\nEndProductions\n";
    let mut a = Animation::from_sources(&[Source::new("s.lm", text)], &mut Field).unwrap();
    a.step(&mut Field).unwrap();
    assert_eq!(symbols(&mut a), "T?H");
    // Without sensors the defaults answer: no force, no sound.
    let mut a = from_text(text);
    assert_eq!(at_frame(&mut a, 1), "??S");
    let who = Who {
        lsys: 0,
        symbol: 0,
        actor: None,
    };
    assert_eq!(lmfilm::lsys::NoSensors.actor(30, who), 1e30);
}

#[test]
fn memory_constants_and_splines() {
    let text = "Camera_AnimationParameters\nt_final_interval 10 1\n\
        Splines\nfunction time_spline 0 3 1 2 0 0 1 1 2 0 1e30 1e30\n\
        Constants\na 1 2\nE 1 0 1\n\
        Axiom\nA () (5 7<) (5>) (T a +) (?00) (E) (3 ?08)\n";
    let mut a = from_text(text);
    assert_eq!(full(&mut a), "A(0,7,7,1,0,1,1)");
    a.advance_to(1, &mut NoSensors).unwrap();
    // At T = 1, t = 1: spline 0 at 1 is 1·2 = 2, E = 1 + T² = 2, a = 1 + 2T.
    assert_eq!(full(&mut a), "A(1,7,7,1,2,2,1)");
}

#[test]
fn long_glued_words_parse_in_linear_time() {
    // 300,000 glued symbols: a quadratic keyword lookahead would take
    // minutes here; the linear one takes milliseconds.
    let text = format!(
        "Axiom\n{}\nProductions\nA (1)\n1 {} EndProb\nEnd\nEndProductions\n",
        "A".repeat(300_000),
        "B".repeat(1000)
    );
    let a = from_text(&text);
    assert_eq!(a.systems[0].word().len(), 300_000);
    assert_eq!(a.systems[0].def.productions[0].parts[0].symbols.len(), 1000);
}

#[test]
fn drawn_variants_derive_the_same_words_with_segments() {
    // The drawn files light the scene, give it a sky and a material and
    // point the turtle up, then derive the grammar with S for F.
    let mut a = load("bracketed_plant_drawn.lm");
    let mut b = load("node_rewriting_drawn.lm");
    for n in 0..=3 {
        let plant = rewrite("F", &[('F', "F[+F]F[-F]F")], n).replace('F', "S");
        assert_eq!(at_frame(&mut a, n as u64), format!("lDm+{plant}"));
        let nodes = rewrite("X", &[('X', "F[+X]F[-X]+X"), ('F', "FF")], n).replace('F', "S");
        assert_eq!(at_frame(&mut b, n as u64), format!("lDm+{nodes}"));
    }
}
