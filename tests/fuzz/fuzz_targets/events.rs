//! A sound event log (table B7).
#![no_main]

use libfuzzer_sys::fuzz_target;
use lmfilm::lsys::Source;
use lmfilm::sound::EventsFile;

fuzz_target!(|data: &[u8]| {
    if let Ok(src) = Source::from_bytes("fuzz.events", data.to_vec()) {
        let _ = EventsFile::parse(src);
    }
});
