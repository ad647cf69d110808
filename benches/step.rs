//! Criterion benchmarks of the step function S (issue targets: ≥ 20 M
//! symbols/s per core on a 1,000,000-symbol context-free word; a timed
//! tree of 1,000,000 symbols derived in under 1 s).

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use lmfilm::lsys::{Animation, NoSensors, Source};

const N: usize = 1_000_000;

fn animation(text: String) -> Animation {
    Animation::from_sources(&[Source::new("bench.lm", text)], &mut NoSensors).unwrap()
}

/// A word of N symbols where every symbol is rewritten at every step
/// (A → B, B → A), or where none is due yet (maximal age 1000).
fn flat(max_age: u32) -> Animation {
    animation(format!(
        "Camera_AnimationParameters\nt_final_interval 1e9 1\nAxiom\n{}\nProductions\n\
         A ({max_age})\n1.0 B EndProb\nEnd\nB ({max_age})\n1.0 A EndProb\nEnd\nEndProductions\n",
        "A".repeat(N)
    ))
}

/// A bracketed word of ~N symbols where every F and A is rewritten at
/// every step through a condition, a left context and parametric
/// expressions: F(x) → F(1.01x), F < A(x) : x > 0 → A(x/2 + 1). The word
/// keeps its length, so every iteration does the same work.
fn bracketed() -> Animation {
    let unit = "F () (1) [ + () () () () (25) A () (1) ] ";
    animation(format!(
        "Camera_AnimationParameters\nt_final_interval 1e9 1\nAxiom\n{}\nProductions\n\
         A (1) [(x)>] (F) ()\n1.0 A () (x2/1+) EndProb\nEnd\n\
         F (1)\n1.0 F () (x1.01*) EndProb\nEnd\nEndProductions\n",
        unit.repeat(N / 6)
    ))
}

fn step(c: &mut Criterion) {
    let mut g = c.benchmark_group("step");
    g.sample_size(20);
    for (name, mut a) in [
        ("rewrite_all", flat(1)),
        ("age_only", flat(1000)),
        ("bracketed_parametric", bracketed()),
    ] {
        let len = a.systems[0].word().len() as u64;
        g.throughput(Throughput::Elements(len));
        g.bench_function(BenchmarkId::new(name, len), |b| {
            b.iter(|| a.step(&mut NoSensors))
        });
    }
    g.finish();
}

/// Code 6.2.1 derived from its axiom to the first frame whose word has at
/// least 1,000,000 symbols (T = 10.96 s, 275 steps of Δt = 0.04).
fn timed_tree(c: &mut Criterion) {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/scenes/examples/cours_tree3.lm"
    );
    let text = std::fs::read_to_string(path).unwrap();
    let mut probe = animation(text.clone());
    while probe.systems[0].word().len() < N {
        probe.step(&mut NoSensors).unwrap();
    }
    let frames = probe.frame;
    let mut g = c.benchmark_group("derive");
    g.sample_size(10);
    g.bench_function(
        BenchmarkId::new(
            "cours_tree3",
            format!("{frames}_frames_{}_symbols", probe.systems[0].word().len()),
        ),
        |b| {
            b.iter(|| {
                let mut a = animation(text.clone());
                a.advance_to(frames, &mut NoSensors).unwrap();
                a.systems[0].word().len()
            })
        },
    );
    g.finish();
}

criterion_group!(benches, step, timed_tree);
criterion_main!(benches);
