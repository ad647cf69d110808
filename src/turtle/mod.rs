//! Interpretation of the derived words into the [`Scene`] of a frame
//! (DESIGN §1 step 1; thesis 2.1.5–2.3.2, appendix C).
//!
//! Each L-system's word is drawn once in its own frame into a shared
//! geometry; its repetitions (table B1) and imported surfaces are
//! instances of it, so a forest costs one tree plus transforms.

pub mod interpret;
pub mod polygon;
pub mod repetition;
pub mod special;
pub mod state;

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

use glam::{DVec3, Vec3};

use crate::lsys::{Animation, Sensors, Who};
use crate::scene::material::{self, Texture};
use crate::scene::{obj, Camera, Geometry, Instance, Light, LightKind, Material, Scene};
pub use interpret::{interpret, Options, Placed, Structure, Tables};
pub use state::Turtle;

/// What the turtle may ask of higher layers (particles, trajectories,
/// the sound log); the defaults answer for a world without them. The
/// same window answers the expressions the turtle evaluates (growth
/// functions) as their [`Sensors`].
pub trait TurtleWorld: Sensors {
    /// Force of the particle fields at `p`, added to the tropism force.
    fn field(&mut self, _p: DVec3) -> DVec3 {
        DVec3::ZERO
    }
    /// The `C` symbol `who` maps its particle and the turtle (C.4);
    /// returns where the turtle goes, if it moves.
    fn map_particle(&mut self, _who: Who, _mapping: ParticleMapping) -> Option<DVec3> {
        None
    }
    /// Velocity of the particle mapped to symbol `who` (`$` par2 = 4).
    fn particle_velocity(&mut self, _who: Who) -> Option<DVec3> {
        None
    }
    /// Position of the particle mapped to symbol `who` (`l` par3 = 4).
    fn particle_position(&mut self, _who: Who) -> Option<DVec3> {
        None
    }
    /// Position and direction of imported trajectory `n` (`$` par2 = 5).
    fn trace(&mut self, _n: i64) -> Option<(DVec3, DVec3)> {
        None
    }
    /// How many actors the film has (`NBR_actors`).
    fn actor_count(&self) -> usize {
        0
    }
    /// An `M` or `g` symbol maps actor `actor` — or, for None, the
    /// current actor — and the turtle (C.5); returns where the turtle
    /// goes, when it goes to the actor.
    fn map_actor(&mut self, _actor: Option<u32>, _mapping: ActorMapping) -> Option<ActorPose> {
        None
    }
    /// The `I` symbol: the records of the traced actors (`trace_actor`)
    /// are written for this frame.
    fn record_actors(&mut self) {}
    /// The planned path actor `actor` shows (its `turtle` 3, show path),
    /// key points from where it is.
    fn shown_path(&mut self, _actor: u32) -> Vec<DVec3> {
        Vec::new()
    }
    /// Microphone `mic` placed at `p` (`l` par3 = 8, 10).
    fn microphone(&mut self, _mic: i64, _p: DVec3) {}
    /// A sound event of the `T` symbol, for the sound event handler.
    fn sound(&mut self, _request: SoundRequest) {}
    /// The `E` symbol: run script `number` with the integer growth values.
    fn command(&mut self, _number: i64, _values: [i64; 3]) {}
    /// A part of actor `actor`'s body: drawn in its own `M` branch, so
    /// its vision looks through it (other actors and the camera see it).
    fn body(&mut self, _actor: u32, _part: BodyPart) {}
}

/// A primitive drawn in an actor's own `M` branch: by the symbol that
/// drew it, or the instance a placement there made.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BodyPart {
    Symbol(u64),
    Object(u32),
}

/// What a `C` symbol asks of the particle layer (C.4), in world
/// coordinates.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ParticleMapping {
    /// par1 = 0 at local age < Δt: the particle starts at the turtle with
    /// mass par2 and velocity par4..6.
    Start {
        at: DVec3,
        mass: f64,
        velocity: DVec3,
    },
    /// par1 = 0 later: the turtle goes to the evolved particle.
    Follow,
    /// par1 = 1: the particle, and the turtle, at par4..6.
    Place { at: DVec3 },
    /// par1 = 6: the particle at the turtle.
    Turtle { at: DVec3 },
    /// par1 = 5: the particle at the racket of actor par4, and the turtle
    /// with it.
    Racket { actor: u32 },
}

/// What an `M` or `g` symbol asks of an actor (C.5), in world
/// coordinates.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ActorMapping {
    /// `M` par1 = 7: the turtle goes to the actor's eye, looking where it
    /// looks, and the actor becomes the current actor — unless it runs
    /// `follow_turtle`, which follows the turtle (`at`, heading `h`).
    ToTurtle {
        at: DVec3,
        h: DVec3,
    },
    /// `g` par1 = 0, 2: the actor's eye at `eye`, looking at `look_at`.
    Place {
        eye: DVec3,
        look_at: DVec3,
    },
    /// `g` par1 = 1: the actor's local goal at `at`.
    LocalGoal {
        at: DVec3,
    },
    /// `M` par1 = 14, 15: the camera, or the look-at point, of the
    /// actor's memory display at `at`.
    DisplayEye {
        at: DVec3,
    },
    DisplayLookAt {
        at: DVec3,
    },
}

/// Where `M` par1 = 7 puts the turtle: at the actor's eye `at`, H along
/// `h`; with `upright`, L vertical (turtle 1, footholds: H is then the
/// horizontal part of `h`); and the material it activates, if any.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ActorPose {
    pub at: DVec3,
    pub h: DVec3,
    pub upright: bool,
    pub material: Option<u32>,
}

impl ActorPose {
    /// The turtle at `eye`, looking at `look_at`.
    pub fn looking(eye: DVec3, look_at: DVec3) -> Self {
        ActorPose {
            at: eye,
            h: look_at - eye,
            upright: false,
            material: None,
        }
    }
}

/// What a `T` symbol asks of the sound event handler (C.6), in world
/// coordinates.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum SoundRequest {
    /// par1 = 0: play sound `sound` back (no place: heard as is).
    Play { sound: u32 },
    /// par1 = 1: source `source` starts sound `sound` at `at`.
    Emit { sound: u32, source: u32, at: DVec3 },
    /// par1 = 2: source `source` moves to `at`.
    Move { source: u32, at: DVec3 },
}

/// A world with no particles, trajectories or sound log, whose sensors
/// give their defaults.
#[derive(Debug, Default, Clone, Copy)]
pub struct NoWorld;

impl Sensors for NoWorld {}

impl TurtleWorld for NoWorld {}

/// Imported surfaces (`fig_obj`/`fig_sm`), loaded once per animation.
#[derive(Debug, Default, Clone)]
pub struct Surfaces {
    /// (L-system index, surface number, geometry index in `geometries`).
    pub index: Vec<(usize, i64, usize)>,
    pub geometries: Vec<Geometry>,
    pub materials: Vec<Material>,
    /// Per geometry, the material of its faces that name none (an OBJ
    /// without MTL): those take the turtle's material at `B` instead.
    pub unset: Vec<Option<u32>>,
}

impl Surfaces {
    /// Reads every surface of every L-system; paths are relative to the
    /// definition file's folder.
    pub fn load(anim: &Animation) -> Result<Surfaces, String> {
        let mut s = Surfaces::default();
        for ls in &anim.systems {
            let dir = Path::new(&ls.def.name).parent().unwrap_or(Path::new("."));
            for (n, file) in &ls.def.surfaces {
                let base = (material::COUNT + s.materials.len()) as u32;
                let path = dir.join(&file.name);
                // The built-in film's surfaces are part of the program.
                let read = if ls.def.name.starts_with(obj::BUILT_IN_PREFIX) {
                    obj::read_built_in_obj(&file.name, base)
                } else {
                    None
                };
                let read = read.unwrap_or_else(|| obj::read_obj(&path, base));
                let (tris, mats) = read.map_err(|e| match e {
                    // Where the scene names the file; problems inside are
                    // located in the OBJ or MTL file itself.
                    obj::MeshError::Read(e) => file.error(format!("surface {n}: {e}")).to_string(),
                    obj::MeshError::Content(e) => e,
                })?;
                // `read_obj` appends the default material last for the
                // faces that name none.
                let unset = mats
                    .last()
                    .filter(|m| **m == material::table()[0])
                    .map(|_| base + mats.len() as u32 - 1)
                    .filter(|u| tris.iter().any(|t| t.material == *u));
                s.unset.push(unset);
                s.materials.extend(mats);
                s.index.push((ls.index, *n, s.geometries.len()));
                s.geometries.push(Geometry {
                    name: file.name.clone(),
                    shapes: Vec::new(),
                    triangles: tris,
                    resolution: 10,
                });
            }
        }
        Ok(s)
    }
}

/// Scene-wide state built while the words are interpreted.
pub struct Builder {
    pub materials: Vec<Material>,
    derived: BTreeMap<(u32, [u32; 3], u8), u32>,
    pub camera: Camera,
    light3: Option<Light>,
    extra_lights: Vec<Light>,
    pub background: Vec3,
    /// Set by `D` par1 = 40, looked at by `l` par3 = 10.
    pub lookat_global: Option<DVec3>,
    warned: BTreeSet<String>,
    /// Warnings and `D` par1 = 30 prints, in order, for the user.
    pub messages: Vec<String>,
    /// Bounding boxes of `D` par1 = 20 … 21 (min, max).
    pub bounding_boxes: Vec<(Vec3, Vec3)>,
    bbox_start: Vec<(usize, usize)>,
    /// Primitives (shapes, triangles, instances) in the scene so far, and
    /// the most it may hold ([`crate::lsys::Limits::shapes`]).
    primitives: usize,
    max_primitives: usize,
}

impl Builder {
    fn new(camera: Camera, surface_materials: &[Material], max_primitives: usize) -> Self {
        let mut materials = material::table();
        materials.extend_from_slice(surface_materials);
        Builder {
            materials,
            derived: BTreeMap::new(),
            camera,
            light3: None,
            extra_lights: Vec::new(),
            background: Vec3::new(0.0, 0.0, 0.0),
            lookat_global: None,
            warned: BTreeSet::new(),
            messages: Vec::new(),
            bounding_boxes: Vec::new(),
            bbox_start: Vec::new(),
            primitives: 0,
            max_primitives,
        }
    }

    /// Counts `n` more primitives; false once the scene would hold more
    /// than its limit, so nothing past it is drawn or allocated.
    fn count(&mut self, n: usize) -> bool {
        self.primitives = self.primitives.saturating_add(n);
        self.primitives <= self.max_primitives
    }

    /// Whether the scene went over its primitive limit.
    fn over(&self) -> bool {
        self.primitives > self.max_primitives
    }

    /// Records a warning once per frame: each names its symbol, so there
    /// is one per symbol kind and problem, never one per symbol, and it
    /// is located at the first place met (`file:line:column` of the text
    /// that made the symbol, or the file).
    pub fn warn(&mut self, place: &str, msg: &str) {
        if self.warned.insert(msg.to_string()) {
            self.messages.push(format!("{place}: warning: {msg}"));
        }
    }

    pub fn print(&mut self, msg: String) {
        self.messages.push(msg);
    }

    /// A material derived from `base`, created once per distinct variant.
    fn derive(
        &mut self,
        base: u32,
        key: [f32; 3],
        tag: u8,
        make: impl FnOnce(&Material) -> Material,
    ) -> u32 {
        let k = (base, key.map(f32::to_bits), tag);
        if let Some(&m) = self.derived.get(&k) {
            return m;
        }
        let m = make(&self.materials[base as usize]);
        self.materials.push(m);
        let i = (self.materials.len() - 1) as u32;
        self.derived.insert(k, i);
        i
    }

    /// `m` par3 = 1: the current material with diffuse `rgb`.
    pub fn animated(&mut self, base: u32, rgb: Vec3) -> u32 {
        self.derive(base, rgb.to_array(), 0, |m| m.with_diffuse(rgb))
    }

    /// `r`: a segment colour (0..255), seen by vision as `base` is.
    pub fn segment(&mut self, rgb: [f64; 3], base: u32) -> u32 {
        let key = rgb.map(|v| v as f32);
        self.derive(base, key, 1, |m| material::segment_colour(rgb, m.vision))
    }

    /// `D` par1 = 10, 11 (and the cloud layer): a material with a texture.
    pub fn textured(&mut self, base: u32, t: Texture) -> u32 {
        let tag = match t {
            Texture::Marble => 2,
            Texture::Bump => 3,
            Texture::Cloud => 4,
        };
        self.derive(base, [0.0; 3], tag, |m| Material {
            texture: Some(t),
            ..m.clone()
        })
    }

    /// A fixed material of the built-in objects (court, clouds).
    ///
    /// Vision sees it as table material `like` (the court as green, its
    /// lines as white), so vision colours stay apart (3.1.2).
    pub fn builtin_material(&mut self, rgb: Vec3, name: &str, like: usize) -> u32 {
        if let Some(i) = self.materials.iter().position(|m| m.name == name) {
            return i as u32;
        }
        let vision = self.materials[like.min(material::COUNT - 1)].vision;
        let mut m = material::segment_colour((rgb * 255.0).as_dvec3().to_array(), vision);
        m.name = name.to_string();
        self.materials.push(m);
        (self.materials.len() - 1) as u32
    }

    /// `D` par1 = 15: a sky blue background.
    pub fn sky(&mut self) {
        self.background = Vec3::new(0.45, 0.62, 0.9);
    }

    /// `D` par1 = 18: a light at the observer.
    pub fn observer_light(&mut self) {
        self.extra_lights
            .push(Light::point(self.camera.eye, Vec3::splat(0.5)));
    }

    pub fn bbox_begin(&mut self, n: (usize, usize)) {
        self.bbox_start.push(n);
    }

    /// Bounds of what was drawn since the matching begin, shapes taken at
    /// a coarse tessellation; false when no begin is open.
    pub fn bbox_end(&mut self, g: &Geometry, end: (usize, usize)) -> bool {
        let Some((s0, t0)) = self.bbox_start.pop() else {
            return false;
        };
        let mut tris: Vec<_> = g.triangles[t0.min(end.1)..end.1].to_vec();
        for sh in &g.shapes[s0.min(end.0)..end.0] {
            crate::scene::mesh::tessellate(sh, 8, &mut tris);
        }
        let mut lo = Vec3::splat(f32::INFINITY);
        let mut hi = Vec3::splat(f32::NEG_INFINITY);
        for v in tris.iter().flat_map(|t| t.v) {
            lo = lo.min(v);
            hi = hi.max(v);
        }
        if lo.x <= hi.x {
            self.bounding_boxes.push((lo, hi));
            self.messages.push(format!(
                "bounding box {:.6} {:.6} {:.6} {:.6} {:.6} {:.6}",
                lo.x, lo.y, lo.z, hi.x, hi.y, hi.z
            ));
        }
        true
    }

    /// `l`: camera (par3 = 0, 1, 2, 4, 5, 8, 10) and light 3 (par3 = 3,
    /// and the extensions 12, 13).
    /// `par` = (par1, par2 = microphone, par3 = mode); `g` = par4..6.
    pub fn camera_symbol(
        &mut self,
        par: [f64; 3],
        g: DVec3,
        who: Who,
        world: &mut dyn TurtleWorld,
    ) {
        let (radius, mic, mode) = (par[0], par[1] as i64, par[2] as i64);
        let c = &mut self.camera;
        match mode {
            0 => c.eye = g.as_vec3(),
            1 => c.look_at = g.as_vec3(),
            2 => {
                c.fov_y = (g.x / 10.0) as f32;
                c.aspect = g.y as f32;
                c.twist = (g.z / 10.0) as f32;
            }
            3 => self.light3 = Some(Light::point(g.as_vec3(), Vec3::ONE)),
            // Extensions: light 3 as the sun travelling along par4..6, or
            // as a sphere of radius par1 at par4..6 for soft shadows.
            12 => {
                let direction = g.as_vec3();
                self.light3 = Some(Light {
                    position: Vec3::ZERO,
                    color: Vec3::ONE,
                    kind: LightKind::Directional { direction },
                });
            }
            13 => {
                let radius = (radius as f32).max(0.0);
                self.light3 = Some(Light {
                    position: g.as_vec3(),
                    color: Vec3::ONE,
                    kind: LightKind::Sphere { radius },
                });
            }
            4 => {
                if let Some(p) = world.particle_position(who) {
                    c.eye = p.as_vec3();
                }
            }
            5 => {
                if let (Some(p), Some(v)) =
                    (world.particle_position(who), world.particle_velocity(who))
                {
                    c.look_at = (p + v.normalize_or_zero() * g.x).as_vec3();
                }
            }
            8 => {
                c.eye = g.as_vec3();
                world.microphone(mic, g);
            }
            10 => {
                c.eye = g.as_vec3();
                if let Some(l) = self.lookat_global {
                    c.look_at = l.as_vec3();
                }
                world.microphone(mic, g);
            }
            _ => {}
        }
    }
}

/// The geometry of surface `gi` placed with the turtle's material `mat`:
/// its faces that name no material take `mat` (thesis: the current
/// material applies to what is drawn). One copy per surface and material
/// and frame; the default material keeps the shared geometry.
fn surface_in(
    gi: usize,
    mat: u32,
    surfaces: &Surfaces,
    geometries: &mut Vec<Geometry>,
    recoloured: &mut BTreeMap<(usize, u32), u32>,
) -> u32 {
    let Some(unset) = surfaces.unset[gi].filter(|_| mat != 0) else {
        return gi as u32;
    };
    *recoloured.entry((gi, mat)).or_insert_with(|| {
        let mut g = surfaces.geometries[gi].clone();
        for t in &mut g.triangles {
            if t.material == unset {
                t.material = mat;
            }
        }
        geometries.push(g);
        (geometries.len() - 1) as u32
    })
}

/// The image size of the camera's window `prefpos_x1_x2_y1_y2`, in
/// pixels (1…16384 a side).
pub fn window([x1, x2, y1, y2]: [i64; 4]) -> (u32, u32) {
    let side = |a: i64, b: i64| (b - a).unsigned_abs().clamp(1, 16384) as u32;
    (side(x1, x2), side(y1, y2))
}

/// Builds the scene of the animation's current frame. `tables` keeps the
/// turtle state tables of each L-system from frame to frame. A scene of
/// more primitives than `opts.limits.shapes` is an error naming the file
/// and the frame.
pub fn build_scene(
    anim: &mut Animation,
    surfaces: &Surfaces,
    tables: &mut Vec<Tables>,
    world: &mut dyn TurtleWorld,
    opts: Options,
) -> Result<(Scene, Vec<String>), String> {
    let cam = &anim.camera;
    let camera = Camera {
        eye: DVec3::from_array(cam.observer).as_vec3(),
        look_at: DVec3::from_array(cam.look_at).as_vec3(),
        twist: (cam.twist / 10.0) as f32,
        fov_y: (cam.view_angle / 10.0) as f32,
        aspect: cam.aspect_ratio as f32,
        near: cam.near as f32,
        far: cam.far as f32,
        width: window(cam.pref_pos).0,
        height: window(cam.pref_pos).1,
    };
    let max = opts.limits.shapes;
    let mut b = Builder::new(camera, &surfaces.materials, max);
    let (time, seed, frame) = (anim.time(), anim.camera.seed, anim.frame);
    let too_many = |file: &str| {
        format!(
            "{file}: frame {frame}: the scene would hold more than {max} primitives (shapes, triangles and copies), the limit; raise it with --max-shapes N"
        )
    };
    let imported: usize = surfaces.geometries.iter().map(|g| g.triangles.len()).sum();
    if !b.count(imported) {
        return Err(too_many(&anim.systems[0].def.name));
    }
    tables.resize(anim.systems.len(), Tables::default());
    let mut geometries: Vec<Geometry> = surfaces.geometries.clone();
    let mut recoloured = BTreeMap::new();
    let mut instances = Vec::new();
    for (k, ls) in anim.systems.iter_mut().enumerate() {
        let st = interpret(ls, time, seed, &mut b, &mut tables[k], world, opts);
        // Each copy is one instance of the word and one per placement.
        let nbr = ls.def.repetition.start_side_nbr_dist.2.max(1) as usize;
        if b.over() || !b.count(nbr.saturating_mul(1 + st.placements.len())) {
            return Err(too_many(&ls.def.name));
        }
        let copies = repetition::transforms(&ls.def.repetition, seed, k);
        let main = geometries.len() as u32;
        geometries.push(st.geometry);
        let mut named = BTreeMap::new();
        for (name, g) in st.named {
            named.insert(name, geometries.len() as u32);
            geometries.push(g);
        }
        // Each placement's geometry, resolved once for all the copies.
        let mut placed = Vec::with_capacity(st.placements.len());
        for &(what, m, mat, owner) in &st.placements {
            let g = match what {
                Placed::Named(n) => named.get(&n).copied(),
                Placed::Surface(n) => surfaces
                    .index
                    .iter()
                    .find(|(l, sn, _)| *l == k && *sn == n)
                    .map(|(_, _, gi)| {
                        surface_in(*gi, mat, surfaces, &mut geometries, &mut recoloured)
                    }),
            };
            match g {
                Some(g) => placed.push((g, m, owner)),
                None => b.warn(
                    &ls.def.name,
                    &format!(
                        "`B` draws surface {what:?}, which the Surfaces section does not declare"
                    ),
                ),
            }
        }
        for r in &copies {
            let object = instances.len() as u32;
            instances.push(Instance {
                geometry: main,
                transform: *r,
                object,
            });
            for (g, m, owner) in &placed {
                let object = instances.len() as u32;
                instances.push(Instance {
                    geometry: *g,
                    transform: *r * *m,
                    object,
                });
                if let Some(a) = owner {
                    world.body(*a, BodyPart::Object(object));
                }
            }
        }
    }
    let mut lights: Vec<Light> = b.light3.into_iter().collect();
    lights.extend(b.extra_lights.iter().copied());
    if lights.is_empty() {
        // Every scene is visible: a white light at the observer.
        lights.push(Light::point(b.camera.eye, Vec3::ONE));
    }
    let scene = Scene {
        frame,
        time,
        camera: b.camera,
        lights,
        materials: b.materials,
        geometries,
        instances,
        background: b.background,
    };
    Ok((scene, b.messages))
}
