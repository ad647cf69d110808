//! A Biovision BVH motion-capture file, and its pose at a few frames.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if let Ok(src) = lmfilm::source::Source::from_bytes("fuzz.bvh", data.to_vec()) {
        if let Ok(m) = lmfilm::scene::mocap::Mocap::parse(&src) {
            for f in [0, 1, m.frame_count()] {
                let _ = m.pose(f);
            }
            let _ = m.frame_at(1.0);
        }
    }
});
