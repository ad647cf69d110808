//! The animation loop's fourth loop (2.1.1, table B1): an L-structure
//! drawn `nbr` times in a square of the x–z plane, each copy stochastically
//! rotated, translated and scaled within its ranges. Deterministic from
//! the scene seed, the L-system and the copy number.

use glam::{Affine3A, EulerRot, Quat, Vec3};

use crate::lsys::definition::RepetitionParams;
use crate::lsys::random::{self, Stream};

/// Tries per copy to find a spot at the minimal distance from the others.
const ATTEMPTS: u64 = 64;

fn between(lo: f64, hi: f64, r: f64) -> f64 {
    lo + (hi - lo) * r
}

/// The transform of every copy of L-system `lsys`.
///
/// Copies lie in the square from (start, start) to (start + side,
/// start + side); `dist` is normalised by the side length. When no spot
/// at that distance is found, the farthest of the tries is taken.
pub fn transforms(p: &RepetitionParams, seed: u64, lsys: usize) -> Vec<Affine3A> {
    let (start, side, nbr, dist) = p.start_side_nbr_dist;
    let n = nbr.clamp(1, 1_000_000) as u64;
    let min_d = dist.max(0.0) * side.abs();
    let mut spots: Vec<(f64, f64)> = Vec::with_capacity(n as usize);
    let mut out = Vec::with_capacity(n as usize);
    for k in 0..n {
        let key = random::key(seed, Stream::Repetition, lsys as u64 + (1 << 32), k);
        let mut best = (f64::NEG_INFINITY, (start, start));
        for a in 0..ATTEMPTS {
            let spot = (
                start + side * random::unit(key, 2 * a),
                start + side * random::unit(key, 2 * a + 1),
            );
            let near = spots
                .iter()
                .map(|q| ((q.0 - spot.0).powi(2) + (q.1 - spot.1).powi(2)).sqrt())
                .fold(f64::INFINITY, f64::min);
            if near > best.0 {
                best = (near, spot);
            }
            if near >= min_d || side == 0.0 {
                break;
            }
        }
        let (x, z) = best.1;
        spots.push((x, z));
        let r = |i: u64| random::unit(key, 1000 + i);
        let rot =
            [0, 1, 2].map(|i| between(p.rotate[i], p.rotate_max[i].max(p.rotate[i]), r(i as u64)));
        let tr = [0, 1, 2].map(|i| {
            between(
                p.translate[i],
                p.translate_max[i].max(p.translate[i]),
                r(3 + i as u64),
            )
        });
        let scale = between(p.scale, p.scale_max.max(p.scale), r(6));
        let q = Quat::from_euler(
            EulerRot::ZYX,
            rot[2].to_radians() as f32,
            rot[1].to_radians() as f32,
            rot[0].to_radians() as f32,
        );
        let t = Vec3::new((x + tr[0]) as f32, tr[1] as f32, (z + tr[2]) as f32);
        out.push(Affine3A::from_scale_rotation_translation(
            Vec3::splat(scale as f32),
            q,
            t,
        ));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn default_is_one_identity_copy() {
        let t = transforms(&RepetitionParams::default(), 1, 0);
        assert_eq!(t, vec![Affine3A::IDENTITY]);
    }

    #[test]
    fn copies_lie_in_their_area_apart_and_in_range() {
        let p = RepetitionParams {
            rotate: [0.0, 0.0, 0.0],
            rotate_max: [0.0, 360.0, 0.0],
            scale: 0.5,
            scale_max: 1.5,
            start_side_nbr_dist: (-50.0, 100.0, 40, 0.05),
            ..RepetitionParams::default()
        };
        let t = transforms(&p, 7, 2);
        assert_eq!(t.len(), 40);
        for (i, a) in t.iter().enumerate() {
            let pos = a.translation;
            assert!((-50.0..=50.0).contains(&pos.x) && (-50.0..=50.0).contains(&pos.z));
            let s = a.matrix3.x_axis.length();
            assert!((0.5..=1.5).contains(&s));
            for b in &t[..i] {
                assert!((b.translation - pos).length() >= 5.0 - 1e-3);
            }
        }
        assert_eq!(t, transforms(&p, 7, 2), "deterministic");
        assert_ne!(t, transforms(&p, 8, 2), "seeded");
    }
}
