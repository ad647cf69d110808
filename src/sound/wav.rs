//! WAV in and out: library sounds of any rate and channel count read as
//! mono signals; the soundtrack written as 16-bit PCM or 32-bit float.

use std::io::{Cursor, Read};
use std::path::Path;

/// A mono sound: samples in [-1, 1] (float files may exceed it) at `rate` Hz.
#[derive(Debug, Clone, PartialEq)]
pub struct Signal {
    pub rate: u32,
    pub samples: Vec<f32>,
}

impl Signal {
    /// The signal at `x` samples from its start by cubic (Catmull-Rom)
    /// interpolation, zero beyond both ends. Cubic rather than the
    /// thesis's linear (eq. 2.4.6) keeps resampling and Doppler shifts
    /// clean at high frequencies.
    #[inline]
    pub fn at(&self, x: f64) -> f64 {
        let s = &self.samples;
        let i = x.floor();
        let f = x - i;
        let i = i as isize;
        let (y0, y1, y2, y3) = if i >= 1 && i + 2 < s.len() as isize {
            let i = i as usize;
            (s[i - 1], s[i], s[i + 1], s[i + 2])
        } else {
            let y = |k: isize| {
                usize::try_from(k)
                    .ok()
                    .and_then(|k| s.get(k))
                    .copied()
                    .unwrap_or(0.0)
            };
            (y(i - 1), y(i), y(i + 1), y(i + 2))
        };
        let (y0, y1, y2, y3) = (y0 as f64, y1 as f64, y2 as f64, y3 as f64);
        y1 + 0.5
            * f
            * (y2 - y0
                + f * (2.0 * y0 - 5.0 * y1 + 4.0 * y2 - y3 + f * (3.0 * (y1 - y2) + y3 - y0)))
    }

    /// Length in seconds.
    pub fn duration(&self) -> f64 {
        self.samples.len() as f64 / self.rate as f64
    }
}

/// Largest WAV file read: a bound on what a wrong path costs.
pub const MAX_WAV_BYTES: u64 = 1 << 30;

/// Largest soundtrack read back (to hash it): the most a WAV file can
/// hold, its sizes being 32-bit.
pub const MAX_SOUNDTRACK_BYTES: u64 = 4 << 30;

/// Most channels a library sound may have.
pub const MAX_CHANNELS: u16 = 64;

/// Highest sample rate of a library sound, in Hz (the soundtrack's limit).
pub const MAX_RATE: u32 = 768_000;

/// Reads a WAV file (a regular file only) as a mono signal: channels are
/// averaged.
pub fn read(path: &Path) -> Result<Signal, String> {
    let bytes = crate::source::read_file(path, MAX_WAV_BYTES)
        .map_err(|e| format!("{}: cannot read: {e}", path.display()))?;
    decode(&bytes).map_err(|e| format!("{}: {e}", path.display()))
}

/// Decodes WAV bytes (8/16/24/32-bit integer or 32-bit float PCM). The
/// header's channel count, rate and length are checked against limits and
/// against the bytes present before anything is allocated.
pub fn decode(bytes: &[u8]) -> Result<Signal, String> {
    let (spec, interleaved) = interleaved(bytes, |spec| {
        if spec.sample_rate == 0 || spec.channels == 0 {
            return Err("the WAV header has no sample rate or no channel".into());
        }
        if spec.channels > MAX_CHANNELS || spec.sample_rate > MAX_RATE {
            return Err(format!(
                "the WAV header announces {} channels at {} Hz; sounds have 1..={MAX_CHANNELS} channels at 1..={MAX_RATE} Hz",
                spec.channels, spec.sample_rate
            ));
        }
        Ok(())
    })?;
    if interleaved.iter().any(|s| !s.is_finite()) {
        return Err("the file holds samples that are not finite numbers".into());
    }
    let channels = spec.channels as usize;
    let samples = interleaved
        .chunks_exact(channels)
        .map(|frame| frame.iter().sum::<f32>() / channels as f32)
        .collect();
    Ok(Signal {
        rate: spec.sample_rate,
        samples,
    })
}

/// The samples of WAV bytes, interleaved, integers scaled to [-1, 1),
/// after `check` accepted the header and the header's length was checked
/// against the bytes present (before anything is allocated).
pub fn interleaved(
    bytes: &[u8],
    check: impl FnOnce(&hound::WavSpec) -> Result<(), String>,
) -> Result<(hound::WavSpec, Vec<f32>), String> {
    let reader =
        hound::WavReader::new(Cursor::new(bytes)).map_err(|e| format!("not a WAV file: {e}"))?;
    let spec = reader.spec();
    check(&spec)?;
    // A header that announces more samples than the bytes hold (a
    // truncated file, a damaged length) is refused before decoding.
    let announced = u64::from(reader.len()) * u64::from(spec.bits_per_sample.div_ceil(8));
    if announced > bytes.len() as u64 {
        return Err(format!(
            "the WAV header announces {} samples, more than the file's {} bytes hold (a truncated file?)",
            reader.len(),
            bytes.len()
        ));
    }
    let samples = match spec.sample_format {
        hound::SampleFormat::Float => reader.into_samples::<f32>().collect::<Result<_, _>>(),
        hound::SampleFormat::Int => {
            let scale = 1.0 / (1u64 << (spec.bits_per_sample.clamp(1, 32) - 1)) as f32;
            reader
                .into_samples::<i32>()
                .map(|s| s.map(|s| s as f32 * scale))
                .collect::<Result<_, _>>()
        }
    }
    .map_err(|e| format!("cannot decode the samples: {e}"))?;
    Ok((spec, samples))
}

/// The length in seconds of WAV bytes, from the header alone.
pub fn duration(reader: impl Read) -> Result<f64, String> {
    let reader = hound::WavReader::new(reader).map_err(|e| format!("not a WAV file: {e}"))?;
    let rate = reader.spec().sample_rate;
    if rate == 0 {
        return Err("the WAV header has no sample rate".into());
    }
    Ok(f64::from(reader.duration()) / f64::from(rate))
}

/// How the soundtrack's samples are stored.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum SampleFormat {
    /// 16-bit PCM; samples beyond [-1, 1] are clamped and counted.
    Pcm16,
    /// 32-bit IEEE float, unclamped.
    Float32,
}

impl SampleFormat {
    /// The name the command line and the records use.
    pub fn name(self) -> &'static str {
        match self {
            SampleFormat::Pcm16 => "pcm16",
            SampleFormat::Float32 => "float32",
        }
    }
}

/// The WAV bytes of equally long channels, interleaved, and the number of
/// samples clamped (always 0 for float).
pub fn encode(
    channels: &[Vec<f32>],
    rate: u32,
    format: SampleFormat,
) -> Result<(Vec<u8>, u64), String> {
    let n_channels = u16::try_from(channels.len())
        .ok()
        .filter(|&c| c > 0)
        .ok_or_else(|| {
            format!(
                "a WAV file holds 1 to 65535 channels, not {}",
                channels.len()
            )
        })?;
    let len = channels[0].len();
    let spec = hound::WavSpec {
        channels: n_channels,
        sample_rate: rate,
        bits_per_sample: if format == SampleFormat::Pcm16 {
            16
        } else {
            32
        },
        sample_format: match format {
            SampleFormat::Pcm16 => hound::SampleFormat::Int,
            SampleFormat::Float32 => hound::SampleFormat::Float,
        },
    };
    let mut bytes =
        Vec::with_capacity(44 + len * channels.len() * spec.bits_per_sample as usize / 8);
    let mut clipped = 0u64;
    let err = |e: hound::Error| format!("cannot encode the WAV file: {e}");
    let mut w = hound::WavWriter::new(Cursor::new(&mut bytes), spec).map_err(err)?;
    for i in 0..len {
        for ch in channels {
            let x = ch[i];
            match format {
                SampleFormat::Pcm16 => {
                    if x.abs() > 1.0 {
                        clipped += 1;
                    }
                    w.write_sample((x.clamp(-1.0, 1.0) * 32767.0).round() as i16)
                }
                SampleFormat::Float32 => w.write_sample(x),
            }
            .map_err(err)?;
        }
    }
    w.finalize().map_err(err)?;
    unpositioned(&mut bytes);
    Ok((bytes, clipped))
}

/// Clears the loudspeaker positions (`dwChannelMask`) of a
/// WAVE_FORMAT_EXTENSIBLE header, which hound fills for more than two
/// channels (front left, right, centre, LFE …): lmfilm's channels are
/// microphones or ambisonic components, never loudspeakers, and a player
/// that took channel 4 for an LFE would filter it (the AMB and AmbiX
/// practice: a mask of 0). A file of one or two channels has no mask.
fn unpositioned(bytes: &mut [u8]) {
    // RIFF header (12), `fmt ` chunk header (8), then the format tag.
    const TAG: usize = 20;
    const MASK: usize = TAG + 20;
    if bytes.get(12..16) == Some(b"fmt ") && bytes.get(TAG..TAG + 2) == Some(&[0xfe, 0xff]) {
        if let Some(mask) = bytes.get_mut(MASK..MASK + 4) {
            mask.fill(0);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Four channels (an ambisonic master) carry no loudspeaker
    /// positions: hound reads the file back, and its mask is 0, where
    /// hound alone wrote FL FR FC LFE (0x0f).
    #[test]
    fn many_channels_name_no_loudspeakers() {
        let x = vec![vec![0.25f32; 10]; 4];
        for format in [SampleFormat::Pcm16, SampleFormat::Float32] {
            let (bytes, _) = encode(&x, 48_000, format).unwrap();
            assert_eq!(&bytes[20..22], &[0xfe, 0xff], "WAVE_FORMAT_EXTENSIBLE");
            assert_eq!(&bytes[40..44], &[0, 0, 0, 0], "{format:?}");
            let r = hound::WavReader::new(Cursor::new(&bytes)).unwrap();
            assert_eq!((r.spec().channels, r.len()), (4, 40));
        }
        let (mono, _) = encode(&x[..1], 48_000, SampleFormat::Pcm16).unwrap();
        assert_eq!(&mono[20..22], &[1, 0], "plain PCM, untouched");
    }

    #[test]
    fn sixteen_bits_round_to_the_nearest_step_and_clamp_at_full_scale() {
        let x = vec![0.0, 0.25, -0.25, 0.6 / 32767.0, 1.0, -1.0, 1.5, -3.0];
        let (bytes, clipped) =
            encode(std::slice::from_ref(&x), 48_000, SampleFormat::Pcm16).unwrap();
        assert_eq!(clipped, 2);
        let r = hound::WavReader::new(Cursor::new(bytes)).unwrap();
        let got: Vec<i16> = r.into_samples::<i16>().map(Result::unwrap).collect();
        assert_eq!(got, [0, 8192, -8192, 1, 32767, -32767, 32767, -32767]);
        // Float keeps every value as it is.
        let (bytes, clipped) =
            encode(std::slice::from_ref(&x), 48_000, SampleFormat::Float32).unwrap();
        assert_eq!(clipped, 0);
        let r = hound::WavReader::new(Cursor::new(bytes)).unwrap();
        let got: Vec<f32> = r.into_samples::<f32>().map(Result::unwrap).collect();
        assert_eq!(got, x);
    }

    fn one_second() -> Vec<u8> {
        encode(&[vec![0.25; 100]], 100, SampleFormat::Pcm16)
            .unwrap()
            .0
    }

    /// A header announcing 2 G samples in a small file is refused before
    /// any sample is decoded.
    #[test]
    fn announced_length_beyond_the_bytes_is_refused_before_allocating() {
        let mut b = one_second();
        let data = b.windows(4).position(|w| w == b"data").unwrap();
        b[data + 4..data + 8].copy_from_slice(&(u32::MAX - 1).to_le_bytes());
        let e = decode(&b).unwrap_err();
        assert!(e.contains("more than the file's"), "{e}");
        // Cut short: the same.
        let mut b = one_second();
        b.truncate(b.len() - 50);
        assert!(decode(&b).unwrap_err().contains("truncated"));
    }

    #[test]
    fn absurd_channel_counts_and_rates_are_refused() {
        let mut b = one_second();
        let fmt = b.windows(4).position(|w| w == b"fmt ").unwrap();
        b[fmt + 10..fmt + 12].copy_from_slice(&1000u16.to_le_bytes());
        assert!(decode(&b).is_err());
        let mut b = one_second();
        // 10 MHz, with the byte rate (2 bytes a sample) to match.
        b[fmt + 12..fmt + 16].copy_from_slice(&10_000_000u32.to_le_bytes());
        b[fmt + 16..fmt + 20].copy_from_slice(&20_000_000u32.to_le_bytes());
        let e = decode(&b).unwrap_err();
        assert!(e.contains("10000000 Hz"), "{e}");
        assert_eq!(decode(&one_second()).unwrap().samples.len(), 100);
    }
}
