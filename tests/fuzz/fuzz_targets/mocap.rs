//! A Biovision BVH motion-capture file, and its pose at a few frames.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if let Ok(text) = std::str::from_utf8(data) {
        if let Ok(m) = lmfilm::scene::mocap::Mocap::parse(text) {
            for f in [0, 1, m.frame_count()] {
                let _ = m.pose(f);
            }
            let _ = m.frame_at(1.0);
        }
    }
});
