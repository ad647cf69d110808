//! One L-system and its iterative step function S (definition 2.1.4).
//!
//! The word lives in two buffers, the current and the next, swapped after
//! each step: memory for two words and no more (2.1.3).

use super::context::{left_matches, right_matches};
use super::definition::{Definition, Production, RightSide, SymbolTemplate};
use super::eval::{Bindings, Machine, State};
use super::expr::Expr;
use super::sensors::{Sensors, Who};
use super::word::{branch_end, Symbol};
use crate::random::{self, Stream};

/// An ephemeral `e` symbol met while deriving (appendix C.6): it never
/// enters the word; later layers create particles or push automata from it.
#[derive(Debug, Clone, PartialEq)]
pub struct Ephemeral {
    /// Index in the new word of the symbol that follows the `e` (the `C`
    /// that carries the particle, for instance).
    pub position: usize,
    /// Unique identifier given to the `e` itself.
    pub id: u64,
    /// par1..par3 (par1 selects the meaning: 0 automata, 10, 11 fields).
    pub par: [f64; 3],
    /// Its growth functions: field expressions or the automata text.
    pub growth: u32,
    /// The current actor where it stands (its branch's `M` par1 = 7).
    pub actor: Option<u32>,
}

/// Where a cut symbol in an applied right side sends the old branch.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Cut {
    /// `](i)`, −100 < i < 0 (5.10): the whole branch enclosing the
    /// replaced symbol, brackets included, gives way to the right side.
    Branch,
    /// `](100)`: the rest of the enclosing branch after the replaced
    /// symbol is eliminated with all its sub-branches.
    Rest,
}

/// The output state at an open branch, to roll back to for a cut.
#[derive(Debug, Clone, Copy)]
struct Mark {
    open: usize,
    out: usize,
    ids: u64,
    events: usize,
}

/// The current actor along a word read left to right (C.5): an `M`
/// par1 = 7 makes actor par3 current for the symbols after it in its
/// branch and the branches it opens; closing the branch restores the one
/// before.
#[derive(Debug, Default)]
pub struct ActorScope {
    saved: Vec<Option<u32>>,
    current: Option<u32>,
}

impl ActorScope {
    /// A scope whose current actor is `actor` to begin with.
    pub fn starting(actor: Option<u32>) -> Self {
        ActorScope {
            saved: Vec::new(),
            current: actor,
        }
    }

    /// The current actor of `s`, the next symbol of the word.
    pub fn visit(&mut self, s: &Symbol) -> Option<u32> {
        let [kind, _, actor] = s.par;
        if s.is_push() {
            self.saved.push(self.current);
        } else if s.is_pop() {
            self.leave();
        } else if s.ch == b'M' && kind == 7.0 {
            // A number that names no actor (negative, fractional, NaN)
            // leaves the current actor; the turtle warns of it.
            if (0.0..=f64::from(u32::MAX)).contains(&actor) && actor.fract() == 0.0 {
                self.current = Some(actor as u32);
            }
        }
        self.current
    }

    /// Leaves the innermost open branch (a cut removed its end).
    pub fn leave(&mut self) {
        if let Some(a) = self.saved.pop() {
            self.current = a;
        }
    }
}

/// Keys of the axiom's random parameter expressions (no replaced symbol).
const AXIOM_KEY: u64 = u64::MAX - 1024;

/// One L-system: its definition, its word and the state its expressions
/// keep from step to step.
pub struct LSystem {
    pub def: Definition,
    /// Position in the animation (file order).
    pub index: usize,
    pub state: State,
    /// This L-system's time step: Δt times its `time_scale`.
    pub dt: f64,
    word: Vec<Symbol>,
    next: Vec<Symbol>,
    /// Productions by left-side character: a range of `order`.
    by_char: Vec<(u32, u32)>,
    order: Vec<u32>,
    events: Vec<Ephemeral>,
    scratch: Scratch,
    marks: Vec<Mark>,
    /// Id counter to resume from after a cut rolled the output back.
    pending_ids: Option<u64>,
}

impl LSystem {
    /// Builds the L-system and its initial word from the axiom; ids are
    /// drawn from `ids` left to right.
    pub fn new(
        def: Definition,
        index: usize,
        dt: f64,
        seed: u64,
        ids: &mut u64,
        sensors: &mut dyn Sensors,
    ) -> Self {
        let mut by_char = vec![(0u32, 0u32); 256];
        let mut order = Vec::with_capacity(def.productions.len());
        for c in 0..=255u8 {
            let start = order.len() as u32;
            order.extend(
                def.productions
                    .iter()
                    .enumerate()
                    .filter(|(_, p)| p.lhs == c)
                    .map(|(k, _)| k as u32),
            );
            by_char[c as usize] = (start, order.len() as u32 - start);
        }
        let scale = def.repetition.time_scale;
        let state = State::new(&def);
        let mut ls = LSystem {
            def,
            index,
            state,
            dt: if scale > 0.0 { dt * scale } else { dt },
            word: Vec::new(),
            next: Vec::new(),
            by_char,
            order,
            events: Vec::new(),
            scratch: Scratch::default(),
            marks: Vec::new(),
            pending_ids: None,
        };
        let frame = Bindings {
            time: 0.0,
            age: 0.0,
            par: [0.0; 3],
            field: [0.0; 7],
            key: 0,
            who: Who {
                lsys: index,
                symbol: AXIOM_KEY - index as u64,
                actor: None,
            },
            growth: 0,
        };
        let mut m = Machine::new(&ls.def, &mut ls.state, sensors, seed);
        // A cut in the axiom has no branch to act on: it is dropped.
        ls.scratch.fill(&mut m, &ls.def.axiom, &frame);
        ls.word.clear();
        ls.append_scratch(ids);
        std::mem::swap(&mut ls.word, &mut ls.next);
        ls
    }

    /// The current word.
    pub fn word(&self) -> &[Symbol] {
        &self.word
    }

    /// The word, for layers that write into it (the query symbol `?`).
    pub fn word_mut(&mut self) -> &mut [Symbol] {
        &mut self.word
    }

    /// The ephemeral symbols met by the last step (or the axiom).
    pub fn events(&self) -> &[Ephemeral] {
        &self.events
    }

    /// Growth function values of `s` at global time `time`, with
    /// `actor` the current actor of its branch.
    pub fn growth(
        &mut self,
        s: &Symbol,
        time: f64,
        actor: Option<u32>,
        seed: u64,
        sensors: &mut dyn Sensors,
    ) -> [f64; 3] {
        if s.growth == 0 {
            return [0.0; 3];
        }
        let frame = self.frame(s, time, 0, actor);
        Machine::new(&self.def, &mut self.state, sensors, seed).growth(&frame)
    }

    fn frame(&self, s: &Symbol, time: f64, key: u64, actor: Option<u32>) -> Bindings {
        Bindings {
            time,
            age: s.age(self.dt),
            par: s.par,
            field: [0.0; 7],
            key,
            who: Who {
                lsys: self.index,
                symbol: s.id,
                actor,
            },
            growth: s.growth,
        }
    }

    /// S: derives the word at `time + dt` from the word at `time`.
    /// `step` numbers the step (keys of random conditions). A next word
    /// of more than `max_symbols` symbols is never allocated: the step
    /// stops, the word stays as it was, and the error holds how many
    /// symbols the next word had reached.
    pub fn step(
        &mut self,
        time: f64,
        step: u64,
        seed: u64,
        ids: &mut u64,
        sensors: &mut dyn Sensors,
        max_symbols: usize,
    ) -> Result<(), usize> {
        self.events.clear();
        let limit = self.def.repetition.time_const;
        if limit > 0.0 && time > limit {
            return Ok(());
        }
        let old = std::mem::take(&mut self.word);
        self.next.clear();
        self.marks.clear();
        let start_ids = *ids;
        let n = old.len();
        let mut i = 0;
        let mut scope = ActorScope::default();
        while i < n {
            let s = old[i];
            let actor = scope.visit(&s);
            if s.is_push() {
                self.marks.push(Mark {
                    open: i,
                    out: self.next.len(),
                    ids: *ids,
                    events: self.events.len(),
                });
            } else if s.is_pop() {
                self.marks.pop();
            }
            let (lo, count) = self.by_char[s.ch as usize];
            if count > 0 {
                let at = (time, step, actor);
                if let Some(p) = self.applicable(&old, i, lo, count, at, seed, sensors) {
                    let prod = &self.def.productions[p as usize];
                    let part = choose(prod, seed, s.id, p);
                    let frame = self.frame(&s, time, 0, actor);
                    let templates = &self.def.productions[p as usize].parts[part].symbols;
                    let mut m = Machine::new(&self.def, &mut self.state, sensors, seed);
                    let cut = self.scratch.fill(&mut m, templates, &frame);
                    i = match cut {
                        None => i + 1,
                        Some(Cut::Branch) => match self.marks.pop() {
                            Some(m) => {
                                scope.leave();
                                self.rollback(m.out, m.ids, m.events);
                                branch_end(&old, m.open + 1).map_or(n, |e| e + 1)
                            }
                            None => {
                                self.rollback(0, start_ids, 0);
                                n
                            }
                        },
                        Some(Cut::Rest) => match self.marks.last() {
                            Some(_) => branch_end(&old, i + 1).unwrap_or(n),
                            None => n,
                        },
                    };
                    if let Err(need) = room(&mut self.next, self.scratch.symbols.len(), max_symbols)
                    {
                        self.word = old;
                        return Err(need);
                    }
                    self.append_scratch(ids);
                    continue;
                }
            }
            // Axiom 2: the symbol keeps ageing.
            if let Err(need) = room(&mut self.next, 1, max_symbols) {
                self.word = old;
                return Err(need);
            }
            let mut s = s;
            s.ticks += 1;
            self.next.push(s);
            i += 1;
        }
        self.word = old;
        std::mem::swap(&mut self.word, &mut self.next);
        Ok(())
    }

    /// The first production, in file order, whose age, context and
    /// condition hold for `old[i]`.
    #[allow(clippy::too_many_arguments)]
    fn applicable(
        &mut self,
        old: &[Symbol],
        i: usize,
        lo: u32,
        count: u32,
        (time, step, actor): (f64, u64, Option<u32>),
        seed: u64,
        sensors: &mut dyn Sensors,
    ) -> Option<u32> {
        let s = &old[i];
        let next_age = s.birth + f64::from(s.ticks + 1) * self.dt;
        // Ages are compared with a tolerance far below Δt (DESIGN §3).
        let eps = self.dt * 1e-6;
        let mut frame = self.frame(s, time, 0, actor);
        let mut m = Machine::new(&self.def, &mut self.state, sensors, seed);
        for &p in &self.order[lo as usize..(lo + count) as usize] {
            let prod: &Production = &m.def.productions[p as usize];
            // The random key costs a few hashes: only programs need it.
            if frame.key == 0
                && (prod.condition.is_some() || matches!(prod.max_age, Expr::Prog { .. }))
            {
                frame.key = random::key(seed, Stream::Condition, s.id, step);
            }
            if next_age < m.eval(prod.max_age, &frame) - eps {
                continue;
            }
            if prod.left.is_some_and(|c| !left_matches(old, i, c)) {
                continue;
            }
            if prod.right.is_some_and(|c| !right_matches(old, i, c)) {
                continue;
            }
            if let Some(c) = prod.condition {
                if m.eval(c, &frame) == 0.0 {
                    continue;
                }
            }
            return Some(p);
        }
        None
    }

    fn rollback(&mut self, out: usize, ids_at: u64, events: usize) {
        self.next.truncate(out);
        self.events.truncate(events);
        // Identifiers handed out in the removed part are handed out again.
        self.pending_ids = Some(ids_at);
    }

    /// Moves `scratch` to the end of the next word, numbering symbols and
    /// `e` events left to right.
    fn append_scratch(&mut self, ids: &mut u64) {
        if let Some(at) = self.pending_ids.take() {
            *ids = at;
        }
        let base = self.next.len();
        let mut ev = self.scratch.events.drain(..).peekable();
        for (k, mut s) in self.scratch.symbols.drain(..).enumerate() {
            while let Some(mut e) = ev.next_if(|e| e.position == k) {
                e.id = *ids;
                *ids += 1;
                e.position += base;
                self.events.push(e);
            }
            s.id = *ids;
            *ids += 1;
            self.next.push(s);
        }
        for mut e in ev {
            e.id = *ids;
            *ids += 1;
            e.position += base;
            self.events.push(e);
        }
    }
}

/// Makes room in `next` for `more` symbols, growing it by doubling but
/// never past `max` symbols: a word over the limit is refused before it
/// is allocated. The error is the length `next` would need.
fn room(next: &mut Vec<Symbol>, more: usize, max: usize) -> Result<(), usize> {
    let need = next.len().saturating_add(more);
    if need > max {
        return Err(need);
    }
    if need > next.capacity() {
        let want = next.capacity().saturating_mul(2).clamp(need, max);
        next.reserve_exact(want - next.len());
    }
    Ok(())
}

/// Symbols and events of one applied right side, before they get ids.
#[derive(Default)]
struct Scratch {
    symbols: Vec<Symbol>,
    events: Vec<Ephemeral>,
}

impl Scratch {
    /// Evaluates templates (ids not yet assigned); returns the first cut
    /// met. Parameter expressions refer to `frame`, the replaced symbol;
    /// `!` in them is keyed by the template's position.
    fn fill(
        &mut self,
        m: &mut Machine,
        templates: &[SymbolTemplate],
        frame: &Bindings,
    ) -> Option<Cut> {
        self.symbols.clear();
        self.events.clear();
        let mut cut = None;
        let mut scope = ActorScope::starting(frame.who.actor);
        for (j, t) in templates.iter().enumerate() {
            let programs = [t.age, t.par[0], t.par[1], t.par[2]];
            let key = if programs
                .iter()
                .any(|e| matches!(e, Some(Expr::Prog { .. })))
            {
                random::key(m.seed, Stream::Parameter, frame.who.symbol, j as u64)
            } else {
                0
            };
            let f = Bindings { key, ..*frame };
            let birth = m.eval_or(t.age, &f, 0.0);
            let par = [
                m.eval_or(t.par[0], &f, 0.0),
                m.eval_or(t.par[1], &f, 0.0),
                m.eval_or(t.par[2], &f, 0.0),
            ];
            match t.ch {
                b']' if par[0] < 0.0 && par[0] > -100.0 => {
                    cut = cut.or(Some(Cut::Branch));
                }
                b']' if par[0] == 100.0 => {
                    cut = cut.or(Some(Cut::Rest));
                }
                b'e' => self.events.push(Ephemeral {
                    position: self.symbols.len(),
                    id: 0,
                    par,
                    growth: t.growth,
                    actor: scope.current,
                }),
                ch => {
                    let symbol = Symbol {
                        id: 0,
                        birth,
                        par,
                        growth: t.growth,
                        ticks: 0,
                        ch,
                        origin: u32::try_from(t.offset).unwrap_or(super::word::NO_ORIGIN),
                    };
                    scope.visit(&symbol);
                    self.symbols.push(symbol);
                }
            }
        }
        cut
    }
}

/// Picks a probability part, keyed on the symbol so the choice does not
/// depend on evaluation order; probabilities are normalised by their sum.
fn choose(p: &Production, seed: u64, id: u64, prod: u32) -> usize {
    if p.parts.len() == 1 {
        return 0;
    }
    let r = random::unit(random::key(seed, Stream::Choice, id, u64::from(prod)), 0) * p.total;
    let mut acc = 0.0;
    for (k, part) in p.parts.iter().enumerate() {
        acc += part.probability;
        if r < acc {
            return k;
        }
    }
    last_positive(&p.parts)
}

fn last_positive(parts: &[RightSide]) -> usize {
    parts.iter().rposition(|p| p.probability > 0.0).unwrap_or(0)
}
