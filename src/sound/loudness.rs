//! Loudness normalisation of the final mix (ITU-R BS.1770-4, EBU R 128
//! style): the renderer's raw levels follow the physics (a source 40 m
//! away is quiet), which leaves films nearly inaudible, so the mix is
//! scaled to a target integrated loudness under a true-peak ceiling.
//!
//! - Integrated loudness: each channel is K-weighted (a high-shelf
//!   pre-filter for the head's acoustic effect, then the RLB high-pass),
//!   squared and averaged over 400 ms blocks overlapping by 75 %; blocks
//!   below −70 LUFS (absolute gate) and then those more than 10 LU below
//!   the loudness of the rest (relative gate) are left out, so silence
//!   between events does not drag the measure down.
//! - True peak (annex 2): the largest magnitude of the signal oversampled
//!   4× with the recommendation's 48-tap interpolation filter, so peaks
//!   between samples, which a DAC or a lossy encoder would reproduce, are
//!   counted too.
//! - Short raised-cosine fades at both ends, so a sound cut by the start
//!   or the end of the film does not click.
//!
//! Everything is f64 in a fixed order (each channel on its own, channels
//! summed in order), so the bytes do not depend on the thread count.

use std::f64::consts::PI;
use std::ops::RangeInclusive;

use rayon::prelude::*;

/// The default target: −16 LUFS, the level streaming platforms and
/// podcasts normalise to (EBU R 128's −23 LUFS is for broadcast with a
/// calibrated listening level; a film file is mostly played on laptops
/// and phones, where −23 sounds faint).
pub const DEFAULT_TARGET: f64 = -16.0;

/// Targets accepted, in LUFS: the absolute gate up to full scale.
pub const TARGETS: RangeInclusive<f64> = -70.0..=0.0;

/// The true-peak ceiling in dBTP: 1 dB of headroom for the resampling and
/// lossy encoding (AAC in the MP4) that follow.
pub const CEILING: f64 = -1.0;

/// Length of each end's fade in seconds: long enough to remove a click,
/// too short to hear as a fade.
pub const FADE: f64 = 0.005;

/// BS.1770's offset making a 997 Hz sine at 0 dBFS in one channel read −3.01.
const OFFSET: f64 = -0.691;
/// Absolute gate, LUFS.
const ABSOLUTE_GATE: f64 = -70.0;
/// Relative gate, LU below the absolutely gated loudness.
const RELATIVE_GATE: f64 = 10.0;

/// The annex 2 interpolation filter, one row per phase of the 4×
/// oversampling (the 48-tap prototype read every 4th tap).
const TRUE_PEAK_PHASES: [[f64; 12]; 4] = [
    [
        0.0017089843750,
        0.0109863281250,
        -0.0196533203125,
        0.0332031250000,
        -0.0594482421875,
        0.1373291015625,
        0.9721679687500,
        -0.1022949218750,
        0.0476074218750,
        -0.0266113281250,
        0.0148925781250,
        -0.0083007812500,
    ],
    [
        -0.0291748046875,
        0.0292968750000,
        -0.0517578125000,
        0.0891113281250,
        -0.1665039062500,
        0.4650878906250,
        0.7797851562500,
        -0.2003173828125,
        0.1015625000000,
        -0.0582275390625,
        0.0330810546875,
        -0.0189208984375,
    ],
    [
        -0.0189208984375,
        0.0330810546875,
        -0.0582275390625,
        0.1015625000000,
        -0.2003173828125,
        0.7797851562500,
        0.4650878906250,
        -0.1665039062500,
        0.0891113281250,
        -0.0517578125000,
        0.0292968750000,
        -0.0291748046875,
    ],
    [
        -0.0083007812500,
        0.0148925781250,
        -0.0266113281250,
        0.0476074218750,
        -0.1022949218750,
        0.9721679687500,
        0.1373291015625,
        -0.0594482421875,
        0.0332031250000,
        -0.0196533203125,
        0.0109863281250,
        0.0017089843750,
    ],
];

/// What normalisation did to a mix.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Normalization {
    /// The target, LUFS.
    pub target: f64,
    /// Integrated loudness of the mix as rendered, LUFS; `None` when it
    /// is silent (no block above the absolute gate), and then left so.
    pub measured: Option<f64>,
    /// The gain applied, dB (0 for a silent mix).
    pub gain: f64,
    /// True peak before the gain, dBTP (−∞ for all zeros).
    pub peak: f64,
    /// The ceiling held the gain below what the target asked for.
    pub limited: bool,
}

impl Normalization {
    /// Integrated loudness after the gain, LUFS (`None`: silent).
    pub fn loudness(&self) -> Option<f64> {
        self.measured.map(|l| l + self.gain)
    }

    /// True peak after the gain, dBTP.
    pub fn true_peak(&self) -> f64 {
        self.peak + self.gain
    }

    /// One line for the user, e.g. `-16.0 LUFS (gain +23.4 dB), true peak -3.2 dBTP`.
    pub fn summary(&self) -> String {
        match self.loudness() {
            None => "silent (below the -70 LUFS gate): left as is".into(),
            Some(l) => format!(
                "{l:.1} LUFS (gain {:+.1} dB), true peak {:.1} dBTP",
                self.gain,
                self.true_peak()
            ),
        }
    }

    /// Why the target was not reached, when the ceiling lowered the gain.
    pub fn warning(&self) -> Option<String> {
        let l = self.loudness().filter(|_| self.limited)?;
        Some(format!(
            "the soundtrack reaches {l:.1} LUFS, not {:.1}: more gain would put its true peak \
             above {CEILING} dBTP",
            self.target
        ))
    }
}

/// Checks a loudness target given in LUFS.
pub fn check_target(target: f64) -> Result<(), String> {
    if target.is_finite() && TARGETS.contains(&target) {
        Ok(())
    } else {
        Err(format!(
            "the loudness target must be a number of LUFS in [{}, {}], got {target}",
            TARGETS.start(),
            TARGETS.end()
        ))
    }
}

/// Fades both ends in and scales the mix to `target` LUFS, lowered to keep
/// the true peak at or below [`CEILING`]. A silent mix is left silent.
pub fn normalize(channels: &mut [Vec<f32>], rate: u32, target: f64) -> Normalization {
    fade(channels, rate);
    let measured = integrated(channels, rate);
    let peak = decibels(true_peak(channels));
    let mut gain = measured.map_or(0.0, |l| target - l);
    let limited = measured.is_some() && peak + gain > CEILING;
    if limited {
        gain = CEILING - peak;
    }
    if gain != 0.0 {
        let g = 10f64.powf(gain / 20.0);
        channels.par_iter_mut().for_each(|ch| {
            for x in ch.iter_mut() {
                *x = (f64::from(*x) * g) as f32;
            }
        });
    }
    Normalization {
        target,
        measured,
        gain,
        peak,
        limited,
    }
}

/// 20·log10 of an amplitude (−∞ for 0).
fn decibels(amplitude: f64) -> f64 {
    20.0 * amplitude.log10()
}

/// Raised-cosine fades over [`FADE`] seconds (at least one sample) at both
/// ends: the first and the last samples become 0.
pub fn fade(channels: &mut [Vec<f32>], rate: u32) {
    let n = ((FADE * f64::from(rate)).round() as usize).max(1);
    let w: Vec<f64> = (0..n)
        .map(|i| 0.5 * (1.0 - (PI * i as f64 / n as f64).cos()))
        .collect();
    for ch in channels {
        for (x, w) in ch.iter_mut().zip(&w) {
            *x = (f64::from(*x) * w) as f32;
        }
        for (x, w) in ch.iter_mut().rev().zip(&w) {
            *x = (f64::from(*x) * w) as f32;
        }
    }
}

/// A biquad section, a0 = 1.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Biquad {
    b: [f64; 3],
    a: [f64; 2],
}

impl Biquad {
    const IDENTITY: Biquad = Biquad {
        b: [1.0, 0.0, 0.0],
        a: [0.0, 0.0],
    };
}

/// The two K-weighting stages for `rate` Hz, by the bilinear transform of
/// the analogue filters behind BS.1770's 48 kHz table (the parameters
/// libebur128 fitted to it), so any sample rate is weighted alike. A
/// stage whose corner is at or above Nyquist has nothing to act on at
/// that rate and is left out.
fn k_weighting(rate: u32) -> [Biquad; 2] {
    let fs = f64::from(rate);
    // Stage 1: high shelf, +4 dB above ~1.7 kHz (the head as a rigid sphere).
    let (f0, gain_db, q) = (1681.974450955533, 3.999843853973347, 0.7071752369554196);
    let shelf = if f0 < fs / 2.0 {
        let k = (PI * f0 / fs).tan();
        let vh = 10f64.powf(gain_db / 20.0);
        let vb = vh.powf(0.4996667741545416);
        let a0 = 1.0 + k / q + k * k;
        Biquad {
            b: [
                (vh + vb * k / q + k * k) / a0,
                2.0 * (k * k - vh) / a0,
                (vh - vb * k / q + k * k) / a0,
            ],
            a: [2.0 * (k * k - 1.0) / a0, (1.0 - k / q + k * k) / a0],
        }
    } else {
        Biquad::IDENTITY
    };
    // Stage 2: the RLB high-pass at ~38 Hz.
    let (f0, q) = (38.13547087602444, 0.5003270373238773);
    let high_pass = if f0 < fs / 2.0 {
        let k = (PI * f0 / fs).tan();
        let a0 = 1.0 + k / q + k * k;
        Biquad {
            b: [1.0, -2.0, 1.0],
            a: [2.0 * (k * k - 1.0) / a0, (1.0 - k / q + k * k) / a0],
        }
    } else {
        Biquad::IDENTITY
    };
    [shelf, high_pass]
}

/// The length in samples of the 100 ms steps blocks are made of, for
/// channels of up to `len` samples: a track shorter than one 400 ms block
/// is one step (and one block) of its whole length.
fn step_length(len: usize, rate: u32) -> usize {
    let step = ((f64::from(rate) / 10.0).round() as usize).max(1);
    if len < 4 * step {
        len.max(1)
    } else {
        step
    }
}

/// Sums of the K-weighted squared samples over consecutive steps of
/// `step` samples (complete steps only).
fn step_energies(x: &[f32], rate: u32, step: usize) -> Vec<f64> {
    let [s1, s2] = k_weighting(rate);
    let mut sums = Vec::with_capacity(x.len() / step + 1);
    let (mut w1, mut w2) = ([0.0f64; 2], [0.0f64; 2]);
    let mut acc = 0.0;
    let mut filled = 0;
    for &v in x {
        // Transposed direct form II, stage after stage.
        let v = f64::from(v);
        let y = s1.b[0] * v + w1[0];
        w1 = [s1.b[1] * v - s1.a[0] * y + w1[1], s1.b[2] * v - s1.a[1] * y];
        let z = s2.b[0] * y + w2[0];
        w2 = [s2.b[1] * y - s2.a[0] * z + w2[1], s2.b[2] * y - s2.a[1] * z];
        acc += z * z;
        filled += 1;
        if filled == step {
            sums.push(acc);
            acc = 0.0;
            filled = 0;
        }
    }
    sums
}

/// Integrated loudness of the channels in LUFS (every channel weighted
/// 1.0: microphones are not a loudspeaker layout, so there is no surround
/// or LFE channel to weight otherwise); `None` when no 400 ms block is
/// above the absolute gate. A channel shorter than the others is silent
/// after its end.
pub fn integrated(channels: &[Vec<f32>], rate: u32) -> Option<f64> {
    let len = channels.iter().map(Vec::len).max()?;
    let step = step_length(len, rate);
    let per_channel: Vec<Vec<f64>> = channels
        .par_iter()
        .map(|ch| step_energies(ch, rate, step))
        .collect();
    // Mean squares of each block, summed over channels in order.
    let steps_per_block = if len < 4 * step { 1 } else { 4 };
    let blocks = (len / step + 1).saturating_sub(steps_per_block);
    let power: Vec<f64> = (0..blocks)
        .map(|j| {
            per_channel
                .iter()
                .map(|sums| {
                    sums.get(j..j + steps_per_block)
                        .map_or(0.0, |s| s.iter().sum())
                })
                .sum::<f64>()
                / (steps_per_block * step) as f64
        })
        .collect();
    let loudness = |p: f64| OFFSET + 10.0 * p.log10();
    let gated_mean = |gate: f64| {
        let kept: Vec<f64> = power
            .iter()
            .copied()
            .filter(|&p| loudness(p) > gate)
            .collect();
        (!kept.is_empty()).then(|| kept.iter().sum::<f64>() / kept.len() as f64)
    };
    let relative = loudness(gated_mean(ABSOLUTE_GATE)?) - RELATIVE_GATE;
    gated_mean(ABSOLUTE_GATE.max(relative)).map(loudness)
}

/// The largest magnitude of the channels oversampled 4× (annex 2), or of
/// their samples if that is larger (the filter's phase 0 passes a sample
/// at 0.97), as an amplitude (1.0 = full scale).
pub fn true_peak(channels: &[Vec<f32>]) -> f64 {
    channels
        .par_iter()
        .map(|ch| {
            // Output n of phase p is Σ h_p[k]·x[n − k]: with 11 zeros on
            // each side, every output is one window, newest sample last.
            let pad = [0.0f64; 11];
            let x: Vec<f64> = pad
                .iter()
                .copied()
                .chain(ch.iter().map(|&v| f64::from(v)))
                .chain(pad)
                .collect();
            // The taps reversed, to run along the window in order.
            let phases = TRUE_PEAK_PHASES.map(|mut h| {
                h.reverse();
                h
            });
            let mut peak = ch.iter().fold(0.0f64, |m, &v| m.max(f64::from(v).abs()));
            for w in x.windows(12) {
                for h in &phases {
                    let y: f64 = h.iter().zip(w).map(|(h, x)| h * x).sum();
                    peak = peak.max(y.abs());
                }
            }
            peak
        })
        .reduce(|| 0.0, f64::max)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sine(freq: f64, amplitude: f64, secs: f64, rate: u32) -> Vec<f32> {
        let n = (secs * f64::from(rate)) as usize;
        (0..n)
            .map(|i| (amplitude * (2.0 * PI * freq * i as f64 / f64::from(rate)).sin()) as f32)
            .collect()
    }

    #[test]
    fn k_weighting_at_48_khz_is_the_recommendations_table() {
        let [s1, s2] = k_weighting(48_000);
        let close = |a: &[f64], b: &[f64]| a.iter().zip(b).all(|(a, b)| (a - b).abs() < 1e-9);
        assert!(close(
            &s1.b,
            &[1.53512485958697, -2.69169618940638, 1.19839281085285]
        ));
        assert!(close(&s1.a, &[-1.69065929318241, 0.73248077421585]));
        assert!(close(&s2.b, &[1.0, -2.0, 1.0]));
        assert!(close(&s2.a, &[-1.99004745483398, 0.99007225036621]));
    }

    /// |H| in dB of the two stages at `f` Hz.
    fn response(stages: &[Biquad; 2], f: f64, rate: u32) -> f64 {
        let w = 2.0 * PI * f / f64::from(rate);
        let (c1, s1, c2, s2) = (w.cos(), w.sin(), (2.0 * w).cos(), (2.0 * w).sin());
        let gain = |b: [f64; 3], a: [f64; 3]| {
            let num = (b[0] + b[1] * c1 + b[2] * c2).hypot(b[1] * s1 + b[2] * s2);
            let den = (a[0] + a[1] * c1 + a[2] * c2).hypot(a[1] * s1 + a[2] * s2);
            num / den
        };
        stages
            .iter()
            .map(|s| 20.0 * gain(s.b, [1.0, s.a[0], s.a[1]]).log10())
            .sum()
    }

    #[test]
    fn k_weighting_has_the_same_response_at_every_rate() {
        let reference = k_weighting(48_000);
        for rate in [32_000, 44_100, 88_200, 96_000, 192_000] {
            let k = k_weighting(rate);
            for f in [20.0, 50.0, 100.0, 500.0, 1000.0, 2000.0, 5000.0, 10_000.0] {
                let (a, b) = (response(&k, f, rate), response(&reference, f, 48_000));
                assert!((a - b).abs() < 0.05, "{rate} Hz at {f} Hz: {a} vs {b} dB");
            }
        }
        // About +4 dB high up; +0.691 dB at 997 Hz, which the -0.691 of
        // the loudness formula takes back.
        assert!((response(&reference, 10_000.0, 48_000) - 4.0).abs() < 0.3);
        assert!((response(&reference, 997.0, 48_000) + OFFSET).abs() < 0.01);
    }

    #[test]
    fn a_full_scale_997_hz_sine_in_one_channel_reads_minus_3_01_lufs() {
        for rate in [44_100, 48_000, 96_000] {
            let l = integrated(&[sine(997.0, 1.0, 5.0, rate)], rate).unwrap();
            assert!((l + 3.01).abs() < 0.02, "{rate} Hz: {l}");
        }
        // 20 dB down reads 20 LU less; two such channels add 3 dB.
        let x = sine(997.0, 0.1, 5.0, 48_000);
        let l = integrated(&[x.clone(), x], 48_000).unwrap();
        assert!((l + 20.0).abs() < 0.02, "{l}");
    }

    #[test]
    fn silence_and_sounds_below_the_gate_have_no_loudness() {
        assert_eq!(integrated(&[vec![0.0; 48_000]], 48_000), None);
        assert_eq!(integrated(&[sine(997.0, 1e-4, 2.0, 48_000)], 48_000), None);
        assert_eq!(integrated(&[Vec::new()], 48_000), None);
        assert_eq!(integrated(&[], 48_000), None);
        // Channels of unequal lengths (not from the renderer) are fine too.
        let l = integrated(&[sine(997.0, 1.0, 2.0, 48_000), Vec::new()], 48_000);
        assert!((l.unwrap() + 3.01).abs() < 0.05);
        let mut silent = vec![vec![0.0f32; 1000]];
        let n = normalize(&mut silent, 48_000, DEFAULT_TARGET);
        assert_eq!((n.measured, n.gain, n.limited), (None, 0.0, false));
        assert!(silent[0].iter().all(|&x| x == 0.0));
    }

    #[test]
    fn the_relative_gate_ignores_quiet_passages() {
        // 2 s of a -20 dBFS sine then 8 s of one 30 dB quieter: the quiet
        // blocks are more than 10 LU down and do not count (ungated, the
        // mean would read -30). The 3 blocks across the change count,
        // a little quieter.
        let mut x = sine(997.0, 0.1, 2.0, 48_000);
        x.extend(sine(997.0, 0.1 / 31.62, 8.0, 48_000));
        let l = integrated(&[x], 48_000).unwrap();
        assert!((-23.5..-23.0).contains(&l), "{l}");
    }

    #[test]
    fn odd_and_tiny_rates_do_not_break_the_filters() {
        for rate in [1, 50, 100, 3000, 8000, 22_050, 192_000] {
            let mut ch = vec![sine(30.0 * f64::from(rate) / 100.0, 0.5, 3.0, rate)];
            let n = normalize(&mut ch, rate, DEFAULT_TARGET);
            assert!(n.gain.is_finite() && n.peak.is_finite(), "{rate}: {n:?}");
            assert!(ch[0].iter().all(|x| x.is_finite()));
        }
    }

    #[test]
    fn true_peak_sees_between_the_samples() {
        // A sine at a quarter of the rate sampled at ±45°: samples at
        // 0.707, true peak 1.0.
        let x: Vec<f32> = (0..4800)
            .map(|i| (PI / 2.0 * i as f64 + PI / 4.0).sin() as f32)
            .collect();
        let sample_peak = x.iter().fold(0.0f32, |m, v| m.max(v.abs()));
        assert!((sample_peak - std::f32::consts::FRAC_1_SQRT_2).abs() < 1e-3);
        let tp = true_peak(&[x]);
        assert!((tp - 1.0).abs() < 0.05, "{tp}");
    }

    #[test]
    fn the_ceiling_limits_the_gain_of_a_peaky_mix() {
        // Sparse clicks: quiet on average, full scale at the clicks.
        let mut x = vec![0.0f32; 48_000 * 4];
        for k in 0..8 {
            x[6000 + k * 24_000] = 0.5;
        }
        let mut ch = vec![x];
        let n = normalize(&mut ch, 48_000, DEFAULT_TARGET);
        assert!(n.limited && n.warning().is_some(), "{n:?}");
        assert!((n.true_peak() - CEILING).abs() < 1e-9);
        assert!(n.loudness().unwrap() < DEFAULT_TARGET);
        assert!((decibels(true_peak(&ch)) - CEILING).abs() < 1e-3);
    }

    #[test]
    fn fades_zero_both_ends_and_leave_the_middle() {
        let mut ch = vec![vec![1.0f32; 2000], vec![1.0f32; 3]];
        fade(&mut ch, 48_000);
        assert_eq!((ch[0][0], ch[0][1999], ch[0][1000]), (0.0, 0.0, 1.0));
        // 5 ms = 240 samples; half way at 120.
        assert!(ch[0][10] < 0.01 && (ch[0][120] - 0.5).abs() < 1e-6 && ch[0][239] > 0.99);
        assert_eq!(ch[0][240], 1.0);
        assert_eq!((ch[1][0], ch[1][2]), (0.0, 0.0));
    }

    #[test]
    fn targets_outside_the_range_are_refused() {
        for t in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY, 0.5, -70.5] {
            assert!(check_target(t).is_err(), "{t}");
        }
        for t in [-70.0, -23.0, -16.0, 0.0] {
            assert!(check_target(t).is_ok(), "{t}");
        }
    }
}
