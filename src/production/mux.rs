//! `lmfilm mux` (DESIGN §5): the PNG frames and the soundtrack into an MP4
//! (H.264 + AAC) through the `ffmpeg` executable. ffmpeg is optional: the
//! frames and the soundtrack are the film's real outputs, the MP4 is a
//! convenience, so a missing ffmpeg is a clear message, never a failed run.

use std::ffi::OsString;
use std::fmt;
use std::fs;
use std::io;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

use crate::atomic::temp_path;

/// The most lines of ffmpeg's own error output an error message keeps.
const STDERR_LINES: usize = 20;

/// Frames per second as ffmpeg wants it: a reduced fraction, so that
/// 29.97 fps is exactly 30000/1001 and never drifts from the soundtrack.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct FrameRate {
    pub num: u32,
    pub den: u32,
}

impl FrameRate {
    /// 1/Δt as the simplest fraction with a denominator up to 1001 that
    /// matches to floating-point rounding (25/1 for 0.04, 30000/1001 for
    /// 0.033366…), else the nearest multiple of 1/1000 (24/1 for a Δt
    /// typed as 0.0416667).
    pub fn from_dt(dt: f64) -> Result<FrameRate, MuxError> {
        if !(dt.is_finite() && dt > 0.0) {
            return Err(MuxError::FrameRate { dt });
        }
        let fps = 1.0 / dt;
        let (num, den) = (1..=1001u32)
            .map(|den| ((f64::from(den) * fps).round(), den))
            .find(|&(num, den)| (num - f64::from(den) * fps).abs() <= 1e-9 * num)
            .unwrap_or(((1000.0 * fps).round(), 1000));
        if !(1.0..=f64::from(u32::MAX)).contains(&num) {
            return Err(MuxError::FrameRate { dt });
        }
        let num = num as u32;
        let g = gcd(num, den);
        Ok(FrameRate {
            num: num / g,
            den: den / g,
        })
    }
}

impl fmt::Display for FrameRate {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}/{}", self.num, self.den)
    }
}

fn gcd(a: u32, b: u32) -> u32 {
    if b == 0 {
        a
    } else {
        gcd(b, a % b)
    }
}

/// Why no MP4 was made.
#[derive(Debug)]
pub enum MuxError {
    /// Δt gives no usable frame rate.
    FrameRate { dt: f64 },
    /// No `ffmpeg` on the PATH.
    FfmpegMissing { dir: PathBuf },
    /// A file or the output folder could not be used.
    Io { path: PathBuf, source: io::Error },
    /// ffmpeg ran and failed; `stderr` holds the end of its messages.
    Ffmpeg { status: String, stderr: String },
}

impl fmt::Display for MuxError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            MuxError::FrameRate { dt } => write!(
                f,
                "cannot make a video with a frame interval of {dt} s: Δt must be a \
                 positive number of seconds"
            ),
            MuxError::FfmpegMissing { dir } => write!(
                f,
                "ffmpeg is not installed, so no MP4 was made; the frames and the \
                 soundtrack are already in {dir}. Install ffmpeg (e.g. `apt-get install \
                 ffmpeg`) and run `lmfilm mux {dir}`",
                dir = dir.display()
            ),
            MuxError::Io { path, source } => write!(f, "{}: {source}", path.display()),
            MuxError::Ffmpeg { status, stderr } => {
                write!(f, "ffmpeg failed ({status}):\n{stderr}")
            }
        }
    }
}

impl std::error::Error for MuxError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            MuxError::Io { source, .. } => Some(source),
            _ => None,
        }
    }
}

/// Whether an `ffmpeg` executable runs.
pub fn ffmpeg_available() -> bool {
    Command::new("ffmpeg")
        .arg("-version")
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .status()
        .is_ok_and(|s| s.success())
}

/// Encodes `dir/frames` (an ffmpeg image pattern relative to `dir`, e.g.
/// `frames/film.%04d.png`, numbered from 0) at `rate`, with `soundtrack`
/// (relative to `dir` or absolute) as AAC when given, into
/// `dir/<name>.mp4`. The video goes to a temporary name first and is
/// renamed when complete, so a killed mux never leaves a broken MP4.
pub fn mux(
    dir: &Path,
    name: &str,
    rate: FrameRate,
    frames: &str,
    soundtrack: Option<&Path>,
) -> Result<PathBuf, MuxError> {
    for path in std::iter::once(dir.to_path_buf()).chain(soundtrack.map(|s| dir.join(s))) {
        fs::metadata(&path).map_err(|source| MuxError::Io { path, source })?;
    }
    let out = dir.join(format!("{name}.mp4"));
    let tmp = temp_path(&out).map_err(|source| MuxError::Io {
        path: out.clone(),
        source,
    })?;
    let tmp_name = tmp.file_name().unwrap_or_default().to_string_lossy();
    let result = run_ffmpeg(dir, &ffmpeg_args(rate, frames, soundtrack, &tmp_name));
    let result = result.and_then(|()| {
        fs::rename(&tmp, &out).map_err(|source| MuxError::Io {
            path: out.clone(),
            source,
        })
    });
    if result.is_err() {
        let _ = fs::remove_file(&tmp);
    }
    result.map(|()| out)
}

/// The ffmpeg command line. `bitexact` and no metadata keep encoder
/// versions and dates out of the file; odd frame sizes are padded by one
/// pixel because yuv420p needs even ones.
fn ffmpeg_args(
    rate: FrameRate,
    frames: &str,
    soundtrack: Option<&Path>,
    out: &str,
) -> Vec<OsString> {
    let rate = rate.to_string();
    let mut args = os(&["-hide_banner", "-nostdin", "-loglevel", "error", "-y"]);
    args.extend(os(&["-framerate", &rate, "-i", frames]));
    if let Some(sound) = soundtrack {
        args.extend([OsString::from("-i"), sound.as_os_str().to_owned()]);
    }
    args.extend(os(&[
        "-map",
        "0:v:0",
        "-vf",
        "pad=ceil(iw/2)*2:ceil(ih/2)*2",
    ]));
    args.extend(os(&["-c:v", "libx264", "-pix_fmt", "yuv420p"]));
    if soundtrack.is_some() {
        args.extend(os(&["-map", "1:a:0", "-c:a", "aac"]));
    }
    args.extend(os(&["-map_metadata", "-1", "-fflags", "+bitexact"]));
    args.extend(os(&["-flags:v", "+bitexact", "-flags:a", "+bitexact"]));
    args.extend(os(&["-movflags", "+faststart", "-f", "mp4", out]));
    args
}

fn os(items: &[&str]) -> Vec<OsString> {
    items.iter().map(OsString::from).collect()
}

/// Runs ffmpeg in `dir`; a missing executable and a failed encode are
/// told apart.
fn run_ffmpeg(dir: &Path, args: &[OsString]) -> Result<(), MuxError> {
    let output = Command::new("ffmpeg")
        .current_dir(dir)
        .args(args)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .output()
        .map_err(|source| match source.kind() {
            io::ErrorKind::NotFound => MuxError::FfmpegMissing {
                dir: dir.to_path_buf(),
            },
            _ => MuxError::Io {
                path: PathBuf::from("ffmpeg"),
                source,
            },
        })?;
    if output.status.success() {
        return Ok(());
    }
    let stderr = String::from_utf8_lossy(&output.stderr);
    let lines: Vec<&str> = stderr.lines().collect();
    Err(MuxError::Ffmpeg {
        status: output.status.to_string(),
        stderr: lines[lines.len().saturating_sub(STDERR_LINES)..].join("\n"),
    })
}
