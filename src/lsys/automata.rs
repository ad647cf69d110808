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

/// (name, fewest numbers, most numbers, takes a word after the numbers).
type Spec = (&'static str, usize, usize, bool);

/// Automata commands of the BNF and table B6 (where they disagree on the
/// argument count, both counts are accepted).
const COMMANDS: &[Spec] = &[
    ("KEYFRAMEdef", 1, 1, true),
    ("coll_test_func", 1, 1, false),
    ("heuristic", 1, 1, false),
    ("rel_search_level", 0, 1, false),
    ("goal", 3, 3, false),
    ("local_goal", 3, 4, false),
    ("rgb_interest", 4, 4, false),
    ("eps_arrived", 1, 2, false),
    ("eps_look_at_goal", 1, 2, false),
    ("eps_look_at", 1, 2, false),
    ("reset_goal", 0, 0, false),
    ("turtle", 1, 1, false),
    ("mem_displ_cubes", 0, 0, false),
    ("mem_no_displ", 0, 0, false),
    ("mem_displ_points", 0, 0, false),
    ("vis_mem_on", 0, 0, false),
    ("vis_mem_off", 0, 0, false),
    ("obs", 3, 3, false),
    ("lat", 3, 3, false),
    ("align", 3, 3, false),
    ("init", 4, 4, false),
    ("fov", 1, 1, false),
    ("interest", 2, 2, false),
    ("size_actor", 1, 1, false),
    ("dist_coll", 1, 1, false),
    ("tennis_state", 1, 1, false),
    ("state", 1, 1, false),
    ("optim_rate", 1, 1, false),
    ("speed", 1, 1, false),
    ("inertia", 1, 1, false),
    ("ahead", 1, 1, false),
    ("optim_ahead", 1, 1, false),
    ("vision_range", 3, 3, false),
    ("motor_init", 3, 3, false),
    ("words_to_speak", 1, MAX_WORDS, false),
    ("listen_to", 2, 2, false),
    ("foothold_plane", 1, 1, false),
    ("foothold_step", 2, 2, false),
    ("step_weights", 6, 6, false),
    ("foothold_map", 2, 3, false),
];

/// Most words one `words_to_speak` may give.
pub const MAX_WORDS: usize = 64;

impl AutomataCommand {
    /// The command's keyword.
    pub fn name(&self) -> &'static str {
        use AutomataCommand as C;
        match self {
            C::KeyframeDef { .. } => "KEYFRAMEdef",
            C::CollTestFunc(_) => "coll_test_func",
            C::Heuristic(_) => "heuristic",
            C::RelSearchLevel(_) => "rel_search_level",
            C::Goal(_) => "goal",
            C::LocalGoal { .. } => "local_goal",
            C::RgbInterest { .. } => "rgb_interest",
            C::EpsArrived { .. } => "eps_arrived",
            C::EpsLookAtGoal { .. } => "eps_look_at_goal",
            C::EpsLookAt { .. } => "eps_look_at",
            C::ResetGoal => "reset_goal",
            C::Turtle(_) => "turtle",
            C::MemDisplCubes => "mem_displ_cubes",
            C::MemNoDispl => "mem_no_displ",
            C::MemDisplPoints => "mem_displ_points",
            C::VisMemOn => "vis_mem_on",
            C::VisMemOff => "vis_mem_off",
            C::Obs(_) => "obs",
            C::Lat(_) => "lat",
            C::Align(_) => "align",
            C::Init { .. } => "init",
            C::Fov(_) => "fov",
            C::Interest { .. } => "interest",
            C::SizeActor(_) => "size_actor",
            C::DistColl(_) => "dist_coll",
            C::TennisState(_) => "tennis_state",
            C::State(_) => "state",
            C::OptimRate(_) => "optim_rate",
            C::Speed(_) => "speed",
            C::Inertia(_) => "inertia",
            C::Ahead(_) => "ahead",
            C::OptimAhead(_) => "optim_ahead",
            C::VisionRange { .. } => "vision_range",
            C::MotorInit { .. } => "motor_init",
            C::FootholdPlane(_) => "foothold_plane",
            C::FootholdStep { .. } => "foothold_step",
            C::StepWeights(_) => "step_weights",
            C::FootholdMap { .. } => "foothold_map",
            C::WordsToSpeak(_) => "words_to_speak",
            C::ListenTo { .. } => "listen_to",
        }
    }

    /// Whether `word` is a command keyword.
    pub fn is_keyword(word: &str) -> bool {
        COMMANDS.iter().any(|c| c.0 == word)
    }
}

/// A command with the location of its keyword and of each of its
/// arguments (the words after the keyword, in file order, the file name
/// of `KEYFRAMEdef` included).
#[derive(Debug, Clone, PartialEq)]
pub struct CommandAt {
    pub command: AutomataCommand,
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
        let Some(&(name, min, max, takes_word)) = COMMANDS.iter().find(|sp| sp.0 == w) else {
            return Ok(out);
        };
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
        let file = if takes_word {
            let (w_at, w) = s.word(&format!("a file name after `{name}`"))?;
            args.push(Span::new(s.src, w_at));
            Some(FileRef::new(s.src, w_at, w))
        } else {
            None
        };
        let command = typed(s, name, &numbers, file)?;
        out.push(CommandAt {
            command,
            span: Span::new(s.src, at),
            args,
        });
    }
}

/// The typed command `name` of `numbers` (each with its offset), whose
/// count the caller checked against [`COMMANDS`].
fn typed(
    s: &Scanner,
    name: &str,
    numbers: &[(f64, usize)],
    file: Option<FileRef>,
) -> Result<AutomataCommand, Diagnostic> {
    use AutomataCommand as C;
    let int = |i: usize| -> Result<i64, Diagnostic> {
        let (v, offset) = numbers[i];
        // Integers up to 2^53 are exact in an f64.
        if v.fract() != 0.0 || v.abs() > 9_007_199_254_740_992.0 {
            return Err(s.error(offset, format!("`{name}` takes an integer here, found {v}")));
        }
        Ok(v as i64)
    };
    let f = |i: usize| numbers[i].0;
    let v3 = |i: usize| [f(i), f(i + 1), f(i + 2)];
    let n = numbers.len();
    // The optional leading local goal number of the longer forms.
    let index = |full: usize| -> Result<Option<i64>, Diagnostic> {
        if n == full {
            int(0).map(Some)
        } else {
            Ok(None)
        }
    };
    Ok(match name {
        "KEYFRAMEdef" => C::KeyframeDef {
            n: int(0)?,
            file: file.expect("KEYFRAMEdef takes a word"),
        },
        "coll_test_func" => C::CollTestFunc(int(0)?),
        "heuristic" => C::Heuristic(int(0)?),
        "rel_search_level" => C::RelSearchLevel((n == 1).then(|| f(0))),
        "goal" => C::Goal(v3(0)),
        "local_goal" => C::LocalGoal {
            index: index(4)?,
            at: v3(n - 3),
        },
        "rgb_interest" => C::RgbInterest {
            rgb: [int(0)?, int(1)?, int(2)?],
            active: int(3)?,
        },
        "eps_arrived" => C::EpsArrived {
            index: index(2)?,
            distance: f(n - 1),
        },
        "eps_look_at_goal" => C::EpsLookAtGoal {
            index: index(2)?,
            threshold: f(n - 1),
        },
        "eps_look_at" => C::EpsLookAt {
            index: index(2)?,
            threshold: f(n - 1),
        },
        "reset_goal" => C::ResetGoal,
        "turtle" => C::Turtle(int(0)?),
        "mem_displ_cubes" => C::MemDisplCubes,
        "mem_no_displ" => C::MemNoDispl,
        "mem_displ_points" => C::MemDisplPoints,
        "vis_mem_on" => C::VisMemOn,
        "vis_mem_off" => C::VisMemOff,
        "obs" => C::Obs(v3(0)),
        "lat" => C::Lat(v3(0)),
        "align" => C::Align(v3(0)),
        "init" => C::Init {
            display_every: int(0)?,
            min: f(1),
            max: f(2),
            voxel_edge: f(3),
        },
        "fov" => C::Fov(int(0)?),
        "interest" => C::Interest {
            active: int(0)?,
            thing: int(1)?,
        },
        "size_actor" => C::SizeActor(f(0)),
        "dist_coll" => C::DistColl(f(0)),
        "tennis_state" => C::TennisState(int(0)?),
        "state" => C::State(int(0)?),
        "optim_rate" => C::OptimRate(int(0)?),
        "speed" => C::Speed(f(0)),
        "inertia" => C::Inertia(f(0)),
        "ahead" => C::Ahead(int(0)?),
        "optim_ahead" => C::OptimAhead(int(0)?),
        "vision_range" => C::VisionRange {
            near: f(0),
            far: f(1),
            memory_range: f(2),
        },
        "motor_init" => C::MotorInit {
            max_speed: f(0),
            scale: f(1),
            ray_trace: int(2)?,
        },
        "words_to_speak" => C::WordsToSpeak((0..n).map(int).collect::<Result<_, _>>()?),
        "listen_to" => C::ListenTo {
            source: int(0)?,
            count: int(1)?,
        },
        "foothold_plane" => C::FootholdPlane(f(0)),
        "foothold_step" => C::FootholdStep {
            df_max: f(0),
            max_change: f(1),
        },
        "step_weights" => C::StepWeights([f(0), f(1), f(2), f(3), f(4), f(5)]),
        "foothold_map" => C::FootholdMap {
            range: f(0),
            min_voxels: int(1)?,
            foot: (n == 3).then(|| f(2)),
        },
        _ => unreachable!("every command of COMMANDS has an arm"),
    })
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
