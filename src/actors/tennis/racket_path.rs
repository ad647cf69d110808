//! The racket's timed path (thesis 5.6.6, eq. 5.6.15–5.6.17): key points
//! with times from the racket now, through the stroke, back to the start
//! point, joined by a C¹ cubic Hermite curve with Catmull-Rom tangents
//! m_k = (P_{k+1} − P_{k−1}) / (t_{k+1} − t_{k−1}), one-sided at the ends
//! (the sound layer's [`Trajectory`]).
//!
//! With m the impact's index and n = 2m the last one: P₀ now; P₁ one step
//! along the racket's current velocity, so the velocity stays continuous
//! (the trajectory's first tangent is the first chord); P₂ … P_{m−1} on
//! the line to the stroke's start; P_{m−1}, P_m, P_{m+1} the stroke,
//! evenly timed on a straight line, so the tangent at the impact is
//! exactly the racket velocity c; P_{m+2} … P_{n−1} on the line back to
//! the start point, reached return_time after the stroke; P_n a step
//! towards the opponent's start point, so the racket ends facing it.

use glam::DVec3;

use super::hit::RacketHit;
use super::impact::Impact;
use crate::sound::trajectory::Trajectory;

/// Longest a stroke lasts (s); a longer one is shortened.
pub const MAX_HIT_DURATION: f64 = 0.1;
/// The racket speed (m/s) a still racket strikes with, along its normal.
pub const MIN_RACKET_SPEED: f64 = 0.1;
/// How far the last key point lies towards the opponent's start point.
const FACING: f64 = 0.05;
/// The fewest key points before the impact: P₀, P₁, P_{m−2}, P_{m−1}.
const MIN_MIDDLE: usize = 4;

/// What a racket path is planned from.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StrokePlan {
    /// The time now, and the racket's position and velocity then.
    pub now: f64,
    pub position: DVec3,
    pub velocity: DVec3,
    pub impact: Impact,
    pub hit: RacketHit,
    /// The length (m) of the straight stroke on either side of the impact.
    pub hit_length: f64,
    /// Seconds from the stroke's end back to the start point.
    pub return_time: f64,
    pub start: DVec3,
    pub opponent_start: DVec3,
    /// The impact's key index m (at least 3).
    pub middle: usize,
}

/// A planned racket path: its key points with strictly increasing times,
/// and the C¹ curve through them (Catmull–Rom tangents, the sound's
/// trajectory curve).
#[derive(Debug, Clone)]
pub struct RacketPath {
    times: Vec<f64>,
    points: Vec<DVec3>,
    curve: Trajectory,
}

/// The stroke's direction of motion and speed: the hit's velocity, or
/// `MIN_RACKET_SPEED` along its normal when the racket would stand still.
fn stroke_motion(hit: &RacketHit) -> (DVec3, f64) {
    if hit.speed.abs() < MIN_RACKET_SPEED {
        (hit.normal, MIN_RACKET_SPEED)
    } else {
        (hit.normal * hit.speed.signum(), hit.speed.abs())
    }
}

impl RacketPath {
    /// Eq. 5.6.15–5.6.17. None when the stroke cannot be planned: no time
    /// left before it, or a hit length or return time that is not
    /// positive.
    pub fn plan(p: &StrokePlan) -> Option<Self> {
        let m = p.middle.max(MIN_MIDDLE);
        let (dir, speed) = stroke_motion(&p.hit);
        let duration = (p.hit_length / speed).min(MAX_HIT_DURATION);
        let length = speed * duration;
        let (t_i, impact) = (p.impact.time, p.impact.point);
        // The stroke: five collinear keys evenly timed, so that the racket
        // moves straight at c for `duration` on both sides of the impact.
        let stroke: Vec<(f64, DVec3)> = (-2..=2)
            .map(|k| {
                let k = f64::from(k);
                (t_i + k * duration, impact + dir * (k * length))
            })
            .collect();
        let (lead_time, lead) = stroke[0];
        let approach = (lead_time - p.now) / (m - 2) as f64;
        if !(approach > 0.0 && duration > 0.0 && p.return_time > 0.0) {
            return None;
        }
        let mut times = vec![p.now];
        let mut points = vec![p.position];
        let first = p.position + p.velocity * approach;
        for k in 1..=m - 3 {
            times.push(p.now + k as f64 * approach);
            points.push(first.lerp(lead, (k - 1) as f64 / (m - 3) as f64));
        }
        times.extend(stroke.iter().map(|s| s.0));
        points.extend(stroke.iter().map(|s| s.1));
        let (end_time, end) = stroke[4];
        let back = p.return_time / (m - 3) as f64;
        for k in 1..=m - 3 {
            times.push(end_time + k as f64 * back);
            points.push(end.lerp(p.start, k as f64 / (m - 3) as f64));
        }
        times.push(end_time + p.return_time + back);
        points.push(p.start + FACING * (p.opponent_start - p.start));
        let curve = Trajectory::new(&times, &points);
        Some(RacketPath {
            times,
            points,
            curve,
        })
    }

    /// Position and velocity on the curve at `t` in [t₀, t_n].
    fn curve(&self, t: f64) -> (DVec3, DVec3) {
        self.curve.position_velocity(t, &mut 0)
    }

    /// The key points and their times.
    pub fn keys(&self) -> (&[f64], &[DVec3]) {
        (&self.times, &self.points)
    }

    /// When the racket arrives at its last key point.
    pub fn end(&self) -> f64 {
        self.times[self.times.len() - 1]
    }

    /// The racket's position and velocity at `t`; it waits at the first
    /// key point before the path and at the last one after it.
    pub fn at(&self, t: f64) -> (DVec3, DVec3) {
        if t < self.times[0] {
            return (self.points[0], DVec3::ZERO);
        }
        if t >= self.end() {
            return (self.points[self.points.len() - 1], DVec3::ZERO);
        }
        self.curve(t)
    }

    /// The racket's normal at `t`: its direction of motion, held from the
    /// path's ends while it waits (zero only if it never moved there).
    pub fn normal(&self, t: f64) -> DVec3 {
        self.curve(t.clamp(self.times[0], self.end()))
            .1
            .normalize_or_zero()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::actors::tennis::hit::hit;

    fn plan() -> StrokePlan {
        let v = DVec3::new(-22.0, -3.0, 1.0);
        let a = DVec3::new(20.0, 5.0, -4.0);
        StrokePlan {
            now: 1.0,
            position: DVec3::new(11.0, 1.0, 0.0),
            velocity: DVec3::new(0.0, 0.0, 1.5),
            impact: Impact {
                point: DVec3::new(10.0, 1.0, 2.0),
                time: 1.8,
            },
            hit: hit(v, a),
            hit_length: 0.5,
            return_time: 1.5,
            start: DVec3::new(12.0, 1.0, 0.0),
            opponent_start: DVec3::new(-12.0, 1.0, 0.0),
            middle: 5,
        }
    }

    #[test]
    fn passes_through_every_key_at_its_time() {
        let path = RacketPath::plan(&plan()).unwrap();
        let (times, points) = path.keys();
        assert_eq!(times.len(), 11);
        assert!(times.windows(2).all(|w| w[0] < w[1]), "{times:?}");
        for (&t, &p) in times.iter().zip(points) {
            assert!((path.at(t).0 - p).length() < 1e-12, "t = {t}");
        }
    }

    #[test]
    fn strikes_at_the_impact_point_with_the_racket_velocity() {
        let p = plan();
        let path = RacketPath::plan(&p).unwrap();
        let (pos, vel) = path.at(p.impact.time);
        assert!((pos - p.impact.point).length() < 1e-12);
        let c = p.hit.velocity();
        assert!((vel - c).length() < 1e-9 * c.length(), "{vel} vs {c}");
        assert!((path.normal(p.impact.time) - c.normalize()).length() < 1e-9);
        // The stroke: P_{m−1}, P_m, P_{m+1} on a line, evenly timed.
        let (times, points) = path.keys();
        let (before, after) = (times[5] - times[4], times[6] - times[5]);
        assert!((before - after).abs() < 1e-12);
        assert!(before <= MAX_HIT_DURATION + 1e-15);
        assert!((points[6] - 2.0 * points[5] + points[4]).length() < 1e-12);
    }

    #[test]
    fn a_slow_stroke_is_shortened_to_a_tenth_of_a_second() {
        let mut p = plan();
        p.hit.speed = 2.0; // 0.5 m would last 0.25 s
        let path = RacketPath::plan(&p).unwrap();
        let (times, points) = path.keys();
        assert!((times[6] - times[5] - MAX_HIT_DURATION).abs() < 1e-12);
        assert!(((points[6] - points[5]).length() - 0.2).abs() < 1e-12);
        assert!((path.at(p.impact.time).1 - p.hit.velocity()).length() < 1e-9);
    }

    #[test]
    fn a_still_racket_strikes_slowly_along_its_normal() {
        let mut p = plan();
        p.hit.speed = 0.0;
        let path = RacketPath::plan(&p).unwrap();
        let vel = path.at(p.impact.time).1;
        assert!((vel - p.hit.normal * MIN_RACKET_SPEED).length() < 1e-9);
    }

    #[test]
    fn a_backward_stroke_moves_against_the_normal() {
        let mut p = plan();
        p.hit.speed = -5.0;
        let path = RacketPath::plan(&p).unwrap();
        let vel = path.at(p.impact.time).1;
        assert!((vel - p.hit.normal * -5.0).length() < 1e-9);
    }

    #[test]
    fn leaves_with_the_current_velocity() {
        let p = plan();
        let path = RacketPath::plan(&p).unwrap();
        let (pos, vel) = path.at(p.now);
        assert_eq!(pos, p.position);
        assert!((vel - p.velocity).length() < 1e-12);
    }

    #[test]
    fn returns_to_the_start_point_facing_the_opponent() {
        let p = plan();
        let path = RacketPath::plan(&p).unwrap();
        let (times, _) = path.keys();
        let back = times[7] + p.return_time;
        assert!((path.at(back).0 - p.start).length() < 1e-12);
        let face = p.start + 0.05 * (p.opponent_start - p.start);
        assert_eq!(path.at(path.end() + 3.0), (face, DVec3::ZERO));
        let towards = (p.opponent_start - p.start).normalize();
        assert!((path.normal(path.end() + 3.0) - towards).length() < 1e-9);
    }

    /// On both sides of the impact, for the stroke's duration, the racket
    /// moves straight at c: a ball early or late meets the same face.
    #[test]
    fn the_stroke_is_straight_at_c_around_the_impact() {
        let p = plan();
        let path = RacketPath::plan(&p).unwrap();
        let (times, _) = path.keys();
        let duration = times[6] - times[5];
        let c = p.hit.velocity();
        for f in [-1.0, -0.6, -0.2, 0.3, 0.7, 1.0] {
            let t = p.impact.time + f * duration;
            let (pos, vel) = path.at(t);
            assert!((vel - c).length() < 1e-9 * c.length(), "{f}: {vel} vs {c}");
            let on_line = p.impact.point + c * (t - p.impact.time);
            assert!((pos - on_line).length() < 1e-9, "{f}: {pos}");
        }
    }

    #[test]
    fn no_plan_without_time_before_the_stroke() {
        let mut p = plan();
        p.impact.time = p.now + 0.05;
        assert!(RacketPath::plan(&p).is_none());
        let mut p = plan();
        p.return_time = 0.0;
        assert!(RacketPath::plan(&p).is_none());
        let mut p = plan();
        p.hit_length = 0.0;
        assert!(RacketPath::plan(&p).is_none());
    }

    #[test]
    fn the_smallest_path_has_nine_keys() {
        let mut p = plan();
        p.middle = 0;
        let path = RacketPath::plan(&p).unwrap();
        assert_eq!(path.keys().0.len(), 9);
        assert!((path.at(p.impact.time).0 - p.impact.point).length() < 1e-12);
    }
}
