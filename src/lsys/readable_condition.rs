//! A rule's condition in the readable form (issue 40): `x > 0 and not
//! (y == 1 or z < t)`, read into the steps of the classic form's postfix
//! logic (definition 2.1.6): atoms comparing two expressions, then `&`,
//! `|`, `!` after their operands.

use super::scan::trivia_end;
use crate::source::{Diagnostic, Source};

/// One step of a condition in postfix.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum PostfixOp {
    /// `left pred right`: the byte ranges of the two expressions, where
    /// the comparison is written and its classic predicate (`<`, `p`,
    /// `>`, `g`, `=`, `!`).
    Compare {
        left: (usize, usize),
        right: (usize, usize),
        at: usize,
        pred: char,
    },
    /// `&`, `|` or `!` after its operands, and where its word is.
    Logic { op: char, at: usize },
}

/// The steps of the condition written at `start..end` of `src`.
pub fn condition(src: &Source, start: usize, end: usize) -> Result<Vec<PostfixOp>, Diagnostic> {
    let mut p = Condition {
        src,
        text: &src.text,
        pos: start,
        end,
        steps: Vec::new(),
    };
    p.or()?;
    p.skip()?;
    if p.pos < p.end {
        return Err(src.error(p.pos, "unexpected text in the condition"));
    }
    Ok(p.steps)
}

struct Condition<'a> {
    src: &'a Source,
    text: &'a str,
    pos: usize,
    end: usize,
    steps: Vec<PostfixOp>,
}

/// The comparisons and their classic predicates.
const COMPARISONS: [(&str, char); 6] = [
    ("<=", 'p'),
    (">=", 'g'),
    ("==", '='),
    ("!=", '!'),
    ("<", '<'),
    (">", '>'),
];

impl Condition<'_> {
    /// Skips whitespace and comments, not past the condition's end.
    fn skip(&mut self) -> Result<(), Diagnostic> {
        let end = trivia_end(self.src, self.text.len(), self.pos)?;
        self.pos = end.min(self.end);
        Ok(())
    }

    fn word(&mut self, w: &str) -> bool {
        let _ = self.skip();
        let rest = &self.text[self.pos..self.end];
        let at_word = rest.starts_with(w)
            && !rest[w.len()..]
                .bytes()
                .next()
                .is_some_and(|c| c.is_ascii_alphanumeric() || c == b'_');
        if at_word {
            self.pos += w.len();
        }
        at_word
    }

    fn or(&mut self) -> Result<(), Diagnostic> {
        self.and()?;
        while self.word("or") {
            let at = self.pos;
            self.and()?;
            self.steps.push(PostfixOp::Logic { op: '|', at });
        }
        Ok(())
    }

    fn and(&mut self) -> Result<(), Diagnostic> {
        self.not()?;
        while self.word("and") {
            let at = self.pos;
            self.not()?;
            self.steps.push(PostfixOp::Logic { op: '&', at });
        }
        Ok(())
    }

    fn not(&mut self) -> Result<(), Diagnostic> {
        if self.word("not") {
            let at = self.pos;
            self.not()?;
            self.steps.push(PostfixOp::Logic { op: '!', at });
            return Ok(());
        }
        self.primary()
    }

    /// `( condition )` or a comparison.
    fn primary(&mut self) -> Result<(), Diagnostic> {
        self.skip()?;
        if self.text.as_bytes().get(self.pos).copied() == Some(b'(') {
            let close = self.matching(self.pos)?;
            if self.has_comparison(self.pos + 1, close) {
                self.pos += 1;
                let end = std::mem::replace(&mut self.end, close);
                self.or()?;
                self.skip()?;
                if self.pos != close {
                    return Err(self.src.error(self.pos, "unexpected text in the condition"));
                }
                self.end = end;
                self.pos = close + 1;
                return Ok(());
            }
        }
        self.comparison()
    }

    fn matching(&self, open: usize) -> Result<usize, Diagnostic> {
        let mut depth = 0;
        for (i, c) in self.text[open..self.end].bytes().enumerate() {
            match c {
                b'(' => depth += 1,
                b')' => {
                    depth -= 1;
                    if depth == 0 {
                        return Ok(open + i);
                    }
                }
                _ => {}
            }
        }
        Err(self.src.error(open, "this `(` is not closed"))
    }

    /// Whether `from..to` holds a comparison or a logic word outside
    /// parentheses: a condition, not an expression, in parentheses.
    fn has_comparison(&self, from: usize, to: usize) -> bool {
        let t = &self.text[from..to];
        let mut depth = 0;
        for (i, c) in t.bytes().enumerate() {
            match c {
                b'(' => depth += 1,
                b')' => depth -= 1,
                b'<' | b'>' | b'=' | b'!' if depth == 0 => return true,
                _ if depth == 0 => {
                    let boundary = i == 0 || !t.as_bytes()[i - 1].is_ascii_alphanumeric();
                    if boundary
                        && ["and ", "or ", "not "]
                            .iter()
                            .any(|w| t[i..].starts_with(w))
                    {
                        return true;
                    }
                }
                _ => {}
            }
        }
        false
    }

    /// An expression's extent: up to `stop` outside parentheses.
    fn operand(&mut self, comparison_ends: bool) -> Result<(usize, usize), Diagnostic> {
        self.skip()?;
        let start = self.pos;
        let b = self.text.as_bytes();
        let mut depth = 0usize;
        let mut i = start;
        while i < self.end {
            let c = b[i];
            match c {
                b'(' => depth += 1,
                b')' if depth == 0 => break,
                b')' => depth -= 1,
                b'<' | b'>' | b'=' | b'!' if depth == 0 && comparison_ends => break,
                c if depth == 0 && !comparison_ends && c.is_ascii_alphabetic() => {
                    let boundary =
                        i == 0 || !(b[i - 1].is_ascii_alphanumeric() || b[i - 1] == b'_');
                    let rest = &self.text[i..self.end];
                    let word = rest
                        .bytes()
                        .take_while(|c| c.is_ascii_alphanumeric() || *c == b'_')
                        .count();
                    if boundary && ["and", "or", "not"].contains(&&rest[..word]) {
                        break;
                    }
                    i += word;
                    continue;
                }
                _ => {}
            }
            i += 1;
        }
        let end = start + self.text[start..i].trim_end().len();
        if end == start {
            return Err(self
                .src
                .error(start, "a comparison needs an expression here"));
        }
        self.pos = i;
        Ok((start, end))
    }

    /// `lhs cmp rhs`.
    fn comparison(&mut self) -> Result<(), Diagnostic> {
        let (l0, l1) = self.operand(true)?;
        let at = self.pos;
        let rest = &self.text[at..self.end];
        let Some(&(sign, pred)) = COMPARISONS.iter().find(|(s, _)| rest.starts_with(s)) else {
            return Err(self.src.error(
                at,
                "a condition compares two expressions: `x > 0`, `y <= 3`, `z != 1` (combined with and, or, not)",
            ));
        };
        self.pos += sign.len();
        let (r0, r1) = self.operand(false)?;
        self.steps.push(PostfixOp::Compare {
            left: (l0, l1),
            right: (r0, r1),
            at,
            pred,
        });
        Ok(())
    }
}
