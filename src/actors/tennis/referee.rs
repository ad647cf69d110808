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
use super::court::{side_of, BALL_LOW};
use super::ears::Ears;
use super::eyes::{Sightings, BALL};
use super::judge::{Heard, Judge, Verdict};
use super::score::Match;
use crate::actors::behaviour::{Script, Senses};
use crate::actors::live::state::{INIT_TENNIS_GAME, UPDATE_TENNIS_GAME};
use crate::actors::live::Living;
use crate::lsys::automata::Automata;

/// The collision sounds of table D.1 the referee judges.
const BALL_RACKET: u32 = 0;
const BALL_GROUND: u32 = 1;
const BALL_NET: u32 = 9;

/// What the referee keeps between frames.
#[derive(Debug, Clone, PartialEq)]
pub struct Umpire {
    pub game: Match,
    judge: Judge,
    /// The ball where vision placed it at the last frames.
    seen: Sightings,
    /// The collisions judged already.
    ears: Ears,
    /// What ended the last `tennis_error_detection`, for `referee`.
    verdict: Option<Verdict>,
    /// Every verdict given, with the time it was given: the match's
    /// record (what the calls said, in order).
    pub verdicts: Vec<(f64, Verdict)>,
}

impl Umpire {
    fn new(game: Match) -> Self {
        let judge = Judge::new(game.server(), game.half());
        Umpire {
            game,
            judge,
            seen: Sightings::default(),
            ears: Ears::default(),
            verdict: None,
            verdicts: Vec::new(),
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
        let lead = self
            .umpire
            .as_ref()
            .map_or(Vec3::ZERO, |u| u.seen.lead(senses.dt));
        if let Some(ball) = self.follow_thing(lead) {
            if let Some(u) = self.umpire.as_mut() {
                u.seen.push(senses.time, ball.position);
            }
        }
        let Some(u) = self.umpire.as_mut() else {
            // Without a match there is nothing to judge: the referee
            // automata starts one.
            return self.activate(Script::of(Automata::Referee));
        };
        let since = *self.progress.since.get_or_insert(senses.time);
        let heard = u.ears.news(senses.heard).into_iter();
        let collisions = heard
            .filter(|e| e.start >= since)
            .filter(|e| [BALL_RACKET, BALL_GROUND, BALL_NET].contains(&e.sound));
        for e in collisions {
            let (start, sound, from) = (e.start, e.sound, [e.position.x, e.position.z]);
            let event = match sound {
                BALL_NET => Heard::BallNet,
                // Which side of the net a stroke came from, the ear tells.
                BALL_RACKET => Heard::BallRacket {
                    striker: side_of(from),
                },
                // Where the ball bounced, the eyes tell; when they lost
                // it, the ear does, from where the sound came.
                _ => Heard::BallGround {
                    at: (u.seen.bounce(start, BALL_LOW, senses.dt)).map_or(from, |p| [p.x, p.z]),
                },
            };
            if let Some(v) = u.judge.hear(event) {
                u.verdict = Some(v);
                u.verdicts.push((senses.time, v));
                return self.pop();
            }
        }
    }
}
