//! The automata of actors (thesis 5.1, table 5.1.1) and the commands of an
//! `actorNbr_automata` option (appendix B, table B6), parsed into typed
//! values that remember where they were written, so that a later layer
//! (the actor table) can point a [`Diagnostic`] at the offending word.
//!
//! This module knows the file format only: arities, integer arguments and
//! the automata names and numbers. What a value means for an actor (its
//! ranges, the actor numbers) is checked by `crate::actors`.

use std::fmt;

use super::scan::{near_miss, Scanner};
use crate::source::{Diagnostic, FileRef, Source};

/// Where a word stands in a definition file: `file:line:column` and the
/// line, ready to become a [`Diagnostic`] with a caret under the word.
#[derive(Debug, Clone, PartialEq)]
pub struct Span {
    /// The location (its message empty).
    at: Diagnostic,
}

impl Span {
    /// The word at byte `offset` of `src`.
    pub fn new(src: &Source, offset: usize) -> Span {
        Span {
            at: src.error(offset, ""),
        }
    }

    /// An error located at the word.
    pub fn error(&self, message: impl Into<String>) -> Diagnostic {
        Diagnostic {
            message: message.into(),
            ..self.at.clone()
        }
    }

    pub fn file(&self) -> &str {
        &self.at.file
    }

    /// 1-based line.
    pub fn line(&self) -> usize {
        self.at.line
    }

    /// 1-based column, in characters.
    pub fn column(&self) -> usize {
        self.at.column
    }
}

impl fmt::Display for Span {
    /// `file:line:column`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}:{}:{}", self.at.file, self.at.line, self.at.column)
    }
}

/// A value read from a definition file with the location of its word.
#[derive(Debug, Clone, PartialEq)]
pub struct Located<T> {
    pub value: T,
    pub span: Span,
}

impl<T> Located<T> {
    /// An error located at the value's word.
    pub fn error(&self, message: impl Into<String>) -> Diagnostic {
        self.span.error(message)
    }
}

/// The automata of table 5.1.1, plus `tennis_error_detection` (5.7) and
/// `auto_align` (table B6). Numbers: see [`Automata::number`] and
/// docs/actors.md; the thesis fixes only 19 = `auto_align` (and its
/// section 3.1.5 example runs the vision-and-memory test automata as 9,
/// hence 9 = `watch`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Automata {
    Talk,
    Listen,
    Observe,
    WalkLocal,
    WalkContinuously,
    Referee,
    PlayTennis,
    PlayTennisInteractively,
    WalkStepworthy,
    Watch,
    FollowTurtle,
    LSystem,
    TennisErrorDetection,
    AutoAlign,
}

/// (automata, number, name) — the one table of numbers and names.
const AUTOMATA_TABLE: [(Automata, i64, &str); 14] = [
    (Automata::Talk, 0, "talk"),
    (Automata::Listen, 1, "listen"),
    (Automata::Observe, 2, "observe"),
    (Automata::WalkLocal, 3, "walk_local"),
    (Automata::WalkContinuously, 4, "walk_continuously"),
    (Automata::Referee, 5, "referee"),
    (Automata::PlayTennis, 6, "play_tennis"),
    (
        Automata::PlayTennisInteractively,
        7,
        "play_tennis_interactively",
    ),
    (Automata::WalkStepworthy, 8, "walk_stepworthy"),
    (Automata::Watch, 9, "watch"),
    (Automata::FollowTurtle, 10, "follow_turtle"),
    (Automata::LSystem, 11, "L-system"),
    (Automata::TennisErrorDetection, 12, "tennis_error_detection"),
    (Automata::AutoAlign, 19, "auto_align"),
];

impl Automata {
    /// Every automata, in increasing number.
    pub const ALL: [Automata; 14] = [
        Automata::Talk,
        Automata::Listen,
        Automata::Observe,
        Automata::WalkLocal,
        Automata::WalkContinuously,
        Automata::Referee,
        Automata::PlayTennis,
        Automata::PlayTennisInteractively,
        Automata::WalkStepworthy,
        Automata::Watch,
        Automata::FollowTurtle,
        Automata::LSystem,
        Automata::TennisErrorDetection,
        Automata::AutoAlign,
    ];

    fn row(self) -> (Automata, i64, &'static str) {
        AUTOMATA_TABLE[self as usize]
    }

    /// The number an `actorNbr_automata` option gives it (and `?35` returns).
    pub fn number(self) -> i64 {
        self.row().1
    }

    /// Its name in table 5.1.1 (`L-system` keeps the thesis's hyphen).
    pub fn name(self) -> &'static str {
        self.row().2
    }

    pub fn from_number(n: i64) -> Option<Automata> {
        AUTOMATA_TABLE.iter().find(|r| r.1 == n).map(|r| r.0)
    }

    pub fn from_name(name: &str) -> Option<Automata> {
        AUTOMATA_TABLE.iter().find(|r| r.2 == name).map(|r| r.0)
    }

    /// `0 talk, 1 listen, …` for error messages.
    pub fn list() -> String {
        AUTOMATA_TABLE
            .iter()
            .map(|r| format!("{} {}", r.1, r.2))
            .collect::<Vec<_>>()
            .join(", ")
    }
}

impl fmt::Display for Automata {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// One command of table B6, its arguments typed. Where the BNF and table
/// B6 disagree on the arity, both are accepted and the optional leading
/// local goal number is `None` when it is left out.
#[derive(Debug, Clone, PartialEq)]
pub enum AutomataCommand {
    /// `KEYFRAMEdef n FILE`: reads the TRACK file and numbers it n.
    KeyframeDef {
        n: i64,
        file: FileRef,
    },
    /// `coll_test_func n`: the collision test heuristic of a planned path.
    CollTestFunc(i64),
    /// `heuristic n`: the search heuristic.
    Heuristic(i64),
    /// `rel_search_level [x]`: the search voxel size relative to the
    /// visual memory's (the BNF gives no argument).
    RelSearchLevel(Option<f64>),
    /// `goal x y z`: pushed on the goal stack.
    Goal([f64; 3]),
    /// `local_goal [n] x y z`: local goal vector n.
    LocalGoal {
        index: Option<i64>,
        at: [f64; 3],
    },
    /// `rgb_interest r g b on`: interest colour (0..255) and 1/0.
    RgbInterest {
        rgb: [i64; 3],
        active: i64,
    },
    /// `eps_arrived [n] d`: arrived at local goal n closer than d (`?33`).
    EpsArrived {
        index: Option<i64>,
        distance: f64,
    },
    /// `eps_look_at_goal [n] c`: scalar product threshold (`?32`).
    EpsLookAtGoal {
        index: Option<i64>,
        threshold: f64,
    },
    /// `eps_look_at [n] c`: scalar product threshold (`?32`).
    EpsLookAt {
        index: Option<i64>,
        threshold: f64,
    },
    /// `reset_goal`: empties the goal stack.
    ResetGoal,
    /// `turtle n`: the actor–turtle mapping (0 navigation, 1 footholds,
    /// 2 tennis racket, 3 show path, 4 interactive racket).
    Turtle(i64),
    MemDisplCubes,
    MemNoDispl,
    MemDisplPoints,
    VisMemOn,
    VisMemOff,
    /// `obs x y z`: the eye position.
    Obs([f64; 3]),
    /// `lat x y z`: the look-at point.
    Lat([f64; 3]),
    /// `align x y z`: the point `auto_align` turns to.
    Align([f64; 3]),
    /// `init m min max edge`: memory display every m frames, the world
    /// cube (min, min, min)–(max, max, max), the voxel edge.
    Init {
        display_every: i64,
        min: f64,
        max: f64,
        voxel_edge: f64,
    },
    /// `fov n`: the view angle in tenths of a degree.
    Fov(i64),
    /// `interest on thing`: 0/1, and 0 ball (material 10), 1 player 0
    /// (material 11), 2 player 1 (material 12).
    Interest {
        active: i64,
        thing: i64,
    },
    /// `size_actor d`: the actor's largest edge, world units.
    SizeActor(f64),
    /// `dist_coll d`: the local collision distance, world units.
    DistColl(f64),
    /// `tennis_state n` (0..13).
    TennisState(i64),
    /// `state n`: the vision system's state (0..26).
    State(i64),
    /// `optim_rate m`: optimise the path spline every m frames.
    OptimRate(i64),
    /// `speed v`: the maximal speed.
    Speed(f64),
    /// `inertia x`.
    Inertia(f64),
    /// `ahead n`: path key points checked for collisions.
    Ahead(i64),
    /// `optim_ahead n`: path key points optimised.
    OptimAhead(i64),
    /// `vision_range near far memory`: clipping range and the range of
    /// the visual memory's update.
    VisionRange {
        near: f64,
        far: f64,
        memory_range: f64,
    },
    /// `words_to_speak s…` (lmfilm's): the sound numbers the `talk`
    /// automata says, in order (the thesis's table `words_to_speak`,
    /// which its automata fill themselves).
    WordsToSpeak(Vec<i64>),
    /// `listen_to source n` (lmfilm's): what the `listen` automata
    /// captures, the next n sound events of that source.
    ListenTo {
        source: i64,
        count: i64,
    },
    /// `foothold_plane y` (lmfilm's): the height of the foothold
    /// locations' plane for `walk_stepworthy` (5.9.2).
    FootholdPlane(f64),
    /// `foothold_step df_max max_change` (lmfilm's): the walking model
    /// of `walk_stepworthy` (5.9.3): the longest step, and the most a
    /// step's length may change from the step before.
    FootholdStep {
        df_max: f64,
        max_change: f64,
    },
    /// `step_weights p0 n0 p1 n1 p2 n2` (lmfilm's): the weights and
    /// exponents of the step cost, eq. 7.3.1.
    StepWeights([f64; 6]),
    /// `foothold_map range min_voxels [foot]` (lmfilm's): the local
    /// map's radius around the actor, its smallest foothold in voxels,
    /// and its largest in world units.
    FootholdMap {
        range: f64,
        min_voxels: i64,
        foot: Option<f64>,
    },
    /// `motor_init speed scale trace`: humanoid maximal speed (mm/s),
    /// scale factor, ray tracer output 1/0.
    MotorInit {
        max_speed: f64,
        scale: f64,
        ray_trace: i64,
    },
}

/// One automata command: its keyword, the fewest and most numbers it
/// takes, whether a word follows them, and how its arguments build the
/// typed command. The one definition of each command: parsing, its name
/// in messages and its arity all come from here.
struct Spec {
    name: &'static str,
    min: usize,
    max: usize,
    takes_word: bool,
    build: fn(&Args) -> Result<AutomataCommand, Diagnostic>,
}

use AutomataCommand as C;

/// Automata commands of the BNF and table B6 (where they disagree on the
/// argument count, both counts are accepted).
const COMMANDS: &[Spec] = &[
    Spec {
        name: "KEYFRAMEdef",
        min: 1,
        max: 1,
        takes_word: true,
        build: |a| {
            Ok(C::KeyframeDef {
                n: a.int(0)?,
                file: a.file(),
            })
        },
    },
    Spec {
        name: "coll_test_func",
        min: 1,
        max: 1,
        takes_word: false,
        build: |a| Ok(C::CollTestFunc(a.int(0)?)),
    },
    Spec {
        name: "heuristic",
        min: 1,
        max: 1,
        takes_word: false,
        build: |a| Ok(C::Heuristic(a.int(0)?)),
    },
    Spec {
        name: "rel_search_level",
        min: 0,
        max: 1,
        takes_word: false,
        build: |a| Ok(C::RelSearchLevel((a.n() == 1).then(|| a.f(0)))),
    },
    Spec {
        name: "goal",
        min: 3,
        max: 3,
        takes_word: false,
        build: |a| Ok(C::Goal(a.v3(0))),
    },
    Spec {
        name: "local_goal",
        min: 3,
        max: 4,
        takes_word: false,
        build: |a| {
            Ok(C::LocalGoal {
                index: a.index(4)?,
                at: a.v3(a.n() - 3),
            })
        },
    },
    Spec {
        name: "rgb_interest",
        min: 4,
        max: 4,
        takes_word: false,
        build: |a| {
            Ok(C::RgbInterest {
                rgb: [a.int(0)?, a.int(1)?, a.int(2)?],
                active: a.int(3)?,
            })
        },
    },
    Spec {
        name: "eps_arrived",
        min: 1,
        max: 2,
        takes_word: false,
        build: |a| {
            Ok(C::EpsArrived {
                index: a.index(2)?,
                distance: a.f(a.n() - 1),
            })
        },
    },
    Spec {
        name: "eps_look_at_goal",
        min: 1,
        max: 2,
        takes_word: false,
        build: |a| {
            Ok(C::EpsLookAtGoal {
                index: a.index(2)?,
                threshold: a.f(a.n() - 1),
            })
        },
    },
    Spec {
        name: "eps_look_at",
        min: 1,
        max: 2,
        takes_word: false,
        build: |a| {
            Ok(C::EpsLookAt {
                index: a.index(2)?,
                threshold: a.f(a.n() - 1),
            })
        },
    },
    Spec {
        name: "reset_goal",
        min: 0,
        max: 0,
        takes_word: false,
        build: |_| Ok(C::ResetGoal),
    },
    Spec {
        name: "turtle",
        min: 1,
        max: 1,
        takes_word: false,
        build: |a| Ok(C::Turtle(a.int(0)?)),
    },
    Spec {
        name: "mem_displ_cubes",
        min: 0,
        max: 0,
        takes_word: false,
        build: |_| Ok(C::MemDisplCubes),
    },
    Spec {
        name: "mem_no_displ",
        min: 0,
        max: 0,
        takes_word: false,
        build: |_| Ok(C::MemNoDispl),
    },
    Spec {
        name: "mem_displ_points",
        min: 0,
        max: 0,
        takes_word: false,
        build: |_| Ok(C::MemDisplPoints),
    },
    Spec {
        name: "vis_mem_on",
        min: 0,
        max: 0,
        takes_word: false,
        build: |_| Ok(C::VisMemOn),
    },
    Spec {
        name: "vis_mem_off",
        min: 0,
        max: 0,
        takes_word: false,
        build: |_| Ok(C::VisMemOff),
    },
    Spec {
        name: "obs",
        min: 3,
        max: 3,
        takes_word: false,
        build: |a| Ok(C::Obs(a.v3(0))),
    },
    Spec {
        name: "lat",
        min: 3,
        max: 3,
        takes_word: false,
        build: |a| Ok(C::Lat(a.v3(0))),
    },
    Spec {
        name: "align",
        min: 3,
        max: 3,
        takes_word: false,
        build: |a| Ok(C::Align(a.v3(0))),
    },
    Spec {
        name: "init",
        min: 4,
        max: 4,
        takes_word: false,
        build: |a| {
            Ok(C::Init {
                display_every: a.int(0)?,
                min: a.f(1),
                max: a.f(2),
                voxel_edge: a.f(3),
            })
        },
    },
    Spec {
        name: "fov",
        min: 1,
        max: 1,
        takes_word: false,
        build: |a| Ok(C::Fov(a.int(0)?)),
    },
    Spec {
        name: "interest",
        min: 2,
        max: 2,
        takes_word: false,
        build: |a| {
            Ok(C::Interest {
                active: a.int(0)?,
                thing: a.int(1)?,
            })
        },
    },
    Spec {
        name: "size_actor",
        min: 1,
        max: 1,
        takes_word: false,
        build: |a| Ok(C::SizeActor(a.f(0))),
    },
    Spec {
        name: "dist_coll",
        min: 1,
        max: 1,
        takes_word: false,
        build: |a| Ok(C::DistColl(a.f(0))),
    },
    Spec {
        name: "tennis_state",
        min: 1,
        max: 1,
        takes_word: false,
        build: |a| Ok(C::TennisState(a.int(0)?)),
    },
    Spec {
        name: "state",
        min: 1,
        max: 1,
        takes_word: false,
        build: |a| Ok(C::State(a.int(0)?)),
    },
    Spec {
        name: "optim_rate",
        min: 1,
        max: 1,
        takes_word: false,
        build: |a| Ok(C::OptimRate(a.int(0)?)),
    },
    Spec {
        name: "speed",
        min: 1,
        max: 1,
        takes_word: false,
        build: |a| Ok(C::Speed(a.f(0))),
    },
    Spec {
        name: "inertia",
        min: 1,
        max: 1,
        takes_word: false,
        build: |a| Ok(C::Inertia(a.f(0))),
    },
    Spec {
        name: "ahead",
        min: 1,
        max: 1,
        takes_word: false,
        build: |a| Ok(C::Ahead(a.int(0)?)),
    },
    Spec {
        name: "optim_ahead",
        min: 1,
        max: 1,
        takes_word: false,
        build: |a| Ok(C::OptimAhead(a.int(0)?)),
    },
    Spec {
        name: "vision_range",
        min: 3,
        max: 3,
        takes_word: false,
        build: |a| {
            Ok(C::VisionRange {
                near: a.f(0),
                far: a.f(1),
                memory_range: a.f(2),
            })
        },
    },
    Spec {
        name: "motor_init",
        min: 3,
        max: 3,
        takes_word: false,
        build: |a| {
            Ok(C::MotorInit {
                max_speed: a.f(0),
                scale: a.f(1),
                ray_trace: a.int(2)?,
            })
        },
    },
    Spec {
        name: "words_to_speak",
        min: 1,
        max: MAX_WORDS,
        takes_word: false,
        build: |a| {
            Ok(C::WordsToSpeak(
                (0..a.n()).map(|i| a.int(i)).collect::<Result<_, _>>()?,
            ))
        },
    },
    Spec {
        name: "listen_to",
        min: 2,
        max: 2,
        takes_word: false,
        build: |a| {
            Ok(C::ListenTo {
                source: a.int(0)?,
                count: a.int(1)?,
            })
        },
    },
    Spec {
        name: "foothold_plane",
        min: 1,
        max: 1,
        takes_word: false,
        build: |a| Ok(C::FootholdPlane(a.f(0))),
    },
    Spec {
        name: "foothold_step",
        min: 2,
        max: 2,
        takes_word: false,
        build: |a| {
            Ok(C::FootholdStep {
                df_max: a.f(0),
                max_change: a.f(1),
            })
        },
    },
    Spec {
        name: "step_weights",
        min: 6,
        max: 6,
        takes_word: false,
        build: |a| {
            Ok(C::StepWeights([
                a.f(0),
                a.f(1),
                a.f(2),
                a.f(3),
                a.f(4),
                a.f(5),
            ]))
        },
    },
    Spec {
        name: "foothold_map",
        min: 2,
        max: 3,
        takes_word: false,
        build: |a| {
            Ok(C::FootholdMap {
                range: a.f(0),
                min_voxels: a.int(1)?,
                foot: (a.n() == 3).then(|| a.f(2)),
            })
        },
    },
];

/// Most words one `words_to_speak` may give.
pub const MAX_WORDS: usize = 64;

impl AutomataCommand {
    /// Whether `word` is a command keyword.
    pub fn is_keyword(word: &str) -> bool {
        COMMANDS.iter().any(|c| c.name == word)
    }

    /// Every command keyword with how many arguments it takes (min, max).
    pub fn keywords() -> impl Iterator<Item = (&'static str, usize, usize)> {
        COMMANDS.iter().map(|c| (c.name, c.min, c.max))
    }
}

/// A command with the location of its keyword and of each of its
/// arguments (the words after the keyword, in file order, the file name
/// of `KEYFRAMEdef` included).
#[derive(Debug, Clone, PartialEq)]
pub struct CommandAt {
    pub command: AutomataCommand,
    /// The keyword it was written with.
    pub keyword: &'static str,
    pub span: Span,
    pub args: Vec<Span>,
}

impl CommandAt {
    /// An error located at the keyword.
    pub fn error(&self, message: impl Into<String>) -> Diagnostic {
        self.span.error(message)
    }

    /// An error located at argument `i` counted from the last argument
    /// backwards (0 = the last): optional arguments come first, so the
    /// last ones keep their place whichever arity was written.
    pub fn arg_error_from_end(&self, i: usize, message: impl Into<String>) -> Diagnostic {
        match self.args.len().checked_sub(i + 1) {
            Some(k) => self.args[k].error(message),
            None => self.span.error(message),
        }
    }
}

/// An `actorNbr_automata` option: the actor, the automata pushed on its
/// stack and the commands that configure it.
#[derive(Debug, Clone, PartialEq)]
pub struct ActorAutomata {
    pub actor: Located<i64>,
    pub automata: Located<Automata>,
    pub commands: Vec<CommandAt>,
}

/// A behaviour command string of an `e` symbol with par1 = 0 (C.6):
/// `[actor] automata commands…`; without the actor number it is the
/// current actor of the `e`'s branch (the last `M` par1 = 7 before it).
#[derive(Debug, Clone, PartialEq)]
pub struct BehaviourString {
    pub actor: Option<Located<i64>>,
    pub automata: Located<Automata>,
    pub commands: Vec<CommandAt>,
}

/// Parses the text of an `e` par1 = 0 (a group's, from byte `at`): an
/// automata name or number alone, or the forms of `actorNbr_automata`.
pub fn parse_script(s: &mut Scanner, at: usize) -> Result<BehaviourString, Diagnostic> {
    let (first_at, first) = s.peek_word()?;
    let alone = if let Some(a) = Automata::from_name(first) {
        Some(a)
    } else if s.at_number()? {
        // One number, then a command or nothing: the automata alone.
        let save = s.pos;
        let n = s.int("an actor or automata number")?;
        let (_, next) = s.peek_word()?;
        let single = next.is_empty() || AutomataCommand::is_keyword(next);
        s.pos = save;
        match (single, Automata::from_number(n)) {
            (true, Some(a)) => Some(a),
            (true, None) => {
                return Err(s.error(
                    first_at,
                    format!(
                        "unknown automata number {n}; the automata are {}",
                        Automata::list()
                    ),
                ))
            }
            (false, _) => None,
        }
    } else {
        None
    };
    if let Some(a) = alone {
        s.word("the automata")?;
        return Ok(BehaviourString {
            actor: None,
            automata: Located {
                value: a,
                span: Span::new(s.src, first_at),
            },
            commands: parse_commands(s)?,
        });
    }
    let a = parse_actor_automata(s, at)?;
    Ok(BehaviourString {
        actor: Some(a.actor),
        automata: a.automata,
        commands: a.commands,
    })
}

/// Parses what follows the keyword `actorNbr_automata` (at byte `at`).
///
/// The BNF repeats the actor number (`int Automata`, Automata = `int int
/// …`) while table B6 names two numbers: both the two- and three-number
/// forms are read, the first number is the actor and the last the
/// automata. The automata may also be given by name after one or two
/// numbers (`actorNbr_automata 0 watch`).
pub fn parse_actor_automata(s: &mut Scanner, at: usize) -> Result<ActorAutomata, Diagnostic> {
    let mut ids = Vec::new();
    while ids.len() < 3 && s.at_number()? {
        let offset = s.peek_word()?.0;
        ids.push((s.int("an actor or automata number")?, offset));
    }
    let names: Vec<&str> = AUTOMATA_TABLE.iter().map(|r| r.2).collect();
    let (next_at, next) = s.peek_word()?;
    let by_name = if ids.len() < 3 && !next.is_empty() {
        Automata::from_name(next)
    } else {
        None
    };
    let src = s.src;
    let span = |offset| Span::new(src, offset);
    let automata = match by_name {
        Some(a) if !ids.is_empty() => {
            s.word("the automata name")?;
            Located {
                value: a,
                span: span(next_at),
            }
        }
        _ if ids.len() >= 2 => {
            let (n, offset) = ids[ids.len() - 1];
            let Some(a) = Automata::from_number(n) else {
                return Err(s.error(
                    offset,
                    format!(
                        "unknown automata number {n}; the automata are {}",
                        Automata::list()
                    ),
                ));
            };
            // Two numbers and then a misspelt name: say so rather than
            // "unknown option".
            if ids.len() == 2 && !AutomataCommand::is_keyword(next) {
                if let Some(k) = near_miss(next, &names) {
                    return Err(s.error(
                        next_at,
                        format!("unknown automata `{next}`; did you mean `{k}`?"),
                    ));
                }
            }
            Located {
                value: a,
                span: span(offset),
            }
        }
        _ if ids.len() == 1 && !next.is_empty() && !AutomataCommand::is_keyword(next) => {
            let hint = near_miss(next, &names)
                .map_or_else(String::new, |k| format!(" (did you mean `{k}`?)"));
            return Err(s.error(
                next_at,
                format!(
                    "unknown automata `{next}`{hint}; give its number or name: {}",
                    Automata::list()
                ),
            ));
        }
        _ => {
            let found = if next.is_empty() {
                "the end of the file".to_string()
            } else {
                format!("`{next}`")
            };
            let at = if next.is_empty() { at } else { next_at };
            return Err(s.error(
                at,
                format!(
                    "`actorNbr_automata` needs the actor and automata numbers \
                     (or the automata name), found {found}"
                ),
            ));
        }
    };
    let (actor, actor_at) = ids[0];
    // The BNF's repeated actor number (three numbers, or two before a
    // name) says the actor again: one that differs names no actor the
    // line configures (issue 54: it was read over in silence).
    let repeated = match by_name {
        Some(_) => ids.get(1),
        None => ids.get(1).filter(|_| ids.len() == 3),
    };
    if let Some(&(again, again_at)) = repeated.filter(|(n, _)| *n != actor) {
        return Err(s.error(
            again_at,
            format!(
                "the actor number is repeated as {again}, but the line's actor is {actor}; \
                 the repeated number (the BNF's form `actor actor automata`) must be the same, or left out"
            ),
        ));
    }
    Ok(ActorAutomata {
        actor: Located {
            value: actor,
            span: span(actor_at),
        },
        automata,
        commands: parse_commands(s)?,
    })
}

/// Reads automata commands while the next word is one.
pub fn parse_commands(s: &mut Scanner) -> Result<Vec<CommandAt>, Diagnostic> {
    let mut out = Vec::new();
    loop {
        let (_, w) = s.peek_word()?;
        let Some(spec) = COMMANDS.iter().find(|sp| sp.name == w) else {
            return Ok(out);
        };
        let (name, min, max) = (spec.name, spec.min, spec.max);
        let (at, _) = s.word(name)?;
        let mut numbers = Vec::new();
        let mut args = Vec::new();
        while numbers.len() < max && s.at_number()? {
            let offset = s.peek_word()?.0;
            numbers.push((s.number(&format!("an argument of `{name}`"))?, offset));
            args.push(Span::new(s.src, offset));
        }
        if numbers.len() < min {
            let counts = if min == max {
                format!("{min}")
            } else {
                format!("{min} or {max}")
            };
            return Err(s.error(
                at,
                format!(
                    "`{name}` takes {counts} number{}, found {}",
                    if max == 1 { "" } else { "s" },
                    numbers.len()
                ),
            ));
        }
        let file = if spec.takes_word {
            let (w_at, w) = s.word(&format!("a file name after `{name}`"))?;
            args.push(Span::new(s.src, w_at));
            Some(FileRef::new(s.src, w_at, w))
        } else {
            None
        };
        let command = (spec.build)(&Args {
            s,
            name,
            numbers: &numbers,
            file,
        })?;
        out.push(CommandAt {
            command,
            keyword: name,
            span: Span::new(s.src, at),
            args,
        });
    }
}

/// A command's arguments as written: the numbers with their offsets,
/// and the word after them.
struct Args<'a> {
    s: &'a Scanner<'a>,
    name: &'static str,
    numbers: &'a [(f64, usize)],
    file: Option<FileRef>,
}

impl Args<'_> {
    fn n(&self) -> usize {
        self.numbers.len()
    }

    /// Number `i`, which must be an integer.
    fn int(&self, i: usize) -> Result<i64, Diagnostic> {
        let (v, offset) = self.numbers[i];
        // Integers up to 2^53 are exact in an f64.
        if v.fract() != 0.0 || v.abs() > 9_007_199_254_740_992.0 {
            let name = self.name;
            return Err(self
                .s
                .error(offset, format!("`{name}` takes an integer here, found {v}")));
        }
        Ok(v as i64)
    }

    fn f(&self, i: usize) -> f64 {
        self.numbers[i].0
    }

    fn v3(&self, i: usize) -> [f64; 3] {
        [self.f(i), self.f(i + 1), self.f(i + 2)]
    }

    /// The optional leading local goal number of the longer forms.
    fn index(&self, full: usize) -> Result<Option<i64>, Diagnostic> {
        if self.n() == full {
            self.int(0).map(Some)
        } else {
            Ok(None)
        }
    }

    fn file(&self) -> FileRef {
        self.file
            .clone()
            .expect("a command that takes a word has one")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Parses `actorNbr_automata REST` (the keyword at byte 0).
    fn parse(rest: &str) -> Result<ActorAutomata, Diagnostic> {
        let src = Source::new("t.lm", format!("actorNbr_automata {rest}\n"));
        let mut s = Scanner::new(&src);
        s.word("the keyword")?;
        let a = parse_actor_automata(&mut s, 0)?;
        assert!(s.at_end()?, "left over after {rest}");
        Ok(a)
    }

    /// The error of `rest`, checked to point at the first `word` with a caret.
    fn refused(rest: &str, word: &str) -> Diagnostic {
        let d = parse(rest).expect_err(rest);
        let column = "actorNbr_automata ".len() + rest.find(word).unwrap() + 1;
        let shown = d.to_string();
        assert!(shown.starts_with(&format!("t.lm:1:{column}: ")), "{shown}");
        assert!(
            shown.ends_with(&format!("\n  {}^", " ".repeat(column - 1))),
            "{shown}"
        );
        d
    }

    /// The repeated actor number of the BNF's form says the same actor,
    /// or the line is refused there (issue 54).
    #[test]
    fn a_repeated_actor_number_is_the_same_actor() {
        assert_eq!(parse("3 3 9").unwrap().actor.value, 3);
        assert_eq!(parse("3 3 watch").unwrap().actor.value, 3);
        let d = refused("0 7 9", "7");
        assert!(d.message.contains("repeated as 7"), "{d}");
        let d = refused("2 5 watch obs 0 0 1", "5");
        assert!(d.message.contains("the line's actor is 2"), "{d}");
    }

    #[test]
    fn the_thesis_line() {
        let a = parse("0 0 9 init 10 -20 300 2.0 obs 0 0 50 lat 0 0 0").unwrap();
        assert_eq!(a.actor.value, 0);
        assert_eq!(a.automata.value, Automata::Watch);
        assert_eq!(a.automata.span.column(), 23);
        let c: Vec<_> = a.commands.iter().map(|c| &c.command).collect();
        assert_eq!(
            c,
            [
                &AutomataCommand::Init {
                    display_every: 10,
                    min: -20.0,
                    max: 300.0,
                    voxel_edge: 2.0
                },
                &AutomataCommand::Obs([0.0, 0.0, 50.0]),
                &AutomataCommand::Lat([0.0; 3]),
            ]
        );
        assert_eq!(a.commands[0].span.to_string(), "t.lm:1:25");
        assert_eq!(a.commands[0].args.len(), 4);
        assert_eq!(a.commands[0].args[3].column(), 41);
    }

    #[test]
    fn by_number_or_by_name() {
        for (rest, actor, automata) in [
            ("2 19", 2, Automata::AutoAlign),
            ("2 auto_align", 2, Automata::AutoAlign),
            ("3 3 watch", 3, Automata::Watch),
            ("1 L-system", 1, Automata::LSystem),
            ("1 1 12", 1, Automata::TennisErrorDetection),
            (
                "0 tennis_error_detection",
                0,
                Automata::TennisErrorDetection,
            ),
        ] {
            let a = parse(rest).unwrap();
            assert_eq!(
                (a.actor.value, a.automata.value),
                (actor, automata),
                "{rest}"
            );
        }
    }

    #[test]
    fn refusals_point_at_the_word() {
        refused("0 0 13", "13");
        let d = refused("0 wach", "wach");
        assert!(d.message.contains("`watch`"), "{d}");
        refused("0 0 wach", "wach");
        refused("0 init 1 2 3 4", "init");
        refused("watch", "watch");
        refused("0 9 fov 45.5", "45.5");
        refused("0 9 init 1.5 -20 300 2", "1.5");
        refused("0 9 lat 1 2", "lat");
        refused("0 9 KEYFRAMEdef walk.track", "KEYFRAMEdef");
    }
}
