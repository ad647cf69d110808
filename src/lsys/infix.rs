//! Infix expressions (issue 40, thesis 8.1.2: "ordinary infix
//! expressions converted to the postfix form at parsing"): a group that
//! starts with `=` — `(= 2 * sin(90 * time) + x)` — is read with the
//! usual precedence and compiled into the same ops as its postfix
//! spelling (`(2 90 T * $ * x +)`), every function of tables B2–B5 by
//! name. Errors point into the group's own text.

use super::expr::{special_arity, Compiler, Emitter, Op, Param};
use super::functions::constant_index;
use super::scan::{name_suggestion, MAX_NUMBER};
use crate::source::Diagnostic;

/// The named functions: (name, op, arguments).
pub const FUNCTIONS: [(&str, Op, usize); 10] = [
    ("sin", Op::Sin, 1),
    ("cos", Op::Cos, 1),
    ("asin", Op::Asin, 1),
    ("tanh", Op::Tanh, 1),
    ("abs", Op::Abs, 1),
    ("step", Op::PostfixOp, 2),
    ("mem", Op::MemGet, 1),
    ("mem_set", Op::MemSet, 2),
    ("rand", Op::Rand, 0),
    ("rand_range", Op::RandRange, 2),
];

/// The special functions `?nn` of table B5 by name (their arguments are
/// [`special_arity`]'s); docs/language.md lists what each computes.
pub const SPECIALS: [(&str, u8); 42] = [
    ("spline0", 0),
    ("spline1", 1),
    ("spline2", 2),
    ("spline3", 3),
    ("clamp01", 8),
    ("toward_x", 9),
    ("wall_x", 12),
    ("wall_y", 13),
    ("wall_z", 14),
    ("racket_force_x", 15),
    ("racket_force_y", 16),
    ("racket_force_z", 17),
    ("gravity", 18),
    ("tennis_net", 19),
    ("swim", 20),
    ("repeated_shape", 21),
    ("repeated_shape_last", 22),
    ("attraction", 23),
    ("attraction_last", 24),
    ("wing_beat", 25),
    ("ground_repulsion", 26),
    ("ball_ground_ramp", 27),
    ("hermite_age", 28),
    ("hermite", 29),
    ("seen_distance", 30),
    ("obstacle_side", 31),
    ("looks_at_goal", 32),
    ("arrived", 33),
    ("phase_degrees", 34),
    ("automata", 35),
    ("interest_found", 36),
    ("rgb_interest_found", 37),
    ("rgb_interest_goal", 38),
    ("near_goal", 39),
    ("force_at", 40),
    ("growth1", 41),
    ("growth2", 42),
    ("growth3", 43),
    ("channel", 50),
    ("sounds_now", 60),
    ("sound_of_source", 61),
    ("source_of_sound", 62),
];

/// The parameters by name (the letters of table B5 stay valid too).
pub const PARAMETERS: [(&str, Param); 12] = [
    ("age", Param::Age),
    ("time", Param::Time),
    ("x", Param::Par(0)),
    ("y", Param::Par(1)),
    ("z", Param::Par(2)),
    ("other_x", Param::Other(0)),
    ("other_y", Param::Other(1)),
    ("other_z", Param::Other(2)),
    ("vel_x", Param::Velocity(0)),
    ("vel_y", Param::Velocity(1)),
    ("vel_z", Param::Velocity(2)),
    ("distance", Param::Distance),
];

/// Every function's name, for suggestions.
fn function_names() -> Vec<&'static str> {
    let named = FUNCTIONS.iter().map(|(n, _, _)| *n);
    named.chain(SPECIALS.iter().map(|(n, _)| *n)).collect()
}

/// A reader of one infix text, pushing ops in postfix order.
struct Reader<'c, 'a> {
    c: &'c mut Compiler<'a>,
    em: &'c mut Emitter,
    text: &'c str,
    offset: usize,
    i: usize,
    /// How deep the reader is nested: bounded, so a line of a million
    /// `(` is an error, not a stack overflow.
    depth: usize,
}

/// Most an infix expression may nest (parentheses, calls, minus signs,
/// powers).
pub const MAX_NESTING: usize = 64;

impl Compiler<'_> {
    /// Appends the ops of infix `text` (which starts at `offset`).
    pub fn infix(&mut self, em: &mut Emitter, text: &str, offset: usize) -> Result<(), Diagnostic> {
        let mut r = Reader {
            c: self,
            em,
            text,
            offset,
            i: 0,
            depth: 0,
        };
        r.sum()?;
        r.skip();
        if r.i < text.len() {
            return Err(r.error(r.i, "unexpected text after the expression"));
        }
        Ok(())
    }
}

impl Reader<'_, '_> {
    fn error(&self, at: usize, message: &str) -> Diagnostic {
        self.c.src.error(self.offset + at, message.to_string())
    }

    fn skip(&mut self) {
        while self.text[self.i..].starts_with([' ', '\t', '\r']) {
            self.i += 1;
        }
    }

    fn peek(&mut self) -> Option<u8> {
        self.skip();
        self.text.as_bytes().get(self.i).copied()
    }

    fn push(&mut self, op: Op, at: usize) -> Result<(), Diagnostic> {
        self.c.push(self.em, op, self.offset + at)
    }

    /// sum := product (('+' | '-') product)*
    fn sum(&mut self) -> Result<(), Diagnostic> {
        self.product()?;
        while let Some(c @ (b'+' | b'-')) = self.peek() {
            let at = self.i;
            self.i += 1;
            self.product()?;
            self.push(if c == b'+' { Op::Add } else { Op::Sub }, at)?;
        }
        Ok(())
    }

    /// product := unary (('*' | '/' | '%') unary)*
    fn product(&mut self) -> Result<(), Diagnostic> {
        self.unary()?;
        while let Some(c @ (b'*' | b'/' | b'%')) = self.peek() {
            let at = self.i;
            self.i += 1;
            self.unary()?;
            let op = match c {
                b'*' => Op::Mul,
                b'/' => Op::Div,
                _ => Op::Mod,
            };
            self.push(op, at)?;
        }
        Ok(())
    }

    /// unary := '-' unary | power. Every nesting (parentheses, calls,
    /// minus signs, powers) passes here, where its depth is bounded.
    fn unary(&mut self) -> Result<(), Diagnostic> {
        self.depth += 1;
        if self.depth > MAX_NESTING {
            let message = format!("the expression nests more than {MAX_NESTING} deep");
            return Err(self.error(self.i, &message));
        }
        let done = self.unary_within();
        self.depth -= 1;
        done
    }

    fn unary_within(&mut self) -> Result<(), Diagnostic> {
        if self.peek() == Some(b'-') {
            let at = self.i;
            self.i += 1;
            self.unary()?;
            return self.push(Op::Neg, at);
        }
        self.power()
    }

    /// power := atom ('^' unary)?   (right to left: 2^3^2 = 2^9)
    fn power(&mut self) -> Result<(), Diagnostic> {
        self.atom()?;
        if self.peek() == Some(b'^') {
            let at = self.i;
            self.i += 1;
            self.unary()?;
            self.push(Op::Pow, at)?;
        }
        Ok(())
    }

    /// atom := number | name | name '(' args ')' | '(' sum ')'
    fn atom(&mut self) -> Result<(), Diagnostic> {
        let at = self.i;
        match self.peek() {
            Some(b'(') => {
                self.i += 1;
                self.sum()?;
                self.close(at)
            }
            Some(b'0'..=b'9' | b'.') => self.number(),
            Some(c) if c.is_ascii_alphabetic() || c == b'_' => self.name(),
            Some(_) => Err(self.error(at, "expected a number, a name or `(`")),
            None => Err(self.error(at, "the expression ends where a value is expected")),
        }
    }

    fn close(&mut self, open: usize) -> Result<(), Diagnostic> {
        if self.peek() != Some(b')') {
            return Err(self.error(open, "this `(` is not closed"));
        }
        self.i += 1;
        Ok(())
    }

    fn number(&mut self) -> Result<(), Diagnostic> {
        let start = self.i;
        let b = self.text.as_bytes();
        while self.i < b.len() && (b[self.i].is_ascii_digit() || b[self.i] == b'.') {
            self.i += 1;
        }
        // An exponent: 1e-3, 2.5E4.
        if self.i < b.len() && matches!(b[self.i], b'e' | b'E') {
            let mut j = self.i + 1;
            if j < b.len() && matches!(b[j], b'+' | b'-') {
                j += 1;
            }
            if j < b.len() && b[j].is_ascii_digit() {
                while j < b.len() && b[j].is_ascii_digit() {
                    j += 1;
                }
                self.i = j;
            }
        }
        let lit = &self.text[start..self.i];
        let v = lit
            .parse::<f64>()
            .ok()
            .filter(|v| v.is_finite() && *v <= MAX_NUMBER)
            .ok_or_else(|| {
                self.error(
                    start,
                    &format!("`{lit}` is not a number of at most {MAX_NUMBER:e}"),
                )
            })?;
        self.push(Op::Num(v), start)
    }

    fn name(&mut self) -> Result<(), Diagnostic> {
        let start = self.i;
        let b = self.text.as_bytes();
        while self.i < b.len() && (b[self.i].is_ascii_alphanumeric() || b[self.i] == b'_') {
            self.i += 1;
        }
        let name = &self.text[start..self.i];
        if self.peek() == Some(b'(') {
            return self.call(name, start);
        }
        let op = match PARAMETERS.iter().find(|(n, _)| *n == name) {
            Some(&(_, p)) => Op::Param(p),
            None => self.letter(name, start)?,
        };
        self.push(op, start)
    }

    /// The one-letter parameters and Constants functions of the postfix
    /// form.
    fn letter(&self, name: &str, at: usize) -> Result<Op, Diagnostic> {
        let &[c] = name.as_bytes() else {
            let mut known = function_names();
            known.extend(PARAMETERS.iter().map(|(n, _)| *n));
            return Err(self.error(
                at,
                &format!(
                    "unknown name `{name}` in an expression{}",
                    name_suggestion(name, &known)
                ),
            ));
        };
        Ok(match c {
            b't' => Op::Param(Param::Age),
            b'T' => Op::Param(Param::Time),
            b'X' | b'Y' | b'Z' => Op::Param(Param::Other(c - b'X')),
            b'u' | b'v' | b'w' => Op::Param(Param::Velocity(c - b'u')),
            b'r' if !self.c.constants.defined(b'r') => Op::Param(Param::Distance),
            b'a'..=b's' | b'A'..=b'S' if self.c.constants.defined(c) => {
                Op::Constant(constant_index(c))
            }
            b'a'..=b's' | b'A'..=b'S' => {
                return Err(self.error(
                    at,
                    &format!(
                        "function `{name}` is used but not defined in the Constants section (add e.g. `{name} 1.0 0.0`)"
                    ),
                ))
            }
            _ => return Err(self.error(at, &format!("unknown name `{name}` in an expression"))),
        })
    }

    /// `name(args…)`: a function of tables B2–B5 by name.
    fn call(&mut self, name: &str, at: usize) -> Result<(), Diagnostic> {
        let (op, arity) = if let Some(&(_, op, n)) = FUNCTIONS.iter().find(|(n, _, _)| *n == name) {
            (op, n)
        } else if let Some(&(_, n)) = SPECIALS.iter().find(|(s, _)| *s == name) {
            if n <= 3 && !self.c.splines.contains(&u32::from(n)) {
                return Err(self.error(
                    at,
                    &format!(
                        "`{name}` reads spline {n}, which the Splines section does not define"
                    ),
                ));
            }
            (Op::Special(n), special_arity(n).unwrap_or(0))
        } else {
            let known = function_names();
            return Err(self.error(
                at,
                &format!("unknown function `{name}`{}", name_suggestion(name, &known)),
            ));
        };
        let open = self.i;
        self.i += 1;
        let mut given = 0;
        if self.peek() != Some(b')') {
            loop {
                self.sum()?;
                given += 1;
                if self.peek() != Some(b',') {
                    break;
                }
                self.i += 1;
            }
        }
        self.close(open)?;
        if given != arity {
            return Err(self.error(
                at,
                &format!(
                    "`{name}` takes {arity} argument{}, given {given}",
                    if arity == 1 { "" } else { "s" }
                ),
            ));
        }
        self.push(op, at)
    }
}
