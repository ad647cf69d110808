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
    /// The current actor of the symbol's branch: the last `M` par1 = 7
    /// before it in the branch or the branches enclosing it (C.5).
    pub actor: Option<u32>,
}

/// What the L-system knows when it asks for a tennis force field
/// (`?15`, `?19`, `?26`, `?27`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FieldQuery {
    /// The special function: 15, 19, 26 or 27.
    pub code: u8,
    /// `x y z` of the query symbol.
    pub at: [f64; 3],
    /// `X Y Z u v w r` of the force-field semantics (zero otherwise).
    pub field: [f64; 7],
    /// The `fConst` row the function reads ([`FieldQuery::row_of`]),
    /// zeros where the file declares none.
    pub row: [f64; 8],
}

impl FieldQuery {
    /// The `fConst` row read by special function `code`: 0 (racket),
    /// 1 (net), 5 (ground), 6 (wall).
    pub fn row_of(code: u8) -> usize {
        match code {
            15 => 0,
            19 => 1,
            26 => 5,
            _ => 6,
        }
    }
}

/// The answer to a [`FieldQuery`].
#[derive(Debug, Default, Clone, Copy, PartialEq)]
pub struct FieldValue {
    /// The value of the special function.
    pub value: f64,
    /// `?15`: the racket force F, which the L-system stores in
    /// `Const[0][7]` for `?16`, `?17`; 0 for the others.
    pub force: f64,
    /// `?15`: the racket's normal n, which `?16`, `?17` take the y and z
    /// of (it may be the racket's motion, not `Const[0][0..2]`).
    pub normal: [f64; 3],
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

    /// `?15`, `?19`, `?26`, `?27`: the tennis force fields (racket, net,
    /// ground, wall; thesis 7.1), computed by the physics layer
    /// (`physics::tennis`). An implementation that feels them also hears
    /// how deep the query is in the repelling field, for the integrator's
    /// peak detectors (thesis 7.4). Default: a world without physics has
    /// no field (value and force 0).
    fn tennis(&mut self, _q: &FieldQuery) -> FieldValue {
        FieldValue::default()
    }

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
