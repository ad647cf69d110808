//! The path tracer against what is known exactly: the white furnace,
//! the Whitted look's direct light, the thin lens's circle of
//! confusion, and the same bits for any thread count and SIMD path.

use std::sync::Arc;

use glam::{Affine3A, Vec3};

use super::*;
use crate::render::accel::tri4::Simd;
use crate::render::motion::Motion;
use crate::render::{render_with, Image, Integrator, Settings};
use crate::scene::{
    material, Camera, Geometry, Instance, Lens, Light, LightKind, Material, Scene, Shape,
    ShapeKind, Sky,
};

/// The gallery's scene: shapes, textures, mirror and glass.
fn gallery() -> Scene {
    use crate::lsys::{Animation, NoSensors};
    use crate::turtle::{build_scene, NoWorld, Options, Surfaces};
    let root = env!("CARGO_MANIFEST_DIR");
    let file = format!("{root}/scenes/examples/gallery.lm");
    let mut anim = Animation::load(&[file], &mut NoSensors).unwrap();
    let surfaces = Surfaces::load(&anim).unwrap();
    build_scene(
        &mut anim,
        &surfaces,
        &mut Vec::new(),
        &mut NoWorld,
        Options::default(),
    )
    .unwrap()
    .0
}

/// A grey diffuse material without highlight of albedo `rho`.
fn diffuse(rho: f32) -> Material {
    Material {
        diffuse: Vec3::splat(rho),
        specular: Vec3::ZERO,
        ..material::table()[0].clone()
    }
}

fn camera(eye: Vec3, look_at: Vec3, fov_y: f32, side: u32) -> Camera {
    Camera {
        eye,
        look_at,
        twist: 0.0,
        fov_y,
        aspect: 1.0,
        near: 0.1,
        far: 1e4,
        width: side,
        height: side,
        lens: Lens::default(),
    }
}

/// Spheres (centre, radius, material) and triangles in one geometry.
fn scene(camera: Camera, spheres: &[(Vec3, f32, u32)], materials: Vec<Material>) -> Scene {
    let shapes = spheres
        .iter()
        .map(|&(c, r, material)| Shape {
            kind: ShapeKind::Sphere,
            transform: Affine3A::from_scale_rotation_translation(
                Vec3::splat(r),
                glam::Quat::IDENTITY,
                c,
            ),
            material,
            symbol: 1,
        })
        .collect();
    Scene {
        frame: 0,
        time: 0.0,
        camera,
        lights: Vec::new(),
        materials,
        geometries: vec![Geometry {
            name: "test".into(),
            shapes,
            triangles: Vec::new(),
            resolution: 8,
        }],
        instances: vec![Instance {
            geometry: 0,
            transform: Affine3A::IDENTITY,
            object: 0,
        }],
        background: Vec3::ZERO,
        sky: Sky::Gradient,
    }
}

fn path(side: u32, spp: u32, max_depth: u32) -> Settings {
    Settings {
        spp,
        max_depth,
        integrator: Integrator::Path,
        layers: false,
        ..Settings::final_quality(side, side)
    }
}

/// The mean of the red channel over the pixels within `r` pixels of the
/// image centre.
fn disc_mean(img: &Image, r: f32) -> f32 {
    let (w, h) = (img.width, img.height);
    let (mut sum, mut n) = (0.0, 0);
    for y in 0..h {
        for x in 0..w {
            let (dx, dy) = (
                x as f32 + 0.5 - w as f32 / 2.0,
                y as f32 + 0.5 - h as f32 / 2.0,
            );
            if dx * dx + dy * dy < r * r {
                sum += img.rgba[(y * w + x) as usize][0];
                n += 1;
            }
        }
    }
    sum / n as f32
}

/// The white furnace: a diffuse sphere of albedo ρ inside a uniform sky
/// of radiance L shows ρ·L (every path escapes after its first bounce
/// off a convex shape, at any depth); the background shows L.
#[test]
fn white_furnace() {
    for (rho, sky, depth) in [(0.8, 1.0, 0), (0.8, 1.0, 5), (0.5, 2.0, 2), (1.0, 0.7, 3)] {
        let mut s = scene(
            camera(Vec3::new(0.0, 0.0, 4.0), Vec3::ZERO, 40.0, 48),
            &[(Vec3::ZERO, 1.0, 0)],
            vec![diffuse(rho)],
        );
        (s.background, s.sky) = (Vec3::splat(sky), Sky::Uniform);
        let img = crate::render::render(s, &path(48, 256, depth));
        let disc = disc_mean(&img, 8.0);
        assert!(
            (disc / (rho * sky) - 1.0).abs() < 0.01,
            "ρ {rho}, L {sky}, depth {depth}: the sphere shows {disc}, not {}",
            rho * sky
        );
        assert!(
            (img.rgba[0][0] - sky).abs() < 1e-5,
            "the background is the sky"
        );
    }
}

/// With no sky, the direct light of a thesis light on a diffuse plane
/// is what the Whitted look shows (irradiance π·c, no falloff), and the
/// ambient environment adds Rayshade's ambient 0.2·ρ: the two looks
/// agree on a plane lit by a directional and a point light.
#[test]
fn direct_light_matches_the_whitted_look() {
    let rho = 0.6;
    let mut m = diffuse(rho);
    m.ambient = Vec3::splat(AMBIENT * rho);
    let mut s = scene(
        camera(Vec3::new(0.0, 5.0, 0.01), Vec3::ZERO, 20.0, 16),
        &[],
        vec![m],
    );
    s.geometries[0].triangles = vec![
        crate::scene::Triangle {
            v: [
                Vec3::new(-50.0, 0.0, -50.0),
                Vec3::new(-50.0, 0.0, 50.0),
                Vec3::new(50.0, 0.0, 50.0),
            ],
            material: 0,
            symbol: 2,
        },
        crate::scene::Triangle {
            v: [
                Vec3::new(-50.0, 0.0, -50.0),
                Vec3::new(50.0, 0.0, 50.0),
                Vec3::new(50.0, 0.0, -50.0),
            ],
            material: 0,
            symbol: 2,
        },
    ];
    s.lights = vec![
        Light {
            position: Vec3::ZERO,
            color: Vec3::new(0.5, 0.4, 0.3),
            kind: LightKind::Directional {
                direction: Vec3::new(0.3, -1.0, 0.2),
            },
        },
        Light::point(Vec3::new(3.0, 40.0, -2.0), Vec3::splat(0.3)),
    ];
    let s = Arc::new(s);
    let whitted = crate::render::render(s.clone(), &Settings::final_quality(16, 16));
    let traced = crate::render::render(s, &path(16, 512, 0));
    for (a, b) in whitted.rgba.iter().zip(&traced.rgba) {
        for c in 0..3 {
            assert!(
                (a[c] / b[c] - 1.0).abs() < 0.01,
                "Whitted {a:?}, path {b:?}"
            );
        }
    }
}

/// A point of a tiny sphere at distance z, seen through a lens of
/// radius R focused at f, is spread over a circle of diameter
/// 2R·|z − f|/z on the plane in focus (the thin-lens formula); one at
/// the focus distance stays as sharp as through the pinhole.
#[test]
fn depth_of_field_follows_the_thin_lens() {
    let (side, fov) = (64u32, 20.0f32);
    let tan = (fov.to_radians() / 2.0).tan();
    let spread = |z: f32, lens: Lens| {
        let mut c = camera(Vec3::ZERO, Vec3::new(0.0, 0.0, -1.0), fov, side);
        c.lens = lens;
        let s = scene(
            c,
            &[(Vec3::new(0.0, 0.0, -z), 0.002 * z, 0)],
            vec![diffuse(0.5)],
        );
        let img = crate::render::render(s, &path(side, 256, 0));
        // The spot's radius from its alpha-weighted second moment: a
        // uniform disc of radius r has a variance r²/4 along x.
        let (mut m, mut mx, mut mxx) = (0.0f64, 0.0f64, 0.0f64);
        for (i, p) in img.rgba.iter().enumerate() {
            let x = (i as u32 % side) as f64 + 0.5;
            let a = f64::from(p[3]);
            (m, mx, mxx) = (m + a, mx + a * x, mxx + a * x * x);
        }
        let var = mxx / m - (mx / m).powi(2);
        2.0 * var.sqrt() as f32
    };
    let (radius, focus) = (0.5, 10.0);
    let lens = Lens { radius, focus };
    let pixel = 2.0 * tan / side as f32;
    for z in [5.0f32, 20.0, 40.0] {
        let coc = 2.0 * radius * (z - focus).abs() / z;
        let expected = coc / focus / pixel / 2.0;
        let r = spread(z, lens);
        assert!(
            (r / expected - 1.0).abs() < 0.05,
            "z {z}: spot radius {r} px, thin lens {expected} px"
        );
    }
    let sharp = spread(focus, lens);
    let pinhole = spread(focus, Lens::default());
    assert!(
        (sharp - pinhole).abs() < 0.1,
        "in focus {sharp} px, pinhole {pinhole} px"
    );
}

/// The same bits for 1 and 2 threads and every SIMD path the machine
/// has, on the gallery (mirror, glass, textures, a sky) with a lens.
#[test]
fn same_bits_for_any_thread_count_and_simd_path() {
    let mut scene = gallery();
    scene.camera.lens = Lens {
        radius: 0.2,
        focus: 0.0,
    };
    scene.background = Vec3::new(0.45, 0.62, 0.9);
    let scene = Arc::new(scene);
    let st = Settings {
        layers: true,
        ..path(40, 24, 4)
    };
    let mut images = Vec::new();
    for simd in Simd::available() {
        let accel = crate::render::Accel::new(scene.clone()).with_simd(simd);
        for threads in [1, 2] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            let img = pool.install(|| render_with(&accel, &st, &|_, _| {}));
            images.push((simd, threads, img));
        }
    }
    let bits = |img: &Image| {
        img.rgba
            .iter()
            .flat_map(|p| p.map(f32::to_bits))
            .collect::<Vec<_>>()
    };
    let first = bits(&images[0].2);
    assert!(
        images[0].2.rgba.iter().any(|p| p[0] > 0.05),
        "the gallery is lit"
    );
    for (simd, threads, img) in &images[1..] {
        assert!(bits(img) == first, "{simd:?}, {threads} threads");
    }
}

/// The white furnace in general: where every surface is a white
/// diffuse inside a uniform sky of radiance L, light bounces between
/// them unabsorbed and every pixel shows L (paths end only by Russian
/// roulette, unbiased) — on the gallery, whose shapes face each other,
/// bumped and marbled.
#[test]
fn white_furnace_of_a_whole_scene() {
    let mut scene = gallery();
    for m in &mut scene.materials {
        *m = Material {
            texture: m
                .texture
                .filter(|t| *t != crate::scene::material::Texture::Cloud),
            ..diffuse(1.0)
        };
    }
    scene.lights.clear();
    (scene.background, scene.sky) = (Vec3::splat(0.5), Sky::Uniform);
    let img = crate::render::render(scene, &path(24, 256, 64));
    let mean = img.rgba.iter().map(|p| p[0]).sum::<f32>() / img.rgba.len() as f32;
    assert!((mean / 0.5 - 1.0).abs() < 0.01, "mean {mean}, not 0.5");
}

/// Motion blur: a sphere that moves D between a frame and the next,
/// seen with the shutter open a fraction s of the interval, is smeared
/// over s·D (its silhouette convolved with a box of that length, so the
/// alpha's variance along the motion grows by (s·D)²/12) — whether the
/// shape moves within its geometry or its instance moves.
#[test]
fn motion_blur_spreads_a_point_over_its_screen_motion() {
    let (side, fov) = (64u32, 20.0f32);
    let pixel = 2.0 * (fov.to_radians() / 2.0).tan() * 10.0 / side as f32;
    let at = |x: f32| {
        scene(
            camera(Vec3::ZERO, Vec3::new(0.0, 0.0, -1.0), fov, side),
            &[(Vec3::new(x, 0.0, -10.0), 0.3, 0)],
            vec![diffuse(0.5)],
        )
    };
    let by_instance = |x: f32| {
        let mut s = at(0.0);
        s.instances[0].transform = Affine3A::from_translation(Vec3::new(x, 0.0, 0.0));
        s
    };
    // Mean and variance of x under the alpha.
    let moments = |accel: &crate::render::Accel| {
        let img = render_with(accel, &path(side, 256, 0), &|_, _| {});
        let (mut m, mut mx, mut mxx) = (0.0f64, 0.0f64, 0.0f64);
        for (i, p) in img.rgba.iter().enumerate() {
            let x = (i as u32 % side) as f64 + 0.5;
            let a = f64::from(p[3]);
            (m, mx, mxx) = (m + a, mx + a * x, mxx + a * x * x);
        }
        (mx / m, mxx / m - (mx / m).powi(2))
    };
    for (moved, shutter) in [(2.0f32, 0.5f32), (1.0, 1.0), (3.0, 0.25)] {
        for make in [&at as &dyn Fn(f32) -> Scene, &by_instance] {
            let (now, next) = (make(-1.0), make(-1.0 + moved));
            let motion = Motion::between(&now, &next, shutter);
            assert!(!motion.is_still());
            let still = moments(&crate::render::Accel::new(now.clone()));
            let blurred = moments(&crate::render::Accel::moving(now, &motion));
            let length = (12.0 * (blurred.1 - still.1)).sqrt() as f32;
            let expected = shutter * moved / pixel;
            assert!(
                (length / expected - 1.0).abs() < 0.03,
                "moved {moved} m, shutter {shutter}: blur {length} px, screen motion {expected} px"
            );
            let shift = (blurred.0 - still.0) as f32;
            assert!(
                (shift - expected / 2.0).abs() < 0.2,
                "centre moved {shift} px"
            );
        }
    }
}

/// The path tracer's samples are the same every frame: a scene that does
/// not change renders the same bits at frames 3 and 8 (its noise does not
/// flicker), where the Whitted look's jitter is the frame's own.
#[test]
fn a_still_scene_renders_the_same_noise_every_frame() {
    let at = |frame: u64, integrator: Integrator| {
        let st = Settings {
            frame,
            integrator,
            ..path(24, 4, 3)
        };
        crate::render::render(gallery(), &st).rgba
    };
    assert_eq!(at(3, Integrator::Path), at(8, Integrator::Path));
    assert_ne!(at(3, Integrator::Whitted), at(8, Integrator::Whitted));
}
