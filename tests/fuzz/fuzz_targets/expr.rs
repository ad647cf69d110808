//! An expression in every place a scene puts one (an age, a parameter, a
//! growth function, a condition), with every Constants letter defined,
//! compiled and evaluated over two steps; postfix, or infix after `=`.
#![no_main]

use libfuzzer_sys::fuzz_target;
use lmfilm::lsys::{Animation, NoSensors, Source};

fuzz_target!(|data: &[u8]| {
    let Ok(expr) = std::str::from_utf8(data) else {
        return;
    };
    // A group ends at `)` or a line end: the fuzzer's text stays inside
    // (an infix group, `= …`, nests parentheses).
    if expr.contains('\n') || (!expr.starts_with('=') && expr.contains([')', '('])) {
        return;
    }
    let constants: String = ('a'..='s')
        .map(|c| format!("{c} 1 2\n"))
        .chain(('A'..='D').map(|c| format!("{c} 1 2\n")))
        .chain(('E'..='S').map(|c| format!("{c} 1 2 3\n")))
        .collect();
    let text = format!(
        "Camera_AnimationParameters\nt_final_interval 3 1\nSplines\n\
         time_spline 0 2 1 1 0 0 1 1 1e30 1e30\nConstants\n{constants}Axiom\n\
         A ({expr}) ({expr}) () () ({expr})\nProductions\nA (1) [({expr})>]\n\
         1 B ({expr}) EndProb\nEnd\nEndProductions\n"
    );
    if let Ok(mut anim) = Animation::from_sources(&[Source::new("e.lm", text)], &mut NoSensors) {
        let _ = anim.advance_to(2, &mut NoSensors);
    }
});
