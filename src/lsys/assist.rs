//! What an editor asks of a definition file (issue 40's language
//! server): its first error, what the word under the cursor means, the
//! names that complete it, and where the rules of a symbol are. Both
//! forms; positions are 1-based lines and columns in characters.

use super::automata::AutomataCommand;
use super::catalogue::{named, slot_timing, Meaning, MEANINGS, SLOTS};
use super::expr::special_arity;
use super::infix::{FUNCTIONS, PARAMETERS, SPECIALS};
use super::parse::parse;
use super::readable::is_readable;
use super::scan::{READABLE_SECTIONS, SECTIONS};
use crate::source::{Diagnostic, Source};

/// The first error of the file, if any.
pub fn check(name: &str, text: &str) -> Option<Diagnostic> {
    parse(&Source::new(name, text)).err()
}

/// The word at `line`, `column` and the column it starts at: an
/// identifier, or in a classic file the symbol character there.
fn word_at(text: &str, line: usize, column: usize) -> Option<(String, usize)> {
    let l = text.lines().nth(line.checked_sub(1)?)?;
    let chars: Vec<char> = l.chars().collect();
    let at = column.checked_sub(1)?.min(chars.len().saturating_sub(1));
    let ident = |c: char| c.is_ascii_alphanumeric() || c == '_';
    if chars.is_empty() {
        return None;
    }
    if !ident(chars[at]) {
        return Some((chars[at].to_string(), at + 1));
    }
    let mut start = at;
    while start > 0 && ident(chars[start - 1]) {
        start -= 1;
    }
    let mut end = at;
    while end < chars.len() && ident(chars[end]) {
        end += 1;
    }
    Some((chars[start..end].iter().collect(), start + 1))
}

/// Markdown of one meaning: its signature, what it does, its classic
/// spelling and when each parameter is evaluated.
fn describe(m: &Meaning) -> String {
    let mut s = format!(
        "**{}** — `{}`\n\n{}\n\nClassic: `{}`",
        m.signature(),
        m.ch as char,
        m.doc,
        m.classic()
    );
    for p in m.params {
        s.push_str(&format!(
            "\n- `{}` ({}): slot {} — {}",
            p.name,
            p.unit.describe(),
            SLOTS[p.slot as usize],
            slot_timing(p.slot)
        ));
    }
    s
}

/// What the word at the position means, as Markdown.
pub fn hover(name: &str, text: &str, line: usize, column: usize) -> Option<String> {
    let (word, _) = word_at(text, line, column)?;
    if let Some(m) = named(&word) {
        return Some(describe(m));
    }
    if let Some((n, _, args)) = FUNCTIONS.iter().find(|f| f.0 == word) {
        return Some(format!(
            "**{n}** — a function of {args} argument(s) (tables B2–B4)"
        ));
    }
    if let Some((n, k)) = SPECIALS.iter().find(|f| f.0 == word) {
        let args = special_arity(*k).unwrap_or(0);
        return Some(format!(
            "**{n}** — `?{k:02}`, a special function of table B5 ({args} argument(s)); docs/language.md §5.6"
        ));
    }
    if let Some((n, _)) = PARAMETERS.iter().find(|p| p.0 == word) {
        return Some(format!("**{n}** — a parameter of expressions (table B5)"));
    }
    if let Some((n, min, max)) = AutomataCommand::keywords().find(|c| c.0 == word) {
        return Some(format!(
            "**{n}** — an automata command (table B6) of {min}–{max} argument(s), in `automata(\"…\")` or an `e` symbol's text; docs/actors.md"
        ));
    }
    if let Some(k) = READABLE_SECTIONS.iter().position(|s| *s == word) {
        return Some(format!("Section **{word}** (classic `{}`)", SECTIONS[k]));
    }
    let c = word.bytes().next()?;
    // A symbol: its meanings (a classic file's letters, or a readable
    // file's own letters).
    let meanings: Vec<&Meaning> = MEANINGS.iter().filter(|m| m.ch == c).collect();
    if word.len() != 1 {
        return None;
    }
    if meanings.is_empty() {
        return Some(format!(
            "`{word}` — a symbol with no meaning to the turtle: only the rules rewrite it{}",
            if is_readable(name) {
                ""
            } else {
                " (age, x, y, z, f1, f2, f3)"
            }
        ));
    }
    let list: Vec<String> = meanings
        .iter()
        .map(|m| format!("- `{}` → **{}**: {}", m.classic(), m.signature(), m.doc))
        .collect();
    Some(format!("`{word}` — by its selectors:\n{}", list.join("\n")))
}

/// Names that complete the identifier before the position: symbols of
/// the catalogue, functions, parameters, sections, with a detail each.
pub fn complete(text: &str, line: usize, column: usize) -> Vec<(String, String)> {
    let prefix = text
        .lines()
        .nth(line.saturating_sub(1))
        .map(|l| {
            let before: String = l.chars().take(column.saturating_sub(1)).collect();
            let n = before
                .chars()
                .rev()
                .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
                .count();
            before
                .chars()
                .skip(before.chars().count() - n)
                .collect::<String>()
        })
        .unwrap_or_default();
    let mut out: Vec<(String, String)> = Vec::new();
    out.extend(MEANINGS.iter().map(|m| (m.name.to_string(), m.signature())));
    out.extend(
        FUNCTIONS
            .iter()
            .map(|(n, _, a)| (n.to_string(), format!("function of {a} argument(s)"))),
    );
    out.extend(
        SPECIALS
            .iter()
            .map(|(n, k)| (n.to_string(), format!("?{k:02}, table B5"))),
    );
    out.extend(
        PARAMETERS
            .iter()
            .map(|(n, _)| (n.to_string(), "parameter".to_string())),
    );
    out.extend(
        READABLE_SECTIONS
            .iter()
            .map(|s| (s.to_string(), "section".to_string())),
    );
    out.extend(AutomataCommand::keywords().map(|(n, min, max)| {
        (
            n.to_string(),
            format!("automata command, {min}–{max} argument(s)"),
        )
    }));
    for k in ["rule", "at_age", "left", "right", "if", "and", "or", "not"] {
        out.push((k.to_string(), "keyword".to_string()));
    }
    out.retain(|(n, _)| n.starts_with(&prefix));
    out
}

/// Where the rules (productions) of the symbol at the position are.
pub fn definitions(name: &str, text: &str, line: usize, column: usize) -> Vec<(usize, usize)> {
    let Some((word, _)) = word_at(text, line, column) else {
        return Vec::new();
    };
    let &[c] = word.as_bytes() else {
        return Vec::new();
    };
    let Ok(def) = parse(&Source::new(name, text)) else {
        return Vec::new();
    };
    def.productions
        .iter()
        .filter(|p| p.lhs == c)
        .map(|p| def.source.place(p.offset))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    const READABLE: &str =
        "axiom\nsphere(0.5) A\nproductions\nrule A at_age 1 {\n    1 -> turn_left(30) A\n}\n";

    #[test]
    fn hover_completion_and_definitions() {
        let h = hover("t.lmr", READABLE, 2, 3).unwrap();
        assert!(h.contains("sphere(diameter: a length in metres)"), "{h}");
        assert!(h.contains("Classic: `a`"), "{h}");
        let h = hover("t.lm", "Axiom\nf () () () (2)\n", 2, 1).unwrap();
        assert!(h.contains("move_to"), "{h}");
        let c = complete(READABLE, 5, 16);
        assert!(c.iter().any(|(n, _)| n == "turn_left"), "{c:?}");
        assert!(c.iter().all(|(n, _)| n.starts_with("turn_")), "{c:?}");
        let text = "axiom\nautomata(\"goal 1 0 2\")\n";
        let c = complete(text, 2, 12);
        assert!(
            c.iter().any(|(n, d)| n == "goal" && d.contains("automata")),
            "{c:?}"
        );
        assert!(hover("t.lmr", text, 2, 12).unwrap().contains("table B6"));
        assert_eq!(definitions("t.lmr", READABLE, 2, 13), vec![(4, 1)]);
        assert!(check("t.lmr", READABLE).is_none());
        let e = check("t.lmr", "axiom\nsphere(radius: 1)\n").unwrap();
        assert_eq!((e.line, e.column), (2, 8));
    }
}
