//! The particle table of code C.4.1.

use glam::DVec3;

use crate::lsys::expr::Expr;

/// Three compiled expressions of an `e` symbol: a field `f` (par1 = 10)
/// or an individual part `g` (par1 = 11) of eq. 2.3.1.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Law {
    pub f: [Option<Expr>; 3],
    /// Key of the random numbers `!`, `#`: the `e`'s id, so they are
    /// fixed for the particle's life as growth functions are.
    pub key: u64,
}

/// How a particle moves (symbol `C`, par1).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mode {
    /// Declared by `e` symbols, its `C` not yet interpreted: no position.
    Waiting,
    /// par1 = 0: evolved by eq. 2.3.1.
    Integrated,
    /// par1 = 1: placed at par4..6 each frame, velocity from positions.
    Placed,
    /// par1 = 6: placed at the turtle each frame, velocity from positions.
    Turtle,
    /// par1 = 5: placed at a racket actor each frame, velocity from
    /// positions, and moving on at that velocity while the integrated
    /// particles evolve to the next frame (a racket strikes while it
    /// moves: the ball must meet it where it is, not where it was).
    Racket,
}

/// One row of the particle table.
#[derive(Debug, Clone, PartialEq)]
pub struct Particle {
    /// Identifier of the `C` symbol that follows the particle's `e`s.
    pub id: u64,
    /// The L-system whose expressions the laws are.
    pub lsys: usize,
    pub mass: f64,
    pub pos: DVec3,
    pub vel: DVec3,
    pub mode: Mode,
    /// The field it exerts on the others (and on the turtle).
    pub field: Option<Law>,
    /// Cutoff radius of the field (`e` par1 = 10, par2 > 0): it acts only
    /// where r < reach, which lets [`super::grid`] skip far carriers.
    /// Infinite for an unbounded field.
    pub reach: f64,
    /// Its individual part g.
    pub own: Option<Law>,
    /// Global time of its initialisation: `t` in its laws is T − born.
    pub born: f64,
    /// Global time of its last placement (modes 1 and 6), for the
    /// velocity from successive positions.
    pub placed: f64,
    /// Swim phase in radians (code 4.1.1: phase += 0.2 · speed per
    /// second), read by `?20` and `?34`.
    pub phase: f64,
}

impl Particle {
    pub fn new(id: u64, lsys: usize) -> Self {
        Particle {
            id,
            lsys,
            mass: 1.0,
            pos: DVec3::ZERO,
            vel: DVec3::ZERO,
            mode: Mode::Waiting,
            field: None,
            reach: f64::INFINITY,
            own: None,
            born: 0.0,
            placed: 0.0,
            phase: 0.0,
        }
    }

    /// Whether it has a position (its `C` was interpreted).
    pub fn is_placed(&self) -> bool {
        self.mode != Mode::Waiting
    }

    /// Where a carrier is at time `t` of a step: a racket moves on at its
    /// velocity from its placement, the others stay where `C` put them.
    pub fn at(&self, t: f64) -> DVec3 {
        match self.mode {
            Mode::Racket => self.pos + self.vel * (t - self.placed),
            _ => self.pos,
        }
    }
}
