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
use crate::actors::behaviour::{Behaviour, Senses};
use crate::lsys::automata::Automata;

mod referee_automata;

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
