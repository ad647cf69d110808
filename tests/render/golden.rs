//! Golden images: every shape and material rendered and compared by hash
//! of the exact pixel bits (colour, depth, object id).
//!
//! After an intended change of the renderer's output, look at the new
//! images (`lmfilm still scenes/examples/gallery.lm -o gallery.png`), then
//! re-bless:  `LMFILM_BLESS=1 cargo test --test render golden::`
//! which rewrites tests/golden/render.txt; commit it with the change.

use crate::common::*;
use lmfilm::lsys::NoSensors;
use lmfilm::render::{render, Image, Settings};

fn fnv(img: &Image) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    let mut eat = |b: u32| {
        for byte in b.to_le_bytes() {
            h ^= u64::from(byte);
            h = h.wrapping_mul(0x0100_0000_01b3);
        }
    };
    for (i, p) in img.rgba.iter().enumerate() {
        p.iter().for_each(|v| eat(v.to_bits()));
        eat(img.depth[i].to_bits());
        eat(img.object[i]);
    }
    h
}

fn image(file: &str, time: f64, settings: Settings) -> Image {
    let mut a = load(file);
    a.advance_to(a.frame_at(time), &mut NoSensors).unwrap();
    let (s, _) = scene(&mut a);
    let mut st = settings;
    st.frame = a.frame;
    render(s.clone(), &st)
}

#[test]
fn golden_images() {
    let mut gallery = Settings::final_quality(160, 90);
    gallery.spp = 4;
    let path = Settings {
        integrator: lmfilm::render::Integrator::Path,
        max_depth: 3,
        ..gallery
    };
    let denoised = Settings {
        denoise: true,
        ..path
    };
    let cases = [
        ("gallery_final", image("gallery.lm", 0.0, gallery)),
        ("gallery_path", image("gallery.lm", 0.0, path)),
        ("gallery_path_denoised", image("gallery.lm", 0.0, denoised)),
        (
            "gallery_preview",
            image("gallery.lm", 0.0, Settings::preview(160, 90)),
        ),
        (
            "growing_tree",
            image(
                "growing_tree_drawn.lm",
                1.5,
                Settings::final_quality(64, 48),
            ),
        ),
        (
            "cours_tree3",
            image("cours_tree3.lm", 3.0, Settings::preview(96, 72)),
        ),
    ];
    let got: String = cases
        .iter()
        .map(|(n, img)| format!("{n} {:016x}\n", fnv(img)))
        .collect();
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/golden/render.txt");
    if std::env::var_os("LMFILM_BLESS").is_some() {
        std::fs::write(path, &got).unwrap();
        return;
    }
    let want = std::fs::read_to_string(path).unwrap_or_default();
    assert_eq!(
        got, want,
        "rendered images changed; if intended, re-bless (see the top of this file)"
    );
    // The gallery is not empty: most pixels see the ground or the sky.
    assert!(cases[0].1.rgba.iter().all(|p| p[0] + p[1] + p[2] > 0.0));
}
