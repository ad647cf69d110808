//! Timed benchmark of the particle system (issue 7, 8.1.4): RK4 steps per
//! second for 10,000 particles carrying short-range repulsive fields,
//! summed over the grid and over all pairs (the thesis's O(n²) loop),
//! on 2 threads. Prints its figures; target ≥ 10 grid steps/s.

use std::time::Instant;

use glam::DVec3;
use lmfilm::lsys::{Animation, NoSensors, Source};
use lmfilm::physics::Physics;

const N: usize = 10_000;
/// Cutoff in mean spacings (density 1).
const REACH: f64 = 2.0;
const DT: f64 = 0.04;

/// N particles, each with the field (x − X)·(R − r), zero beyond R, and
/// the damping g = −3v, at seeded random positions in a cube of density
/// 1; one RK4 sub-step per frame.
fn cloud(seed: u64) -> Physics {
    let one = format!(
        "e () (10) ({REACH}) () (x X - {REACH} r - *) (y Y - {REACH} r - *) (z Z - {REACH} r - *) \
         e () (11) () () (u 3 * _) (v 3 * _) (w 3 * _) C () () (1) () (0) (0) (0) "
    );
    let text = format!(
        "Camera_AnimationParameters\nnbrCalcStep_seed 1 1\nt_final_interval 1e9 {DT}\n\n\
         Axiom\n{}\n\nProductions\nEndProductions\n",
        one.repeat(N)
    );
    let anim = Animation::from_sources(&[Source::new("bench.lm", text)], &mut NoSensors).unwrap();
    let mut ph = Physics::new(&anim);
    ph.register(&anim).unwrap();
    let side = (N as f64).cbrt();
    let mut state = seed;
    let mut uniform = move || {
        // splitmix64
        state = state.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = state;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    };
    for s in anim.systems[0].word().iter().filter(|s| s.ch == b'C') {
        let at = DVec3::new(uniform(), uniform(), uniform()) * side;
        assert!(ph.start(s.id, at, 1.0, DVec3::ZERO));
    }
    ph
}

/// CPU seconds used by the process: the wall clock alone is unfair when
/// other jobs share the 2 cores.
fn cpu() -> f64 {
    let mut ts = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: `ts` is a valid, writable timespec.
    unsafe { libc::clock_gettime(libc::CLOCK_PROCESS_CPUTIME_ID, &mut ts) };
    ts.tv_sec as f64 + ts.tv_nsec as f64 * 1e-9
}

/// Wall and CPU seconds per RK4 step over `steps` steps.
fn time(ph: &mut Physics, steps: u32) -> (f64, f64) {
    let (start, cpu0) = (Instant::now(), cpu());
    for _ in 0..steps {
        ph.evolve(ph.time() + DT);
    }
    let n = f64::from(steps);
    (start.elapsed().as_secs_f64() / n, (cpu() - cpu0) / n)
}

fn report(what: &str, (wall, cpu): (f64, f64)) {
    println!(
        "physics/{what}: {:.2} RK4 steps/s ({:.1} ms/step wall, {:.1} ms/step CPU)",
        1.0 / wall,
        wall * 1e3,
        cpu * 1e3
    );
}

fn main() {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .unwrap();
    pool.install(|| {
        let mut grid = cloud(1);
        time(&mut grid, 1);
        report(
            &format!("grid n = {N}, cutoff {REACH} spacings, 2 threads, 20 steps"),
            time(&mut grid, 20),
        );
        let mut all = cloud(1);
        all.set_all_pairs(true);
        report(
            &format!("all-pairs n = {N}, same cloud, 2 threads, 1 step"),
            time(&mut all, 1),
        );
    });
}
