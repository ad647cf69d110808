//! Scene snapshots: one [`Scene`] per file, so `derive` runs the simulation
//! once and any number of `render` processes on any machines ray-trace the
//! frames (DESIGN §1, §5, `DIR/scene/NNNN.snap`).
//!
//! Layout (all integers little-endian):
//!
//! | bytes | content |
//! |---|---|
//! | 8 | magic `LMSNAP\0\0` |
//! | 4 | format version, u32 ([`VERSION`]) |
//! | 8 | payload length, u64 |
//! | n | payload: the postcard encoding of the [`Scene`] |
//! | 8 | FNV-1a 64 hash of the payload, u64 |
//!
//! postcard writes floats as their raw bits and has a single encoding per
//! value, so a round trip is bit-exact and the same scene always gives the
//! same bytes (DESIGN §4). The trailing hash catches files cut short or
//! damaged in transit between machines, which postcard alone might decode
//! into a plausible but wrong scene.

use std::fmt;
use std::fs;
use std::io;
use std::path::{Path, PathBuf};

use super::Scene;

/// First bytes of every snapshot, to reject other files early.
pub const MAGIC: [u8; 8] = *b"LMSNAP\0\0";

/// Format version written by this build; bump it whenever `Scene` or any
/// type inside it changes shape, since postcard is not self-describing.
pub const VERSION: u32 = 2;

/// Bytes before the payload: magic, version, payload length.
const HEADER_LEN: usize = 8 + 4 + 8;
/// Bytes after the payload: the hash.
const TRAILER_LEN: usize = 8;

/// Why a snapshot could not be read.
#[derive(Debug)]
pub enum SnapshotError {
    /// The file could not be opened or read.
    Io(io::Error),
    /// The bytes do not start with [`MAGIC`].
    NotASnapshot,
    /// The file has a format version this build cannot read.
    Version { found: u32, supported: u32 },
    /// The bytes end before the length the header announces.
    Truncated,
    /// The payload does not match its hash, or bytes follow the hash.
    Corrupt,
    /// The payload is intact but is not a `Scene` of this build (a build
    /// that changed `Scene` without bumping [`VERSION`]).
    Decode(String),
    /// Any of the above, in the named file (what [`read`] returns).
    File {
        path: PathBuf,
        error: Box<SnapshotError>,
    },
}

impl SnapshotError {
    /// The error itself, without the [`SnapshotError::File`] wrapper, so
    /// callers can match on the cause whether or not a file was involved.
    pub fn kind(&self) -> &SnapshotError {
        match self {
            SnapshotError::File { error, .. } => error.kind(),
            other => other,
        }
    }

    /// The file the error happened in, if it came from [`read`].
    pub fn path(&self) -> Option<&Path> {
        match self {
            SnapshotError::File { path, .. } => Some(path),
            _ => None,
        }
    }

    fn in_file(self, path: &Path) -> SnapshotError {
        SnapshotError::File {
            path: path.to_path_buf(),
            error: Box::new(self),
        }
    }
}

impl fmt::Display for SnapshotError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SnapshotError::Io(e) => write!(f, "cannot read scene snapshot: {e}"),
            SnapshotError::NotASnapshot => f.write_str(
                "not an lmfilm scene snapshot (bad magic bytes); \
                 expected a `.snap` file written by `lmfilm derive`",
            ),
            SnapshotError::Version { found, supported } if found > supported => write!(
                f,
                "scene snapshot has format version {found}, newer than the version \
                 {supported} this lmfilm reads; use the lmfilm that wrote it, or re-run \
                 `lmfilm derive` with this one"
            ),
            SnapshotError::Version { found, supported } => write!(
                f,
                "scene snapshot has old format version {found} (this lmfilm reads \
                 version {supported}); re-run `lmfilm derive` to regenerate it"
            ),
            SnapshotError::Truncated => f.write_str(
                "scene snapshot is truncated (an interrupted copy?); copy it again or \
                 re-run `lmfilm derive` to regenerate it",
            ),
            SnapshotError::Corrupt => f.write_str(
                "scene snapshot is corrupt (checksum mismatch or data after its end); \
                 copy it again or re-run `lmfilm derive` to regenerate it",
            ),
            SnapshotError::Decode(e) => write!(
                f,
                "scene snapshot does not decode as a scene of this lmfilm ({e}); it was \
                 probably written by an incompatible build: re-run `lmfilm derive`"
            ),
            SnapshotError::File { path, error } => write!(f, "{}: {error}", path.display()),
        }
    }
}

impl std::error::Error for SnapshotError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            SnapshotError::Io(e) => Some(e),
            SnapshotError::File { error, .. } => error.source(),
            _ => None,
        }
    }
}

impl From<io::Error> for SnapshotError {
    fn from(e: io::Error) -> Self {
        SnapshotError::Io(e)
    }
}

/// FNV-1a 64: tiny, dependency-free and enough to detect accidental damage
/// (this is not a defence against deliberate tampering).
fn fnv1a64(bytes: &[u8]) -> u64 {
    const OFFSET: u64 = 0xcbf2_9ce4_8422_2325;
    const PRIME: u64 = 0x0000_0100_0000_01b3;
    bytes
        .iter()
        .fold(OFFSET, |h, &b| (h ^ u64::from(b)).wrapping_mul(PRIME))
}

/// The snapshot bytes of `scene`; equal scenes (bit for bit) give equal bytes.
pub fn encode(scene: &Scene) -> Vec<u8> {
    // Serializing plain data into a Vec cannot fail: every type in `Scene`
    // is a struct, enum, sequence or primitive that postcard supports.
    let payload = postcard::to_stdvec(scene).expect("postcard encodes every Scene");
    let mut out = Vec::with_capacity(HEADER_LEN + payload.len() + TRAILER_LEN);
    out.extend_from_slice(&MAGIC);
    out.extend_from_slice(&VERSION.to_le_bytes());
    out.extend_from_slice(&(payload.len() as u64).to_le_bytes());
    out.extend_from_slice(&payload);
    out.extend_from_slice(&fnv1a64(&payload).to_le_bytes());
    out
}

/// Reads `N` bytes at `at`, or reports the file as truncated.
fn take<const N: usize>(bytes: &[u8], at: usize) -> Result<[u8; N], SnapshotError> {
    bytes
        .get(at..at + N)
        .and_then(|s| s.try_into().ok())
        .ok_or(SnapshotError::Truncated)
}

/// The scene in snapshot bytes. Checks magic, then version (before anything
/// else, so a future layout still reports its version), then length and
/// hash, and only then decodes. Never panics, whatever the bytes.
pub fn decode(bytes: &[u8]) -> Result<Scene, SnapshotError> {
    let magic_seen = &bytes[..bytes.len().min(MAGIC.len())];
    if magic_seen != &MAGIC[..magic_seen.len()] {
        return Err(SnapshotError::NotASnapshot);
    }
    let _: [u8; 8] = take(bytes, 0)?;
    let found = u32::from_le_bytes(take(bytes, 8)?);
    if found != VERSION {
        return Err(SnapshotError::Version {
            found,
            supported: VERSION,
        });
    }
    let len = u64::from_le_bytes(take(bytes, 12)?);
    let rest = &bytes[HEADER_LEN..];
    // Compare in u64 so a huge announced length cannot overflow usize.
    let needed = len.checked_add(TRAILER_LEN as u64);
    match needed {
        Some(n) if (rest.len() as u64) < n => return Err(SnapshotError::Truncated),
        None => return Err(SnapshotError::Truncated),
        Some(n) if (rest.len() as u64) > n => return Err(SnapshotError::Corrupt),
        Some(_) => {}
    }
    // `len` fits in usize now: it is at most `rest.len()`.
    let (payload, trailer) = rest.split_at(len as usize);
    let stored = u64::from_le_bytes(take(trailer, 0)?);
    if stored != fnv1a64(payload) {
        return Err(SnapshotError::Corrupt);
    }
    let (scene, unused) = postcard::take_from_bytes::<Scene>(payload)
        .map_err(|e| SnapshotError::Decode(e.to_string()))?;
    if !unused.is_empty() {
        return Err(SnapshotError::Decode(format!(
            "{} unused bytes after the scene",
            unused.len()
        )));
    }
    Ok(scene)
}

/// Writes the snapshot of `scene` to `path` atomically, so a killed run
/// never leaves a half-written snapshot that a `render` process could pick
/// up. Errors name the file.
pub fn write(scene: &Scene, path: &Path) -> io::Result<()> {
    super::atomic::write_atomic(path, &encode(scene))
}

/// Reads the snapshot at `path`; every error names the file.
pub fn read(path: &Path) -> Result<Scene, SnapshotError> {
    let bytes = fs::read(path).map_err(|e| SnapshotError::Io(e).in_file(path))?;
    decode(&bytes).map_err(|e| e.in_file(path))
}
