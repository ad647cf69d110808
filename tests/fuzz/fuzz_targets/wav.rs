//! A WAV sound of the library.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let _ = lmfilm::sound::wav::decode(data);
});
