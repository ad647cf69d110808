//! A scene snapshot: the raw bytes, and the same bytes as a payload
//! sealed with a right header and hash, so the fuzzer reaches the decoder
//! and the validation, not only the checksum. An accepted scene renders.
#![no_main]

use libfuzzer_sys::fuzz_target;
use lmfilm::render::{render, Settings};
use lmfilm::scene::snapshot::{decode, MAGIC, VERSION};

fn fnv1a64(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3)
    })
}

fuzz_target!(|data: &[u8]| {
    let _ = decode(data);
    let mut sealed = MAGIC.to_vec();
    sealed.extend_from_slice(&VERSION.to_le_bytes());
    sealed.extend_from_slice(&(data.len() as u64).to_le_bytes());
    sealed.extend_from_slice(data);
    sealed.extend_from_slice(&fnv1a64(data).to_le_bytes());
    if let Ok(scene) = decode(&sealed) {
        let settings = Settings {
            shadows: true,
            max_depth: 1,
            ..Settings::preview(8, 6)
        };
        render(scene, &settings);
    }
});
