//! Atomic file writes (DESIGN §5): a killed run never leaves a
//! half-written output that a later run or a render process could pick up.
//!
//! Render-farm shards on many machines write into one shared folder, so a
//! temporary name carries the host name as well as the pid and a counter:
//! `NAME.~HOST~PID~N.tmp`. A stale temporary is removed only when it is
//! this host's and its process is gone — never another machine's
//! half-written frame.

use std::fs;
use std::io::{self, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::OnceLock;

/// Distinguishes temporary files of concurrent writes within one process.
static TEMP_COUNTER: AtomicU64 = AtomicU64::new(0);

/// Environment variable that names this host in temporary files (for
/// containers that all share one host name, and for tests).
pub const HOST_VAR: &str = "LMFILM_HOST";

/// This machine's name as temporary files carry it: `LMFILM_HOST`, else
/// `HOSTNAME`, else the kernel's host name; characters other than letters, digits, `-`
/// and `.` become `_`, so `~` always separates the fields.
pub fn host_name() -> &'static str {
    static HOST: OnceLock<String> = OnceLock::new();
    HOST.get_or_init(|| {
        let raw = [HOST_VAR, "HOSTNAME"]
            .iter()
            .find_map(|v| std::env::var(v).ok().filter(|h| !h.is_empty()))
            .or_else(|| {
                fs::read_to_string("/proc/sys/kernel/hostname")
                    .ok()
                    .map(|h| h.trim().to_string())
            })
            .filter(|h| !h.is_empty())
            .unwrap_or_else(|| "localhost".into());
        raw.chars()
            .map(|c| {
                if c.is_ascii_alphanumeric() || c == '-' || c == '.' {
                    c
                } else {
                    '_'
                }
            })
            .collect()
    })
}

/// A fresh temporary name beside `path`: `NAME.~HOST~PID~N.tmp`. Host,
/// pid and a counter keep concurrent writers of one path apart.
pub fn temp_path(path: &Path) -> io::Result<PathBuf> {
    let name = path.file_name().ok_or_else(|| {
        io::Error::new(
            io::ErrorKind::InvalidInput,
            format!("cannot write {}: not a file path", path.display()),
        )
    })?;
    let mut tmp_name = name.to_os_string();
    tmp_name.push(format!(
        ".~{}~{}~{}.tmp",
        host_name(),
        std::process::id(),
        TEMP_COUNTER.fetch_add(1, Ordering::Relaxed)
    ));
    Ok(path.with_file_name(tmp_name))
}

/// Writes `bytes` to a temporary file beside `path` (a rename across file
/// systems is not atomic), then renames it over `path`. Errors name the
/// file.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> io::Result<()> {
    let tmp = temp_path(path)?;
    let result = fs::File::create(&tmp)
        .and_then(|mut f| f.write_all(bytes))
        .and_then(|()| fs::rename(&tmp, path));
    result.map_err(|e| {
        let _ = fs::remove_file(&tmp);
        io::Error::new(e.kind(), format!("cannot write {}: {e}", path.display()))
    })
}

/// The (host, pid) of a temporary file's name, if it is one of ours.
pub fn temp_owner(name: &str) -> Option<(&str, u32)> {
    let stem = name.strip_suffix(".tmp")?;
    let mut fields = stem.rsplitn(4, '~');
    let _counter: u64 = fields.next()?.parse().ok()?;
    let pid = fields.next()?.parse().ok()?;
    let host = fields.next()?;
    fields.next()?.strip_suffix('.')?;
    Some((host, pid))
}

/// Removes the temporary files that writers killed in the middle left in
/// `dir`: those of this host whose process no longer runs. Another
/// host's are left alone (it may be writing right now), and so is
/// everything where processes cannot be checked (not Linux).
pub fn remove_stale_temps(dir: &Path) {
    let Ok(entries) = fs::read_dir(dir) else {
        return;
    };
    for e in entries.flatten() {
        let name = e.file_name().to_string_lossy().into_owned();
        let Some((host, pid)) = temp_owner(&name) else {
            continue;
        };
        if host == host_name() && pid != std::process::id() && !running(pid) {
            let _ = fs::remove_file(e.path());
        }
    }
}

/// Whether process `pid` runs on this machine (Linux: /proc); elsewhere
/// assumed so, which keeps every file.
fn running(pid: u32) -> bool {
    if cfg!(target_os = "linux") {
        Path::new("/proc").join(pid.to_string()).exists()
    } else {
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn temp_names_carry_host_and_pid() {
        assert_eq!(
            temp_owner("lmfilm.0001.png.~node-7.farm~4242~3.tmp"),
            Some(("node-7.farm", 4242))
        );
        assert_eq!(temp_owner("a~b.json.~h~1~0.tmp"), Some(("h", 1)));
        assert_eq!(temp_owner("lmfilm.0001.png.4242.3.tmp"), None);
        assert_eq!(temp_owner("x.~h~pid~0.tmp"), None);
    }

    #[test]
    fn another_hosts_temporary_is_kept() {
        let dir = std::env::temp_dir().join(format!("lmfilm-atomic-{}", std::process::id()));
        fs::create_dir_all(&dir).unwrap();
        // pid 0 never names a user process: dead on this host.
        let mine = dir.join(format!("f.png.~{}~0~0.tmp", host_name()));
        let theirs = dir.join("f.png.~some-other-host~0~0.tmp");
        fs::write(&mine, b"x").unwrap();
        fs::write(&theirs, b"x").unwrap();
        remove_stale_temps(&dir);
        assert!(!mine.exists() && theirs.exists());
        let _ = fs::remove_dir_all(&dir);
    }
}
