//! The stroke (thesis 5.6.4–5.6.5): the aim point of the simple
//! strategy, the velocity the ball should leave with (eq. 5.6.8) and the
//! learning of its coefficient c2, and the racket velocity and normal
//! that make the ball leave with it (eq. 5.6.9–5.6.14).
//!
//! The thesis's geometry, taken as written: the racket's mass is
//! infinite, the ball's velocity v is mirrored in the racket's plane
//! (r, |r| = |v|) and the racket's velocity c is added: a = r + c
//! (eq. 5.6.10). A moving mirror of physics would add c twice; the
//! players learn the speed of their strokes from where the ball lands
//! (c2), which absorbs the difference (docs/tennis.md).

use glam::DVec3;

use super::court::{BASE_LINE, SIDELINE};
use super::impact::horizontal;

/// Most the ratio of planned to effective length counts in one stroke
/// (a factor of 2 either way); the speed follows its fourth root, so one
/// landing changes the speed by at most 19 %.
const MAX_RATIO: f64 = 2.0;
/// Planned or effective distances below this (m) teach nothing.
const LEARN_MIN: f64 = 1e-3;

/// The racket at the stroke: its normal n and its signed speed along it;
/// the racket velocity is c = speed·n. A negative speed moves the racket
/// backwards, slowing the ball down.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RacketHit {
    pub normal: DVec3,
    pub speed: f64,
}

impl RacketHit {
    /// The racket velocity c.
    pub fn velocity(&self) -> DVec3 {
        self.normal * self.speed
    }
}

/// Eq. 5.6.9–5.6.14: the racket that sends a ball arriving at `v` away at
/// `a`. The normal is n = (a − v)/|a − v| (eq. 5.6.11): a reflection only
/// changes the velocity along n. c = x·(a − v) with x = C/A =
/// (a² − v²)/(a − v)² (eq. 5.6.14), so the speed along n is
/// (a² − v²)/|a − v| = (a + v)·n, the form computed (no cancellation).
/// For |a| = |v| (a the mirror image of v, or a = −v) the racket stands
/// still (eq. 5.6.11, 5.6.12); for a = v there is no stroke: c = 0 and a
/// normal along which v does not change.
pub fn hit(v: DVec3, a: DVec3) -> RacketHit {
    let change = a - v;
    if change == DVec3::ZERO {
        let normal = match v.try_normalize() {
            Some(dir) => dir.any_orthonormal_vector(),
            None => DVec3::Y,
        };
        return RacketHit { normal, speed: 0.0 };
    }
    let normal = change.normalize();
    RacketHit {
        normal,
        speed: (a + v).dot(normal),
    }
}

/// The strategy's aim (5.6.4): the back corner of the opponent's singles
/// court farther from the `opponent`, `deep` inside the base line and
/// `wide` inside the side line. The
/// opponent's side is the sign of its x (the net is at x = 0); the two
/// corners at the net are not candidates, since a ball at a constant
/// inclination could not land there over the net.
pub fn aim_point(opponent: DVec3, deep: f64, wide: f64) -> DVec3 {
    let x = (BASE_LINE - deep).copysign(opponent.x);
    let z = if opponent.z > 0.0 {
        wide - SIDELINE
    } else {
        SIDELINE - wide
    };
    DVec3::new(x, 0.0, z)
}

/// A stroke the actor remembers to learn from: where it hit the ball and
/// how far (horizontally) it planned to send it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Shot {
    pub impact: DVec3,
    pub planned: f64,
}

impl Shot {
    pub fn new(impact: DVec3, aim: DVec3) -> Self {
        Shot {
            impact,
            planned: horizontal(aim - impact).length(),
        }
    }
}

/// The wished ball velocity of eq. 5.6.8: |a| = c1 + c2·(horizontal
/// distance to the aim), at a constant `inclination` (radians above the
/// horizontal); c2 is learned.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Aim {
    pub c1: f64,
    pub c2: f64,
    pub inclination: f64,
}

impl Aim {
    /// The velocity a from the impact point towards the aim point. An aim
    /// straight below the impact point leaves only the vertical part.
    pub fn velocity(&self, impact: DVec3, aim: DVec3) -> DVec3 {
        let run = horizontal(aim - impact);
        let speed = self.c1 + self.c2 * run.length();
        let (up, along) = self.inclination.sin_cos();
        speed * (run.normalize_or_zero() * along + DVec3::Y * up)
    }

    /// Learns c2 from where the ball of `shot` `landed` (seen when the
    /// actor hears it hit the ground, or the opponent's racket low).
    /// A range grows about with the square of the speed, so the speed of
    /// the planned distance would be scaled by √(planned / effective);
    /// a landing is one noisy measure (a ball struck off the straight
    /// part of the stroke), so the speed moves half that way in
    /// logarithm — the fourth root — the ratio clamped to [1/2, 2]; c2
    /// follows from eq. 5.6.8 and stays ≥ 0. A shot too short to measure
    /// keeps c2.
    pub fn learn(&mut self, shot: &Shot, landed: DVec3) {
        let effective = horizontal(landed - shot.impact).length();
        if shot.planned < LEARN_MIN || effective < LEARN_MIN {
            return;
        }
        let ratio = (shot.planned / effective).clamp(1.0 / MAX_RATIO, MAX_RATIO);
        let speed = (self.c1 + self.c2 * shot.planned) * ratio.sqrt().sqrt();
        self.c2 = ((speed - self.c1) / shot.planned).max(0.0);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::actors::tennis::test_ball::Ball;
    use proptest::prelude::*;

    /// The ball leaving the racket of normal n moving at c: v mirrored in
    /// the racket's plane, plus c (eq. 5.6.10).
    fn reflect(v: DVec3, c: DVec3, n: DVec3) -> DVec3 {
        v - 2.0 * v.dot(n) * n + c
    }

    fn vec3() -> impl Strategy<Value = DVec3> {
        (-60.0..60.0f64, -60.0..60.0f64, -60.0..60.0f64).prop_map(|(x, y, z)| DVec3::new(x, y, z))
    }

    proptest! {
        #[test]
        fn the_ball_leaves_with_the_wished_velocity(v in vec3(), a in vec3()) {
            let scale = v.length().max(a.length()).max(1.0);
            prop_assume!((a - v).length() > 1e-3 * scale);
            let h = hit(v, a);
            let c = h.velocity();
            prop_assert!((h.normal.length() - 1.0).abs() < 1e-12);
            let out = reflect(v, c, h.normal);
            prop_assert!((out - a).length() <= 1e-9 * scale, "{out} vs {a}");
        }
    }

    #[test]
    fn special_cases_of_the_text() {
        let v = DVec3::new(-20.0, -3.0, 1.0);
        // a = v: no stroke, and v passes the still racket unchanged.
        let none = hit(v, v);
        assert_eq!(none.speed, 0.0);
        assert!((reflect(v, DVec3::ZERO, none.normal) - v).length() < 1e-12);
        assert_eq!(hit(DVec3::ZERO, DVec3::ZERO).velocity(), DVec3::ZERO);
        // a = −v: a still racket facing the ball (eq. 5.6.12).
        let back = hit(v, -v);
        assert!(back.speed.abs() < 1e-12);
        assert!((back.normal + v.normalize()).length() < 1e-12);
        // a the mirror image r of v: a still racket (eq. 5.6.11).
        let r = DVec3::new(20.0, -3.0, 1.0);
        let mirror = hit(v, r);
        assert!(mirror.speed.abs() < 1e-12);
        assert!((mirror.normal - DVec3::X).length() < 1e-12);
    }

    #[test]
    fn a_slower_ball_needs_a_racket_moving_backwards() {
        let v = DVec3::new(-20.0, 0.0, 0.0);
        let h = hit(v, DVec3::new(5.0, 0.0, 0.0));
        // Mirrored, +20; the racket at −15 leaves +5.
        assert!((h.velocity() - DVec3::new(-15.0, 0.0, 0.0)).length() < 1e-12);
        assert!(h.speed < 0.0 && h.normal == DVec3::X);
    }

    #[test]
    fn the_racket_velocity_is_eq_5_6_14() {
        let (v, a) = (DVec3::new(-18.0, -2.0, 1.5), DVec3::new(25.0, 4.0, -3.0));
        let d = a - v;
        let x = (a.length_squared() - v.length_squared()) / d.length_squared();
        assert!((hit(v, a).velocity() - x * d).length() < 1e-9);
    }

    #[test]
    fn aims_at_the_back_corner_away_from_the_opponent() {
        let p = aim_point(DVec3::new(11.0, 0.0, 1.0), 0.5, 0.5);
        assert!((p - DVec3::new(11.385, 0.0, -3.615)).length() < 1e-12);
        let p = aim_point(DVec3::new(-9.0, 0.0, -2.0), 0.5, 0.5);
        assert!((p - DVec3::new(-11.385, 0.0, 3.615)).length() < 1e-12);
    }

    #[test]
    fn aim_velocity_follows_eq_5_6_8() {
        let aim = Aim {
            c1: 8.0,
            c2: 0.5,
            inclination: 0.3,
        };
        let impact = DVec3::new(-11.0, 1.0, 0.0);
        let target = DVec3::new(9.0, 0.0, 15.0);
        let a = aim.velocity(impact, target);
        // Horizontal distance 25: |a| = 8 + 12.5.
        assert!((a.length() - 20.5).abs() < 1e-12);
        assert!((a.y / a.length() - 0.3f64.sin()).abs() < 1e-12);
        assert!((a.z / a.x - 0.75).abs() < 1e-12);
        let up = aim.velocity(impact, DVec3::new(-11.0, 0.0, 0.0));
        assert!((up - DVec3::Y * 8.0 * 0.3f64.sin()).length() < 1e-12);
    }

    /// Where a ball hit at `a` from `impact` lands, with air damping.
    fn landing(impact: DVec3, a: DVec3) -> DVec3 {
        let ball = Ball {
            p: impact,
            v: a,
            k: 0.5,
        };
        ball.at(ball.down_at(0.0))
    }

    #[test]
    fn c2_is_learned_from_where_the_ball_lands() {
        let mut aim = Aim {
            c1: 10.0,
            c2: 2.0,
            inclination: 0.25,
        };
        let misses: Vec<f64> = (0..16)
            .map(|i| {
                let impact = DVec3::new(-11.0 - 0.2 * f64::from(i % 3), 1.0, 1.0);
                let target = aim_point(DVec3::new(10.0, 0.0, f64::from(i % 2) - 0.5), 0.5, 0.5);
                let shot = Shot::new(impact, target);
                let landed = landing(impact, aim.velocity(impact, target));
                aim.learn(&shot, landed);
                horizontal(landed - target).length()
            })
            .collect();
        // Each landing moves the speed a fourth root of the way: the
        // misses shrink steadily, below half a metre within a dozen.
        assert!(misses[0] > 5.0, "{misses:?}");
        assert!(misses.windows(2).all(|w| w[1] < w[0]), "{misses:?}");
        assert!(misses[12..].iter().all(|&m| m < 0.5), "{misses:?}");
    }

    #[test]
    fn c2_learning_ignores_shots_too_short_to_measure() {
        let mut aim = Aim {
            c1: 10.0,
            c2: 2.0,
            inclination: 0.25,
        };
        let shot = Shot::new(DVec3::ZERO, DVec3::X * 20.0);
        aim.learn(&shot, DVec3::Y);
        assert_eq!(aim.c2, 2.0);
        // Far too long: the speed falls by at most a factor 2^(1/4).
        aim.learn(&shot, DVec3::X * 1e4);
        let speed = 50.0 * 0.5f64.powf(0.25);
        assert!((aim.c2 - ((speed - 10.0) / 20.0)).abs() < 1e-12);
    }
}
