//! What an expression may ask of the world outside the L-system.
//!
//! The L-system layer knows nothing of particles, actors or sound; the
//! special functions that need them (table B5) call this trait, which the
//! film driver implements. [`NoSensors`] gives the documented defaults used
//! when a scene is derived on its own (`lmfilm print`).

/// The symbol an expression is evaluated for: later layers map it to the
/// current actor or particle.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Who {
    /// Index of the L-system in the animation (file order).
    pub lsys: usize,
    /// Unique identifier of the symbol.
    pub symbol: u64,
}

pub trait Sensors {
    /// `?40`: magnitude of the force felt at `p` (the query symbol's x, y, z).
    fn force(&mut self, _p: [f64; 3]) -> f64 {
        0.0
    }

    /// `?30`–`?39`: vision and navigation state of the current actor.
    /// Default: nothing is seen (`?30` distance 1e30, `?31` 0, `?35` 0,
    /// every yes/no query −1).
    fn actor(&mut self, code: u8, _who: Who) -> f64 {
        match code {
            30 => 1e30,
            31 | 34 | 35 => 0.0,
            _ => -1.0,
        }
    }

    /// `?18`, `?20`, `?25`: gravity force and swim motor of the current
    /// particle. Default: a resting particle of mass 1 (`?18` = −9.81).
    fn particle(&mut self, code: u8, _who: Who) -> f64 {
        match code {
            18 => -9.81,
            _ => 0.0,
        }
    }

    /// `?15`, `?19`, `?26`, `?27` report how deep a particle is in a
    /// repelling field (`level`, 1 at full contact, 0 outside), so the
    /// integrator's peak detectors (thesis 7.4) can hear collisions.
    /// Default: nobody listens.
    fn contact(&mut self, _code: u8, _level: f64) {}

    /// `?34`: swim phase of the current particle in degrees. Default 0.
    fn phase_degrees(&mut self, _who: Who) -> f64 {
        0.0
    }

    /// `?50`: value of imported data channel `channel` at `arg`. Default 0.
    fn channel(&mut self, _channel: f64, _arg: f64) -> f64 {
        0.0
    }

    /// `?60`: number of on-going sound events. Default 0.
    fn sounds_playing(&mut self) -> f64 {
        0.0
    }

    /// `?61`: sound emitted by source `source`, −1 if none.
    fn sound_of_source(&mut self, _source: f64) -> f64 {
        -1.0
    }

    /// `?62`: source emitting sound `sound`, −1 if none.
    fn source_of_sound(&mut self, _sound: f64) -> f64 {
        -1.0
    }
}

/// The defaults of every sensor: an empty, silent world.
#[derive(Debug, Default, Clone, Copy)]
pub struct NoSensors;

impl Sensors for NoSensors {}
