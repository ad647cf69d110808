//! The definition file parser (appendix A, code 6.2.1): sections in their
//! fixed order, any of them omitted when empty.

use super::automata::{parse_script, BehaviourString};
use super::definition::{
    CameraParams, Definition, Growth, Production, RepetitionParams, RightSide, SymbolTemplate,
};
use super::expr::{Code, Compiler, Expr, Op};
use super::functions::{constant_arity, Constants, Spline};
use super::options::{parse_option, unknown_option};
use super::readable::{is_readable, to_classic};
use super::scan::{is_symbol_char, suggestion, Group, Scanner, SECTIONS};
use crate::source::{Diagnostic, FileRef, Source};

/// Largest window coordinate of `pref_pos_x1_x2_y1_y2`: far beyond any
/// screen, and differences of two stay far inside `i64`.
const MAX_WINDOW: i64 = 1 << 20;

/// Most copies `startp_sidel_nbr_dist` may ask for (placing them is
/// quadratic in their number).
const MAX_COPIES: i64 = 1_000_000;

/// Most key points of one spline.
const MAX_KEYS: i64 = 1_000_000;

/// Largest camera number: the camera goes into every frame's scene as
/// `f32`, where coordinates stay within ±1e18 (`scene::MAX_MAGNITUDE`).
const MAX_CAMERA: f64 = 1e18;

/// A camera number within ±[`MAX_CAMERA`].
fn camera_number(s: &mut Scanner, what: &str) -> Result<f64, Diagnostic> {
    let at = s.peek_word()?.0;
    let v = s.number(what)?;
    if v.abs() > MAX_CAMERA {
        return Err(s.error(
            at,
            format!("{what} must be within ±{MAX_CAMERA:e}, found {v:e}"),
        ));
    }
    Ok(v)
}

/// A lens length (m): not negative.
fn lens_number(s: &mut Scanner, what: &str) -> Result<f64, Diagnostic> {
    let at = s.peek_word()?.0;
    let v = camera_number(s, what)?;
    if v < 0.0 {
        return Err(s.error(at, format!("{what} must be ≥ 0 (metres), found {v}")));
    }
    Ok(v)
}

fn camera_floats(s: &mut Scanner, what: &str) -> Result<[f64; 3], Diagnostic> {
    Ok([
        camera_number(s, what)?,
        camera_number(s, what)?,
        camera_number(s, what)?,
    ])
}

/// A repetition scale: a copy of scale 0 (or one that rounds to 0 in the
/// renderer's `f32`) is flat and its transform cannot be inverted.
fn scale(s: &mut Scanner) -> Result<f64, Diagnostic> {
    let at = s.peek_word()?.0;
    let v = s.number("the scale")?;
    if !(1e-6..=1e6).contains(&v) {
        return Err(s.error(at, format!("the scale must be 1e-6..=1e6, found {v}")));
    }
    Ok(v)
}

/// Parses a whole definition file, classic or readable (`.lmr`, spelt
/// in the classic form first).
pub fn parse(src: &Source) -> Result<Definition, Diagnostic> {
    if is_readable(&src.name) && src.written.is_none() {
        return parse(&to_classic(src)?);
    }
    let mut p = Parser {
        s: Scanner::new(src),
        def: Definition {
            name: src.name.clone(),
            source: src.clone(),
            camera: CameraParams::default(),
            has_camera: false,
            repetition: RepetitionParams::default(),
            options: Vec::new(),
            splines: Vec::new(),
            constants: Constants::default(),
            surfaces: Vec::new(),
            motions: Vec::new(),
            axiom: Vec::new(),
            productions: Vec::new(),
            code: Code::default(),
            growth: vec![Growth::default()],
        },
        spline_numbers: Vec::new(),
    };
    p.file()?;
    Ok(p.def)
}

struct Parser<'a> {
    s: Scanner<'a>,
    def: Definition,
    spline_numbers: Vec<u32>,
}

impl<'a> Parser<'a> {
    fn file(&mut self) -> Result<(), Diagnostic> {
        let mut next = 0;
        while !self.s.at_end()? {
            let (at, w) = self.s.peek_word()?;
            let Some(k) = SECTIONS.iter().position(|s| *s == w) else {
                return Err(self.s.error(
                    at,
                    format!(
                        "expected a section name ({}), found `{w}`{}",
                        SECTIONS[next.min(7)..].join(", "),
                        suggestion(w, &SECTIONS)
                    ),
                ));
            };
            if k < next {
                return Err(self.s.error(
                    at,
                    format!(
                        "section `{w}` is out of order or repeated: sections come in the order {}",
                        SECTIONS.join(", ")
                    ),
                ));
            }
            self.s.word(w)?;
            next = k + 1;
            match k {
                0 => self.camera()?,
                1 => self.repetition()?,
                2 => self.options()?,
                3 => self.splines()?,
                4 => self.constants()?,
                5 => self.surfaces()?,
                6 => self.axiom()?,
                _ => self.productions()?,
            }
        }
        Ok(())
    }

    fn at_section(&mut self) -> Result<bool, Diagnostic> {
        self.s.at_section()
    }

    fn unknown(&self, at: usize, w: &str, section: &str, known: &str) -> Diagnostic {
        self.s.error(
            at,
            format!(
                "unknown keyword `{w}` in {section}; expected one of {known}{}",
                suggestion(w, &known.split(", ").collect::<Vec<_>>())
            ),
        )
    }

    fn camera(&mut self) -> Result<(), Diagnostic> {
        self.def.has_camera = true;
        let c = &mut self.def.camera;
        let s = &mut self.s;
        while !s.at_section()? {
            let (at, w) = s.word("a keyword")?;
            match w {
                "pref_pos_x1_x2_y1_y2" | "prefpos_x1_x2_y1_y2" => {
                    for v in &mut c.pref_pos {
                        *v = s.int_in("a window coordinate", -MAX_WINDOW..=MAX_WINDOW)?;
                    }
                }
                "observer" => c.observer = camera_floats(s, "the observer position")?,
                "lookatPoint" => c.look_at = camera_floats(s, "the look-at point")?,
                "twist" => c.twist = camera_number(s, "the twist angle")?,
                "viewAngle" => {
                    c.view_angle = camera_number(s, "the view angle in tenths of a degree")?
                }
                "aspectRatio" => c.aspect_ratio = camera_number(s, "the aspect ratio")?,
                "near" => c.near = camera_number(s, "the near distance")?,
                "far" => c.far = camera_number(s, "the far distance")?,
                "aperture" => c.aperture = lens_number(s, "the aperture radius")?,
                "focusDistance" => c.focus_distance = lens_number(s, "the focus distance")?,
                "swapinterval" => c.swap_interval = s.number("the swap interval")?,
                "nbrCalcStep_seed" => {
                    c.nbr_calc_step = s.int("the number of calculation steps")?;
                    let (sat, sw) = s.word("the seed")?;
                    c.seed = sw.parse::<u64>().map_err(|_| {
                        s.error(sat, format!("the seed must be a non-negative integer, found `{sw}`"))
                    })?;
                }
                "t_final_interval" => {
                    c.t_final_at = at;
                    c.t_final = s.number("the duration of the animation")?;
                    let dat = s.peek_word()?.0;
                    c.dt = s.number("the time interval Δt")?;
                    if c.dt <= 0.0 || c.t_final < 0.0 {
                        return Err(s.error(dat, "Δt must be > 0 and the duration ≥ 0"));
                    }
                }
                _ => {
                    return Err(self.unknown(at, w, "Camera_AnimationParameters",
                        "pref_pos_x1_x2_y1_y2, observer, lookatPoint, twist, viewAngle, aspectRatio, near, far, aperture, focusDistance, swapinterval, nbrCalcStep_seed, t_final_interval"))
                }
            }
        }
        Ok(())
    }

    fn repetition(&mut self) -> Result<(), Diagnostic> {
        let r = &mut self.def.repetition;
        let s = &mut self.s;
        while !s.at_section()? {
            let (at, w) = s.word("a keyword")?;
            match w {
                "rotate" => r.rotate = s.floats("a rotation angle")?,
                "rotate_max" => r.rotate_max = s.floats("a rotation angle")?,
                "translate" => r.translate = s.floats("a translation")?,
                "translate_max" => r.translate_max = s.floats("a translation")?,
                "scale" => r.scale = scale(s)?,
                "scale_max" => r.scale_max = scale(s)?,
                "time_scale" => r.time_scale = s.number("the time scale")?,
                "time_const" => r.time_const = s.number("the time limit")?,
                "startp_sidel_nbr_dist" => {
                    r.start_side_nbr_dist = (
                        s.number("the start point")?,
                        s.number("the side length")?,
                        s.int_in("the number of objects", 0..=MAX_COPIES)?,
                        s.number("the minimal distance")?,
                    )
                }
                _ => {
                    return Err(self.unknown(at, w, "RepetitionParameters",
                        "rotate, rotate_max, translate, translate_max, scale, scale_max, time_scale, time_const, startp_sidel_nbr_dist"))
                }
            }
        }
        Ok(())
    }

    fn options(&mut self) -> Result<(), Diagnostic> {
        while !self.at_section()? {
            match parse_option(&mut self.s)? {
                Some(o) => self.def.options.push(o),
                None => {
                    let (at, w) = self.s.peek_word()?;
                    return Err(unknown_option(&self.s, at, w));
                }
            }
        }
        Ok(())
    }

    fn splines(&mut self) -> Result<(), Diagnostic> {
        while !self.at_section()? {
            let (at, w) = self.s.word("`time_spline`")?;
            if w == "function" && self.s.at_keyword("time_spline")? {
                self.s.word("time_spline")?;
            } else if w != "time_spline" {
                return Err(self.s.error(at, format!("expected `function time_spline n count scale_arg scale_value …`, found `{w}`")));
            }
            let number = self.s.int("the spline number")?;
            let count = self.s.int_in("the number of key points", 0..=MAX_KEYS)?;
            let sa = self.s.number("the argument scale")?;
            let sv = self.s.number("the value scale")?;
            if !(0..100).contains(&number) || count < 0 {
                return Err(self
                    .s
                    .error(at, "spline number must be 0..99 and the count ≥ 0"));
            }
            let mut keys: Vec<(f64, f64)> = Vec::new();
            for _ in 0..count {
                let kat = self.s.peek_word()?.0;
                let a = self.s.number("a key point argument")? * sa;
                let v = self.s.number("a key point value")? * sv;
                if keys.last().is_some_and(|k| k.0 >= a) {
                    return Err(self.s.error(kat, "key point arguments must increase"));
                }
                keys.push((a, v));
            }
            let end = self.s.peek_word()?.0;
            let t = [
                self.s.number("the end marker 1e30")?,
                self.s.number("the end marker 1e30")?,
            ];
            if t != [1e30, 1e30] {
                return Err(self.s.error(
                    end,
                    format!("expected the end marker `1e30 1e30` after {count} key points"),
                ));
            }
            if self.def.spline(number as u32).is_some() {
                return Err(self
                    .s
                    .error(at, format!("spline {number} is defined twice")));
            }
            self.def.splines.push(Spline {
                number: number as u32,
                keys,
            });
            self.spline_numbers.push(number as u32);
        }
        Ok(())
    }

    fn constants(&mut self) -> Result<(), Diagnostic> {
        while !self.at_section()? {
            let (at, w) = self.s.word("a constant letter")?;
            let c = w.as_bytes()[0];
            let arity = (w.len() == 1).then(|| constant_arity(c)).flatten().ok_or_else(|| {
                self.s.error(at, format!("`{w}` is not a Constants function: use a..s or A..D (2 coefficients) or E..S (3)"))
            })?;
            let v = self.s.numbers(arity, "a coefficient")?;
            if v.len() != arity {
                // Points at the word that should have been a number
                // (`nan`, the next letter, the next section).
                let (nat, next) = self.s.peek_word()?;
                let found = if next.is_empty() {
                    "the end of the file".to_string()
                } else {
                    format!("`{next}`")
                };
                return Err(self.s.error(
                    nat,
                    format!(
                        "expected coefficient {} of `{w}` (it takes {arity}), found {found}",
                        v.len() + 1
                    ),
                ));
            }
            let mut k = [0.0; 3];
            k[..arity].copy_from_slice(&v);
            self.def.constants.set(c, k);
        }
        Ok(())
    }

    fn surfaces(&mut self) -> Result<(), Diagnostic> {
        while !self.at_section()? {
            let (at, w) = self.s.word("`fig_sm`")?;
            // `fig_sm` names the thesis's SM files, long gone; both it and
            // `fig_obj` point to Wavefront OBJ files now.
            if w != "fig_sm" && w != "fig_obj" && w != "fig_bvh" {
                return Err(self.s.error(
                    at,
                    format!("expected `fig_obj number file.obj` (or `fig_sm`), or `fig_bvh number file.bvh`, found `{w}`"),
                ));
            }
            let n = self.s.int("the surface number")?;
            let (at, f) = self.s.word("the surface file name")?;
            let file = (n, FileRef::new(self.s.src, at, f));
            if w == "fig_bvh" {
                self.def.motions.push(file);
            } else {
                self.def.surfaces.push(file);
            }
        }
        Ok(())
    }

    fn axiom(&mut self) -> Result<(), Diagnostic> {
        let mut axiom = Vec::new();
        while !self.at_section()? {
            self.s.reject_near_miss(&SECTIONS)?;
            axiom.push(self.symbol()?);
        }
        self.def.axiom = axiom;
        Ok(())
    }

    /// Compiles one `( )` group of this file.
    fn compile(&mut self, text: &str, offset: usize) -> Result<Option<Expr>, Diagnostic> {
        Compiler {
            src: self.s.src,
            code: &mut self.def.code,
            constants: &self.def.constants,
            splines: &self.spline_numbers,
        }
        .group(text, offset)
    }

    /// The behaviour command string of an `e` par1 = 0 in group `g`,
    /// nothing but commands left in it.
    fn script(&mut self, g: Group) -> Result<BehaviourString, Diagnostic> {
        let end = g.offset + g.text.len();
        let mut s = Scanner::within(self.s.src, g.offset, end);
        let script = parse_script(&mut s, g.offset)?;
        let (at, rest) = s.peek_word()?;
        if !rest.is_empty() {
            return Err(s.error(
                at,
                format!("`{rest}` is not an automata command (table B6)"),
            ));
        }
        Ok(script)
    }

    /// A parametric symbol: a character and up to 7 `( )` groups (age, x,
    /// y, z, f1, f2, f3); trailing empty groups may be omitted.
    fn symbol(&mut self) -> Result<SymbolTemplate, Diagnostic> {
        self.s.skip_trivia()?;
        let offset = self.s.pos;
        let ch = match self.s.peek() {
            Some(c) if is_symbol_char(c) => c,
            Some(b'(') => {
                return Err(self.s.error(
                    offset,
                    "a `( )` group without a symbol, or more than 7 groups after a symbol",
                ))
            }
            _ => {
                let w: String = self.s.src.text[offset..].chars().take(1).collect();
                return Err(self.s.error(offset, format!("`{w}` is not a symbol: symbols are letters, digits and [ ] {{ }} / ^ & $ + - ? .")));
            }
        };
        self.s.bump();
        let mut groups = Vec::with_capacity(7);
        while groups.len() < 7 {
            match self.s.group()? {
                Some(g) => groups.push(g),
                None => break,
            }
        }
        let get = |k: usize| groups.get(k).copied();
        let mut exprs: [Option<Expr>; 7] = [None; 7];
        // `e` with par1 = 0 carries an automata command as text in its
        // first growth group (appendix C.6), not an expression.
        // par1 is compiled first to know; an empty par1 is 0 too.
        if let Some(g) = get(1) {
            exprs[1] = self.compile(g.text, g.offset)?;
        }
        let text_growth = ch == b'e' && matches!(exprs[1], None | Some(Expr::Const(0.0)));
        for (k, g) in groups.iter().enumerate() {
            if k != 1 && !(text_growth && k == 4) {
                exprs[k] = self.compile(g.text, g.offset)?;
            }
        }
        let script = match get(4).filter(|_| text_growth) {
            Some(g) => Some(self.script(g)?),
            None => None,
        };
        let growth = Growth {
            f: [exprs[4], exprs[5], exprs[6]],
            script,
        };
        let growth = if growth == Growth::default() {
            0
        } else {
            self.def.growth.push(growth);
            (self.def.growth.len() - 1) as u32
        };
        Ok(SymbolTemplate {
            ch,
            age: exprs[0],
            par: [exprs[1], exprs[2], exprs[3]],
            growth,
            offset,
        })
    }

    fn productions(&mut self) -> Result<(), Diagnostic> {
        loop {
            if self.s.at_end()? {
                return Err(self.s.error(
                    self.s.pos,
                    "missing `EndProductions` at the end of the Productions section",
                ));
            }
            if self.s.at_keyword("EndProductions")? {
                self.s.word("EndProductions")?;
                return Ok(());
            }
            self.s.reject_near_miss(&["EndProductions"])?;
            let p = self.production()?;
            self.def.productions.push(p);
        }
    }

    fn context(&mut self) -> Result<Option<u8>, Diagnostic> {
        let Some(g) = self.s.group()? else {
            return Ok(None);
        };
        let t = g.text.trim();
        match t.as_bytes() {
            [] => Ok(None),
            [c] if is_symbol_char(*c) => Ok(Some(*c)),
            _ => Err(self.s.error(
                g.offset,
                format!("a context is one symbol, e.g. `(A)`, found `({t})`"),
            )),
        }
    }

    fn production(&mut self) -> Result<Production, Diagnostic> {
        let offset = self.s.pos;
        let lhs = match self.s.peek() {
            Some(c) if is_symbol_char(c) => c,
            _ => {
                let (at, w) = self.s.peek_word()?;
                return Err(self.s.error(at, format!("expected a production (a symbol and its `(max age)`) or `EndProductions`, found `{w}`")));
            }
        };
        self.s.bump();
        let after = self.s.pos;
        let Some(age) = self.s.group()? else {
            return Err(self.s.error(
                after,
                format!(
                    "expected the maximal age `( )` after the left side `{}`",
                    lhs as char
                ),
            ));
        };
        let max_age = self
            .compile(age.text, age.offset)?
            .unwrap_or(Expr::Const(0.0));
        self.s.skip_trivia()?;
        let condition = match self.s.peek() {
            Some(b'[') => Some(self.condition()?),
            Some(b'(') => {
                let g = self.s.group()?.expect("peeked `(`");
                if !g.text.trim().is_empty() {
                    return Err(self.s.error(
                        g.offset,
                        "a condition is written `[(expr)pred]`, e.g. `[(x)>]`; `()` means none",
                    ));
                }
                None
            }
            _ => None,
        };
        let left = self.context()?;
        let right = self.context()?;
        let mut parts = Vec::new();
        loop {
            if self.s.at_keyword("End")? {
                self.s.word("End")?;
                break;
            }
            let (at, w) = self.s.peek_word()?;
            if w.is_empty() || w == "EndProductions" {
                let _ = at;
                return Err(self.s.error(offset, format!("missing `End` for this production of `{}`: close it after its last `EndProb`", lhs as char)));
            }
            let probability = self.s.number("a probability or `End`")?;
            if probability < 0.0 {
                return Err(self.s.error(at, "a probability must not be negative"));
            }
            let mut symbols = Vec::new();
            loop {
                self.s.skip_trivia()?;
                if self.s.at_keyword("EndProb")? {
                    self.s.word("EndProb")?;
                    break;
                }
                if self.s.at_end()?
                    || self.s.at_keyword("End")?
                    || self.s.at_keyword("EndProductions")?
                {
                    return Err(self.s.error(
                        self.s.pos,
                        "missing `EndProb` at the end of this right side",
                    ));
                }
                self.s
                    .reject_near_miss(&["EndProb", "End", "EndProductions"])?;
                symbols.push(self.symbol()?);
            }
            parts.push(RightSide {
                probability,
                symbols,
            });
        }
        let total: f64 = parts.iter().map(|p| p.probability).sum();
        if parts.is_empty() || total <= 0.0 {
            return Err(self.s.error(offset, "a production needs at least one right side `probability … EndProb` with a probability > 0"));
        }
        Ok(Production {
            lhs,
            max_age,
            condition,
            left,
            right,
            parts,
            total,
            offset,
        })
    }

    /// A logical expression (definition 2.1.6).
    fn condition(&mut self) -> Result<Expr, Diagnostic> {
        let mut c = Compiler {
            src: self.s.src,
            code: &mut self.def.code,
            constants: &self.def.constants,
            splines: &self.spline_numbers,
        };
        condition(&mut self.s, &mut c)
    }
}

/// A logical expression: `[(expr)pred]` atoms combined postfix by
/// `&`, `|` and `!` (definition 2.1.6).
pub fn condition(s: &mut Scanner, c: &mut Compiler) -> Result<Expr, Diagnostic> {
    let start = s.pos;
    let mut em = c.begin();
    loop {
        s.skip_trivia()?;
        let at = s.pos;
        match s.peek() {
            Some(b'[') => {
                s.bump();
                let Some(g) = s.group()? else {
                    return Err(s.error(
                        s.pos,
                        "expected `(expr)` after `[` in a condition, e.g. `[(x)>]`",
                    ));
                };
                if g.text.trim().is_empty() {
                    return Err(s.error(g.offset, "empty expression in a condition atom"));
                }
                let before = c.code.ops.len();
                c.expression(&mut em, g.text, g.offset)?;
                if c.code.ops.len() == before {
                    return Err(s.error(g.offset, "empty expression in a condition atom"));
                }
                s.skip_trivia()?;
                let pat = s.pos;
                let pred = match s.peek() {
                    Some(b'<') => Op::Lt,
                    Some(b'p') => Op::Le,
                    Some(b'>') => Op::Gt,
                    Some(b'g') => Op::Ge,
                    Some(b'=') => Op::Eq,
                    Some(b'!') => Op::Ne,
                    _ => return Err(s.error(
                        pat,
                        "expected a predicate `<`, `p`, `>`, `g`, `=` or `!` after the expression",
                    )),
                };
                s.bump();
                c.push(&mut em, pred, pat)?;
                s.skip_trivia()?;
                if s.peek() != Some(b']') {
                    return Err(s.error(s.pos, "expected `]` to close the condition atom"));
                }
                s.bump();
            }
            Some(b'&') => {
                s.bump();
                c.push(&mut em, Op::And, at)?;
            }
            Some(b'|') => {
                s.bump();
                c.push(&mut em, Op::Or, at)?;
            }
            Some(b'!') => {
                s.bump();
                c.push(&mut em, Op::Not, at)?;
            }
            _ => break,
        }
    }
    c.finish(em, start)
}
