//! Data channels (thesis 6.3.3, `NbrChannels_listOfNames`, `?50`): ASCII
//! files of sampled values that the expressions read at any time.
//!
//! A channel file is whitespace-separated text: the header — the time
//! step (a positive number) and the number of values n — then n values.
//! Value k is the channel at time k·step; between samples the value is
//! interpolated linearly, and before the first or after the last sample
//! it is that sample's (clamped). Channels are numbered by their place in
//! the declaration, from 0 (as actors, surfaces and sounds are).

use std::path::Path;

use crate::error::{Error, Result};
use crate::lsys::options::OptionItem;
use crate::lsys::Animation;
use crate::source::{read_file, Diagnostic, FileRef, Source};

/// Largest channel or trace file read (64 MiB).
pub const MAX_DATA_BYTES: u64 = 64 << 20;

/// Most values a channel may announce.
pub const MAX_VALUES: u64 = 10_000_000;

/// Largest magnitude of a value read from a data file: as in scenes.
pub const MAX_VALUE: f64 = crate::lsys::scan::MAX_NUMBER;

/// One imported data channel.
#[derive(Debug, Clone, PartialEq)]
pub struct Channel {
    /// The file as the scene names it.
    pub name: String,
    /// Time between two samples.
    pub step: f64,
    pub values: Vec<f64>,
}

impl Channel {
    /// The channel at time `t`: linear between samples, clamped at both
    /// ends; a `t` that is not a number gives the first sample.
    pub fn at(&self, t: f64) -> f64 {
        let last = self.values.len() - 1;
        let u = t / self.step;
        if u.is_nan() || u <= 0.0 {
            return self.values[0];
        }
        if u >= last as f64 {
            return self.values[last];
        }
        let k = u.floor() as usize;
        let f = u - k as f64;
        let (a, b) = (self.values[k], self.values[k + 1]);
        if f == 0.0 {
            a
        } else {
            a + (b - a) * f
        }
    }
}

/// The words of a text with their byte offsets.
pub(super) fn words(text: &str) -> impl Iterator<Item = (usize, &str)> {
    text.split_ascii_whitespace()
        .map(move |w| (w.as_ptr() as usize - text.as_ptr() as usize, w))
}

/// The number `w` at byte `at` of `src`: finite, within ±[`MAX_VALUE`].
pub(super) fn number(
    src: &Source,
    at: usize,
    w: &str,
    what: &str,
) -> std::result::Result<f64, Diagnostic> {
    match w.parse::<f64>() {
        Ok(v) if v.is_finite() && v.abs() <= MAX_VALUE => Ok(v),
        Ok(_) => Err(src.error(
            at,
            format!("{what} `{w}` is not a finite number within ±{MAX_VALUE:e}"),
        )),
        Err(_) => Err(src.error(at, format!("{what}: `{w}` is not a number"))),
    }
}

/// Parses a channel file's text (see the module).
pub fn parse(src: &Source) -> std::result::Result<(f64, Vec<f64>), Diagnostic> {
    let mut w = words(&src.text);
    let end = src.text.len();
    let header = "a channel file starts with its time step and its number of values";
    let Some((at, s)) = w.next() else {
        return Err(src.error(end, format!("the file is empty; {header}")));
    };
    let step = number(src, at, s, "the time step")?;
    if step <= 0.0 {
        return Err(src.error(at, format!("the time step must be > 0, found {s}")));
    }
    let Some((at, s)) = w.next() else {
        return Err(src.error(end, format!("no number of values; {header}")));
    };
    let n = match s.parse::<u64>() {
        Ok(n) if (1..=MAX_VALUES).contains(&n) => n,
        _ => {
            return Err(src.error(
                at,
                format!(
                    "the number of values must be a whole number 1..={MAX_VALUES}, found `{s}`"
                ),
            ))
        }
    };
    let mut values = Vec::with_capacity(n.min(1 << 16) as usize);
    for (at, s) in w {
        if values.len() as u64 == n {
            return Err(src.error(at, format!("more values than the {n} the header announces")));
        }
        values.push(number(src, at, s, "a value")?);
    }
    if (values.len() as u64) < n {
        return Err(src.error(
            end,
            format!(
                "the header announces {n} values, the file has {}",
                values.len()
            ),
        ));
    }
    Ok((step, values))
}

/// Reads data file `file` named in the scene `dir`'s file: a file that
/// cannot be read is reported where the scene names it.
pub(super) fn read_source(dir: &Path, file: &FileRef, what: &str) -> Result<Source> {
    let path = dir.join(&file.name);
    let bytes = read_file(&path, MAX_DATA_BYTES)
        .map_err(|e| file.error(format!("{what} {}: cannot read: {e}", path.display())))?;
    Ok(Source::from_bytes(path.display().to_string(), bytes)?)
}

/// Reads every channel the scene declares, in declaration order (file
/// order, then list order), each relative to the folder of the file
/// that declares it.
pub fn load(anim: &Animation) -> Result<Vec<Channel>> {
    let mut channels = Vec::new();
    for ls in &anim.systems {
        let dir = Path::new(&ls.def.name).parent().unwrap_or(Path::new("."));
        for o in &ls.def.options {
            let OptionItem::Channels(files) = o else {
                continue;
            };
            for file in files {
                if channels.len() as i64 >= crate::lsys::options::MAX_CHANNELS {
                    let msg = format!(
                        "at most {} data channels (thesis 6.3.3); this is one more",
                        crate::lsys::options::MAX_CHANNELS
                    );
                    return Err(file.error(msg).into());
                }
                let src = read_source(dir, file, "channel file")?;
                let (step, values) = parse(&src).map_err(Error::from)?;
                channels.push(Channel {
                    name: file.name.clone(),
                    step,
                    values,
                });
            }
        }
    }
    Ok(channels)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn channel(text: &str) -> std::result::Result<Vec<f64>, Diagnostic> {
        parse(&Source::new("c.chan", text)).map(|(_, v)| v)
    }

    #[test]
    fn values_are_interpolated_and_clamped() {
        let c = Channel {
            name: "c".into(),
            step: 0.5,
            values: channel("0.5 3\n1 3 -1\n").unwrap(),
        };
        assert_eq!(c.at(-1.0), 1.0);
        assert_eq!(c.at(0.0), 1.0);
        assert_eq!(c.at(0.25), 2.0);
        assert_eq!(c.at(0.5), 3.0);
        assert_eq!(c.at(0.75), 1.0);
        assert_eq!(c.at(1.0), -1.0);
        assert_eq!(c.at(7.0), -1.0);
        assert_eq!(c.at(f64::NAN), 1.0);
    }

    #[test]
    fn bad_files_are_located() {
        let cases = [
            ("", 1, 1, "empty"),
            ("0 2 1 2", 1, 1, "time step must be > 0"),
            ("x 2 1 2", 1, 1, "not a number"),
            ("0.1", 1, 4, "no number of values"),
            ("0.1 2.5 1 2", 1, 5, "whole number"),
            ("0.1 0", 1, 5, "whole number"),
            ("0.1 99999999999 1", 1, 5, "whole number"),
            ("0.1 3\n1 2\n", 3, 1, "announces 3 values, the file has 2"),
            ("0.1 2\n1 nan\n", 2, 3, "finite"),
            ("0.1 2\n1 2o\n", 2, 3, "not a number"),
            ("0.1 2\n1 2 3\n", 2, 5, "more values"),
        ];
        for (text, line, column, what) in cases {
            let e = channel(text).unwrap_err();
            assert_eq!((e.line, e.column), (line, column), "{text:?}: {e}");
            assert!(e.message.contains(what), "{text:?}: {e}");
        }
    }
}
