//! Actors as they live through a film: their state variables (table B6),
//! where each one's eye is and looks, its last vision window and what it
//! made of it, and its visual memory. The frame loop's sense step (DESIGN
//! §1 step 3) makes every actor with a vision window see into the frame's
//! BVH, in parallel, and remember what it saw.

use std::collections::BTreeMap;

use glam::{DVec3, Vec3};
use rayon::prelude::*;

use super::behaviour::{AutomataProgress, Behaviour, Conversation, Deed, Senses};
use super::footholds::plan::{Gait, Weights};
use super::footholds::walk::Footing;
use super::navigate::Navigation;
use super::tennis::Tennis;
use super::{Actor, Table};
use crate::actors::perception::memory::{Forgetting, VisualMemory};
use crate::actors::perception::octree::Cube;
use crate::actors::perception::vision::{
    self, Body, Interest, OwnBody, Percepts, View, Window, THESIS_THRESHOLD,
};
use crate::lsys::automata::{Automata, AutomataCommand};
use crate::lsys::Limits;
use crate::render::Accel;

/// The view angle before any `fov` command: 60°, in tenths of a degree.
const DEFAULT_FOV: i64 = 600;

/// How the memory's occupied voxels are drawn (`mem_displ_cubes`,
/// `mem_displ_points`, `mem_no_displ`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum DisplayMode {
    #[default]
    None,
    Cubes,
    Points,
}

/// The memory display of an actor (thesis 3.1.5): how, how often, and
/// from where (`M` par1 = 14, 15; by default from the actor's eye).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct MemoryDisplay {
    pub mode: DisplayMode,
    /// Every `every` frames (`init`'s display modulo; 0 or 1: each frame).
    pub every: u64,
    pub eye: Option<Vec3>,
    pub look_at: Option<Vec3>,
}

impl MemoryDisplay {
    /// Whether the display is drawn at `frame`.
    pub fn at(&self, frame: u64) -> bool {
        self.mode != DisplayMode::None && frame.is_multiple_of(self.every.max(1))
    }
}

/// One actor's state variables, eye, window and memory.
pub struct Living {
    pub id: usize,
    /// The automata that runs (the top of the behaviour stack).
    pub automata: Option<Automata>,
    pub eye: Vec3,
    pub look_at: Vec3,
    /// View angle in tenths of a degree (`fov`).
    pub fov: i64,
    /// Clipping range of the vision window (`vision_range near far`).
    pub near: f32,
    pub far: f32,
    /// Edge of the vision window, when the actor has one.
    pub edge: Option<u32>,
    /// Flat colours the window tells apart (`iVisionWinSize`).
    pub max_colors: u32,
    /// `size_actor` and `dist_coll` (`?31`).
    pub size_actor: f32,
    pub dist_coll: f32,
    /// `interest 1 thing`: 0 ball, 1 player 0, 2 player 1.
    pub interest: Option<i64>,
    /// `rgb_interest r g b 1`.
    pub rgb_interest: Option<[i64; 3]>,
    /// The goal stack (`goal`, `reset_goal`); the last is the top.
    pub goals: Vec<Vec3>,
    /// Local goal vectors by number (`local_goal`, `g` par1 = 1, `?38`).
    pub local_goals: BTreeMap<i64, Vec3>,
    /// Thresholds by local goal number (`eps_arrived`, `eps_look_at`).
    pub eps_arrived: BTreeMap<i64, f64>,
    pub eps_look_at: BTreeMap<i64, f64>,
    /// `align`: the point `auto_align` turns to.
    pub align: Option<Vec3>,
    /// `state`: the vision system's state (0..26); `tennis_state` is
    /// the tennis automata's ([`Tennis`]).
    pub state: i64,
    /// `turtle`: the actor–turtle mapping (6.3.4).
    pub turtle: i64,
    /// Whether what it sees goes into its memory (`vis_mem_on`/`off`).
    pub memory_on: bool,
    /// The visual memory, once `init` declared its cube.
    pub memory: Option<VisualMemory>,
    /// Range of the memory's update (`vision_range`'s third number).
    memory_range: f32,
    pub display: MemoryDisplay,
    /// What its `M` branch drew this frame, which its vision looks
    /// through.
    pub body: OwnBody,
    /// Why it last gave a goal up, for `trace`; None once it heads for
    /// another.
    pub gave_up: Option<String>,
    /// What it has to say to the film maker this frame (an automata
    /// that cannot go on), taken by the frame loop as warnings.
    pub notes: Vec<String>,
    /// The problems it has warned of once already ([`Living::note_once`]).
    warned: std::collections::BTreeSet<&'static str>,
    /// What the actor saw at the last sense step, and made of it.
    pub window: Option<Window>,
    /// How long that step took (vision and memory), for `--timings`:
    /// never part of an output.
    pub seeing: std::time::Duration,
    pub percepts: Option<Percepts>,
    /// The behaviour stack (5.1): the next command string is the last.
    pub stack: Vec<Behaviour>,
    /// Where the running automata is.
    pub progress: AutomataProgress,
    /// `speed`: how fast it walks, world units a second.
    pub speed: f32,
    /// Each automaton's own state, next to its code: `talk` and
    /// `listen`'s, `walk_continuously`'s (its tuning and its path),
    /// the tennis automata's, `walk_stepworthy`'s.
    pub conversation: Conversation,
    pub navigation: Navigation,
    pub tennis: Tennis,
    pub footing: Footing,
}

/// Walking speed before any `speed` command, world units a second.
const DEFAULT_SPEED: f32 = 1.0;

/// Default threshold of `?33`, `?39` (world units) and `?32` (cosine).
const EPS_ARRIVED: f64 = 0.1;
const EPS_LOOK_AT: f64 = 0.99;

impl Living {
    /// The actor with its script on its behaviour stack, the first
    /// `actorNbr_automata` line popped and running.
    pub fn new(actor: &Actor) -> Living {
        let mut me = Living {
            id: actor.id(),
            automata: None,
            eye: Vec3::ZERO,
            look_at: Vec3::Z,
            fov: DEFAULT_FOV,
            near: 0.01,
            far: 1e6,
            edge: actor.vision().map(|v| v.edge),
            max_colors: actor.vision().map_or(0, |v| v.max_colors),
            size_actor: 0.0,
            dist_coll: 1.0,
            interest: None,
            rgb_interest: None,
            goals: Vec::new(),
            local_goals: BTreeMap::new(),
            eps_arrived: BTreeMap::new(),
            eps_look_at: BTreeMap::new(),
            align: None,
            state: 0,
            turtle: 0,
            memory_on: true,
            memory: None,
            memory_range: f32::INFINITY,
            display: MemoryDisplay::default(),
            body: OwnBody::default(),
            gave_up: None,
            notes: Vec::new(),
            warned: Default::default(),
            window: None,
            seeing: std::time::Duration::ZERO,
            percepts: None,
            stack: Vec::new(),
            progress: AutomataProgress::default(),
            speed: DEFAULT_SPEED,
            conversation: Conversation::default(),
            navigation: Navigation::default(),
            tennis: Tennis::default(),
            footing: Footing::default(),
        };
        for entry in actor.automata().iter().rev() {
            me.push(Behaviour {
                automata: entry.automata,
                commands: entry.commands.iter().map(|c| c.command.clone()).collect(),
            });
        }
        me.pop();
        me
    }

    /// Sets the state variables one automata command names (table B6);
    /// the others keep their values (6.3.4). Every command has its arm:
    /// a new one that forgets its effect does not compile.
    pub fn apply(&mut self, command: &AutomataCommand) {
        use AutomataCommand as C;
        let v = |p: [f64; 3]| DVec3::from_array(p).as_vec3();
        match *command {
            C::Obs(p) => self.eye = v(p),
            C::Lat(p) => self.look_at = v(p),
            C::Align(p) => self.align = Some(v(p)),
            C::Fov(f) => self.fov = f,
            C::VisionRange {
                near,
                far,
                memory_range,
            } => {
                (self.near, self.far) = (near as f32, far as f32);
                self.memory_range = if memory_range > 0.0 {
                    memory_range as f32
                } else {
                    f32::INFINITY
                };
                let range = self.memory_range;
                if let Some(m) = &mut self.memory {
                    m.set_rule(Forgetting { range, ..m.rule() });
                }
            }
            C::Init {
                display_every,
                min,
                max,
                voxel_edge,
            } => {
                self.display.every = display_every.max(0) as u64;
                let cube = Cube::new(min, max, voxel_edge);
                let rule = Forgetting {
                    range: self.memory_range,
                    ..Forgetting::thesis(cube.voxel_edge)
                };
                self.memory = Some(VisualMemory::new(cube, rule));
            }
            C::SizeActor(d) => self.size_actor = d as f32,
            C::DistColl(d) => self.dist_coll = d as f32,
            C::Interest { active, thing } => self.interest = (active == 1).then_some(thing),
            C::RgbInterest { rgb, active } => self.rgb_interest = (active == 1).then_some(rgb),
            C::Goal(p) => self.goals.push(v(p)),
            C::ResetGoal => self.goals.clear(),
            C::LocalGoal { index, at } => {
                self.local_goals.insert(index.unwrap_or(0), v(at));
            }
            C::EpsArrived { index, distance } => {
                self.eps_arrived.insert(index.unwrap_or(0), distance);
            }
            C::EpsLookAt { index, threshold } | C::EpsLookAtGoal { index, threshold } => {
                self.eps_look_at.insert(index.unwrap_or(0), threshold);
            }
            C::State(s) => self.state = s,
            C::Speed(v) => self.speed = v as f32,
            C::Heuristic(n) => self.navigation.tuning.heuristic = n,
            C::CollTestFunc(n) => self.navigation.tuning.coll_test_func = n,
            C::RelSearchLevel(x) => {
                self.navigation.tuning.rel_search_level =
                    x.map_or(1, |x| x.round().clamp(0.0, 20.0) as u32)
            }
            C::Ahead(n) => self.navigation.tuning.ahead = n,
            C::OptimRate(n) => self.navigation.tuning.optim_rate = n,
            C::OptimAhead(n) => self.navigation.tuning.optim_ahead = n,
            C::Inertia(x) => self.navigation.tuning.inertia = x as f32,
            C::WordsToSpeak(ref w) => {
                self.conversation.words = w.iter().map(|&s| s as u32).collect()
            }
            C::ListenTo { source, count } => {
                self.conversation.listen_to = Some((source as u32, count as usize))
            }
            C::TennisState(s) => self.tennis.state = s,
            C::Turtle(t) => self.turtle = t,
            C::VisMemOn => self.memory_on = true,
            C::VisMemOff => self.memory_on = false,
            C::MemDisplCubes => self.display.mode = DisplayMode::Cubes,
            C::MemDisplPoints => self.display.mode = DisplayMode::Points,
            C::MemNoDispl => self.display.mode = DisplayMode::None,
            C::FootholdPlane(y) => self.footing.settings.plane = Some(y as f32),
            C::FootholdStep { df_max, max_change } => {
                self.footing.settings.gait = Gait {
                    df_max: df_max as f32,
                    max_change: max_change as f32,
                }
            }
            C::StepWeights([p0, n0, p1, n1, p2, n2]) => {
                self.footing.settings.weights = Weights {
                    p0,
                    n0,
                    p1,
                    n1,
                    p2,
                    n2,
                }
            }
            C::FootholdMap {
                range,
                min_voxels,
                foot,
            } => {
                let s = &mut self.footing.settings;
                s.range = range as f32;
                s.min_voxels = u32::try_from(min_voxels).unwrap_or(u32::MAX);
                if let Some(f) = foot {
                    s.foot = f as f32;
                }
            }
            // The thesis's humanoid (AGENTlib) plays keyframed tracks and
            // has a walking motor; lmfilm's bodies walk as their actor's
            // eye moves (docs/actors.md, "Bodies"): these are checked and
            // set nothing.
            C::KeyframeDef { .. } | C::MotorInit { .. } => {}
        }
    }

    /// The goal the actor heads for now: local goal 0 when set, else the
    /// goal it navigates to, else the top of its goal stack (docs/actors.md,
    /// "Sensor functions").
    pub fn actual_goal(&self) -> Option<Vec3> {
        self.local_goals
            .get(&0)
            .copied()
            .or(self.navigation.destination)
            .or(self.footing.destination)
            .or_else(|| self.goals.last().copied())
    }

    /// Its destination: the top of the goal stack, else local goal 0.
    pub fn destination(&self) -> Option<Vec3> {
        self.goals
            .last()
            .copied()
            .or_else(|| self.local_goals.get(&0).copied())
    }

    fn eps_arrived(&self) -> f64 {
        self.eps_arrived_at(0) as f64
    }

    /// `eps_arrived` of local goal `n`.
    pub fn eps_arrived_at(&self, n: i64) -> f32 {
        self.eps_arrived.get(&n).copied().unwrap_or(EPS_ARRIVED) as f32
    }

    /// `?30`–`?39` as this actor's last sense step and state give them
    /// (table B5); `?38` sets local goal 1 to the thing it found.
    pub fn sensor(&mut self, code: u8) -> f64 {
        let p = self.percepts.as_ref();
        let truth = |b: bool| if b { 1.0 } else { -1.0 };
        match code {
            30 => p.map_or(vision::NOTHING, |p| p.centre_distance),
            31 => p.map_or(0.0, |p| p.obstacle),
            32 => self.actual_goal().map_or(-1.0, |g| {
                let eps = self.eps_look_at.get(&0).copied().unwrap_or(EPS_LOOK_AT);
                vision::looks_at_goal(self.eye, self.look_at, g, eps)
            }),
            33 => self.actual_goal().map_or(-1.0, |g| {
                vision::arrived_at_goal(self.eye, g, self.eps_arrived())
            }),
            39 => self.destination().map_or(-1.0, |g| {
                vision::arrived_at_goal(self.eye, g, self.eps_arrived())
            }),
            35 => self.automata.map_or(-1.0, |a| a.number() as f64),
            36 => p.map_or(-1.0, |p| p.interest_found),
            37 => p.map_or(-1.0, |p| p.rgb_interest_found),
            38 => match p.and_then(|p| p.rgb) {
                Some(found) => {
                    self.local_goals.insert(1, found.position);
                    1.0
                }
                None => truth(false),
            },
            _ => 0.0,
        }
    }

    /// Sees into `accel` and remembers what it saw, at `frame`.
    fn sense(&mut self, accel: &Accel, frame: u64) {
        let Some(edge) = self.edge else { return };
        let start = std::time::Instant::now();
        let view = View::new(self.eye, self.look_at, self.fov, self.near, self.far);
        self.body.seal();
        let window = vision::see(accel, &self.body, &view, edge);
        if let (Some(memory), true) = (&mut self.memory, self.memory_on) {
            let stamp = u32::try_from(frame).unwrap_or(u32::MAX);
            // The memory is for the static surroundings (3.1.3): the
            // things that move, which vision tells by their colour codes
            // (the ball, the players: table B6 `interest`), stay out.
            memory.integrate_static(&window.depth_view(), stamp, |i| {
                !window.pixels[i].shows_a_thing()
            });
        }
        let body = Body {
            size_actor: self.size_actor,
            dist_coll: self.dist_coll,
            interest: self.interest.and_then(|t| Interest::thing(accel, t)),
            rgb_interest: self
                .rgb_interest
                .map(|c| Interest::rgb(c, THESIS_THRESHOLD)),
        };
        self.percepts = Some(window.percepts(&body));
        self.window = Some(window);
        self.seeing = start.elapsed();
    }
}

/// A point as the actors' warnings write it: x, y, z to the centimetre,
/// or in scientific notation past ±10⁷.
pub(crate) fn show(p: Vec3) -> String {
    let one = |v: f32| {
        if v.abs() < 1e7 {
            format!("{v:.2}")
        } else {
            format!("{v:e}")
        }
    };
    format!("{}, {}, {}", one(p.x), one(p.y), one(p.z))
}

impl Living {
    /// A warning of this frame about this actor, naming its automata.
    pub(crate) fn note(&mut self, what: &str) {
        let automata = self.automata.map_or("no automata", |a| a.name());
        self.notes
            .push(format!("warning: actor {} ({automata}): {what}", self.id));
    }

    /// A warning said the first time only: the problem `key` names
    /// stays for as long as the scene does the same thing.
    pub(crate) fn note_once(&mut self, key: &'static str, what: &str) {
        if self.warned.insert(key) {
            self.note(what);
        }
    }

    /// Gives its goal up for `why`, said once as a warning and kept for
    /// `trace`.
    pub(crate) fn give_up_goal(&mut self, why: String) {
        self.note(&why);
        self.gave_up = Some(why);
    }
}

/// Every actor of the table, as it stands before the first frame, its
/// work held to `limits`.
pub fn living(table: &Table, limits: &Limits) -> Vec<Living> {
    let mut all: Vec<Living> = table.actors().iter().map(Living::new).collect();
    for a in &mut all {
        a.navigation.tuning.max_plan_voxels = limits.plan_voxels;
    }
    all
}

/// The sense step: every actor sees, in parallel; each writes only its
/// own window, percepts and memory, so the result does not depend on
/// threads.
pub fn sense(actors: &mut [Living], accel: &Accel, frame: u64) {
    actors.par_iter_mut().for_each(|a| a.sense(accel, frame));
}

/// The act step: every actor's automata does its frame's work, one
/// actor after the other in actor order; returns what they do to the
/// world outside themselves, in that order.
pub fn act(actors: &mut [Living], senses: &Senses) -> Vec<Deed> {
    let mut deeds = Vec::new();
    for a in actors {
        a.act(senses, &mut deeds);
    }
    deeds
}

/// An error once the actors' memories hold more than `max` bytes
/// together ([`Limits::memory_bytes`] in a film), naming the largest: a
/// voxel edge too fine for what the actors see.
pub fn check_memory(actors: &[Living], max: u64) -> Result<(), String> {
    let bytes = |a: &Living| a.memory.as_ref().map_or(0, |m| m.memory_bytes() as u64);
    let total: u64 = actors.iter().map(bytes).sum();
    if total <= max {
        return Ok(());
    }
    let big = actors.iter().max_by_key(|a| bytes(a)).expect("some memory");
    Err(format!(
        "the actors' visual memories hold {} bytes, more than {}; actor {}'s holds {} voxels in {} bytes: give its `init` a larger voxel edge or a smaller cube, or raise the limit with --max-memory BYTES",
        total,
        max,
        big.id,
        big.memory.as_ref().map_or(0, |m| m.voxels()),
        bytes(big)
    ))
}
