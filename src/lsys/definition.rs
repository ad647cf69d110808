//! A parsed L-system definition file (appendix A, table B1): every section
//! as data, the axiom and productions with their expressions compiled.

use super::expr::{Code, Expr};
use super::functions::{Constants, Spline};
use super::options::OptionItem;
use crate::source::{FileRef, Source};

/// `Camera_AnimationParameters`, including the two lines the BNF forgets.
#[derive(Debug, Clone, PartialEq)]
pub struct CameraParams {
    /// Window x1 x2 y1 y2 on the screen; the default image size.
    pub pref_pos: [i64; 4],
    pub observer: [f64; 3],
    pub look_at: [f64; 3],
    pub twist: f64,
    /// Vertical field of view in tenths of a degree.
    pub view_angle: f64,
    pub aspect_ratio: f64,
    pub near: f64,
    pub far: f64,
    pub swap_interval: f64,
    /// RK4 sub-steps per frame for the particle system.
    pub nbr_calc_step: i64,
    /// The scene seed of every random number.
    pub seed: u64,
    /// Duration of the animation in seconds.
    pub t_final: f64,
    /// Δt, the time between two frames.
    pub dt: f64,
    /// The thin lens's aperture radius and distance in focus (m;
    /// extensions `aperture`, `focusDistance`: 0 is the pinhole, and
    /// the look-at point's distance).
    pub aperture: f64,
    pub focus_distance: f64,
    /// Byte offset of the `t_final_interval` line (0 when there is none),
    /// where an error about the film's length points.
    pub t_final_at: usize,
}

impl Default for CameraParams {
    fn default() -> Self {
        CameraParams {
            pref_pos: [0, 639, 0, 479],
            observer: [0.0, 0.0, 100.0],
            look_at: [0.0, 0.0, 0.0],
            twist: 0.0,
            view_angle: 500.0,
            aspect_ratio: 4.0 / 3.0,
            near: 0.1,
            far: 10000.0,
            swap_interval: 1.0,
            nbr_calc_step: 4,
            seed: 0,
            t_final: 10.0,
            dt: 0.04,
            aperture: 0.0,
            focus_distance: 0.0,
            t_final_at: 0,
        }
    }
}

/// `RepetitionParameters`: stochastic placement of copies of the structure.
#[derive(Debug, Clone, PartialEq)]
pub struct RepetitionParams {
    pub rotate: [f64; 3],
    pub rotate_max: [f64; 3],
    pub translate: [f64; 3],
    pub translate_max: [f64; 3],
    pub scale: f64,
    pub scale_max: f64,
    /// Factor applied to Δt for this L-system (≤ 0 means 1).
    pub time_scale: f64,
    /// If > 0, derivation stops once the global time exceeds it.
    pub time_const: f64,
    /// Start point, side length, number of objects, minimal distance.
    pub start_side_nbr_dist: (f64, f64, i64, f64),
}

impl Default for RepetitionParams {
    fn default() -> Self {
        RepetitionParams {
            rotate: [0.0; 3],
            rotate_max: [0.0; 3],
            translate: [0.0; 3],
            translate_max: [0.0; 3],
            scale: 1.0,
            scale_max: 1.0,
            time_scale: 1.0,
            time_const: 0.0,
            start_side_nbr_dist: (0.0, 0.0, 1, 0.0),
        }
    }
}

/// An axiom or right-side symbol: its character and compiled groups.
#[derive(Debug, Clone, PartialEq)]
pub struct SymbolTemplate {
    pub ch: u8,
    /// Initial age (group 1).
    pub age: Option<Expr>,
    /// x, y, z (groups 2–4), evaluated once when the symbol is created.
    pub par: [Option<Expr>; 3],
    /// Index into [`Definition::growth`] of groups 5–7.
    pub growth: u32,
    /// Byte offset in the file, for diagnostics of later layers.
    pub offset: usize,
}

/// The growth functions of a symbol, evaluated at interpretation time.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Growth {
    pub f: [Option<Expr>; 3],
    /// The behaviour command string of `e` with par1 = 0 (C.6): its first
    /// growth group is text rather than an expression.
    pub script: Option<crate::lsys::automata::BehaviourString>,
}

/// One `probability … EndProb` part of a production.
#[derive(Debug, Clone, PartialEq)]
pub struct RightSide {
    pub probability: f64,
    pub symbols: Vec<SymbolTemplate>,
}

/// `LeftSide (max age) condition (left context) (right context) parts End`.
#[derive(Debug, Clone, PartialEq)]
pub struct Production {
    pub lhs: u8,
    pub max_age: Expr,
    pub condition: Option<Expr>,
    pub left: Option<u8>,
    pub right: Option<u8>,
    pub parts: Vec<RightSide>,
    /// Sum of the part probabilities; choices are normalised by it.
    pub total: f64,
    pub offset: usize,
}

/// A whole definition file.
#[derive(Debug, Clone)]
pub struct Definition {
    pub name: String,
    /// The file, to locate what later layers warn about.
    pub source: Source,
    pub camera: CameraParams,
    /// Whether the file had a `Camera_AnimationParameters` section.
    pub has_camera: bool,
    pub repetition: RepetitionParams,
    pub options: Vec<OptionItem>,
    pub splines: Vec<Spline>,
    pub constants: Constants,
    /// `fig_sm n file` declarations.
    pub surfaces: Vec<(i64, FileRef)>,
    /// `fig_bvh number file.bvh`: motion captures that drive bodies.
    pub motions: Vec<(i64, FileRef)>,
    pub axiom: Vec<SymbolTemplate>,
    pub productions: Vec<Production>,
    pub code: Code,
    pub growth: Vec<Growth>,
}

impl Definition {
    /// The `fConst` arrays declared in Options, indexed by number.
    pub fn fconst(&self) -> Vec<[f64; 8]> {
        let mut v: Vec<[f64; 8]> = Vec::new();
        for o in &self.options {
            if let OptionItem::FConst { index, values } = o {
                let i = *index as usize;
                if v.len() <= i {
                    v.resize(i + 1, [0.0; 8]);
                }
                v[i] = *values;
            }
        }
        v
    }

    /// `file:line:column` of byte `offset` (a symbol's
    /// [`Symbol::origin`](super::Symbol::origin)), or the file alone
    /// when the offset is not in it.
    pub fn locate(&self, offset: u32) -> String {
        match usize::try_from(offset)
            .ok()
            .filter(|o| *o < self.source.text.len())
        {
            Some(o) => {
                let (line, column) = self.source.place(o);
                format!("{}:{line}:{column}", self.name)
            }
            None => self.name.clone(),
        }
    }

    pub fn spline(&self, n: u32) -> Option<&Spline> {
        self.splines.iter().find(|s| s.number == n)
    }
}
