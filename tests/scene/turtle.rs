//! The turtle's interpretation of words into scenes (issue 3).

use crate::common::*;
use glam::{Vec3, Vec3A};
use lmfilm::lsys::NoSensors;
use lmfilm::scene::{mesh, snapshot, Scene, ShapeKind};
use lmfilm::turtle::{build_scene, NoWorld, Options, Surfaces};

/// (start, end) of every cylinder-like shape along its local x axis.
fn segments(s: &Scene) -> Vec<(Vec3A, Vec3A)> {
    s.geometries
        .iter()
        .flat_map(|g| g.shapes.iter())
        .map(|sh| {
            let t = sh.transform;
            let len = match sh.kind {
                ShapeKind::Capsule { length } => length,
                ShapeKind::Trunk { length, .. } => length,
                _ => 1.0,
            };
            (t.translation, t.translation + t.matrix3.x_axis * len)
        })
        .collect()
}

fn near(a: Vec3A, b: Vec3) -> bool {
    (a - Vec3A::from(b)).length() < 1e-5
}

#[test]
fn growing_tree_tips_where_the_thesis_draws_them() {
    let mut a = load("growing_tree_drawn.lm");
    a.advance_to(a.frame_at(1.5), &mut NoSensors).unwrap();
    let (s, _) = scene(&mut a);
    let seg = segments(&s);
    assert_eq!(seg.len(), 3);
    assert!(
        near(seg[0].0, Vec3::ZERO) && near(seg[0].1, Vec3::new(0.0, 6.5, 0.0)),
        "{seg:?}"
    );
    assert!(
        near(seg[1].0, Vec3::new(0.0, 6.5, 0.0)) && near(seg[1].1, Vec3::new(-1.5, 6.5, 0.0)),
        "{seg:?}"
    );
    assert!(near(seg[2].1, Vec3::new(1.5, 6.5, 0.0)), "{seg:?}");
}

#[test]
fn rotations_move_the_heading() {
    // From H = +x: + turns toward L (+y), & pitches toward −U (−z),
    // / rolls, and f moves along the new heading.
    for (turn, end) in [
        ("+", Vec3::new(0.0, 1.0, 0.0)),
        ("-", Vec3::new(0.0, -1.0, 0.0)),
        ("&", Vec3::new(0.0, 0.0, -1.0)),
        ("^", Vec3::new(0.0, 0.0, 1.0)),
        ("/", Vec3::new(1.0, 0.0, 0.0)),
    ] {
        let mut a = from_text(&format!(
            "Axiom\n{turn} () () () () (90) f () () () () (1) ? \n"
        ));
        scene(&mut a);
        let q = a.systems[0].word()[2];
        assert!(
            (Vec3::from_array(q.par.map(|v| v as f32)) - end).length() < 1e-6,
            "{turn}: {:?}",
            q.par
        );
    }
    // f par3 = 1, 2, 3: absolute vector, absolute position, turtle frame.
    let mut a = from_text(
        "Axiom\n+()()()()(90) f()()()(1)(1)(2)(3) ? f()()()(2)(5)(5)(5) f()()()(3)(1)(2)(0) ?\n",
    );
    scene(&mut a);
    let w = a.systems[0].word();
    assert_eq!(w[2].par, [1.0, 2.0, 3.0]);
    // At (5,5,5) with H = +y, L = −x: 1·H + 2·L = (−2, 1, 0).
    let p = w[5].par;
    assert!(
        (p[0] - 3.0).abs() < 1e-9 && (p[1] - 6.0).abs() < 1e-9 && (p[2] - 5.0).abs() < 1e-9,
        "{p:?}"
    );
}

/// Mean of the shape end points: where the crown is.
fn crown(s: &Scene) -> Vec3A {
    let seg = segments(s);
    seg.iter().map(|p| p.1).sum::<Vec3A>() / seg.len() as f32
}

#[test]
fn code_6_2_1_bends_toward_the_force_and_follows_the_wind() {
    let text = std::fs::read_to_string(example("cours_tree3.lm")).unwrap();
    let at = |text: &str| {
        let mut a = from_text(text);
        a.advance_to(a.frame_at(3.0), &mut NoSensors).unwrap();
        crown(&scene(&mut a).0)
    };
    let still = at(&text.replace("v () (1) () () (2.5) (1) ()", "v () (2)"));
    let windy = at(&text);
    let force = Vec3A::new(-0.31, 0.3, 0.19);
    let shift = windy - still;
    assert!(shift.length() > 0.5, "the tree bends: {shift:?}");
    assert!(shift.dot(force) > 0.0, "toward the force: {shift:?}");
    let other = at(&text.replace("(0.31_) (0.3) (0.19)", "(0.31) (0.3) (0.19)"));
    let other_shift = other - still;
    assert!(
        shift.x < 0.0 && other_shift.x > 0.0,
        "the tip's side follows the wind: {shift:?} {other_shift:?}"
    );
    let stiff = at(&text.replace("(2.5) (1) ()", "(25) (1) ()"));
    assert!(
        (stiff - still).length() < shift.length(),
        "a stiffer tree bends less"
    );
}

#[test]
fn query_symbol_and_state_tables_persist_across_frames() {
    // [(1) saves the state at the end of each frame; ](1) starts the next
    // frame from it, so the walker advances 1 per frame.
    let mut a = from_text(
        "Camera_AnimationParameters\nt_final_interval 10 1\nAxiom\n[ ] () (1) (1) f () () () () (1) [ () (1) (1) ? ]\n",
    );
    let surfaces = Surfaces::load(&a).unwrap();
    let mut tables = Vec::new();
    for frame in 1..=3 {
        build_scene(
            &mut a,
            &surfaces,
            &mut tables,
            &mut NoWorld,
            Options::default(),
        )
        .unwrap();
        let q = a.systems[0].word()[4];
        assert_eq!(q.par, [frame as f64, 0.0, 0.0]);
        a.step(&mut NoSensors).unwrap();
    }
}

#[test]
fn shapes_have_their_analytic_sizes() {
    let text = "Axiom\nc () () () () (2) (3) (4)\nO () () () () (5) (0.5) (0.5)\no () () () () (2) (1) (1)\nP () () () () (3) (1) (0.5)\na () () () () (2)\ns () () () () (2) (4) (6)\np () () () () (3) (2) (2)\nR () () () () (4)\n";
    let mut a = from_text(text);
    let (s, messages) = scene(&mut a);
    assert!(messages.is_empty(), "{messages:?}");
    let g = &s.geometries[0];
    assert_eq!(g.shapes.len(), 7);
    assert_eq!(g.triangles.len(), 6, "the pyramid is exact as triangles");
    let size = |k: usize| {
        let mut tris = Vec::new();
        mesh::tessellate(&g.shapes[k], 64, &mut tris);
        let (lo, hi) = tris
            .iter()
            .flat_map(|t| t.v)
            .fold((Vec3::MAX, Vec3::MIN), |(lo, hi), v| (lo.min(v), hi.max(v)));
        hi - lo
    };
    let close = |a: Vec3, b: Vec3| (a - b).abs().max_element() < 0.01 * b.max_element();
    // Along the heading (+x): the cube 2 long, 3 × 4 across.
    assert!(close(size(0), Vec3::new(2.0, 3.0, 4.0)), "{:?}", size(0));
    // Capsule: length 5 plus two caps of radius 0.5.
    assert!(close(size(1), Vec3::new(6.0, 1.0, 1.0)), "{:?}", size(1));
    assert!(close(size(2), Vec3::new(2.0, 2.0, 2.0)), "{:?}", size(2));
    // Trunk: length 3, sphere of radius 1 at the base, 0.5 at the end.
    assert!(close(size(3), Vec3::new(4.5, 2.0, 2.0)), "{:?}", size(3));
    // Sphere of diameter 2; ellipsoid of diameters 2, 4, 6.
    assert!(close(size(4), Vec3::new(2.0, 2.0, 2.0)), "{:?}", size(4));
    assert!(close(size(5), Vec3::new(2.0, 4.0, 6.0)), "{:?}", size(5));
    // The segment is a thin cylinder 4 long.
    assert!(close(size(6), Vec3::new(4.0, 0.05, 0.05)), "{:?}", size(6));
}

#[test]
fn degenerate_shapes_are_skipped_with_one_warning_per_kind() {
    let mut a = from_text(
        "Axiom\nc () () () () (1_) (1) (1) c () () () () (2_) (1) (1) a () () () () (1_) O () () () () (1) (0 0/) (1)\n",
    );
    let (s, messages) = scene(&mut a);
    assert_eq!(s.geometries[0].shapes.len(), 0);
    assert_eq!(messages.len(), 3, "{messages:?}");
    assert!(messages[0].contains("`c`"));
    assert!(
        messages[0].starts_with("test.lm:2:1: warning: "),
        "{messages:?}"
    );
}

#[test]
fn shapes_not_grown_yet_are_skipped_silently() {
    // Growth functions start at 0 at birth: a size of exactly 0 is no mistake.
    let mut a = from_text("Axiom\nc () () () () (0) (1) (1) S a () () () () (0) O\n");
    let (s, messages) = scene(&mut a);
    assert_eq!(s.geometries[0].shapes.len(), 0);
    assert!(messages.is_empty(), "{messages:?}");
}

#[test]
fn camera_lights_and_materials() {
    let mut a = load("cours_tree3.lm");
    let (s, _) = scene(&mut a);
    assert_eq!(s.camera.eye, Vec3::new(0.0, 15.0, 130.0));
    assert_eq!(s.camera.fov_y, 50.0);
    assert_eq!((s.camera.width, s.camera.height), (721, 576));
    assert_eq!(s.lights.len(), 1, "a default light at the observer");
    assert_eq!(s.lights[0].position, s.camera.eye);
    // m () (6) selects material 6, gray, for every shape.
    assert!(s.geometries[0]
        .shapes
        .iter()
        .all(|sh| s.materials[sh.material as usize].name == "gray"));
    let mut a = from_text("Axiom\nl () () () (0) (1) (2) (3) l () () () (3) (4) (5) (6) l () () () (2) (300) (2) (0) m () (4) () (1) (0.5) (0.25) (1) a () () () () (1)\n");
    let (s, _) = scene(&mut a);
    assert_eq!(s.camera.eye, Vec3::new(1.0, 2.0, 3.0));
    assert_eq!(s.camera.fov_y, 30.0);
    assert_eq!(s.lights[0].position, Vec3::new(4.0, 5.0, 6.0));
    let m = &s.materials[s.geometries[0].shapes[0].material as usize];
    assert_eq!(m.diffuse, Vec3::new(0.5, 0.25, 1.0), "diffuse animation");
}

#[test]
fn repetition_shares_one_geometry() {
    let text = "RepetitionParameters\nrotate_max 0 360 0\nstartp_sidel_nbr_dist -20 40 25 0.1\nAxiom\n+()()()()(90) N () () () () (3) (0.2) (0.2) a () () () () (2)\n";
    let mut a = from_text(text);
    let (s, _) = scene(&mut a);
    assert_eq!(s.geometries.len(), 1);
    assert_eq!(s.instances.len(), 25);
    assert!(s.instances.iter().all(|i| i.geometry == 0));
    for i in &s.instances {
        let p = i.transform.translation;
        assert!((-20.0..=20.0).contains(&p.x) && (-20.0..=20.0).contains(&p.z));
    }
    assert_eq!(s.expanded_counts(), (50, 0));
}

#[test]
fn snapshot_round_trip_is_bit_exact() {
    let mut a = load("cours_tree3.lm");
    a.advance_to(60, &mut NoSensors).unwrap();
    let (s, _) = scene(&mut a);
    let bytes = snapshot::encode(&s);
    let back = snapshot::decode(&bytes).unwrap();
    assert_eq!(back, s);
    assert_eq!(snapshot::encode(&back), bytes);
}

#[test]
fn polygons_and_special_symbols() {
    // A concave L-shaped leaf, a slab polygon, the ground and the court.
    let leaf = "{ . f()()()(2)(2)(0)(0) . f()()()(2)(2)(1)(0) . f()()()(2)(1)(1)(0) . f()()()(2)(1)(2)(0) . f()()()(2)(0)(2)(0) . }";
    let text = format!("Axiom\n{leaf} {{ . f()()()(1)(1)(0)(0) . f()()()(1)(1)(0)(1) . }} () (0) (1) (1) (0.5) D () (2) () () (0) D () (41) (1)\n");
    let mut a = from_text(&text);
    let (s, messages) = scene(&mut a);
    assert!(messages.is_empty(), "{messages:?}");
    let g = &s.geometries[0];
    let area: f32 = g.triangles[..4]
        .iter()
        .map(|t| (t.v[1] - t.v[0]).cross(t.v[2] - t.v[0]).length() / 2.0)
        .sum();
    assert!((area - 3.0).abs() < 1e-5, "leaf area {area}");
    // The slab: 1 + 1 faces and 3 sides of 2 triangles.
    assert_eq!(g.triangles.len(), 4 + 8 + 2);
    assert!(g.shapes.len() >= 10, "court surface, lines and net");
}

#[test]
fn a_forest_costs_one_tree_plus_transforms() {
    // Code 6.2.1 at T = 8 (tens of thousands of shapes), once and as a
    // forest of 1,000 copies: the snapshot grows by the transforms only.
    let text = std::fs::read_to_string(example("cours_tree3.lm")).unwrap();
    let forest = text.replace(
        "RepetitionParameters\n/* in this file the repetition section is empty */",
        "RepetitionParameters\nrotate_max 0 360 0\nscale 0.8\nscale_max 1.2\nstartp_sidel_nbr_dist -500 1000 1000 0.01",
    );
    assert_ne!(forest, text);
    let size = |t: &str| {
        let mut a = from_text(t);
        a.advance_to(200, &mut NoSensors).unwrap();
        let (s, _) = scene(&mut a);
        (
            s.geometries[0].shapes.len(),
            s.instances.len(),
            snapshot::encode(&s).len(),
        )
    };
    let (shapes, one, bytes_one) = size(&text);
    let (shapes_f, many, bytes_many) = size(&forest);
    assert!(shapes > 10_000, "{shapes}");
    assert_eq!((shapes_f, one, many), (shapes, 1, 1000));
    let per_copy = (bytes_many - bytes_one) as f64 / 999.0;
    assert!(per_copy < 64.0, "{per_copy} bytes per copy");
}

#[test]
fn imported_surfaces_are_instances_in_the_turtle_frame() {
    let mut a = load("leaves.lm");
    a.advance_to(a.frame_at(4.0), &mut NoSensors).unwrap();
    let (s, messages) = scene(&mut a);
    assert!(messages.is_empty(), "{messages:?}");
    // Geometry 0 is the leaf, 1 the stem; 4 leaves placed as instances.
    assert_eq!(s.geometries[0].triangles.len(), 2);
    assert_eq!(s.instances.iter().filter(|i| i.geometry == 0).count(), 4);
    let leaf_mat = &s.materials[s.geometries[0].triangles[0].material as usize];
    assert_eq!(leaf_mat.name, "leaf_green");
    // The first leaf hangs from the stem's first node, at height 0.5.
    let first = s.instances.iter().find(|i| i.geometry == 0).unwrap();
    assert!(
        (first.transform.translation.y - 0.5).abs() < 1e-5,
        "{:?}",
        first.transform
    );
}

#[test]
fn named_objects_become_instances_with_rayshade_transforms() {
    // D 6 names object 1, D 1 ends it, D 7 places it twice; D 8 moves the
    // second placement by (0, 5, 0).
    // Defined 2 along x: placements are relative to where it was defined.
    let text = "Axiom\nf () () () () (2) D () (6) () () (1) a () () () () (1) D () (1) f () () () () (8) D () (7) () () (1) f () () () () (10) D () (7) () () (1) D () (8) () () (0) (5) (0)\n";
    let mut a = from_text(text);
    let (s, messages) = scene(&mut a);
    assert!(messages.is_empty(), "{messages:?}");
    assert_eq!(s.geometries.len(), 2);
    assert!(s.geometries[0].is_empty());
    assert_eq!(s.geometries[1].name, "obj1");
    // Where the sphere ends up: its centre through the instance transform.
    let centre = s.geometries[1].shapes[0].transform.translation;
    let placed: Vec<Vec3A> = s
        .instances
        .iter()
        .filter(|i| i.geometry == 1)
        .map(|i| i.transform.transform_point3a(centre))
        .collect();
    assert_eq!(placed.len(), 2);
    assert!(
        near(placed[0], Vec3::new(10.0, 0.0, 0.0)) && near(placed[1], Vec3::new(20.0, 5.0, 0.0)),
        "{placed:?}"
    );
}

#[test]
fn tennis_court_at_real_dimensions() {
    let mut a = from_text("Axiom\nD () (41)\n");
    let (s, _) = scene(&mut a);
    let bounds = |name: &str| {
        let mut tris = Vec::new();
        for sh in &s.geometries[0].shapes {
            if s.materials[sh.material as usize].name == name {
                mesh::tessellate(sh, 8, &mut tris);
            }
        }
        tris.iter()
            .flat_map(|t| t.v)
            .fold((Vec3::MAX, Vec3::MIN), |(lo, hi), v| (lo.min(v), hi.max(v)))
    };
    let (lo, hi) = bounds("court_line");
    assert!(
        (hi.x - 11.885).abs() < 1e-3 && (lo.x + 11.885).abs() < 1e-3,
        "length 23.77: {lo} {hi}"
    );
    assert!(
        (hi.z - 5.485).abs() < 1e-3 && (lo.z + 5.485).abs() < 1e-3,
        "doubles width 10.97: {lo} {hi}"
    );
    let (lo, hi) = bounds("court_net");
    assert!(
        (hi.y - 0.91).abs() < 1e-4 && lo.y.abs() < 1e-6,
        "net height: {lo} {hi}"
    );
    assert!(lo.x > -0.02 && hi.x < 0.02, "net in the y–z plane at x = 0");
    assert!(
        (hi.z - 6.399).abs() < 1e-2,
        "net posts 0.914 m outside: {hi}"
    );
}

#[test]
fn bounding_box_print_textures_and_observer_light() {
    let text = "Axiom\nD () (20) c () () () () (2) (2) (2) D () (21) f () () () () (3) D () (30) D () (10) a () () () () (1) D () (18) D () (15)\n";
    let mut a = from_text(text);
    let (s, messages) = scene(&mut a);
    assert_eq!(
        messages,
        [
            "bounding box 0.000000 -1.000000 -1.000000 2.000000 1.000000 1.000000",
            "turtle position 5.000000 0.000000 0.000000"
        ]
    );
    let sphere = s.geometries[0].shapes[1];
    assert_eq!(
        s.materials[sphere.material as usize].texture,
        Some(lmfilm::scene::material::Texture::Marble)
    );
    assert_eq!(s.lights.len(), 1);
    assert_eq!(s.lights[0].position, s.camera.eye);
    assert_ne!(s.background, Vec3::ZERO, "D 15 gives a sky");
}

/// The path tracer's scene settings: the lens from the camera section
/// and from `l` par3 = 14 (a later frame's word wins), and `D` 15 with
/// a colour as a uniform sky of that radiance.
#[test]
fn lens_and_uniform_sky_from_the_scene() {
    use lmfilm::scene::{Lens, Sky};
    let camera = "Camera_AnimationParameters\nobserver 0 0 5\naperture 0.05\nfocusDistance 4\nt_final_interval 1 0.04\n";
    let mut a = crate::common::from_text(&format!("{camera}Axiom\nD () (15) a () (1)\n"));
    let (s, _) = crate::common::scene(&mut a);
    assert_eq!(
        s.camera.lens,
        Lens {
            radius: 0.05,
            focus: 4.0
        }
    );
    assert_eq!(
        (s.sky, s.background),
        (Sky::Gradient, Vec3::new(0.45, 0.62, 0.9))
    );
    let word = "Axiom\nl () () () (14) (0.2) (7) D () (15) () () (0.5) (2) (0.25) a () (1)\n";
    let mut a = crate::common::from_text(&format!("{camera}{word}"));
    let (s, _) = crate::common::scene(&mut a);
    assert_eq!(
        s.camera.lens,
        Lens {
            radius: 0.2,
            focus: 7.0
        }
    );
    assert_eq!(
        (s.sky, s.background),
        (Sky::Uniform, Vec3::new(0.5, 2.0, 0.25))
    );
    let bad = lmfilm::lsys::Source::new("bad.lm", "Camera_AnimationParameters\naperture -1\n");
    let e = lmfilm::lsys::Animation::from_sources(&[bad], &mut lmfilm::lsys::NoSensors)
        .map(|_| ())
        .unwrap_err()
        .to_string();
    assert!(e.contains("the aperture radius must be ≥ 0"), "{e}");
}

#[test]
fn not_a_number_never_reaches_the_scene() {
    let text = "Axiom\nf () () () (1) (0 0/) c () () () () (1) (1) (1) + () () () () (0 0/) c () () () () (1) (1) (1) f () () () () (1 0 /) a () () () () (1)\n";
    let mut a = from_text(text);
    let (s, messages) = scene(&mut a);
    assert!(messages.iter().any(|m| m.contains("`f`")), "{messages:?}");
    let g = &s.geometries[0];
    assert!(g.shapes.iter().all(|sh| sh.transform.is_finite()));
    assert_eq!(
        g.shapes.len(),
        3,
        "bad moves and turns are skipped, the shapes stand"
    );
}

#[test]
fn low_resolution_n_is_kept() {
    let mut a = from_text("Axiom\nn () (4) a () () () () (1)\n");
    assert_eq!(scene(&mut a).0.geometries[0].resolution, 4);
    let mut a = from_text("Axiom\na () () () () (1)\n");
    assert_eq!(scene(&mut a).0.geometries[0].resolution, 10);
}

#[test]
fn a_surface_without_materials_takes_the_current_material() {
    let dir = fresh_dir("turtle", "obj-no-mtl");
    std::fs::write(dir.join("tri.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    let lm = dir.join("s.lm");
    std::fs::write(
        &lm,
        "Surfaces\nfig_obj 1 tri.obj\nAxiom\nm () (4) B () (1) () () (1) (1) (1) [ f () () () (2) m () (0) B () (1) () () (1) (1) (1) ]\n",
    )
    .unwrap();
    let mut a = lmfilm::lsys::Animation::load(&[&lm], &mut NoSensors).unwrap();
    let (s, _) = scene(&mut a);
    // The instance of each placement, in order: the word, then the two `B`.
    let colour = |k: usize| {
        let g = &s.geometries[s.instances[k].geometry as usize];
        s.materials[g.triangles[0].material as usize].name.clone()
    };
    assert_eq!(s.instances.len(), 3);
    assert_eq!(colour(1), "red", "m () (4) before B applies");
    assert_eq!(
        colour(2),
        s.materials[0].name,
        "the default stays the default"
    );
    std::fs::remove_dir_all(&dir).ok();
}
