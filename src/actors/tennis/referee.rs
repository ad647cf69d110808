//! The referee (thesis 5.7): two automata. `tennis_error_detection`
//! tracks the ball with its eyes and judges the collisions it hears;
//! when a service or a point ends it stops, and `referee` updates the
//! match, puts the call in `words_to_speak` and says it through `talk`.
//!
//! The referee perceives only: where the ball is comes from its vision
//! (the thing of interest, material 10), when it hit the ground, a racket
//! or the net from the sounds it hears (table D.1: 1, 0, 9), and from
//! which side of the net a stroke came from where its sound came from.
//! Where the ball bounced is read off its path as vision saw it at the
//! last two frames, at the moment the sound began.

use glam::Vec3;

use super::call;
use super::court::side_of;
use super::judge::{Heard, Judge, Verdict};
use super::score::Match;
use crate::actors::behaviour::{Script, Senses};
use crate::actors::live::state::{FIX_THING, INIT_TENNIS_GAME, LOOK_AROUND, UPDATE_TENNIS_GAME};
use crate::actors::live::Living;
use crate::lsys::automata::Automata;

/// The collision sounds of table D.1 the referee judges.
const BALL_RACKET: u32 = 0;
const BALL_GROUND: u32 = 1;
const BALL_NET: u32 = 9;

/// `interest` number of the ball (material 10).
const BALL: i64 = 0;
/// The view angle a search for the ball starts with (5.7: 40°), and the
/// narrowest and widest it zooms to, in tenths of a degree.
const SEARCH_FOV: i64 = 400;
const MIN_FOV: i64 = 20;
const MAX_FOV: i64 = 1200;
/// Vision keeps the thing it follows between these many pixels, zooming
/// by 1.5 (5.6.1).
const MIN_PIXELS: u32 = 5;
const MAX_PIXELS: u32 = 12;
const ZOOM: f64 = 1.5;

/// What the referee keeps between frames.
#[derive(Debug, Clone, PartialEq)]
pub struct Umpire {
    pub game: Match,
    judge: Judge,
    /// The ball where vision placed it at the last two frames, the older
    /// first: (time, position).
    seen: [Option<(f64, Vec3)>; 2],
    /// Collisions that began before this are judged already.
    heard_until: f64,
    /// What ended the last `tennis_error_detection`, for `referee`.
    verdict: Option<Verdict>,
}

impl Umpire {
    fn new(game: Match) -> Self {
        let judge = Judge::new(game.server(), game.half());
        Umpire {
            game,
            judge,
            seen: [None; 2],
            heard_until: f64::NEG_INFINITY,
            verdict: None,
        }
    }

    /// Where the ball was at `t` as vision saw it: on the line between
    /// its last two sightings (a frame apart), or the nearest of them.
    fn ball_at(&self, t: f64) -> Option<Vec3> {
        match self.seen {
            [Some((t0, p0)), Some((t1, p1))] if t1 > t0 => {
                let f = ((t - t0) / (t1 - t0)).clamp(0.0, 1.0);
                Some(p0.lerp(p1, f as f32))
            }
            [_, Some((_, p))] | [Some((_, p)), None] => Some(p),
            [None, None] => None,
        }
    }
}

impl Living {
    /// `referee` (5.7): at the first run, init_tennis_game (a one-set
    /// match, green serving) and the first service's call; after each
    /// error, update_tennis_game and its call. The call is said by
    /// `talk`, then `tennis_error_detection` watches the next service;
    /// after the match's last call the next behaviour runs.
    pub(in crate::actors) fn referee(&mut self) {
        let words = match self.umpire.as_mut() {
            None => {
                self.state = INIT_TENNIS_GAME;
                let umpire = Umpire::new(Match::default());
                let words = call::service(&umpire.game).to_vec();
                self.umpire = Some(umpire);
                words
            }
            Some(u) => {
                self.state = UPDATE_TENNIS_GAME;
                let Some(verdict) = u.verdict.take() else {
                    // Nothing to call: watch the play.
                    return self.activate(Script::of(Automata::TennisErrorDetection));
                };
                let words = call::update(&mut u.game, verdict);
                u.judge = Judge::new(u.game.server(), u.game.half());
                words
            }
        };
        let finished = self.umpire.as_ref().is_some_and(|u| u.game.finished());
        if !finished {
            self.push(Script::of(Automata::Referee));
            self.push(Script::of(Automata::TennisErrorDetection));
        }
        self.words = words;
        self.activate(Script::of(Automata::Talk));
    }

    /// `tennis_error_detection` (5.7): follows the ball with its eyes and
    /// gives the collisions heard since it started to the judge, in the
    /// order they began; a verdict ends it.
    pub(in crate::actors) fn tennis_error_detection(&mut self, senses: &Senses) {
        self.interest = Some(BALL);
        self.follow_ball(senses.time);
        let Some(u) = self.umpire.as_mut() else {
            // Without a match there is nothing to judge: the referee
            // automata starts one.
            return self.activate(Script::of(Automata::Referee));
        };
        let since = *self.progress.since.get_or_insert(senses.time);
        let mut heard: Vec<(f64, u32, [f64; 2])> = senses
            .heard
            .iter()
            .filter(|e| e.start >= since && e.start > u.heard_until)
            .filter(|e| [BALL_RACKET, BALL_GROUND, BALL_NET].contains(&e.sound))
            .map(|e| (e.start, e.sound, [e.position.x, e.position.z]))
            .collect();
        heard.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        for (start, sound, from) in heard {
            u.heard_until = start;
            let seen = u.ball_at(start).map(|p| [f64::from(p.x), f64::from(p.z)]);
            let event = match (sound, seen) {
                (BALL_NET, _) => Heard::BallNet,
                // Which side of the net a stroke came from, the ear tells.
                (BALL_RACKET, _) => Heard::BallRacket {
                    striker: side_of(from),
                },
                (BALL_GROUND, Some(at)) => Heard::BallGround { at },
                // A bounce heard with the ball never seen: nothing to
                // judge where it fell by.
                _ => continue,
            };
            if let Some(v) = u.judge.hear(event) {
                u.verdict = Some(v);
                return self.pop();
            }
        }
    }

    /// The vision part of both tennis automata (5.6.1, 5.7): look for the
    /// ball with a 40° view (look_around_set, then look_around: the eyes
    /// turn half a view a frame), then follow it (fix_thing), zooming to
    /// keep it between 5 and 12 pixels; lost, look for it again.
    fn follow_ball(&mut self, time: f64) {
        match self.percepts.as_ref().and_then(|p| p.thing) {
            Some(ball) => {
                self.state = FIX_THING;
                self.look_at = ball.position;
                if ball.pixels < MIN_PIXELS {
                    self.fov = ((self.fov as f64 / ZOOM) as i64).max(MIN_FOV);
                } else if ball.pixels > MAX_PIXELS {
                    self.fov = ((self.fov as f64 * ZOOM) as i64).min(MAX_FOV);
                }
                if let Some(u) = self.umpire.as_mut() {
                    u.seen = [u.seen[1], Some((time, ball.position))];
                }
            }
            None if self.state == LOOK_AROUND => self.turn_eyes(self.half_view()),
            None => {
                self.state = LOOK_AROUND;
                self.fov = SEARCH_FOV;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A bounce is placed on the ball's path between its last two
    /// sightings, at the moment its sound began; outside them, at the
    /// nearest; with one sighting, there; with none, nowhere.
    #[test]
    fn the_bounce_is_placed_between_the_last_two_sightings() {
        let mut u = Umpire::new(Match::default());
        assert_eq!(u.ball_at(1.0), None);
        u.seen = [None, Some((1.0, Vec3::new(4.0, 0.2, 0.0)))];
        assert_eq!(u.ball_at(0.5), Some(Vec3::new(4.0, 0.2, 0.0)));
        u.seen = [u.seen[1], Some((1.04, Vec3::new(5.0, 0.6, 1.0)))];
        let at = u.ball_at(1.01).unwrap();
        assert!((at - Vec3::new(4.25, 0.3, 0.25)).length() < 1e-5, "{at}");
        assert_eq!(u.ball_at(2.0), Some(Vec3::new(5.0, 0.6, 1.0)));
        assert_eq!(u.ball_at(0.0), Some(Vec3::new(4.0, 0.2, 0.0)));
    }
}
