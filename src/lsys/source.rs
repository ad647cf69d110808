//! Source text of a definition file and the diagnostics that point into it.
//!
//! Every error about user input names `file:line:column`, repeats the line
//! and puts a caret under the column, so a user can fix it without a debugger.

use std::fmt;

/// One definition file's text with its display name.
#[derive(Debug, Clone)]
pub struct Source {
    pub name: String,
    pub text: String,
}

impl Source {
    pub fn new(name: impl Into<String>, text: impl Into<String>) -> Self {
        Source {
            name: name.into(),
            text: text.into(),
        }
    }

    /// A diagnostic at byte `offset` of the text.
    pub fn error(&self, offset: usize, message: impl Into<String>) -> Diagnostic {
        let (line_start, line, column) = position(&self.text, offset);
        let line_end = self.text[line_start..]
            .find('\n')
            .map_or(self.text.len(), |i| line_start + i);
        Diagnostic {
            file: self.name.clone(),
            line,
            column,
            message: message.into(),
            source_line: self.text[line_start..line_end]
                .trim_end_matches('\r')
                .to_string(),
        }
    }
}

/// Start of the line, line and column (1-based, in characters) of byte
/// `offset` of `text`.
pub fn position(text: &str, offset: usize) -> (usize, usize, usize) {
    let mut offset = offset.min(text.len());
    while !text.is_char_boundary(offset) {
        offset -= 1;
    }
    let before = &text[..offset];
    let line_start = before.rfind('\n').map_or(0, |i| i + 1);
    let line = before.matches('\n').count() + 1;
    let column = text[line_start..offset].chars().count() + 1;
    (line_start, line, column)
}

/// A user-facing error located in a file.
#[derive(Debug, Clone, PartialEq)]
pub struct Diagnostic {
    pub file: String,
    pub line: usize,
    pub column: usize,
    pub message: String,
    pub source_line: String,
}

impl fmt::Display for Diagnostic {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "{}:{}:{}: {}",
            self.file, self.line, self.column, self.message
        )?;
        // Tabs keep their width so the caret lines up under the column.
        let pad: String = self
            .source_line
            .chars()
            .take(self.column - 1)
            .map(|c| if c == '\t' { '\t' } else { ' ' })
            .collect();
        writeln!(f, "  {}", self.source_line)?;
        write!(f, "  {pad}^")
    }
}

impl std::error::Error for Diagnostic {}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn locates_line_and_column() {
        let s = Source::new("a.lm", "Axiom\n  F (x+\n");
        let d = s.error(10, "stack underflow");
        assert_eq!((d.line, d.column), (2, 5));
        assert_eq!(
            d.to_string(),
            "a.lm:2:5: stack underflow\n    F (x+\n      ^"
        );
    }
}
