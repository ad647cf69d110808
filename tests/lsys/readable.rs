//! The readable form (issue 40): every shipped scene ships spelt in it,
//! up to date; the classic, readable and thesis-postfix spellings parse
//! into the same definition, op for op, for every scene and for
//! generated files; mistakes are located in the readable file and teach
//! (the nearest name, the parameter and its unit).

use std::path::{Path, PathBuf};

use lmfilm::lsys::readable_writer::to_readable;
use lmfilm::lsys::thesis_form::to_thesis;
use lmfilm::lsys::{parse, Definition, Source};

use crate::common::{scene_files, Rng};

fn scenes() -> Vec<PathBuf> {
    let scenes = scene_files("lm");
    assert!(scenes.len() > 40, "{} scenes", scenes.len());
    scenes
}

/// What a definition means, without where it was written: offsets and
/// file names cleared.
fn meaning(mut d: Definition) -> String {
    let name = d.name.clone();
    for s in &mut d.axiom {
        s.offset = 0;
    }
    for p in &mut d.productions {
        p.offset = 0;
        for part in &mut p.parts {
            for s in &mut part.symbols {
                s.offset = 0;
            }
        }
    }
    d.source = Source::new("", "");
    d.name = String::new();
    // An empty group and `(0)` mean the same (language.md §3): a
    // selector the readable form fixes may come back either way.
    format!("{d:?}")
        .replace(&name, "FILE")
        .replace("Some(Const(0.0))", "None")
}

fn parsed(name: &str, text: &str) -> Definition {
    parse(&Source::new(name, text)).unwrap_or_else(|e| panic!("{e}"))
}

fn readable_path(p: &Path) -> PathBuf {
    p.with_extension("lmr")
}

#[test]
fn every_scene_ships_its_readable_form_up_to_date() {
    for p in scenes() {
        let text = std::fs::read_to_string(&p).unwrap();
        let want = to_readable(&Source::new(p.display().to_string(), text))
            .unwrap_or_else(|e| panic!("{e}"));
        let shipped = std::fs::read_to_string(readable_path(&p))
            .unwrap_or_else(|e| panic!("{}: {e} (run `make readable`)", p.display()));
        assert!(
            shipped == want,
            "{} is not the readable spelling of {}: run `make readable`",
            readable_path(&p).display(),
            p.display()
        );
    }
}

#[test]
fn classic_readable_and_thesis_spellings_mean_the_same() {
    for p in scenes() {
        let classic = std::fs::read_to_string(&p).unwrap();
        let readable = std::fs::read_to_string(readable_path(&p)).unwrap();
        let a = meaning(parsed("s.lm", &classic));
        let b = meaning(parsed("s.lmr", &readable));
        assert!(a == b, "{}: the readable form means otherwise", p.display());
        let thesis = to_thesis(&Source::new("s.lmr", readable.as_str())).unwrap();
        assert!(
            !thesis.contains("(="),
            "{}: an infix group left",
            p.display()
        );
        assert_eq!(meaning(parsed("s.lm", &thesis)), a, "{}", p.display());
        // Comments survive both ways.
        let comments = |t: &str| t.matches("/*").count();
        assert_eq!(comments(&readable), comments(&classic), "{}", p.display());
        assert_eq!(comments(&thesis), comments(&classic), "{}", p.display());
    }
}

/// A random postfix expression over parameters, constants `a`, `b` and
/// every operator and function.
fn expression(r: &mut Rng, depth: u32) -> String {
    let leaf = |r: &mut Rng| {
        let k = r.next() % 12;
        match k {
            0..=3 => format!("{}", (r.next() % 1000) as f64 / 8.0),
            4 => "x".into(),
            5 => "y".into(),
            6 => "z".into(),
            7 => "t".into(),
            8 => "T".into(),
            9 => "a".into(),
            10 => "?40".into(),
            _ => "!".into(),
        }
    };
    if depth == 0 || r.next().is_multiple_of(3) {
        return leaf(r);
    }
    let a = expression(r, depth - 1);
    match r.next() % 14 {
        0 => format!("{a} _"),
        1 => format!("{a} |"),
        2 => format!("{a} $"),
        3 => format!("{a} >"),
        4 => format!("{a} ?08"),
        k => {
            let b = expression(r, depth - 1);
            let op = ["+", "-", "*", "/", "^", "%", "~", "<", "#"][(k - 5) as usize];
            format!("{a} {b} {op}")
        }
    }
}

/// A random condition: atoms combined in postfix.
fn condition(r: &mut Rng, depth: u32) -> String {
    let preds = ["<", "p", ">", "g", "=", "!"];
    if depth == 0 || r.next().is_multiple_of(2) {
        let pred = preds[(r.next() % 6) as usize];
        return format!("[({}){pred}]", expression(r, 2));
    }
    let a = condition(r, depth - 1);
    match r.next() % 3 {
        0 => format!("{a} !"),
        k => format!(
            "{a} {} {}",
            condition(r, depth - 1),
            ["&", "|"][(k - 1) as usize]
        ),
    }
}

/// A random symbol with random groups.
fn symbol(r: &mut Rng) -> String {
    let chars = b"ABFXfcaRSmlvD+-&^/$[]?.{}TMgeCnOoPpqsdNQrBEI";
    let ch = chars[(r.next() % chars.len() as u64) as usize] as char;
    let n = r.next() % 8;
    let mut s = ch.to_string();
    for k in 0..n {
        let g = match r.next() % 4 {
            0 => String::new(),
            1 => format!("{}", r.next() % 60),
            // A selector's value, e.g. par1 = 7 of M.
            2 if k <= 3 => format!("{}", r.next() % 8),
            _ => expression(r, 3),
        };
        if ch == 'e' && k == 4 {
            s.push_str(" (goal 1 2 3)");
            continue;
        }
        s.push_str(&format!(" ({g})"));
    }
    s
}

fn generated(r: &mut Rng) -> String {
    let mut t = String::from(
        "/* generated */\nCamera_AnimationParameters\nt_final_interval 3 0.5\n\nConstants\na 1 2\nb 0.5 0\n\nAxiom\n",
    );
    for _ in 0..r.next() % 12 {
        t.push_str(&symbol(r));
        t.push(if r.next().is_multiple_of(3) {
            '\n'
        } else {
            ' '
        });
    }
    t.push_str("\n\nProductions\n");
    for _ in 0..r.next() % 5 {
        let lhs = ["A", "B", "F", "X"][(r.next() % 4) as usize];
        t.push_str(&format!("{lhs} ({})", expression(r, 2)));
        if r.next().is_multiple_of(2) {
            t.push_str(&format!(" {}", condition(r, 2)));
        } else {
            t.push_str(" ()");
        }
        match r.next() % 3 {
            0 => t.push_str(" (A)"),
            1 => t.push_str(" () (B) /* right */"),
            _ => {}
        }
        t.push('\n');
        for _ in 0..1 + r.next() % 3 {
            t.push_str(&format!("{} ", 1 + r.next() % 4));
            for _ in 0..r.next() % 6 {
                t.push_str(&symbol(r));
                t.push(' ');
            }
            t.push_str("EndProb\n");
        }
        t.push_str("End\n");
    }
    t.push_str("EndProductions\n");
    t
}

#[test]
fn generated_files_mean_the_same_in_every_spelling() {
    let mut r = Rng(40);
    let mut checked = 0;
    for _ in 0..400 {
        let classic = generated(&mut r);
        let Ok(def) = parse(&Source::new("g.lm", classic.as_str())) else {
            continue; // e.g. a `]` cut in the axiom's place is fine, others not
        };
        checked += 1;
        let want = meaning(def);
        let readable = to_readable(&Source::new("g.lm", classic.as_str()))
            .unwrap_or_else(|e| panic!("{e}\n{classic}"));
        let got = parse(&Source::new("g.lmr", readable.as_str()))
            .unwrap_or_else(|e| panic!("{e}\n{classic}\n{readable}"));
        assert_eq!(meaning(got), want, "{classic}\n{readable}");
        let thesis = to_thesis(&Source::new("g.lmr", readable.as_str())).unwrap();
        assert_eq!(
            meaning(parsed("g.lm", &thesis)),
            want,
            "{readable}\n{thesis}"
        );
        // Spelt readable again, the thesis form gives the same text.
        assert_eq!(
            to_readable(&Source::new("g.lm", thesis.as_str())).unwrap(),
            readable
        );
    }
    assert!(checked > 300, "only {checked} generated files parsed");
}

/// The error of reading `text` as a readable file.
fn error(text: &str) -> lmfilm::lsys::Diagnostic {
    match parse(&Source::new("e.lmr", text)) {
        Ok(_) => panic!("accepted: {text}"),
        Err(e) => e,
    }
}

/// Found by the `readable` fuzz target: the classic form lets a section's
/// name follow a symbol without a space; its readable spelling keeps them
/// apart.
#[test]
fn a_section_glued_to_a_symbol_is_spelt_apart() {
    let classic = "Axiom\nF XYZAProductions\nA (1)\n1 B EndProb\nEnd\nEndProductions\n";
    let readable = to_readable(&Source::new("g.lm", classic)).unwrap();
    assert!(readable.contains("A\nproductions"), "{readable}");
    assert_eq!(
        meaning(parsed("g.lmr", &readable)),
        meaning(parsed("g.lm", classic))
    );
}

/// Found by the `readable` fuzz target: a vertical tab (Unicode
/// whitespace, not ASCII) in a keyword section made the reader stand
/// still and grow without bound.
#[test]
fn a_vertical_tab_in_a_keyword_line_is_an_error_not_a_hang() {
    let e = error("camera\npref_pos_x1_x2_y1_y\t\x0b0 180\naxiom\nF\n");
    assert_eq!((e.line, e.column), (2, 1), "{e}");
    assert!(e.message.contains("unknown keyword"), "{e}");
}

#[test]
fn mistakes_are_located_in_the_readable_file_and_teach() {
    let cases: &[(&str, (usize, usize), &[&str])] = &[
        (
            "axiom\nsphere(0.5) turn_lft(30)\n",
            (2, 13),
            &["unknown symbol `turn_lft`", "did you mean `turn_left`?"],
        ),
        (
            "axiom\nsphere(radius: 1)\n",
            (2, 8),
            &["no parameter `radius`", "diameter: a length in metres"],
        ),
        (
            "axiom\nturn_left(30, 40)\n",
            (2, 15),
            &["takes 1 argument", "angle: an angle in degrees"],
        ),
        (
            "axiom\ndiffuse(0.2, 1.5, 0)\n",
            (2, 14),
            &["`green` is a colour component in 0…1, found 1.5"],
        ),
        (
            "axiom\nactor(0.5)\n",
            (2, 7),
            &["`actor` is an actor number"],
        ),
        ("axiom\nbody(hold: 7)\n", (2, 12), &["`hold`", "3 its hips"]),
        ("axiom\nmaterial(\"red\")\n", (2, 11), &["not a text"]),
        (
            "axiom\nautomata(goal)\n",
            (2, 10),
            &["`command` is an automata command in quotes"],
        ),
        ("axiom\nF(x: 1, x: 2)\n", (2, 9), &["`x` is given twice"]),
        (
            "axiom\nsphere(sine(time))\n",
            (2, 8),
            &["unknown function `sine`", "`sin`"],
        ),
        (
            "axiom\nsphere(2 * q)\n",
            (2, 12),
            &["`q` is used but not defined in the Constants section"],
        ),
        (
            "Axiom\nF\n",
            (1, 1),
            &["in the readable form it is `axiom`"],
        ),
        (
            "axiom\nF\nproductions\nrule F at_age 1 if x + 1 {\n  1 -> G\n}\n",
            (4, 25),
            &["a condition compares two expressions"],
        ),
        (
            "axiom\nF\nproductions\nrule F at_age 1 iff x > 0 {\n  1 -> G\n}\n",
            (4, 17),
            &["did you mean `if`?"],
        ),
        (
            "axiom\nF\nproductions\nrule F {\n  G\n}\n",
            (5, 3),
            &["probability"],
        ),
        (
            "axiom\nF\nproductions\nrule F {\n  1 -> 2\n}\n",
            (5, 8),
            &["a digit symbol is quoted: '1'"],
        ),
        (
            "axiom\nF\nproductions\nrule F {\n  1 -> G\n",
            (4, 8),
            &["`{` is not closed"],
        ),
        ("axiom\nsphere(1 /* c */)\n", (2, 10), &["a comment inside"]),
        ("camera\nt_final_interval 1 0\naxiom\nF\n", (2, 20), &[]),
    ];
    for (text, (line, column), parts) in cases {
        let e = error(text);
        assert_eq!((e.line, e.column), (*line, *column), "{text}: {e}");
        assert!(e.file.ends_with("e.lmr"), "{e}");
        for p in *parts {
            assert!(e.message.contains(p), "{text}: `{p}` not in {e}");
        }
    }
}
