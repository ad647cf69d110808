//! The world of one frame (DESIGN §1 step 1): primitives grouped in shared
//! geometries, instances placing them, materials, camera and lights.
//!
//! Plain data, built by the turtle, read by the renderer and by actor
//! vision, and shipped between machines as a snapshot.

pub mod body;
pub mod camera;
pub mod gait;
pub mod material;
pub mod mesh;
pub mod mocap;
pub mod motor;
pub mod mtl;
pub mod obj;
pub mod obj_parse;
pub mod rig;
pub mod shape;
pub mod snapshot;

use glam::{Affine3A, Vec3};
use serde::{Deserialize, Serialize};

pub use camera::{Camera, Lens, Light, LightKind};
pub use material::Material;
pub use shape::{Shape, ShapeKind, Triangle};

/// See [`crate::aabb::MAX_COORDINATE`].
pub use crate::aabb::MAX_COORDINATE;

/// Largest magnitude of any number in a scene or snapshot (coordinates
/// of placed primitives are held to [`MAX_COORDINATE`] besides): the
/// BVH's surface areas and products of coordinates stay finite in `f32`
/// (a vertex at 1e24 among unit-sized shapes made the BVH builder panic).
pub const MAX_MAGNITUDE: f32 = 1e18;

/// Shapes drawn in one coordinate frame; placed in the world by instances.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct Geometry {
    pub name: String,
    /// Analytic shapes, each a unit shape under an affine transform.
    pub shapes: Vec<Shape>,
    /// Polygons, pyramids, planes and imported meshes.
    pub triangles: Vec<Triangle>,
    /// Tessellation resolution (`n`, minimum 3) of the shapes, for exports.
    pub resolution: u32,
}

impl Geometry {
    pub fn is_empty(&self) -> bool {
        self.shapes.is_empty() && self.triangles.is_empty()
    }
}

/// One placement of a geometry.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Instance {
    pub geometry: u32,
    pub transform: Affine3A,
    /// Object id of the instance (for id layers and vision).
    pub object: u32,
}

/// Everything the renderer needs for one frame.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Scene {
    pub frame: u64,
    /// Global time T of the frame.
    pub time: f64,
    pub camera: Camera,
    pub lights: Vec<Light>,
    pub materials: Vec<Material>,
    pub geometries: Vec<Geometry>,
    pub instances: Vec<Instance>,
    /// Sky colour seen where no object is hit (`D` par1 = 15 sets a sky).
    pub background: Vec3,
    /// How the sky spreads its colour over the directions.
    pub sky: Sky,
}

/// The sky's shape: `D` par1 = 15 alone gives the gradient with clouds,
/// with a colour (par4–par6) a uniform sky of that radiance (a studio
/// environment, the path tracer's white furnace).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub enum Sky {
    /// From the zenith colour to a lighter horizon, with clouds.
    #[default]
    Gradient,
    /// The same radiance every way.
    Uniform,
}

impl Scene {
    /// Number of analytic shapes and triangles once instances are expanded.
    pub fn expanded_counts(&self) -> (usize, usize) {
        self.instances.iter().fold((0, 0), |(s, t), i| {
            let g = &self.geometries[i.geometry as usize];
            (s + g.shapes.len(), t + g.triangles.len())
        })
    }
}
