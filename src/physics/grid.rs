//! A uniform grid of the carriers of short-range fields (issue 7, beyond
//! the thesis's O(n²) loop of 8.1.4): a particle only looks at the 27
//! cells around it instead of at every carrier.

use glam::DVec3;

/// Cell coordinates are clamped to ±2^50 so that the ±1 neighbours never
/// overflow; clamping only merges far cells, it never separates
/// neighbours.
const LIMIT: f64 = (1u64 << 50) as f64;

/// Cell coordinates: floor(position / side).
type Cell = [i64; 3];

/// Start and end in `Grid::carriers` of the cells z − 1 ..= z + 1 of the
/// nine columns around a cell.
type Runs = [(u32, u32); 9];

/// Carriers binned in cubic cells whose side is at least every carrier's
/// reach, so every carrier within reach of a point lies in one of the 27
/// cells around that point's cell.
#[derive(Debug)]
pub struct Grid {
    side: f64,
    /// The carriers' cells, sorted: cells are lexicographic (x, y, z), so
    /// the three cells z − 1 ..= z + 1 of a column are one contiguous run.
    cells: Vec<Cell>,
    /// Row, position, reach and a bound on reach² of each carrier of
    /// `cells`, side by side so the scan of a run reads contiguous memory.
    carriers: Vec<(u32, DVec3, f64, f64)>,
    /// Each occupied cell (sorted) and the nine runs of `carriers` around
    /// it: the particles of a cell share them, which saves 17 of the 18
    /// binary searches per query.
    occupied: Vec<(Cell, Runs)>,
}

impl Grid {
    /// Bins `carriers` (table row, position, reach) in cells of side
    /// `side`, the largest reach among them. The side is widened by a
    /// relative 1e-6 so that rounding in `x / side` (at most 2^-53 of it)
    /// cannot put a carrier within reach two cells away while |x / side|
    /// stays below 10^9.
    pub fn new(side: f64, carriers: impl Iterator<Item = (usize, DVec3, f64)>) -> Self {
        let side = side * (1.0 + 1e-6);
        // Above reach² · (1 + 1e-12), √ is surely ≥ reach (√ is
        // correctly rounded): most candidates are rejected without it.
        let mut binned: Vec<(Cell, (u32, DVec3, f64, f64))> = carriers
            .map(|(k, at, reach)| {
                let bound = reach * reach * (1.0 + 1e-12);
                (cell(side, at), (k as u32, at, reach, bound))
            })
            .collect();
        binned.sort_unstable_by_key(|&(c, (k, ..))| (c, k));
        let (cells, carriers): (Vec<Cell>, _) = binned.into_iter().unzip();
        let mut grid = Grid {
            side,
            cells,
            carriers,
            occupied: Vec::new(),
        };
        let mut occupied: Vec<Cell> = grid.cells.clone();
        occupied.dedup();
        grid.occupied = occupied.into_iter().map(|c| (c, grid.runs(c))).collect();
        grid
    }

    /// The runs of `carriers` in the 27 cells around `c`, one per column.
    fn runs(&self, [x, y, z]: Cell) -> Runs {
        let mut runs = [(0, 0); 9];
        for (run, (dx, dy)) in runs
            .iter_mut()
            .zip((-1..=1).flat_map(|dx| (-1..=1).map(move |dy| (dx, dy))))
        {
            let (lo, hi) = ([x + dx, y + dy, z - 1], [x + dx, y + dy, z + 1]);
            let start = self.cells.partition_point(|c| *c < lo);
            let end = start + self.cells[start..].partition_point(|c| *c <= hi);
            *run = (start as u32, end as u32);
        }
        runs
    }

    /// Calls `visit(row, r)` for every carrier whose reach exceeds its
    /// distance r to `at`, in no particular order.
    pub fn near(&self, at: DVec3, mut visit: impl FnMut(usize, f64)) {
        let c = cell(self.side, at);
        let runs = match self.occupied.binary_search_by(|(o, _)| o.cmp(&c)) {
            Ok(j) => self.occupied[j].1,
            Err(_) => self.runs(c),
        };
        for (start, end) in runs {
            for &(k, q, reach, bound) in &self.carriers[start as usize..end as usize] {
                // The same r as `at.distance(q)`, the all-pairs test's.
                let d2 = (at - q).length_squared();
                if d2 <= bound {
                    let r = d2.sqrt();
                    if r < reach {
                        visit(k as usize, r);
                    }
                }
            }
        }
    }
}

/// The cell of `at`; NaN coordinates land in cell 0, where their NaN
/// distances exclude them anyway.
fn cell(side: f64, at: DVec3) -> Cell {
    let c = |v: f64| (v / side).floor().clamp(-LIMIT, LIMIT) as i64;
    [c(at.x), c(at.y), c(at.z)]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_every_carrier_within_reach() {
        let pts: Vec<DVec3> = (0..200)
            .map(|i| {
                let f = f64::from(i);
                DVec3::new(
                    (f * 0.37).sin() * 5.0,
                    (f * 0.11).cos() * 5.0,
                    f * 0.05 - 5.0,
                )
            })
            .collect();
        let reach = |k: usize| 0.5 + (k % 3) as f64 * 0.5;
        let grid = Grid::new(
            1.5,
            pts.iter().enumerate().map(|(k, &at)| (k, at, reach(k))),
        );
        for &at in &pts {
            let mut found = vec![None; pts.len()];
            grid.near(at, |k, r| found[k] = Some(r));
            for (k, q) in pts.iter().enumerate() {
                let r = at.distance(*q);
                assert_eq!(found[k], (r < reach(k)).then_some(r));
            }
        }
    }
}
