//! The animation loop's fourth loop (2.1.1, table B1): an L-structure
//! drawn `nbr` times in a square of the x–z plane, each copy stochastically
//! rotated, translated and scaled within its ranges. Deterministic from
//! the scene seed, the L-system and the copy number.

use glam::{Affine3A, EulerRot, Quat, Vec3};

use crate::lsys::definition::RepetitionParams;
use crate::random::{self, Stream};

/// Tries per copy to find a spot at the minimal distance from the others.
const ATTEMPTS: u64 = 64;

fn between(lo: f64, hi: f64, r: f64) -> f64 {
    lo + (hi - lo) * r
}

/// The copies placed so far, for exact nearest-distance queries: a
/// square grid over the placement area with one to two copies per cell,
/// rebuilt each time the copies double (O(n) in all), so a query looks
/// at nine cells or so instead of every copy (quadratic: 10⁵ crowded
/// copies were 3·10¹¹ distances; now 1 s). Cells keep their first two
/// copies inline, row after row, so the nine cells are a few cache lines.
struct Spots {
    all: Vec<(f64, f64)>,
    lo: (f64, f64),
    cell: f64,
    dim: usize,
    cells: Vec<Cell>,
    /// The copies past a cell's first two, one list per crowded cell.
    more: Vec<Vec<(f64, f64)>>,
}

/// The copies of one grid cell: two inline, the rest in list `more − 1`.
#[derive(Clone, Copy, Default)]
struct Cell {
    inline: [(f64, f64); 2],
    len: u32,
    more: u32,
}

impl Spots {
    /// An empty set in the square from `lo` of side `len` (> 0, finite).
    fn new(lo: (f64, f64), len: f64, capacity: usize) -> Spots {
        Spots {
            all: Vec::with_capacity(capacity),
            lo,
            cell: len,
            dim: 1,
            cells: vec![Cell::default()],
            more: Vec::new(),
        }
    }

    fn add(&mut self, c: usize, p: (f64, f64)) {
        let cell = &mut self.cells[c];
        match cell.inline.get_mut(cell.len as usize) {
            Some(slot) => *slot = p,
            None => {
                if cell.more == 0 {
                    self.more.push(Vec::new());
                    cell.more = self.more.len() as u32;
                }
                self.more[cell.more as usize - 1].push(p);
            }
        }
        cell.len += 1;
    }

    fn points(&self, c: usize) -> impl Iterator<Item = &(f64, f64)> {
        let cell = &self.cells[c];
        let more = match cell.more {
            0 => &[][..],
            m => &self.more[m as usize - 1][..],
        };
        cell.inline[..(cell.len as usize).min(2)].iter().chain(more)
    }

    fn index(&self, v: f64, lo: f64) -> usize {
        (((v - lo) / self.cell).floor().max(0.0) as usize).min(self.dim - 1)
    }

    fn cell_of(&self, p: (f64, f64)) -> usize {
        self.index(p.0, self.lo.0) * self.dim + self.index(p.1, self.lo.1)
    }

    fn push(&mut self, p: (f64, f64)) {
        self.all.push(p);
        let n = self.all.len();
        // At most 2048² cells (170 MB).
        let dim = ((n as f64).sqrt().ceil() as usize).clamp(1, 2048);
        if n.is_power_of_two() && dim > self.dim {
            self.cell *= self.dim as f64 / dim as f64;
            self.dim = dim;
            self.cells = vec![Cell::default(); dim * dim];
            self.more.clear();
            for k in 0..n {
                let q = self.all[k];
                self.add(self.cell_of(q), q);
            }
        } else {
            self.add(self.cell_of(p), p);
        }
    }

    /// The distance from `q` to the nearest copy when it is below
    /// `limit`; infinity otherwise. Rings of cells are searched outward
    /// until no nearer copy can lie beyond them.
    fn nearest(&self, q: (f64, f64), limit: f64) -> f64 {
        let (ci, cj) = (self.index(q.0, self.lo.0), self.index(q.1, self.lo.1));
        let (ci, cj, dim) = (ci as i64, cj as i64, self.dim as i64);
        let mut best = f64::INFINITY;
        for r in 0..=dim {
            // Ring r lies r − 1 cells away at least (less a margin for
            // rounding at the cell edges).
            if (r as f64 - 1.001) * self.cell >= best.min(limit) {
                break;
            }
            for i in (ci - r).max(0)..=(ci + r).min(dim - 1) {
                let edge = (i - ci).abs() == r;
                // Inside the ring only its two ends; on its edges, all.
                let step = if edge { 1 } else { (2 * r).max(1) as usize };
                for j in (cj - r..=cj + r).step_by(step) {
                    if !(0..dim).contains(&j) {
                        continue;
                    }
                    for p in self.points((i * dim + j) as usize) {
                        best = best.min(((p.0 - q.0).powi(2) + (p.1 - q.1).powi(2)).sqrt());
                    }
                }
            }
        }
        if best < limit {
            best
        } else {
            f64::INFINITY
        }
    }
}

/// The transform of every copy of L-system `lsys`.
///
/// Copies lie in the square from (start, start) to (start + side,
/// start + side); `dist` is normalised by the side length. When no spot
/// at that distance is found, the farthest of the tries is taken.
/// Without a finite area and distance there is nothing to keep apart:
/// each copy takes its first try.
pub fn transforms(p: &RepetitionParams, seed: u64, lsys: usize) -> Vec<Affine3A> {
    let (start, side, nbr, dist) = p.start_side_nbr_dist;
    // The scene's primitive limit bounds `nbr` (turtle::build_scene).
    let n = nbr.max(1) as u64;
    let min_d = dist.max(0.0) * side.abs();
    let spread = start.is_finite() && side.is_finite() && side != 0.0 && min_d.is_finite();
    let lo = start.min(start + side);
    let mut spots = Spots::new((lo, lo), side.abs(), n as usize);
    let mut out = Vec::with_capacity(n as usize);
    for k in 0..n {
        let key = random::key(seed, Stream::Repetition, lsys as u64 + (1 << 32), k);
        let mut best = (f64::NEG_INFINITY, (start, start));
        for a in 0..ATTEMPTS {
            let spot = (
                start + side * random::unit(key, 2 * a),
                start + side * random::unit(key, 2 * a + 1),
            );
            let near = if spread {
                spots.nearest(spot, min_d)
            } else {
                f64::INFINITY
            };
            if near > best.0 {
                best = (near, spot);
            }
            if near >= min_d || !spread {
                break;
            }
        }
        let (x, z) = best.1;
        if spread {
            spots.push((x, z));
        }
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

    /// The spots as every copy's tries against every earlier copy chose
    /// them (the search before the grid).
    fn brute_force(start: f64, side: f64, n: u64, dist: f64, seed: u64) -> Vec<(f32, f32)> {
        let min_d = dist.max(0.0) * side.abs();
        let mut spots: Vec<(f64, f64)> = Vec::new();
        for k in 0..n {
            let key = random::key(seed, Stream::Repetition, 1 << 32, k);
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
            spots.push(best.1);
        }
        spots.iter().map(|&(x, z)| (x as f32, z as f32)).collect()
    }

    #[test]
    fn grid_search_places_copies_as_the_brute_force_did() {
        for (start, side, n, dist) in [
            (-50.0, 100.0, 300, 0.05),
            (0.0, 1.0, 3000, 0.5),
            (3.0, -2.0, 500, 0.01),
            (0.0, 10.0, 200, 0.0),
            (1e6, 1.0, 400, 0.02),
            (0.0, 0.0, 5, 0.5),
        ] {
            let p = RepetitionParams {
                start_side_nbr_dist: (start, side, n, dist),
                ..RepetitionParams::default()
            };
            let got: Vec<(f32, f32)> = transforms(&p, 11, 0)
                .iter()
                .map(|a| (a.translation.x, a.translation.z))
                .collect();
            assert_eq!(
                got,
                brute_force(start, side, n as u64, dist, 11),
                "{start} {side} {n} {dist}"
            );
        }
    }

    #[test]
    fn crowded_copies_take_near_linear_time() {
        // 10⁵ copies, far more than fit 0.5 apart: every copy tries 64
        // spots, which the brute force measured against every earlier
        // copy (3·10¹¹ distances).
        let p = RepetitionParams {
            start_side_nbr_dist: (0.0, 1.0, 100_000, 0.5),
            ..RepetitionParams::default()
        };
        let t = std::time::Instant::now();
        assert_eq!(transforms(&p, 1, 0).len(), 100_000);
        assert!(t.elapsed().as_secs_f64() < 20.0, "{:?}", t.elapsed());
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
