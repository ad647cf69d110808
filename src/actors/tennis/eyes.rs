//! What the players and the referee make of what they see (5.6.1, 5.7):
//! the colour codes of the things of interest, and the ball's sightings
//! — where it was at a given moment, its velocity — as [`Sightings`].
//! How their eyes look for the thing and follow it is `look.rs`.

use std::collections::VecDeque;

use glam::{DVec3, Vec3};

/// `interest` numbers of the colour-coded things: the ball (material
/// 10), player 0 (11) and player 1 (12).
pub const BALL: i64 = 0;
pub fn player_thing(player: usize) -> i64 {
    1 + player as i64
}

/// The last sightings of the ball, (time, position), oldest first.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Sightings {
    seen: VecDeque<(f64, DVec3)>,
}

/// Sightings kept: enough for eq. 5.6.1's three frames.
const KEPT: usize = 4;
/// How long past its last sighting the ball's path is carried on (s).
const EXTRAPOLATE: f64 = 0.2;

impl Sightings {
    pub fn push(&mut self, time: f64, at: Vec3) {
        if self.seen.len() == KEPT {
            self.seen.pop_front();
        }
        self.seen.push_back((time, at.as_dvec3()));
    }

    pub fn clear(&mut self) {
        self.seen.clear();
    }

    /// The last sighting.
    pub fn last(&self) -> Option<(f64, DVec3)> {
        self.seen.back().copied()
    }

    /// Where the ball was at `t`: on the line through its last two
    /// sightings — between them, or on from the last one for at most
    /// `EXTRAPOLATE` seconds — or at its only sighting; None when the
    /// last sighting is too old to say.
    pub fn at(&self, t: f64) -> Option<DVec3> {
        let n = self.seen.len();
        let &(t1, p1) = self.seen.back()?;
        if t - t1 > EXTRAPOLATE {
            return None;
        }
        match n.checked_sub(2).map(|i| self.seen[i]) {
            Some((t0, p0)) if t1 > t0 => {
                let f = ((t - t0) / (t1 - t0)).max(0.0);
                Some(p0.lerp(p1, f))
            }
            _ => Some(p1),
        }
    }

    /// Where the ball bounced, from its last two sightings, the one
    /// before the bounce and the one after (a frame apart): the path
    /// falls and climbs back about as fast, so the bounce divides the
    /// segment between them as their heights above the ball's lowest
    /// point `low` do. None without two recent sightings.
    pub fn bounce(&self, t: f64, low: f64, dt: f64) -> Option<DVec3> {
        let n = self.seen.len();
        let ((t0, p0), (t1, p1)) = (self.seen[n.checked_sub(2)?], self.seen[n - 1]);
        if t1 - t0 > 2.5 * dt || (t - t1).abs() > 1.5 * dt {
            return None;
        }
        let (h0, h1) = ((p0.y - low).max(0.0), (p1.y - low).max(0.0));
        let f = if h0 + h1 > 0.0 { h0 / (h0 + h1) } else { 0.5 };
        Some(p0.lerp(p1, f))
    }

    /// The ball's motion over one frame `dt` at the last two sightings'
    /// velocity: how far ahead the eyes look.
    pub fn lead(&self, dt: f64) -> Vec3 {
        let n = self.seen.len();
        match n.checked_sub(2).map(|i| (self.seen[i], self.seen[n - 1])) {
            Some(((t0, p0), (t1, p1))) if t1 > t0 && t1 - t0 <= 2.5 * dt => {
                ((p1 - p0) * (dt / (t1 - t0))).as_vec3()
            }
            _ => Vec3::ZERO,
        }
    }

    /// Eq. 5.6.1 over the last `frames` frames of `dt`: the mean velocity,
    /// when the ball was seen at both ends of the window.
    pub fn velocity(&self, frames: u32, dt: f64) -> Option<DVec3> {
        let (t1, p1) = self.last()?;
        let window = f64::from(frames) * dt;
        let &(t0, p0) = self
            .seen
            .iter()
            .find(|s| ((t1 - s.0) - window).abs() < 0.25 * dt)?;
        (t1 > t0).then(|| (p1 - p0) / (t1 - t0))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A bounce is placed on the ball's path through its last two
    /// sightings, at the moment its sound began; before them, at the
    /// older; with one sighting, there; with none, nowhere.
    #[test]
    fn the_ball_is_placed_between_the_last_two_sightings() {
        let mut s = Sightings::default();
        assert_eq!(s.at(1.0), None);
        let near = |a: Option<DVec3>, b: [f64; 3]| (a.unwrap() - DVec3::from(b)).length() < 1e-6;
        s.push(1.0, Vec3::new(4.0, 0.2, 0.0));
        assert!(near(s.at(0.5), [4.0, 0.2, 0.0]));
        s.push(1.04, Vec3::new(5.0, 0.6, 1.0));
        let at = s.at(1.01).unwrap();
        assert!((at - DVec3::new(4.25, 0.3, 0.25)).length() < 1e-6, "{at}");
        // Carried on past the last sighting, for a while.
        assert!(near(s.at(1.08), [6.0, 1.0, 2.0]));
        assert_eq!(s.at(2.0), None);
        assert!(near(s.at(0.0), [4.0, 0.2, 0.0]));
    }

    /// A bounce lies between a sighting before it and one after, where
    /// their heights above the lowest point say.
    #[test]
    fn the_bounce_is_placed_by_the_heights_of_the_sightings() {
        let mut s = Sightings::default();
        s.push(1.0, Vec3::new(4.0, 0.4, 0.0));
        assert_eq!(s.bounce(1.0, 0.1, 0.04), None);
        s.push(1.04, Vec3::new(5.0, 0.2, 0.0));
        let at = s.bounce(1.04, 0.1, 0.04).unwrap();
        assert!((at.x - 4.75).abs() < 1e-6, "{at}");
        assert_eq!(s.bounce(2.0, 0.1, 0.04), None);
    }

    /// The velocity needs sightings three frames apart.
    #[test]
    fn velocity_over_three_frames() {
        let mut s = Sightings::default();
        let dt = 0.04;
        for k in [0, 1, 3] {
            s.push(k as f64 * dt, Vec3::new(k as f32, 0.0, 0.0));
        }
        let v = s.velocity(3, dt).unwrap();
        assert!((v.x - 25.0).abs() < 1e-4, "{v}");
        s.push(4.0 * dt, Vec3::new(4.0, 0.0, 0.0));
        s.push(5.0 * dt, Vec3::new(5.0, 0.0, 0.0));
        // The sighting of frame 2 is missing: no window of three frames.
        assert_eq!(s.velocity(3, dt), None);
    }
}
