//! Loudness normalisation of the final mix (ITU-R BS.1770-4, EBU R 128
//! style): the renderer's raw levels follow the physics (a source 40 m
//! away is quiet), which leaves films nearly inaudible, so the mix is
//! brought to a target integrated loudness under a true-peak ceiling.
//! This module measures and decides the gain; where gain alone would
//! pass the ceiling, the [`super::limiter`] holds the peaks down while
//! the gain is raised until the limited mix meets the target.
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

use super::limiter::{Limiter, STAGES};

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

/// The true peak is held this far below the ceiling, dB (by gain or by
/// the limiter): room for meters finer than annex 2's 4×, which see a
/// little more between its points (an 8× sinc meter reads the limited
/// films up to 0.04 dB higher).
const MARGIN: f64 = 0.1;

/// The most the limiter may lower a peak, dB. A track needing more is so
/// sparse (a lone click in seconds of silence) that limiting no longer
/// makes it louder: its gated loudness is that of the peaks themselves.
pub const MAX_LIMITING: f64 = 40.0;

/// The make-up gain is adjusted until the loudness is this close to the
/// target, LU.
const TOLERANCE: f64 = 0.02;

/// The most make-up gains tried (each a limiter pass and a measure).
const ATTEMPTS: usize = 8;

/// The target counts as reached this close, LU; further off,
/// [`Normalization::warning`] says why.
const REACHED: f64 = 0.1;

/// What normalisation did to a mix.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Normalization {
    /// The target, LUFS.
    pub target: f64,
    /// Integrated loudness of the mix as rendered, LUFS; `None` when it
    /// is silent (no block above the absolute gate), and then left so.
    pub measured: Option<f64>,
    /// The gain applied, dB (0 for a silent mix): with the limiter, the
    /// make-up gain, before its cuts.
    pub gain: f64,
    /// True peak before the gain, dBTP (−∞ for all zeros).
    pub peak: f64,
    /// The deepest cut of the limiter, dB (0: not needed).
    pub limiting: f64,
    /// Integrated loudness of the result, LUFS (`None`: silent).
    pub loudness: Option<f64>,
    /// True peak of the result, dBTP.
    pub true_peak: f64,
}

impl Normalization {
    /// One line for the user, e.g. `-16.0 LUFS (gain +23.4 dB), true peak
    /// -3.2 dBTP`, then `, limited up to 6.2 dB` if the limiter worked.
    pub fn summary(&self) -> String {
        match self.loudness {
            None => "silent (below the -70 LUFS gate): left as is".into(),
            Some(l) => {
                let mut s = format!(
                    "{l:.1} LUFS (gain {:+.1} dB), true peak {:.1} dBTP",
                    self.gain, self.true_peak
                );
                if self.limiting > 0.0 {
                    s += &format!(", limited up to {:.1} dB", self.limiting);
                }
                s
            }
        }
    }

    /// Why the target was not reached, when the track is too sparse.
    pub fn warning(&self) -> Option<String> {
        let l = self
            .loudness
            .filter(|l| (l - self.target).abs() > REACHED)?;
        Some(format!(
            "the soundtrack reaches {l:.1} LUFS, not {:.1}: even with its peaks limited by \
             {MAX_LIMITING} dB (the most allowed) more gain would put its true peak above \
             {CEILING} dBTP",
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

/// Fades both ends in and brings the mix to `target` LUFS with its true
/// peak at most [`CEILING`]: by gain alone when that keeps the peak
/// below the ceiling, otherwise by more gain and a [`Limiter`] on the
/// peaks (the gentlest of [`STAGES`] that can), the gain adjusted until
/// the limited mix meets the target (or the limiter cuts
/// [`MAX_LIMITING`]). A silent mix is left silent.
pub fn normalize(channels: &mut [Vec<f32>], rate: u32, target: f64) -> Normalization {
    normalize_weighted(channels, rate, target, &[])
}

/// [`normalize`] with the loudness measured with BS.1770 channel
/// `weights` (a channel without one weighs 1.0): one gain and one
/// limiter for every channel, so their balance is kept. The ambisonic
/// master is measured on W alone (`[1, 0, 0, 0]`).
pub fn normalize_weighted(
    channels: &mut [Vec<f32>],
    rate: u32,
    target: f64,
    weights: &[f64],
) -> Normalization {
    let integrated = |channels: &[Vec<f32>]| integrated_weighted(channels, rate, weights);
    fade(channels, rate);
    let mut envelope = peak_envelope(channels);
    let peak = decibels(envelope.iter().copied().fold(0.0, f64::max));
    let Some(measured) = integrated(channels) else {
        return Normalization {
            target,
            measured: None,
            gain: 0.0,
            peak,
            limiting: 0.0,
            loudness: None,
            true_peak: peak,
        };
    };
    let limit = CEILING - MARGIN;
    let plain = target - measured;
    if peak + plain <= limit {
        let g = amplitude(plain);
        channels.par_iter_mut().for_each(|ch| {
            for x in ch.iter_mut() {
                *x = (f64::from(*x) * g) as f32;
            }
        });
        return Normalization {
            target,
            measured: Some(measured),
            gain: plain,
            peak,
            limiting: 0.0,
            loudness: Some(target),
            true_peak: peak + plain,
        };
    }
    // The limiter reads the envelope in log amplitude; gain G scales it
    // by G, so it is computed once.
    for v in &mut envelope {
        *v = v.ln();
    }
    let mut out = channels.to_vec();
    let mut gains = Vec::new();
    // One attempt: make-up gain `g` dB, limited; (miss in LU, cut in dB).
    let mut attempt = |limiter: &Limiter, g: f64, out: &mut [Vec<f32>]| {
        let ln_limit = (limit - g) * std::f64::consts::LN_10 / 20.0;
        let cut = -limiter.gains(&envelope, ln_limit, &mut gains);
        let a = amplitude(g);
        out.par_iter_mut().zip(&*channels).for_each(|(o, x)| {
            for ((o, &x), &k) in o.iter_mut().zip(x).zip(&gains) {
                *o = (f64::from(x) * a * k) as f32;
            }
        });
        let l = integrated(out).unwrap_or(measured + g);
        (l - target, cut)
    };
    // For each limiter in turn, a safeguarded secant search on the
    // make-up gain: the loudness rises with it, at most dB for dB (all of
    // it below the limit, less and less as the limiter cuts deeper).
    // Below `lowest` nothing is limited and the loudness is known;
    // `highest` is the most limiting. The next limiter is tried only if
    // this one cannot reach the target even there.
    let lowest = limit - peak;
    let highest = lowest + MAX_LIMITING;
    let limiters = STAGES.map(|stage| Limiter::new(rate, stage));
    // (limiter, gain, miss, cut) of the best attempt, and the last one's.
    let mut best = (0, plain.min(highest), f64::INFINITY, 0.0);
    let mut tried = (0, f64::NAN);
    'limiters: for (i, limiter) in limiters.iter().enumerate() {
        let (mut below, mut above) = ((lowest, measured + lowest - target), None::<(f64, f64)>);
        let mut last = below;
        let mut g = plain.min(highest);
        for _ in 0..ATTEMPTS {
            let (miss, cut) = attempt(limiter, g, &mut out);
            tried = (i, g);
            if miss.abs() < best.2.abs() {
                best = (i, g, miss, cut);
            }
            if miss.abs() <= TOLERANCE {
                break 'limiters;
            }
            if miss < 0.0 && g >= highest {
                continue 'limiters;
            }
            if miss < 0.0 {
                below = (g, miss);
            } else {
                above = Some((g, miss));
            }
            // The secant through the last two attempts, if it falls
            // inside the bracket; else the most limiting gain if nothing
            // was too loud yet, or halfway into the bracket.
            let slope = (miss - last.1) / (g - last.0);
            last = (g, miss);
            let next = g - miss / slope;
            g = match above {
                _ if slope > 0.0 && next > below.0 && next < above.map_or(highest, |a| a.0) => next,
                None => highest,
                Some(a) => 0.5 * (below.0 + a.0),
            };
        }
        // Out of attempts short of the tolerance: the best one.
        break;
    }
    let (i, mut gain, mut miss, limiting) = best;
    if (i, gain) != tried {
        attempt(&limiters[i], gain, &mut out);
    }
    // The guarantee: a last plain scale if any true peak is still above
    // the limit (by a hair where the gain moved under a peak).
    let mut true_peak = decibels(true_peak(&out));
    if true_peak > limit {
        let a = amplitude(limit - true_peak);
        out.par_iter_mut().for_each(|ch| {
            for x in ch.iter_mut() {
                *x = (f64::from(*x) * a) as f32;
            }
        });
        gain += limit - true_peak;
        miss = integrated(&out).map_or(miss, |l| l - target);
        true_peak = limit;
    }
    for (ch, o) in channels.iter_mut().zip(out) {
        *ch = o;
    }
    Normalization {
        target,
        measured: Some(measured),
        gain,
        peak,
        limiting,
        loudness: Some(target + miss),
        true_peak,
    }
}

/// The amplitude factor of a gain in dB.
fn amplitude(db: f64) -> f64 {
    10f64.powf(db / 20.0)
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
    integrated_weighted(channels, rate, &[])
}

/// [`integrated`] with each channel's energy weighted by BS.1770's
/// channel `weights` (1.0 for a channel without one; a channel of weight
/// 0 is left out).
pub fn integrated_weighted(channels: &[Vec<f32>], rate: u32, weights: &[f64]) -> Option<f64> {
    let len = channels.iter().map(Vec::len).max()?;
    let step = step_length(len, rate);
    let weight = |k: usize| weights.get(k).copied().unwrap_or(1.0);
    let per_channel: Vec<Vec<f64>> = channels
        .par_iter()
        .enumerate()
        .filter(|(k, _)| weight(*k) != 0.0)
        .map(|(k, ch)| {
            let mut e = step_energies(ch, rate, step);
            if weight(k) != 1.0 {
                e.iter_mut().for_each(|x| *x *= weight(k));
            }
            e
        })
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

/// Samples per task of [`peak_envelope`].
const CHUNK: usize = 1 << 15;

/// The peak envelope of the mix as the true-peak meter sees it: for each
/// sample, the largest magnitude over all channels of the sample itself
/// and of the 4× interpolated values (annex 2) between it and its
/// neighbours. The filter's ringing before the first and after the last
/// sample counts for those samples, so the envelope's maximum is the
/// true peak.
pub fn peak_envelope(channels: &[Vec<f32>]) -> Vec<f64> {
    let len = channels.iter().map(Vec::len).max().unwrap_or(0);
    // The taps reversed, to run along a window of 12 samples in order.
    let phases = TRUE_PEAK_PHASES.map(|mut h| {
        h.reverse();
        h
    });
    let mut envelope = vec![0.0f64; len];
    envelope
        .par_chunks_mut(CHUNK)
        .enumerate()
        .for_each(|(c, out)| {
            let (start, n) = (c * CHUNK, out.len());
            // Values between samples m and m + 1 come from the window of
            // samples m − 5 ..= m + 6 (output n of phase p is
            // Σ h_p[k]·x[n − k], here n = m + 6); at the ends, from the
            // 6 windows before and after.
            let first = if start == 0 { -6 } else { start as isize - 1 };
            let last = if start + n == len {
                len as isize + 4
            } else {
                (start + n) as isize - 1
            };
            // x[i] is sample start − 11 + i, zero outside the channel.
            let mut x = Vec::with_capacity(n + 22);
            for ch in channels {
                x.clear();
                x.extend((0..n + 22).map(|i| {
                    (start + i)
                        .checked_sub(11)
                        .and_then(|k| ch.get(k))
                        .map_or(0.0, |&v| f64::from(v))
                }));
                for (o, v) in out.iter_mut().zip(&x[11..]) {
                    *o = o.max(v.abs());
                }
                for m in first..=last {
                    let w = &x[(m + 6 - start as isize) as usize..][..12];
                    let y = phases.iter().fold(0.0f64, |peak, h| {
                        let y: f64 = h.iter().zip(w).map(|(h, x)| h * x).sum();
                        peak.max(y.abs())
                    });
                    for k in [m, m + 1] {
                        let k = k.clamp(0, len as isize - 1) as usize;
                        if let Some(o) = k.checked_sub(start).and_then(|i| out.get_mut(i)) {
                            *o = o.max(y);
                        }
                    }
                }
            }
        });
    envelope
}

/// The true peak of the channels (annex 2), as an amplitude (1.0 = full
/// scale): the largest magnitude of the channels oversampled 4×, or of
/// their samples if that is larger (the filter's phase 0 passes a sample
/// at 0.97).
pub fn true_peak(channels: &[Vec<f32>]) -> f64 {
    peak_envelope(channels).into_iter().fold(0.0, f64::max)
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
        assert_eq!((n.measured, n.gain, n.limiting), (None, 0.0, 0.0));
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

    /// A deterministic noise in [−1, 1].
    fn noise(n: usize, seed: u64) -> Vec<f32> {
        let mut state = seed;
        (0..n)
            .map(|_| {
                state = state
                    .wrapping_mul(6_364_136_223_846_793_005)
                    .wrapping_add(1_442_695_040_888_963_407);
                ((state >> 11) as f64 / (1u64 << 52) as f64 - 1.0) as f32
            })
            .collect()
    }

    /// Normalises `channels` to the default target and checks the result
    /// against the report: true peak at most the limit, loudness as said.
    fn normalised(mut channels: Vec<Vec<f32>>) -> (Normalization, Vec<Vec<f32>>) {
        let n = normalize(&mut channels, 48_000, DEFAULT_TARGET);
        let tp = decibels(true_peak(&channels));
        assert!(tp <= CEILING - MARGIN + 1e-6, "{tp} dBTP: {n:?}");
        assert!((tp - n.true_peak).abs() < 1e-3, "{tp} dBTP: {n:?}");
        let l = integrated(&channels, 48_000);
        assert!(
            (l.unwrap() - n.loudness.unwrap()).abs() < 1e-3,
            "{l:?}: {n:?}"
        );
        (n, channels)
    }

    #[test]
    fn percussive_tracks_are_limited_to_the_target() {
        // Hits every 0.6 s: a sharp attack decaying in 5 ms, peaks near
        // full scale, and a quiet hum between: plain gain would stop
        // several LU short.
        let rate = 48_000.0;
        let hits: Vec<f32> = (0..48_000 * 6)
            .map(|i| {
                let t = i as f64 / rate;
                let since = t % 0.6;
                let hit = (-since / 0.005).exp() * (2.0 * PI * 400.0 * since).sin();
                (0.9 * hit + 0.01 * (2.0 * PI * 60.0 * t).sin()) as f32
            })
            .collect();
        let other: Vec<f32> = hits.iter().map(|x| -0.7 * x).collect();
        let (n, _) = normalised(vec![hits, other]);
        let l = n.loudness.unwrap();
        assert!((l - DEFAULT_TARGET).abs() <= TOLERANCE, "{n:?}");
        assert!(n.limiting > 3.0 && n.warning().is_none(), "{n:?}");
        assert!(n
            .summary()
            .ends_with(&format!("limited up to {:.1} dB", n.limiting)));
        // A 100 ms burst of noise in 3 s of silence gets there too; one of
        // 20 ms cannot: at the ceiling, even flattened, it carries too
        // little energy for its 400 ms blocks.
        for (ms, reached) in [(100, true), (20, false)] {
            let mut x = vec![0.0f32; 48_000 * 3];
            x[48_000..48_000 + 48 * ms].copy_from_slice(&noise(48 * ms, 7));
            let (n, _) = normalised(vec![x]);
            let miss = n.loudness.unwrap() - DEFAULT_TARGET;
            assert_eq!(miss.abs() <= TOLERANCE, reached, "{ms} ms: {n:?}");
            assert_eq!(n.warning().is_none(), reached, "{ms} ms: {n:?}");
        }
    }

    #[test]
    fn lone_clicks_cannot_reach_the_target_and_say_so() {
        // Single samples: limiting cuts a click as much as it raises it,
        // so the gated loudness is that of clicks at the ceiling.
        let mut x = vec![0.0f32; 48_000 * 4];
        for k in 0..8 {
            x[6000 + k * 24_000] = 0.5;
        }
        let (n, y) = normalised(vec![x]);
        assert!(n.loudness.unwrap() < DEFAULT_TARGET - 10.0, "{n:?}");
        assert!((n.true_peak - (CEILING - MARGIN)).abs() < 1e-3, "{n:?}");
        let w = n.warning().unwrap();
        assert!(w.contains("not -16.0") && w.contains("40 dB"), "{w}");
        // The clicks themselves, no louder than plain gain makes them.
        let peak = y[0].iter().fold(0.0f32, |m, v| m.max(v.abs()));
        assert!(y[0][6000] == peak && y[0][6001].abs() < 1e-3 * peak);
        // One full-scale sample alone, DC, full-scale noise: no panic,
        // the peak held.
        let mut click = vec![0.0f32; 48_000 * 3];
        click[70_000] = 1.0;
        normalised(vec![click]);
        let (n, _) = normalised(vec![vec![1.0f32; 96_000]]);
        assert!(n.loudness.is_some_and(f64::is_finite), "{n:?}");
        let (n, _) = normalised(vec![noise(480_000, 1), noise(480_000, 2)]);
        assert!(
            (n.loudness.unwrap() - DEFAULT_TARGET).abs() <= TOLERANCE,
            "{n:?}"
        );
    }

    #[test]
    fn the_limited_mix_does_not_depend_on_the_thread_count() {
        let x: Vec<f32> = noise(200_000, 3)
            .iter()
            .enumerate()
            .map(|(i, v)| v * if i % 40_000 < 100 { 1.0 } else { 0.02 })
            .collect();
        let run = |threads| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            pool.install(|| {
                let mut ch = vec![x.clone(), x.iter().rev().copied().collect()];
                let n = normalize(&mut ch, 48_000, DEFAULT_TARGET);
                (n, ch)
            })
        };
        let (a, b) = (run(1), run(2));
        assert!(a.0.limiting > 0.0, "{:?}", a.0);
        assert_eq!(a, b);
    }

    #[test]
    fn the_envelope_sees_the_true_peak_and_steady_sound_is_not_limited() {
        // The envelope's maximum is the meter's true peak, also across
        // the chunks the envelope is computed in.
        let x: Vec<f32> = (0..3 * CHUNK + 17)
            .map(|i| (PI / 2.0 * i as f64 + PI / 4.0).sin() as f32 * (i % 1000) as f32 / 1000.0)
            .collect();
        let e = peak_envelope(&[x.clone(), Vec::new()]);
        assert_eq!(e.len(), x.len());
        assert!(e.iter().zip(&x).all(|(e, x)| *e >= f64::from(x.abs())));
        // A steady sine is scaled, not limited.
        let (n, _) = normalised(vec![sine(997.0, 0.01, 3.0, 48_000)]);
        assert_eq!(n.limiting, 0.0);
        assert!((n.loudness.unwrap() - DEFAULT_TARGET).abs() < 1e-9);
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
