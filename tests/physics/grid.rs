//! Short-range fields on the grid (issue 7, beyond 8.1.4): the grid sum
//! equals the all-pairs sum restricted to r < cutoff bit for bit, for any
//! thread count, and a particle out of every reach feels only its g.

use glam::DVec3;
use lmfilm::lsys::{Animation, NoSensors, Source};
use lmfilm::physics::{Mode, Particle, Physics};

/// Seeded uniform numbers in [0, 1) (splitmix64).
struct Rng(u64);

impl Rng {
    fn unit(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }

    fn vec(&mut self, scale: f64) -> DVec3 {
        DVec3::new(self.unit(), self.unit(), self.unit()) * scale
    }
}

/// One particle declaration: a repulsive field (x − X)(R − r) vanishing at
/// the cutoff R, or (R = 0) a weak unbounded attraction, and damping −3v.
fn particle(reach: f64) -> String {
    let field = if reach > 0.0 {
        let f = |a: &str, b: &str| format!("({a} {b} - {reach} r - *)");
        format!("{} {} {}", f("x", "X"), f("y", "Y"), f("z", "Z"))
    } else {
        "(X x - 0.01 *) (Y y - 0.01 *) (Z z - 0.01 *)".to_string()
    };
    format!(
        "e () (10) ({reach}) () {field} e () (11) () () (u 3 * _) (v 3 * _) (w 3 * _) \
         C () () (1) () (0) (0) (0) "
    )
}

/// A table of particles with the given cutoffs (0: unbounded) started at
/// `at` with velocities `vel`; Δt = 0.04 with 4 RK4 sub-steps.
fn physics(reach: &[f64], at: &[DVec3], vel: &[DVec3]) -> Physics {
    let axiom: String = reach.iter().map(|&r| particle(r)).collect();
    let text = format!(
        "Camera_AnimationParameters\nnbrCalcStep_seed 4 1\nt_final_interval 100 0.04\n\n\
         Axiom\n{axiom}\n\nProductions\nEndProductions\n"
    );
    let anim = Animation::from_sources(&[Source::new("grid.lm", text)], &mut NoSensors).unwrap();
    let mut ph = Physics::new(&anim);
    ph.register(&anim).unwrap();
    let ids = anim.systems[0].word().iter().filter(|s| s.ch == b'C');
    for (k, s) in ids.enumerate() {
        assert!(ph.start(s.id, at[k], 1.0, vel[k]));
    }
    ph
}

/// 300 particles in a cube of density ~1: cutoffs 1, 1.5 and 2, one in
/// five unbounded; every seventh placed (acts, does not move).
fn cloud(seed: u64) -> Physics {
    let n = 300;
    let mut rng = Rng(seed);
    let reach: Vec<f64> = (0..n).map(|k| [0.0, 1.0, 1.5, 2.0, 1.5][k % 5]).collect();
    let at: Vec<DVec3> = (0..n).map(|_| rng.vec(6.7)).collect();
    let vel: Vec<DVec3> = (0..n).map(|_| rng.vec(2.0) - DVec3::ONE).collect();
    let mut ph = physics(&reach, &at, &vel);
    let ids: Vec<u64> = ph.particles().iter().map(|p| p.id).collect();
    for (k, id) in ids.into_iter().enumerate().step_by(7) {
        ph.place(id, at[k], Mode::Placed);
    }
    ph
}

/// The table after each of `frames` frames.
fn frames(mut ph: Physics, frames: usize) -> Vec<Vec<Particle>> {
    (0..frames)
        .map(|_| {
            ph.evolve(ph.time() + 0.04);
            ph.particles().to_vec()
        })
        .collect()
}

fn in_pool<T: Send>(threads: usize, f: impl FnOnce() -> T + Send) -> T {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap()
        .install(f)
}

/// Positions and velocities as bits, for exact comparisons.
fn bits(frames: &[Vec<Particle>]) -> Vec<[u64; 6]> {
    frames
        .iter()
        .flatten()
        .map(|p| {
            let [a, b, c] = p.pos.to_array().map(f64::to_bits);
            let [d, e, f] = p.vel.to_array().map(f64::to_bits);
            [a, b, c, d, e, f]
        })
        .collect()
}

#[test]
fn grid_equals_all_pairs_with_cutoff_bit_for_bit() {
    for seed in [1, 2] {
        let grid = frames(cloud(seed), 6);
        let mut all = cloud(seed);
        all.set_all_pairs(true);
        let all = frames(all, 6);
        assert_eq!(bits(&grid), bits(&all), "seed {seed}");
        // The fields did something: the particles moved off their start.
        let start = cloud(seed);
        let moved = grid[5]
            .iter()
            .zip(start.particles())
            .filter(|(a, b)| a.pos != b.pos)
            .count();
        assert!(moved > 200, "{moved}");
    }
}

#[test]
fn one_or_two_threads_give_the_same_bits() {
    let one = in_pool(1, || frames(cloud(3), 4));
    let two = in_pool(2, || frames(cloud(3), 4));
    assert_eq!(bits(&one), bits(&two));
}

#[test]
fn a_particle_out_of_every_reach_feels_only_its_g() {
    // Two particles 1 apart with cutoff 1.5 push each other; a third
    // 10 away moves exactly as it does alone.
    let reach = [1.5, 1.5, 1.5];
    let at = [DVec3::ZERO, DVec3::X, DVec3::new(0.0, 10.0, 0.0)];
    let vel = [DVec3::ZERO, DVec3::ZERO, DVec3::new(0.5, 0.0, 0.0)];
    let three = frames(physics(&reach, &at, &vel), 5);
    let alone = frames(physics(&reach[2..], &at[2..], &vel[2..]), 5);
    for (a, b) in three.iter().zip(&alone) {
        assert_eq!(a[2].pos, b[0].pos);
        assert_eq!(a[2].vel, b[0].vel);
        assert!(a[0].pos.x < 0.0 && a[1].pos.x > 1.0);
    }
    // Damping alone: v = v0 e^(−3t) up to the RK4 error (~(3h)⁵/120 a step).
    let t = 5.0 * 0.04;
    assert!((alone[4][0].vel.x - 0.5 * (-3.0f64 * t).exp()).abs() < 1e-8);
}
