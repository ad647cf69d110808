//! The Whitted integrator (`--integrator whitted`): Rayshade's shading
//! ([`shade`]) of each sample's first surface, its shadow rays cast
//! together light by light, and where the scene allows ([`batch::applies`])
//! a row's samples cast and shaded sixteen lanes at a time.

use glam::Vec3;

use super::accel::{Accel, Hit, Query};
use super::camera::CameraRays;
use super::sample::{filtered, Centre, Integrate, PixelOut, Samples};
use super::settings::Settings;
use super::{batch, shade};
use crate::random::{self, Stream};

/// The Whitted integrator's buffers for a row: its samples' camera
/// rays, shadow rays and the lanes of [`batch::row`], kept from pixel to
/// pixel so that a pixel allocates nothing.
#[derive(Default)]
pub struct Whitted {
    samples: Samples,
    shading: Shading,
}

/// A pixel's rays one at a time, and a row's lanes.
#[derive(Default)]
struct Shading {
    queries: Vec<Query>,
    hits: Vec<Option<Hit>>,
    /// Where each sample's ray meets a surface with a material.
    points: Vec<Option<shade::Point>>,
    /// The hard shadow rays, as (light, ray), sample after sample.
    rays: Vec<(usize, Query)>,
    /// Where each sample's rays start, and where the last ends.
    starts: Vec<usize>,
    /// The rays in the order cast (light after light), and their answers.
    bundle: Vec<Query>,
    order: Vec<usize>,
    answers: Vec<bool>,
    /// Whether each ray is blocked, as (light, blocked), in `rays`' order.
    seen: Vec<(usize, bool)>,
    /// A row's rays for [`batch::row`], and their (colour, hit).
    row: Vec<batch::Lane>,
    lit: Vec<(Vec3, Option<Hit>)>,
    /// The lanes of [`batch::row`].
    lanes: batch::Buffers,
}

impl Shading {
    /// Finds the samples' [`shade::Point`]s and casts their hard shadow
    /// rays into `seen`: together, light by light, so that a bundle holds
    /// the rays of one light from neighbouring points.
    fn shadows(&mut self, accel: &Accel, st: &Settings) {
        self.points.clear();
        self.points.extend(
            self.queries
                .iter()
                .zip(&self.hits)
                .map(|(q, hit)| shade::point(accel, hit.as_ref()?, q.origin, q.dir)),
        );
        self.rays.clear();
        self.starts.clear();
        for pt in &self.points {
            self.starts.push(self.rays.len());
            if let Some(pt) = pt {
                shade::shadow_rays(accel, pt, st, &mut self.rays);
            }
        }
        self.starts.push(self.rays.len());
        self.order.clear();
        self.order.extend(0..self.rays.len());
        if accel.scene.lights.len() > 1 {
            let rays = &self.rays;
            self.order.sort_by_key(|&i| rays[i].0);
        }
        self.bundle.clear();
        self.bundle
            .extend(self.order.iter().map(|&i| self.rays[i].1));
        accel.occluded_all(&self.bundle, &mut self.answers);
        self.seen.clear();
        self.seen.extend(self.rays.iter().map(|r| (r.0, false)));
        for (&i, &b) in self.order.iter().zip(&self.answers) {
            self.seen[i].1 = b;
        }
    }

    /// Casts pixel (x, y)'s samples' camera rays together (a pixel's rays
    /// are the most coherent there are).
    fn cast(
        &mut self,
        accel: &Accel,
        cam: &CameraRays,
        (x, y): (u32, u32),
        offsets: &[(f32, f32)],
    ) {
        self.queries.clear();
        self.queries.extend(offsets.iter().map(|&(ox, oy)| Query {
            origin: cam.eye(),
            dir: cam.dir(x as f32 + ox, y as f32 + oy),
            tmin: 0.0,
            tmax: f32::INFINITY,
        }));
        accel.cast_all(&self.queries, &mut self.hits);
    }

    /// The samples' colours one at a time (scenes with sphere lights:
    /// see [`batch::applies`]; the same bits as [`batch::row`]'s), after
    /// their shadow rays together.
    fn colours_one_by_one(
        &mut self,
        accel: &Accel,
        st: &Settings,
        key: u64,
        colours: &mut Vec<(Vec3, bool)>,
    ) {
        self.shadows(accel, st);
        colours.clear();
        for (s, (q, hit)) in self.queries.iter().zip(&self.hits).enumerate() {
            let colour = match (hit, &self.points[s]) {
                (Some(_), Some(pt)) => shade::shade_seen(
                    accel,
                    pt,
                    q.dir,
                    st,
                    0,
                    random::key(key, Stream::Pixel, s as u64, 1),
                    &self.seen[self.starts[s]..self.starts[s + 1]],
                ),
                // A surface without a material is black (as `shade_hit`).
                (Some(_), None) => Vec3::ZERO,
                (None, _) => shade::background(accel, q.dir),
            };
            colours.push((colour, hit.is_some()));
        }
    }
}

impl Shading {
    /// Pixel (x, y)'s samples' colours, one ray at a time after
    /// another.
    fn pixel(
        &mut self,
        samples: &mut Samples,
        accel: &Accel,
        cam: &CameraRays,
        st: &Settings,
        at: (u32, u32),
    ) -> PixelOut {
        samples.pixel(accel, cam, st, at, |key, s| {
            self.cast(accel, cam, at, &s.offsets);
            self.colours_one_by_one(accel, st, key, &mut s.colours);
        })
    }
}

impl Integrate for Whitted {
    /// Where the samples are cast and shaded together ([`batch::applies`]),
    /// the row's rays go through [`batch::row`] a run of pixels at a time;
    /// otherwise pixel by pixel.
    fn row(
        &mut self,
        accel: &Accel,
        cam: &CameraRays,
        st: &Settings,
        y: u32,
        put: &mut dyn FnMut(u32, PixelOut),
    ) {
        let Whitted {
            samples,
            shading: sc,
        } = self;
        if !batch::applies(accel) {
            for x in 0..st.width {
                put(x, sc.pixel(samples, accel, cam, st, (x, y)));
            }
            return;
        }
        let n = st.spp.max(1) as usize;
        // A pixel's one sample is its centre ray (`offsets`).
        let centre_lane = st.layers && n > 1;
        let per = n + usize::from(centre_lane);
        // Runs of pixels of about [`RUN_LANES`] rays: a whole row's at many
        // samples would hold width × spp lanes (60 MB a thread at 1920 wide
        // and 1024 samples).
        let run = (RUN_LANES / per).max(1) as u32;
        for first in (0..st.width).step_by(run as usize) {
            sc.row.clear();
            for x in first..(first + run).min(st.width) {
                let key = samples.at(st, x, y);
                let lanes = samples.offsets.iter().enumerate();
                sc.row.extend(lanes.map(|(s, &offset)| batch::Lane {
                    x,
                    offset,
                    key,
                    sample: Some(s as u32),
                }));
                if centre_lane {
                    sc.row.push(batch::Lane {
                        x,
                        offset: (0.5, 0.5),
                        key,
                        sample: None,
                    });
                }
            }
            batch::row(accel, cam, st, y, &sc.row, &mut sc.lanes, &mut sc.lit);
            for ((lanes, lit), x) in sc.row.chunks(per).zip(sc.lit.chunks(per)).zip(first..) {
                let samples = lanes[..n]
                    .iter()
                    .zip(&lit[..n])
                    .map(|(lane, &(c, hit))| (lane.offset, c, hit.is_some()));
                let centre = match lit[per - 1].1 {
                    Some(hit) if st.layers => Some(Centre::of(accel, cam, st, hit, (x, y))),
                    _ => None,
                };
                put(x, filtered(st, samples, centre));
            }
        }
    }
}

/// About how many rays [`Whitted::row`] casts and shades in one call of
/// [`batch::row`] (a multiple of the 16 lanes).
const RUN_LANES: usize = 256;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lsys::{Animation, NoSensors};
    use crate::render::accel::tri4::Simd;
    use crate::scene::{Light, LightKind};
    use crate::turtle::{build_scene, NoWorld, Options, Surfaces};

    /// A row's samples cast and shaded together, several pixels to a
    /// packet ([`row`]), get the bits of each pixel's cast and shaded one
    /// at a time, on every SIMD path (so the camera rays in lanes are the
    /// same rays), and the centre rays' lanes the single cast's layers:
    /// the gallery's shapes, textures, mirror and glass, with a sun and a
    /// second, coloured point light added, shadows on and off, the final
    /// and the preview presets, with and without layers, 1, 3 and 20
    /// samples a pixel (a pixel in two chunks of lanes, or across two).
    #[test]
    fn batch_shading_gives_the_one_at_a_time_bits() {
        let root = env!("CARGO_MANIFEST_DIR");
        let file = format!("{root}/scenes/examples/gallery.lm");
        let mut anim = Animation::load(&[file], &mut NoSensors).unwrap();
        let surfaces = Surfaces::load(&anim).unwrap();
        let (mut scene, _) = build_scene(
            &mut anim,
            &surfaces,
            &mut Vec::new(),
            &mut NoWorld,
            Options::default(),
        )
        .unwrap();
        scene.lights.push(Light {
            position: Vec3::ZERO,
            color: Vec3::new(0.3, 0.25, 0.2),
            kind: LightKind::Directional {
                direction: Vec3::new(-0.4, -1.0, -0.3),
            },
        });
        scene.lights.push(Light::point(
            Vec3::new(-6.0, 5.0, 4.0),
            Vec3::new(0.5, 0.6, 0.7),
        ));
        let (w, h) = (40, 24);
        let cam = CameraRays::new(&scene.camera, w, h);
        let scene = std::sync::Arc::new(scene);
        let (mut lit, mut textured, mut covered) = (0, 0, 0);
        let bits = |p: &PixelOut| {
            let f = |v: &[f32]| v.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
            (f(&p.rgba), f(&[p.depth]), f(&p.normal), p.object)
        };
        for simd in Simd::available() {
            let accel = Accel::new(scene.clone()).with_simd(simd);
            assert!(batch::applies(&accel));
            for (shadows, layers, spp, mut st) in [
                (true, true, 20, Settings::final_quality(w, h)),
                (false, false, 3, Settings::final_quality(w, h)),
                (true, true, 3, Settings::preview(w, h)),
                (true, true, 1, Settings::final_quality(w, h)),
                (true, false, 1, Settings::final_quality(w, h)),
            ] {
                (st.shadows, st.layers, st.spp) = (shadows, layers, spp);
                let mut whitted = Whitted::default();
                for y in 0..h {
                    let mut together = Vec::new();
                    whitted.row(&accel, &cam, &st, y, &mut |x, p| together.push((x, p)));
                    assert_eq!(together.len(), w as usize);
                    let Whitted {
                        samples,
                        shading: sc,
                    } = &mut whitted;
                    for (x, p) in together {
                        let alone = sc.pixel(samples, &accel, &cam, &st, (x, y));
                        assert_eq!(bits(&p), bits(&alone), "{simd:?} ({x}, {y})");
                        covered += usize::from(alone.object != u32::MAX);
                        lit += sc.seen.iter().filter(|s| !s.1).count();
                        textured += sc
                            .points
                            .iter()
                            .flatten()
                            .filter(|p| scene.materials[p.material].texture.is_some())
                            .count();
                    }
                }
            }
        }
        assert!(
            lit > 10_000 && textured > 1000 && covered > 1000,
            "{lit} lit, {textured} textured, {covered} centres on a surface"
        );
    }
}
