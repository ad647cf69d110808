//! A scene with actors: loaded, then its first frames run, so that the
//! actors' commands, windows, memories, goals and the turtle's mappings
//! meet the sense and act steps. Seed it with the actor scenes
//! (docs/hostile-input.md). A panic, a hang or an abort is a finding;
//! an error is the right answer to a bad scene.
#![no_main]

use libfuzzer_sys::fuzz_target;
use lmfilm::film::Film;
use lmfilm::lsys::Source;
use lmfilm::turtle::Options;

/// Frames run per input: enough for a navigator to plan, observe and
/// start walking.
const FRAMES: usize = 6;

fuzz_target!(|data: &[u8]| {
    let Ok(src) = Source::from_bytes("fuzz.lm", data.to_vec()) else {
        return;
    };
    // Limits that keep one input well under libFuzzer's time and memory
    // budgets: small words, scenes, images, plans and memories.
    let mut opts = Options::default();
    opts.limits.symbols = 100_000;
    opts.limits.shapes = 200_000;
    opts.limits.frames = 10_000;
    opts.limits.plan_voxels = 1 << 14;
    opts.limits.memory_bytes = 256 << 20;
    let Ok(mut film) = Film::from_sources(&[src], None, opts) else {
        return;
    };
    for _ in 0..FRAMES {
        match film.next_frame() {
            Ok(Some(_)) => {}
            _ => return,
        }
    }
});
