//! The classical fourth-order Runge–Kutta step of appendix H.

/// Advances `y` from `t` to `t + h` for y' = F(t, y). `f(t, y, dy)`
/// writes F(t, y) into `dy`. The stages are combined in the thesis's
/// order, Y + K1/6 + K2/3 + K3/3 + K4/6, so results do not depend on how
/// `f` is computed.
pub fn step(y: &mut [f64], t: f64, h: f64, mut f: impl FnMut(f64, &[f64], &mut [f64])) {
    let n = y.len();
    let mut k = [vec![0.0; n], vec![0.0; n], vec![0.0; n], vec![0.0; n]];
    let mut tmp = vec![0.0; n];
    f(t, y, &mut k[0]);
    stage(&mut tmp, y, &k[0], h / 2.0);
    f(t + h / 2.0, &tmp, &mut k[1]);
    stage(&mut tmp, y, &k[1], h / 2.0);
    f(t + h / 2.0, &tmp, &mut k[2]);
    stage(&mut tmp, y, &k[2], h);
    f(t + h, &tmp, &mut k[3]);
    for i in 0..n {
        let (k1, k2, k3, k4) = (h * k[0][i], h * k[1][i], h * k[2][i], h * k[3][i]);
        y[i] = y[i] + k1 / 6.0 + k2 / 3.0 + k3 / 3.0 + k4 / 6.0;
    }
}

/// `out = y + s·dy`.
fn stage(out: &mut [f64], y: &[f64], dy: &[f64], s: f64) {
    for ((o, a), b) in out.iter_mut().zip(y).zip(dy) {
        *o = a + s * b;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exact_for_a_cubic() {
        // y' = 3t² is integrated exactly by RK4 (Simpson's rule).
        let mut y = [0.0];
        step(&mut y, 1.0, 0.5, |t, _, dy| dy[0] = 3.0 * t * t);
        assert!((y[0] - (1.5f64.powi(3) - 1.0)).abs() < 1e-12);
    }
}
