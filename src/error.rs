//! The one error every command returns, and its exit code (DESIGN §5).
//!
//! Each layer says what went wrong in its own words — a [`Diagnostic`]
//! that points into a scene, a manifest that does not parse, a disk that
//! is full — and the place that knows whose fault it is sorts it into one
//! of two kinds: the user's input (exit 2, with its location where it has
//! one) or anything else (exit 1).

use std::fmt;

use crate::source::Diagnostic;

/// Whose fault an error is, which decides the exit code.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    /// Bad input or usage: a scene, a file it names, an option, a folder
    /// made by something else. Exit code 2.
    Input,
    /// Anything else: a disk that is full, a script that failed, ffmpeg.
    /// Exit code 1.
    Other,
}

/// An error with its kind and the message shown to the user.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Error {
    kind: Kind,
    message: String,
}

/// A result whose error is [`Error`].
pub type Result<T> = std::result::Result<T, Error>;

impl Error {
    /// Bad input or usage (exit 2); the message names where when it can.
    pub fn input(message: impl Into<String>) -> Error {
        Error {
            kind: Kind::Input,
            message: message.into(),
        }
    }

    /// Anything that is not the input's fault (exit 1).
    pub fn other(message: impl Into<String>) -> Error {
        Error {
            kind: Kind::Other,
            message: message.into(),
        }
    }

    /// A file that could not be read or written, with a hint at the usual
    /// causes (exit 1).
    pub fn io(path: &std::path::Path, e: impl fmt::Display) -> Error {
        Error::other(format!(
            "{}: {e} (is the folder writable and the disk not full?)",
            path.display()
        ))
    }

    pub fn kind(&self) -> Kind {
        self.kind
    }

    pub fn message(&self) -> &str {
        &self.message
    }

    /// The process exit code: 2 for input, 1 for anything else.
    pub fn exit_code(&self) -> u8 {
        match self.kind {
            Kind::Input => 2,
            Kind::Other => 1,
        }
    }

    /// The same error with `prefix: ` in front of its message (a frame
    /// number, a folder).
    pub fn context(self, prefix: impl fmt::Display) -> Error {
        Error {
            kind: self.kind,
            message: format!("{prefix}: {}", self.message),
        }
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.message)
    }
}

impl std::error::Error for Error {}

/// A diagnostic points into the user's text: always input.
impl From<Diagnostic> for Error {
    fn from(d: Diagnostic) -> Error {
        Error::input(d.to_string())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn input_is_exit_2_and_the_rest_exit_1() {
        assert_eq!(Error::input("bad").exit_code(), 2);
        assert_eq!(Error::other("disk").exit_code(), 1);
        let e = Error::input("no such sound").context("frame 3");
        assert_eq!(
            (e.kind(), e.to_string().as_str()),
            (Kind::Input, "frame 3: no such sound")
        );
    }
}
