//! Postfix expressions (thesis 2.1.4, tables B2–B5) compiled once into a
//! flat program of [`Op`]s; nothing is parsed while deriving.
//!
//! The compiler tracks the stack depth of every operator, so a program that
//! would underflow, or leave more than one value, is a compile error with
//! its column, and evaluation needs no checks.

use super::functions::{constant_index, Constants};
use super::scan::MAX_NUMBER;
use crate::source::{Diagnostic, Source};

/// Deepest stack a program may use; far beyond any hand-written expression.
pub const MAX_DEPTH: usize = 32;

/// The parameters of table B5 (normal and force-field semantics).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Param {
    /// `t`: local age of the symbol.
    Age,
    /// `T`: global time.
    Time,
    /// `x y z`: par1..par3 (or the particle position).
    Par(u8),
    /// `X Y Z`: position of the interacting particle.
    Other(u8),
    /// `u v w`: velocity of the particle.
    Velocity(u8),
    /// `r`: distance to the interacting particle.
    Distance,
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Op {
    Num(f64),
    Param(Param),
    /// A Constants function (a..s, A..S) by letter index.
    Constant(u8),
    /// `!`: uniform random number in [0, 1).
    Rand,
    /// `#`: c0 + c1·random, c1 on top of the stack.
    RandRange,
    Add,
    Sub,
    Mul,
    Div,
    Pow,
    Mod,
    /// `~`: 0 if a < b or a < 0, else 1.
    PostfixOp,
    /// `<` (binary): memory[a] = b, leaves b.
    MemSet,
    Abs,
    Neg,
    Sin,
    Cos,
    Asin,
    Tanh,
    /// `>` (unary) and `?44`: memory[a].
    MemGet,
    /// `?nn` special function.
    Special(u8),
    /// Predicates of table B4, comparing the top with 0.
    Lt,
    Le,
    Gt,
    Ge,
    Eq,
    Ne,
    And,
    Or,
    Not,
}

impl Op {
    /// (values popped, values pushed).
    fn effect(self) -> (usize, usize) {
        use Op::*;
        match self {
            Num(_) | Param(_) | Constant(_) | Rand => (0, 1),
            RandRange | Add | Sub | Mul | Div | Pow | Mod | PostfixOp | MemSet | And | Or => (2, 1),
            Abs | Neg | Sin | Cos | Asin | Tanh | MemGet | Lt | Le | Gt | Ge | Eq | Ne | Not => {
                (1, 1)
            }
            Special(n) => (special_arity(n).unwrap_or(0), 1),
        }
    }
}

/// Arity of the special functions of table B5; `None` for undefined numbers.
pub fn special_arity(n: u8) -> Option<usize> {
    match n {
        3 | 8 | 29 | 44 => Some(1),
        50 => Some(2),
        0..=2 | 9 | 12..=43 | 60..=62 => Some(0),
        _ => None,
    }
}

/// A compiled expression: a constant, or a range of the shared op table.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Expr {
    Const(f64),
    Prog { start: u32, len: u32 },
}

/// The op table of one definition file.
#[derive(Debug, Default, Clone)]
pub struct Code {
    pub ops: Vec<Op>,
}

/// Compiles expressions of one file against its Constants and Splines.
pub struct Compiler<'a> {
    pub src: &'a Source,
    pub code: &'a mut Code,
    pub constants: &'a Constants,
    pub splines: &'a [u32],
}

/// Tracks stack depth while ops are appended.
pub struct Emitter {
    start: usize,
    depth: usize,
}

impl<'a> Compiler<'a> {
    pub fn begin(&self) -> Emitter {
        Emitter {
            start: self.code.ops.len(),
            depth: 0,
        }
    }

    pub fn push(&mut self, em: &mut Emitter, op: Op, offset: usize) -> Result<(), Diagnostic> {
        let (pop, push) = op.effect();
        if em.depth < pop {
            let hint = if op == Op::Sub && em.depth == 0 {
                "; a negative number is written `2_`"
            } else {
                "; postfix puts operands first, e.g. `x 2 *`"
            };
            return Err(self.src.error(
                offset,
                format!(
                    "stack underflow: this operator needs {pop} value{}, the stack holds {}{hint}",
                    if pop == 1 { "" } else { "s" },
                    em.depth
                ),
            ));
        }
        em.depth = em.depth - pop + push;
        if em.depth > MAX_DEPTH {
            return Err(self.src.error(
                offset,
                format!("expression too deep: more than {MAX_DEPTH} values on the stack"),
            ));
        }
        self.code.ops.push(op);
        Ok(())
    }

    /// Ends a program that must leave exactly one value.
    pub fn finish(&mut self, em: Emitter, offset: usize) -> Result<Expr, Diagnostic> {
        if em.depth != 1 {
            return Err(self.src.error(
                offset,
                format!(
                    "expression leaves {} values on the stack; it must leave exactly one (combine them with an operator)",
                    em.depth
                ),
            ));
        }
        let ops = &self.code.ops[em.start..];
        if let [Op::Num(v)] = ops {
            let v = *v;
            self.code.ops.truncate(em.start);
            return Ok(Expr::Const(v));
        }
        Ok(Expr::Prog {
            start: em.start as u32,
            len: ops.len() as u32,
        })
    }

    /// Compiles the text of a `( )` group; an empty group gives `None`.
    pub fn group(&mut self, text: &str, offset: usize) -> Result<Option<Expr>, Diagnostic> {
        if text
            .trim_matches(|c: char| c.is_whitespace() || c == '\'')
            .is_empty()
        {
            return Ok(None);
        }
        let mut em = self.begin();
        self.expression(&mut em, text, offset)?;
        self.finish(em, offset).map(Some)
    }

    /// Appends the ops of the expression `text` (at `offset`): infix when
    /// it starts with `=` (issue 40), else postfix.
    pub fn expression(
        &mut self,
        em: &mut Emitter,
        text: &str,
        offset: usize,
    ) -> Result<(), Diagnostic> {
        let lead = text.len() - text.trim_start().len();
        match text[lead..].strip_prefix('=') {
            Some(infix) => self.infix(em, infix, offset + lead + 1),
            None => self.tokens(em, text, offset),
        }
    }

    /// Appends the ops of postfix `text` (which starts at `offset`).
    pub fn tokens(
        &mut self,
        em: &mut Emitter,
        text: &str,
        offset: usize,
    ) -> Result<(), Diagnostic> {
        let b = text.as_bytes();
        let mut i = 0;
        while i < b.len() {
            let at = offset + i;
            let c = b[i];
            let op = match c {
                b' ' | b'\t' | b'\r' | b'\'' => {
                    i += 1;
                    continue;
                }
                b'0'..=b'9' | b'.' => {
                    let start = i;
                    while i < b.len() && b[i].is_ascii_digit() {
                        i += 1;
                    }
                    if i < b.len() && b[i] == b'.' {
                        i += 1;
                        while i < b.len() && b[i].is_ascii_digit() {
                            i += 1;
                        }
                    }
                    let lit = &text[start..i];
                    let v = lit
                        .parse::<f64>()
                        .ok()
                        .filter(|v| *v <= MAX_NUMBER)
                        .ok_or_else(|| {
                            self.src.error(
                                at,
                                format!("`{lit}` is not a number of at most {MAX_NUMBER:e}"),
                            )
                        })?;
                    self.push(em, Op::Num(v), at)?;
                    continue;
                }
                b'?' => {
                    let digits = text
                        .get(i + 1..i + 3)
                        .filter(|d| d.bytes().all(|c| c.is_ascii_digit()));
                    let Some(d) = digits else {
                        return Err(self
                            .src
                            .error(at, "`?` must be followed by two digits, e.g. `?40`"));
                    };
                    let n: u8 = d.parse().unwrap_or(99);
                    if special_arity(n).is_none() {
                        return Err(self.src.error(
                            at,
                            format!("unknown special function `?{d}`: table B5 defines ?00–?03, ?08, ?09, ?12–?44, ?50 and ?60–?62"),
                        ));
                    }
                    if n <= 3 && !self.splines.contains(&(n as u32)) {
                        return Err(self.src.error(
                            at,
                            format!("`?{d}` reads spline {n}, which the Splines section does not define"),
                        ));
                    }
                    i += 3;
                    self.push(em, if n == 44 { Op::MemGet } else { Op::Special(n) }, at)?;
                    continue;
                }
                b't' => Op::Param(Param::Age),
                b'T' => Op::Param(Param::Time),
                b'x' | b'y' | b'z' => Op::Param(Param::Par(c - b'x')),
                b'X' | b'Y' | b'Z' => Op::Param(Param::Other(c - b'X')),
                b'u' | b'v' | b'w' => Op::Param(Param::Velocity(c - b'u')),
                b'r' if !self.constants.defined(b'r') => Op::Param(Param::Distance),
                b'a'..=b's' | b'A'..=b'S' => {
                    if !self.constants.defined(c) {
                        return Err(self.src.error(
                            at,
                            format!("function `{}` is used but not defined in the Constants section (add e.g. `{} 1.0 0.0`)", c as char, c as char),
                        ));
                    }
                    Op::Constant(constant_index(c))
                }
                b'!' => Op::Rand,
                b'#' => Op::RandRange,
                b'+' => Op::Add,
                b'-' => Op::Sub,
                b'*' => Op::Mul,
                b'/' => Op::Div,
                b'^' => Op::Pow,
                b'%' => Op::Mod,
                b'~' => Op::PostfixOp,
                b'<' => Op::MemSet,
                b'|' => Op::Abs,
                b'_' => Op::Neg,
                b'$' => Op::Sin,
                b'&' => Op::Cos,
                b':' => Op::Asin,
                b'"' => Op::Tanh,
                b'>' => Op::MemGet,
                _ => {
                    let ch = text[i..].chars().next().unwrap_or('?');
                    let hint = if ch == '-' || ch == '−' {
                        " (a negative number is written `2_`)"
                    } else {
                        ""
                    };
                    return Err(self.src.error(
                        at,
                        format!("unknown operator or parameter `{ch}` in expression{hint}"),
                    ));
                }
            };
            self.push(em, op, at)?;
            i += 1;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn compile(text: &str, constants: &Constants) -> Result<(Code, Option<Expr>), Diagnostic> {
        let src = Source::new("t", format!("({text})"));
        let mut code = Code::default();
        let mut c = Compiler {
            src: &src,
            code: &mut code,
            constants,
            splines: &[],
        };
        let e = c.group(text, 1)?;
        Ok((code, e))
    }

    #[test]
    fn folds_constants_and_reports_errors() {
        let k = Constants::default();
        assert_eq!(compile("2", &k).unwrap().1, Some(Expr::Const(2.0)));
        assert_eq!(compile("  ", &k).unwrap().1, None);
        let (code, e) = compile("x2*", &k).unwrap();
        assert_eq!(e, Some(Expr::Prog { start: 0, len: 3 }));
        assert_eq!(code.ops[1], Op::Num(2.0));
        let err = compile("x+", &k).unwrap_err();
        assert!(err.message.contains("stack underflow"), "{err}");
        assert_eq!(err.column, 3);
        assert!(compile("x y", &k).unwrap_err().message.contains("leaves 2"));
        assert!(compile("x @", &k)
            .unwrap_err()
            .message
            .contains("unknown operator"));
        assert!(compile("a", &k).unwrap_err().message.contains("Constants"));
        assert!(compile("?07", &k)
            .unwrap_err()
            .message
            .contains("special function"));
        assert!(compile("?01", &k).unwrap_err().message.contains("spline 1"));
    }
}
