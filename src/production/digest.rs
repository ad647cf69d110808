//! The sha256 digests that bind every output to its inputs (DESIGN §4):
//! records and manifests name each file by its hash.

use std::io::{self, Read};
use std::path::Path;

use sha2::{Digest, Sha256};

use crate::source::open_file;

/// Lowercase hex sha256 of `bytes`.
pub fn sha256_bytes(bytes: &[u8]) -> String {
    hex(&Sha256::digest(bytes))
}

/// Lowercase hex sha256 of a file, read in blocks so that large EXRs are
/// never held in memory whole: a regular file of at most `limit` bytes
/// only ([`open_file`]: a pipe, a device or a folder is refused, never
/// waited on).
pub fn sha256_file(path: &Path, limit: u64) -> io::Result<String> {
    let mut file = open_file(path, limit)?;
    let mut hasher = Sha256::new();
    let mut buf = vec![0u8; 1 << 16];
    loop {
        match file.read(&mut buf) {
            Ok(0) => return Ok(hex(&hasher.finalize())),
            Ok(n) => hasher.update(&buf[..n]),
            Err(e) if e.kind() == io::ErrorKind::Interrupted => {}
            Err(e) => return Err(e),
        }
    }
}

fn hex(bytes: &[u8]) -> String {
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}
