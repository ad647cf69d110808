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

/// Why a file was not read: what it is instead of a regular file of at
/// most its limit. It travels inside the [`io::Error`] (kind
/// `InvalidInput`) that [`open_file`] and [`read_file`] return; [`refused`]
/// takes it out.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Refused {
    /// A folder.
    Folder,
    /// A device, such as `/dev/zero`, whose reading may never end.
    Device,
    /// A named pipe (FIFO): reading waits for a writer, then for its end.
    Pipe,
    /// A socket.
    Socket,
    /// A regular file over the limit when opened.
    TooLarge { size: u64, limit: u64 },
    /// A regular file that grew past the limit while it was read.
    Grew { limit: u64 },
}

impl Refused {
    /// What a file of this kind is instead of a regular file, None for a
    /// regular file.
    pub fn of_kind(kind: std::fs::FileType) -> Option<Refused> {
        use std::os::unix::fs::FileTypeExt;
        if kind.is_file() {
            None
        } else if kind.is_dir() {
            Some(Refused::Folder)
        } else if kind.is_fifo() {
            Some(Refused::Pipe)
        } else if kind.is_socket() {
            Some(Refused::Socket)
        } else {
            Some(Refused::Device)
        }
    }

    /// Whether the file is something else than a regular file (a folder,
    /// a device, a pipe, a socket), not merely too large.
    pub fn not_a_file(self) -> bool {
        !matches!(self, Refused::TooLarge { .. } | Refused::Grew { .. })
    }
}

impl fmt::Display for Refused {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Refused::Folder => f.write_str("is a folder, not a file"),
            Refused::Device => {
                f.write_str("is a device, not a regular file (reading it might never end)")
            }
            Refused::Pipe => f.write_str(
                "is a named pipe (FIFO), not a regular file (reading it waits for whatever writes to it)",
            ),
            Refused::Socket => f.write_str("is a socket, not a regular file"),
            Refused::TooLarge { size, limit } => write!(
                f,
                "is too large: {size} bytes, {} over the limit of {limit}",
                size - limit
            ),
            Refused::Grew { limit } => write!(
                f,
                "grew past the limit of {limit} bytes while it was read (is it still being written?)"
            ),
        }
    }
}

impl std::error::Error for Refused {}

impl From<Refused> for io::Error {
    fn from(r: Refused) -> io::Error {
        io::Error::new(io::ErrorKind::InvalidInput, r)
    }
}

/// Why [`open_file`] or [`read_file`] refused a file, when that is what
/// the error says (not a missing file, nor a permission).
pub fn refused(e: &io::Error) -> Option<Refused> {
    e.get_ref()?.downcast_ref::<Refused>().copied()
}

/// A file opened by [`open_file`]: reads at most its limit, and fails
/// (with [`Refused::Grew`]) rather than read past it.
#[derive(Debug)]
pub struct Bounded {
    file: io::Take<std::fs::File>,
    limit: u64,
    read: u64,
    size: u64,
}

impl Bounded {
    /// The file's size when it was opened.
    pub fn size(&self) -> u64 {
        self.size
    }
}

impl Read for Bounded {
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        let n = self.file.read(buf)?;
        self.read += n as u64;
        if self.read > self.limit {
            return Err(Refused::Grew { limit: self.limit }.into());
        }
        Ok(n)
    }
}

/// Opens a file lmfilm reads, as what it must be: a regular file (not a
/// folder, nor a device such as `/dev/zero` that never ends, nor a pipe
/// that waits for a writer) of at most `limit` bytes. The file is opened
/// without waiting (`O_NONBLOCK`: opening a pipe never blocks) and its
/// kind and size are those of the opened handle (`fstat`), so a file
/// swapped between a check and the opening is refused too. The reader
/// fails rather than read past `limit` (a file still being written).
/// The errors say which of these failed ([`refused`]).
pub fn open_file(path: &Path, limit: u64) -> io::Result<Bounded> {
    use std::os::unix::fs::{FileTypeExt, OpenOptionsExt};
    let file = match std::fs::OpenOptions::new()
        .read(true)
        .custom_flags(libc::O_NONBLOCK | libc::O_NOCTTY)
        .open(path)
    {
        Ok(f) => f,
        // Opening a socket fails with "no such device or address".
        Err(e) if e.raw_os_error() == Some(libc::ENXIO) => {
            let socket = std::fs::metadata(path).is_ok_and(|m| m.file_type().is_socket());
            return Err(if socket { Refused::Socket.into() } else { e });
        }
        Err(e) => return Err(e),
    };
    let meta = file.metadata()?;
    let refused = Refused::of_kind(meta.file_type()).or_else(|| {
        (meta.len() > limit).then_some(Refused::TooLarge {
            size: meta.len(),
            limit,
        })
    });
    if let Some(r) = refused {
        return Err(r.into());
    }
    Ok(Bounded {
        file: file.take(limit.saturating_add(1)),
        limit,
        read: 0,
        size: meta.len(),
    })
}

/// Reads a file the user named or lmfilm wrote, through [`open_file`]:
/// only a regular file, and at most `limit` bytes, checked when opened
/// and while reading (a file may grow).
pub fn read_file(path: &Path, limit: u64) -> io::Result<Vec<u8>> {
    let mut file = open_file(path, limit)?;
    let mut bytes = Vec::with_capacity(file.size() as usize);
    file.read_to_end(&mut bytes)?;
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

    /// A fresh folder for one test of the opener.
    fn folder(name: &str) -> std::path::PathBuf {
        let dir = std::env::temp_dir().join(format!("lmfilm-source-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    fn refusal(path: &Path, limit: u64) -> Refused {
        let e = open_file(path, limit).expect_err("refused");
        refused(&e).unwrap_or_else(|| panic!("{}: not a refusal: {e}", path.display()))
    }

    #[test]
    fn a_pipe_is_refused_without_waiting_for_a_writer() {
        let dir = folder("fifo");
        let fifo = dir.join("pipe");
        let name = std::ffi::CString::new(fifo.to_str().unwrap()).unwrap();
        // SAFETY: a valid NUL-terminated path.
        assert_eq!(unsafe { libc::mkfifo(name.as_ptr(), 0o600) }, 0);
        // Blocking here would hang the test: nothing ever writes to it.
        assert_eq!(refusal(&fifo, 1 << 20), Refused::Pipe);
        let e = read_file(&fifo, 1 << 20).unwrap_err();
        assert!(e.to_string().contains("named pipe"), "{e}");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn a_device_is_refused_even_behind_a_link() {
        assert_eq!(refusal(Path::new("/dev/zero"), 1 << 20), Refused::Device);
        let dir = folder("device");
        let link = dir.join("frame.png");
        std::os::unix::fs::symlink("/dev/zero", &link).unwrap();
        assert_eq!(refusal(&link, 1 << 20), Refused::Device);
        assert!(refusal(&link, 1).not_a_file());
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn a_folder_is_refused() {
        let dir = folder("folder");
        assert_eq!(refusal(&dir, 1 << 20), Refused::Folder);
        let e = read_file(&dir, 1 << 20).unwrap_err();
        assert_eq!(e.to_string(), "is a folder, not a file");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn a_file_over_the_limit_is_refused_and_one_within_is_read() {
        let dir = folder("limit");
        let file = dir.join("record.json");
        std::fs::write(&file, b"0123456789").unwrap();
        let r = refusal(&file, 4);
        assert_eq!(r, Refused::TooLarge { size: 10, limit: 4 });
        assert!(!r.not_a_file());
        assert_eq!(
            r.to_string(),
            "is too large: 10 bytes, 6 over the limit of 4"
        );
        assert_eq!(read_file(&file, 10).unwrap(), b"0123456789");
        // A file that grows past the limit after it was opened.
        let mut opened = open_file(&file, 12).unwrap();
        std::fs::write(&file, b"0123456789abcdef").unwrap();
        let mut bytes = Vec::new();
        let e = opened.read_to_end(&mut bytes).unwrap_err();
        assert_eq!(refused(&e), Some(Refused::Grew { limit: 12 }));
        // A missing file is no refusal: its error says so.
        let e = open_file(&dir.join("missing"), 4).unwrap_err();
        assert_eq!(e.kind(), io::ErrorKind::NotFound);
        assert_eq!(refused(&e), None);
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
