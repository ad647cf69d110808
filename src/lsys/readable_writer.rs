//! A classic `.lm` file spelt in the readable form (issue 40): symbols by
//! their catalogue names, expressions in infix, productions as rules.
//! Comments and line breaks are kept where they were; the section
//! keywords' lines are copied as they are. Reading the result gives the
//! same definition, op for op.

use std::collections::BTreeSet;

use super::catalogue::{is_cut, Meaning, Unit, MEANINGS, SLOTS};
use super::definition::Definition;
use super::expr::{Code, Compiler, Expr, Op};
use super::parse::{condition, parse};
use super::scan::{Group, Scanner, READABLE_SECTIONS, SECTIONS};
use super::unparse;
use crate::source::{Diagnostic, Source};

/// What one `( )` group of a classic symbol holds.
#[derive(Debug, Clone, PartialEq)]
enum Value {
    Empty,
    Number(f64),
    Expression(String),
    /// An automata command (`e` with par1 = 0).
    Text(String),
}

impl Value {
    fn number(&self) -> Option<f64> {
        match self {
            Value::Empty => Some(0.0),
            Value::Number(v) => Some(*v),
            _ => None,
        }
    }

    fn text(&self) -> String {
        match self {
            Value::Empty => String::new(),
            Value::Number(v) => unparse::number(*v),
            Value::Expression(e) => e.clone(),
            Value::Text(t) => format!("\"{t}\""),
        }
    }
}

/// The readable spelling of the classic file `src`.
pub fn to_readable(src: &Source) -> Result<String, Diagnostic> {
    let def = parse(src)?;
    let mut w = Writer {
        s: Scanner::new(src),
        splines: def.splines.iter().map(|s| s.number).collect(),
        rewritten: def.productions.iter().map(|p| p.lhs).collect(),
        def,
        out: String::with_capacity(src.text.len() * 2),
        copied: 0,
    };
    w.file()?;
    Ok(w.out)
}

struct Writer<'a> {
    s: Scanner<'a>,
    def: Definition,
    splines: Vec<u32>,
    /// Symbols some production rewrites: spelt as themselves, never by a
    /// catalogue name (`B` of an ABOP example is not a surface).
    rewritten: BTreeSet<u8>,
    out: String,
    /// How far the classic text is written out.
    copied: usize,
}

impl Writer<'_> {
    fn text(&self) -> &str {
        &self.s.src.text
    }

    /// Copies the whitespace and comments before the next token; returns
    /// whether there were any.
    fn trivia(&mut self, indent: bool) -> Result<bool, Diagnostic> {
        self.s.skip_trivia()?;
        let piece = self.text()[self.copied..self.s.pos].to_string();
        self.copied = self.s.pos;
        if !indent {
            self.out.push_str(&piece);
            return Ok(!piece.is_empty());
        }
        // Right sides sit inside a rule's braces: lines that start at the
        // margin are indented, but for the rule's closing brace.
        let mut rest = piece.as_str();
        let closes = self.next_closes_rule();
        while let Some(i) = rest.find('\n') {
            self.out.push_str(&rest[..=i]);
            rest = &rest[i + 1..];
            let margin = !rest.starts_with([' ', '\t', '\n', '\r']);
            if margin && !(rest.is_empty() && closes) {
                self.out.push_str("    ");
            }
        }
        self.out.push_str(rest);
        Ok(!piece.is_empty())
    }

    fn next_closes_rule(&mut self) -> bool {
        self.s.at_keyword("End").unwrap_or(false)
    }

    fn error(&self, at: usize, message: impl Into<String>) -> Diagnostic {
        self.s.error(at, message)
    }

    fn file(&mut self) -> Result<(), Diagnostic> {
        loop {
            self.trivia(false)?;
            if self.s.at_end()? {
                return Ok(());
            }
            let (at, w) = self.s.word("a section")?;
            let k = SECTIONS
                .iter()
                .position(|s| *s == w)
                .ok_or_else(|| self.error(at, format!("expected a section name, found `{w}`")))?;
            // The classic form lets a section's name follow a symbol
            // without a space (`Fproductions` would read as one name).
            if !self.out.is_empty() && !self.out.ends_with(char::is_whitespace) {
                self.out.push('\n');
            }
            self.out.push_str(READABLE_SECTIONS[k]);
            self.copied = self.s.pos;
            match k {
                6 => self.axiom()?,
                7 => self.productions()?,
                _ => self.keywords()?,
            }
        }
    }

    /// A section of keyword lines, copied.
    fn keywords(&mut self) -> Result<(), Diagnostic> {
        let mut end = self.copied;
        loop {
            if self.s.at_section()? {
                break;
            }
            let (at, w) = self.s.word("a keyword")?;
            if READABLE_SECTIONS.contains(&w) {
                return Err(self.error(
                    at,
                    format!("`{w}` would read as a section name in the readable form"),
                ));
            }
            end = self.s.pos;
        }
        self.out.push_str(&self.s.src.text[self.copied..end]);
        self.copied = end;
        self.s.pos = end;
        Ok(())
    }

    fn axiom(&mut self) -> Result<(), Diagnostic> {
        loop {
            let spaced = self.trivia(false)?;
            if self.s.at_section()? {
                return Ok(());
            }
            self.symbol(spaced)?;
        }
    }

    /// The value of group `g` of a symbol.
    fn value(&mut self, g: Option<Group>) -> Result<Value, Diagnostic> {
        let Some(g) = g else {
            return Ok(Value::Empty);
        };
        let mut code = Code::default();
        let compiled = Compiler {
            src: self.s.src,
            code: &mut code,
            constants: &self.def.constants,
            splines: &self.splines,
        }
        .group(g.text, g.offset)?;
        Ok(match compiled {
            None => Value::Empty,
            Some(Expr::Const(v)) => Value::Number(v),
            Some(Expr::Prog { .. }) => match code.ops[..] {
                // A negative number (`1_`) reads as one, e.g. a cut's kind.
                [Op::Num(v), Op::Neg] => Value::Number(-v),
                _ => Value::Expression(unparse::expression(&code.ops).ok_or_else(|| {
                    self.error(g.offset, "this expression has no infix spelling")
                })?),
            },
        })
    }

    /// One classic symbol, written as a name or as itself.
    fn symbol(&mut self, spaced: bool) -> Result<(), Diagnostic> {
        let at = self.s.pos;
        let ch = self.s.peek().unwrap_or(b' ');
        self.s.bump();
        let mut groups = Vec::new();
        let mut comments = String::new();
        let mut end = self.s.pos;
        while groups.len() < 7 {
            let before = self.s.pos;
            match self.s.group()? {
                Some(g) => {
                    let gap = &self.text()[before..g.offset - 1];
                    if gap.contains("/*") {
                        comments.push(' ');
                        comments.push_str(gap.trim());
                    }
                    groups.push(g);
                    end = self.s.pos;
                }
                None => break,
            }
        }
        self.s.pos = end;
        self.copied = end;
        let mut values = vec![Value::Empty; 7];
        values[1] = self.value(groups.get(1).copied())?;
        let script = ch == b'e' && values[1].number() == Some(0.0);
        for (k, g) in groups.iter().enumerate() {
            if k == 1 {
                continue;
            }
            values[k] = if script && k == 4 {
                let t = g.text.trim();
                if t.contains('"') {
                    return Err(self.error(
                        g.offset,
                        "an automata command with `\"` has no readable spelling",
                    ));
                }
                Value::Text(t.to_string())
            } else {
                self.value(Some(*g))?
            };
        }
        let spelt = self
            .spell(ch, &values, groups.is_empty())
            .ok_or_else(|| self.error(at, "this symbol has no readable spelling"))?;
        let glue = !spaced
            && !self.out.is_empty()
            && !self.out.ends_with(|c: char| c.is_whitespace() || c == '[')
            && spelt != "]";
        if glue {
            self.out.push(' ');
        }
        self.out.push_str(&spelt);
        self.out.push_str(&comments);
        Ok(())
    }

    /// The readable spelling of symbol `ch` with its groups' values.
    fn spell(&self, ch: u8, values: &[Value], bare: bool) -> Option<String> {
        if !self.rewritten.contains(&ch) {
            // A bare letter whose meaning takes parameters is taken for a
            // letter of the rules' own (`C` of an ABOP example).
            let plain = bare && ch.is_ascii_alphabetic();
            let found = MEANINGS
                .iter()
                .find(|m| m.ch == ch && fits(m, values))
                .filter(|m| !plain || m.params.is_empty());
            if let Some(m) = found {
                let ordered = m.params.iter().map(|p| (p.name, p.slot));
                let free = (0..7).filter(|&slot| m.free(slot));
                return Some(call(m.name, &arguments(ordered, free, values)));
            }
        }
        if values.iter().any(|v| matches!(v, Value::Text(_))) {
            return None;
        }
        // x, y, z, f1, f2, f3 in order, the age by name.
        let ordered = (1..7u8).map(|slot| (SLOTS[slot as usize], slot));
        Some(call(&raw(ch), &arguments(ordered, [0], values)))
    }

    fn productions(&mut self) -> Result<(), Diagnostic> {
        loop {
            self.trivia(false)?;
            if self.s.at_keyword("EndProductions")? {
                self.s.word("EndProductions")?;
                // What follows is comments only: copied, and nothing for
                // the keyword (the readable form's rules end with the file).
                let rest = self.text()[self.s.pos..].to_string();
                let out = self.out.trim_end().len();
                self.out.truncate(out);
                self.out.push_str(&rest);
                if !self.out.ends_with('\n') {
                    self.out.push('\n');
                }
                self.s.pos = self.text().len();
                self.copied = self.s.pos;
                return Ok(());
            }
            self.production()?;
        }
    }

    fn context(&mut self) -> Result<Option<u8>, Diagnostic> {
        Ok(self.s.group()?.and_then(|g| g.text.trim().bytes().next()))
    }

    fn production(&mut self) -> Result<(), Diagnostic> {
        let lhs = self.s.peek().unwrap_or(b' ');
        self.s.bump();
        let age = self.s.group()?;
        let age = self.value(age)?;
        self.s.skip_trivia()?;
        let cond = match self.s.peek() {
            Some(b'[') => {
                let at = self.s.pos;
                let mut code = Code::default();
                let mut c = Compiler {
                    src: self.s.src,
                    code: &mut code,
                    constants: &self.def.constants,
                    splines: &self.splines,
                };
                condition(&mut self.s, &mut c)?;
                let text = unparse::condition(&code.ops).ok_or_else(|| {
                    self.error(at, "this condition has no readable spelling: write each atom `[(expr)pred]` and combine them with & | !")
                })?;
                Some(text)
            }
            Some(b'(') => {
                self.s.group()?;
                None
            }
            _ => None,
        };
        let left = self.context()?;
        let right = self.context()?;
        // Back to the end of the head, so that the line break after it
        // is kept.
        let head_end = self.text()[..self.s.pos].trim_end().len();
        self.s.pos = head_end.max(self.copied);
        self.copied = self.s.pos;
        let mut head = format!("rule {}", raw(lhs));
        if age != Value::Empty {
            head.push_str(&format!(" at_age {}", age.text()));
        }
        if let Some(c) = left {
            head.push_str(&format!(" left {}", raw(c)));
        }
        if let Some(c) = right {
            head.push_str(&format!(" right {}", raw(c)));
        }
        if let Some(c) = cond {
            head.push_str(&format!(" if {c}"));
        }
        head.push_str(" {");
        self.out.push_str(&head);
        loop {
            self.trivia(true)?;
            if self.s.at_keyword("End")? {
                self.s.word("End")?;
                self.copied = self.s.pos;
                self.out.push('}');
                return Ok(());
            }
            let (_, p) = self.s.word("a probability")?;
            self.out.push_str(p);
            self.out.push_str(" ->");
            self.copied = self.s.pos;
            loop {
                let spaced = self.trivia(true)?;
                if self.s.at_keyword("EndProb")? {
                    self.s.word("EndProb")?;
                    self.copied = self.s.pos;
                    let kept = self.out.trim_end_matches([' ', '\t']).len();
                    self.out.truncate(kept);
                    break;
                }
                self.symbol(spaced)?;
            }
        }
    }
}

/// Whether a meaning's selectors match the values, and every other group
/// has a name in it.
fn fits(m: &Meaning, values: &[Value]) -> bool {
    let fixed = m
        .fixed
        .iter()
        .all(|&(slot, v)| values[slot as usize].number() == Some(v));
    let cut = !m.cut || values[1].number().is_some_and(is_cut);
    let named = values.iter().enumerate().all(|(slot, v)| {
        *v == Value::Empty
            || m.fixed.iter().any(|f| f.0 as usize == slot)
            || m.params.iter().any(|p| p.slot as usize == slot)
            || m.free(slot as u8)
    });
    let text = values.iter().enumerate().all(|(slot, v)| {
        !matches!(v, Value::Text(_))
            || m.params
                .iter()
                .any(|p| p.slot as usize == slot && p.unit == Unit::Text)
    });
    // A plain number its unit refuses is written as the bare symbol with
    // its slots (`m(42.5)`), which the readable form reads unchecked.
    let typed = m.params.iter().all(|p| match values[p.slot as usize] {
        Value::Number(v) => p.unit.reject(v).is_none(),
        _ => true,
    });
    fixed && cut && named && text && typed
}

/// The arguments of a symbol: the `ordered` parameters (name, slot) by
/// position while none is left out, by name after; then the `named`
/// slots by their generic names.
fn arguments(
    ordered: impl Iterator<Item = (&'static str, u8)>,
    named: impl IntoIterator<Item = u8>,
    values: &[Value],
) -> Vec<String> {
    let mut args = Vec::new();
    let mut positional = true;
    for (name, slot) in ordered {
        let v = &values[slot as usize];
        if *v == Value::Empty {
            positional = false;
            continue;
        }
        args.push(if positional {
            v.text()
        } else {
            format!("{name}: {}", v.text())
        });
    }
    for slot in named {
        let v = &values[slot as usize];
        if *v != Value::Empty {
            args.push(format!("{}: {}", SLOTS[slot as usize], v.text()));
        }
    }
    args
}

fn call(name: &str, args: &[String]) -> String {
    match (name, args.is_empty()) {
        ("push", true) => "[".to_string(),
        ("pop", true) => "]".to_string(),
        (_, true) => name.to_string(),
        _ => format!("{name}({})", args.join(", ")),
    }
}

/// A symbol as itself: a letter bare, any other character quoted.
pub fn raw(ch: u8) -> String {
    if ch.is_ascii_alphabetic() {
        (ch as char).to_string()
    } else {
        format!("'{}'", ch as char)
    }
}
