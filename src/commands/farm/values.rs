//! The values `farm slurm` writes into its job scripts, each read as the
//! one value it must be (issue 53): Slurm names of a few plain
//! characters, a wall time and a memory size parsed and written back in
//! Slurm's own form, paths that bash and `sbatch` read back exactly.
//! Whatever else a user types is refused here, naming the option and
//! the character, before any script is written.

use std::path::Path;
use std::str::FromStr;

/// What a character is, as a person reads it in an error.
fn describe(c: char) -> String {
    let name = match c {
        ' ' => "a space",
        '\n' => "a line break",
        '\r' => "a carriage return",
        '\t' => "a tab",
        '"' => "a double quote",
        '\'' => "a single quote",
        '\\' => "a backslash",
        '$' => "a dollar sign",
        '`' => "a backquote",
        ';' => "a semicolon",
        '#' => "a hash",
        '%' => "a percent sign",
        _ if c.is_control() => "a control character",
        _ => "",
    };
    let code = format!("U+{:04X}", c as u32);
    match name {
        "" => format!("'{c}' ({code})"),
        n => format!("{n} ({code})"),
    }
}

/// The first character of `text` that `allowed` refuses, and where.
fn first_refused(text: &str, allowed: impl Fn(char) -> bool) -> Option<(usize, char)> {
    text.chars()
        .enumerate()
        .find(|&(_, c)| !allowed(c))
        .map(|(i, c)| (i + 1, c))
}

/// A Slurm partition (or a comma-separated list of them) or account:
/// letters, digits, `_`, `.` and `-` only, at most 64 characters each.
#[derive(Debug, Clone, PartialEq)]
pub struct SlurmName(String);

impl SlurmName {
    fn parse(text: &str, list: bool) -> Result<SlurmName, String> {
        let plain = |c: char| c.is_ascii_alphanumeric() || matches!(c, '_' | '.' | '-');
        let what = if list {
            "a Slurm partition name (or names separated by commas)"
        } else {
            "a Slurm account name"
        };
        if let Some((at, c)) = first_refused(text, |c| plain(c) || (list && c == ',')) {
            return Err(format!(
                "{:?} has {} at character {at}; {what} has only letters, digits, '_', '.' and '-'",
                text,
                describe(c)
            ));
        }
        let names: Vec<&str> = text.split(',').collect();
        if names.iter().any(|n| n.is_empty() || n.starts_with('-')) {
            return Err(format!(
                "{text:?} is not {what}: each name is non-empty and does not start with '-'"
            ));
        }
        if names.iter().any(|n| n.len() > 64) {
            return Err(format!("{text:?} is longer than 64 characters a name"));
        }
        Ok(SlurmName(text.to_string()))
    }

    pub fn as_str(&self) -> &str {
        &self.0
    }
}

/// `--partition`: one name or several separated by commas.
pub fn partition(text: &str) -> Result<SlurmName, String> {
    SlurmName::parse(text, true)
}

/// `--account`: one name.
pub fn account(text: &str) -> Result<SlurmName, String> {
    SlurmName::parse(text, false)
}

/// A job's wall-time limit in seconds, or none (Slurm's `UNLIMITED`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WallTime(pub Option<u64>);

/// The largest limit accepted: a year (Slurm's own cap is far larger,
/// but a farm job of more than a year is a typing error).
const MAX_WALL_TIME: u64 = 366 * 86_400;

impl FromStr for WallTime {
    type Err = String;

    /// Slurm's forms: `M`, `M:S`, `H:M:S`, `D-H`, `D-H:M`, `D-H:M:S`,
    /// and `UNLIMITED` or `INFINITE`.
    fn from_str(text: &str) -> Result<WallTime, String> {
        let form = "Slurm's forms are MINUTES, MINUTES:SECONDS, HOURS:MINUTES:SECONDS, \
                    DAYS-HOURS, DAYS-HOURS:MINUTES or DAYS-HOURS:MINUTES:SECONDS (or UNLIMITED)";
        if let Some((at, c)) =
            first_refused(text, |c| c.is_ascii_alphanumeric() || c == ':' || c == '-')
        {
            return Err(format!(
                "{text:?} has {} at character {at}; {form}",
                describe(c)
            ));
        }
        if text.eq_ignore_ascii_case("unlimited") || text.eq_ignore_ascii_case("infinite") {
            return Ok(WallTime(None));
        }
        let bad = || format!("{text:?} is not a wall time; {form}");
        let number = |s: &str| -> Result<u64, String> {
            if s.is_empty() || s.len() > 9 || !s.bytes().all(|b| b.is_ascii_digit()) {
                return Err(bad());
            }
            s.parse().map_err(|_| bad())
        };
        let (days, rest) = match text.split_once('-') {
            Some((d, r)) => (Some(number(d)?), r),
            None => (None, text),
        };
        let parts = rest
            .split(':')
            .map(number)
            .collect::<Result<Vec<u64>, String>>()?;
        let secs = match (days, parts.as_slice()) {
            (None, [m]) => m * 60,
            (None, [m, s]) => m * 60 + s,
            (None, [h, m, s]) => h * 3600 + m * 60 + s,
            (Some(d), [h]) => d * 86_400 + h * 3600,
            (Some(d), [h, m]) => d * 86_400 + h * 3600 + m * 60,
            (Some(d), [h, m, s]) => d * 86_400 + h * 3600 + m * 60 + s,
            _ => return Err(bad()),
        };
        if secs == 0 || secs > MAX_WALL_TIME {
            return Err(format!(
                "{text:?} is not a wall time between 1 second and 366 days"
            ));
        }
        Ok(WallTime(Some(secs)))
    }
}

impl std::fmt::Display for WallTime {
    /// Slurm's `D-HH:MM:SS`, or `UNLIMITED`.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self.0 {
            None => write!(f, "UNLIMITED"),
            Some(s) => write!(
                f,
                "{}-{:02}:{:02}:{:02}",
                s / 86_400,
                s % 86_400 / 3600,
                s % 3600 / 60,
                s % 60
            ),
        }
    }
}

/// A job's memory: a whole number of mebibytes, as Slurm's `--mem`
/// reads `500M`, `4G`, `1T` or a bare number of megabytes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Memory(pub u64);

impl FromStr for Memory {
    type Err = String;

    fn from_str(text: &str) -> Result<Memory, String> {
        let form = "memory is a whole number with an optional unit K, M, G or T (500M, 4G)";
        if let Some((at, c)) = first_refused(text, |c| c.is_ascii_alphanumeric()) {
            return Err(format!(
                "{text:?} has {} at character {at}; {form}",
                describe(c)
            ));
        }
        let digits = text.trim_end_matches(|c: char| c.is_ascii_alphabetic());
        let unit = &text[digits.len()..];
        let scale_kib: u64 = match unit.to_ascii_uppercase().as_str() {
            "K" => 1,
            "" | "M" => 1 << 10,
            "G" => 1 << 20,
            "T" => 1 << 30,
            _ => return Err(format!("{text:?}: unknown unit {unit:?}; {form}")),
        };
        let n: u64 = (!digits.is_empty() && digits.len() <= 12)
            .then(|| digits.parse().ok())
            .flatten()
            .ok_or_else(|| format!("{text:?} is not a memory size; {form}"))?;
        let mib = (n * scale_kib).div_ceil(1 << 10);
        if mib == 0 || mib > 1 << 30 {
            return Err(format!("{text:?} is not between 1 MiB and 1 PiB"));
        }
        Ok(Memory(mib))
    }
}

impl std::fmt::Display for Memory {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}M", self.0)
    }
}

/// A path the scripts hold: UTF-8 (it is written as text) and without
/// control characters (a line break would end a script's line). `what`
/// names the option for the error.
pub fn script_path(path: &Path, what: &str) -> Result<String, String> {
    let text = path.to_str().ok_or_else(|| {
        format!(
            "{what}: {} is not UTF-8; the job scripts hold it as text, so choose a path in UTF-8",
            path.display()
        )
    })?;
    if let Some((at, c)) = first_refused(text, |c| !c.is_control()) {
        return Err(format!(
            "{what}: {text:?} has {} at character {at}; the job scripts cannot hold it",
            describe(c)
        ));
    }
    Ok(text.to_string())
}

/// The film folder, which `#SBATCH --output` holds too: a script path
/// that also has no backslash (in a Slurm file pattern it turns the
/// `%j` of the logs' names off).
pub fn folder_path(path: &Path, what: &str) -> Result<String, String> {
    let text = script_path(path, what)?;
    if let Some(at) = text.find('\\') {
        return Err(format!(
            "{what}: {text:?} has {} at byte {}; Slurm's log names cannot hold it",
            describe('\\'),
            at + 1
        ));
    }
    Ok(text)
}

/// `s` quoted for bash: one word whatever it holds.
pub fn shell_quote(s: &str) -> String {
    format!("'{}'", s.replace('\'', r"'\''"))
}

/// A log file's pattern quoted for an `#SBATCH` line: `sbatch` splits
/// those lines at blanks outside double quotes, takes `\"` and `\\` as
/// the characters, and Slurm's file pattern takes `%%` as one `%`.
/// `pattern` is the folder (refused by [`folder_path`] when it holds a
/// backslash or a control character) joined with a name holding Slurm's
/// own `%j`, `%A` or `%a`.
pub fn sbatch_log(folder: &str, name: &str) -> String {
    let folder = folder.replace('%', "%%").replace('"', "\\\"");
    format!("\"{folder}/{name}\"")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_are_plain_or_refused_naming_the_character() {
        assert_eq!(partition("render,gpu-2").unwrap().as_str(), "render,gpu-2");
        let e = partition("debug --export=LD_PRELOAD=x").unwrap_err();
        assert!(e.contains("a space (U+0020) at character 6"), "{e}");
        assert!(account("a,b").unwrap_err().contains("','"));
        assert!(partition("-x").is_err() && partition("a,,b").is_err() && partition("").is_err());
        assert!(account("x\ny").unwrap_err().contains("a line break"));
    }

    #[test]
    fn wall_times_read_as_slurm_reads_them() {
        let t = |s: &str| s.parse::<WallTime>().map(|w| w.to_string());
        assert_eq!(t("90").unwrap(), "0-01:30:00");
        assert_eq!(t("5:30").unwrap(), "0-00:05:30");
        assert_eq!(t("02:00:00").unwrap(), "0-02:00:00");
        assert_eq!(t("1-12").unwrap(), "1-12:00:00");
        assert_eq!(t("1-2:3").unwrap(), "1-02:03:00");
        assert_eq!(t("1-2:3:4").unwrap(), "1-02:03:04");
        assert_eq!(t("unlimited").unwrap(), "UNLIMITED");
        for bad in [
            "",
            "1:2:3:4",
            "1-",
            "-1",
            "a",
            "1 -2",
            "0",
            "400-0",
            "1--2",
            "99999999999",
        ] {
            assert!(t(bad).is_err(), "{bad}");
        }
        assert!(t("1;id").unwrap_err().contains("a semicolon"));
    }

    #[test]
    fn memory_reads_as_slurm_reads_it() {
        let m = |s: &str| s.parse::<Memory>().map(|m| m.0);
        assert_eq!(m("500M"), Ok(500));
        assert_eq!(m("4G"), Ok(4096));
        assert_eq!(m("1t"), Ok(1 << 20));
        assert_eq!(m("1536"), Ok(1536));
        assert_eq!(m("100K"), Ok(1));
        for bad in ["", "G", "4GB", "4 G", "-4G", "4.5G", "0", "9999999999999G"] {
            assert!(m(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn paths_are_text_without_control_characters() {
        assert!(script_path(Path::new("/a b/it's $(x)"), "-o").is_ok());
        let e = script_path(Path::new("/a\nb"), "-o").unwrap_err();
        assert!(e.starts_with("-o: ") && e.contains("a line break"), "{e}");
        assert!(folder_path(Path::new("/a\\b"), "-o")
            .unwrap_err()
            .contains("backslash"));
        use std::os::unix::ffi::OsStrExt;
        let raw = std::ffi::OsStr::from_bytes(b"/a\xffb");
        assert!(script_path(Path::new(raw), "--lmfilm")
            .unwrap_err()
            .contains("UTF-8"));
        assert_eq!(
            sbatch_log("/f \"1\" 100%", "x-%j.out"),
            r#""/f \"1\" 100%%/x-%j.out""#
        );
        assert_eq!(shell_quote("it's"), r"'it'\''s'");
    }
}
