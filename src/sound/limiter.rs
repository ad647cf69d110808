//! A look-ahead true-peak limiter, so a soundtrack of short, loud events
//! (a bouncing ball, a click) can reach its loudness target without its
//! true peak passing the ceiling: plain gain would stop at the ceiling,
//! several LU short (the ball scene at −24 LUFS instead of −16).
//!
//! It computes one gain per sample, shared by all channels (linked, so
//! the stereo image does not move), from the peak envelope of the mix
//! ([`super::loudness::peak_envelope`]: samples and 4× interpolated
//! values, as the true-peak meter sees them):
//!
//! 1. **Need.** ℓ[k] = min(0, ln(limit) − ln(envelope[k])): the log gain
//!    that brings sample k's peak down to the limit.
//! 2. **Hold.** h[j] = min ℓ over [j − S, j + L − 1 + S], L the look-ahead
//!    ([`LimiterTiming::lookahead`]) and S the [`SPREAD`]: a gain is no higher than the need of any
//!    sample it reaches within the look-ahead.
//! 3. **Release.** e[j] = min(h[j], β·e[j − 1]): after a peak the gain
//!    recovers exponentially (time constant [`LimiterTiming::release`]), not at
//!    once, which would click.
//! 4. **Attack.** a[n] = mean of e over [n − L + 1, n]: the gain glides
//!    down over the look-ahead instead of jumping. Every e in the mean of
//!    a sample within S of a peak is at most that peak's need, so
//!    a[n] ≤ ℓ[k] for |n − k| ≤ S: the gain is flat over the
//!    interpolation filter around each peak and the peak lands on the
//!    limit.
//!
//! Everything is f64 in one pass in sample order; working in log gain
//! makes the attack and release glide evenly in dB.

use std::collections::VecDeque;

/// A limiter's timing, seconds.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LimiterTiming {
    /// Look-ahead: the attack glide before each peak.
    pub lookahead: f64,
    /// Release time constant, exponential in dB: fast after deep cuts,
    /// gentle after shallow ones.
    pub release: f64,
}

/// The limiters the normaliser tries, gentlest first; it moves to the
/// next only when one cannot reach the target within
/// [`super::loudness::MAX_LIMITING`].
///
/// The releases are short because the tracks that need a limiter are
/// hits (a ball, a racket, a frog): their loudness can only come from the
/// ring after each onset peak, so the gain must come back while the hit
/// rings (a ball's thud falls about 4 dB every 10 ms). With a broadcast
/// limiter's 80 ms release the ball scene stayed at −22 LUFS even cut by
/// 30 dB.
///
/// - 1.5 ms look-ahead, 10 ms release: the films (the ball scene reaches
///   −16 LUFS with a 27 dB cut, the flyby log with 14 dB); long enough
///   that the gain dips smoothly instead of clicking.
/// - 0.5 ms, 2 ms: close to a soft clipper, for a track of short pulses
///   only (a frog croaking once next to one microphone stays at −17.3
///   LUFS with the first even cut by 40 dB; this one reaches −16 with a
///   23 dB cut). It distorts the onsets more, which is what making such a
///   track that loud means.
pub const STAGES: [LimiterTiming; 2] = [
    LimiterTiming {
        lookahead: 0.0015,
        release: 0.01,
    },
    LimiterTiming {
        lookahead: 0.0005,
        release: 0.002,
    },
];

/// Samples on either side of a peak held at its gain: twice the half
/// length of the annex 2 interpolation filter (6 samples), so the
/// interpolated peaks, which depend on the 12 samples around them, scale
/// exactly, and finer meters' longer filters nearly so.
pub const SPREAD: usize = 12;

/// The limiter for one sample rate.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Limiter {
    /// Look-ahead in samples, at least 1.
    lookahead: usize,
    /// Release factor per sample, in [0, 1).
    release: f64,
}

impl Limiter {
    /// The limiter with `stage`'s timing at `rate` Hz (0 taken as 1).
    pub fn new(rate: u32, stage: LimiterTiming) -> Limiter {
        let fs = f64::from(rate.max(1));
        Limiter {
            lookahead: ((stage.lookahead * fs).round() as usize).max(1),
            release: (-1.0 / (stage.release * fs)).exp(),
        }
    }

    /// Writes into `gains` one gain in (0, 1] per sample such that
    /// gain · exp(ln_envelope) ≤ exp(ln_limit) at every sample; returns
    /// the deepest cut asked for, in dB (negative; 0: none).
    /// `ln_envelope` holds the natural logarithm of the peak envelope
    /// (−∞ where it is 0).
    pub fn gains(&self, ln_envelope: &[f64], ln_limit: f64, gains: &mut Vec<f64>) -> f64 {
        let len = ln_envelope.len();
        let (l, s) = (self.lookahead, SPREAD);
        let need = |k: isize| {
            usize::try_from(k)
                .ok()
                .and_then(|k| ln_envelope.get(k))
                .map_or(0.0, |&v| (ln_limit - v).min(0.0))
        };
        gains.clear();
        gains.reserve(len);
        // The hold's window is [j − s, j + l − 1 + s]; j starts where the
        // window first reaches sample 0, before which everything is 0.
        let width = (l + 2 * s) as isize;
        let first = -((l + s) as isize);
        let mut window: VecDeque<(isize, f64)> = VecDeque::with_capacity(l + 2 * s + 1);
        let mut ring = vec![0.0f64; l];
        let (mut sum, mut nonzero) = (0.0f64, 0usize);
        let mut e = 0.0f64;
        let mut deepest = 0.0f64;
        // Prime the window with all but its last sample for j = first.
        for k in first - s as isize..first + width - 1 - s as isize {
            push(&mut window, k, need(k));
        }
        for j in first..len as isize {
            // Hold: slide the window to end at j + l − 1 + s.
            let newest = j + (l + s) as isize - 1;
            push(&mut window, newest, need(newest));
            while window.front().is_some_and(|&(k, _)| k < j - s as isize) {
                window.pop_front();
            }
            let h = window.front().map_or(0.0, |&(_, v)| v);
            deepest = deepest.min(h);
            // Release, then the attack's running mean over l samples.
            // A release within 10⁻⁹ of unity (far below an f32's
            // resolution) is unity, so the gain comes back to exactly 1.
            let released = self.release * e;
            e = h.min(if released > -1e-9 { 0.0 } else { released });
            let slot = j.rem_euclid(l as isize) as usize;
            nonzero -= usize::from(ring[slot] != 0.0);
            nonzero += usize::from(e != 0.0);
            sum += e - ring[slot];
            ring[slot] = e;
            if nonzero == 0 {
                // Exactly unity gain again, with no rounding left over.
                sum = 0.0;
            }
            if j >= 0 {
                gains.push(if sum < 0.0 {
                    (sum / l as f64).exp()
                } else {
                    1.0
                });
            }
        }
        deepest * 20.0 / std::f64::consts::LN_10
    }
}

/// Adds (k, v) to a window kept as increasing values from front to back,
/// so its front is the window's minimum.
fn push(window: &mut VecDeque<(isize, f64)>, k: isize, v: f64) {
    while window.back().is_some_and(|&(_, w)| w >= v) {
        window.pop_back();
    }
    window.push_back((k, v));
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ln(x: &[f64]) -> Vec<f64> {
        x.iter().map(|v| v.ln()).collect()
    }

    #[test]
    fn nothing_above_the_limit_is_unity_gain() {
        let lim = Limiter::new(48_000, STAGES[0]);
        let mut g = Vec::new();
        let env = ln(&[0.0, 0.1, 0.5, 0.2, 0.0]);
        assert_eq!(lim.gains(&env, 0.5f64.ln(), &mut g), 0.0);
        assert_eq!(g, vec![1.0; 5]);
        assert_eq!(lim.gains(&[], 0.0, &mut g), 0.0);
        assert!(g.is_empty());
    }

    #[test]
    fn a_peak_lands_on_the_limit_with_a_flat_gain_around_it() {
        let rate = 48_000;
        let lim = Limiter::new(rate, STAGES[0]);
        // One peak 12 dB over the limit at sample 1000, one near the end.
        let mut env = vec![0.1f64; 48_000];
        env[1000] = 4.0;
        env[47_990] = 2.0;
        let mut g = Vec::new();
        let deepest = lim.gains(&ln(&env), 0.0, &mut g);
        assert!((deepest + 12.041).abs() < 1e-3, "{deepest}");
        assert_eq!(g.len(), env.len());
        for (k, peak) in [(1000, 4.0), (47_990, 2.0)] {
            for (n, g) in g.iter().enumerate().take(k + SPREAD + 1).skip(k - SPREAD) {
                assert!(g * peak <= 1.0 + 1e-12, "{n}: {}", g * peak);
            }
        }
        assert!((g[1000] - 0.25).abs() < 1e-9 && (g[1000 + SPREAD] - 0.25).abs() < 1e-9);
        // The attack glides down over the look-ahead, the release back up.
        let l = (STAGES[0].lookahead * 48_000.0) as usize;
        assert!(g[1000 - SPREAD - l] == 1.0 && g[1000 - SPREAD - l / 2] > 0.4);
        assert!(g.windows(2).skip(1100).take(40_000).all(|w| w[1] >= w[0]));
        let after = |secs: f64| -20.0 * g[1000 + (secs * f64::from(rate)) as usize].log10();
        assert!(after(0.005) > 5.0 && after(0.03) < 1.5 && after(0.1) < 0.01);
        assert!(g[40_000] > 0.9999);
        // The second stage lets go sooner.
        let mut fast = Vec::new();
        Limiter::new(rate, STAGES[1]).gains(&ln(&env), 0.0, &mut fast);
        assert!(fast[1000] <= 0.25 + 1e-12 && fast[1240] > 0.8 && g[1240] < 0.5);
        assert!(g[47_999] <= 0.5);
    }

    #[test]
    fn tiny_rates_and_tracks_are_fine() {
        for (rate, stage) in [0, 1, 8000].into_iter().zip(STAGES.iter().cycle()) {
            let lim = Limiter::new(rate, *stage);
            let mut g = Vec::new();
            lim.gains(&ln(&[3.0, 0.0]), 0.0, &mut g);
            assert!((g[0] - 1.0 / 3.0).abs() < 1e-12, "{rate}: {g:?}");
            assert!(g[1] <= 1.0 / 3.0 + 1e-12, "{rate}: {g:?}");
        }
    }
}
