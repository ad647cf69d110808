//! The detectors at work: after each RK4 sub-step, the integrated
//! particles' contact levels are read and a rising one is a collision.

use super::*;
use crate::physics::{Laws, Physics};

impl Physics {
    /// Collisions found since the last call, in time then table order.
    pub fn take_collisions(&mut self) -> Vec<Collision> {
        std::mem::take(&mut self.peaks.found)
    }

    /// Whether law `f` of a particle of L-system `lsys` calls a
    /// repelling function.
    fn law_repels(&self, lsys: usize, f: &[Option<Expr>; 3]) -> bool {
        self.defs
            .get(lsys)
            .is_some_and(|d| f.iter().any(|&e| repels(d, e)))
    }

    /// Runs the detectors of the `moving` particles at the state `y` of
    /// global time `t` (their positions and velocities, six numbers each).
    pub(in crate::physics) fn detect(&mut self, moving: &[usize], y: &[f64], t: f64) {
        let fields: Vec<usize> = (0..self.particles.len())
            .filter(|&k| {
                let q = &self.particles[k];
                q.is_placed() && q.field.is_some_and(|l| self.law_repels(q.lsys, &l.f))
            })
            .collect();
        let own: Vec<bool> = moving
            .iter()
            .map(|&i| {
                let p = &self.particles[i];
                p.own.is_some_and(|l| self.law_repels(p.lsys, &l.f))
            })
            .collect();
        if fields.is_empty() && !own.contains(&true) {
            return;
        }
        let mut pos: Vec<DVec3> = self.particles.iter().map(|p| p.at(t)).collect();
        let mut vel: Vec<DVec3> = self.particles.iter().map(|p| p.vel).collect();
        for (j, &i) in moving.iter().enumerate() {
            pos[i] = DVec3::from_slice(&y[6 * j..6 * j + 3]);
            vel[i] = DVec3::from_slice(&y[6 * j + 3..6 * j + 6]);
        }
        // One task per particle, as the forces: the same for any threads.
        let levels: Vec<Levels> = moving
            .par_iter()
            .zip(&own)
            .map(|(&i, &own)| {
                let mut laws = Laws::new(self);
                let p = &self.particles[i];
                if let (true, Some(law)) = (own, p.own) {
                    laws.own(p, law, pos[i], vel[i], t);
                }
                for &k in fields.iter().filter(|&&k| k != i) {
                    let q = &self.particles[k];
                    if let Some(law) = q.field {
                        let r = pos[i].distance(pos[k]);
                        laws.field(q, law, pos[i], pos[k], vel[k], r, t);
                    }
                }
                laws.levels
            })
            .collect();
        let n = self.particles.len();
        self.peaks.touching.resize(n, [false; 3]);
        for (&i, l) in moving.iter().zip(&levels) {
            for c in Contact::ALL {
                let (level, touching) = (l[c.index()], &mut self.peaks.touching[i][c.index()]);
                if !*touching && level >= THRESHOLD {
                    *touching = true;
                    self.peaks.found.push(Collision {
                        row: i,
                        kind: c,
                        time: t,
                        at: pos[i],
                    });
                } else if *touching && (level < REARM || level.is_nan()) {
                    *touching = false;
                }
            }
        }
    }
}
