//! Actors (thesis 3.1, 5): the actor table built from the Options
//! section's `NBR_actors`, `iVisionWinSize` and `actorNbr_automata` —
//! each actor's vision window and its automata stack with their typed
//! commands, refusing with a located error what no actor could run — and
//! the actors themselves: their state ([`live`]), what they perceive
//! (vision into the frame's BVH, the visual memory it feeds, their
//! images), how they plan (path search, heuristics, spline, footholds)
//! and the automata that act on it (behaviour, navigation, tennis);
//! docs/actors.md.

pub mod behaviour;
pub mod footholds;
pub mod live;
pub mod navigate;
pub mod perception;
pub mod planning;
pub mod state;
pub mod tennis;

use crate::lsys::automata::{ActorAutomata, Automata, AutomataCommand, CommandAt, Located, Span};
use crate::lsys::options::OptionItem;
use crate::lsys::Animation;
use crate::source::Diagnostic;
use planning::heuristics::{self, Kind};

/// Most actors a scene may declare.
pub const MAX_ACTORS: i64 = 100_000;

/// Edge lengths a vision window may have, in pixels.
pub const WINDOW_EDGES: std::ops::RangeInclusive<i64> = 1..=1024;

/// Most pixels the actors' vision windows may have together: what one
/// frame's sense step casts and keeps (about 52 bytes a pixel, 220 MB),
/// and the most points it can insert into the memories (docs/limits.md).
pub const MAX_VISION_PIXELS: u64 = 1 << 22;

/// Most sound events one `listen` may wait for.
pub const MAX_HEARD: i64 = 10_000;

/// Most colours a window may tell apart (24-bit colours).
pub const MAX_COLORS: i64 = 1 << 24;

/// Most voxels along an edge of the `init` world cube (an octree of
/// depth 20 at most).
pub const MAX_VOXELS_PER_EDGE: f64 = (1u64 << 20) as f64;

/// An actor's vision window (`iVisionWinSize`): edge × edge pixels and
/// the number of flat colours it recognises.
#[derive(Debug, Clone, PartialEq)]
pub struct VisionWindow {
    pub edge: u32,
    pub max_colors: u32,
    /// Where it was declared.
    pub span: Span,
}

/// One automata on an actor's stack, with the commands that configure
/// it, in the order the file gives them.
#[derive(Debug, Clone, PartialEq)]
pub struct StackEntry {
    pub automata: Automata,
    /// The automata's number or name in the file.
    pub span: Span,
    pub commands: Vec<CommandAt>,
}

/// An actor as the scene declares it.
#[derive(Debug, Clone, PartialEq)]
pub struct Actor {
    id: usize,
    vision: Option<VisionWindow>,
    stack: Vec<StackEntry>,
}

impl Actor {
    /// Its number, 0..NBR_actors.
    pub fn id(&self) -> usize {
        self.id
    }

    /// Its vision window, if `iVisionWinSize` declares one.
    pub fn vision(&self) -> Option<&VisionWindow> {
        self.vision.as_ref()
    }

    /// Its automata in declaration order: the first runs first (the
    /// user's sequence is pushed on the actor's behaviour stack, 5.1).
    pub fn automata(&self) -> &[StackEntry] {
        &self.stack
    }
}

/// The actors of a scene, indexed by number.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Table {
    actors: Vec<Actor>,
}

impl Table {
    /// The table the Options sections of every L-system of `anim`
    /// declare; empty when none declares actors.
    pub fn from_animation(anim: &Animation) -> Result<Table, Diagnostic> {
        let table = Table::from_options(anim.systems.iter().flat_map(|s| &s.def.options))?;
        // The behaviour command strings of the `e` symbols (C.6).
        let scripts = anim.systems.iter().flat_map(|s| &s.def.growth);
        for script in scripts.filter_map(|g| g.script.as_ref()) {
            let n = table.actors.len();
            match &script.actor {
                Some(a) if !(0..n as i64).contains(&a.value) => {
                    return Err(a.error(format!(
                        "actor {} does not exist: the scene has {n} actors (NBR_actors)",
                        a.value
                    )))
                }
                None if n == 0 => {
                    return Err(script
                        .automata
                        .error("a behaviour for an actor, and the scene has none (NBR_actors)"))
                }
                _ => {}
            }
            for c in &script.commands {
                check(c)?;
            }
        }
        Ok(table)
    }

    /// The table of these options (of one or several files, in order).
    pub fn from_options<'a>(
        options: impl IntoIterator<Item = &'a OptionItem>,
    ) -> Result<Table, Diagnostic> {
        let options: Vec<&OptionItem> = options.into_iter().collect();
        // NBR_actors first: it may come after the actors' options.
        let mut count: Option<&Located<i64>> = None;
        for o in &options {
            if let OptionItem::NbrActors(n) = o {
                if !(0..=MAX_ACTORS).contains(&n.value) {
                    return Err(n.error(format!(
                        "the number of actors must be 0..={MAX_ACTORS}, found {}",
                        n.value
                    )));
                }
                match count {
                    Some(first) if first.value != n.value => {
                        return Err(n.error(format!(
                            "`NBR_actors {}` disagrees with `NBR_actors {}` at {}",
                            n.value, first.value, first.span
                        )))
                    }
                    Some(_) => {}
                    None => count = Some(n),
                }
            }
        }
        let n = count.map_or(0, |c| c.value);
        let mut actors: Vec<Actor> = (0..n as usize)
            .map(|id| Actor {
                id,
                vision: None,
                stack: Vec::new(),
            })
            .collect();
        let actor_index = |a: &Located<i64>, what: &str| -> Result<usize, Diagnostic> {
            match count {
                None => Err(a.error(format!(
                    "`{what}` names actor {}, but no `NBR_actors` declares the actors; add `NBR_actors N` to the Options section",
                    a.value
                ))),
                Some(_) if !(0..n).contains(&a.value) => Err(a.error(format!(
                    "actor {} does not exist: `NBR_actors {n}` declares actors 0..={}",
                    a.value,
                    n - 1
                ))),
                Some(_) => Ok(a.value as usize),
            }
        };
        let mut pixels = 0u64;
        for o in &options {
            match o {
                OptionItem::VisionWinSize {
                    actor,
                    edge,
                    max_colors,
                } => {
                    let i = actor_index(actor, "iVisionWinSize")?;
                    if !WINDOW_EDGES.contains(&edge.value) {
                        return Err(edge.error(format!(
                            "the vision window edge must be {}..={} pixels, found {}",
                            WINDOW_EDGES.start(),
                            WINDOW_EDGES.end(),
                            edge.value
                        )));
                    }
                    if !(0..=MAX_COLORS).contains(&max_colors.value) {
                        return Err(max_colors.error(format!(
                            "the maximal number of colours must be 0..={MAX_COLORS}, found {}",
                            max_colors.value
                        )));
                    }
                    if let Some(first) = &actors[i].vision {
                        return Err(actor.error(format!(
                            "actor {i} already has a vision window, declared at {}",
                            first.span
                        )));
                    }
                    pixels += (edge.value * edge.value) as u64;
                    if pixels > MAX_VISION_PIXELS {
                        return Err(edge.error(format!(
                            "the actors' vision windows would have {pixels} pixels together, more than {MAX_VISION_PIXELS} (four windows of 1024 × 1024); make them smaller"
                        )));
                    }
                    actors[i].vision = Some(VisionWindow {
                        edge: edge.value as u32,
                        max_colors: max_colors.value as u32,
                        span: actor.span.clone(),
                    });
                }
                OptionItem::ActorAutomata(ActorAutomata {
                    actor,
                    automata,
                    commands,
                }) => {
                    let i = actor_index(actor, "actorNbr_automata")?;
                    for c in commands {
                        check(c)?;
                    }
                    actors[i].stack.push(StackEntry {
                        automata: automata.value,
                        span: automata.span.clone(),
                        commands: commands.clone(),
                    });
                }
                _ => {}
            }
        }
        Ok(Table { actors })
    }

    /// The actors, by number.
    pub fn actors(&self) -> &[Actor] {
        &self.actors
    }

    pub fn get(&self, id: usize) -> Option<&Actor> {
        self.actors.get(id)
    }

    pub fn len(&self) -> usize {
        self.actors.len()
    }

    pub fn is_empty(&self) -> bool {
        self.actors.is_empty()
    }
}

/// The checks an automata command's arguments share; each refusal
/// points at the argument, counted from the last one backwards (0 =
/// last: optional arguments come first).
struct Check<'a>(&'a CommandAt);

/// Whole numbers without an upper bound of their own.
const BIG: i64 = i64::MAX;

impl Check<'_> {
    fn refuse(&self, k: usize, what: String) -> Result<(), Diagnostic> {
        let name = self.0.keyword;
        Err(self.0.arg_error_from_end(k, format!("`{name}`: {what}")))
    }

    fn int_in(&self, k: usize, v: i64, lo: i64, hi: i64, what: &str) -> Result<(), Diagnostic> {
        if (lo..=hi).contains(&v) {
            Ok(())
        } else {
            self.refuse(k, format!("{what} must be {lo}..={hi}, found {v}"))
        }
    }

    fn at_least(&self, k: usize, v: f64, lo: f64, what: &str) -> Result<(), Diagnostic> {
        if v >= lo {
            Ok(())
        } else {
            self.refuse(k, format!("{what} must be at least {lo}, found {v}"))
        }
    }

    fn positive(&self, k: usize, v: f64, what: &str) -> Result<(), Diagnostic> {
        if v > 0.0 {
            Ok(())
        } else {
            self.refuse(k, format!("{what} must be greater than 0, found {v}"))
        }
    }

    fn index(&self, k: usize, i: Option<i64>) -> Result<(), Diagnostic> {
        match i {
            Some(i) => self.int_in(k, i, 0, BIG, "the local goal number"),
            None => Ok(()),
        }
    }

    /// A number of table G.1 of the kind the command needs.
    fn heuristic_of(&self, n: i64, kind: Kind, what: &str) -> Result<(), Diagnostic> {
        let found = u32::try_from(n).ok().and_then(heuristics::heuristic);
        if found.is_some_and(|h| h.kind == kind) {
            return Ok(());
        }
        let numbers: Vec<String> = heuristics::HEURISTICS
            .iter()
            .filter(|h| h.kind == kind)
            .map(|h| h.number.to_string())
            .collect();
        self.refuse(
            0,
            format!("{n} is not {what} of table G.1: {}", numbers.join(", ")),
        )
    }

    /// `init`: the memory display modulo and the world cube, cut into at
    /// most [`MAX_VOXELS_PER_EDGE`] voxels a side.
    fn world_cube(
        &self,
        display_every: i64,
        min: f64,
        max: f64,
        voxel_edge: f64,
    ) -> Result<(), Diagnostic> {
        self.int_in(3, display_every, 0, BIG, "the memory display modulo")?;
        if min >= max {
            return self.refuse(
                1,
                format!(
                    "the world cube's maximum must be greater than its minimum {min}, found {max}"
                ),
            );
        }
        self.positive(0, voxel_edge, "the voxel edge")?;
        if (max - min) / voxel_edge > MAX_VOXELS_PER_EDGE {
            return self.refuse(
                0,
                format!(
                    "a voxel edge of {voxel_edge} cuts the world cube's edge {} into more than {MAX_VOXELS_PER_EDGE} voxels",
                    max - min
                ),
            );
        }
        Ok(())
    }

    /// `eps_look_at[_goal] [n] threshold`: a scalar product of unit vectors.
    fn look_threshold(&self, i: Option<i64>, threshold: f64) -> Result<(), Diagnostic> {
        self.index(1, i)?;
        if (-1.0..=1.0).contains(&threshold) {
            Ok(())
        } else {
            self.refuse(
                0,
                format!(
                    "the threshold is a scalar product of unit vectors, -1..=1, found {threshold}"
                ),
            )
        }
    }

    /// `vision_range near far memory_range`.
    fn vision_range(&self, near: f64, far: f64, memory_range: f64) -> Result<(), Diagnostic> {
        self.at_least(2, near, 0.0, "the near distance")?;
        if far <= near {
            return self.refuse(
                1,
                format!(
                    "the far distance must be greater than the near distance {near}, found {far}"
                ),
            );
        }
        self.at_least(0, memory_range, 0.0, "the memory update range")
    }

    /// `step_weights`: weights and exponents, none negative.
    fn step_weights(&self, w: &[f64; 6]) -> Result<(), Diagnostic> {
        for (k, v) in w.iter().enumerate() {
            let what = if k % 2 == 0 {
                "a weight"
            } else {
                "an exponent"
            };
            self.at_least(5 - k, *v, 0.0, what)?;
        }
        Ok(())
    }

    /// `foothold_map range min_voxels [foot]`.
    fn foothold_map(
        &self,
        range: f64,
        min_voxels: i64,
        foot: Option<f64>,
    ) -> Result<(), Diagnostic> {
        let k = usize::from(foot.is_some());
        self.positive(1 + k, range, "the map's range")?;
        self.int_in(k, min_voxels, 1, BIG, "the smallest foothold (voxels)")?;
        match foot {
            Some(f) => self.at_least(0, f, 0.0, "the largest foothold"),
            None => Ok(()),
        }
    }
}

/// Refuses a command whose arguments no actor could use; the error
/// points at the offending argument.
fn check(c: &CommandAt) -> Result<(), Diagnostic> {
    use AutomataCommand as C;
    let ck = Check(c);
    match &c.command {
        C::KeyframeDef { n, .. } => ck.int_in(1, *n, 0, BIG, "the track number"),
        C::CollTestFunc(n) => ck.heuristic_of(*n, Kind::Test, "a collision test"),
        C::Heuristic(n) => ck.heuristic_of(*n, Kind::Search, "a search heuristic"),
        // The logarithmic level of B.6 / appendix G: 0 is the memory's
        // own voxel, 1 twice its edge, …
        C::RelSearchLevel(Some(x)) if (0.0..=20.0).contains(x) && x.fract() == 0.0 => Ok(()),
        C::RelSearchLevel(Some(x)) => ck.refuse(
            0,
            format!(
                "the logarithmic relative search level must be a whole number 0..=20 (search voxels of 2^level memory voxels a side), found {x}"
            ),
        ),
        C::RelSearchLevel(None) => Ok(()),
        C::LocalGoal { index: i, .. } => ck.index(3, *i),
        C::RgbInterest { rgb, active } => {
            for (k, v) in rgb.iter().enumerate() {
                ck.int_in(3 - k, *v, 0, 255, "a colour component")?;
            }
            ck.int_in(0, *active, 0, 1, "the switch (1 on, 0 off)")
        }
        C::EpsArrived { index: i, distance } => {
            ck.index(1, *i)?;
            // Arrived is closer than the distance: at 0 none ever is.
            ck.positive(
                0,
                *distance,
                "the arrival distance (arrived is closer than it: at 0 no actor ever arrives)",
            )
        }
        C::EpsLookAtGoal {
            index: i,
            threshold,
        }
        | C::EpsLookAt {
            index: i,
            threshold,
        } => ck.look_threshold(*i, *threshold),
        C::Turtle(n) => ck.int_in(0, *n, 0, 4, "the turtle mapping"),
        C::Init {
            display_every,
            min,
            max,
            voxel_edge,
        } => ck.world_cube(*display_every, *min, *max, *voxel_edge),
        C::Fov(n) => ck.int_in(0, *n, 1, 1799, "the view angle (tenths of a degree)"),
        C::Interest { active, thing } => {
            ck.int_in(1, *active, 0, 1, "the switch (1 on, 0 off)")?;
            ck.int_in(
                0,
                *thing,
                0,
                2,
                "the thing of interest (0 ball, 1 player 0, 2 player 1)",
            )
        }
        C::SizeActor(x) => ck.at_least(0, *x, 0.0, "the actor size"),
        C::DistColl(x) => ck.at_least(0, *x, 0.0, "the collision distance"),
        C::TennisState(n) => ck.int_in(0, *n, 0, 13, "the tennis state"),
        C::State(n) => ck.int_in(0, *n, 0, 26, "the vision state"),
        C::OptimRate(n) => ck.int_in(0, *n, 1, BIG, "the optimisation modulo"),
        C::Speed(x) => ck.at_least(0, *x, 0.0, "the speed"),
        C::Inertia(x) => ck.at_least(0, *x, 0.0, "the inertia"),
        C::Ahead(n) => ck.int_in(0, *n, 0, BIG, "the number of key points"),
        C::OptimAhead(n) => ck.int_in(0, *n, 0, BIG, "the number of key points"),
        C::VisionRange {
            near,
            far,
            memory_range,
        } => ck.vision_range(*near, *far, *memory_range),
        C::MotorInit {
            max_speed,
            scale,
            ray_trace,
        } => {
            ck.at_least(2, *max_speed, 0.0, "the maximal speed")?;
            ck.positive(1, *scale, "the scale factor")?;
            ck.int_in(0, *ray_trace, 0, 1, "the ray tracer switch (1 on, 0 off)")
        }
        C::WordsToSpeak(words) => {
            let n = words.len();
            for (j, w) in words.iter().enumerate() {
                ck.int_in(n - 1 - j, *w, 0, i64::from(u32::MAX), "a sound number")?;
            }
            Ok(())
        }
        C::ListenTo { source, count } => {
            ck.int_in(1, *source, 0, i64::from(u32::MAX), "the sound source")?;
            ck.int_in(0, *count, 1, MAX_HEARD, "the number of sound events")
        }
        C::FootholdPlane(_) => Ok(()),
        C::FootholdStep { df_max, max_change } => {
            ck.positive(1, *df_max, "the longest step")?;
            ck.at_least(0, *max_change, 0.0, "the step length change")
        }
        C::StepWeights(w) => ck.step_weights(w),
        C::FootholdMap {
            range,
            min_voxels,
            foot,
        } => ck.foothold_map(*range, *min_voxels, *foot),
        C::Goal(_)
        | C::ResetGoal
        | C::MemDisplCubes
        | C::MemNoDispl
        | C::MemDisplPoints
        | C::VisMemOn
        | C::VisMemOff
        | C::Obs(_)
        | C::Lat(_)
        | C::Align(_) => Ok(()),
    }
}

#[cfg(test)]
mod tests;
