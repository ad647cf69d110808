//! Where and when the ball will meet the racket (thesis 5.6.2–5.6.3):
//! the ball's velocity from the positions the actor saw (eq. 5.6.1), the
//! time the ball falls to the hitting height without air damping
//! (eq. 5.6.2), the horizontal distance extrapolated and shortened by the
//! learned heuristic (eq. 5.6.4–5.6.5), the learning of its factor x
//! (eq. 5.6.6), and the impact point after a bounce (eq. 5.6.7).
//!
//! Distances and speeds that the heuristic shortens are horizontal: the
//! vertical motion is given by eq. 5.6.2 alone (docs/tennis.md).

use glam::DVec3;

/// The constant o of eq. 5.6.5: where (in m²) the correction sets in.
pub const O: f64 = 10_000.0;

/// Extrapolated or travelled distances below this (m) teach nothing:
/// eq. 5.6.6 divides by d² and by dist.
const LEARN_MIN: f64 = 1e-3;

/// A planned meeting of ball and racket: where, and at what time.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Impact {
    pub point: DVec3,
    pub time: f64,
}

/// Eq. 5.6.1: the ball's velocity from its position now and `frames`
/// frames of `frame_dt` seconds before.
pub fn ball_velocity(now: DVec3, before: DVec3, frames: u32, frame_dt: f64) -> DVec3 {
    (now - before) / (f64::from(frames) * frame_dt)
}

/// The ball's velocity now from eq. 5.6.1's mean over the last `window`
/// seconds: the mean is the velocity at the window's middle, and gravity
/// `g` has lowered the vertical part by g·window/2 since (exactly, without
/// air damping). The mean itself would make eq. 5.6.2's impact time late.
pub fn velocity_now(mean: DVec3, window: f64, g: f64) -> DVec3 {
    mean - DVec3::Y * (0.5 * g * window)
}

/// The horizontal part of a vector (y up).
pub fn horizontal(v: DVec3) -> DVec3 {
    DVec3::new(v.x, 0.0, v.z)
}

/// Eq. 5.6.2: how long until a ball at `height` rising at `vy` is at `h`
/// on its way down, under gravity `g` (> 0) alone — the later root of
/// height + vy·t − ½·g·t² = h. None when it never gets there again: it is
/// below h and does not rise to it, or already past it falling.
pub fn impact_delay(height: f64, vy: f64, h: f64, g: f64) -> Option<f64> {
    let disc = vy * vy + 2.0 * g * (height - h);
    if disc < 0.0 {
        return None;
    }
    let t = (vy + disc.sqrt()) / g;
    (t >= 0.0).then_some(t)
}

/// Eq. 5.6.5: the extrapolated distance d shortened by the heuristic,
/// linear for d² ≪ o and d/x for d² ≫ o.
pub fn corrected_distance(d: f64, x: f64) -> f64 {
    let d2 = d * d;
    d * (d2 + O) / (x * d2 + O)
}

/// The earlier root of eq. 5.6.2: how long until a ball below `h`
/// rising at `vy` gets up to `h`. None when it is not below h and rising,
/// or does not rise that high.
pub fn rising_delay(height: f64, vy: f64, h: f64, g: f64) -> Option<f64> {
    let disc = vy * vy + 2.0 * g * (height - h);
    (height < h && vy > 0.0 && disc >= 0.0).then(|| (vy - disc.sqrt()) / g)
}

/// Eq. 5.6.2–5.6.5: the impact point at height `h` of a ball seen at
/// `p` with velocity `v` at time `now`, with the learned factor `x`.
pub fn estimate_impact(p: DVec3, v: DVec3, now: f64, h: f64, g: f64, x: f64) -> Option<Impact> {
    extrapolate(p, v, now, impact_delay(p.y, v.y, h, g)?, h, x)
}

/// The impact on the rise: as [`estimate_impact`] with the earlier root,
/// for a ball that bounced and climbs to `h`.
pub fn rising_impact(p: DVec3, v: DVec3, now: f64, h: f64, g: f64, x: f64) -> Option<Impact> {
    extrapolate(p, v, now, rising_delay(p.y, v.y, h, g)?, h, x)
}

/// Eq. 5.6.4–5.6.5: the ball's horizontal run over `delay`, corrected.
fn extrapolate(p: DVec3, v: DVec3, now: f64, delay: f64, h: f64, x: f64) -> Option<Impact> {
    let run = horizontal(v);
    let dist = corrected_distance(run.length() * delay, x);
    let point = horizontal(p) + run.normalize_or_zero() * dist + DVec3::Y * h;
    Some(Impact {
        point,
        time: now + delay,
    })
}

/// Eq. 5.6.7: the impact point after the bounce. The thesis runs the
/// ball twice the horizontal run of a straight fall from `h` at its
/// vertical speed (2h/|v_y|: "too fast, but good enough"); on the match
/// that put the racket 1.4–1.7 m past where the rising ball crossed the
/// hitting height, the ball 0.6–0.8 m over the racket (docs/tennis.md).
/// lmfilm's reading: the fall to the bottom of the bounce at `low` and
/// the rise back to `h` under gravity `g`, the ball leaving the ground as
/// fast as it came (2·(u − |v_y|)/g with u the speed at the bottom). The
/// time follows at the same horizontal speed. None when the ball is not
/// falling, or `h` is not over `low`.
pub fn after_bounce(first: &Impact, v: DVec3, h: f64, low: f64, g: f64) -> Option<Impact> {
    let fall = -v.y;
    if fall <= 1e-9 || h <= low {
        return None;
    }
    let bottom = (fall * fall + 2.0 * g * (h - low)).sqrt();
    let run = 2.0 * (bottom - fall) / g;
    Some(Impact {
        point: first.point + horizontal(v) * run,
        time: first.time + run,
    })
}

/// Which impact the player takes (5.6.3): the one closer to it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Choice {
    pub impact: Impact,
    /// Whether it lets the ball bounce first.
    pub bounce: bool,
}

/// 5.6.3: the impact point closer to the `player`, the first one on a tie.
pub fn choose_impact(player: DVec3, first: Impact, second: Option<Impact>) -> Choice {
    match second {
        Some(s) if s.point.distance(player) < first.point.distance(player) => Choice {
            impact: s,
            bounce: true,
        },
        _ => Choice {
            impact: first,
            bounce: false,
        },
    }
}

/// Eq. 5.6.6 solved for x: the factor that maps the extrapolated
/// distance `d` onto the travelled `dist`. None when either is too short
/// to say anything. A negative x is clamped to 0, since x·d² + o must
/// stay positive for eq. 5.6.5 at every range.
pub fn measured_x(d: f64, dist: f64) -> Option<f64> {
    if d < LEARN_MIN || dist < LEARN_MIN {
        return None;
    }
    let x = (d * (d * d + O) / dist - O) / (d * d);
    x.is_finite().then_some(x.max(0.0))
}

/// The factor x of eq. 5.6.5 as the actor learns it (eq. 5.6.6): each
/// exchange measures one value, and x is the mean of the last two.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Learner {
    x: f64,
    last: f64,
}

impl Learner {
    /// Starts at `x`, which also stands for the measurement before the
    /// first one.
    pub fn new(x: f64) -> Self {
        Learner { x, last: x }
    }

    pub fn x(&self) -> f64 {
        self.x
    }

    /// Learns from the ball seen at `p1` with velocity `v1` at `t1`
    /// (entering bounce_or_not_bounce) and at `p2` at `t2` (entering
    /// hit_phase or bounce_begin); a degenerate pair keeps x.
    pub fn learn(&mut self, p1: DVec3, v1: DVec3, t1: f64, p2: DVec3, t2: f64) {
        let d = horizontal(v1).length() * (t2 - t1);
        let dist = horizontal(p2 - p1).length();
        if let Some(x) = measured_x(d, dist) {
            self.x = 0.5 * (self.last + x);
            self.last = x;
        }
    }
}

impl Default for Learner {
    /// x = 1: plain extrapolation until the actor has learned.
    fn default() -> Self {
        Learner::new(1.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::actors::tennis::test_ball::{Ball, G};

    #[test]
    fn velocity_from_positions_frames_apart() {
        let v = ball_velocity(DVec3::new(1.2, 0.0, 0.3), DVec3::ZERO, 3, 0.04);
        assert!((v - DVec3::new(10.0, 0.0, 2.5)).length() < 1e-12);
        // A ball falling freely: the mean over 0.12 s is its velocity
        // 0.06 s ago.
        let ball = |t: f64| DVec3::new(0.0, 3.0 * t - 0.5 * G * t * t, 0.0);
        let mean = ball_velocity(ball(1.0), ball(0.88), 3, 0.04);
        assert!((velocity_now(mean, 0.12, G).y - (3.0 - G)).abs() < 1e-9);
    }

    #[test]
    fn impact_time_is_the_later_root() {
        // From 1 m rising at 4.905 m/s: back at 1 m after 1 s.
        let t = impact_delay(1.0, 4.905, 1.0, G).unwrap();
        assert!((t - 1.0).abs() < 1e-12);
        // From 2 m at rest down to 0.775 m: ½·9.81·t² = 1.225 → t = 0.5.
        assert!((impact_delay(2.0, 0.0, 0.775, G).unwrap() - 0.4998).abs() < 1e-3);
        // Below h and falling, or below and not rising high enough.
        assert_eq!(impact_delay(0.5, -1.0, 1.0, G), None);
        assert_eq!(impact_delay(0.5, 1.0, 1.0, G), None);
        // Exactly reaching h at the apex.
        let vy = (2.0 * G * 0.5).sqrt();
        assert!((impact_delay(0.5, vy, 1.0, G).unwrap() - vy / G).abs() < 1e-12);
    }

    #[test]
    fn corrected_distance_is_linear_near_and_shortened_far() {
        assert_eq!(corrected_distance(0.0, 2.0), 0.0);
        assert!((corrected_distance(1.0, 2.0) - 1.0).abs() < 1e-3);
        // Figure 5.6.4: x = 2 halves long distances.
        assert!((corrected_distance(1e4, 2.0) / 1e4 - 0.5).abs() < 1e-3);
        assert_eq!(corrected_distance(37.0, 1.0), 37.0);
    }

    #[test]
    fn estimate_without_damping_is_exact() {
        let p = DVec3::new(-10.0, 1.5, 2.0);
        let v = DVec3::new(20.0, 3.0, -1.0);
        let i = estimate_impact(p, v, 5.0, 1.0, G, 1.0).unwrap();
        let dt = i.time - 5.0;
        let exact = p + v * dt - DVec3::Y * 0.5 * G * dt * dt;
        assert!((i.point - exact).length() < 1e-9, "{:?} {exact:?}", i.point);
        assert!((i.point.y - 1.0).abs() < 1e-12);
    }

    #[test]
    fn measured_x_inverts_the_correction() {
        for &(d, x) in &[(5.0, 3.0), (30.0, 0.5), (200.0, 2.0)] {
            let x2 = measured_x(d, corrected_distance(d, x)).unwrap();
            assert!((x2 - x).abs() < 1e-9, "{x2} {x}");
        }
        assert_eq!(measured_x(0.0, 3.0), None);
        assert_eq!(measured_x(3.0, 0.0), None);
        // Much farther than extrapolated: x would make 5.6.5 blow up.
        assert_eq!(measured_x(100.0, 1000.0), Some(0.0));
    }

    #[test]
    fn learner_averages_two_consecutive_values() {
        let mut l = Learner::default();
        let d = 20.0; // 10 m/s for 2 s
        let p1 = DVec3::ZERO;
        let v1 = DVec3::new(6.0, -3.0, 8.0);
        l.learn(
            p1,
            v1,
            1.0,
            DVec3::new(0.0, 0.0, corrected_distance(d, 5.0)),
            3.0,
        );
        assert!((l.x() - 3.0).abs() < 1e-9, "(1 + 5) / 2: {}", l.x());
        l.learn(
            p1,
            v1,
            1.0,
            DVec3::new(corrected_distance(d, 7.0), 0.0, 0.0),
            3.0,
        );
        assert!((l.x() - 6.0).abs() < 1e-9, "(5 + 7) / 2: {}", l.x());
        // A ball seen twice at the same spot teaches nothing.
        l.learn(p1, v1, 1.0, p1, 1.0);
        assert!((l.x() - 6.0).abs() < 1e-9);
    }

    #[test]
    fn second_impact_point_hand_computed() {
        // Falling at 4 m/s, 12 m/s along x and 3 along z, hit at 0.8 m,
        // bouncing at 0 under g = 10: at the bottom it falls at
        // √(16 + 16) = 5.657 m/s; down and up again take
        // 2·(5.657 − 4)/10 = 0.3314 s, a run of (3.977, 0.994). The
        // thesis's 2h/|V_y| = 0.4 s ran 20 % too far.
        let first = Impact {
            point: DVec3::new(5.0, 0.8, 1.0),
            time: 2.0,
        };
        let v = DVec3::new(12.0, -4.0, 3.0);
        let second = after_bounce(&first, v, 0.8, 0.0, 10.0).unwrap();
        let t = 2.0 * (32f64.sqrt() - 4.0) / 10.0;
        assert!((t - 0.331_37).abs() < 1e-5);
        assert!((second.point - DVec3::new(5.0 + 12.0 * t, 0.8, 1.0 + 3.0 * t)).length() < 1e-12);
        assert!((second.time - (2.0 + t)).abs() < 1e-12);
        // Fast, it tends to the thesis's run from the bottom's height.
        let fast = after_bounce(&first, DVec3::new(0.0, -400.0, 0.0), 0.8, 0.1, 10.0).unwrap();
        assert!((fast.time - 2.0 - 2.0 * 0.7 / 400.0).abs() < 1e-6);
        assert_eq!(after_bounce(&first, DVec3::X, 0.8, 0.0, 10.0), None);
        assert_eq!(after_bounce(&first, v, 0.1, 0.14, 10.0), None);
        // The player deep behind the bounce takes the second.
        let deep = choose_impact(DVec3::new(11.0, 0.0, 2.0), first, Some(second));
        assert!(deep.bounce && deep.impact == second);
        let close = choose_impact(DVec3::new(6.0, 0.0, 1.0), first, Some(second));
        assert!(!close.bounce && close.impact == first);
        assert!(!choose_impact(DVec3::ZERO, first, None).bounce);
    }

    /// One exchange: the opponent hits at x = −11; the player sees the
    /// ball every 0.04 s, estimates at t1 (entering bounce_or_not_bounce,
    /// 0.2 s after the hit) and sees the ball at the impact at t2. The
    /// estimation error at t1 with the current x, then x learned.
    fn exchange(ball: Ball, learner: &mut Learner, h: f64) -> f64 {
        let dt = 0.04;
        let t1 = 0.2;
        let p1 = ball.at(t1);
        let mean = ball_velocity(p1, ball.at(t1 - 3.0 * dt), 3, dt);
        let v1 = velocity_now(mean, 3.0 * dt, G);
        let estimate = estimate_impact(p1, v1, t1, h, G, learner.x()).unwrap();
        let t2 = ball.down_at(h);
        let truth = ball.at(t2);
        learner.learn(p1, v1, t1, truth, t2);
        horizontal(estimate.point - truth).length()
    }

    #[test]
    fn estimation_error_shrinks_as_x_is_learned_over_a_rally() {
        let mut learner = Learner::default();
        let h = 1.0;
        let errors: Vec<f64> = (0..8)
            .map(|i| {
                let f = f64::from(i);
                let ball = Ball {
                    p: DVec3::new(-11.0, 1.0, 0.5 * (f - 4.0)),
                    v: DVec3::new(
                        26.0 + (f * 1.7) % 4.0,
                        4.0 + (f * 0.9) % 1.5,
                        1.0 - 0.25 * f,
                    ),
                    k: 0.5,
                };
                exchange(ball, &mut learner, h)
            })
            .collect();
        // Over a court, o = 10000 m² makes the correction about quadratic
        // in d while drag shortens about linearly: the x that fits depends
        // a little on the range, and the error stays at a few decimetres.
        let late = &errors[2..];
        let worst = late.iter().cloned().fold(0.0, f64::max);
        let mean = late.iter().sum::<f64>() / late.len() as f64;
        assert!(
            errors[0] > 1.0,
            "drag makes plain extrapolation miss: {errors:?}"
        );
        assert!(worst < 0.35 * errors[0], "{errors:?}");
        assert!(mean < 0.2 * errors[0], "{errors:?}");
        assert!(learner.x() > 1.0, "the ball is slowed: x = {}", learner.x());
    }
}
