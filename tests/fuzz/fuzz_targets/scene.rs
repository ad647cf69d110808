//! A definition file: read as UTF-8 (or a located error), then parsed.
#![no_main]

use libfuzzer_sys::fuzz_target;
use lmfilm::lsys::{parse, Source};

fuzz_target!(|data: &[u8]| {
    if let Ok(src) = Source::from_bytes("fuzz.lm", data.to_vec()) {
        let _ = parse(&src);
    }
});
