//! The referee's automata (`referee`, `tennis_error_detection`, thesis
//! 5.7) as the actor runs them, over the umpire state of the parent
//! module.

use super::*;
use crate::actors::live::Living;
use crate::actors::state::{INIT_TENNIS_GAME, UPDATE_TENNIS_GAME};

impl Living {
    /// `referee` (5.7): at the first run, init_tennis_game (a one-set
    /// match, green serving) and the first service's call; after each
    /// error, update_tennis_game and its call. The call is said by
    /// `talk`, then `tennis_error_detection` watches the next service;
    /// after the match's last call the next behaviour runs.
    pub(in crate::actors) fn referee(&mut self) {
        let words = match self.tennis.umpire.as_mut() {
            None => {
                self.state = INIT_TENNIS_GAME;
                let umpire = Umpire::new(Match::default());
                let words = call::service(&umpire.game).to_vec();
                self.tennis.umpire = Some(umpire);
                words
            }
            Some(u) => {
                self.state = UPDATE_TENNIS_GAME;
                let Some(verdict) = u.verdict.take() else {
                    // Nothing to call: watch the play.
                    return self.activate(Behaviour::of(Automata::TennisErrorDetection));
                };
                let words = call::update(&mut u.game, verdict);
                u.judge = Judge::new(u.game.server(), u.game.half());
                words
            }
        };
        let finished = self
            .tennis
            .umpire
            .as_ref()
            .is_some_and(|u| u.game.finished());
        if !finished {
            self.push(Behaviour::of(Automata::Referee));
            self.push(Behaviour::of(Automata::TennisErrorDetection));
        }
        self.conversation.words = words;
        self.activate(Behaviour::of(Automata::Talk));
    }

    /// `tennis_error_detection` (5.7): follows the ball with its eyes and
    /// gives the collisions heard since it started to the judge, in the
    /// order they began; a verdict ends it.
    pub(in crate::actors) fn tennis_error_detection(&mut self, senses: &Senses) {
        self.interest = Some(BALL);
        let lead = self
            .tennis
            .umpire
            .as_ref()
            .map_or(Vec3::ZERO, |u| u.seen.lead(senses.dt));
        if let Some(ball) = self.follow_thing(lead) {
            if let Some(u) = self.tennis.umpire.as_mut() {
                u.seen.push(senses.time, ball.position);
            }
        }
        let Some(u) = self.tennis.umpire.as_mut() else {
            // Without a match there is nothing to judge: the referee
            // automata starts one.
            return self.activate(Behaviour::of(Automata::Referee));
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
