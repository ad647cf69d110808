//! An MTL material library.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let _ = lmfilm::scene::mtl::parse(data);
});
