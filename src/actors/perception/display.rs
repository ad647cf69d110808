//! What people look at (thesis 3.1.5, docs/actors.md): an actor's vision
//! window as an RGB image, and its visual memory as a scene for the ray
//! tracer — each occupied voxel a cube or a small sphere, coloured by
//! height and lit by a headlight, seen from the display's camera (`M`
//! par1 = 14, 15) or else from the actor's own eye.
//!
//! Pure functions of the actor's state: the film layer writes the images
//! (`actors/N/vision.NNNN.png`, `actors/N/memory.NNNN.png`).

use glam::{Affine3A, Vec3};

use super::memory::VisualMemory;
use super::vision::Window;
use crate::actors::live::{DisplayMode, Living};
use crate::render::{self, output, Settings};
use crate::scene::{material, Camera, Geometry, Instance, Light, Scene, Shape, ShapeKind};

/// About how many pixels a side the images are.
pub const IMAGE_SIDE: u32 = 256;

/// Radius of a point of the `Points` display, in voxel edges (a sphere
/// 0.3 voxel edge across).
const POINT_RADIUS: f64 = 0.15;

/// Colour bands of the height colouring, low (blue) to high (yellow).
const BANDS: [[f32; 3]; 6] = [
    [0.15, 0.25, 0.8],
    [0.1, 0.55, 0.75],
    [0.15, 0.65, 0.35],
    [0.55, 0.7, 0.15],
    [0.85, 0.65, 0.1],
    [0.9, 0.85, 0.3],
];

/// The integer scale that brings a window of `edge` pixels to about
/// [`IMAGE_SIDE`] pixels a side (at least 1).
pub fn vision_scale(edge: u32) -> u32 {
    (IMAGE_SIDE / edge.max(1)).max(1)
}

/// The window's shaded colours (the background where nothing is seen),
/// scaled up by [`vision_scale`] without smoothing: a linear image, which
/// [`output::encode_png`] writes as sRGB as it writes the frames.
pub fn vision_image(window: &Window) -> output::Image {
    let edge = window.edge;
    let s = vision_scale(edge);
    let side = edge * s;
    let mut img = output::Image::new(side, side);
    for y in 0..side {
        for x in 0..side {
            let p = &window.pixels[((y / s) * edge + x / s) as usize];
            let i = (y * side + x) as usize;
            img.rgba[i] = [p.shaded.x, p.shaded.y, p.shaded.z, 1.0];
        }
    }
    img
}

/// The eye and look-at point the memory is shown from: the display's
/// when set, else the actor's own.
pub fn display_view(actor: &Living) -> (Vec3, Vec3) {
    (
        actor.display.eye.unwrap_or(actor.eye),
        actor.display.look_at.unwrap_or(actor.look_at),
    )
}

/// The memory's occupied voxels as a scene: one box (`Cubes`) or one
/// sphere 0.3 voxel edge across (`Points`) per voxel, coloured by height
/// in bands, a headlight at the eye, a black background; the camera at
/// `eye` looking at `look_at` with the view angle `fov` (degrees),
/// `side` × `side` pixels. `None` for [`DisplayMode::None`].
pub fn memory_scene(
    memory: &VisualMemory,
    mode: DisplayMode,
    eye: Vec3,
    look_at: Vec3,
    fov: f32,
    side: u32,
) -> Option<Scene> {
    let kind = match mode {
        DisplayMode::None => return None,
        DisplayMode::Cubes => ShapeKind::Box,
        DisplayMode::Points => ShapeKind::Sphere,
    };
    let tree = memory.octree();
    let voxels = tree.occupied_voxels();
    let (lo, hi) = voxels.iter().fold((u32::MAX, 0), |(lo, hi), (v, _)| {
        (lo.min(v[1]), hi.max(v[1]))
    });
    let base = material::table()[0].clone();
    let materials: Vec<material::Material> = BANDS
        .iter()
        .enumerate()
        .map(|(k, c)| material::Material {
            name: format!("memory{k}"),
            ..base.with_diffuse(Vec3::from_array(*c))
        })
        .collect();
    let bands = BANDS.len() as u64;
    let shapes = voxels
        .iter()
        .map(|&(v, _)| {
            let (min, e) = tree.voxel_box(v);
            let band = if hi > lo {
                (u64::from(v[1] - lo) * bands / (u64::from(hi - lo) + 1)) as u32
            } else {
                0
            };
            let transform = match kind {
                // The unit box spans [0,1] × [−½,½]²: its min corner goes
                // to the voxel's.
                ShapeKind::Box => Affine3A::from_scale_rotation_translation(
                    Vec3::splat(e as f32),
                    glam::Quat::IDENTITY,
                    Vec3::new(
                        min[0] as f32,
                        (min[1] + e / 2.0) as f32,
                        (min[2] + e / 2.0) as f32,
                    ),
                ),
                _ => {
                    let c = tree.centre(v);
                    Affine3A::from_scale_rotation_translation(
                        Vec3::splat((POINT_RADIUS * e) as f32),
                        glam::Quat::IDENTITY,
                        Vec3::new(c[0] as f32, c[1] as f32, c[2] as f32),
                    )
                }
            };
            Shape {
                kind,
                transform,
                material: band,
                symbol: 0,
            }
        })
        .collect();
    let geometry = Geometry {
        name: "memory".into(),
        shapes,
        triangles: Vec::new(),
        resolution: 8,
    };
    Some(Scene {
        frame: 0,
        time: 0.0,
        camera: Camera {
            eye,
            look_at,
            twist: 0.0,
            fov_y: fov.clamp(1.0, 170.0),
            aspect: 1.0,
            near: 0.01,
            far: 1e6,
            width: side,
            height: side,
            lens: Default::default(),
        },
        lights: vec![Light::point(eye, Vec3::ONE)],
        materials,
        geometries: vec![geometry],
        instances: vec![Instance {
            geometry: 0,
            transform: Affine3A::IDENTITY,
            object: 0,
        }],
        background: Vec3::ZERO,
        sky: Default::default(),
    })
}

/// The actor's memory drawn at `frame`, [`IMAGE_SIDE`] pixels a side,
/// when its display is on at that frame and it has a memory.
pub fn memory_image(actor: &Living, frame: u64) -> Option<output::Image> {
    if !actor.display.at(frame) {
        return None;
    }
    let memory = actor.memory.as_ref()?;
    let (eye, look_at) = display_view(actor);
    let scene = memory_scene(
        memory,
        actor.display.mode,
        eye,
        look_at,
        actor.fov as f32 / 10.0,
        IMAGE_SIDE,
    )?;
    let settings = Settings {
        spp: 2,
        layers: false,
        frame,
        ..Settings::preview(IMAGE_SIDE, IMAGE_SIDE)
    };
    Some(render::render(scene, &settings))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::actors::perception::octree::Cube;

    #[test]
    fn scale_brings_windows_near_256() {
        assert_eq!(vision_scale(32), 8);
        assert_eq!(vision_scale(64), 4);
        assert_eq!(vision_scale(100), 2);
        assert_eq!(vision_scale(1024), 1);
        assert_eq!(vision_scale(0), 256);
    }

    #[test]
    fn memory_scene_has_a_shape_per_voxel() {
        let mut m = VisualMemory::with_thesis_rule(Cube::new(-10.0, 10.0, 1.0));
        m.insert([0.5, 0.5, 0.5], 0);
        m.insert([3.5, 2.5, 0.5], 0);
        let s = memory_scene(
            &m,
            DisplayMode::Cubes,
            Vec3::new(0.0, 0.0, -10.0),
            Vec3::ZERO,
            45.0,
            64,
        )
        .unwrap();
        assert_eq!(s.geometries[0].shapes.len(), 2);
        assert!(render::check(&s).is_ok());
        let img = render::render(s, &Settings::preview(64, 64));
        assert!(img.rgba.iter().any(|p| p[0] + p[1] + p[2] > 0.0));
        assert!(memory_scene(&m, DisplayMode::None, Vec3::ZERO, Vec3::Z, 45.0, 8).is_none());
    }
}
