//! The particle system of thesis 2.3.1: particles that carry force fields
//! and feel everyone else's (eq. 2.3.1), evolved by RK4 (appendix H).
//!
//! Particles are declared by the ephemeral `e` symbols at derivation
//! ([`Physics::register`]) and mapped to the turtle by `C` at
//! interpretation ([`Physics::start`], [`Physics::place`]). See
//! `docs/physics.md`.

mod grid;
pub mod particles;
pub mod peaks;
pub mod rk4;
pub mod tennis;

use std::collections::BTreeMap;
use std::sync::Arc;

use glam::DVec3;
use rayon::prelude::*;

use crate::lsys::eval::{Bindings, Machine, State};
use crate::lsys::options::OptionItem;
use crate::lsys::{Animation, Definition, FieldQuery, FieldValue, Sensors, Who};
use crate::random::{self, Stream};
use grid::Grid;
pub use particles::{Law, Mode, Particle};
pub use peaks::{Collision, Contact};

/// Size of the particle table when no `MaxPart` is declared.
pub const DEFAULT_MAX_PART: usize = 100_000;

/// `e` par1 values that declare a particle's laws (C.6).
const FIELD: f64 = 10.0;
const OWN: f64 = 11.0;

/// The global interaction table and what its laws need to be evaluated.
#[derive(Debug, Clone)]
pub struct Physics {
    /// The definitions the laws are compiled in, by L-system index.
    defs: Arc<[Definition]>,
    /// Their `fConst` and memories. Laws evaluate on copies, so what a
    /// law stores never depends on evaluation order or threads.
    states: Vec<State>,
    particles: Vec<Particle>,
    /// Row of each particle id.
    rows: BTreeMap<u64, usize>,
    max: usize,
    seed: u64,
    substeps: u32,
    /// Global time of the particles' positions.
    time: f64,
    /// Sum over every carrier even when fields are bounded (the thesis's
    /// O(n²) loop): the reference the grid must match, and the baseline
    /// of `benches/physics.rs`.
    all_pairs: bool,
    /// The peak detectors of 7.4.
    peaks: peaks::Peaks,
    /// The table as the film last sensed it, and its time (see
    /// [`Physics::sense`]).
    sensed: Vec<Particle>,
    sensed_time: f64,
}

/// Answers `?18` (gravity force of the current particle) while a law of
/// a particle of mass `mass` is evaluated; the other sensors keep their
/// defaults.
struct Body {
    mass: f64,
    /// Contact levels the law reported, for the peak detectors.
    levels: peaks::Levels,
}

impl Sensors for Body {
    fn particle(&mut self, code: u8, _who: Who) -> f64 {
        match code {
            18 => -9.81 * self.mass,
            _ => 0.0,
        }
    }

    /// `?15`, `?19`, `?26`, `?27`, whose contact levels the peak
    /// detectors hear.
    fn tennis(&mut self, q: &FieldQuery) -> FieldValue {
        let felt = tennis::field(q);
        peaks::record(&mut self.levels, q.code, felt.level);
        felt.field
    }
}

impl Physics {
    /// An empty table for the animation's definitions: `MaxPart` of the
    /// first file that declares it, `nbrCalcStep_seed` sub-steps.
    pub fn new(anim: &Animation) -> Self {
        let defs: Arc<[Definition]> = anim.systems.iter().map(|s| s.def.clone()).collect();
        let max = defs
            .iter()
            .flat_map(|d| &d.options)
            .find_map(|o| match o {
                OptionItem::MaxPart(n) => Some((*n).max(0) as usize),
                _ => None,
            })
            .unwrap_or(DEFAULT_MAX_PART);
        Physics {
            states: defs.iter().map(State::new).collect(),
            defs,
            particles: Vec::new(),
            rows: BTreeMap::new(),
            max,
            seed: anim.camera.seed,
            substeps: anim.camera.nbr_calc_step.clamp(1, 1 << 20) as u32,
            time: anim.time(),
            all_pairs: false,
            peaks: peaks::Peaks::default(),
            sensed: Vec::new(),
            sensed_time: anim.time(),
        }
    }

    /// Evaluates bounded fields by looking at every carrier (`true`) or
    /// only at those in the grid cells around each particle (`false`, the
    /// default). Both give the same bits; only the cost differs.
    pub fn set_all_pairs(&mut self, on: bool) {
        self.all_pairs = on;
    }

    /// Every particle of the table, placed or not, in declaration order.
    pub fn particles(&self) -> &[Particle] {
        &self.particles
    }

    /// The particle of `C` symbol `id`, if it has been placed.
    pub fn get(&self, id: u64) -> Option<&Particle> {
        let p = &self.particles[*self.rows.get(&id)?];
        p.is_placed().then_some(p)
    }

    /// Global time of the particles' state.
    pub fn time(&self) -> f64 {
        self.time
    }

    /// Reads the `e` events of the last derivation step (or the axioms):
    /// each declares the field (par1 = 10, cutoff radius par2 when > 0)
    /// or the individual part (par1 = 11) of the particle of the symbol
    /// that follows it.
    pub fn register(&mut self, anim: &Animation) -> Result<(), String> {
        for ls in &anim.systems {
            for e in ls.events() {
                if e.par[0] != FIELD && e.par[0] != OWN {
                    continue;
                }
                let (Some(s), Some(g)) = (
                    ls.word().get(e.position),
                    ls.def.growth.get(e.growth as usize),
                ) else {
                    continue;
                };
                let row = match self.rows.get(&s.id) {
                    Some(&r) => r,
                    None => {
                        if self.particles.len() >= self.max {
                            return Err(format!(
                                "{}: more particles than MaxPart = {} (declare a larger `MaxPart` in the Options section)",
                                ls.def.name, self.max
                            ));
                        }
                        self.rows.insert(s.id, self.particles.len());
                        self.particles.push(Particle::new(s.id, ls.index));
                        self.particles.len() - 1
                    }
                };
                let law = Law {
                    f: g.f,
                    key: random::key(self.seed, Stream::Growth, e.id, 0),
                };
                let p = &mut self.particles[row];
                if e.par[0] == FIELD {
                    p.field = Some(law);
                    p.reach = if e.par[1] > 0.0 {
                        e.par[1]
                    } else {
                        f64::INFINITY
                    };
                } else {
                    p.own = Some(law);
                }
            }
        }
        Ok(())
    }

    /// `C` par1 = 0 at local age < Δt: the particle starts at `at` with
    /// `mass` (≤ 0 or not a number: 1, as code 7.1.1 leaves it empty) and
    /// velocity `vel`. Returns false if `id` declares no particle.
    pub fn start(&mut self, id: u64, at: DVec3, mass: f64, vel: DVec3) -> bool {
        let Some(&row) = self.rows.get(&id) else {
            return false;
        };
        let p = &mut self.particles[row];
        p.mode = Mode::Integrated;
        p.mass = if mass > 0.0 && mass.is_finite() {
            mass
        } else {
            1.0
        };
        p.pos = at;
        p.vel = vel;
        p.born = self.time;
        p.placed = self.time;
        true
    }

    /// A tennis server's toss (5.6): the ball — the first particle in
    /// table order that `C` par1 = 0 started — is at `at` with velocity
    /// `vel` from now on. False when the film has no such particle.
    pub fn toss(&mut self, at: DVec3, vel: DVec3) -> bool {
        let Some(ball) = self
            .particles
            .iter_mut()
            .find(|p| p.mode == Mode::Integrated)
        else {
            return false;
        };
        ball.pos = at;
        ball.vel = vel;
        ball.placed = self.time;
        true
    }

    /// `C` par1 = 1 (`mode` [`Mode::Placed`]), 5 ([`Mode::Racket`]) or 6
    /// ([`Mode::Turtle`]):
    /// the particle is at `at`; its velocity comes from its previous
    /// placement, one frame or more ago.
    pub fn place(&mut self, id: u64, at: DVec3, mode: Mode) {
        let Some(&row) = self.rows.get(&id) else {
            return;
        };
        let time = self.time;
        let p = &mut self.particles[row];
        if p.mode != mode {
            p.mode = mode;
            p.vel = DVec3::ZERO;
            p.born = time;
        } else if time > p.placed {
            p.vel = (at - p.pos) / (time - p.placed);
        }
        p.pos = at;
        p.placed = time;
    }

    /// The global field Σ f_k at `at` (tropism): every placed particle's
    /// field that reaches `at`, in table order.
    pub fn field_at(&self, at: DVec3) -> DVec3 {
        self.field_of(&self.particles, self.time, at)
    }

    /// The field of the table `particles` at time `time`.
    fn field_of(&self, particles: &[Particle], time: f64, at: DVec3) -> DVec3 {
        let mut laws = Laws::new(self);
        let mut f = DVec3::ZERO;
        for q in particles {
            let r = at.distance(q.pos);
            if let (true, true, Some(law)) = (q.is_placed(), reaches(q.reach, r), q.field) {
                f += laws.field(q, law, at, q.pos, q.vel, r, time);
            }
        }
        f
    }

    /// The touch sensors take their reading (DESIGN §1 step 3): the table
    /// as it stands at the end of a frame's interpretation is what
    /// expressions sense (`?20`, `?34`, `?40`) from that frame's
    /// derivation through the next frame's interpretation, while the
    /// table itself evolves and the turtle places particles. The copy
    /// reuses its buffer from frame to frame.
    pub fn sense(&mut self) {
        self.sensed.clone_from(&self.particles);
        self.sensed_time = self.time;
    }

    /// What the touch sensors read at their last reading.
    pub fn touch(&self) -> Touch<'_> {
        Touch { physics: self }
    }

    /// Evolves the integrated particles from the current time to `to`
    /// with `nbrCalcStep` RK4 sub-steps; the others stay where `C` put
    /// them and act through their fields.
    pub fn evolve(&mut self, to: f64) {
        let from = self.time;
        let moving: Vec<usize> = (0..self.particles.len())
            .filter(|&i| self.particles[i].mode == Mode::Integrated)
            .collect();
        let forward = to > from && (to - from).is_finite();
        if moving.is_empty() || !forward {
            self.time = to;
            return;
        }
        let mut pos: Vec<DVec3> = self.particles.iter().map(|p| p.pos).collect();
        let mut vel: Vec<DVec3> = self.particles.iter().map(|p| p.vel).collect();
        let mut y = vec![0.0; 6 * moving.len()];
        for (j, &i) in moving.iter().enumerate() {
            y[6 * j..6 * j + 3].copy_from_slice(&pos[i].to_array());
            y[6 * j + 3..6 * j + 6].copy_from_slice(&vel[i].to_array());
        }
        let rackets: Vec<usize> = (0..self.particles.len())
            .filter(|&i| self.particles[i].mode == Mode::Racket)
            .collect();
        let h = (to - from) / f64::from(self.substeps);
        for s in 0..self.substeps {
            let t = from + f64::from(s) * h;
            rk4::step(&mut y, t, h, |t, y, dy| {
                for (j, &i) in moving.iter().enumerate() {
                    pos[i] = DVec3::from_slice(&y[6 * j..6 * j + 3]);
                    vel[i] = DVec3::from_slice(&y[6 * j + 3..6 * j + 6]);
                }
                for &i in &rackets {
                    pos[i] = self.particles[i].at(t);
                }
                let carriers = self.carriers(&pos);
                // One task per particle, each summing in table order: the
                // same numbers whatever the thread count.
                let acc: Vec<DVec3> = moving
                    .par_iter()
                    .map_init(
                        || (Laws::new(self), Vec::new()),
                        |(laws, rows), &i| {
                            self.acceleration(i, &pos, &vel, t, &carriers, laws, rows)
                        },
                    )
                    .collect();
                for (j, &i) in moving.iter().enumerate() {
                    dy[6 * j..6 * j + 3].copy_from_slice(&vel[i].to_array());
                    dy[6 * j + 3..6 * j + 6].copy_from_slice(&acc[j].to_array());
                }
            });
            self.detect(&moving, &y, t + h);
        }
        for (j, &i) in moving.iter().enumerate() {
            let p = &mut self.particles[i];
            p.pos = DVec3::from_slice(&y[6 * j..6 * j + 3]);
            p.vel = DVec3::from_slice(&y[6 * j + 3..6 * j + 6]);
            // Code 4.1.1's swim motor: the tail beats faster as it swims.
            p.phase += 0.2 * p.vel.length() * (to - from);
        }
        self.time = to;
    }

    /// The carriers of fields at the positions `pos` of an RK4 stage.
    fn carriers(&self, pos: &[DVec3]) -> Carriers {
        let mut far = Vec::new();
        let mut near = Vec::new();
        let mut reach = 0.0f64;
        for (k, q) in self.particles.iter().enumerate() {
            if !q.is_placed() || q.field.is_none() {
                continue;
            }
            if self.all_pairs || q.reach == f64::INFINITY {
                far.push(k as u32);
            } else {
                near.push((k, pos[k], q.reach));
                reach = reach.max(q.reach);
            }
        }
        let grid = (!near.is_empty()).then(|| Grid::new(reach, near.into_iter()));
        Carriers { far, grid }
    }

    /// Eq. 2.3.1: (g_i + Σ_{k≠i} f_k) / m_i with the positions and
    /// velocities of an RK4 stage, f_k summed in table order over the
    /// carriers that reach x_i. `laws` and `rows` are the task's scratch,
    /// reset here so the result does not depend on what ran before.
    #[allow(clippy::too_many_arguments)]
    fn acceleration(
        &self,
        i: usize,
        pos: &[DVec3],
        vel: &[DVec3],
        t: f64,
        carriers: &Carriers,
        laws: &mut Laws,
        rows: &mut Vec<(u32, f64)>,
    ) -> DVec3 {
        laws.reset(self);
        let p = &self.particles[i];
        let at = pos[i];
        let mut f = match p.own {
            Some(law) => laws.own(p, law, at, vel[i], t),
            None => DVec3::ZERO,
        };
        let mut pull = |k: usize, r: f64| {
            let q = &self.particles[k];
            if let (true, Some(law)) = (k != i, q.field) {
                f += laws.field(q, law, at, pos[k], vel[k], r, t);
            }
        };
        match &carriers.grid {
            None => {
                for &k in &carriers.far {
                    let k = k as usize;
                    let r = at.distance(pos[k]);
                    if reaches(self.particles[k].reach, r) {
                        pull(k, r);
                    }
                }
            }
            Some(grid) => {
                // Unbounded carriers and the bounded ones within reach,
                // back in table order.
                rows.clear();
                rows.extend(
                    carriers
                        .far
                        .iter()
                        .map(|&k| (k, at.distance(pos[k as usize]))),
                );
                grid.near(at, |k, r| rows.push((k as u32, r)));
                rows.sort_unstable_by_key(|&(k, _)| k);
                for &(k, r) in rows.iter() {
                    pull(k as usize, r);
                }
            }
        }
        f / p.mass
    }
}

/// The particle table as the touch sensors last read it
/// ([`Physics::sense`]).
#[derive(Clone, Copy)]
pub struct Touch<'a> {
    physics: &'a Physics,
}

impl Touch<'_> {
    /// `?40`: the global field at `at`.
    pub fn field_at(&self, at: DVec3) -> DVec3 {
        let p = self.physics;
        p.field_of(&p.sensed, p.sensed_time, at)
    }

    /// The particle of `C` symbol `id`, if it had been placed.
    pub fn get(&self, id: u64) -> Option<&Particle> {
        let p = self.physics;
        let q = p.sensed.get(*p.rows.get(&id)?)?;
        q.is_placed().then_some(q)
    }
}

/// Whether a field of cutoff `reach` acts at distance `r`: always when
/// unbounded (as in the thesis, even for a NaN distance), else r < reach.
fn reaches(reach: f64, r: f64) -> bool {
    reach == f64::INFINITY || r < reach
}

/// Who acts on whom during one RK4 stage.
struct Carriers {
    /// Placed carriers summed without the grid, in table order: the
    /// unbounded fields, or every field in all-pairs mode.
    far: Vec<u32>,
    /// The placed carriers of bounded fields, if any.
    grid: Option<Grid>,
}

/// Evaluates laws on private copies of the L-systems' states.
struct Laws<'a> {
    defs: &'a [Definition],
    states: Vec<State>,
    seed: u64,
    /// Deepest contact levels the evaluated laws reported.
    levels: peaks::Levels,
}

impl<'a> Laws<'a> {
    fn new(ph: &'a Physics) -> Self {
        Laws {
            defs: &ph.defs,
            states: ph.states.clone(),
            seed: ph.seed,
            levels: [0.0; 3],
        }
    }

    /// Back to the L-systems' states, reusing the copies' memory instead
    /// of allocating a fresh clone per particle and RK4 stage. The
    /// destructuring makes a new `State` field a compile error here.
    fn reset(&mut self, ph: &Physics) {
        for (mine, theirs) in self.states.iter_mut().zip(&ph.states) {
            let State {
                fconst,
                memory,
                racket_normal,
            } = theirs;
            mine.fconst.clone_from(fconst);
            mine.memory = *memory;
            mine.racket_normal = *racket_normal;
        }
    }

    /// Field `law` of carrier `q` (at `from`, velocity `u`) felt at `at`:
    /// x y z = `at`, X Y Z = `from`, u v w = the carrier's velocity
    /// (eq. 2.3.1: f_k depends on ẋ_k), r = their distance.
    #[allow(clippy::too_many_arguments)]
    fn field(
        &mut self,
        q: &Particle,
        law: Law,
        at: DVec3,
        from: DVec3,
        u: DVec3,
        r: f64,
        t: f64,
    ) -> DVec3 {
        let field = [from.x, from.y, from.z, u.x, u.y, u.z, r];
        self.eval(q, law, at, field, t)
    }

    /// Individual part `law` of `p` at `at` with velocity `u`: x y z and
    /// u v w are its own, X Y Z and r are 0.
    fn own(&mut self, p: &Particle, law: Law, at: DVec3, u: DVec3, t: f64) -> DVec3 {
        self.eval(p, law, at, [0.0, 0.0, 0.0, u.x, u.y, u.z, 0.0], t)
    }

    fn eval(&mut self, p: &Particle, law: Law, at: DVec3, field: [f64; 7], t: f64) -> DVec3 {
        let (Some(def), Some(state)) = (self.defs.get(p.lsys), self.states.get_mut(p.lsys)) else {
            return DVec3::ZERO;
        };
        let frame = Bindings {
            time: t,
            age: t - p.born,
            par: at.to_array(),
            field,
            key: law.key,
            who: Who {
                lsys: p.lsys,
                symbol: p.id,
                actor: None,
            },
            growth: 0,
        };
        let mut body = Body {
            mass: p.mass,
            levels: self.levels,
        };
        let mut m = Machine::new(def, state, &mut body, self.seed);
        let f = DVec3::new(
            m.eval_or(law.f[0], &frame, 0.0),
            m.eval_or(law.f[1], &frame, 0.0),
            m.eval_or(law.f[2], &frame, 0.0),
        );
        self.levels = body.levels;
        f
    }
}
