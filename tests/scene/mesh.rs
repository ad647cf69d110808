//! Tessellation of the analytic shapes and the OBJ export/import.

use std::collections::HashMap;
use std::f32::consts::PI;
use std::path::{Path, PathBuf};

use glam::{Affine3A, Quat, Vec3};
use lmfilm::scene::mesh::{expand, tessellate};
use lmfilm::scene::obj::{read_obj, write_obj};
use lmfilm::scene::{Camera, Geometry, Instance, Material, Scene, Shape, ShapeKind, Triangle};

fn transform(scale: Vec3) -> Affine3A {
    let rot = Quat::from_euler(glam::EulerRot::XYZ, 0.3, -0.7, 1.1);
    Affine3A::from_scale_rotation_translation(scale, rot, Vec3::new(1.0, -2.0, 3.0))
}

fn shape(kind: ShapeKind, transform: Affine3A) -> Shape {
    Shape {
        kind,
        transform,
        material: 2,
        symbol: 42,
    }
}

/// The shapes under test with a non-trivial transform; trunks are rigid.
fn cases() -> Vec<Shape> {
    let stretch = transform(Vec3::new(1.5, 0.7, 2.0));
    let rigid = transform(Vec3::ONE);
    vec![
        shape(ShapeKind::Box, stretch),
        shape(ShapeKind::Sphere, stretch),
        shape(ShapeKind::Cylinder, stretch),
        shape(ShapeKind::Capsule { length: 2.5 }, stretch),
        shape(
            ShapeKind::Trunk {
                length: 3.0,
                r0: 0.6,
                r1: 0.6,
            },
            rigid,
        ),
        shape(
            ShapeKind::Trunk {
                length: 2.0,
                r0: 1.0,
                r1: 0.3,
            },
            rigid,
        ),
        // A fat start sphere that swallows the whole cone and the end sphere.
        shape(
            ShapeKind::Trunk {
                length: 0.5,
                r0: 2.0,
                r1: 0.4,
            },
            rigid,
        ),
    ]
}

/// Analytic bounding box: an ellipsoid `t`(sphere of radius r at local c)
/// has half-extent r·|row j| of the linear part along world axis j, and a
/// disk in the local y–z plane r·|(m_j1, m_j2)|.
fn analytic_bbox(s: &Shape) -> (Vec3, Vec3) {
    let t = s.transform;
    let m = t.matrix3;
    let rows = [m.row(0), m.row(1), m.row(2)];
    let full = Vec3::from_array(rows.map(|r| r.length()));
    let disk = Vec3::from_array(rows.map(|r| (r.y * r.y + r.z * r.z).sqrt()));
    let mut lo = Vec3::splat(f32::INFINITY);
    let mut hi = Vec3::splat(f32::NEG_INFINITY);
    let mut add = |centre: Vec3, half: Vec3| {
        let c = t.transform_point3(centre);
        lo = lo.min(c - half);
        hi = hi.max(c + half);
    };
    match s.kind {
        ShapeKind::Box => {
            for i in 0..8 {
                let x = (i & 1) as f32;
                let y = ((i >> 1) & 1) as f32 - 0.5;
                let z = ((i >> 2) & 1) as f32 - 0.5;
                add(Vec3::new(x, y, z), Vec3::ZERO);
            }
        }
        ShapeKind::Sphere => add(Vec3::ZERO, full),
        ShapeKind::Cylinder => {
            add(Vec3::ZERO, disk);
            add(Vec3::X, disk);
        }
        ShapeKind::Capsule { length } => {
            add(Vec3::ZERO, full);
            add(Vec3::X * length, full);
        }
        // The frustum lies inside the hull of its two end spheres.
        ShapeKind::Trunk { length, r0, r1 } => {
            add(Vec3::ZERO, full * r0);
            add(Vec3::X * length, full * r1);
        }
    }
    (lo, hi)
}

/// Analytic volume; a trunk by integrating π·R(x)² of the union outline.
fn analytic_volume(s: &Shape) -> f32 {
    let det = s.transform.matrix3.determinant();
    let unit = match s.kind {
        ShapeKind::Box => 1.0,
        ShapeKind::Sphere => 4.0 / 3.0 * PI,
        ShapeKind::Cylinder => PI,
        ShapeKind::Capsule { length } => PI * length + 4.0 / 3.0 * PI,
        ShapeKind::Trunk { length, r0, r1 } => {
            let (l, r0, r1) = (length as f64, r0 as f64, r1 as f64);
            let sphere = |c: f64, r: f64, x: f64| (r * r - (x - c) * (x - c)).max(0.0).sqrt();
            let radius = |x: f64| {
                let cone = if (0.0..=l).contains(&x) {
                    r0 + (r1 - r0) * x / l
                } else {
                    0.0
                };
                sphere(0.0, r0, x).max(sphere(l, r1, x)).max(cone)
            };
            let (lo, hi) = ((-r0).min(l - r1), r0.max(l + r1));
            let n = 200_000;
            let dx = (hi - lo) / n as f64;
            let sum: f64 = (0..n)
                .map(|i| radius(lo + (i as f64 + 0.5) * dx).powi(2))
                .sum();
            (std::f64::consts::PI * sum * dx) as f32
        }
    };
    unit * det
}

fn mesh(s: &Shape, resolution: u32) -> Vec<Triangle> {
    let mut out = Vec::new();
    tessellate(s, resolution, &mut out);
    out
}

fn bbox(tris: &[Triangle]) -> (Vec3, Vec3) {
    tris.iter().flat_map(|t| t.v).fold(
        (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
        |(lo, hi), p| (lo.min(p), hi.max(p)),
    )
}

/// Signed volume by the divergence theorem: positive when outward.
fn volume(tris: &[Triangle]) -> f32 {
    let sum: f64 = tris
        .iter()
        .map(|t| {
            t.v[0]
                .as_dvec3()
                .dot(t.v[1].as_dvec3().cross(t.v[2].as_dvec3()))
        })
        .sum();
    (sum / 6.0) as f32
}

type Key = [u32; 3];

fn key(p: Vec3) -> Key {
    p.to_array().map(f32::to_bits)
}

#[test]
fn bounding_boxes_match_analytic_ones() {
    for s in cases() {
        let tris = mesh(&s, 32);
        assert!(!tris.is_empty(), "{:?}", s.kind);
        let (lo, hi) = bbox(&tris);
        let (alo, ahi) = analytic_bbox(&s);
        let tol = (ahi - alo).max_element() * 0.02;
        assert!(
            lo.distance(alo) <= tol && hi.distance(ahi) <= tol,
            "{:?}: mesh {lo}..{hi}, analytic {alo}..{ahi}",
            s.kind
        );
    }
}

#[test]
fn meshes_are_closed_and_consistently_oriented() {
    for s in cases() {
        for resolution in [3, 4, 7, 32] {
            let tris = mesh(&s, resolution);
            // Each directed edge once, and its reverse once: closed, and
            // neighbouring triangles agree on orientation.
            let mut edges: HashMap<(Key, Key), u32> = HashMap::new();
            for t in &tris {
                for i in 0..3 {
                    *edges
                        .entry((key(t.v[i]), key(t.v[(i + 1) % 3])))
                        .or_default() += 1;
                }
            }
            for (&(a, b), &n) in &edges {
                assert_eq!(n, 1, "{:?} at {resolution}: edge used {n} times", s.kind);
                assert_eq!(
                    edges.get(&(b, a)),
                    Some(&1),
                    "{:?} at {resolution}: open edge",
                    s.kind
                );
            }
        }
    }
}

#[test]
fn volumes_match_analytic_ones() {
    for s in cases() {
        let (got, want) = (volume(&mesh(&s, 64)), analytic_volume(&s));
        assert!(
            (got - want).abs() <= 0.03 * want,
            "{:?}: mesh {got}, analytic {want}",
            s.kind
        );
        // Vertices lie on the surface and every kink of a union outline is
        // a vertex, so the mesh is inscribed and never bigger.
        assert!(got <= want * 1.0001, "{:?}: mesh {got} > {want}", s.kind);
    }
}

#[test]
fn shape_attributes_are_copied() {
    for s in cases() {
        for t in mesh(&s, 8) {
            assert_eq!((t.material, t.symbol), (2, 42));
        }
    }
}

#[test]
fn box_and_cylinder_triangle_counts() {
    let id = Affine3A::IDENTITY;
    assert_eq!(mesh(&shape(ShapeKind::Box, id), 32).len(), 12);
    // Two cap fans and one side band of two triangles per segment.
    assert_eq!(mesh(&shape(ShapeKind::Cylinder, id), 32).len(), 4 * 32);
}

fn material(name: &str, diffuse: Vec3, transmit: f32) -> Material {
    Material {
        name: name.into(),
        ambient: diffuse * 0.2,
        diffuse,
        specular: Vec3::splat(0.3),
        shininess: 20.0,
        reflect: 0.0,
        transmit,
        ior: if transmit > 0.0 { 1.5 } else { 1.0 },
        vision: diffuse,
        texture: None,
    }
}

fn small_scene() -> Scene {
    let tri = Triangle {
        v: [Vec3::ZERO, Vec3::X, Vec3::new(0.25, 1.0, 0.5)],
        material: 1,
        symbol: 9,
    };
    let tree = Geometry {
        name: "tree".into(),
        shapes: vec![
            shape(
                ShapeKind::Trunk {
                    length: 2.0,
                    r0: 0.3,
                    r1: 0.2,
                },
                Affine3A::from_rotation_y(-1.2),
            ),
            Shape {
                material: 0,
                ..shape(ShapeKind::Sphere, transform(Vec3::splat(0.5)))
            },
        ],
        triangles: vec![tri],
        resolution: 8,
    };
    let block = Geometry {
        name: "block".into(),
        shapes: vec![shape(ShapeKind::Box, Affine3A::IDENTITY)],
        triangles: vec![],
        resolution: 8,
    };
    Scene {
        frame: 3,
        time: 0.12,
        camera: Camera {
            eye: Vec3::new(0.0, -10.0, 2.0),
            look_at: Vec3::ZERO,
            twist: 0.0,
            fov_y: 45.0,
            aspect: 4.0 / 3.0,
            near: 0.1,
            far: 100.0,
            width: 320,
            height: 240,
            lens: Default::default(),
        },
        lights: vec![],
        materials: vec![
            material("bark brown", Vec3::new(0.4, 0.3, 0.1), 0.0),
            material("leaf", Vec3::new(0.1, 0.6, 0.1), 0.0),
            material("glass", Vec3::new(0.1, 0.1, 0.1), 0.8),
        ],
        geometries: vec![tree, block],
        instances: vec![
            Instance {
                geometry: 0,
                transform: Affine3A::from_translation(Vec3::new(5.0, 0.0, 0.0)),
                object: 1,
            },
            Instance {
                geometry: 1,
                transform: Affine3A::from_scale(Vec3::new(-1.0, 2.0, 1.0)),
                object: 2,
            },
            Instance {
                geometry: 0,
                transform: transform(Vec3::splat(1.3)),
                object: 3,
            },
        ],
        background: Vec3::ZERO,
        sky: Default::default(),
    }
}

fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("lmfilm-mesh-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

#[test]
fn expand_places_instances_in_order() {
    let scene = small_scene();
    let tris = expand(&scene);
    let mut tree = Vec::new();
    for s in &scene.geometries[0].shapes {
        tessellate(s, 8, &mut tree);
    }
    tree.extend(&scene.geometries[0].triangles);
    assert_eq!(tris.len(), 2 * tree.len() + 12);
    let moved = scene.instances[0].transform;
    for (a, b) in tris.iter().zip(&tree) {
        assert_eq!(a.v, b.v.map(|p| moved.transform_point3(p)));
        assert_eq!((a.material, a.symbol), (b.material, b.symbol));
    }
    // The mirrored box still has outward normals.
    let block = &tris[tree.len()..tree.len() + 12];
    assert!(volume(block) > 0.0);
}

#[test]
fn obj_round_trip() {
    let scene = small_scene();
    let dir = temp_dir("roundtrip");
    let path = dir.join("frame 0003.obj");
    write_obj(&scene, &path).unwrap();
    let first = std::fs::read(&path).unwrap();
    let first_mtl = std::fs::read(dir.join("frame 0003.mtl")).unwrap();
    write_obj(&scene, &path).unwrap();
    assert_eq!(first, std::fs::read(&path).unwrap(), "OBJ bytes differ");
    assert_eq!(
        first_mtl,
        std::fs::read(dir.join("frame 0003.mtl")).unwrap()
    );
    // No temporary files left behind.
    assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 2);

    let want = expand(&scene);
    let (got, materials) = read_obj(&path, 10).unwrap();
    assert_eq!(got.len(), want.len());
    for (g, w) in got.iter().zip(&want) {
        for (p, q) in g.v.iter().zip(&w.v) {
            assert!(p.distance(*q) <= 1e-5, "{p} vs {q}");
        }
        assert_eq!(g.symbol, 0);
        let m = &materials[(g.material - 10) as usize];
        let original = &scene.materials[w.material as usize];
        assert_eq!(m.name, original.name.replace(' ', "_"));
        assert!(m.diffuse.distance(original.diffuse) < 1e-5);
        assert!(m.ambient.distance(original.ambient) < 1e-5);
        assert!((m.transmit - original.transmit).abs() < 1e-5);
        assert!((m.ior - original.ior).abs() < 1e-5);
        assert!((m.shininess - original.shininess).abs() < 1e-4);
        assert_eq!(m.vision, m.diffuse);
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn read_obj_without_materials_gets_default_grey() {
    let dir = temp_dir("plain");
    let path = dir.join("quad.obj");
    std::fs::write(&path, "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n").unwrap();
    let (tris, materials) = read_obj(&path, 5).unwrap();
    assert_eq!(tris.len(), 2);
    assert!(tris.iter().all(|t| t.material == 5));
    assert_eq!(materials.len(), 1);

    // A missing MTL is not an error either.
    std::fs::write(
        &path,
        "mtllib nowhere.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nusemtl red\nf 1 2 3\n",
    )
    .unwrap();
    let (tris, materials) = read_obj(&path, 0).unwrap();
    assert_eq!((tris.len(), tris[0].material, materials.len()), (1, 0, 1));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn read_obj_reports_bad_files() {
    let dir = temp_dir("bad");
    let missing = dir.join("missing.obj");
    let err = read_obj(&missing, 0).unwrap_err().to_string();
    assert!(err.contains("missing.obj"), "{err}");

    let bad = dir.join("bad.obj");
    for text in [
        "v 0 0 0\nf 1 2 3\n",
        "v 0 0 x\nf 1 1 1\n",
        "v inf 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
        "v 0 0 0\nf 1 2 -7\n",
    ] {
        std::fs::write(&bad, text).unwrap();
        let err = read_obj(&bad, 0).unwrap_err().to_string();
        assert!(err.contains("bad.obj"), "{err}");
    }

    // OBJ errors are located: file:line:column, the line and a caret.
    std::fs::write(&bad, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 -7\n").unwrap();
    let err = read_obj(&bad, 0).unwrap_err().to_string();
    assert!(
        err.ends_with(":4:7: vertex -7 does not exist (3 vertices so far)\n  f 1 2 -7\n        ^"),
        "{err}"
    );

    // A colour with two components made tobj panic; it is a located error
    // in the MTL file now.
    std::fs::write(dir.join("bad.mtl"), "newmtl a\nKd 1 0\n").unwrap();
    std::fs::write(
        &bad,
        "mtllib bad.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl a\nf 1 2 3\n",
    )
    .unwrap();
    let err = read_obj(&bad, 0).unwrap_err().to_string();
    assert!(
        err.contains("bad.mtl:2:7: `Kd` takes 1 or 3 numbers"),
        "{err}"
    );
    assert!(err.ends_with("  Kd 1 0\n        ^"), "{err}");

    // A folder or a device is not a mesh.
    let err = read_obj(&dir, 0).unwrap_err().to_string();
    assert!(err.contains("is a folder"), "{err}");
    let err = read_obj(Path::new("/dev/zero"), 0).unwrap_err().to_string();
    assert!(err.contains("not a regular file"), "{err}");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn mtl_names_are_one_unique_word() {
    let mut scene = small_scene();
    scene.materials[0].name = "a b".into();
    scene.materials[1].name = "a_b".into();
    scene.materials[2].name = String::new();
    // A triangle naming a material the scene lacks.
    scene.geometries[1].shapes[0].material = 7;
    let dir = temp_dir("names");
    let path = dir.join("f.obj");
    write_obj(&scene, &path).unwrap();
    let mtl = std::fs::read_to_string(dir.join("f.mtl")).unwrap();
    let names: Vec<&str> = mtl
        .lines()
        .filter_map(|l| l.strip_prefix("newmtl "))
        .collect();
    assert_eq!(names, ["a_b", "a_b_1", "material_2", "missing_7"]);
    assert!(mtl.contains("illum 7"), "glass is transparent: {mtl}");
    let (tris, materials) = read_obj(&path, 0).unwrap();
    assert_eq!(tris.len(), expand(&scene).len());
    assert_eq!(materials.len(), 4);

    // An OBJ named *.mtl would be overwritten by its own materials.
    assert!(write_obj(&scene, &dir.join("g.mtl")).is_err());
    std::fs::remove_dir_all(&dir).unwrap();
}
