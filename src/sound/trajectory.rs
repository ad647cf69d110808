//! Positions between frame keys: a C¹ cubic Hermite curve through the keys
//! (Catmull-Rom tangents), held before the first key and continued in a
//! straight line after the last.
//!
//! The thesis interpolates linearly (eq. 2.4.5), which puts a kink in the
//! velocity, hence a jump of the Doppler pitch, at every frame. Tangents
//! m_k = (p_{k+1} − p_{k−1}) / (t_{k+1} − t_{k−1}) (one-sided at the ends)
//! keep the velocity continuous and reproduce motion at constant velocity
//! exactly, also when frames are not evenly spaced.

use glam::DVec3;

/// One polynomial piece p(s) = a + b·s + c·s² + d·s³ with
/// s = (t − start)·inv_h.
#[derive(Debug, Clone, Copy)]
struct Piece {
    start: f64,
    inv_h: f64,
    a: DVec3,
    b: DVec3,
    c: DVec3,
    d: DVec3,
}

/// A trajectory through keys (tᵢ, pᵢ). Piece 0 holds p₀ before t₀; piece
/// k (1 ≤ k < n) joins keys k−1 and k; piece n continues after the last.
#[derive(Debug, Clone)]
pub struct Trajectory {
    knots: Vec<f64>,
    pieces: Vec<Piece>,
}

impl Trajectory {
    /// `times` strictly increasing, as long as `positions` and not empty.
    pub fn new(times: &[f64], positions: &[DVec3]) -> Self {
        assert_eq!(times.len(), positions.len());
        let n = times.len();
        assert!(n > 0, "a trajectory needs a key");
        let tangent = |k: usize| -> DVec3 {
            if n == 1 {
                return DVec3::ZERO;
            }
            let (i, j) = (k.saturating_sub(1), (k + 1).min(n - 1));
            (positions[j] - positions[i]) / (times[j] - times[i])
        };
        let mut pieces = Vec::with_capacity(n + 1);
        pieces.push(Piece {
            start: times[0],
            inv_h: 0.0,
            a: positions[0],
            b: DVec3::ZERO,
            c: DVec3::ZERO,
            d: DVec3::ZERO,
        });
        for k in 1..n {
            let h = times[k] - times[k - 1];
            let (p0, p1) = (positions[k - 1], positions[k]);
            let (m0, m1) = (tangent(k - 1) * h, tangent(k) * h);
            pieces.push(Piece {
                start: times[k - 1],
                inv_h: 1.0 / h,
                a: p0,
                b: m0,
                c: 3.0 * (p1 - p0) - 2.0 * m0 - m1,
                d: 2.0 * (p0 - p1) + m0 + m1,
            });
        }
        pieces.push(Piece {
            start: times[n - 1],
            inv_h: 1.0,
            a: positions[n - 1],
            b: tangent(n - 1),
            c: DVec3::ZERO,
            d: DVec3::ZERO,
        });
        Trajectory {
            knots: times.to_vec(),
            pieces,
        }
    }

    /// The index of the piece holding `t`; `hint` is the last one found,
    /// since consecutive calls are nearly always in the same piece.
    #[inline]
    fn piece(&self, t: f64, hint: &mut usize) -> usize {
        let k = &self.knots;
        let fits = |j: usize| (j == 0 || k[j - 1] <= t) && (j == k.len() || t < k[j]);
        let h = (*hint).min(k.len());
        let j = if fits(h) {
            h
        } else if h < k.len() && fits(h + 1) {
            h + 1
        } else {
            k.partition_point(|&x| x <= t)
        };
        *hint = j;
        j
    }

    /// Position at `t`.
    #[inline]
    pub fn position(&self, t: f64, hint: &mut usize) -> DVec3 {
        let p = &self.pieces[self.piece(t, hint)];
        let s = (t - p.start) * p.inv_h;
        p.a + s * (p.b + s * (p.c + s * p.d))
    }

    /// Position and velocity at `t`.
    #[inline]
    pub fn position_velocity(&self, t: f64, hint: &mut usize) -> (DVec3, DVec3) {
        let p = &self.pieces[self.piece(t, hint)];
        let s = (t - p.start) * p.inv_h;
        let pos = p.a + s * (p.b + s * (p.c + s * p.d));
        let vel = (p.b + s * (2.0 * p.c + 3.0 * s * p.d)) * p.inv_h;
        (pos, vel)
    }

    /// The first time in [from, to] the speed is `limit` or more, and the
    /// speed then, probed at `from`, at eighths of every piece in between
    /// and at `to`.
    pub fn reaches_speed(&self, from: f64, to: f64, limit: f64) -> Option<(f64, f64)> {
        let k = &self.knots;
        let near = &k[k.partition_point(|&x| x <= from).saturating_sub(1)
            ..(k.partition_point(|&x| x < to) + 1).min(k.len())];
        let inner = near
            .windows(2)
            .flat_map(|w| (0..8).map(move |i| w[0] + (w[1] - w[0]) * i as f64 / 8.0));
        let probes = std::iter::once(from)
            .chain(inner.filter(|&t| t > from && t < to))
            .chain(std::iter::once(to));
        let mut hint = 0;
        probes
            .map(|t| (self.position_velocity(t, &mut hint).1.length(), t))
            .find(|&(v, _)| v >= limit)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn constant_velocity_is_exact_between_and_after_keys() {
        let v = DVec3::new(3.0, -1.0, 0.5);
        let times = [0.0, 0.04, 0.1, 0.12, 0.2];
        let pos: Vec<DVec3> = times.iter().map(|&t| DVec3::ONE + v * t).collect();
        let tr = Trajectory::new(&times, &pos);
        let mut hint = 0;
        for i in 0..300 {
            let t = i as f64 * 0.001;
            let (p, vel) = tr.position_velocity(t, &mut hint);
            assert!((p - (DVec3::ONE + v * t)).length() < 1e-12, "t = {t}");
            assert!((vel - v).length() < 1e-9, "t = {t}");
        }
        // Held before the first key.
        assert_eq!(tr.position(-1.0, &mut hint), DVec3::ONE);
    }

    #[test]
    fn finds_the_first_time_a_speed_is_reached() {
        // Still until t = 1, then accelerating along x.
        let times: Vec<f64> = (0..=40).map(|i| i as f64 * 0.1).collect();
        let pos: Vec<DVec3> = times
            .iter()
            .map(|&t| {
                DVec3::X
                    * if t < 1.0 {
                        0.0
                    } else {
                        50.0 * (t - 1.0).powi(2)
                    }
            })
            .collect();
        let tr = Trajectory::new(&times, &pos);
        // v = 100 (t − 1) up to 300 m/s at the last key, t = 4; after it
        // the last chord's 295 m/s.
        assert_eq!(tr.reaches_speed(0.0, 10.0, 301.0), None);
        let (v, t) = tr.reaches_speed(0.5, 10.0, 296.0).unwrap();
        assert!(v >= 296.0 && (3.9..4.0).contains(&t), "{v} at {t}");
        let (v, t) = tr.reaches_speed(2.0, 3.0, 150.0).unwrap();
        assert!(v >= 150.0 && (2.5..2.6).contains(&t), "{v} at {t}");
        assert_eq!(tr.reaches_speed(0.0, 0.9, 1e-9), None);
    }

    #[test]
    fn passes_through_keys_with_continuous_velocity() {
        let times = [0.0, 1.0, 2.0, 3.0];
        let pos = [DVec3::ZERO, DVec3::X, DVec3::new(1.0, 2.0, 0.0), DVec3::Y];
        let tr = Trajectory::new(&times, &pos);
        let mut hint = 0;
        for (t, p) in times.iter().zip(pos) {
            assert!((tr.position(*t, &mut hint) - p).length() < 1e-12);
            if *t == 0.0 {
                continue; // held before the first key: no velocity there
            }
            let before = tr.position_velocity(t - 1e-9, &mut hint).1;
            let after = tr.position_velocity(t + 1e-9, &mut hint).1;
            assert!((before - after).length() < 1e-6, "t = {t}");
        }
    }
}
