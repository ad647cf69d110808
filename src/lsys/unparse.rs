//! Compiled expressions back to text: the infix spelling of a program
//! (issue 40's converter), written so that reading it again compiles to
//! exactly the same ops, and a production's condition as `y <= 3 and not
//! x == 0`.

use super::expr::{special_arity, Op, Param};
use super::infix::{FUNCTIONS, PARAMETERS, SPECIALS};

/// Binding strength of a printed expression: sums, products, a
/// negation, powers, atoms (the infix grammar's levels).
const SUM: u8 = 1;
const PRODUCT: u8 = 2;
const NEGATION: u8 = 3;
const ATOM: u8 = 5;

/// Binding strength of a printed condition: or, and, not, an atom.
const OR: u8 = 1;
const AND: u8 = 2;
const NOT: u8 = 3;
const COMPARISON: u8 = 4;

/// A value on the printer's stack: text and how strongly it binds; a
/// condition or an arithmetic value.
#[derive(Clone)]
struct Printed {
    text: String,
    strength: u8,
    logic: bool,
    /// For an arithmetic `a - b`: a and b, so that `a - b < 0` prints as
    /// `a < b`.
    difference: Option<Box<(Printed, Printed)>>,
}

fn value(text: String, strength: u8) -> Printed {
    Printed {
        text,
        strength,
        logic: false,
        difference: None,
    }
}

fn wrap(p: &Printed, least: u8) -> String {
    if p.strength >= least {
        p.text.clone()
    } else {
        format!("({})", p.text)
    }
}

/// A number as the infix form reads it back to the same `f64`.
pub fn number(v: f64) -> String {
    format!("{v}")
}

/// The name of a parameter in the infix form.
fn parameter(p: Param) -> &'static str {
    PARAMETERS
        .iter()
        .find(|(_, q)| *q == p)
        .map_or("?", |(n, _)| *n)
}

/// The letter of a Constants function by its index.
fn constant_letter(i: u8) -> char {
    if i < 26 {
        (b'a' + i) as char
    } else {
        (b'A' + i - 26) as char
    }
}

/// The symbol of a predicate.
fn comparison(op: Op) -> Option<&'static str> {
    Some(match op {
        Op::Lt => "<",
        Op::Le => "<=",
        Op::Gt => ">",
        Op::Ge => ">=",
        Op::Eq => "==",
        Op::Ne => "!=",
        _ => return None,
    })
}

/// Prints `ops`; `None` when they are not one expression (or one
/// condition, with `logic`) the readable form can spell: a predicate of
/// a condition or a logic operator on a plain value.
fn print(ops: &[Op], logic: bool) -> Option<String> {
    let mut st: Vec<Printed> = Vec::new();
    for &op in ops {
        let pushed = match op {
            Op::Num(v) => value(number(v), ATOM),
            Op::Param(p) => value(parameter(p).to_string(), ATOM),
            Op::Constant(i) => value(constant_letter(i).to_string(), ATOM),
            Op::Add | Op::Sub | Op::Mul | Op::Div | Op::Mod => {
                let b = st.pop()?;
                let a = st.pop()?;
                if a.logic || b.logic {
                    return None;
                }
                let (sign, level) = match op {
                    Op::Add => ("+", SUM),
                    Op::Sub => ("-", SUM),
                    Op::Mul => ("*", PRODUCT),
                    Op::Div => ("/", PRODUCT),
                    _ => ("%", PRODUCT),
                };
                let text = format!("{} {sign} {}", wrap(&a, level), wrap(&b, level + 1));
                let mut p = value(text, level);
                if op == Op::Sub {
                    p.difference = Some(Box::new((a, b)));
                }
                p
            }
            Op::Pow => {
                let b = st.pop()?;
                let a = st.pop()?;
                if a.logic || b.logic {
                    return None;
                }
                // power := atom '^' unary
                value(format!("{} ^ {}", wrap(&a, ATOM), wrap(&b, NEGATION)), 4)
            }
            Op::Neg => {
                let a = st.pop()?;
                if a.logic {
                    return None;
                }
                value(format!("-{}", wrap(&a, NEGATION)), NEGATION)
            }
            Op::Lt | Op::Le | Op::Gt | Op::Ge | Op::Eq | Op::Ne => {
                let a = st.pop()?;
                if a.logic || !logic {
                    return None;
                }
                let sign = comparison(op)?;
                let text = match &a.difference {
                    // `a - b < 0` is `a < b`, unless b is the 0 that a
                    // comparison with nothing on its right is written with.
                    Some(d) if d.1.text != "0" => format!("{} {sign} {}", d.0.text, d.1.text),
                    _ => format!("{} {sign} 0", a.text),
                };
                Printed {
                    text,
                    strength: COMPARISON,
                    logic: true,
                    difference: None,
                }
            }
            Op::And | Op::Or => {
                let b = st.pop()?;
                let a = st.pop()?;
                if !a.logic || !b.logic {
                    return None;
                }
                let (word, level) = if op == Op::And {
                    ("and", AND)
                } else {
                    ("or", OR)
                };
                Printed {
                    text: format!("{} {word} {}", wrap(&a, level), wrap(&b, level + 1)),
                    strength: level,
                    logic: true,
                    difference: None,
                }
            }
            Op::Not => {
                let a = st.pop()?;
                if !a.logic {
                    return None;
                }
                Printed {
                    text: format!("not {}", wrap(&a, NOT)),
                    strength: NOT,
                    logic: true,
                    difference: None,
                }
            }
            call => {
                let (name, n) = function(call)?;
                let args = st.split_off(st.len().checked_sub(n)?);
                if args.iter().any(|a| a.logic) {
                    return None;
                }
                let args: Vec<String> = args.into_iter().map(|a| a.text).collect();
                value(format!("{name}({})", args.join(", ")), ATOM)
            }
        };
        st.push(pushed);
    }
    match st.as_slice() {
        [one] if one.logic == logic => Some(one.text.clone()),
        _ => None,
    }
}

/// The name and argument count of a function op.
fn function(op: Op) -> Option<(&'static str, usize)> {
    if let Op::Special(n) = op {
        let name = SPECIALS.iter().find(|(_, k)| *k == n)?.0;
        return Some((name, special_arity(n)?));
    }
    FUNCTIONS
        .iter()
        .find(|(_, o, _)| *o == op)
        .map(|(name, _, n)| (*name, *n))
}

/// The infix spelling of one expression's ops.
pub fn expression(ops: &[Op]) -> Option<String> {
    print(ops, false)
}

/// The readable spelling of a condition's ops.
pub fn condition(ops: &[Op]) -> Option<String> {
    print(ops, true)
}

/// The postfix spelling of one expression's ops (thesis 2.1.4), tokens
/// apart; `None` for a distance `r` where a Constants function `r` is
/// defined (the letter would read as the function).
pub fn postfix(ops: &[Op], constant_r: bool) -> Option<String> {
    let mut out: Vec<String> = Vec::with_capacity(ops.len());
    for &op in ops {
        out.push(match op {
            Op::Num(v) => number(v),
            Op::Param(Param::Distance) if constant_r => return None,
            Op::Param(p) => match p {
                Param::Age => "t".into(),
                Param::Time => "T".into(),
                Param::Par(i) => ((b'x' + i) as char).to_string(),
                Param::Other(i) => ((b'X' + i) as char).to_string(),
                Param::Velocity(i) => ((b'u' + i) as char).to_string(),
                Param::Distance => "r".into(),
            },
            Op::Constant(i) => constant_letter(i).to_string(),
            Op::Special(n) => format!("?{n:02}"),
            op => match op {
                Op::Rand => "!",
                Op::RandRange => "#",
                Op::Add => "+",
                Op::Sub => "-",
                Op::Mul => "*",
                Op::Div => "/",
                Op::Pow => "^",
                Op::Mod => "%",
                Op::PostfixOp => "~",
                Op::MemSet => "<",
                Op::Abs => "|",
                Op::Neg => "_",
                Op::Sin => "$",
                Op::Cos => "&",
                Op::Asin => ":",
                Op::Tanh => "\"",
                Op::MemGet => ">",
                _ => return None,
            }
            .into(),
        });
    }
    Some(out.join(" "))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lsys::expr::{Code, Compiler, Expr};
    use crate::lsys::functions::Constants;
    use crate::source::Source;

    fn ops(text: &str) -> Vec<Op> {
        let src = Source::new("t", text);
        let mut code = Code::default();
        let mut c = Compiler {
            src: &src,
            code: &mut code,
            constants: &Constants::default(),
            splines: &[],
        };
        match c.group(text, 0).unwrap().unwrap() {
            Expr::Const(v) => vec![Op::Num(v)],
            Expr::Prog { .. } => code.ops,
        }
    }

    #[test]
    fn printed_infix_compiles_to_the_same_ops() {
        for postfix in [
            "x2*",
            "xy+z*",
            "xyz--",
            "xy-z-",
            "2 3 2^^",
            "2 3^2^",
            "x_2^",
            "x2^_",
            "x_ _",
            "xy_-",
            "T90*$2*x+",
            "1 2#",
            "3>",
            "3 4<",
            "?40",
            "x y ~ t |+",
            "0.25_",
            "x 1 2 ?50 +",
        ] {
            let o = ops(postfix);
            let text = expression(&o).unwrap();
            assert_eq!(ops(&format!("= {text}")), o, "{postfix} → {text}");
            let back = super::postfix(&o, false).unwrap();
            assert_eq!(ops(&back), o, "{postfix} → {back}");
        }
    }
}
