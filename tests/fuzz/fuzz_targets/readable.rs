//! A readable definition file (`.lmr`): read as UTF-8, spelt in the
//! classic form and parsed; and any classic file that parses, spelt
//! readable, must parse again.
#![no_main]

use libfuzzer_sys::fuzz_target;
use lmfilm::lsys::readable_writer::to_readable;
use lmfilm::lsys::{parse, Source};

fuzz_target!(|data: &[u8]| {
    if let Ok(src) = Source::from_bytes("fuzz.lmr", data.to_vec()) {
        let _ = parse(&src);
    }
    if let Ok(src) = Source::from_bytes("fuzz.lm", data.to_vec()) {
        if parse(&src).is_ok() {
            if let Ok(text) = to_readable(&src) {
                if let Err(e) = parse(&Source::new("fuzz.lmr", text.as_str())) {
                    panic!("the readable spelling does not parse: {e}\n{text}");
                }
            }
        }
    }
});
