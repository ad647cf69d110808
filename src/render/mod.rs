//! The ray tracer (DESIGN §1 step 4): a two-level 4-wide BVH built by obvhs, with exact
//! shapes, Whitted shading as Rayshade did it, stratified supersampling
//! keyed by (frame, pixel, sample), rows on rayon, EXR and PNG output.
//! The same [`accel::Accel::cast`] serves actor vision.

pub mod accel;
pub mod batch;
pub mod camera;
pub mod denoise;
mod integrator;
pub mod motion;
pub mod output;
pub mod path;
pub mod sample;
pub mod settings;
pub mod shade;
pub mod simd;
pub mod whitted;

use std::sync::atomic::{AtomicU32, Ordering};
use std::sync::Arc;

use rayon::prelude::*;

use crate::aabb::{self, Aabb, MAX_COORDINATE};
use crate::scene::Scene;
pub use accel::{Accel, Hit};
pub use output::{Image, ImageFormat};
pub use settings::{Filter, Integrator, Preset, Settings};

/// Refuses a scene the ray tracer cannot hold (snapshots come from
/// disk): a primitive or an instance whose bounds are not finite or reach
/// beyond ±[`MAX_COORDINATE`]. [`Accel::new`] leaves such ones out
/// rather than fail; this names the first.
pub fn check(scene: &Scene) -> Result<(), String> {
    let beyond = format!("is not finite or reaches beyond ±{MAX_COORDINATE:e}");
    let mut boxes = Vec::with_capacity(scene.geometries.len());
    for (k, g) in scene.geometries.iter().enumerate() {
        let mut b = Aabb::empty();
        for (i, s) in g.shapes.iter().enumerate() {
            let sb = accel::shapes::bounds(s).ok_or_else(|| {
                format!(
                    "geometry {k} ({}): shape {i} (symbol {}) {beyond}",
                    g.name, s.symbol
                )
            })?;
            b.extend(sb.min);
            b.extend(sb.max);
        }
        for (i, t) in g.triangles.iter().enumerate() {
            let sb = accel::shapes::triangle_bounds(&t.v).ok_or_else(|| {
                format!(
                    "geometry {k} ({}): triangle {i} (symbol {}) {beyond}",
                    g.name, t.symbol
                )
            })?;
            b.extend(sb.min);
            b.extend(sb.max);
        }
        boxes.push((!g.is_empty()).then_some(b));
    }
    for (k, i) in scene.instances.iter().enumerate() {
        let Some(b) = boxes.get(i.geometry as usize) else {
            return Err(format!(
                "instance {k} places geometry {}, which the scene does not have",
                i.geometry
            ));
        };
        if b.is_some_and(|b| aabb::transformed(&b, &i.transform).is_none()) {
            return Err(format!(
                "instance {k} (of geometry {}) {beyond}",
                i.geometry
            ));
        }
    }
    Ok(())
}

/// Renders `scene` into an image. Rows are computed independently into
/// fixed slots, so the result does not depend on the thread count.
pub fn render(scene: impl Into<Arc<Scene>>, settings: &Settings) -> Image {
    render_with(&Accel::new(scene), settings, &|_, _| {})
}

/// Renders with an already built acceleration structure; `progress(done,
/// total)` is called as rows finish (from any thread, in any order). Each
/// row is written straight into the image's layers: gathering the rows
/// first held a second copy of the frame (8 MB at 640 × 360).
pub fn render_with(
    accel: &Accel,
    settings: &Settings,
    progress: &(dyn Fn(u32, u32) + Sync),
) -> Image {
    let (w, h) = (settings.width, settings.height);
    let mut img = Image::new(w, h);
    if img.is_empty() {
        return img;
    }
    let cam = camera::CameraRays::new(&accel.scene.camera, w, h);
    let done = AtomicU32::new(0);
    let row = w as usize;
    img.rgba
        .par_chunks_mut(row)
        .zip(img.depth.par_chunks_mut(row))
        .zip(img.normal.par_chunks_mut(row))
        .zip(img.object.par_chunks_mut(row))
        .zip(img.albedo.par_chunks_mut(row))
        .zip(img.variance.par_chunks_mut(row))
        .enumerate()
        // A row per task. Otherwise rayon hands each thread runs of rows
        // it does not split once started (a quarter of the frame with
        // two threads), and rows differ in cost (sky against forest):
        // one thread sat idle at the end. Forest, two threads: 1.65 of
        // 2 cores busy, 1.80 this way.
        .with_max_len(1)
        .for_each(
            |(y, (((((rgba, depth), normal), object), albedo), variance))| {
                let mut integrator = integrator::start(settings.integrator);
                integrator.row(accel, &cam, settings, y as u32, &mut |x, p| {
                    let i = x as usize;
                    (rgba[i], depth[i], normal[i], object[i]) =
                        (p.rgba, p.depth, p.normal, p.object);
                    (albedo[i], variance[i]) = (p.albedo, p.variance);
                });
                progress(done.fetch_add(1, Ordering::Relaxed) + 1, h);
            },
        );
    if settings.denoise {
        denoise::denoise(&mut img);
    }
    img
}
