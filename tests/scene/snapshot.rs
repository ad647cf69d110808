//! Scene snapshots (DESIGN §1, §5): bit-exact round trips, deterministic
//! bytes, atomic files, and a clear error, never a panic, on bad bytes.

use crate::common;

use std::path::PathBuf;

use crate::common::Rng;

use glam::{Affine3A, Quat, Vec3};
use lmfilm::scene::material::Texture;
use lmfilm::scene::snapshot::{self, SnapshotError, MAGIC, VERSION};
use lmfilm::scene::{
    Camera, Geometry, Instance, Light, LightKind, Material, Scene, Shape, ShapeKind, Triangle,
};

/// Float values that a careless format would alter: signed zero,
/// subnormals, extremes, infinities and NaNs with payloads.
fn awkward() -> Vec<f32> {
    let mut v = vec![
        -0.0,
        0.0,
        f32::from_bits(1),            // smallest subnormal
        -f32::from_bits(0x007f_ffff), // largest subnormal, negative
        f32::MIN_POSITIVE,
        f32::MAX,
        f32::MIN,
        f32::INFINITY,
        f32::NEG_INFINITY,
        f32::EPSILON,
        f32::from_bits(0x7fc0_1234), // quiet NaN with a payload
        f32::from_bits(0xffc0_0001), // negative quiet NaN with a payload
        1.0 / 3.0,
    ];
    // x87 (32-bit x86) quiets signalling NaNs when it moves them.
    if cfg!(not(target_arch = "x86")) {
        v.push(f32::from_bits(0x7f80_0001));
    }
    v
}

fn v3(a: f32, b: f32, c: f32) -> Vec3 {
    Vec3::new(a, b, c)
}

fn sample_scene() -> Scene {
    scene_with(awkward())
}

/// The sample scene with finite, moderate numbers only: one `decode`
/// accepts (it refuses NaNs, infinities and numbers beyond 1e18).
fn valid_scene() -> Scene {
    let mut s = scene_with(vec![
        0.5, -0.0, 1e-3, 2.0, 0.25, 3.0, 1.5, -2.0, 0.75, 4.0, 1.25, 0.1, 6.0,
    ]);
    s.camera.far = 1e18;
    for m in &mut s.materials {
        m.transmit = m.transmit.clamp(0.0, 1.0);
    }
    for g in &mut s.geometries {
        for sh in &mut g.shapes {
            if let ShapeKind::Trunk { length, .. } = &mut sh.kind {
                *length = length.min(1e6);
            }
        }
        for t in &mut g.triangles {
            t.material %= 3;
        }
    }
    snapshot::validate(&s).unwrap();
    s
}

fn scene_with(w: Vec<f32>) -> Scene {
    let at = |i: usize| w[i % w.len()];
    let skew = Affine3A::from_cols_array(&[
        1.0,
        0.25,
        -0.0,
        0.5,
        2.0,
        at(2),
        -1.5,
        at(10),
        3.0,
        7.0,
        -8.0,
        at(5),
    ]);
    let trs = Affine3A::from_scale_rotation_translation(
        v3(0.3, 1.7, 2.9),
        Quat::from_euler(glam::EulerRot::XYZ, 0.1, -1.2, 2.3),
        v3(-4.0, 0.0, 1e-3),
    );
    let kinds = [
        ShapeKind::Box,
        ShapeKind::Sphere,
        ShapeKind::Cylinder,
        ShapeKind::Capsule { length: at(3) },
        ShapeKind::Capsule { length: 2.5 },
        ShapeKind::Trunk {
            length: 4.0,
            r0: at(0),
            r1: at(11),
        },
        ShapeKind::Trunk {
            length: f32::MAX,
            r0: 0.5,
            r1: 0.25,
        },
    ];
    let shapes = kinds
        .iter()
        .enumerate()
        .map(|(i, &kind)| Shape {
            kind,
            transform: if i % 2 == 0 { skew } else { trs },
            material: i as u32 % 3,
            symbol: u64::MAX - i as u64,
        })
        .collect();
    let triangles = (0..4)
        .map(|i| Triangle {
            v: [
                v3(at(i), at(i + 1), at(i + 2)),
                v3(1.0, -0.0, 2.0),
                v3(at(i + 7), 0.5, at(i + 9)),
            ],
            material: i as u32,
            symbol: 1 << (i * 10),
        })
        .collect();
    let material = |name: &str, k: usize, texture| Material {
        name: name.to_string(),
        ambient: v3(at(k), 0.1, 0.2),
        diffuse: v3(0.8, at(k + 1), 0.0),
        specular: v3(1.0, 1.0, at(k + 2)),
        shininess: at(k + 3),
        reflect: 0.25,
        transmit: at(k + 4),
        ior: 1.33,
        vision: v3(at(k + 5), 0.0, 1.0),
        texture,
    };
    Scene {
        frame: 1234,
        time: 49.36,
        camera: Camera {
            eye: v3(0.0, 1.7, -10.0),
            look_at: v3(at(0), at(1), at(2)),
            twist: at(12),
            fov_y: 45.0,
            aspect: at(10),
            near: f32::MIN_POSITIVE,
            far: f32::MAX,
            width: 1920,
            height: 1080,
            lens: Default::default(),
        },
        lights: vec![
            Light {
                position: v3(10.0, 20.0, -0.0),
                color: v3(1.0, 0.9, 0.8),
                kind: LightKind::Sphere { radius: at(4) },
            },
            Light {
                position: v3(at(5), at(6), at(7)),
                color: v3(at(8), at(9), at(10)),
                kind: LightKind::Directional {
                    direction: v3(at(1), at(2), at(3)),
                },
            },
        ],
        materials: vec![
            material("plain", 0, None),
            material("marble ✓ ünïcode", 4, Some(Texture::Marble)),
            material("", 8, Some(Texture::Bump)),
        ],
        geometries: vec![
            Geometry {
                name: "tree".into(),
                shapes,
                triangles,
                resolution: 16,
            },
            Geometry {
                name: "leaf".into(),
                shapes: vec![Shape {
                    kind: ShapeKind::Sphere,
                    transform: Affine3A::IDENTITY,
                    material: 0,
                    symbol: 0,
                }],
                triangles: vec![Triangle {
                    v: [v3(0.0, 0.0, 0.0), v3(1.0, 0.0, 0.0), v3(0.0, 1.0, 0.0)],
                    material: 2,
                    symbol: 42,
                }],
                resolution: 3,
            },
            Geometry::default(),
        ],
        instances: vec![
            Instance {
                geometry: 0,
                transform: Affine3A::IDENTITY,
                object: 1,
            },
            Instance {
                geometry: 1,
                transform: trs,
                object: 2,
            },
            Instance {
                geometry: 1,
                transform: skew * trs,
                object: u32::MAX,
            },
        ],
        background: v3(at(10), -0.0, at(3)),
        sky: Default::default(),
    }
}

/// Every f32 of a scene as bits, in a fixed order, so scenes holding NaNs
/// (which defeat `PartialEq`) can still be compared exactly.
fn float_bits(s: &Scene) -> Vec<u32> {
    let mut out = Vec::new();
    let mut v = |x: Vec3| out.extend(x.to_array().map(f32::to_bits));
    let c = &s.camera;
    v(c.eye);
    v(c.look_at);
    v(v3(c.twist, c.fov_y, c.aspect));
    v(v3(c.near, c.far, 0.0));
    for l in &s.lights {
        v(l.position);
        v(l.color);
    }
    for m in &s.materials {
        v(m.ambient);
        v(m.diffuse);
        v(m.specular);
        v(v3(m.shininess, m.reflect, m.transmit));
        v(v3(m.ior, 0.0, 0.0));
        v(m.vision);
    }
    v(s.background);
    let affine = |a: &Affine3A| a.to_cols_array().map(f32::to_bits);
    let mut rest = Vec::new();
    for g in &s.geometries {
        for sh in &g.shapes {
            rest.extend(affine(&sh.transform));
            match sh.kind {
                ShapeKind::Capsule { length } => rest.push(length.to_bits()),
                ShapeKind::Trunk { length, r0, r1 } => {
                    rest.extend([length, r0, r1].map(f32::to_bits))
                }
                _ => {}
            }
        }
        for t in &g.triangles {
            for p in t.v {
                rest.extend(p.to_array().map(f32::to_bits));
            }
        }
    }
    for i in &s.instances {
        rest.extend(affine(&i.transform));
    }
    out.extend(rest);
    out
}

/// The non-float content, compared with `Debug` (floats print there too,
/// but NaNs print alike; the bits are checked by `float_bits`).
fn structure(s: &Scene) -> String {
    format!("{s:?}")
}

fn fnv1a64(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3)
    })
}

/// A snapshot around arbitrary payload bytes with a valid header and hash,
/// so the bytes reach the postcard decoder instead of the hash check.
fn seal(payload: &[u8]) -> Vec<u8> {
    let mut out = MAGIC.to_vec();
    out.extend_from_slice(&VERSION.to_le_bytes());
    out.extend_from_slice(&(payload.len() as u64).to_le_bytes());
    out.extend_from_slice(payload);
    out.extend_from_slice(&fnv1a64(payload).to_le_bytes());
    out
}

fn payload_of(bytes: &[u8]) -> &[u8] {
    &bytes[20..bytes.len() - 8]
}

fn scratch_dir(test: &str) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR"))
        .join("scene_snapshot")
        .join(test);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

#[test]
fn round_trip_is_bit_exact() {
    let scene = sample_scene();
    let bytes = snapshot::encode(&scene);
    let back = snapshot::decode_unchecked(&bytes).unwrap();
    assert_eq!(snapshot::encode(&back), bytes, "re-encoding changed bytes");
    assert_eq!(float_bits(&back), float_bits(&scene));
    assert_eq!(structure(&back), structure(&scene));
    // The awkward values really are in there.
    let bits = float_bits(&scene);
    for x in awkward() {
        assert!(bits.contains(&x.to_bits()), "{:#x} missing", x.to_bits());
    }
}

#[test]
fn round_trip_equals_without_nans() {
    let mut scene = sample_scene();
    scene.geometries.truncate(1);
    scene.geometries[0].triangles.clear();
    let clean = Scene {
        lights: vec![],
        materials: vec![],
        instances: vec![],
        background: Vec3::ZERO,
        sky: Default::default(),
        camera: Camera {
            look_at: Vec3::X,
            twist: -0.0,
            aspect: 1.5,
            ..scene.camera
        },
        geometries: vec![Geometry {
            shapes: scene.geometries[0]
                .shapes
                .iter()
                .map(|s| Shape {
                    transform: Affine3A::from_translation(v3(-0.0, 1e-40, 3.0)),
                    kind: match s.kind {
                        ShapeKind::Trunk { length, .. } => ShapeKind::Trunk {
                            length,
                            r0: -0.0,
                            r1: 1e-45,
                        },
                        k => k,
                    },
                    ..*s
                })
                .collect(),
            ..Geometry::default()
        }],
        ..scene
    };
    let back = snapshot::decode_unchecked(&snapshot::encode(&clean)).unwrap();
    assert_eq!(back, clean);
    assert_eq!(float_bits(&back), float_bits(&clean));
}

#[test]
fn encoding_is_deterministic_and_has_the_documented_layout() {
    let a = snapshot::encode(&sample_scene());
    let b = snapshot::encode(&sample_scene());
    assert_eq!(a, b);
    assert_eq!(&a[..8], b"LMSNAP\0\0");
    // Version 2: lights carry their kind (point, directional, sphere);
    // 3: the camera its lens, the scene its sky's shape.
    assert_eq!(u32::from_le_bytes(a[8..12].try_into().unwrap()), 3);
    assert_eq!(VERSION, 3);
    let len = u64::from_le_bytes(a[12..20].try_into().unwrap()) as usize;
    assert_eq!(a.len(), 20 + len + 8);
    let hash = u64::from_le_bytes(a[20 + len..].try_into().unwrap());
    assert_eq!(hash, fnv1a64(&a[20..20 + len]));
    assert_eq!(seal(payload_of(&a)), a);
}

#[test]
fn file_round_trip_and_atomic_write() {
    let dir = scratch_dir("file_round_trip");
    let path = dir.join("0007.snap");
    let scene = valid_scene();
    snapshot::write(&scene, &path).unwrap();
    let back = snapshot::read(&path).unwrap();
    assert_eq!(float_bits(&back), float_bits(&scene));
    assert_eq!(std::fs::read(&path).unwrap(), snapshot::encode(&scene));

    // Overwriting replaces the file whole, and no temporary file is left.
    let mut other = valid_scene();
    other.frame = 8;
    other.geometries.clear();
    other.instances.clear();
    snapshot::write(&other, &path).unwrap();
    assert_eq!(snapshot::read(&path).unwrap().frame, 8);
    let names: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(names, vec![std::ffi::OsString::from("0007.snap")]);
}

#[test]
fn file_errors_name_the_file() {
    let dir = scratch_dir("file_errors");
    let missing = dir.join("0001.snap");
    let e = snapshot::read(&missing).unwrap_err();
    assert!(matches!(e.kind(), SnapshotError::Io(_)), "{e:?}");
    assert_eq!(e.path(), Some(missing.as_path()));
    assert!(e.to_string().contains("0001.snap"), "{e}");
    assert!(std::error::Error::source(&e).is_some());

    let bad = dir.join("0002.snap");
    std::fs::write(&bad, b"P6\n640 480\n255\n").unwrap();
    let e = snapshot::read(&bad).unwrap_err();
    assert!(matches!(e.kind(), SnapshotError::NotASnapshot), "{e:?}");
    let msg = e.to_string();
    assert!(msg.contains("0002.snap") && msg.contains("not an lmfilm scene snapshot"));

    let cut = dir.join("0003.snap");
    let bytes = snapshot::encode(&sample_scene());
    std::fs::write(&cut, &bytes[..bytes.len() / 2]).unwrap();
    let e = snapshot::read(&cut).unwrap_err();
    assert!(matches!(e.kind(), SnapshotError::Truncated), "{e:?}");
    assert!(e.to_string().contains("0003.snap"), "{e}");

    // Writing into a missing directory fails with the path in the message
    // and leaves nothing behind.
    let nowhere = dir.join("no such dir").join("0004.snap");
    let e = snapshot::write(&sample_scene(), &nowhere).unwrap_err();
    assert_eq!(e.kind(), std::io::ErrorKind::NotFound);
    assert!(e.to_string().contains("0004.snap"), "{e}");
}

#[test]
fn bad_magic_is_not_a_snapshot() {
    let mut bytes = snapshot::encode(&sample_scene());
    for i in 0..8 {
        let mut b = bytes.clone();
        b[i] ^= 0x20;
        assert!(matches!(
            snapshot::decode(&b),
            Err(SnapshotError::NotASnapshot)
        ));
    }
    assert!(matches!(
        snapshot::decode(b"hello"),
        Err(SnapshotError::NotASnapshot)
    ));
    assert!(matches!(
        snapshot::decode(b"{\"frame\": 1}"),
        Err(SnapshotError::NotASnapshot)
    ));
    bytes[0] = b'X';
    assert!(snapshot::decode(&bytes)
        .unwrap_err()
        .to_string()
        .contains("magic"));
}

#[test]
fn other_versions_are_reported() {
    let bytes = snapshot::encode(&sample_scene());
    for found in [VERSION + 1, 0, u32::MAX] {
        let mut b = bytes.clone();
        b[8..12].copy_from_slice(&found.to_le_bytes());
        // A newer version is reported even if its layout after the version
        // field differs entirely.
        b.truncate(12 + (found as usize % 5));
        let e = snapshot::decode(&b).unwrap_err();
        match e {
            SnapshotError::Version {
                found: f,
                supported,
            } => {
                assert_eq!((f, supported), (found, VERSION));
                let msg = e.to_string();
                assert!(msg.contains(&found.to_string()), "{msg}");
                let hint = if found > VERSION { "newer" } else { "old" };
                assert!(msg.contains(hint), "{msg}");
            }
            ref other => panic!("version {found}: {other:?}"),
        }
    }
}

#[test]
fn truncations_are_truncated() {
    let bytes = snapshot::encode(&sample_scene());
    let n = bytes.len();
    for len in [0, 1, 7, 8, 11, 12, 19, 20, 21, n / 2, n - 9, n - 8, n - 1] {
        match snapshot::decode(&bytes[..len]) {
            Err(SnapshotError::Truncated) => {}
            other => panic!("truncated to {len} of {n}: {other:?}"),
        }
    }
    // A length field larger than any file, including one that overflows.
    for len in [u64::MAX, u64::MAX - 7, 1 << 40] {
        let mut b = bytes.clone();
        b[12..20].copy_from_slice(&len.to_le_bytes());
        assert!(matches!(
            snapshot::decode(&b),
            Err(SnapshotError::Truncated)
        ));
    }
}

#[test]
fn damage_is_corrupt() {
    let bytes = snapshot::encode(&sample_scene());
    let n = bytes.len();
    // A flipped bit anywhere in the payload or hash.
    for i in (20..n).step_by(7).chain([20, n - 9, n - 8, n - 1]) {
        let mut b = bytes.clone();
        b[i] ^= 0x01;
        assert!(
            matches!(snapshot::decode(&b), Err(SnapshotError::Corrupt)),
            "flip at {i}"
        );
    }
    // Extra bytes after the hash (say, two snapshots concatenated).
    let mut b = bytes.clone();
    b.extend_from_slice(&bytes);
    assert!(matches!(snapshot::decode(&b), Err(SnapshotError::Corrupt)));
    assert!(snapshot::decode(&b)
        .unwrap_err()
        .to_string()
        .contains("corrupt"));
}

#[test]
fn intact_but_foreign_payload_is_a_decode_error() {
    let bytes = snapshot::encode(&sample_scene());
    let payload = payload_of(&bytes);
    // Cut short, but hashed as if whole: postcard runs out of input.
    let e = snapshot::decode(&seal(&payload[..payload.len() / 2])).unwrap_err();
    assert!(matches!(e, SnapshotError::Decode(_)), "{e:?}");
    // A byte too many.
    let mut longer = payload.to_vec();
    longer.push(0);
    let e = snapshot::decode(&seal(&longer)).unwrap_err();
    assert!(matches!(e, SnapshotError::Decode(_)), "{e:?}");
    assert!(e.to_string().contains("unused"), "{e}");
    // Empty payload.
    assert!(matches!(
        snapshot::decode(&seal(&[])),
        Err(SnapshotError::Decode(_))
    ));
}

#[test]
fn huge_counts_in_the_payload_do_not_allocate_or_hang() {
    // frame, time, camera as in a real scene, then a light count of 2^63.
    let mut scene = sample_scene();
    scene.lights.clear();
    scene.materials.clear();
    scene.geometries.clear();
    scene.instances.clear();
    let payload = postcard::to_stdvec(&scene).unwrap();
    // The light count is the byte after frame (varint), time (8), camera.
    let camera_len = postcard::to_stdvec(&scene.camera).unwrap().len();
    let frame_len = postcard::to_stdvec(&scene.frame).unwrap().len();
    let at = frame_len + 8 + camera_len;
    assert_eq!(payload[at], 0);
    for count in [u64::MAX, 1 << 62, u32::MAX as u64, 1 << 20] {
        let mut p = payload[..at].to_vec();
        p.extend(postcard::to_stdvec(&count).unwrap());
        p.extend_from_slice(&payload[at + 1..]);
        let e = snapshot::decode(&seal(&p)).unwrap_err();
        assert!(matches!(e, SnapshotError::Decode(_)), "{e:?}");
    }
}

#[test]
fn fuzz_truncations_and_flips_never_panic() {
    let bytes = snapshot::encode(&sample_scene());
    let payload = payload_of(&bytes).to_vec();
    // Every prefix, both of the file and of the payload (resealed so the
    // decoder itself sees it).
    for len in 0..bytes.len() {
        assert!(snapshot::decode(&bytes[..len]).is_err());
    }
    for len in 0..payload.len() {
        let _ = snapshot::decode(&seal(&payload[..len]));
    }
    let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
    for round in 0..20_000 {
        let mut p = payload.clone();
        for _ in 0..1 + rng.below(4) {
            let i = rng.below(p.len());
            p[i] = match rng.below(3) {
                0 => p[i] ^ (1 << rng.below(8)),
                1 => rng.next() as u8,
                _ => 0xff,
            };
        }
        if round % 4 == 0 {
            p.truncate(rng.below(p.len() + 1));
        }
        // Sealed: reaches postcard; unsealed: stopped by the hash.
        if let Ok(s) = snapshot::decode(&seal(&p)) {
            // postcard accepts overlong varints, so the bytes may differ,
            // but whatever decodes must survive its own round trip.
            let again = snapshot::decode(&snapshot::encode(&s)).unwrap();
            assert!(float_bits(&again) == float_bits(&s));
            assert!(structure(&again) == structure(&s));
        }
        let mut raw = bytes.clone();
        let i = rng.below(raw.len());
        raw[i] ^= 1 << rng.below(8);
        assert!(snapshot::decode(&raw).is_err(), "flip at {i} accepted");
    }
    // Pure noise, with and without a valid envelope.
    for _ in 0..2_000 {
        let noise: Vec<u8> = (0..rng.below(300)).map(|_| rng.next() as u8).collect();
        let _ = snapshot::decode(&noise);
        let _ = snapshot::decode(&seal(&noise));
    }
}

/// Damage that keeps the hash right (a flipped float, an edited file)
/// must not reach the renderer: `decode` validates the scene.
#[test]
fn impossible_scenes_are_refused_with_what_is_wrong() {
    let invalid = |s: &Scene| match snapshot::decode(&snapshot::encode(s)) {
        Err(SnapshotError::Invalid(m)) => m,
        other => panic!("expected Invalid, got {other:?}"),
    };
    // The awkward sample holds NaNs and infinities.
    assert!(invalid(&sample_scene()).contains("not a finite number"));

    // Regression: gallery frame 5 with one instance's 1.0 flipped to 0.0
    // panicked in the BVH (accel.rs:58); a singular transform is refused.
    let mut s = valid_scene();
    s.instances[1].transform.matrix3.x_axis.x = 0.0;
    s.instances[1].transform.matrix3.x_axis.y = 0.0;
    s.instances[1].transform.matrix3.x_axis.z = 0.0;
    let m = invalid(&s);
    assert!(
        m.contains("instance 1") && m.contains("cannot be inverted"),
        "{m}"
    );

    let mut s = valid_scene();
    s.geometries[1].triangles[0].v[1].y = f32::INFINITY;
    assert!(invalid(&s).contains("triangle 0 of geometry 1"));

    let mut s = valid_scene();
    s.instances[0].geometry = 99;
    assert!(invalid(&s).contains("places geometry 99, but the scene has 3"));

    let mut s = valid_scene();
    s.geometries[0].shapes[0].material = 3;
    assert!(invalid(&s).contains("material 3, but the scene has 3 materials"));

    let mut s = valid_scene();
    s.camera.width = 0;
    assert!(invalid(&s).contains("width is 0"));

    let mut s = valid_scene();
    s.camera.lens.radius = -0.1;
    assert!(invalid(&s).contains("aperture radius and focus distance must be ≥ 0"));

    let mut s = valid_scene();
    s.camera.lens.focus = f32::NAN;
    assert!(invalid(&s).contains("focus distance"));

    let mut s = valid_scene();
    s.lights[0].position.x = 1e19;
    assert!(invalid(&s).contains("position of light 0"));

    // Read from a file, the error names it and says to derive again.
    let dir = scratch_dir("impossible");
    let path = dir.join("0005.snap");
    std::fs::write(&path, snapshot::encode(&s)).unwrap();
    let e = snapshot::read(&path).unwrap_err().to_string();
    assert!(
        e.contains("0005.snap") && e.contains("lmfilm derive"),
        "{e}"
    );
}

#[test]
fn a_folder_or_device_is_not_a_snapshot() {
    let dir = scratch_dir("not_a_file");
    let e = snapshot::read(&dir).unwrap_err().to_string();
    assert!(e.contains("is a folder"), "{e}");
    let e = snapshot::read(std::path::Path::new("/dev/zero"))
        .unwrap_err()
        .to_string();
    assert!(e.contains("not a regular file"), "{e}");
}

/// Regression (issue 11): a derived snapshot whose instance transform had
/// a 1.0 flipped to 0.0, its hash fixed up, made `lmfilm render` panic
/// in the BVH on the gallery (accel.rs:58), and render a wrong picture
/// here. It is an error naming the file and the fault, exit code 2.
#[test]
fn render_refuses_an_edited_snapshot_with_exit_2() {
    let dir = scratch_dir("edited");
    let scene = dir.join("one.lm");
    std::fs::write(
        &scene,
        "Camera_AnimationParameters\nt_final_interval 0 0.04\nAxiom\nF\n",
    )
    .unwrap();
    let lmfilm = |args: &[&std::ffi::OsStr]| {
        std::process::Command::new(env!("CARGO_BIN_EXE_lmfilm"))
            .args(args)
            .output()
            .unwrap()
    };
    let out = dir.join("film");
    let derive = lmfilm(&[
        "derive".as_ref(),
        scene.as_ref(),
        "-o".as_ref(),
        out.as_ref(),
    ]);
    assert!(derive.status.success(), "{derive:?}");
    let snap = out.join("scene").join("0000.snap");
    let bytes = std::fs::read(&snap).unwrap();
    let mut payload = payload_of(&bytes).to_vec();
    // The last 1.0 of the payload: the instance transform's z_axis.z
    // (the background after it is black).
    let one = 1.0f32.to_le_bytes();
    let at = payload.windows(4).rposition(|w| w == one).unwrap();
    payload[at..at + 4].copy_from_slice(&0.0f32.to_le_bytes());
    std::fs::write(&snap, seal(&payload)).unwrap();
    // The derive record's hash would catch the edit first; a record that
    // agrees with the edited bytes leaves it to the content checks.
    common::agree_with_snapshot(&out);
    let render = lmfilm(&[
        "render".as_ref(),
        out.as_ref(),
        "--preset".as_ref(),
        "preview".as_ref(),
    ]);
    let err = String::from_utf8_lossy(&render.stderr);
    assert_eq!(render.status.code(), Some(2), "{err}");
    assert!(!err.contains("panicked"), "{err}");
    assert!(
        err.contains("0000.snap")
            && err.contains("cannot be inverted")
            && err.contains("lmfilm derive"),
        "{err}"
    );
}

/// Regression (cargo-fuzz, snapshot target): a triangle vertex at
/// (1.1e27, -1.5e14, 1.9e17) among the gallery's unit-sized shapes passed
/// a bound of 1e30 and made the BVH builder panic (obvhs ploc/mod.rs:203).
/// Coordinates, placed by their instances too, stay within ±1e18.
#[test]
fn huge_coordinates_are_refused_before_the_bvh() {
    let invalid = |s: &Scene| match snapshot::decode(&snapshot::encode(s)) {
        Err(SnapshotError::Invalid(m)) => m,
        other => panic!("expected Invalid, got {other:?}"),
    };
    let mut s = valid_scene();
    s.geometries[1].triangles[0].v[2] = v3(1.143_142_7e27, -1.533_450_8e14, 1.905_503_6e17);
    assert!(invalid(&s).contains("a corner of triangle 0 of geometry 1"));

    // Each number within the bound, the placed geometry beyond it.
    let mut s = valid_scene();
    s.geometries[1].triangles[0].v[1] = v3(1e10, 0.0, 0.0);
    s.instances[1].transform = Affine3A::from_scale(Vec3::splat(1e10));
    assert!(invalid(&s).contains("a corner of instance 1 (geometry 1)"));

    // A shape's transform may scale its unit shape beyond the bound.
    let mut s = valid_scene();
    s.geometries[1].shapes[0].transform =
        Affine3A::from_scale(v3(9e17, 1.0, 1.0)) * Affine3A::from_translation(v3(0.5, 0.0, 0.0));
    let m = invalid(&s);
    assert!(m.contains("a corner of shape 0 of geometry 1"), "{m}");
}

/// Regression (cargo-fuzz, snapshot target): an instance transform with
/// an axis of 5.9e-39 has a finite determinant (-2.4e-22) and a finite
/// inverse, whose entries of 1e38 sent rays that the traversal turned
/// into a leaf index of 2^31 − 1 (accel.rs:58, the panic again).
/// An inverse beyond ±1e18 is refused like a singular one.
#[test]
fn nearly_flat_transforms_are_refused() {
    let mut s = valid_scene();
    s.instances[0].transform = Affine3A::from_cols_array(&[
        -5.293_956e-23,
        -200_382_860.0,
        -199_544_000.0,
        -199_019_710.0,
        -199_019_710.0,
        5.675_433e-39,
        5.934_869e-39,
        0.0,
        0.0,
        5.831_554e-39,
        5.785_636e-39,
        5.831_554e-39,
    ]);
    match snapshot::decode(&snapshot::encode(&s)) {
        Err(SnapshotError::Invalid(m)) => {
            assert!(m.contains("instance 0 cannot be inverted"), "{m}")
        }
        other => panic!("expected Invalid, got {other:?}"),
    }
}

/// Regression (cargo-fuzz, snapshot target): a glass material with an
/// index of refraction of 0 sent the ray inside along −n, which reached
/// `accel.rs:58`. Indices are 0.001..=10 (the MTL range), mirroring and
/// transmission fractions 0..=1.
#[test]
fn absurd_materials_are_refused() {
    let invalid = |s: &Scene| match snapshot::decode(&snapshot::encode(s)) {
        Err(SnapshotError::Invalid(m)) => m,
        other => panic!("expected Invalid, got {other:?}"),
    };
    let mut s = valid_scene();
    s.materials[0].ior = 0.0;
    assert!(invalid(&s).contains("material 0 (\"plain\"): index of refraction is 0"));
    let mut s = valid_scene();
    s.materials[1].transmit = 1.5;
    assert!(invalid(&s).contains("transmission is 1.5"));
    let mut s = valid_scene();
    s.materials[2].reflect = -0.25;
    assert!(invalid(&s).contains("reflection is -0.25"));
}
