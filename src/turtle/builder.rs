//! The scene a frame's words build: the shared geometry, materials,
//! lights and camera, and the surfaces (OBJ meshes) the scene imports.

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

use glam::{DVec3, Vec3};

use super::world::*;
use crate::lsys::{Animation, Who};
use crate::scene::material::{self, Texture};
use crate::scene::mocap::Mocap;
use crate::scene::{obj, Camera, Geometry, Lens, Light, LightKind, Material, Sky};
use crate::source::Source;

/// The brightest uniform sky `D` par1 = 15 may give (a radiance).
pub const MAX_SKY: f32 = 1000.0;

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
    /// (L-system index, motion number, the motion capture) of `fig_bvh`.
    pub motions: Vec<(usize, i64, Mocap)>,
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
                let (tris, mats) = obj::read_obj(&path, base).map_err(|e| match e {
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
            for (n, file) in &ls.def.motions {
                let path = dir.join(&file.name);
                let bytes = crate::source::read_file(&path, obj::MAX_MESH_BYTES)
                    .map_err(|e| file.error(format!("motion {n}: {e}")).to_string())?;
                // Problems inside are located in the BVH file itself.
                let m = Source::from_bytes(path.display().to_string(), bytes)
                    .and_then(|src| Mocap::parse(&src))
                    .map_err(|e| e.to_string())?;
                s.motions.push((ls.index, *n, m));
            }
        }
        Ok(s)
    }
}

/// Scene-wide state built while the words are interpreted.
pub struct Builder {
    pub materials: Vec<Material>,
    pub(super) derived: BTreeMap<(u32, [u32; 3], u8), u32>,
    pub camera: Camera,
    pub(super) light3: Option<Light>,
    pub(super) extra_lights: Vec<Light>,
    pub background: Vec3,
    pub sky: Sky,
    /// Set by `D` par1 = 40, looked at by `l` par3 = 10.
    pub lookat_global: Option<DVec3>,
    pub(super) warned: BTreeSet<String>,
    /// Warnings and `D` par1 = 30 prints, in order, for the user.
    pub messages: Vec<String>,
    /// Bounding boxes of `D` par1 = 20 … 21 (min, max).
    pub bounding_boxes: Vec<(Vec3, Vec3)>,
    pub(super) bbox_start: Vec<(usize, usize)>,
    /// Primitives (shapes, triangles, instances) in the scene so far, and
    /// the most it may hold ([`crate::lsys::Limits::shapes`]).
    pub(super) primitives: usize,
    pub(super) max_primitives: usize,
}

impl Builder {
    pub(super) fn new(
        camera: Camera,
        surface_materials: &[Material],
        max_primitives: usize,
    ) -> Self {
        let mut materials = material::table();
        materials.extend_from_slice(surface_materials);
        Builder {
            materials,
            derived: BTreeMap::new(),
            camera,
            light3: None,
            extra_lights: Vec::new(),
            background: Vec3::new(0.0, 0.0, 0.0),
            sky: Sky::Gradient,
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
    pub(super) fn count(&mut self, n: usize) -> bool {
        self.primitives = self.primitives.saturating_add(n);
        self.primitives <= self.max_primitives
    }

    /// Whether the scene went over its primitive limit.
    pub(super) fn over(&self) -> bool {
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
    pub(super) fn derive(
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

    /// `D` par1 = 15: a sky blue background, or a uniform sky of the
    /// colour par4–par6 when one is given (components clamped to
    /// 0..=[`MAX_SKY`]; a radiance, so it may pass 1).
    pub fn sky(&mut self, colour: DVec3) {
        let c = colour.as_vec3();
        if c.is_finite() && c.max_element() > 0.0 {
            self.background = c.clamp(Vec3::ZERO, Vec3::splat(MAX_SKY));
            self.sky = Sky::Uniform;
        } else {
            self.background = Vec3::new(0.45, 0.62, 0.9);
            self.sky = Sky::Gradient;
        }
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
            14 => {
                let ok = |v: f64| {
                    if v.is_finite() {
                        v.clamp(0.0, 1e6) as f32
                    } else {
                        0.0
                    }
                };
                c.lens = Lens {
                    radius: ok(g.x),
                    focus: ok(g.y),
                };
            }
            _ => {}
        }
    }
}

/// The geometry of surface `gi` placed with the turtle's material `mat`:
/// its faces that name no material take `mat` (thesis: the current
/// material applies to what is drawn). One copy per surface and material
/// and frame; the default material keeps the shared geometry.
pub(super) fn surface_in(
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
