//! The stack machine that evaluates compiled expressions, and the special
//! functions of table B5 that the L-system layer answers itself.

use super::definition::Definition;
use super::expr::{Expr, Op, Param, MAX_DEPTH};
use super::functions::hermite;
use super::sensors::{FieldQuery, FieldValue, Sensors, Who};
use crate::random::{self, Stream};

/// Slots of the symbol memory read by `>`/`?44` and written by `<`.
pub const MEMORY_SLOTS: usize = 100;

/// What an expression's parameters refer to.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bindings {
    /// `T`: global time.
    pub time: f64,
    /// `t`: local age.
    pub age: f64,
    /// `x y z`.
    pub par: [f64; 3],
    /// `X Y Z u v w r` of the force-field semantics (zero otherwise).
    pub field: [f64; 7],
    /// Key of the random numbers `!` and `#` (slot = op position).
    pub key: u64,
    pub who: Who,
    /// Growth functions of the symbol, for `?41`–`?43`.
    pub growth: u32,
}

/// Mutable state of one L-system that expressions read and write.
#[derive(Debug, Clone)]
pub struct State {
    /// `fConst` arrays; `?15`, `?21`, `?23` store results in slot 7.
    pub fconst: Vec<[f64; 8]>,
    pub memory: [f64; MEMORY_SLOTS],
    /// The normal of the last `?15`'s racket, for `?16`, `?17`.
    pub racket_normal: [f64; 3],
}

impl State {
    pub fn new(def: &Definition) -> Self {
        State {
            fconst: def.fconst(),
            memory: [0.0; MEMORY_SLOTS],
            racket_normal: [0.0; 3],
        }
    }

    fn c(&self, i: usize, j: usize) -> f64 {
        self.fconst.get(i).map_or(0.0, |a| a[j])
    }

    fn set_c(&mut self, i: usize, j: usize, v: f64) {
        if self.fconst.len() <= i {
            self.fconst.resize(i + 1, [0.0; 8]);
        }
        self.fconst[i][j] = v;
    }
}

/// Evaluates expressions of one definition file.
pub struct Machine<'a> {
    pub def: &'a Definition,
    pub state: &'a mut State,
    pub sensors: &'a mut dyn Sensors,
    pub seed: u64,
    /// Repetition k of the L-structure, for `?21`.
    pub repetition: u64,
    /// Set while growth functions are evaluated for `?41`–`?43`, so a
    /// growth function that asks for itself gets 0 instead of recursing.
    in_growth: bool,
}

fn slot(v: f64) -> Option<usize> {
    (v >= 0.0 && v < MEMORY_SLOTS as f64).then_some(v as usize)
}

impl<'a> Machine<'a> {
    pub fn new(
        def: &'a Definition,
        state: &'a mut State,
        sensors: &'a mut dyn Sensors,
        seed: u64,
    ) -> Self {
        Machine {
            def,
            state,
            sensors,
            seed,
            repetition: 0,
            in_growth: false,
        }
    }

    #[inline]
    pub fn eval(&mut self, e: Expr, f: &Bindings) -> f64 {
        match e {
            Expr::Const(v) => v,
            Expr::Prog { start, len } => self.run(start as usize, len as usize, f),
        }
    }

    #[inline]
    pub fn eval_or(&mut self, e: Option<Expr>, f: &Bindings, default: f64) -> f64 {
        e.map_or(default, |e| self.eval(e, f))
    }

    /// The three growth function values of a symbol (0 where absent).
    pub fn growth(&mut self, f: &Bindings) -> [f64; 3] {
        let g = self.def.growth[f.growth as usize].f;
        let frame = Bindings {
            key: random::key(self.seed, Stream::Growth, f.who.symbol, 0),
            ..*f
        };
        let was = std::mem::replace(&mut self.in_growth, true);
        let v = [
            self.eval_or(g[0], &frame, 0.0),
            self.eval_or(g[1], &frame, 0.0),
            self.eval_or(g[2], &frame, 0.0),
        ];
        self.in_growth = was;
        v
    }

    fn run(&mut self, start: usize, len: usize, f: &Bindings) -> f64 {
        let def = self.def;
        let ops = &def.code.ops[start..start + len];
        let mut st = [0.0f64; MAX_DEPTH];
        let mut sp = 0usize;
        macro_rules! bin {
            ($e:expr) => {{
                sp -= 1;
                let b = st[sp];
                let a = st[sp - 1];
                st[sp - 1] = $e(a, b);
            }};
        }
        macro_rules! un {
            ($e:expr) => {{
                st[sp - 1] = $e(st[sp - 1]);
            }};
        }
        for (pc, &op) in ops.iter().enumerate() {
            match op {
                Op::Num(v) => {
                    st[sp] = v;
                    sp += 1;
                }
                Op::Param(p) => {
                    st[sp] = match p {
                        Param::Age => f.age,
                        Param::Time => f.time,
                        Param::Par(i) => f.par[i as usize],
                        Param::Other(i) => f.field[i as usize],
                        Param::Velocity(i) => f.field[3 + i as usize],
                        Param::Distance => f.field[6],
                    };
                    sp += 1;
                }
                Op::Constant(i) => {
                    st[sp] = def.constants.eval(i, f.time);
                    sp += 1;
                }
                Op::Rand => {
                    st[sp] = random::unit(f.key, (start + pc) as u64);
                    sp += 1;
                }
                Op::RandRange => {
                    let r = random::unit(f.key, (start + pc) as u64);
                    bin!(|a: f64, b: f64| a + b * r)
                }
                Op::Add => bin!(|a, b| a + b),
                Op::Sub => bin!(|a, b| a - b),
                Op::Mul => bin!(|a, b| a * b),
                Op::Div => bin!(|a, b| a / b),
                Op::Pow => bin!(f64::powf),
                Op::Mod => bin!(|a, b| a % b),
                Op::PostfixOp => bin!(|a, b| if a < b || a < 0.0 { 0.0 } else { 1.0 }),
                Op::MemSet => {
                    sp -= 1;
                    let v = st[sp];
                    if let Some(i) = slot(st[sp - 1]) {
                        self.state.memory[i] = v;
                    }
                    st[sp - 1] = v;
                }
                Op::Abs => un!(f64::abs),
                Op::Neg => un!(|a: f64| -a),
                Op::Sin => un!(|a: f64| a.to_radians().sin()),
                Op::Cos => un!(|a: f64| a.to_radians().cos()),
                Op::Asin => un!(|a: f64| a.asin().to_degrees()),
                Op::Tanh => un!(f64::tanh),
                Op::MemGet => {
                    let m = &self.state.memory;
                    un!(|a| slot(a).map_or(0.0, |i| m[i]))
                }
                Op::Lt => un!(|a| f64::from(a < 0.0)),
                Op::Le => un!(|a| f64::from(a <= 0.0)),
                Op::Gt => un!(|a| f64::from(a > 0.0)),
                Op::Ge => un!(|a| f64::from(a >= 0.0)),
                Op::Eq => un!(|a| f64::from(a == 0.0)),
                Op::Ne => un!(|a| f64::from(a != 0.0)),
                Op::And => bin!(|a, b| f64::from(a != 0.0 && b != 0.0)),
                Op::Or => bin!(|a, b| f64::from(a != 0.0 || b != 0.0)),
                Op::Not => un!(|a| f64::from(a == 0.0)),
                Op::Special(n) => match n {
                    3 | 8 | 29 => {
                        let a = st[sp - 1];
                        st[sp - 1] = self.unary_special(n, a);
                    }
                    50 => {
                        sp -= 1;
                        let arg = st[sp];
                        st[sp - 1] = self.sensors.channel(st[sp - 1], arg);
                    }
                    _ => {
                        st[sp] = self.special(n, f);
                        sp += 1;
                    }
                },
            }
        }
        st[0]
    }

    fn unary_special(&mut self, n: u8, a: f64) -> f64 {
        match n {
            3 => self.def.spline(3).map_or(0.0, |s| s.eval(a)),
            8 => a.clamp(0.0, 1.0),
            _ => {
                let s = &self.state;
                hermite(a + s.c(5, 3), s.c(5, 0), s.c(5, 1), s.c(5, 2))
            }
        }
    }

    /// Asks the world for tennis force field `code` at the symbol.
    fn tennis(&mut self, code: u8, f: &Bindings) -> FieldValue {
        let row = FieldQuery::row_of(code);
        let q = FieldQuery {
            code,
            at: f.par,
            field: f.field,
            row: self.state.fconst.get(row).copied().unwrap_or([0.0; 8]),
        };
        self.sensors.tennis(&q)
    }

    /// Nullary special functions (table B5).
    fn special(&mut self, n: u8, f: &Bindings) -> f64 {
        let [x, y, z] = f.par;
        let [ox, .., r] = f.field;
        let s = &mut *self.state;
        match n {
            0..=2 => self.def.spline(n as u32).map_or(0.0, |sp| sp.eval(f.age)),
            9 => {
                if r < 1e-20 {
                    1.0
                } else {
                    (ox - x) / r
                }
            }
            12..=14 => {
                let [p0, p1, p2] = self.def.constants.coefficients(b'P').unwrap_or_default();
                let q = [x, y, z][(n - 12) as usize];
                if q < p0 {
                    p2
                } else if q > p1 {
                    -p2
                } else {
                    0.0
                }
            }
            15 => {
                // Racket field (physics::tennis); ?16, ?17 read its force.
                let v = self.tennis(15, f);
                self.state.set_c(0, 7, v.force);
                self.state.racket_normal = v.normal;
                v.value
            }
            16 | 17 => s.c(0, 7) * s.racket_normal[(n - 15) as usize],
            18 | 20 | 25 => self.sensors.particle(n, f.who),
            19 | 26 | 27 => self.tennis(n, f).value,
            21 => {
                let key = random::key(
                    self.seed,
                    Stream::Repetition,
                    f.who.lsys as u64,
                    self.repetition,
                );
                // Base Const[3][2i] varied by ±half its spread Const[3][2i+1]
                // (the printed parentheses are garbled); slot 7 holds the
                // result, so the phase p3 is r3 · Const[3][6].
                let r = |i: u64| random::unit(key, i);
                let p = |i: usize| ((r(i as u64) - 0.5) * s.c(3, 2 * i + 1) + 1.0) * s.c(3, 2 * i);
                let v = p(0) + p(1) * (p(2) * f.time + r(3) * s.c(3, 6)).to_radians().sin();
                s.set_c(3, 7, v);
                v
            }
            22 => s.c(3, 7),
            23 => {
                let v = s.c(4, 0) * s.c(4, 1).powf(s.c(4, 2) * r.powf(s.c(4, 3))) / (r + s.c(4, 4));
                s.set_c(4, 7, v);
                v
            }
            24 => s.c(4, 7),
            28 => hermite(f.age + s.c(5, 3), s.c(5, 0), s.c(5, 1), s.c(5, 2)),
            34 => self.sensors.phase_degrees(f.who),
            30..=39 => self.sensors.actor(n, f.who),
            40 => self.sensors.force(f.par),
            41..=43 => {
                if self.in_growth {
                    0.0
                } else {
                    self.growth(f)[(n - 41) as usize]
                }
            }
            60 => self.sensors.sounds_playing(),
            61 => self.sensors.sound_of_source(x),
            62 => self.sensors.source_of_sound(x),
            _ => 0.0,
        }
    }
}
