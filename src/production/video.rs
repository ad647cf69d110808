//! The film's video, made by lmfilm itself (issue 56): the sRGB frames
//! as H.264 (Cisco's OpenH264, built from its bundled source), the
//! soundtrack as Opus (opus-rs, in Rust), in an MP4 (muxide, in Rust)
//! that browsers and players open. No ffmpeg is needed. The pictures go
//! in groups of about a second ([`group_len`]), each opened by a key
//! frame and encoded by an encoder of its own: the groups are encoded in
//! parallel, and a group's bytes are a function of its frames alone (one
//! encoder thread, a constant quantiser, no clock), so the same frames
//! and soundtrack give the same bytes for any thread count. docs/film.md
//! says why these codecs.

use std::io::Write;

use muxide::api::{AudioCodec, MuxerBuilder, VideoCodec};
use openh264::encoder::{
    Complexity, Encoder, EncoderConfig, FrameRate as H264Rate, FrameType, IntraFramePeriod,
    Profile, QpRange, RateControlMode, UsageType, VuiConfig,
};
use openh264::formats::YUVBuffer;
use openh264::OpenH264API;

/// The quantiser of the default video: the decoded luma of the built-in
/// film is 43.8 dB PSNR from its PNG frames (40 dB at 24), at 3.3 Mbit/s
/// for 480×270 at 25 frames a second (docs/film.md).
pub const DEFAULT_QP: u8 = 20;

/// OpenH264's smallest picture side: a smaller frame is padded to it.
const MIN_SIDE: usize = 16;

/// Opus's frame: 20 ms, 960 samples at 48 kHz.
const OPUS_FRAME_SECONDS: f64 = 0.02;

/// Opus bit rate per channel: transparent for music at 48 kHz.
const OPUS_BITS_PER_CHANNEL: i32 = 96_000;

/// The sample rates Opus encodes.
pub const OPUS_RATES: [u32; 5] = [8_000, 12_000, 16_000, 24_000, 48_000];

/// An image of 8-bit sRGB pixels, row after row.
pub struct Rgb<'a> {
    pub width: u32,
    pub height: u32,
    pub pixels: &'a [u8],
}

/// A soundtrack's samples, interleaved, in [-1, 1].
pub struct Pcm {
    pub rate: u32,
    pub channels: u16,
    pub samples: Vec<f32>,
}

/// One Opus packet of the soundtrack and its time, seconds.
pub struct OpusPacket {
    pub time: f64,
    pub bytes: Vec<u8>,
}

/// Why a video could not be made.
#[derive(Debug)]
pub enum VideoError {
    /// A frame of another size than the first.
    Size {
        frame: u64,
        got: (u32, u32),
        want: (u32, u32),
    },
    /// The soundtrack cannot go into the MP4 as it is.
    Sound(String),
    /// The encoder or the muxer refused (their message).
    Codec(String),
    Io(std::io::Error),
}

impl std::fmt::Display for VideoError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            VideoError::Size { frame, got, want } => write!(
                f,
                "frame {frame} is {}×{}, the film's first frame {}×{}: one video has one size",
                got.0, got.1, want.0, want.1
            ),
            VideoError::Sound(e) => write!(f, "the soundtrack: {e}"),
            VideoError::Codec(e) => write!(f, "the video encoder: {e}"),
            VideoError::Io(e) => write!(f, "{e}"),
        }
    }
}

impl std::error::Error for VideoError {}

/// One encoded picture: its Annex B bytes, and whether it is a key frame.
#[derive(Clone)]
pub struct Picture {
    pub bits: Vec<u8>,
    pub key: bool,
}

/// Frames in a group of pictures: a second's, rounded (a player seeks
/// to the key frame that opens each).
pub fn group_len(fps: f64) -> usize {
    fps.round().max(1.0) as usize
}

/// The size the encoder takes for frames of `size`: even, at least
/// [`MIN_SIDE`] (a frame is padded, its last row or column repeated).
pub fn coded_size(size: (u32, u32)) -> (usize, usize) {
    let side = |n: u32| (n as usize).next_multiple_of(2).max(MIN_SIDE);
    (side(size.0), side(size.1))
}

/// One group of pictures into H.264, a frame at a time, in frame order.
pub struct VideoEncoder {
    encoder: Encoder,
    size: (u32, u32),
    coded: (usize, usize),
    first: u64,
    encoded: Vec<Picture>,
}

impl VideoEncoder {
    /// An encoder for the group that starts at frame `first`, of frames of
    /// `size` at `fps` frames a second, with the constant quantiser `qp`
    /// (0 best … 51 smallest).
    pub fn new(first: u64, size: (u32, u32), fps: f64, qp: u8) -> Result<VideoEncoder, VideoError> {
        let qp = qp.min(51);
        let config = EncoderConfig::new()
            // The quality mode with the quantiser pinned: a constant QP,
            // no rate control that depends on anything but the frames (the
            // bit rate is a ceiling no frame of a film reaches).
            .rate_control_mode(RateControlMode::Quality)
            .bitrate(openh264::encoder::BitRate::from_bps(50_000_000))
            .qp(QpRange::new(qp, qp))
            .usage_type(UsageType::CameraVideoRealTime)
            .complexity(Complexity::High)
            .skip_frames(false)
            .scene_change_detect(false)
            .background_detection(false)
            .adaptive_quantization(false)
            // The group's one key frame, its first.
            .intra_frame_period(IntraFramePeriod::from_num_frames(group_len(fps) as u32))
            .max_frame_rate(H264Rate::from_hz(fps as f32))
            .profile(Profile::Baseline)
            .num_threads(1)
            .vui(VuiConfig::bt709());
        let mut encoder = Encoder::with_api_config(OpenH264API::from_source(), config)
            .map_err(|e| VideoError::Codec(e.to_string()))?;
        // Quiet before it initialises: it warns on stderr that a pinned
        // quantiser leaves the bit rate uncontrolled, which is the point.
        let mut quiet = openh264_sys2::WELS_LOG_QUIET;
        // SAFETY: the trace level is an option OpenH264 takes before its
        // initialisation; it only reads the integer it is given.
        unsafe {
            encoder.raw_api().set_option(
                openh264_sys2::ENCODER_OPTION_TRACE_LEVEL,
                (&raw mut quiet).cast(),
            );
        }
        Ok(VideoEncoder {
            encoder,
            size,
            coded: coded_size(size),
            first,
            encoded: Vec::new(),
        })
    }

    /// Encodes the next frame.
    pub fn push(&mut self, frame: &Rgb) -> Result<(), VideoError> {
        if (frame.width, frame.height) != self.size {
            return Err(VideoError::Size {
                frame: self.first + self.encoded.len() as u64,
                got: (frame.width, frame.height),
                want: self.size,
            });
        }
        let buffer = YUVBuffer::from_vec(bt709(frame, self.coded), self.coded.0, self.coded.1);
        let bits = self
            .encoder
            .encode(&buffer)
            .map_err(|e| VideoError::Codec(e.to_string()))?;
        let key = matches!(bits.frame_type(), FrameType::IDR | FrameType::I);
        self.encoded.push(Picture {
            bits: bits.to_vec(),
            key,
        });
        Ok(())
    }

    /// The group's pictures, in frame order.
    pub fn finish(self) -> Vec<Picture> {
        self.encoded
    }
}

/// sRGB `frame` as BT.709 limited-range Y′CbCr 4:2:0 (I420) of the even
/// size `coded`: luma from each pixel, chroma from the mean of each 2×2
/// block (of its gamma-encoded values, as cameras and ffmpeg do).
pub fn bt709(frame: &Rgb, coded: (usize, usize)) -> Vec<u8> {
    let (w, h) = coded;
    let (fw, fh) = (frame.width as usize, frame.height as usize);
    let mut out = vec![0u8; w * h * 3 / 2];
    let px = |x: usize, y: usize| {
        let k = 3 * (y.min(fh - 1) * fw + x.min(fw - 1));
        let p = &frame.pixels[k..k + 3];
        [f32::from(p[0]), f32::from(p[1]), f32::from(p[2])]
    };
    let luma = |[r, g, b]: [f32; 3]| 0.2126 * r + 0.7152 * g + 0.0722 * b;
    let (y_plane, chroma) = out.split_at_mut(w * h);
    let (u_plane, v_plane) = chroma.split_at_mut(w * h / 4);
    // `(v + 0.5) as u8` is `v.round()` for these values (in [0, 256),
    // where adding a half is exact), without a call to `roundf`.
    for y in 0..h {
        for x in 0..w {
            let v = 16.0 + luma(px(x, y)) * (219.0 / 255.0);
            y_plane[y * w + x] = (v + 0.5) as u8;
        }
    }
    for y in 0..h / 2 {
        for x in 0..w / 2 {
            let mut m = [0.0f32; 3];
            for (dx, dy) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                let p = px(2 * x + dx, 2 * y + dy);
                for c in 0..3 {
                    m[c] += p[c] * 0.25;
                }
            }
            let l = luma(m);
            let cb = 128.0 + (m[2] - l) / 1.8556 * (224.0 / 255.0);
            let cr = 128.0 + (m[0] - l) / 1.5748 * (224.0 / 255.0);
            // Clamped, then truncated: `round().clamp(16, 240)`.
            u_plane[y * (w / 2) + x] = (cb + 0.5).clamp(16.0, 240.0) as u8;
            v_plane[y * (w / 2) + x] = (cr + 0.5).clamp(16.0, 240.0) as u8;
        }
    }
    out
}

/// The soundtrack as Opus packets of 20 ms, each with its time: one or
/// two channels at a rate Opus takes ([`OPUS_RATES`]).
pub fn opus_packets(pcm: &Pcm) -> Result<Vec<OpusPacket>, VideoError> {
    use opus_rs::{Application, OpusEncoder};
    let channels = usize::from(pcm.channels);
    let mut encoder = OpusEncoder::new(pcm.rate as i32, channels, Application::Audio)
        .map_err(|e| VideoError::Sound(format!("Opus cannot encode it: {e}")))?;
    encoder.bitrate_bps = OPUS_BITS_PER_CHANNEL * channels as i32;
    encoder.complexity = 10;
    let frame = (f64::from(pcm.rate) * OPUS_FRAME_SECONDS).round() as usize;
    let mut packets = Vec::new();
    let mut input = vec![0.0f32; frame * channels];
    let mut out = vec![0u8; 4000];
    // The last packet is completed with silence.
    for (k, chunk) in pcm.samples.chunks(frame * channels).enumerate() {
        input.fill(0.0);
        input[..chunk.len()].copy_from_slice(chunk);
        let n = encoder
            .encode(&input, frame, &mut out)
            .map_err(|e| VideoError::Sound(format!("Opus: {e}")))?;
        packets.push(OpusPacket {
            time: k as f64 * OPUS_FRAME_SECONDS,
            bytes: out[..n].to_vec(),
        });
    }
    Ok(packets)
}

/// What an MP4 holds, as a player reads its index.
#[derive(Debug, Clone, PartialEq)]
pub struct Shape {
    /// Pictures in its video track.
    pub pictures: u32,
    /// Its video track's duration, seconds.
    pub seconds: f64,
    /// Its sound track's duration, seconds, when it has one.
    pub sound_seconds: Option<f64>,
}

/// The MP4 at `path` read back by the `mp4` crate (an index reader that
/// is not the muxer that wrote it): its video track's pictures and
/// duration, its sound track's duration.
pub fn shape(path: &std::path::Path) -> Result<Shape, String> {
    let file = std::fs::File::open(path).map_err(|e| e.to_string())?;
    let size = file.metadata().map_err(|e| e.to_string())?.len();
    let reader = mp4::Mp4Reader::read_header(std::io::BufReader::new(file), size)
        .map_err(|e| format!("not an MP4 a player can read: {e}"))?;
    let track = |kind: mp4::TrackType| {
        let mut tracks = reader.tracks().values();
        tracks.find(|t| t.track_type().ok() == Some(kind))
    };
    let video = track(mp4::TrackType::Video).ok_or("no video track")?;
    Ok(Shape {
        pictures: video.sample_count(),
        seconds: video.duration().as_secs_f64(),
        sound_seconds: track(mp4::TrackType::Audio).map(|t| t.duration().as_secs_f64()),
    })
}

/// An Opus packet's length in the MP4, seconds.
const OPUS_PACKET: f64 = 0.02;

/// Whether the MP4 at `path` is a film of `frames` frames every `dt`
/// seconds as a player reads it: a picture for each frame, the film's
/// duration (within half a frame), and a sound track, if any, as long
/// (its last 20 ms packet may run past the end); else what is wrong.
pub fn check_shape(path: &std::path::Path, frames: u64, dt: f64) -> Result<(), String> {
    let shape = shape(path)?;
    let seconds = frames as f64 * dt;
    let half = 0.5 * dt;
    if u64::from(shape.pictures) != frames {
        return Err(format!(
            "holds {} pictures, the film {frames} frames",
            shape.pictures
        ));
    }
    if (shape.seconds - seconds).abs() > half {
        return Err(format!(
            "lasts {:.3} s, the film {seconds:.3} s",
            shape.seconds
        ));
    }
    match shape.sound_seconds {
        Some(s) if s < seconds - half || s > seconds + OPUS_PACKET + half => {
            Err(format!("its sound lasts {s:.3} s, the film {seconds:.3} s"))
        }
        _ => Ok(()),
    }
}

/// The MP4: the `pictures` of `coded` size at `rate` (`num`/`den` frames
/// a second), and the soundtrack's packets when given, written to `out`
/// with the index first (a browser plays it while it loads).
pub fn write_mp4<W: Write>(
    out: W,
    (pictures, coded): (&[Picture], (usize, usize)),
    (num, den): (u32, u32),
    sound: Option<(&Pcm, &[OpusPacket])>,
) -> Result<(), VideoError> {
    let fps = f64::from(num) / f64::from(den);
    let codec = |e: muxide::api::MuxerError| VideoError::Codec(e.to_string());
    let mut builder = MuxerBuilder::new(out)
        .video(VideoCodec::H264, coded.0 as u32, coded.1 as u32, fps)
        .with_fast_start(true);
    if let Some((pcm, _)) = sound {
        builder = builder.audio(AudioCodec::Opus, 48_000, pcm.channels);
    }
    let mut muxer = builder.build().map_err(codec)?;
    let mut packets = sound.map_or(&[][..], |s| s.1).iter().peekable();
    let interval = f64::from(den) / f64::from(num);
    for (k, p) in pictures.iter().enumerate() {
        let pts = k as f64 * interval;
        muxer.write_video(pts, &p.bits, p.key).map_err(codec)?;
        // The sound up to the next frame, interleaved with the pictures.
        while let Some(p) = packets.next_if(|p| p.time < pts + interval) {
            muxer.write_audio(p.time, &p.bytes).map_err(codec)?;
        }
    }
    for p in packets {
        muxer.write_audio(p.time, &p.bytes).map_err(codec)?;
    }
    muxer.finish().map_err(codec)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The conversion's rounding without `roundf` is BT.709's formula
    /// rounded to nearest, for every colour on a grid of steps of 3 (a
    /// 2×2 block of one colour: luma and chroma of the same pixel).
    #[test]
    fn bt709_rounds_to_nearest() {
        let luma = |r: f32, g: f32, b: f32| 0.2126 * r + 0.7152 * g + 0.0722 * b;
        for r in (0..=255u8).step_by(3) {
            for g in (0..=255u8).step_by(3) {
                for b in (0..=255u8).step_by(3) {
                    let pixels = [r, g, b].repeat(4);
                    let frame = Rgb {
                        width: 2,
                        height: 2,
                        pixels: &pixels,
                    };
                    let out = bt709(&frame, (2, 2));
                    let (rf, gf, bf) = (f32::from(r), f32::from(g), f32::from(b));
                    let l = luma(rf, gf, bf);
                    let y = (16.0 + l * (219.0 / 255.0)).round() as u8;
                    let cb = 128.0 + (bf - l) / 1.8556 * (224.0 / 255.0);
                    let cr = 128.0 + (rf - l) / 1.5748 * (224.0 / 255.0);
                    let chroma = |c: f32| c.round().clamp(16.0, 240.0) as u8;
                    assert_eq!(out, [y, y, y, y, chroma(cb), chroma(cr)], "{r} {g} {b}");
                }
            }
        }
    }
}
