//! Criterion benchmark of the turtle (issue 3 target: a word of 1,000,000
//! symbols interpreted into a scene in under 0.5 s).

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use lmfilm::lsys::{Animation, NoSensors, Source};
use lmfilm::turtle::{build_scene, NoWorld, Options, Surfaces};

/// Code 6.2.1 derived to its first word of ≥ 1,000,000 symbols: capsules,
/// rotations, branches, tropism at every shape.
fn tree() -> Animation {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/scenes/examples/cours_tree3.lm"
    );
    let text = std::fs::read_to_string(path).unwrap();
    let mut a = Animation::from_sources(&[Source::new(path, text)], &mut NoSensors).unwrap();
    while a.systems[0].word().len() < 1_000_000 {
        a.step(&mut NoSensors).unwrap();
    }
    a
}

fn interpret(c: &mut Criterion) {
    let mut a = tree();
    let surfaces = Surfaces::load(&a).unwrap();
    let n = a.systems[0].word().len() as u64;
    let mut g = c.benchmark_group("interpret");
    g.sample_size(10);
    g.throughput(Throughput::Elements(n));
    g.bench_function(BenchmarkId::new("cours_tree3", n), |b| {
        let mut tables = Vec::new();
        b.iter(|| {
            build_scene(
                &mut a,
                &surfaces,
                &mut tables,
                &mut NoWorld,
                Options::default(),
            )
            .unwrap()
            .0
            .geometries[0]
                .shapes
                .len()
        })
    });
    g.finish();
}

criterion_group!(benches, interpret);
criterion_main!(benches);
