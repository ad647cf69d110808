//! A cursor over a definition file: words, numbers, `( )` groups and
//! `/* */` comments, every read carrying its byte offset for diagnostics.

use crate::source::{Diagnostic, Source};

pub struct Scanner<'a> {
    pub src: &'a Source,
    bytes: &'a [u8],
    pub pos: usize,
}

/// The text between a `(` and its `)`, with the offset of its first byte.
#[derive(Debug, Clone, Copy)]
pub struct Group<'a> {
    pub offset: usize,
    pub text: &'a str,
}

impl<'a> Scanner<'a> {
    pub fn new(src: &'a Source) -> Self {
        Scanner {
            src,
            bytes: src.text.as_bytes(),
            pos: 0,
        }
    }

    /// A scanner of `src`'s bytes `start..end` only (a group's text), whose
    /// errors are located in the whole file.
    pub fn within(src: &'a Source, start: usize, end: usize) -> Self {
        Scanner {
            src,
            bytes: &src.text.as_bytes()[..end],
            pos: start,
        }
    }

    pub fn error(&self, offset: usize, message: impl Into<String>) -> Diagnostic {
        self.src.error(offset, message)
    }

    /// Skips whitespace and comments; comments do not nest (thesis 6.2).
    pub fn skip_trivia(&mut self) -> Result<(), Diagnostic> {
        self.pos = trivia_end(self.src, self.bytes.len(), self.pos)?;
        Ok(())
    }

    /// True at the end of the file or at the next section's name.
    pub fn at_section(&mut self) -> Result<bool, Diagnostic> {
        if self.at_end()? {
            return Ok(true);
        }
        for k in SECTIONS {
            if self.at_keyword(k)? {
                return Ok(true);
            }
        }
        Ok(false)
    }

    pub fn at_end(&mut self) -> Result<bool, Diagnostic> {
        self.skip_trivia()?;
        Ok(self.pos >= self.bytes.len())
    }

    pub fn peek(&self) -> Option<u8> {
        self.bytes.get(self.pos).copied()
    }

    pub fn bump(&mut self) {
        self.pos += 1;
    }

    fn word_end(&self, from: usize) -> usize {
        let mut end = from;
        while end < self.bytes.len()
            && !self.bytes[end].is_ascii_whitespace()
            && !self.bytes[end..].starts_with(b"/*")
        {
            end += 1;
        }
        end
    }

    /// The next whitespace-delimited word without consuming it.
    pub fn peek_word(&mut self) -> Result<(usize, &'a str), Diagnostic> {
        self.skip_trivia()?;
        let end = self.word_end(self.pos);
        Ok((self.pos, &self.src.text[self.pos..end]))
    }

    /// The next whitespace-delimited word.
    pub fn word(&mut self, what: &str) -> Result<(usize, &'a str), Diagnostic> {
        let (start, w) = self.peek_word()?;
        if w.is_empty() {
            return Err(self.error(start, format!("expected {what}, found the end of the file")));
        }
        self.pos = start + w.len();
        Ok((start, w))
    }

    /// True when the next word is exactly `kw`; costs O(|kw|), so long
    /// runs of glued symbols stay linear to parse.
    pub fn at_keyword(&mut self, kw: &str) -> Result<bool, Diagnostic> {
        self.skip_trivia()?;
        let rest = &self.bytes[self.pos..];
        Ok(rest.starts_with(kw.as_bytes())
            && self.word_end(self.pos + kw.len()) == self.pos + kw.len())
    }

    /// True when the next word is written as a number (even one that
    /// [`Scanner::number`] then refuses as too large).
    pub fn at_number(&mut self) -> Result<bool, Diagnostic> {
        Ok(number_shaped(self.peek_word()?.1).is_some())
    }

    /// A finite number within ±[`MAX_NUMBER`].
    pub fn number(&mut self, what: &str) -> Result<f64, Diagnostic> {
        let (start, w) = self.word(what)?;
        let Some(v) = number_shaped(w) else {
            return Err(self.error(start, format!("expected {what} (a number), found `{w}`")));
        };
        if !v.is_finite() {
            return Err(self.error(start, format!("{what}: `{w}` is not a finite number")));
        }
        if v.abs() > MAX_NUMBER {
            return Err(self.error(
                start,
                format!(
                    "{what}: `{w}` is too large; numbers are at most {MAX_NUMBER:e} in magnitude"
                ),
            ));
        }
        Ok(v)
    }

    pub fn int(&mut self, what: &str) -> Result<i64, Diagnostic> {
        let (start, w) = self.word(what)?;
        w.parse::<i64>().map_err(|e| {
            let why = match e.kind() {
                std::num::IntErrorKind::PosOverflow | std::num::IntErrorKind::NegOverflow => {
                    "an integer too large to hold"
                }
                _ => "not an integer",
            };
            self.error(
                start,
                format!("expected {what} (an integer), found `{w}`: {why}"),
            )
        })
    }

    /// An integer in `range`, or an error naming the range.
    pub fn int_in(
        &mut self,
        what: &str,
        range: std::ops::RangeInclusive<i64>,
    ) -> Result<i64, Diagnostic> {
        let at = self.peek_word()?.0;
        let n = self.int(what)?;
        if range.contains(&n) {
            Ok(n)
        } else {
            Err(self.error(
                at,
                format!(
                    "{what} must be {}..={}, found {n}",
                    range.start(),
                    range.end()
                ),
            ))
        }
    }

    /// Reads up to `max` numbers while the next word is one.
    pub fn numbers(&mut self, max: usize, what: &str) -> Result<Vec<f64>, Diagnostic> {
        let mut v = Vec::new();
        while v.len() < max && self.at_number()? {
            v.push(self.number(what)?);
        }
        Ok(v)
    }

    /// Reads exactly N numbers.
    pub fn floats<const N: usize>(&mut self, what: &str) -> Result<[f64; N], Diagnostic> {
        let mut out = [0.0; N];
        for v in &mut out {
            *v = self.number(what)?;
        }
        Ok(out)
    }

    /// A `( … )` group if one comes next (after trivia).
    pub fn group(&mut self) -> Result<Option<Group<'a>>, Diagnostic> {
        self.skip_trivia()?;
        if self.peek() != Some(b'(') {
            return Ok(None);
        }
        let open = self.pos;
        let mut i = open + 1;
        // An infix group, `(= …)`, nests parentheses (issue 40).
        let infix = self.src.text[open + 1..]
            .trim_start_matches([' ', '\t'])
            .starts_with('=');
        let mut depth = 0usize;
        while i < self.bytes.len() {
            match self.bytes[i] {
                b'(' if infix => {
                    depth += 1;
                    i += 1;
                }
                b')' if depth > 0 => {
                    depth -= 1;
                    i += 1;
                }
                b')' => {
                    self.pos = i + 1;
                    return Ok(Some(Group {
                        offset: open + 1,
                        text: &self.src.text[open + 1..i],
                    }));
                }
                b'(' => {
                    return Err(self.error(
                        i,
                        "`(` inside a group: postfix expressions need no parentheses; close the group before with `)`, or write it in infix, starting with `=`: `(= (x + 1) * 2)`",
                    ))
                }
                // A group never spans lines, so a missing `)` is reported
                // where the group opened, not pages later.
                b'\n' => break,
                _ => i += 1,
            }
        }
        Err(self.error(open, "unclosed group: add the matching `)`"))
    }

    /// Fails when the next word is a misspelt keyword (`EndProduction`),
    /// which would otherwise be read as a run of glued symbols and fail
    /// later with a message that does not name the typo.
    pub fn reject_near_miss(&mut self, keywords: &[&str]) -> Result<(), Diagnostic> {
        self.skip_trivia()?;
        let at = self.pos;
        // Only a whole plain word can be meant as a keyword (symbols with
        // groups, `[`, `+` … are symbol runs); looking at word starts
        // only keeps long glued runs linear to parse.
        if at > 0 && !self.bytes[at - 1].is_ascii_whitespace() && !self.bytes[..at].ends_with(b"*/")
        {
            return Ok(());
        }
        let end = at
            + self.bytes[at..]
                .iter()
                .take_while(|c| c.is_ascii_alphabetic() || **c == b'_')
                .count();
        if end - at < 4 || self.word_end(end) != end {
            return Ok(());
        }
        let w = &self.src.text[at..end];
        match near_miss(w, keywords) {
            Some(k) => Err(self.error(at, format!("`{w}` is not a keyword; did you mean `{k}`?"))),
            None => Ok(()),
        }
    }
}

/// The keyword `word` is a near miss of: a different spelling within a
/// small edit distance (case ignored; a swap of two letters counts one).
pub fn near_miss<'k>(word: &str, keywords: &[&'k str]) -> Option<&'k str> {
    let w = word.to_ascii_lowercase();
    keywords
        .iter()
        .filter(|k| **k != word)
        .map(|k| (edit_distance(&w, &k.to_ascii_lowercase()), *k))
        // About one edit per five letters: `Axoim` → `Axiom`, but
        // never a short symbol run.
        .filter(|(d, k)| *d <= k.len().max(word.len()) / 5)
        .min_by_key(|(d, _)| *d)
        .map(|(_, k)| k)
}

/// `; did you mean `N`?` when `word` is within an edit (one per four
/// letters) of one of `names`: for identifiers of the infix form, where
/// a short name misspelled (`sine`, `tme`) is still a name.
pub fn name_suggestion(word: &str, names: &[&str]) -> String {
    names
        .iter()
        .map(|n| (edit_distance(word, n), *n))
        .filter(|(d, n)| *d <= (n.len().max(word.len()) / 4).max(1))
        .min_by_key(|(d, _)| *d)
        .map_or_else(String::new, |(_, n)| format!("; did you mean `{n}`?"))
}

/// Optimal string alignment distance: insertions, deletions,
/// substitutions and swaps of adjacent letters.
fn edit_distance(a: &str, b: &str) -> usize {
    let (a, b) = (a.as_bytes(), b.as_bytes());
    let mut d = vec![vec![0usize; b.len() + 1]; a.len() + 1];
    for (i, row) in d.iter_mut().enumerate() {
        row[0] = i;
    }
    d[0] = (0..=b.len()).collect();
    for i in 1..=a.len() {
        for j in 1..=b.len() {
            let cost = usize::from(a[i - 1] != b[j - 1]);
            let mut v = (d[i - 1][j] + 1)
                .min(d[i][j - 1] + 1)
                .min(d[i - 1][j - 1] + cost);
            if i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1] {
                v = v.min(d[i - 2][j - 2] + 1);
            }
            d[i][j] = v;
        }
    }
    d[a.len()][b.len()]
}

/// `; did you mean `K`?` when `word` is a near miss of one of `keywords`.
pub fn suggestion(word: &str, keywords: &[&str]) -> String {
    near_miss(word, keywords).map_or_else(String::new, |k| format!("; did you mean `{k}`?"))
}

/// Largest magnitude of a number in a definition file: the Splines end
/// marker `1e30`, and small enough that its square is finite.
pub const MAX_NUMBER: f64 = 1e30;

/// A word written as a decimal number (`1`, `0.5`, `1e30`, `-2`, also
/// `1e999`, which overflows to infinity); `None` for other words (`nan`,
/// `inf`, names).
fn number_shaped(w: &str) -> Option<f64> {
    let b = w.as_bytes();
    let first = *b.first()?;
    let digits_first = first.is_ascii_digit()
        || first == b'.'
        || ((first == b'-' || first == b'+')
            && b.get(1).is_some_and(|c| c.is_ascii_digit() || *c == b'.'));
    if !digits_first {
        return None;
    }
    w.parse::<f64>().ok()
}

/// Characters that may name a symbol (BNF `Symbol`, plus the query `?`
/// and the polygon vertex `.` of appendix C).
pub fn is_symbol_char(c: u8) -> bool {
    c.is_ascii_alphanumeric() || b"[]{}/^&$+-?.".contains(&c)
}

/// Where the whitespace and `/* */` comments of `src` from `from` end,
/// looking no further than `end`; comments do not nest (thesis 6.2), and
/// one that is not closed is an error where it opens.
pub fn trivia_end(src: &Source, end: usize, from: usize) -> Result<usize, Diagnostic> {
    let text = &src.text[..end];
    let mut pos = from;
    loop {
        let rest = &text[pos..];
        let trimmed = rest.trim_start_matches(|c: char| c.is_ascii_whitespace());
        pos += rest.len() - trimmed.len();
        if !trimmed.starts_with("/*") {
            return Ok(pos);
        }
        match trimmed[2..].find("*/") {
            Some(close) => pos += 2 + close + 2,
            None => {
                return Err(src.error(
                    pos,
                    "unclosed comment: add `*/` to end it (comments do not nest)",
                ))
            }
        }
    }
}

/// The section keywords of a definition file, in the order they come.
pub const SECTIONS: [&str; 8] = [
    "Camera_AnimationParameters",
    "RepetitionParameters",
    "Options",
    "Splines",
    "Constants",
    "Surfaces",
    "Axiom",
    "Productions",
];

/// The section names of the readable form (issue 40), in the same order.
pub const READABLE_SECTIONS: [&str; 8] = [
    "camera",
    "repetition",
    "options",
    "splines",
    "constants",
    "surfaces",
    "axiom",
    "productions",
];

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_groups_words_and_comments() {
        let src = Source::new("t", "  /* c */ abc (x2*) 1.5");
        let mut s = Scanner::new(&src);
        assert_eq!(s.word("a word").unwrap().1, "abc");
        let g = s.group().unwrap().unwrap();
        assert_eq!((g.offset, g.text), (15, "x2*"));
        assert_eq!(s.number("n").unwrap(), 1.5);
        assert!(s.at_end().unwrap());
    }

    #[test]
    fn near_misses_name_the_keyword() {
        let kws = ["EndProductions", "Axiom", "End"];
        assert_eq!(near_miss("EndProduction", &kws), Some("EndProductions"));
        assert_eq!(near_miss("Axoim", &kws), Some("Axiom"));
        assert_eq!(near_miss("axiom", &kws), Some("Axiom"));
        assert_eq!(near_miss("end", &kws), Some("End"));
        assert_eq!(near_miss("Axiom", &kws), None);
        assert_eq!(near_miss("Edn", &kws), None);
        assert_eq!(near_miss("FFFF", &kws), None);
    }

    #[test]
    fn unclosed_group_points_at_open_paren() {
        let src = Source::new("t", "F (x2*\nG");
        let mut s = Scanner::new(&src);
        s.word("w").unwrap();
        let e = s.group().unwrap_err();
        assert_eq!((e.line, e.column), (1, 3));
    }
}
