//! `lmfilm mux` (DESIGN §5): the PNG frames and the soundtrack into the
//! film's MP4 (H.264 and Opus, [`super::video`]), made in-process: no
//! ffmpeg is needed.

use std::fmt;
use std::fs;
use std::io;
use std::path::{Path, PathBuf};

use rayon::prelude::*;

use super::video::{self, Pcm, Picture, Rgb, VideoEncoder, VideoError};
use super::video_groups::EncodedGroup;
use crate::atomic::temp_path;
use crate::source::read_file;

/// Frames per second as a reduced fraction, so that 29.97 fps is exactly
/// 30000/1001 and never drifts from the soundtrack.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct FrameRate {
    pub num: u32,
    pub den: u32,
}

impl FrameRate {
    /// Frames a second.
    pub fn fps(self) -> f64 {
        f64::from(self.num) / f64::from(self.den)
    }

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
    /// A file or the output folder could not be used.
    Io { path: PathBuf, source: io::Error },
    /// A frame or the soundtrack could not be read or encoded.
    Input { path: PathBuf, why: String },
    /// The encoder or the muxer failed.
    Video(VideoError),
}

impl fmt::Display for MuxError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            MuxError::FrameRate { dt } => write!(
                f,
                "cannot make a video with a frame interval of {dt} s: Δt must be a \
                 positive number of seconds"
            ),
            MuxError::Io { path, source } => write!(f, "{}: {source}", path.display()),
            MuxError::Input { path, why } => write!(f, "{}: {why}", path.display()),
            MuxError::Video(e) => write!(f, "{e}"),
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

/// The largest soundtrack the MP4 takes: far beyond a film's.
const MAX_SOUNDTRACK_BYTES: u64 = 4 << 30;

/// What [`mux`] made: the MP4, how many of its groups of pictures were
/// encoded while the frames rendered (of how many), and what it had to
/// leave out, said.
#[derive(Debug)]
pub struct Muxed {
    pub mp4: PathBuf,
    pub groups: (usize, usize),
    pub note: Option<String>,
}

/// A frame's PNG as the mux reads it: its number, its path relative to
/// the folder, the most bytes it may have and its hash.
pub struct FramePng {
    pub frame: u64,
    pub rel: PathBuf,
    pub limit: u64,
    pub hash: String,
}

/// Encodes the PNG `frames` (in frame order) at `rate` with the
/// quantiser `qp`, and `soundtrack` (relative to `dir`, with the channels
/// of the listener's left and right ears when it has them) as Opus when
/// given, into `dir/<name>.mp4`. A group of pictures in `ready` made of
/// the same frames (numbers and PNG hashes) and size is taken as it is.
/// The video goes to a temporary name first and is renamed when
/// complete, so a killed mux never leaves a broken MP4.
pub fn mux(
    dir: &Path,
    name: &str,
    (rate, qp): (FrameRate, u8),
    frames: &[FramePng],
    ready: &[EncodedGroup],
    soundtrack: Option<(&Path, Option<[usize; 2]>)>,
) -> Result<Muxed, MuxError> {
    let fps = rate.fps();
    let size = match frames.first() {
        Some(f) => png_size(dir, &f.rel, f.limit)?,
        None => {
            return Err(MuxError::Input {
                path: dir.to_path_buf(),
                why: "the film has no frame to make a video of".into(),
            })
        }
    };
    // Each group of pictures on its own encoder, the groups in parallel
    // (a frame is read back, converted and encoded by its group's task).
    let len = video::group_len(fps);
    let taken = |group: &[FramePng]| {
        ready.iter().find(|r| {
            r.size == size
                && r.frames.len() == group.len()
                && r.frames
                    .iter()
                    .zip(group)
                    .all(|((k, h), f)| *k == f.frame && *h == f.hash)
        })
    };
    let groups: Vec<(Vec<Picture>, bool)> = frames
        .par_chunks(len)
        .map(|group| {
            if let Some(r) = taken(group) {
                return Ok((r.pictures.clone(), true));
            }
            let mut encoder =
                VideoEncoder::new(group[0].frame, size, fps, qp).map_err(MuxError::Video)?;
            for f in group {
                let image = read_png(dir, &f.rel, f.limit)?;
                let rgb = Rgb {
                    width: image.width(),
                    height: image.height(),
                    pixels: image.as_raw(),
                };
                encoder.push(&rgb).map_err(MuxError::Video)?;
            }
            Ok((encoder.finish(), false))
        })
        .collect::<Result<_, MuxError>>()?;
    let counts = (groups.iter().filter(|g| g.1).count(), groups.len());
    let pictures: Vec<Picture> = groups.into_iter().flat_map(|g| g.0).collect();
    let (sound, note) = match soundtrack {
        Some((rel, ears)) => sound_of(&dir.join(rel), ears)?,
        None => (None, None),
    };
    let packets = match &sound {
        Some(pcm) => Some(video::opus_packets(pcm).map_err(MuxError::Video)?),
        None => None,
    };
    let out = dir.join(format!("{name}.mp4"));
    let io_err = |source| MuxError::Io {
        path: out.clone(),
        source,
    };
    let tmp = temp_path(&out).map_err(io_err)?;
    let written = fs::File::create(&tmp)
        .map_err(io_err)
        .and_then(|file| {
            let sound = sound.as_ref().zip(packets.as_deref());
            let video = (&pictures[..], video::coded_size(size));
            video::write_mp4(io::BufWriter::new(file), video, (rate.num, rate.den), sound)
                .map_err(MuxError::Video)
        })
        .and_then(|()| fs::rename(&tmp, &out).map_err(io_err));
    if written.is_err() {
        let _ = fs::remove_file(&tmp);
    }
    written.map(|()| Muxed {
        mp4: out,
        groups: counts,
        note,
    })
}

/// PNG frame `rel` of `dir` (at most `limit` bytes) as 8-bit RGB.
fn read_png(dir: &Path, rel: &Path, limit: u64) -> Result<image::RgbImage, MuxError> {
    png(dir, rel, limit, |reader| {
        reader.decode().map(|i| i.into_rgb8())
    })
}

/// The size of PNG frame `rel` of `dir`, from its header alone (its
/// pixels are decoded where its group is encoded, if at all).
fn png_size(dir: &Path, rel: &Path, limit: u64) -> Result<(u32, u32), MuxError> {
    png(dir, rel, limit, |reader| reader.into_dimensions())
}

/// What `read` makes of PNG frame `rel` of `dir` (at most `limit` bytes).
fn png<T>(
    dir: &Path,
    rel: &Path,
    limit: u64,
    read: impl FnOnce(image::ImageReader<io::Cursor<Vec<u8>>>) -> image::ImageResult<T>,
) -> Result<T, MuxError> {
    let path = dir.join(rel);
    let bytes = read_file(&path, limit).map_err(|source| MuxError::Io {
        path: path.clone(),
        source,
    })?;
    let reader = image::ImageReader::with_format(io::Cursor::new(bytes), image::ImageFormat::Png);
    read(reader).map_err(|e| MuxError::Input {
        path,
        why: format!("not a PNG lmfilm can read: {e}"),
    })
}

/// The soundtrack's samples as the MP4 takes them, at a rate Opus
/// encodes (else none, and why): the listener's `ears` as left and
/// right; without ears, one or two channels as they are, of more the
/// first microphone's.
fn sound_of(
    path: &Path,
    ears: Option<[usize; 2]>,
) -> Result<(Option<Pcm>, Option<String>), MuxError> {
    let input = |why: String| MuxError::Input {
        path: path.to_path_buf(),
        why,
    };
    let bytes = read_file(path, MAX_SOUNDTRACK_BYTES).map_err(|source| MuxError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    // The rate from the header, before the samples are decoded.
    let rate = hound::WavReader::new(io::Cursor::new(&bytes))
        .map_err(|e| input(format!("not a WAV file lmfilm can read: {e}")))?
        .spec()
        .sample_rate;
    if !video::OPUS_RATES.contains(&rate) {
        return Ok((
            None,
            Some(format!(
                "the video has no sound: its soundtrack's rate, {rate} Hz, is none Opus encodes ({}); make the soundtrack at 48000 Hz (`lmfilm sound DIR --rate 48000`) and mux again",
                video::OPUS_RATES.map(|r| r.to_string()).join(", ")
            )),
        ));
    }
    let (spec, samples) = crate::sound::wav::interleaved(&bytes, |_| Ok(())).map_err(input)?;
    let channels = spec.channels.max(1);
    let width = usize::from(channels);
    if let Some([l, r]) = ears.filter(|e| e.iter().all(|&c| c < width)) {
        let stereo = samples
            .chunks_exact(width)
            .flat_map(|s| [s[l], s[r]])
            .collect();
        let note = (channels > 2).then(|| format!(
            "the video's sound is the listener's ears (channels {l} and {r}); soundtrack.wav keeps all {channels} microphones"
        ));
        return Ok((
            Some(Pcm {
                rate: spec.sample_rate,
                channels: 2,
                samples: stereo,
            }),
            note,
        ));
    }
    if channels <= 2 {
        return Ok((
            Some(Pcm {
                rate: spec.sample_rate,
                channels,
                samples,
            }),
            None,
        ));
    }
    let first: Vec<f32> = samples
        .iter()
        .step_by(usize::from(channels))
        .copied()
        .collect();
    Ok((
        Some(Pcm {
            rate: spec.sample_rate,
            channels: 1,
            samples: first,
        }),
        Some(format!(
            "the video's sound is microphone 0's: the soundtrack has {channels} channels, a channel a microphone, and soundtrack.wav keeps them all"
        )),
    ))
}
