//! Source text of a definition file and the diagnostics that point into it.
//!
//! Every error about user input names `file:line:column`, repeats the line
//! and puts a caret under the column, so a user can fix it without a debugger.

use std::fmt;
use std::io::{self, Read};
use std::path::Path;
use std::sync::Arc;

/// One definition file's text with its display name.
#[derive(Debug, Clone)]
pub struct Source {
    pub name: String,
    pub text: String,
    /// The text as the user wrote it, when `text` was made from it (the
    /// classic spelling of a readable file): errors point there.
    pub written: Option<Arc<Written>>,
}

/// A file as written and where each piece of the text made from it came
/// from.
#[derive(Debug)]
pub struct Written {
    pub text: String,
    /// (offset in the made text, offset in the written text, whether the
    /// piece was copied, so that offsets within it advance together),
    /// ordered by the first.
    pub pieces: Vec<(usize, usize, bool)>,
}

impl Written {
    /// Where byte `offset` of the made text came from.
    pub fn origin(&self, offset: usize) -> usize {
        let k = self.pieces.partition_point(|p| p.0 <= offset);
        match k.checked_sub(1).map(|k| self.pieces[k]) {
            Some((made, written, true)) => written + (offset - made),
            Some((_, written, false)) => written,
            None => 0,
        }
    }
}

impl Source {
    pub fn new(name: impl Into<String>, text: impl Into<String>) -> Self {
        Source {
            name: name.into(),
            text: text.into(),
            written: None,
        }
    }

    /// The text errors point into and the offset there of byte `offset`.
    fn shown(&self, offset: usize) -> (&str, usize) {
        match &self.written {
            Some(w) => (&w.text, w.origin(offset)),
            None => (&self.text, offset),
        }
    }

    /// Line and column (1-based) where the user wrote byte `offset`.
    pub fn place(&self, offset: usize) -> (usize, usize) {
        let (text, offset) = self.shown(offset);
        let (_, line, column) = position(text, offset);
        (line, column)
    }

    /// The text of `bytes`, or a diagnostic at the first byte that is not
    /// UTF-8 (the line shown up to it).
    pub fn from_bytes(name: impl Into<String>, bytes: Vec<u8>) -> Result<Self, Diagnostic> {
        match String::from_utf8(bytes) {
            Ok(text) => Ok(Source::new(name, text)),
            Err(e) => {
                let at = e.utf8_error().valid_up_to();
                let bad = e.as_bytes()[at];
                // The valid prefix is the same in the lossy text.
                let shown = Source::new(name, String::from_utf8_lossy(e.as_bytes()).into_owned());
                Err(shown.error(
                    at,
                    format!("byte 0x{bad:02x} is not UTF-8 text; save the file as UTF-8"),
                ))
            }
        }
    }

    /// A diagnostic at byte `offset` of the text.
    pub fn error(&self, offset: usize, message: impl Into<String>) -> Diagnostic {
        let (text, offset) = self.shown(offset);
        let (line_start, line, column) = position(text, offset);
        let line_end = text[line_start..]
            .find('\n')
            .map_or(text.len(), |i| line_start + i);
        Diagnostic {
            file: self.name.clone(),
            line,
            column,
            message: message.into(),
            source_line: text[line_start..line_end]
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

/// A file a definition names (a surface's OBJ, a sound, a script) with
/// where it is named, so a file that cannot be read is reported at the
/// line that names it.
#[derive(Debug, Clone, PartialEq)]
pub struct FileRef {
    pub name: String,
    /// The location of the name (its message empty).
    pub at: Diagnostic,
}

impl FileRef {
    /// The file named by the word `name` at byte `offset` of `src`.
    pub fn new(src: &Source, offset: usize, name: &str) -> Self {
        FileRef {
            name: name.to_string(),
            at: src.error(offset, ""),
        }
    }

    /// An error about the file, located where the definition names it.
    pub fn error(&self, message: impl Into<String>) -> Diagnostic {
        Diagnostic {
            message: message.into(),
            ..self.at.clone()
        }
    }
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

/// Reads a file the user named: only a regular file (not a folder, nor a
/// device such as `/dev/zero` that never ends, nor a pipe), and at most
/// `limit` bytes, checked before reading and while reading (a file may
/// grow). The errors say which of these failed.
pub fn read_file(path: &Path, limit: u64) -> io::Result<Vec<u8>> {
    let invalid = |m: String| io::Error::new(io::ErrorKind::InvalidInput, m);
    let meta = std::fs::metadata(path)?;
    if meta.is_dir() {
        return Err(invalid("is a folder, not a file".into()));
    }
    if !meta.is_file() {
        return Err(invalid(
            "is not a regular file (a device, a pipe or a socket)".into(),
        ));
    }
    let too_big = || invalid(format!("is larger than the limit of {limit} bytes"));
    if meta.len() > limit {
        return Err(too_big());
    }
    let mut bytes = Vec::with_capacity(meta.len() as usize);
    std::fs::File::open(path)?
        .take(limit.saturating_add(1))
        .read_to_end(&mut bytes)?;
    if bytes.len() as u64 > limit {
        return Err(too_big());
    }
    Ok(bytes)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn non_utf8_names_the_first_bad_byte() {
        let d = Source::from_bytes("a.lm", b"Axiom\n  F\xff G\n".to_vec()).unwrap_err();
        assert_eq!((d.line, d.column), (2, 4));
        assert!(d.message.contains("0xff"), "{d}");
    }

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
