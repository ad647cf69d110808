//! Peak detectors of thesis 7.4 (fig. 7.4.1): when a repelling force
//! passes a threshold during a collision, a collision is reported.
//!
//! The repelling functions (`?15` racket, `?19` net, `?26`/`?27` ground)
//! report how deep a particle is in them (a level, 1 at full contact)
//! through [`crate::lsys::Sensors::contact`]. After each RK4 sub-step the
//! integrated particles' levels are read at their new state; a level
//! rising to [`THRESHOLD`] is one collision, and the detector re-arms only
//! once the level has fallen below [`REARM`], so one bounce is one event.
//! Physics reports collisions as plain data; the film layer turns them
//! into sound events (DESIGN §2: physics sits below sound).

use glam::DVec3;
use rayon::prelude::*;

use crate::lsys::expr::{Expr, Op};
use crate::lsys::Definition;

mod detect;

/// Level at which a rising contact is a collision.
pub const THRESHOLD: f64 = 0.5;
/// Level below which the contact has ended and the detector re-arms.
pub const REARM: f64 = 0.25;

/// What a particle collided with.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Contact {
    /// `?26`, `?27`.
    Ground,
    /// `?15`.
    Racket,
    /// `?19`.
    Net,
}

impl Contact {
    const ALL: [Contact; 3] = [Contact::Ground, Contact::Racket, Contact::Net];

    /// The kind of contact a special function reports, if any.
    pub fn of(code: u8) -> Option<Contact> {
        match code {
            26 | 27 => Some(Contact::Ground),
            15 => Some(Contact::Racket),
            19 => Some(Contact::Net),
            _ => None,
        }
    }

    /// Its sound in table D.1: ball_ground 1, ball_racket 0, ball_net 9.
    pub fn sound(self) -> u32 {
        match self {
            Contact::Ground => 1,
            Contact::Racket => 0,
            Contact::Net => 9,
        }
    }

    fn index(self) -> usize {
        self as usize
    }
}

/// Deepest level of each [`Contact`] met by one evaluation.
pub type Levels = [f64; 3];

/// Records the deepest level of each kind of contact.
pub(super) fn record(levels: &mut Levels, code: u8, level: f64) {
    if let Some(c) = Contact::of(code) {
        let l = &mut levels[c.index()];
        // NaN levels are ignored: a broken law makes no sound.
        if level > *l {
            *l = level;
        }
    }
}

/// One collision found by a peak detector.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Collision {
    /// Row of the particle in the table (declaration order).
    pub row: usize,
    pub kind: Contact,
    /// Global time of the sub-step that crossed the threshold.
    pub time: f64,
    /// The particle's position then.
    pub at: DVec3,
}

/// The detectors' state: which particles are in contact, and the
/// collisions not yet taken.
#[derive(Debug, Clone, Default)]
pub struct Peaks {
    touching: Vec<[bool; 3]>,
    found: Vec<Collision>,
}

/// Whether an expression calls a repelling function.
fn repels(def: &Definition, e: Option<Expr>) -> bool {
    match e {
        Some(Expr::Prog { start, len }) => def
            .code
            .ops
            .get(start as usize..start as usize + len as usize)
            .is_some_and(|ops| {
                ops.iter()
                    .any(|op| matches!(op, Op::Special(n) if Contact::of(*n).is_some()))
            }),
        _ => false,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_deepest_level_of_each_kind_is_kept() {
        let mut l: Levels = [0.0; 3];
        record(&mut l, 27, 0.3);
        record(&mut l, 26, 0.7);
        record(&mut l, 27, 0.5);
        record(&mut l, 19, f64::NAN);
        record(&mut l, 18, 5.0);
        assert_eq!(l, [0.7, 0.0, 0.0]);
        assert_eq!(Contact::of(15).map(Contact::sound), Some(0));
        assert_eq!(Contact::of(19).map(Contact::sound), Some(9));
    }
}
