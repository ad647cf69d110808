//! The vision window (thesis 3.1.1, 3.1.2): `?30`, `?31`, colour coding
//! both ways, the thing of interest's area and position, determinism.

use std::f32::consts::PI;

use glam::{Affine3A, Vec3};
use lmfilm::actors::perception::vision::{self, Body, Interest, OwnBody, View, Window, NOTHING};
use lmfilm::render::Accel;
use lmfilm::scene::material::{self, Material};
use lmfilm::scene::{Camera, Geometry, Instance, Light, Scene, Shape, ShapeKind};

/// A scene of these shapes (each its own object), under a white point
/// light at `light`, with the material table plus `extra` materials.
pub fn scene(shapes: &[(ShapeKind, Affine3A, u32)], extra: &[Material], light: Vec3) -> Scene {
    let mut materials = material::table();
    materials.extend_from_slice(extra);
    let geometries: Vec<Geometry> = shapes
        .iter()
        .enumerate()
        .map(|(i, &(kind, transform, material))| Geometry {
            name: format!("g{i}"),
            shapes: vec![Shape {
                kind,
                transform,
                material,
                symbol: i as u64,
            }],
            triangles: Vec::new(),
            resolution: 8,
        })
        .collect();
    let instances = (0..shapes.len() as u32)
        .map(|i| Instance {
            geometry: i,
            transform: Affine3A::IDENTITY,
            object: i,
        })
        .collect();
    Scene {
        frame: 0,
        time: 0.0,
        camera: Camera {
            eye: Vec3::new(0.0, 0.0, 10.0),
            look_at: Vec3::ZERO,
            twist: 0.0,
            fov_y: 30.0,
            aspect: 1.0,
            near: 0.01,
            far: 1000.0,
            width: 64,
            height: 64,
            lens: Default::default(),
        },
        lights: vec![Light::point(light, Vec3::ONE)],
        materials,
        geometries,
        instances,
        background: Vec3::ZERO,
        sky: Default::default(),
    }
}

/// The unit box [0,1]×[−½,½]² made the axis-aligned box min..max.
pub fn cuboid(min: Vec3, max: Vec3) -> Affine3A {
    let size = max - min;
    Affine3A::from_translation(Vec3::new(
        min.x,
        (min.y + max.y) / 2.0,
        (min.z + max.z) / 2.0,
    )) * Affine3A::from_scale(size)
}

fn ball(centre: Vec3, r: f32) -> Affine3A {
    Affine3A::from_translation(centre) * Affine3A::from_scale(Vec3::splat(r))
}

fn see(s: Scene, view: &View, edge: u32) -> Window {
    vision::see(&Accel::new(s), &OwnBody::default(), view, edge)
}

#[test]
fn centre_distance_of_a_box_face() {
    // The face z = 3 of a box, seen from (0, 0, 10): 7 away.
    let s = scene(
        &[(
            ShapeKind::Box,
            cuboid(Vec3::new(-2.0, -2.0, 2.0), Vec3::new(2.0, 2.0, 3.0)),
            1,
        )],
        &[],
        Vec3::new(0.0, 5.0, 10.0),
    );
    let accel = Accel::new(s);
    for edge in [33, 64] {
        let v = View::new(Vec3::new(0.0, 0.0, 10.0), Vec3::ZERO, 450, 0.1, 100.0);
        let w = vision::see(&accel, &OwnBody::default(), &v, edge);
        assert!(
            (w.centre_distance() - 7.0).abs() < 1e-4,
            "{edge}: {}",
            w.centre_distance()
        );
        // A pixel's position, depth and distance agree.
        let p = w.pixel(edge / 3, edge / 2);
        assert!((p.position.z - 3.0).abs() < 1e-4, "{:?}", p);
        assert!((p.depth - 7.0).abs() < 1e-4, "{:?}", p);
        assert!(p.distance >= p.depth);
        // Looking away, or with the far plane before the face: nothing.
        let away = View::new(
            Vec3::new(0.0, 0.0, 10.0),
            Vec3::new(0.0, 0.0, 20.0),
            450,
            0.1,
            100.0,
        );
        assert_eq!(
            vision::see(&accel, &OwnBody::default(), &away, edge).centre_distance(),
            NOTHING
        );
        let short = View { far: 6.9, ..v };
        let w = vision::see(&accel, &OwnBody::default(), &short, edge);
        assert_eq!(w.centre_distance(), NOTHING);
        assert!(w.pixels.iter().all(|p| !p.hit()));
        // The near plane clips by depth: past the front face, the eye
        // sees the back face from inside, 8 away.
        let near = View { near: 7.5, ..v };
        let inside = vision::see(&accel, &OwnBody::default(), &near, edge).centre_distance();
        assert!((inside - 8.0).abs() < 1e-4, "{inside}");
    }
}

#[test]
fn obstacle_left_right_or_none() {
    // The actor at the origin looks along −z; a far wall, and a post
    // left or right of the axis 3 ahead, within the actor's half width.
    let wall = (
        ShapeKind::Box,
        cuboid(Vec3::new(-20.0, -20.0, -31.0), Vec3::new(20.0, 20.0, -30.0)),
        1,
    );
    let post = |x0: f32, x1: f32| {
        (
            ShapeKind::Box,
            cuboid(Vec3::new(x0, -0.5, -3.5), Vec3::new(x1, 0.5, -3.0)),
            2,
        )
    };
    let view = View::new(Vec3::ZERO, Vec3::new(0.0, 0.0, -1.0), 600, 0.1, 100.0);
    let body = |size, dist| Body {
        size_actor: size,
        dist_coll: dist,
        ..Body::default()
    };
    let left = see(
        scene(&[wall, post(-0.8, -0.3)], &[], Vec3::Y * 10.0),
        &view,
        32,
    );
    let right = see(
        scene(&[wall, post(0.3, 0.8)], &[], Vec3::Y * 10.0),
        &view,
        32,
    );
    let clear = see(scene(&[wall], &[], Vec3::Y * 10.0), &view, 32);
    assert_eq!(left.percepts(&body(2.0, 5.0)).obstacle, -1.0);
    assert_eq!(right.percepts(&body(2.0, 5.0)).obstacle, 1.0);
    assert_eq!(clear.percepts(&body(2.0, 5.0)).obstacle, 0.0);
    // The far wall counts only within dist_coll.
    assert_ne!(clear.percepts(&body(2.0, 40.0)).obstacle, 0.0);
    // Beyond dist_coll, or outside the actor's width: no collision.
    assert_eq!(left.percepts(&body(2.0, 2.5)).obstacle, 0.0);
    assert_eq!(left.percepts(&body(0.4, 5.0)).obstacle, 0.0);
    // The closest obstacle decides: a nearer post on the right.
    let both = see(
        scene(
            &[
                wall,
                post(-0.8, -0.3),
                (
                    ShapeKind::Box,
                    cuboid(Vec3::new(0.2, -0.5, -2.5), Vec3::new(0.6, 0.5, -2.0)),
                    2,
                ),
            ],
            &[],
            Vec3::Y * 10.0,
        ),
        &view,
        32,
    );
    assert_eq!(both.percepts(&body(2.0, 5.0)).obstacle, 1.0);
}

/// The thesis's tennis ball material (3.1.2), with ambient red `red`.
fn tennis_ball(red: f32) -> Material {
    Material {
        name: "tennis ball".into(),
        ambient: Vec3::new(red, 0.2, 0.1),
        diffuse: Vec3::new(0.8, 0.4, 0.2),
        specular: Vec3::ZERO,
        ..material::table()[0].clone()
    }
}

#[test]
fn tennis_ball_recognised_by_chromatic_distance() {
    let ball_material = material::COUNT as u32;
    let look = |red| {
        let s = scene(
            &[
                (ShapeKind::Sphere, ball(Vec3::ZERO, 1.0), ball_material),
                (
                    ShapeKind::Box,
                    cuboid(Vec3::new(-5.0, -5.0, -3.0), Vec3::new(5.0, 5.0, -2.0)),
                    1,
                ),
            ],
            &[tennis_ball(red)],
            Vec3::new(3.0, 4.0, 8.0),
        );
        see(
            s,
            &View::new(Vec3::new(0.0, 0.0, 10.0), Vec3::ZERO, 200, 0.1, 100.0),
            48,
        )
    };
    // The ball's normalized colour, 3.1.2: (0.57, 0.29, 0.14).
    let c = material::chromaticity(Vec3::new(0.8, 0.4, 0.2));
    assert!((c - Vec3::new(0.571, 0.286, 0.143)).length() < 1e-3);
    let interest = Interest::rgb([204, 102, 51], vision::THESIS_THRESHOLD);
    let w = look(0.4);
    let ball_pixels = w
        .pixels
        .iter()
        .filter(|p| p.material == ball_material)
        .count();
    assert!(ball_pixels > 200, "{ball_pixels}");
    // Every ball pixel, lit or in its own shade, and nothing else.
    let mask = w.mask(&interest);
    for (p, m) in w.pixels.iter().zip(&mask) {
        assert_eq!(*m, p.material == ball_material, "{p:?}");
    }
    let shades: Vec<f32> = w
        .pixels
        .iter()
        .filter(|p| p.material == ball_material)
        .map(|p| p.shaded.x)
        .collect();
    let (lo, hi) = shades
        .iter()
        .fold((f32::MAX, 0.0f32), |(a, b), &v| (a.min(v), b.max(v)));
    assert!(hi > 2.0 * lo, "the shading varies: {lo}..{hi}");
    assert_eq!(
        w.percepts(&Body {
            rgb_interest: Some(interest),
            ..Body::default()
        })
        .rgb_interest_found,
        1.0
    );
    // Its ambient red changed to 0.1: the actor sees the change.
    let changed = look(0.1);
    assert_eq!(changed.mask(&interest).iter().filter(|&&m| m).count(), 0);
    assert_eq!(
        changed
            .percepts(&Body {
                rgb_interest: Some(interest),
                ..Body::default()
            })
            .rgb_interest_found,
        -1.0
    );
}

#[test]
fn flat_colours_identify_things_exactly() {
    // The ball (material 10) and player 0 (material 11) of table C.2.2.
    let s = scene(
        &[
            (ShapeKind::Sphere, ball(Vec3::new(-1.5, 0.0, 0.0), 1.0), 10),
            (ShapeKind::Sphere, ball(Vec3::new(1.5, 0.0, 0.0), 1.0), 11),
        ],
        &[],
        Vec3::new(0.0, 10.0, 10.0),
    );
    let accel = Accel::new(s);
    let w = vision::see(
        &accel,
        &OwnBody::default(),
        &View::new(Vec3::new(0.0, 0.0, 10.0), Vec3::ZERO, 450, 0.1, 100.0),
        40,
    );
    let colours = w.flat_colours(16);
    assert_eq!(colours.len(), 2);
    assert_eq!(w.flat_colours(1).len(), 1);
    for (thing, material) in [(0, 10u32), (1, 11)] {
        let i = Interest::thing(&accel, thing).unwrap();
        let found = w.find(&i).unwrap();
        let n = w.pixels.iter().filter(|p| p.material == material).count() as u32;
        assert_eq!(found.pixels, n);
        assert_eq!(
            w.percepts(&Body {
                interest: Some(i),
                ..Body::default()
            })
            .interest_found,
            1.0
        );
    }
    // Player 1 (material 12) is not there.
    let p1 = Interest::thing(&accel, 2).unwrap();
    assert_eq!(w.find(&p1), None);
    assert_eq!(
        w.percepts(&Body {
            interest: Some(p1),
            ..Body::default()
        })
        .interest_found,
        -1.0
    );
    assert_eq!(Interest::thing(&accel, 3), None);
}

/// A unit sphere of material 10 at `centre`, seen from (0, 0, d) toward
/// `look_at` through a window of `edge` with the angle `fov` (tenths).
fn sphere_window(centre: Vec3, d: f32, look_at: Vec3, fov: i64, edge: u32) -> (Window, Interest) {
    let s = scene(
        &[(ShapeKind::Sphere, ball(centre, 1.0), 10)],
        &[],
        Vec3::new(0.0, 0.0, d),
    );
    let accel = Accel::new(s);
    let w = vision::see(
        &accel,
        &OwnBody::default(),
        &View::new(Vec3::new(0.0, 0.0, d), look_at, fov, 0.1, 100.0),
        edge,
    );
    (w, Interest::thing(&accel, 0).unwrap())
}

#[test]
fn sphere_position_and_area_centred() {
    // r/D = 1/40: eq. 3.1.7–3.1.8 measure the visible surface at its own
    // depth, about 4r/3D (3 %) below the cross-section (docs/actors.md).
    let (d, edge) = (40.0, 64);
    let (w, i) = sphere_window(Vec3::ZERO, d, Vec3::ZERO, 60, edge);
    let f = w.find(&i).unwrap();
    assert!(f.pixels > 500, "{}", f.pixels);
    // Eq. 3.1.9 averages the visible surface: the sphere's centre, moved
    // toward the eye by the mean height 2r/3 of a hemisphere over its disc.
    let footprint = w.footprint(d - 1.0);
    let expected = Vec3::new(0.0, 0.0, 2.0 / 3.0);
    assert!(
        (f.position - expected).length() < footprint,
        "position {} footprint {footprint}",
        f.position
    );
    // The cross-section π r², by eq. 3.1.7 and 3.1.8.
    assert!((f.area / PI - 1.0).abs() < 0.05, "area {}", f.area / PI);
    assert!(
        (f.area_sum / PI - 1.0).abs() < 0.05,
        "area_sum {}",
        f.area_sum / PI
    );
}

#[test]
fn sphere_area_off_centre_is_better_summed() {
    // A wide window; the sphere seen 22° off its axis.
    let (w, i) = sphere_window(Vec3::new(4.0, 0.0, 0.0), 10.0, Vec3::ZERO, 600, 128);
    let f = w.find(&i).unwrap();
    let (e7, e8) = ((f.area / PI - 1.0).abs(), (f.area_sum / PI - 1.0).abs());
    assert!(e8 < e7, "eq. 3.1.7 off by {e7}, eq. 3.1.8 by {e8}");
    // Its position, laterally, within one pixel's footprint.
    let to = Vec3::new(4.0, 0.0, -10.0).normalize();
    let off = f.position - Vec3::new(4.0, 0.0, 0.0);
    let lateral = (off - off.dot(to) * to).length();
    let footprint = w.footprint(10.0);
    assert!(
        lateral < footprint,
        "lateral {lateral} footprint {footprint}"
    );
}

#[test]
fn goal_functions() {
    let eye = Vec3::ZERO;
    let goal = Vec3::new(0.0, 0.0, -10.0);
    assert_eq!(
        vision::looks_at_goal(eye, Vec3::new(0.0, 0.0, -1.0), goal, 0.99),
        1.0
    );
    assert_eq!(
        vision::looks_at_goal(eye, Vec3::new(1.0, 0.0, -1.0), goal, 0.99),
        -1.0
    );
    assert_eq!(
        vision::looks_at_goal(eye, Vec3::new(1.0, 0.0, -1.0), goal, 0.7),
        1.0
    );
    assert_eq!(vision::arrived_at_goal(eye, goal, 10.5), 1.0);
    assert_eq!(vision::arrived_at_goal(eye, goal, 9.5), -1.0);
}

#[test]
fn identical_for_one_and_two_threads() {
    let shapes: Vec<(ShapeKind, Affine3A, u32)> = (0..40)
        .map(|k| {
            let a = k as f32 * 0.7;
            let c = Vec3::new(
                a.cos() * (2.0 + k as f32 * 0.1),
                a.sin() * 1.5,
                -(k as f32) * 0.2,
            );
            if k % 2 == 0 {
                (ShapeKind::Sphere, ball(c, 0.8), 10 + (k % 3))
            } else {
                (ShapeKind::Box, cuboid(c, c + Vec3::splat(1.0)), k % 27 + 1)
            }
        })
        .collect();
    let accel = Accel::new(scene(&shapes, &[], Vec3::new(2.0, 8.0, 12.0)));
    let view = View::new(
        Vec3::new(0.0, 0.0, 10.0),
        Vec3::new(0.0, 0.0, -2.0),
        500,
        0.1,
        100.0,
    );
    let run = |threads| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| vision::see(&accel, &OwnBody::default(), &view, 64))
    };
    let (one, two) = (run(1), run(2));
    let hits = one.pixels.iter().filter(|p| p.hit()).count();
    assert!(hits > 100, "{hits}");
    assert_eq!(one, two);
}
