//! The Constants functions of the global time (table B5), the timed splines
//! of the Splines section and the Hermite function (eq. 2.3.9).

/// Index of a constant letter: a..z → 0..25, A..Z → 26..51.
pub fn constant_index(c: u8) -> u8 {
    if c.is_ascii_lowercase() {
        c - b'a'
    } else {
        26 + (c - b'A')
    }
}

/// How many coefficients a Constants letter takes: 2 for the linear
/// functions (a..q, r, s, A..D), 3 for E..S; `None` for other letters.
pub fn constant_arity(c: u8) -> Option<usize> {
    match c {
        b'a'..=b's' | b'A'..=b'D' => Some(2),
        b'E'..=b'S' => Some(3),
        _ => None,
    }
}

/// The coefficients of the Constants section, by letter.
#[derive(Debug, Clone)]
pub struct Constants {
    coef: [Option<[f64; 3]>; 52],
}

impl Default for Constants {
    fn default() -> Self {
        Constants { coef: [None; 52] }
    }
}

impl Constants {
    pub fn set(&mut self, letter: u8, c: [f64; 3]) {
        self.coef[constant_index(letter) as usize] = Some(c);
    }

    pub fn defined(&self, letter: u8) -> bool {
        letter.is_ascii_alphabetic() && self.coef[constant_index(letter) as usize].is_some()
    }

    pub fn coefficients(&self, letter: u8) -> Option<[f64; 3]> {
        if !letter.is_ascii_alphabetic() {
            return None;
        }
        self.coef[constant_index(letter) as usize]
    }

    /// Value of the function with letter index `idx` at global time `t`.
    #[inline]
    pub fn eval(&self, idx: u8, t: f64) -> f64 {
        let [c0, c1, c2] = self.coef[idx as usize].unwrap_or_default();
        // idx 26.. are the capitals; E is 30.
        match idx {
            30..=32 => c0 + c1 * t + c2 * t * t, // E..G quadratic
            33..=35 => c0 + c1 * (c2 * t).to_radians().cos(), // H..J cosine, degrees
            36..=40 => c0 + c1 * (c2 * t).to_radians().sin(), // K..O sine, degrees
            41..=44 => c0 + c1 * (c2 * t).exp(), // P..S exponential
            _ => c0 + c1 * t,                    // linear
        }
    }
}

/// A timed spline of the Splines section, key points already scaled.
#[derive(Debug, Clone, PartialEq)]
pub struct Spline {
    pub number: u32,
    /// (argument, value) pairs with strictly increasing arguments.
    pub keys: Vec<(f64, f64)>,
}

impl Spline {
    /// Cubic Hermite interpolation with Catmull–Rom tangents for uneven
    /// spacing; constant beyond the first and last key.
    pub fn eval(&self, a: f64) -> f64 {
        let k = &self.keys;
        match k.len() {
            0 => return 0.0,
            1 => return k[0].1,
            _ => {}
        }
        if a.is_nan() || a <= k[0].0 {
            return k[0].1;
        }
        let last = k.len() - 1;
        if a >= k[last].0 {
            return k[last].1;
        }
        let i = k.partition_point(|p| p.0 <= a) - 1;
        let (x0, y0) = k[i];
        let (x1, y1) = k[i + 1];
        let slope = |j: usize| {
            let (l, r) = (j.saturating_sub(1), (j + 1).min(last));
            (k[r].1 - k[l].1) / (k[r].0 - k[l].0)
        };
        let h = x1 - x0;
        let s = (a - x0) / h;
        let (s2, s3) = (s * s, s * s * s);
        (2.0 * s3 - 3.0 * s2 + 1.0) * y0
            + (s3 - 2.0 * s2 + s) * h * slope(i)
            + (-2.0 * s3 + 3.0 * s2) * y1
            + (s3 - s2) * h * slope(i + 1)
    }
}

/// The cubic Hermite step of eq. 2.3.9: `min` before 0, `max` after `tt`.
pub fn hermite(t: f64, tt: f64, min: f64, max: f64) -> f64 {
    if t <= 0.0 {
        min
    } else if t >= tt {
        max
    } else {
        let u = t / tt;
        min + (max - min) * (3.0 * u * u - 2.0 * u * u * u)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn constant_kinds() {
        let mut k = Constants::default();
        k.set(b'a', [180.0, 2.0, 0.0]);
        k.set(b'E', [1.0, 2.0, 3.0]);
        k.set(b'H', [1.0, 2.0, 90.0]);
        k.set(b'K', [1.0, 2.0, 90.0]);
        k.set(b'P', [1.0, 2.0, 0.5]);
        let at = |c, t| k.eval(constant_index(c), t);
        assert_eq!(at(b'a', 2.0), 184.0);
        assert_eq!(at(b'E', 2.0), 1.0 + 4.0 + 12.0);
        assert!((at(b'H', 1.0) - 1.0).abs() < 1e-12);
        assert!((at(b'K', 1.0) - 3.0).abs() < 1e-12);
        assert!((at(b'P', 2.0) - (1.0 + 2.0 * 1f64.exp())).abs() < 1e-12);
        assert_eq!(constant_arity(b'r'), Some(2));
        assert_eq!(constant_arity(b't'), None);
    }

    #[test]
    fn spline_passes_through_keys_and_clamps() {
        let s = Spline {
            number: 0,
            keys: vec![(0.0, 0.0), (1.0, 2.0), (3.0, 2.0)],
        };
        assert_eq!(s.eval(-1.0), 0.0);
        assert_eq!(s.eval(1.0), 2.0);
        assert_eq!(s.eval(5.0), 2.0);
        let mid = s.eval(0.5);
        assert!(mid > 0.0 && mid < 2.0);
    }

    #[test]
    fn hermite_is_smooth_step() {
        assert_eq!(hermite(-1.0, 2.0, 1.0, 3.0), 1.0);
        assert_eq!(hermite(1.0, 2.0, 1.0, 3.0), 2.0);
        assert_eq!(hermite(5.0, 2.0, 1.0, 3.0), 3.0);
    }
}
