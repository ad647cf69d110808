//! Tennis (thesis 5.6, 5.7): the pure parts the players' and the
//! referee's automata are made of — the match's scoring and calls, and
//! the stroke: impact estimation and learning, the hit, the racket's
//! timed spline.

pub mod call;
pub mod court;
pub mod ears;
pub mod eyes;
pub mod hit;
pub mod impact;
pub mod judge;
mod look;
pub mod player;
pub mod racket_path;
pub mod referee;
pub mod score;
#[cfg(test)]
mod test_ball;

/// What the tennis automata keep of an actor: its `tennis_state` (table
/// B6), and its game as a player or its match as the referee, once the
/// automata first runs.
#[derive(Debug, Default)]
pub struct Tennis {
    pub state: i64,
    pub player: Option<player::Player>,
    pub umpire: Option<referee::Umpire>,
}
