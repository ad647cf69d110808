//! Interpretation of the derived words into the [`Scene`] of a frame
//! (DESIGN §1 step 1; thesis 2.1.5–2.3.2, appendix C).
//!
//! Each L-system's word is drawn once in its own frame into a shared
//! geometry; its repetitions (table B1) and imported surfaces are
//! instances of it, so a forest costs one tree plus transforms.

pub mod builder;
pub mod interpret;
pub mod polygon;
pub mod repetition;
pub mod special;
pub mod state;
pub mod world;

use std::collections::BTreeMap;

use glam::{DVec3, Vec3};

use crate::lsys::Animation;
use crate::scene::{Camera, Geometry, Instance, Lens, Light, Scene};
use builder::surface_in;
pub use builder::{Builder, Surfaces};
pub use interpret::{interpret, Options, Placed, Structure, Tables};
pub use state::Turtle;
pub use world::{
    ActorMapping, ActorPose, BodyPart, NoWorld, ParticleMapping, SoundCue, TurtleWorld,
};

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
        lens: Lens {
            radius: cam.aperture as f32,
            focus: cam.focus_distance as f32,
        },
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
        let st = interpret(
            ls,
            time,
            seed,
            &mut b,
            &mut tables[k],
            world,
            &surfaces.motions,
            opts,
        );
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
        sky: b.sky,
    };
    Ok((scene, b.messages))
}
