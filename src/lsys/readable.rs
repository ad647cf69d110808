//! The readable form of the definition file (issue 40, thesis 8.1.2): a
//! `.lmr` file names its symbols (`move_to(0, 2, 0) sphere(0.5)`), writes
//! expressions in infix, arguments by position or by name with the
//! others left out, and productions as rules:
//!
//! ```text
//! rule A at_age 1 if y <= 3 {
//!     1.0 -> A(x * 2, x + y)
//! }
//! ```
//!
//! It is read by spelling it in the classic form, piece by piece, and
//! parsing that: one parser, one meaning. Every piece remembers where it
//! was written, so errors point into the readable file.

use std::sync::Arc;

use super::catalogue::{named, names, Meaning, Unit, SLOTS};
use super::readable_condition::{condition, PostfixOp};
use super::scan::{is_symbol_char, name_suggestion, trivia_end, READABLE_SECTIONS, SECTIONS};
use crate::source::{Diagnostic, Source, Written};

/// Whether a file is in the readable form: by its extension.
pub fn is_readable(name: &str) -> bool {
    name.ends_with(".lmr")
}

/// The classic spelling of the readable file `src`, infix groups kept
/// (`(= x * 2)`); its errors point into `src`.
pub fn to_classic(src: &Source) -> Result<Source, Diagnostic> {
    to_classic_with(src, None)
}

/// Spells an infix expression in postfix, where it can.
pub type Respell<'a> = &'a dyn Fn(&str) -> Option<String>;

/// As [`to_classic`], each expression spelt by `respell` where it gives
/// a spelling (the thesis's postfix, for `lmfilm convert`).
pub fn to_classic_with(src: &Source, respell: Option<Respell>) -> Result<Source, Diagnostic> {
    let mut r = Reader {
        src,
        text: &src.text,
        pos: 0,
        out: String::with_capacity(src.text.len() * 2),
        pieces: Vec::new(),
        respell,
    };
    r.file()?;
    Ok(Source {
        name: src.name.clone(),
        text: r.out,
        written: Some(Arc::new(Written {
            text: src.text.clone(),
            pieces: r.pieces,
        })),
    })
}

/// Words that open a clause of a rule's head.
const CLAUSES: [&str; 4] = ["at_age", "left", "right", "if"];

/// One argument as written: its name if given, its text and where.
struct Argument<'a> {
    name: Option<(usize, &'a str)>,
    at: usize,
    text: &'a str,
    quoted: bool,
}

struct Reader<'a> {
    src: &'a Source,
    text: &'a str,
    pos: usize,
    out: String,
    pieces: Vec<(usize, usize, bool)>,
    respell: Option<Respell<'a>>,
}

impl<'a> Reader<'a> {
    fn error(&self, at: usize, message: impl Into<String>) -> Diagnostic {
        self.src.error(at, message)
    }

    fn peek(&self) -> Option<u8> {
        self.text.as_bytes().get(self.pos).copied()
    }

    fn rest(&self) -> &'a str {
        &self.text[self.pos..]
    }

    /// Copies `from..to` of the written text: offsets within advance
    /// together. Line breaks inside a group become spaces (a classic group
    /// is one line), which keeps every offset.
    fn copy(&mut self, from: usize, to: usize, in_group: bool) {
        self.pieces.push((self.out.len(), from, true));
        let piece = &self.text[from..to];
        if in_group {
            self.out.push_str(&piece.replace(['\n', '\r'], " "));
        } else {
            self.out.push_str(piece);
        }
    }

    /// Writes made text that stands for what was written at `at`.
    fn put(&mut self, made: &str, at: usize) {
        self.pieces.push((self.out.len(), at, false));
        self.out.push_str(made);
    }

    /// Writes a made word, after a space unless one is there.
    fn put_word(&mut self, word: &str, at: usize) {
        if !self.out.is_empty() && !self.out.ends_with(char::is_whitespace) {
            self.put(" ", at);
        }
        self.put(word, at);
    }

    /// Copies the whitespace and comments ahead.
    fn trivia(&mut self) -> Result<(), Diagnostic> {
        let start = self.pos;
        self.skip_trivia()?;
        self.copy(start, self.pos, false);
        Ok(())
    }

    fn skip_trivia(&mut self) -> Result<(), Diagnostic> {
        self.pos = trivia_end(self.src, self.text.len(), self.pos)?;
        Ok(())
    }

    /// The identifier ahead, not consumed.
    fn peek_name(&self) -> &'a str {
        let rest = self.rest();
        let n = rest
            .bytes()
            .take_while(|c| c.is_ascii_alphanumeric() || *c == b'_')
            .count();
        if rest.bytes().next().is_some_and(|c| c.is_ascii_digit()) {
            return "";
        }
        &rest[..n]
    }

    fn at_section(&self) -> bool {
        READABLE_SECTIONS.contains(&self.peek_name())
    }

    fn file(&mut self) -> Result<(), Diagnostic> {
        loop {
            self.trivia()?;
            if self.pos >= self.text.len() {
                return Ok(());
            }
            let at = self.pos;
            let w = self.peek_name();
            let Some(k) = READABLE_SECTIONS.iter().position(|s| *s == w) else {
                let word: String = self.rest().split_whitespace().next().unwrap_or("").into();
                let hint = match SECTIONS.iter().position(|s| *s == word) {
                    Some(k) => format!("; in the readable form it is `{}`", READABLE_SECTIONS[k]),
                    None => name_suggestion(&word, &READABLE_SECTIONS),
                };
                return Err(self.error(
                    at,
                    format!(
                        "expected a section name ({}), found `{word}`{hint}",
                        READABLE_SECTIONS.join(", ")
                    ),
                ));
            };
            self.pos += w.len();
            self.put(SECTIONS[k], at);
            match k {
                6 => self.axiom()?,
                7 => self.productions()?,
                _ => self.keywords()?,
            }
        }
    }

    /// A section of keyword lines (camera … surfaces), copied as written.
    fn keywords(&mut self) -> Result<(), Diagnostic> {
        loop {
            self.trivia()?;
            if self.pos >= self.text.len() || self.at_section() {
                return Ok(());
            }
            let at = self.pos;
            // A word ends where trivia begins (ASCII whitespace, as
            // `trivia` skips it: a vertical tab is part of a word), so
            // each turn moves on.
            let n = self
                .rest()
                .find(|c: char| c.is_ascii_whitespace())
                .unwrap_or(self.rest().len());
            let n = self.rest()[..n].find("/*").unwrap_or(n);
            let word = &self.rest()[..n];
            if let Some(k) = SECTIONS.iter().position(|s| *s == word) {
                return Err(self.error(
                    at,
                    format!(
                        "in the readable form this section is `{}`",
                        READABLE_SECTIONS[k]
                    ),
                ));
            }
            self.pos += n;
            self.copy(at, self.pos, false);
        }
    }

    fn axiom(&mut self) -> Result<(), Diagnostic> {
        loop {
            self.trivia()?;
            if self.pos >= self.text.len() || self.at_section() {
                return Ok(());
            }
            self.symbol()?;
        }
    }

    /// One symbol: `[`, `]`, a catalogue name, a letter or a quoted
    /// character, each with its arguments in `( )` if it has any.
    fn symbol(&mut self) -> Result<(), Diagnostic> {
        let at = self.pos;
        let (ch, meaning) = match self.peek() {
            Some(b'[') => {
                self.pos += 1;
                return self.symbol_args(b'[', named("push"), at);
            }
            Some(b']') => {
                self.pos += 1;
                return self.symbol_args(b']', named("pop"), at);
            }
            Some(b'\'') => (self.quoted()?, None),
            Some(c) if c.is_ascii_alphabetic() || c == b'_' => {
                let name = self.peek_name();
                self.pos += name.len();
                if let [c] = name.as_bytes() {
                    (*c, None)
                } else {
                    let Some(m) = named(name) else {
                        return Err(self.error(
                            at,
                            format!(
                                "unknown symbol `{name}` (a symbol of the rules' own is one letter, or any character quoted: 'F', '1'){}",
                                name_suggestion(name, &names())
                            ),
                        ));
                    };
                    (m.ch, Some(m))
                }
            }
            Some(c) if c.is_ascii_digit() => {
                return Err(self.error(
                    at,
                    "a number where a symbol is expected: a right side starts `probability ->`, and a digit symbol is quoted: '1'",
                ))
            }
            _ => {
                let c: String = self.rest().chars().take(1).collect();
                return Err(self.error(
                    at,
                    format!("`{c}` is not a symbol: write a name (`turn_left(30)`), a letter, `[`, `]`, or a character quoted ('+')"),
                ));
            }
        };
        self.symbol_args(ch, meaning, at)
    }

    /// A quoted symbol character: `'+'`.
    fn quoted(&mut self) -> Result<u8, Diagnostic> {
        let at = self.pos;
        let b = self.text.as_bytes();
        match (b.get(at + 1), b.get(at + 2)) {
            (Some(&c), Some(b'\'')) if is_symbol_char(c) => {
                self.pos += 3;
                Ok(c)
            }
            _ => Err(self.error(
                at,
                "a quoted symbol is one character among letters, digits and [ ] { } / ^ & $ + - ? ., e.g. '+'",
            )),
        }
    }

    /// The symbol's arguments, if a `(` follows, and its classic spelling.
    fn symbol_args(
        &mut self,
        ch: u8,
        meaning: Option<&'static Meaning>,
        at: usize,
    ) -> Result<(), Diagnostic> {
        let args = if self.peek() == Some(b'(') {
            self.arguments()?
        } else {
            Vec::new()
        };
        let what = meaning.map_or_else(|| format!("`{}`", ch as char), |m| format!("`{}`", m.name));
        let mut slots: [Option<&Argument>; 7] = [None; 7];
        for (k, a) in args.iter().enumerate() {
            let (slot, unit, name) = match (a.name, meaning) {
                (Some((nat, n)), Some(m)) => {
                    let p = m.param(n).ok_or_else(|| self.unknown_param(m, n, nat))?;
                    (p.slot, p.unit, p.name)
                }
                (Some((nat, n)), None) => {
                    let slot = SLOTS.iter().position(|s| *s == n).ok_or_else(|| {
                        self.error(
                            nat,
                            format!(
                                "{what} has no parameter `{n}`; a symbol of its own takes {}{}",
                                SLOTS.join(", "),
                                name_suggestion(n, &SLOTS)
                            ),
                        )
                    })?;
                    (slot as u8, Unit::Number, SLOTS[slot])
                }
                (None, Some(m)) => {
                    let p = m.params.get(k).ok_or_else(|| {
                        self.error(
                            a.at,
                            format!(
                                "{what} takes {} argument{} ({}), given {}; the age and free slots go by name",
                                m.params.len(),
                                if m.params.len() == 1 { "" } else { "s" },
                                m.signature(),
                                args.len()
                            ),
                        )
                    })?;
                    (p.slot, p.unit, p.name)
                }
                (None, None) => {
                    if k >= 6 {
                        return Err(self.error(
                            a.at,
                            format!(
                                "{what} takes at most 6 arguments (x, y, z, f1, f2, f3), given {}",
                                args.len()
                            ),
                        ));
                    }
                    (k as u8 + 1, Unit::Number, SLOTS[k + 1])
                }
            };
            if slots[slot as usize].is_some() {
                let at = a.name.map_or(a.at, |n| n.0);
                return Err(self.error(at, format!("{what}: `{name}` is given twice")));
            }
            self.check(a, unit, name, &what)?;
            slots[slot as usize] = Some(a);
        }
        self.put(&(ch as char).to_string(), at);
        let fixed = meaning.map_or(&[][..], |m| m.fixed);
        let last = (0..7)
            .rev()
            .find(|&k| slots[k].is_some() || fixed.iter().any(|f| f.0 as usize == k && f.1 != 0.0));
        let Some(last) = last else {
            // A named letter given nothing is written with a group, which
            // says it is meant as the name (a bare `C` reads as a letter
            // of the rules' own).
            if meaning.is_some_and(|m| !m.params.is_empty()) && ch.is_ascii_alphabetic() {
                self.put(" ()", at);
                return Ok(());
            }
            // A bare symbol keeps apart from a letter after it (`E n d`
            // is not the keyword `End`).
            if !self.rest().starts_with(char::is_whitespace) {
                self.put(" ", at);
            }
            return Ok(());
        };
        for (k, given) in slots.iter().enumerate().take(last + 1) {
            match (given, fixed.iter().find(|f| f.0 as usize == k)) {
                (Some(a), _) => self.group(a),
                (None, Some((_, v))) => self.put(&format!(" ({v})"), at),
                (None, None) => self.put(" ()", at),
            }
        }
        Ok(())
    }

    fn unknown_param(&self, m: &Meaning, n: &str, at: usize) -> Diagnostic {
        let mut known: Vec<&str> = m.params.iter().map(|p| p.name).collect();
        known.extend(SLOTS.iter().filter(|s| m.param(s).is_some()));
        self.error(
            at,
            format!(
                "`{}` has no parameter `{n}`{}; it takes {} (and by name: {})",
                m.name,
                name_suggestion(n, &known),
                m.signature(),
                SLOTS
                    .iter()
                    .enumerate()
                    .filter(|(slot, _)| m.free(*slot as u8))
                    .map(|(_, s)| *s)
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
        )
    }

    /// Checks a plain-number or quoted argument against its unit.
    fn check(&self, a: &Argument, unit: Unit, name: &str, what: &str) -> Result<(), Diagnostic> {
        if unit == Unit::Text {
            if !a.quoted {
                return Err(self.error(a.at, format!("{what}: `{name}` is {}", unit.describe())));
            }
            return Ok(());
        }
        if a.quoted {
            return Err(self.error(
                a.at,
                format!("{what}: `{name}` is {}, not a text", unit.describe()),
            ));
        }
        let t = a.text.trim();
        if unsigned_number(t.strip_prefix('-').unwrap_or(t)) {
            if let Ok(v) = t.parse::<f64>() {
                if let Some(why) = unit.reject(v) {
                    return Err(self.error(a.at, format!("{what}: `{name}` is {why}, found {t}")));
                }
            }
        }
        Ok(())
    }

    /// The classic group of one argument.
    fn group(&mut self, a: &Argument) {
        let end = a.at + a.text.len();
        let unsigned = unsigned_number(a.text.trim());
        if let Some(p) = self
            .respell
            .filter(|_| !a.quoted && !unsigned)
            .and_then(|r| r(a.text))
        {
            self.put(&format!(" ({p})"), a.at);
            return;
        }
        if a.quoted || unsigned {
            self.put(" (", a.at);
        } else {
            self.put(" (= ", a.at);
        }
        self.copy(a.at, end, true);
        self.put(")", end);
    }

    /// `( args )` after a symbol.
    fn arguments(&mut self) -> Result<Vec<Argument<'a>>, Diagnostic> {
        let open = self.pos;
        self.pos += 1;
        let mut args = Vec::new();
        loop {
            self.skip_space(open)?;
            if self.peek() == Some(b')') && args.is_empty() {
                self.pos += 1;
                return Ok(args);
            }
            let mut name = None;
            let n = self.peek_name();
            if !n.is_empty() {
                let after = self.text[self.pos + n.len()..].trim_start_matches([' ', '\t']);
                if after.starts_with(':') {
                    name = Some((self.pos, n));
                    self.pos = self.text.len() - after.len() + 1;
                    self.skip_space(open)?;
                }
            }
            let at = self.pos;
            let (text, quoted) = if self.peek() == Some(b'"') {
                let end = self.rest()[1..].find(['"', '\n']).map(|e| e + 1);
                match end.filter(|e| self.rest().as_bytes()[*e] == b'"') {
                    Some(e) => {
                        let t = &self.text[at + 1..at + e];
                        self.pos += e + 1;
                        (t, true)
                    }
                    None => return Err(self.error(at, "unclosed text: add the closing `\"`")),
                }
            } else {
                (self.expression_text(open)?, false)
            };
            let at = if quoted { at + 1 } else { at };
            if !quoted && text.trim().is_empty() {
                return Err(self.error(
                    at,
                    "an empty argument: leave it out, or name the ones you give",
                ));
            }
            args.push(Argument {
                name,
                at,
                text,
                quoted,
            });
            self.skip_space(open)?;
            match self.peek() {
                Some(b',') => self.pos += 1,
                Some(b')') => {
                    self.pos += 1;
                    return Ok(args);
                }
                _ => return Err(self.error(self.pos, "expected `,` or `)` after an argument")),
            }
        }
    }

    /// A comment at `at`, inside a symbol's arguments (a classic group
    /// holds none).
    fn comment_inside(&self, at: usize) -> Diagnostic {
        self.error(
            at,
            "a comment inside a symbol's `( )`: move it after the `)`",
        )
    }

    /// Skips whitespace inside arguments; a comment there is an error
    /// (a classic group holds none).
    fn skip_space(&mut self, open: usize) -> Result<(), Diagnostic> {
        let rest = self.rest();
        self.pos += rest.len() - rest.trim_start().len();
        if self.rest().starts_with("/*") {
            return Err(self.comment_inside(self.pos));
        }
        if self.pos >= self.text.len() {
            return Err(self.error(open, "this `(` is not closed"));
        }
        Ok(())
    }

    /// An expression's text up to a `,` or `)` outside parentheses.
    fn expression_text(&mut self, open: usize) -> Result<&'a str, Diagnostic> {
        let start = self.pos;
        let mut depth = 0usize;
        for (i, c) in self.rest().bytes().enumerate() {
            match c {
                b'(' => depth += 1,
                b')' if depth == 0 => {
                    self.pos = start + i;
                    return Ok(&self.text[start..start + i]);
                }
                b')' => depth -= 1,
                b',' if depth == 0 => {
                    self.pos = start + i;
                    return Ok(&self.text[start..start + i]);
                }
                b'/' if self.text[start + i..].starts_with("/*") => {
                    return Err(self.comment_inside(start + i))
                }
                b'"' | b'{' | b'}' | b'[' | b']' => break,
                _ => {}
            }
        }
        Err(self.error(open, "this `(` is not closed"))
    }

    fn productions(&mut self) -> Result<(), Diagnostic> {
        loop {
            self.trivia()?;
            if self.pos >= self.text.len() {
                self.put("\nEndProductions\n", self.text.len());
                return Ok(());
            }
            if self.at_section() {
                return Err(self.error(self.pos, "`productions` is the last section"));
            }
            let at = self.pos;
            if self.peek_name() != "rule" {
                let w: String = self.rest().split_whitespace().next().unwrap_or("").into();
                return Err(self.error(
                    at,
                    format!("expected a rule (`rule A at_age 1 {{ 1 -> … }}`), found `{w}`"),
                ));
            }
            self.pos += 4;
            self.rule(at)?;
        }
    }

    /// The symbol a rule rewrites or a context names: a letter or a
    /// quoted character.
    fn rule_symbol(&mut self, what: &str) -> Result<u8, Diagnostic> {
        self.skip_trivia()?;
        let at = self.pos;
        if self.peek() == Some(b'\'') {
            return self.quoted();
        }
        let n = self.peek_name();
        match n.as_bytes() {
            [c] => {
                self.pos += 1;
                Ok(*c)
            }
            _ => Err(self.error(
                at,
                format!("{what} is one symbol: a letter, or a character quoted ('+'), found `{n}`"),
            )),
        }
    }

    fn rule(&mut self, at: usize) -> Result<(), Diagnostic> {
        let lhs = self.rule_symbol("a rule rewrites")?;
        self.put(&(lhs as char).to_string(), at);
        let mut age: Option<(usize, &str)> = None;
        let mut cond: Option<(usize, &str)> = None;
        let mut contexts: [Option<u8>; 2] = [None, None];
        loop {
            self.skip_trivia()?;
            if self.peek() == Some(b'{') {
                break;
            }
            let cat = self.pos;
            let w = self.peek_name();
            let Some(k) = CLAUSES.iter().position(|c| *c == w) else {
                let found: String = self.rest().split_whitespace().next().unwrap_or("").into();
                return Err(self.error(
                    cat,
                    format!(
                        "expected `{{` or a clause ({}) in this rule's head, found `{found}`{}",
                        CLAUSES.join(", "),
                        name_suggestion(w, &CLAUSES)
                    ),
                ));
            };
            self.pos += w.len();
            let again = match k {
                0 | 3 => {
                    let t = self.head_text(cat, k == 0)?;
                    let slot = if k == 0 { &mut age } else { &mut cond };
                    slot.replace(t).is_some()
                }
                _ => {
                    let c = self.rule_symbol("a context")?;
                    contexts[k - 1].replace(c).is_some()
                }
            };
            if again {
                return Err(self.error(cat, format!("`{w}` is given twice in this rule")));
            }
        }
        match age {
            Some((a, t)) => self.group(&Argument {
                name: None,
                at: a,
                text: t,
                quoted: false,
            }),
            None => self.put(" ()", at),
        }
        // Trailing parts of the classic head are left out.
        let contexts_given = contexts.iter().rposition(Option::is_some);
        match cond {
            Some((c, t)) => {
                for step in condition(self.src, c, c + t.len())? {
                    self.step(step);
                }
                self.pos = c + t.len();
                self.skip_trivia()?;
            }
            None if contexts_given.is_some() => self.put(" ()", at),
            None => {}
        }
        for c in contexts.iter().take(contexts_given.map_or(0, |k| k + 1)) {
            match c {
                Some(c) => self.put(&format!(" ({})", *c as char), at),
                None => self.put(" ()", at),
            }
        }
        // The body: `{ p -> symbols … }`.
        let open = self.pos;
        self.pos += 1;
        if !self.rest().starts_with(char::is_whitespace) {
            self.put(" ", open);
        }
        let mut parts = 0;
        loop {
            self.trivia()?;
            match self.peek() {
                None => return Err(self.error(open, "this rule's `{` is not closed")),
                Some(b'}') => {
                    if parts == 0 {
                        return Err(
                            self.error(self.pos, "a rule needs a right side: `1 -> symbols…`")
                        );
                    }
                    self.put_word("End", self.pos);
                    self.pos += 1;
                    return Ok(());
                }
                _ => {}
            }
            let pat = self.pos;
            let n = number_length(self.rest());
            if n == 0 {
                return Err(self.error(
                    pat,
                    "expected a right side's probability, e.g. `1 -> A B`, or `}`",
                ));
            }
            self.pos += n;
            self.copy(pat, self.pos, false);
            self.skip_trivia()?;
            if !self.rest().starts_with("->") {
                return Err(self.error(self.pos, "expected `->` after the probability"));
            }
            self.pos += 2;
            if !self.rest().starts_with(char::is_whitespace) {
                self.put(" ", self.pos);
            }
            parts += 1;
            self.right_side()?;
        }
    }

    /// A right side's symbols, up to the next `probability ->` or the
    /// rule's `}`, closed by the classic `EndProb`.
    fn right_side(&mut self) -> Result<(), Diagnostic> {
        loop {
            let start = self.pos;
            self.skip_trivia()?;
            // The rule's end or the next right side's `probability ->`; a
            // number without its arrow is a symbol's mistake (`symbol`
            // says so).
            let next_side = || {
                let after = &self.rest()[number_length(self.rest())..];
                after.trim_start().starts_with("->")
            };
            let ends = match self.peek() {
                Some(c) if c.is_ascii_digit() || c == b'.' => next_side(),
                Some(c) => c == b'}',
                None => true,
            };
            if ends {
                self.put_word("EndProb", start);
            }
            self.copy(start, self.pos, false);
            if ends {
                return Ok(());
            }
            self.symbol()?;
        }
    }

    /// One step of a condition in postfix: an atom `lhs cmp rhs` as
    /// `[(= (lhs) - (rhs))pred]` (or `[(= lhs)pred]` when rhs is 0), or a
    /// logic operator.
    fn step(&mut self, step: PostfixOp) {
        match step {
            PostfixOp::Logic { op, at } => self.put(&format!(" {op}"), at),
            PostfixOp::Compare {
                left,
                right,
                at,
                pred,
            } => self.comparison(left, right, at, pred),
        }
    }

    fn comparison(
        &mut self,
        (l0, l1): (usize, usize),
        (r0, r1): (usize, usize),
        at: usize,
        pred: char,
    ) {
        let zero = self.text[r0..r1].trim() == "0";
        let (l, r) = (&self.text[l0..l1], &self.text[r0..r1]);
        let infix = if zero {
            l.to_string()
        } else {
            format!("({l}) - ({r})")
        };
        if let Some(p) = self.respell.and_then(|f| f(&infix)) {
            self.put(&format!(" [({p}){pred}]"), l0);
            return;
        }
        self.put(" [(= ", l0);
        if zero {
            self.copy(l0, l1, true);
        } else {
            self.put("(", l0);
            self.copy(l0, l1, true);
            self.put(") - (", at);
            self.copy(r0, r1, true);
            self.put(")", r1);
        }
        self.put(&format!("){pred}]"), at);
    }

    /// The text of an `at_age` (an `expression`) or `if` clause: up to
    /// the next clause or the `{`, outside parentheses.
    fn head_text(
        &mut self,
        clause: usize,
        expression: bool,
    ) -> Result<(usize, &'a str), Diagnostic> {
        self.skip_trivia()?;
        let start = self.pos;
        let b = self.text.as_bytes();
        let mut depth = 0usize;
        let mut i = start;
        while i < b.len() {
            match b[i] {
                b'(' => depth += 1,
                b')' => depth = depth.saturating_sub(1),
                b'{' if depth == 0 => break,
                c if depth == 0 && (c.is_ascii_alphabetic() || c == b'_') => {
                    let n = b[i..]
                        .iter()
                        .take_while(|c| c.is_ascii_alphanumeric() || **c == b'_')
                        .count();
                    let boundary =
                        i == 0 || !(b[i - 1].is_ascii_alphanumeric() || b[i - 1] == b'_');
                    let word = &self.text[i..i + n];
                    if boundary && CLAUSES.contains(&word) {
                        break;
                    }
                    // A name right after a whole operand starts a clause.
                    let before = self.text[start..i].trim_end();
                    let operand_ended = before.bytes().last().is_some_and(|c| {
                        c.is_ascii_alphanumeric() || matches!(c, b'_' | b')' | b'.')
                    });
                    if expression && boundary && operand_ended && before.len() < i - start {
                        return Err(self.error(
                            i,
                            format!(
                                "expected `{{` or a clause ({}) in this rule's head, found `{word}`{}",
                                CLAUSES.join(", "),
                                name_suggestion(word, &CLAUSES)
                            ),
                        ));
                    }
                    i += n;
                    continue;
                }
                _ => {}
            }
            i += 1;
        }
        let t = self.text[start..i].trim_end();
        if t.is_empty() {
            return Err(self.error(clause, "this clause has nothing after it"));
        }
        self.pos = start + t.len();
        Ok((start, t))
    }
}

/// Whether `text` is written as a plain unsigned decimal (`2`, `0.5`):
/// what a classic group holds as it is, and what a unit can check.
fn unsigned_number(text: &str) -> bool {
    !text.is_empty() && text.bytes().all(|c| c.is_ascii_digit() || c == b'.')
}

/// The length of the decimal number `text` starts with (`1`, `0.5`,
/// `.5`, `1e-3`), 0 if none.
fn number_length(text: &str) -> usize {
    let b = text.as_bytes();
    let digits = |mut i: usize| {
        while i < b.len() && b[i].is_ascii_digit() {
            i += 1;
        }
        i
    };
    let mut i = digits(0);
    if i < b.len() && b[i] == b'.' {
        i = digits(i + 1);
    }
    if i == 0 || &text[..i] == "." {
        return 0;
    }
    if i < b.len() && matches!(b[i], b'e' | b'E') {
        let j = if matches!(b.get(i + 1), Some(b'+' | b'-')) {
            i + 2
        } else {
            i + 1
        };
        let k = digits(j);
        if k > j {
            i = k;
        }
    }
    i
}
