//! Frame output and procedural textures (DESIGN §4–5): EXR/PNG round trips,
//! byte-identical rewrites, chunk order, and the texture functions' ranges.

use std::io;
use std::path::PathBuf;

use glam::{Vec3, Vec3A};
use lmfilm::render::output::*;
use lmfilm::render::shade::texture::*;

/// A fresh directory per test under cargo's scratch space for integration tests.
fn scratch(name: &str) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR"))
        .join("render_output")
        .join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A gradient with every AOV set, including the "no hit" sentinels and
/// values that only a bit-exact path keeps (-0, subnormal, NaN).
/// 37 rows: several 16-line ZIP chunks, the last one partial.
fn gradient(width: u32, height: u32) -> Image {
    let mut img = Image::new(width, height);
    for y in 0..height {
        for x in 0..width {
            let i = (y * width + x) as usize;
            let (fx, fy) = (x as f32 / width as f32, y as f32 / height as f32);
            img.rgba[i] = [fx, fy, 1.0 - fx * fy, 1.0];
            img.normal[i] = Vec3::new(fx - 0.5, 1.0, fy - 0.5).normalize().to_array();
            if (x + y) % 7 == 0 {
                // Background: the documented "no hit" values.
                img.depth[i] = f32::INFINITY;
                img.normal[i] = [0.0; 3];
                img.object[i] = u32::MAX;
            } else {
                img.depth[i] = 1.0 + x as f32 * 0.37 + y as f32 * 1.0e3;
                img.object[i] = x * 1_000_003 + y;
            }
        }
    }
    if img.rgba.len() > 2 {
        img.rgba[1] = [-0.0, f32::MIN_POSITIVE / 4.0, 1.0e30, 0.5];
        img.depth[2] = f32::NAN;
    }
    img
}

fn assert_bit_identical(a: &Image, b: &Image) {
    assert_eq!((a.width, a.height), (b.width, b.height));
    let bits = |v: &[f32]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(a.rgba.as_flattened()), bits(b.rgba.as_flattened()));
    assert_eq!(bits(&a.depth), bits(&b.depth));
    assert_eq!(bits(a.normal.as_flattened()), bits(b.normal.as_flattened()));
    assert_eq!(a.object, b.object);
}

#[test]
fn exr_round_trip_is_bit_exact() {
    let dir = scratch("exr_round_trip");
    let img = gradient(16, 37);
    let path = dir.join("frame.0000.exr");
    write_exr(&img, &path).unwrap();
    let back = read_exr_layers(&path).unwrap();
    assert_bit_identical(&img, &back);
}

#[test]
fn exr_single_pixel_and_odd_sizes_round_trip() {
    let dir = scratch("exr_odd_sizes");
    for (w, h) in [(1, 1), (1, 33), (33, 1), (3, 17)] {
        let img = gradient(w, h);
        let path = dir.join(format!("f{w}x{h}.exr"));
        write_exr(&img, &path).unwrap();
        assert_bit_identical(&img, &read_exr_layers(&path).unwrap());
    }
}

/// Determinism across runs: the writer is sequential, so the same image
/// must give the same bytes. (Byte identity across `RAYON_NUM_THREADS`
/// cannot be tested in-process, since rayon's global pool is fixed once;
/// `exr_chunks_are_in_increasing_line_order` checks the property that
/// guarantees it.)
#[test]
fn exr_and_png_writes_are_byte_identical() {
    let dir = scratch("byte_identical");
    let img = gradient(16, 37);
    for ext in ["exr", "png"] {
        let (a, b) = (dir.join(format!("a.{ext}")), dir.join(format!("b.{ext}")));
        write(&img, &a).unwrap();
        write(&img, &b).unwrap();
        let (a, b) = (std::fs::read(a).unwrap(), std::fs::read(b).unwrap());
        assert!(!a.is_empty());
        assert_eq!(a, b, "{ext} bytes differ between two writes");
    }
    assert_eq!(encode_exr(&img).unwrap(), encode_exr(&img).unwrap());
    assert_eq!(encode_png(&img).unwrap(), encode_png(&img).unwrap());
}

/// Parses the single-part scan-line EXR layout: header attributes, then the
/// chunk offset table, then chunks that each start with their first line's y.
#[test]
fn exr_chunks_are_in_increasing_line_order() {
    let img = gradient(16, 37);
    let bytes = encode_exr(&img).unwrap();
    assert_eq!(&bytes[..4], &[0x76, 0x2f, 0x31, 0x01], "EXR magic");
    let cstr = |at: &mut usize| {
        let end = *at + bytes[*at..].iter().position(|&b| b == 0).unwrap();
        let s = String::from_utf8(bytes[*at..end].to_vec()).unwrap();
        *at = end + 1;
        s
    };
    let le32 = |at: usize| i32::from_le_bytes(bytes[at..at + 4].try_into().unwrap());
    let mut at = 8;
    let (mut line_order, mut compression, mut channels) = (None, None, Vec::new());
    loop {
        let name = cstr(&mut at);
        if name.is_empty() {
            break;
        }
        let _ty = cstr(&mut at);
        let size = le32(at) as usize;
        at += 4;
        let value = &bytes[at..at + size];
        match name.as_str() {
            "lineOrder" => line_order = Some(value[0]),
            "compression" => compression = Some(value[0]),
            "channels" => {
                let mut c = at;
                while bytes[c] != 0 {
                    let ch = cstr(&mut c);
                    let pixel_type = le32(c);
                    channels.push((ch, pixel_type));
                    c += 16;
                }
            }
            _ => {}
        }
        at += size;
    }
    assert_eq!(line_order, Some(0), "INCREASING_Y");
    assert_eq!(compression, Some(3), "ZIP_COMPRESSION (16 lines)");
    let expect = [
        ("A", 2),
        ("B", 2),
        ("G", 2),
        ("N.X", 2),
        ("N.Y", 2),
        ("N.Z", 2),
        ("R", 2),
        ("Z", 2),
        ("id", 0),
    ];
    let got: Vec<(&str, i32)> = channels.iter().map(|(n, t)| (n.as_str(), *t)).collect();
    assert_eq!(got, expect, "channel names and types (0 = UINT, 2 = FLOAT)");

    let chunks = 37_usize.div_ceil(16);
    let offsets: Vec<u64> = (0..chunks)
        .map(|k| u64::from_le_bytes(bytes[at + 8 * k..at + 8 * k + 8].try_into().unwrap()))
        .collect();
    assert_eq!(
        offsets[0] as usize,
        at + 8 * chunks,
        "chunks follow the table"
    );
    for (k, pair) in offsets.windows(2).enumerate() {
        assert!(
            pair[0] < pair[1],
            "chunk {k} is stored after chunk {}",
            k + 1
        );
    }
    for (k, &off) in offsets.iter().enumerate() {
        assert_eq!(
            le32(off as usize),
            16 * k as i32,
            "chunk {k} starts at its line"
        );
    }
}

#[test]
fn png_round_trip_gives_srgb8() {
    let dir = scratch("png_round_trip");
    let mut img = gradient(16, 37);
    // Alpha is coverage only: the colour is written as seen.
    img.rgba[5] = [0.25, 0.1, 0.0, 0.5];
    img.rgba[6] = [0.6, 0.7, 0.9, 0.0];
    let path = dir.join("frame.0000.png");
    write_png(&img, &path).unwrap();
    let decoded = image::open(&path).unwrap();
    assert_eq!(decoded.color(), image::ColorType::Rgb8);
    let decoded = decoded.into_rgb8();
    assert_eq!(decoded.dimensions(), (16, 37));
    for (i, (px, &[r, g, b, _])) in decoded.pixels().zip(&img.rgba).enumerate() {
        assert_eq!(px.0, [srgb8(r), srgb8(g), srgb8(b)], "pixel {i}");
    }
    // Pixel 1 holds -0, a subnormal and 1e30: clamped, not wrapped.
    assert_eq!(decoded.get_pixel(1, 0).0, [0, 0, 255]);
}

#[test]
fn srgb8_matches_the_standard() {
    assert_eq!(srgb8(0.0), 0);
    assert_eq!(srgb8(1.0), 255);
    assert_eq!(srgb8(0.5), 188);
    assert_eq!(srgb8(-1.0), 0);
    assert_eq!(srgb8(7.0), 255);
    assert_eq!(srgb8(f32::NAN), 0);
    assert_eq!(srgb8(f32::INFINITY), 255);
    // Linear segment: 12.92 · 0.001 · 255 = 3.29.
    assert_eq!(srgb8(0.001), 3);
    let mut last = 0;
    for i in 0..=1000 {
        let v = srgb8(i as f32 / 1000.0);
        assert!(v >= last, "monotonic");
        last = v;
    }
}

#[test]
fn write_picks_format_by_extension() {
    let dir = scratch("by_extension");
    let img = gradient(4, 3);
    let exr = dir.join("a.EXR");
    let png = dir.join("a.Png");
    write(&img, &exr).unwrap();
    write(&img, &png).unwrap();
    assert_eq!(
        &std::fs::read(&exr).unwrap()[..4],
        &[0x76, 0x2f, 0x31, 0x01]
    );
    assert_eq!(&std::fs::read(&png).unwrap()[..8], b"\x89PNG\r\n\x1a\n");
    assert_bit_identical(&img, &read_exr_layers(&exr).unwrap());

    for bad in ["a.jpg", "noext"] {
        let err = write(&img, &dir.join(bad)).unwrap_err();
        assert_eq!(err.kind(), io::ErrorKind::InvalidInput);
        let msg = err.to_string();
        assert!(msg.contains(".png") && msg.contains(".exr"), "{msg}");
        assert!(!dir.join(bad).exists());
    }
}

/// 0×0 (and any empty) images are rejected with InvalidInput, no file left.
#[test]
fn empty_and_inconsistent_images_are_errors_not_panics() {
    let dir = scratch("empty");
    for (w, h) in [(0, 0), (0, 5), (5, 0)] {
        let img = Image::new(w, h);
        for ext in ["exr", "png"] {
            let path = dir.join(format!("e{w}x{h}.{ext}"));
            let err = write(&img, &path).unwrap_err();
            assert_eq!(err.kind(), io::ErrorKind::InvalidInput, "{err}");
            assert!(!path.exists());
        }
    }
    let mut img = Image::new(3, 3);
    img.depth.pop();
    let err = write_exr(&img, &dir.join("short.exr")).unwrap_err();
    assert_eq!(err.kind(), io::ErrorKind::InvalidInput);
    assert!(err.to_string().contains("depth"), "{err}");
}

#[test]
fn reading_a_missing_or_bad_file_is_an_error() {
    let dir = scratch("read_errors");
    assert!(read_exr_layers(&dir.join("missing.exr")).is_err());
    let junk = dir.join("junk.exr");
    std::fs::write(&junk, b"not an exr").unwrap();
    assert!(read_exr_layers(&junk).is_err());
}

/// Points on an irregular grid, negative coordinates included.
fn sample_points() -> impl Iterator<Item = Vec3A> {
    (0..20_000).map(|i| {
        let t = i as f32;
        Vec3A::new(
            (t * 0.137).sin() * 40.0 + t * 0.013,
            (t * 0.071).cos() * 300.0 - 7.3,
            t * 0.0731 - 600.0,
        )
    })
}

#[test]
fn noise_is_bounded_deterministic_and_varied() {
    let (mut min, mut max, mut sum, mut sum2) = (f32::MAX, f32::MIN, 0.0f64, 0.0f64);
    let mut count = 0;
    for p in sample_points() {
        let n = noise(p);
        assert!((-1.0..=1.0).contains(&n), "noise({p}) = {n}");
        assert_eq!(n.to_bits(), noise(p).to_bits(), "deterministic");
        min = min.min(n);
        max = max.max(n);
        sum += n as f64;
        sum2 += (n as f64) * (n as f64);
        count += 1;
    }
    let mean = sum / count as f64;
    let var = sum2 / count as f64 - mean * mean;
    assert!(max - min > 1.0, "range {min}..{max}");
    assert!(var > 0.01, "variance {var}");
    assert!(mean.abs() < 0.05, "mean {mean}");
    // Lattice points are zeros of gradient noise.
    assert_eq!(noise(Vec3A::new(3.0, -4.0, 5.0)), 0.0);
    // Non-finite input gives 0, not NaN.
    assert_eq!(noise(Vec3A::new(f32::NAN, 0.5, 0.5)), 0.0);
    assert_eq!(noise(Vec3A::splat(f32::INFINITY)), 0.0);
    // Fixed table: values of Perlin's reference algorithm (in f64), so
    // textures never drift between builds.
    assert!((noise(Vec3A::new(0.5, 0.25, 0.75)) - -0.409_878_73).abs() < 1.0e-6);
    assert!((noise(Vec3A::new(-12.3, 4.56, 78.9)) - 0.310_622_53).abs() < 2.0e-5);
}

#[test]
fn noise_is_continuous() {
    let step = 1.0e-3;
    for p in sample_points().take(5_000) {
        for d in [Vec3A::X, Vec3A::Y, Vec3A::Z, Vec3A::ONE.normalize()] {
            let diff = (noise(p + d * step) - noise(p)).abs();
            // The gradient of improved noise is bounded by a few units.
            assert!(diff < 0.02, "jump {diff} at {p}");
        }
    }
    // Across a lattice cell boundary too.
    let a = noise(Vec3A::new(1.0 - 1.0e-4, 0.3, 0.6));
    let b = noise(Vec3A::new(1.0 + 1.0e-4, 0.3, 0.6));
    assert!((a - b).abs() < 0.01);
}

#[test]
fn turbulence_marble_and_cloud_are_in_range() {
    for p in sample_points().take(5_000) {
        let t = turbulence(p, 6);
        assert!((0.0..2.0).contains(&t), "turbulence {t}");
        let m = marble(p);
        assert!((0.0..=1.0).contains(&m), "marble {m}");
        let c = cloud(p);
        assert!((0.0..=1.0).contains(&c), "cloud {c}");
    }
    let p = Vec3A::new(0.3, 0.6, 0.9);
    assert_eq!(turbulence(p, 0), 0.0);
    assert_eq!(turbulence(p, 1), noise(p).abs());
    // Capped octaves: a huge count neither hangs nor changes the value.
    assert_eq!(turbulence(p, u32::MAX), turbulence(p, MAX_OCTAVES));
    assert!((0.0..=1.0).contains(&marble(Vec3A::splat(f32::NAN))));
    // Marble is not constant.
    let ms: Vec<f32> = sample_points().take(500).map(marble).collect();
    let spread =
        ms.iter().cloned().fold(f32::MIN, f32::max) - ms.iter().cloned().fold(f32::MAX, f32::min);
    assert!(spread > 0.5, "marble spread {spread}");
}

#[test]
fn bump_gives_unit_normals_near_n() {
    let n = Vec3A::new(0.2, 1.0, -0.3);
    let unit = n.normalize();
    for p in sample_points().take(2_000) {
        let b = bump(p, n, 0.01);
        assert!((b.length() - 1.0).abs() < 1.0e-5, "length {}", b.length());
        assert!(
            b.dot(unit) > 0.999,
            "small scale tilts little: {}",
            b.dot(unit)
        );
        let strong = bump(p, n, 1.0);
        assert!((strong.length() - 1.0).abs() < 1.0e-5);
        assert!(
            (bump(p, n, 0.0) - unit).length() < 1.0e-6,
            "scale 0 is n itself"
        );
    }
    // It does tilt somewhere.
    assert!(sample_points()
        .take(100)
        .any(|p| bump(p, n, 0.5).dot(unit) < 0.99));
    // Degenerate normals give zero, not NaN.
    assert_eq!(bump(Vec3A::ONE, Vec3A::ZERO, 1.0), Vec3A::ZERO);
}

#[test]
fn sky_blends_zenith_and_horizon_with_faint_clouds() {
    let zenith = Vec3::new(0.1, 0.3, 0.8);
    let horizon = Vec3::new(0.7, 0.8, 0.9);
    // At and below the horizon: exactly the horizon colour (clouds fade out).
    assert_eq!(sky(Vec3A::X, zenith, horizon), horizon);
    assert_eq!(sky(Vec3A::new(0.3, -1.0, 0.2), zenith, horizon), horizon);
    assert_eq!(sky(Vec3A::ZERO, zenith, horizon), horizon);
    let mut cloudy = 0;
    for p in sample_points().take(2_000) {
        let dir = Vec3A::new(p.x, p.y.abs() + 1.0, p.z);
        let d = dir.normalize();
        let c = sky(dir, zenith, horizon);
        let scaled = sky(dir * 3.0, zenith, horizon);
        assert!(
            (c - scaled).abs().max_element() < 1.0e-5,
            "only the direction counts"
        );
        let base = horizon.lerp(zenith, d.y);
        // Clouds only pull toward white, at most halfway.
        for k in 0..3 {
            assert!(c[k] >= base[k] - 1.0e-6 && c[k] <= base[k] + 0.5 * (1.0 - base[k]) + 1.0e-6);
        }
        if (c - base).length() > 1.0e-3 {
            cloudy += 1;
        }
    }
    assert!(
        cloudy > 0 && cloudy < 2_000,
        "some but not all directions are cloudy: {cloudy}"
    );
}
