//! Interpretation of one word by the turtle (2.1.5–2.3.2, appendix C)
//! into shapes of its L-system's geometry.

use std::collections::BTreeMap;

mod figure;

use glam::{Affine3A, DVec3, Vec3};

use super::builder::Builder;
use super::polygon::{newell, triangulate, PolygonStack};
use super::state::{bend, Turtle};
use super::world::{ActorMapping, BodyPart, ParticleMapping, SoundCue, TurtleWorld};
use crate::lsys::step::ActorScope;
use crate::lsys::word::NO_ORIGIN;
use crate::lsys::{LSystem, Limits, Symbol, Who};
use crate::scene::body::Skeleton;
use crate::scene::mocap::Mocap;
use crate::scene::shape::{bounds, triangle_bounds, OVERLAY};
use crate::scene::{material, MAX_COORDINATE};
use crate::scene::{Geometry, Shape, ShapeKind, Triangle};

/// Settings of the interpretation that the thesis leaves to the renderer.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Options {
    /// Diameter of the thin cylinders drawn for segments `R S`.
    pub segment_width: f64,
    /// How big words, scenes, films and images may grow.
    pub limits: Limits,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            segment_width: 0.05,
            limits: Limits::default(),
        }
    }
}

/// Turtle positions and states saved by `[` with par1 = i; they persist
/// from one frame to the next (5.10.2).
#[derive(Debug, Clone, Default)]
pub struct Tables {
    pub position: BTreeMap<i64, DVec3>,
    pub state: BTreeMap<i64, Turtle>,
}

/// A placement of a shared geometry inside an L-system's frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Placed {
    /// An imported surface of the Surfaces section, by number.
    Surface(i64),
    /// A named object (`D` par1 = 6/13 … 1), by name number.
    Named(i64),
}

/// What one word draws, in its L-system's own frame.
#[derive(Debug, Default)]
pub struct Structure {
    pub geometry: Geometry,
    /// What is placed where, with the turtle's current material then (the
    /// colour of a surface's faces that name no material of their own),
    /// and the actor whose `M` branch placed it (its body).
    pub placements: Vec<(Placed, Affine3A, u32, Option<u32>)>,
    /// Named objects defined by this word.
    pub named: Vec<(i64, Geometry)>,
}

/// The active tropism (2.3.2): the most recent `v` met.
#[derive(Debug, Clone, Copy)]
struct Tropism {
    /// The `v` symbol whose growth functions give the field.
    field: Option<Symbol>,
    elasticity: f64,
    mass: f64,
    on: bool,
}

/// What the turtle stack saves: the turtle and the drawing state.
#[derive(Debug, Clone, Copy)]
struct Saved {
    turtle: Turtle,
    material: u32,
    segment: Option<u32>,
}

/// Whether every position of `m` is a number.
fn mapping_is_finite(m: &ActorMapping) -> bool {
    match *m {
        ActorMapping::Place { eye, look_at } => eye.is_finite() && look_at.is_finite(),
        ActorMapping::LocalGoal { at }
        | ActorMapping::DisplayEye { at }
        | ActorMapping::DisplayLookAt { at } => at.is_finite(),
        ActorMapping::ToTurtle { at, h } => at.is_finite() && h.is_finite(),
    }
}

fn v3(d: DVec3) -> Vec3 {
    d.as_vec3()
}

/// Local → geometry transform of a unit shape at the turtle, scaled along
/// H, L and U.
fn placed(t: &Turtle, sh: f64, sl: f64, su: f64) -> Affine3A {
    Affine3A::from_cols(
        v3(t.h * sh).into(),
        v3(t.l * sl).into(),
        v3(t.u * su).into(),
        v3(t.pos).into(),
    )
}

pub(super) struct Interpreter<'a> {
    ls: &'a mut LSystem,
    b: &'a mut Builder,
    world: &'a mut dyn TurtleWorld,
    /// The motion captures of the Surfaces sections (`fig_bvh`), by
    /// L-system and number.
    motions: &'a [(usize, i64, Mocap)],
    /// The joints of the body last placed (`D` par1 = 50, 52), where
    /// `D` par1 = 51 takes the turtle.
    joints: Option<(Skeleton, Vec<Affine3A>)>,
    time: f64,
    seed: u64,
    opts: Options,
    t: Turtle,
    stack: Vec<Saved>,
    material: u32,
    segment: Option<u32>,
    tropism: Tropism,
    polygons: PolygonStack,
    out: Structure,
    /// Index of the geometry being drawn: None = the main one.
    named: Option<(i64, Turtle)>,
    named_geometry: Geometry,
    /// Inverse of the turtle frame where each named object was defined.
    named_frames: BTreeMap<i64, Affine3A>,
    /// [`Symbol::origin`] of the symbol being interpreted, for warnings.
    origin: u32,
    /// The current actor along the word (`M` par1 = 7, C.5) and the
    /// symbol being interpreted's.
    scope: ActorScope,
    actor: Option<u32>,
}

/// Interprets the word of `ls` at time `time`.
#[allow(clippy::too_many_arguments)]
pub fn interpret(
    ls: &mut LSystem,
    time: f64,
    seed: u64,
    b: &mut Builder,
    tables: &mut Tables,
    world: &mut dyn TurtleWorld,
    motions: &[(usize, i64, Mocap)],
    opts: Options,
) -> Structure {
    let mut it = Interpreter {
        ls,
        b,
        world,
        motions,
        joints: None,
        time,
        seed,
        opts,
        t: Turtle::default(),
        stack: Vec::new(),
        material: 0,
        segment: None,
        tropism: Tropism {
            field: None,
            elasticity: 1.0,
            mass: 1.0,
            on: false,
        },
        polygons: PolygonStack::default(),
        out: Structure::default(),
        named: None,
        named_geometry: Geometry::default(),
        named_frames: BTreeMap::new(),
        origin: NO_ORIGIN,
        scope: ActorScope::default(),
        actor: None,
    };
    let n = it.ls.word().len();
    for i in 0..n {
        it.symbol(i, tables);
    }
    it.end_named();
    it.out.geometry.name = it.ls.def.name.clone();
    // The resolution is the largest `n` met, 10 where none is (C.3).
    for g in std::iter::once(&mut it.out.geometry).chain(it.out.named.iter_mut().map(|n| &mut n.1))
    {
        if g.resolution == 0 {
            g.resolution = 10;
        }
    }
    it.out
}

impl Interpreter<'_> {
    /// A warning about the symbol being interpreted, located at the text
    /// that made it.
    pub(super) fn warn(&mut self, msg: &str) {
        let place = self.ls.def.locate(self.origin);
        self.b.warn(&place, msg);
    }

    fn growth(&mut self, s: &Symbol) -> [f64; 3] {
        self.ls
            .growth(s, self.time, self.actor, self.seed, self.world)
    }

    fn who(&self, s: &Symbol) -> Who {
        Who {
            lsys: self.ls.index,
            symbol: s.id,
            actor: self.actor,
        }
    }

    fn geometry(&mut self) -> &mut Geometry {
        if self.named.is_some() {
            &mut self.named_geometry
        } else {
            &mut self.out.geometry
        }
    }

    /// A shape whose sizes are all finite and > 0 and whose bounds lie
    /// within ±[`MAX_COORDINATE`]; others are skipped with one warning per
    /// symbol kind. Past the scene's primitive limit nothing is drawn
    /// (the builder reports it).
    fn shape(
        &mut self,
        s: &Symbol,
        kind: ShapeKind,
        sizes: &[f64],
        transform: Affine3A,
        material: u32,
    ) {
        if self.skipped(s, sizes, transform.is_finite()) {
            return;
        }
        let shape = Shape {
            kind,
            transform,
            material,
            symbol: s.id,
        };
        self.add_shape(shape, s.ch);
    }

    /// A primitive of `symbol` drawn in the current actor's `M` branch is
    /// part of its body, which its own vision looks through.
    fn own(&mut self, symbol: u64) {
        if let (Some(a), false) = (self.actor, symbol == OVERLAY) {
            self.world.body(a, BodyPart::Symbol(symbol));
        }
    }

    /// Adds `shape`, drawn by symbol `ch`, when its bounds lie within
    /// ±[`MAX_COORDINATE`] (else one warning per symbol kind) and the
    /// scene's primitive limit allows.
    fn add_shape(&mut self, shape: Shape, ch: u8) {
        if bounds(&shape).is_none() {
            self.warn(&format!(
                "`{}` reaching beyond ±{MAX_COORDINATE:e} is skipped",
                ch as char
            ));
            return;
        }
        if self.b.count(1) {
            self.own(shape.symbol);
            self.geometry().shapes.push(shape);
        }
    }

    /// Whether a shape of these sizes is skipped, warning of mistakes: a
    /// size of exactly 0 is a shape not grown yet (growth functions start
    /// at 0 at birth), skipped silently; a negative or non-finite size, or
    /// a turtle frame that is not finite, is warned of.
    fn skipped(&mut self, s: &Symbol, sizes: &[f64], finite: bool) -> bool {
        if finite && sizes.iter().all(|v| v.is_finite() && *v > 0.0) {
            return false;
        }
        if !finite || sizes.iter().any(|v| !(v.is_finite() && *v >= 0.0)) {
            self.warn(&format!(
                "`{}` with a size < 0 or not a number is skipped",
                s.ch as char
            ));
        }
        true
    }

    /// A triangle of symbol `s` whose corners lie within
    /// ±[`MAX_COORDINATE`]; others are skipped with one warning per
    /// symbol kind.
    fn triangle(&mut self, v: [DVec3; 3], material: u32, s: &Symbol) {
        let v = v.map(v3);
        if triangle_bounds(&v).is_none() {
            self.warn(&format!(
                "a triangle of `{}` not finite or beyond ±{MAX_COORDINATE:e} is skipped",
                s.ch as char
            ));
            return;
        }
        if self.b.count(1) {
            self.own(s.id);
            self.geometry().triangles.push(Triangle {
                v,
                material,
                symbol: s.id,
            });
        }
    }

    /// Bends the turtle toward the tropism force at its position.
    fn tropism(&mut self) {
        if !self.tropism.on {
            return;
        }
        let mut f = self.world.field(self.t.pos);
        if let Some(v) = self.tropism.field {
            // The field's x, y, z are the turtle position (C.4).
            let at = Symbol {
                par: self.t.pos.to_array(),
                ..v
            };
            f += DVec3::from_array(self.growth(&at));
        }
        bend(&mut self.t, f * self.tropism.mass, self.tropism.elasticity);
    }

    /// `C`: maps the particle of this symbol and the turtle (C.4).
    fn particle(&mut self, s: &Symbol) {
        let dt = self.ls.dt;
        let [x, y, _] = s.par;
        let mapping = match x as i64 {
            // Ages are compared with a tolerance far below Δt (DESIGN §3).
            0 if s.age(dt) < dt * (1.0 - 1e-9) => ParticleMapping::Start {
                at: self.t.pos,
                mass: y,
                velocity: DVec3::from_array(self.growth(s)),
            },
            0 => ParticleMapping::Follow,
            1 => ParticleMapping::Place {
                at: DVec3::from_array(self.growth(s)),
            },
            6 => ParticleMapping::Turtle { at: self.t.pos },
            5 => {
                let actor = self.growth(s)[0];
                let count = self.world.actor_count();
                match usize::try_from(actor as i64) {
                    Ok(a) if a < count && actor.fract() == 0.0 => {
                        ParticleMapping::Racket { actor: a as u32 }
                    }
                    _ => {
                        return self.warn(&format!(
                            "`C` par1 = 5 names racket actor {actor}, which the scene does not declare (NBR_actors {count}); skipped"
                        ))
                    }
                }
            }
            _ => return,
        };
        if let Some(p) = self.world.map_particle(self.who(s), mapping) {
            if p.is_finite() {
                self.t.pos = p;
            }
        }
    }

    /// `M` (C.5): par1 = 7 puts the turtle at actor par3's eye, looking
    /// where it looks; 14 and 15 place the camera and the look-at point
    /// of its memory display at the turtle.
    fn actor_to_turtle(&mut self, s: &Symbol) {
        let [kind, _, actor] = s.par;
        let mapping = match kind as i64 {
            7 => ActorMapping::ToTurtle {
                at: self.t.pos,
                h: self.t.h,
            },
            14 => ActorMapping::DisplayEye { at: self.t.pos },
            15 => ActorMapping::DisplayLookAt { at: self.t.pos },
            _ => return,
        };
        let count = self.world.actor_count();
        if !(actor >= 0.0 && actor < count as f64 && actor.fract() == 0.0) {
            return self.warn(&format!(
                "`M` names actor {actor}, which the scene does not declare (NBR_actors {count}); skipped"
            ));
        }
        if let Some(pose) = self.world.map_actor(Some(actor as u32), mapping) {
            self.t.pos = pose.at;
            self.t.look_along(pose.h);
            let flat = DVec3::new(pose.h.x, 0.0, pose.h.z).normalize_or_zero();
            if pose.upright && flat != DVec3::ZERO {
                self.t.h = flat;
                self.t.l = DVec3::Y;
                self.t.u = flat.cross(DVec3::Y);
            }
            if let Some(m) = pose.material {
                self.material = m;
            }
        }
        if kind == 7.0 {
            self.show_path(actor as u32);
        }
    }

    /// The planned path of an actor that shows it (`turtle` 3): a small
    /// sphere at each key point, in the current material, drawn for the
    /// viewer only ([`OVERLAY`]: the actors' vision looks through it).
    fn show_path(&mut self, actor: u32) {
        const RADIUS: f64 = 0.08;
        for p in self.world.shown_path(actor) {
            let t = Turtle {
                pos: p,
                ..Turtle::default()
            };
            let shape = Shape {
                kind: ShapeKind::Sphere,
                transform: placed(&t, RADIUS, RADIUS, RADIUS),
                material: self.material,
                symbol: OVERLAY,
            };
            self.add_shape(shape, b'M');
        }
    }

    /// `g` (C.5): maps the turtle to the current actor — par1 = 0 its eye
    /// at the turtle, looking along H; 1 its local goal at the turtle; 2
    /// as 0 with the height par4, looking along H in the horizontal plane.
    fn turtle_to_actor(&mut self, s: &Symbol) {
        if self.world.actor_count() == 0 {
            return self.warn("`g` maps the turtle to an actor, and the scene has none; skipped");
        }
        let (pos, h) = (self.t.pos, self.t.h);
        let mapping = match s.par[0] as i64 {
            0 => ActorMapping::Place {
                eye: pos,
                look_at: pos + h,
            },
            1 => ActorMapping::LocalGoal { at: pos },
            2 => {
                let eye = DVec3::new(pos.x, self.growth(s)[0], pos.z);
                let flat = DVec3::new(h.x, 0.0, h.z).normalize_or_zero();
                let dir = if flat == DVec3::ZERO { h } else { flat };
                ActorMapping::Place {
                    eye,
                    look_at: eye + dir,
                }
            }
            _ => return,
        };
        if mapping_is_finite(&mapping) {
            self.world.map_actor(self.actor, mapping);
        } else {
            self.warn("`g` at a position that is not a number is skipped");
        }
    }

    fn forward(&mut self, d: f64) {
        if d.is_finite() {
            self.t.pos += d * self.t.h;
        }
    }

    fn symbol(&mut self, i: usize, tables: &mut Tables) {
        let s = self.ls.word()[i];
        self.origin = s.origin;
        self.actor = self.scope.visit(&s);
        let [x, y, _] = s.par;
        match s.ch {
            b'+' | b'-' | b'&' | b'^' | b'/' | b'$' | b'f' => self.motion(&s),
            b'[' | b']' => self.bracket(&s, tables),
            b'?' => {
                // The query symbol learns the turtle position (C.6).
                self.ls.word_mut()[i].par = self.t.pos.to_array();
            }
            b'm' | b'r' | b'n' | b'v' => self.drawing_state(&s),
            b'C' => self.particle(&s),
            b'M' => self.actor_to_turtle(&s),
            b'g' => self.turtle_to_actor(&s),
            b'I' => self.world.record_actors(),
            b'l' => {
                let g = DVec3::from_array(self.growth(&s));
                self.b.camera_symbol(s.par, g, self.who(&s), self.world);
            }
            b'R' | b'S' | b'c' | b'd' | b'O' | b'N' | b'o' | b'P' | b'Q' | b'a' | b's' | b'p'
            | b'q' | b'{' | b'.' | b'}' | b'B' => self.draw(&s),
            b'D' => self.d_symbol(&s),
            b'T' => self.sound(&s, x),
            // C.6: script par1; par2 = 0 only for the interactive window,
            // so a film runs it only when par2 ≠ 0.
            b'E' if y != 0.0 => {
                let g = self.growth(&s).map(|v| v as i64);
                self.world.command(x as i64, g);
            }
            _ => {}
        }
    }

    /// The turtle's motion: turns, pitches, rolls, orientation resets and moves (`+ - & ^ / $ f`, C.3).
    fn motion(&mut self, s: &Symbol) {
        let [_, y, z] = s.par;
        match s.ch {
            b'+' | b'-' | b'&' | b'^' | b'/' => {
                let a = self.growth(s)[0];
                match s.ch {
                    b'+' => self.t.turn(a),
                    b'-' => self.t.turn(-a),
                    b'&' => self.t.pitch(a),
                    b'^' => self.t.pitch(-a),
                    _ => self.t.roll(-a),
                }
            }
            b'$' => match y as i64 {
                1 => self.t.level(),
                2 => self.t.hang(),
                3 => self.t.reset_orientation(),
                4 => {
                    if let Some(v) = self.world.particle_velocity(self.who(s)) {
                        self.t.align(v);
                    }
                }
                5 => {
                    if let Some((p, dir)) = self.world.trace(z as i64) {
                        self.t.pos = p;
                        self.t.align(DVec3::new(dir.x, 0.0, dir.z));
                        self.t.horizontal();
                    }
                }
                6 => self.t.horizontal(),
                _ => {
                    let a = self.growth(s)[0];
                    self.t.roll(a);
                }
            },
            b'f' => {
                let g = DVec3::from_array(self.growth(s));
                if !g.is_finite() {
                    self.warn("`f` by a vector that is not a number is skipped");
                    return;
                }
                match z as i64 {
                    1 => self.t.pos += g,
                    2 => self.t.pos = g,
                    3 => self.t.pos += g.x * self.t.h + g.y * self.t.l + g.z * self.t.u,
                    _ => self.forward(g.x),
                }
            }
            _ => {}
        }
    }

    /// `[` and `]`: the turtle's stack, and its position and state tables (C.3).
    fn bracket(&mut self, s: &Symbol, tables: &mut Tables) {
        let [x, y, _] = s.par;
        match s.ch {
            b'[' => {
                let k = x as i64;
                if x == 0.0 {
                    self.stack.push(Saved {
                        turtle: self.t,
                        material: self.material,
                        segment: self.segment,
                    });
                } else if y == 0.0 {
                    tables.position.insert(k, self.t.pos);
                } else {
                    tables.state.insert(k, self.t);
                }
            }
            b']' => {
                let k = x as i64;
                if x == 0.0 {
                    if let Some(sv) = self.stack.pop() {
                        self.t = sv.turtle;
                        self.material = sv.material;
                        self.segment = sv.segment;
                    }
                } else if y == 0.0 {
                    if let Some(p) = tables.position.get(&k) {
                        self.t.pos = *p;
                        self.polygons.vertex(*p);
                    }
                } else if let Some(st) = tables.state.get(&k) {
                    self.t = *st;
                }
            }
            _ => {}
        }
    }

    /// What the next shapes are drawn with: material, segment colour, resolution and tropism (`m r n v`, C.4).
    fn drawing_state(&mut self, s: &Symbol) {
        let [x, _, z] = s.par;
        match s.ch {
            b'm' => {
                if z == 1.0 {
                    let rgb = Vec3::from_array(self.growth(s).map(|v| v as f32));
                    self.material = self.b.animated(self.material, rgb);
                } else if z != 2.0 {
                    self.material = material::by_number(x) as u32;
                }
            }
            b'r' => {
                let rgb = self.growth(s);
                self.segment = Some(self.b.segment(rgb, self.material));
            }
            b'n' => {
                let r = (x.round() as i64).clamp(3, 1024) as u32;
                let g = self.geometry();
                g.resolution = g.resolution.max(r);
            }
            b'v' => match x as i64 {
                0 => {
                    self.tropism.field = Some(*s);
                    self.tropism.on = true;
                }
                1 => {
                    let g = self.growth(s);
                    self.tropism.elasticity = g[0];
                    self.tropism.mass = if g[1] == 0.0 { 1.0 } else { g[1] };
                    self.tropism.on = true;
                }
                2 => self.tropism.on = false,
                _ => {}
            },
            _ => {}
        }
    }

    /// The shapes, polygons and placed surfaces (`R S c d O N o P Q a s p q { . } B`, C.2).
    fn draw(&mut self, s: &Symbol) {
        let [x, y, z] = s.par;
        match s.ch {
            b'R' | b'S' => {
                self.tropism();
                let len = self.growth(s)[0];
                let r = self.opts.segment_width / 2.0;
                let m = self.segment.unwrap_or(self.material);
                self.shape(
                    s,
                    ShapeKind::Cylinder,
                    &[len, r],
                    placed(&self.t, len, r, r),
                    m,
                );
                self.forward(len);
            }
            b'c' | b'd' => {
                let g = self.growth(s);
                self.shape(
                    s,
                    ShapeKind::Box,
                    &g,
                    placed(&self.t, g[0], g[1], g[2]),
                    self.material,
                );
                self.forward(g[0]);
                self.tropism();
            }
            b'O' | b'N' => {
                self.tropism();
                let g = self.growth(s);
                // Unit-radius capsule scaled by (k, par5, par6), k the mean
                // radius, so equal radii give exact half spheres.
                let k = (g[1] * g[2]).sqrt();
                let kind = ShapeKind::Capsule {
                    length: (g[0] / k) as f32,
                };
                self.shape(s, kind, &g, placed(&self.t, k, g[1], g[2]), self.material);
                self.forward(g[0]);
            }
            b'o' => {
                self.tropism();
                let g = self.growth(s);
                self.shape(
                    s,
                    ShapeKind::Cylinder,
                    &g,
                    placed(&self.t, g[0], g[1], g[2]),
                    self.material,
                );
                self.forward(g[0]);
            }
            b'P' | b'Q' => {
                let g = self.growth(s);
                let kind = ShapeKind::Trunk {
                    length: g[0] as f32,
                    r0: g[1] as f32,
                    r1: g[2] as f32,
                };
                self.shape(s, kind, &g, placed(&self.t, 1.0, 1.0, 1.0), self.material);
                self.forward(g[0]);
                self.tropism();
            }
            b'a' => {
                let r = self.growth(s)[0] / 2.0;
                self.shape(
                    s,
                    ShapeKind::Sphere,
                    &[r],
                    placed(&self.t, r, r, r),
                    self.material,
                );
            }
            b's' => {
                let g = self.growth(s).map(|v| v / 2.0);
                self.shape(
                    s,
                    ShapeKind::Sphere,
                    &g,
                    placed(&self.t, g[0], g[1], g[2]),
                    self.material,
                );
                self.tropism();
            }
            b'p' | b'q' => {
                let g = self.growth(s);
                self.pyramid(s, g);
                self.tropism();
            }
            b'{' => self.polygons.open(),
            b'.' => self.polygons.vertex(self.t.pos),
            b'}' => {
                let poly = self.polygons.close();
                let g = self.growth(s);
                self.polygon(s, &poly, [x, y, z], g[0]);
            }
            b'B' => {
                let g = self.growth(s);
                if g.iter().all(|v| v.is_finite() && *v != 0.0) {
                    let m = placed(&self.t, g[0], g[1], g[2]);
                    let placement = (Placed::Surface(x as i64), m, self.material, self.actor);
                    self.out.placements.push(placement);
                } else if g.iter().any(|v| !v.is_finite()) {
                    // A zero scale is a surface not grown yet: no warning.
                    self.warn("`B` with a scale that is not a number is skipped");
                }
            }
            _ => {}
        }
    }

    fn pyramid(&mut self, s: &Symbol, g: [f64; 3]) {
        if self.skipped(s, &g, true) {
            return;
        }
        let t = self.t;
        let apex = t.pos + g[0] * t.h;
        let c = |a: f64, b: f64| t.pos + a * g[1] / 2.0 * t.l + b * g[2] / 2.0 * t.u;
        let base = [c(1.0, 1.0), c(-1.0, 1.0), c(-1.0, -1.0), c(1.0, -1.0)];
        for k in 0..4 {
            // Sides face outward: (b_k, b_{k+1}, apex) winds around +H.
            self.triangle([base[k], base[(k + 1) % 4], apex], self.material, s);
        }
        self.triangle([base[0], base[2], base[1]], self.material, s);
        self.triangle([base[0], base[3], base[2]], self.material, s);
    }

    /// `}` with its variants: par1 = 1 inverts the normal; par2 = 1 adds a
    /// parallel copy at distance par4 along the normal; par3 = 1 closes the
    /// slab with side faces, par3 = 3 with thin cylinders along the edges.
    fn polygon(&mut self, s: &Symbol, poly: &[DVec3], flags: [f64; 3], depth: f64) {
        let tris = triangulate(poly);
        if tris.is_empty() {
            self.warn("a polygon with fewer than 3 distinct vertices or no area is skipped");
            return;
        }
        let invert = flags[0] == 1.0;
        let m = self.material;
        for t in &tris {
            let v = [poly[t[0]], poly[t[1]], poly[t[2]]];
            self.triangle(if invert { [v[0], v[2], v[1]] } else { v }, m, s);
        }
        if flags[1] != 1.0 || !depth.is_finite() {
            return;
        }
        let mut n = newell(poly).normalize();
        if invert {
            n = -n;
        }
        let off: Vec<DVec3> = poly.iter().map(|p| *p + depth * n).collect();
        for t in &tris {
            let v = [off[t[0]], off[t[1]], off[t[2]]];
            self.triangle(if invert { v } else { [v[0], v[2], v[1]] }, m, s);
        }
        let k = poly.len();
        match flags[2] as i64 {
            1 => {
                for a in 0..k {
                    let b = (a + 1) % k;
                    let (p, q, pp, qq) = (poly[a], poly[b], off[a], off[b]);
                    let quad = if invert ^ (depth < 0.0) {
                        [[p, q, qq], [p, qq, pp]]
                    } else {
                        [[p, qq, q], [p, pp, qq]]
                    };
                    for tri in quad {
                        self.triangle(tri, m, s);
                    }
                }
            }
            3 => {
                let r = self.opts.segment_width / 2.0;
                for a in 0..k {
                    for (p, q) in [(poly[a], poly[(a + 1) % k]), (off[a], off[(a + 1) % k])] {
                        let mut t = Turtle::at(p);
                        t.align(q - p);
                        let len = (q - p).length();
                        self.shape(s, ShapeKind::Cylinder, &[len, r], placed(&t, len, r, r), m);
                    }
                }
            }
            _ => {}
        }
    }

    /// Starts recording a named object (`D` par1 = 6 or 13).
    pub(super) fn begin_named(&mut self, name: i64) {
        self.end_named();
        self.named = Some((name, self.t));
    }

    /// Ends the named object being recorded (`D` par1 = 1).
    pub(super) fn end_named(&mut self) {
        if let Some((name, at)) = self.named.take() {
            self.named_frames
                .insert(name, placed(&at, 1.0, 1.0, 1.0).inverse());
            let mut g = std::mem::take(&mut self.named_geometry);
            g.name = format!("obj{name}");
            self.out.named.push((name, g));
        }
    }

    /// Places named object `name` at the turtle, relative to where the
    /// turtle stood when it was defined (`D` par1 = 7).
    pub(super) fn place_named(&mut self, name: i64) {
        let Some(def) = self.named_frames.get(&name).copied() else {
            self.warn(&format!(
                "`D` places object {name}, which no `D` par1 = 6 or 13 defined before"
            ));
            return;
        };
        let now = placed(&self.t, 1.0, 1.0, 1.0) * def;
        let placement = (Placed::Named(name), now, self.material, self.actor);
        self.out.placements.push(placement);
    }

    /// Applies `m` after the last placement (Rayshade transforms follow
    /// the object they modify).
    pub(super) fn transform_last_placement(&mut self, m: Affine3A) {
        match self.out.placements.last_mut() {
            Some((_, t, _, _)) => *t = m * *t,
            None => self.warn(
                "`D` par1 = 4, 8 or 9 transforms the object placed last, but none was placed",
            ),
        }
    }

    pub(super) fn turtle(&self) -> Turtle {
        self.t
    }

    pub(super) fn builder(&mut self) -> &mut Builder {
        self.b
    }

    pub(super) fn material(&self) -> u32 {
        self.material
    }

    pub(super) fn set_material(&mut self, m: u32) {
        self.material = m;
    }

    pub(super) fn push_triangle(&mut self, v: [DVec3; 3], material: u32, s: &Symbol) {
        self.triangle(v, material, s);
    }

    pub(super) fn push_shape(
        &mut self,
        s: &Symbol,
        kind: ShapeKind,
        sizes: &[f64],
        t: &Turtle,
        scale: [f64; 3],
        material: u32,
    ) {
        self.shape(
            s,
            kind,
            sizes,
            placed(t, scale[0], scale[1], scale[2]),
            material,
        );
    }

    /// `T` (C.6): par1 = 0 plays sound par4, 1 starts sound par4 from
    /// source par5 at the turtle, 2 moves source par4 to the turtle.
    fn sound(&mut self, s: &Symbol, mode: f64) {
        let g = self.growth(s);
        let whole =
            |v: f64| (v.is_finite() && v >= 0.0 && v <= u32::MAX as f64).then_some(v as u32);
        let at = self.t.pos;
        let request = match mode as i64 {
            0 => whole(g[0]).map(|sound| SoundCue::Play { sound }),
            1 => whole(g[0])
                .zip(whole(g[1]))
                .map(|(sound, source)| SoundCue::Emit { sound, source, at }),
            2 => whole(g[0]).map(|source| SoundCue::Move { source, at }),
            _ => {
                self.warn(&format!("`T` par1 = {mode} is not 0, 1 or 2: skipped"));
                return;
            }
        };
        match request {
            Some(r) => self.world.sound(r),
            None => self.warn(&format!(
                "`T` needs sound and source numbers ≥ 0, got {} {}: skipped",
                g[0], g[1]
            )),
        }
    }

    pub(super) fn growth_of(&mut self, s: &Symbol) -> [f64; 3] {
        self.growth(s)
    }

    /// How many shapes and triangles the main geometry holds so far.
    pub(super) fn geometry_bounds(&self) -> (usize, usize) {
        (
            self.out.geometry.shapes.len(),
            self.out.geometry.triangles.len(),
        )
    }

    pub(super) fn geometry_ref(&self) -> &Geometry {
        &self.out.geometry
    }
}
