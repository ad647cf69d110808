//! Infix expressions (issue 40): `(= …)` groups read with the usual
//! precedence and every function by name compile to what their postfix
//! spelling compiles to — on a table of cases, on random expressions,
//! and on every expression of every shipped scene, rewritten in infix
//! (the derivation prints the same words); mistakes are located and
//! suggest the nearest name.

use lmfilm::lsys::expr::special_arity;
use lmfilm::lsys::infix::SPECIALS;
use lmfilm::lsys::{Animation, NoSensors, Source};

/// Precedences of the infix form: sums, products, a negation, powers,
/// atoms.
const SUM: u8 = 1;
const PRODUCT: u8 = 2;
const NEGATION: u8 = 3;
const POWER: u8 = 4;
const ATOM: u8 = 5;

fn wrap((text, prec): (String, u8), least: u8) -> String {
    if prec >= least {
        text
    } else {
        format!("({text})")
    }
}

/// The infix spelling of postfix `text`, or None when it is not one
/// postfix expression (a number alone stays None too: nothing to
/// rewrite).
fn infix_of(text: &str) -> Option<String> {
    let b = text.as_bytes();
    let mut st: Vec<(String, u8)> = Vec::new();
    let mut i = 0;
    let mut ops = 0;
    let call = |st: &mut Vec<(String, u8)>, name: &str, n: usize| -> Option<()> {
        let args = st.split_off(st.len().checked_sub(n)?);
        let args: Vec<String> = args.into_iter().map(|a| a.0).collect();
        st.push((format!("{name}({})", args.join(", ")), ATOM));
        Some(())
    };
    while i < b.len() {
        let c = b[i];
        match c {
            b' ' | b'\t' | b'\'' => {}
            b'0'..=b'9' | b'.' => {
                let start = i;
                while i + 1 < b.len() && (b[i + 1].is_ascii_digit() || b[i + 1] == b'.') {
                    i += 1;
                }
                st.push((text[start..=i].to_string(), ATOM));
            }
            b'?' => {
                let n: u8 = text.get(i + 1..i + 3)?.parse().ok()?;
                let arity = special_arity(n)?;
                let name = match n {
                    44 => "mem",
                    _ => SPECIALS.iter().find(|s| s.1 == n)?.0,
                };
                call(&mut st, name, arity)?;
                ops += 1;
                i += 2;
            }
            b't' => st.push(("age".into(), ATOM)),
            b'T' => st.push(("time".into(), ATOM)),
            b'X' | b'Y' | b'Z' => st.push((format!("other_{}", (c - b'X' + b'x') as char), ATOM)),
            b'u' | b'v' | b'w' => st.push((format!("vel_{}", (c - b'u' + b'x') as char), ATOM)),
            b'a'..=b's' | b'x'..=b'z' | b'A'..=b'S' => st.push(((c as char).to_string(), ATOM)),
            b'+' | b'-' | b'*' | b'/' | b'%' | b'^' => {
                let r = st.pop()?;
                let l = st.pop()?;
                let (prec, left, right) = match c {
                    b'+' | b'-' => (SUM, SUM, PRODUCT),
                    b'^' => (POWER, ATOM, NEGATION),
                    _ => (PRODUCT, PRODUCT, NEGATION),
                };
                let t = format!("{} {} {}", wrap(l, left), c as char, wrap(r, right));
                st.push((t, prec));
                ops += 1;
            }
            b'_' => {
                let a = st.pop()?;
                st.push((format!("-{}", wrap(a, NEGATION)), NEGATION));
                ops += 1;
            }
            _ => {
                let (name, n) = match c {
                    b'|' => ("abs", 1),
                    b'$' => ("sin", 1),
                    b'&' => ("cos", 1),
                    b':' => ("asin", 1),
                    b'"' => ("tanh", 1),
                    b'>' => ("mem", 1),
                    b'~' => ("step", 2),
                    b'<' => ("mem_set", 2),
                    b'!' => ("rand", 0),
                    b'#' => ("rand_range", 2),
                    _ => return None,
                };
                call(&mut st, name, n)?;
                ops += 1;
            }
        }
        i += 1;
    }
    (st.len() == 1 && ops > 0).then(|| st.pop().unwrap().0)
}

/// The scene text with every postfix group (of a symbol, of a
/// condition; one that converts) written `(= infix)`.
fn rewritten(text: &str) -> (String, usize) {
    let mut out = String::with_capacity(text.len() * 2);
    let mut count = 0;
    let mut rest = text;
    while let Some(open) = rest.find('(') {
        out.push_str(&rest[..=open]);
        rest = &rest[open + 1..];
        let Some(close) = rest
            .find([')', '\n'])
            .filter(|&c| rest.as_bytes()[c] == b')')
        else {
            continue;
        };
        match infix_of(&rest[..close]) {
            Some(infix) => {
                out.push_str(&format!("= {infix}"));
                count += 1;
            }
            None => out.push_str(&rest[..close]),
        }
        rest = &rest[close..];
    }
    out.push_str(rest);
    (out, count)
}

/// The full words of a scene's first frames.
fn words(name: &str, text: &str) -> Vec<String> {
    let mut a = Animation::from_sources(&[Source::new(name, text)], &mut NoSensors)
        .unwrap_or_else(|e| panic!("{e}"));
    let mut out = Vec::new();
    for frame in [0u64, 3, 11] {
        if a.advance_to(frame, &mut NoSensors).is_err() {
            break;
        }
        let (t, seed) = (a.time(), a.camera.seed);
        for ls in &mut a.systems {
            out.push(lmfilm::lsys::print::word(
                ls,
                lmfilm::lsys::print::Format::Full,
                t,
                seed,
                &mut NoSensors,
            ));
        }
    }
    out
}

#[test]
fn infix_groups_compile_as_their_postfix_spelling() {
    let cases = [
        ("x 2 *", "x * 2"),
        ("2 3 4 * +", "2 + 3 * 4"),
        ("2 3 + 4 *", "(2 + 3) * 4"),
        ("2 3 2 ^ ^", "2 ^ 3 ^ 2"),
        ("2 _ 2 ^", "(-2) ^ 2"),
        ("2 2 ^ _", "-2 ^ 2"),
        ("1 2 - 3 -", "1 - 2 - 3"),
        ("1 2 3 - -", "1 - (2 - 3)"),
        ("90 T * $ 2 *", "sin(90 * time) * 2"),
        ("t T + x y z * / -", "age + T - x / (y * z)"),
        ("x 0.5 ~", "step(x, 0.5)"),
        ("3 4 < 3 > +", "mem_set(3, 4) + mem(3)"),
        ("1e3", "1e3 + 0"),
    ];
    for (postfix, infix) in cases {
        let scene = |g: &str| {
            format!("Camera_AnimationParameters\nt_final_interval 1 0.04\nAxiom\nF () ({g})\n")
        };
        // `1e3` is no postfix number: compare with 1000 + 0 instead.
        let postfix = if postfix == "1e3" {
            "1000 0 +"
        } else {
            postfix
        };
        assert_eq!(
            words("a.lm", &scene(postfix)),
            words("a.lm", &scene(&format!("= {infix}"))),
            "{postfix} against {infix}"
        );
    }
}

/// Every expression of every shipped scene, written in infix (by this
/// test's own printer), derives the same words.
#[test]
fn every_shipped_expression_reads_the_same_in_infix() {
    let root = format!("{}/scenes", env!("CARGO_MANIFEST_DIR"));
    let mut total = 0;
    for dir in std::fs::read_dir(&root).unwrap() {
        let dir = dir.unwrap().path();
        let Ok(files) = std::fs::read_dir(&dir) else {
            continue;
        };
        for f in files {
            let path = f.unwrap().path();
            if path.extension().is_none_or(|e| e != "lm") || path.ends_with("landscape.lm") {
                continue;
            }
            let text = std::fs::read_to_string(&path).unwrap();
            // Scenes that import files are read where they lie.
            let name = path.display().to_string();
            let (infix, count) = rewritten(&text);
            total += count;
            if Animation::from_sources(&[Source::new(&name, &text)], &mut NoSensors).is_err() {
                continue;
            }
            assert_eq!(words(&name, &text), words(&name, &infix), "{name}");
        }
    }
    assert!(total > 500, "{total} expressions rewritten");
}

/// Mistakes in an infix group are located in it: an unknown name
/// suggests the nearest, a wrong number of arguments names the function.
#[test]
fn infix_mistakes_are_located_and_suggest_names() {
    let error = |g: &str| {
        let text =
            format!("Camera_AnimationParameters\nt_final_interval 1 0.04\nAxiom\nF () (= {g})\n");
        Animation::from_sources(&[Source::new("e.lm", &text)], &mut NoSensors)
            .err()
            .unwrap_or_else(|| panic!("{g} was accepted"))
            .to_string()
    };
    let e = error("sine(x)");
    assert!(
        e.contains("did you mean `sin`") && e.contains("e.lm:4:9"),
        "{e}"
    );
    let e = error("2 * tme");
    assert!(e.contains("did you mean `time`"), "{e}");
    assert!(error("step(x)").contains("takes 2 arguments, given 1"));
    assert!(error("(x + 1").contains("closed"));
    assert!(error("sin(x + 1").contains("closed"));
    assert!(error("x + ").contains("ends where a value is expected"));
    assert!(error("x y").contains("unexpected text"));
    assert!(error("spline1()").contains("spline 1"));
    // Deep nesting is an error, not a stack overflow.
    let deep = format!("{}x{}", "(".repeat(100_000), ")".repeat(100_000));
    assert!(error(&deep).contains("nests more than"));
    assert!(error(&"-".repeat(100_000)).contains("nests more than"));
    assert!(error(&"2^".repeat(100_000)).contains("deep"));
}
