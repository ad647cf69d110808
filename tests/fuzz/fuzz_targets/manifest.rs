//! A film's manifest.json and derive.json.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if let Ok(text) = std::str::from_utf8(data) {
        let _ = lmfilm::production::manifest::Manifest::parse(text);
        if let Ok(r) = serde_json::from_str::<lmfilm::production::record::DeriveRecord>(text) {
            let _ = r.validate();
        }
    }
});
