//! The voxel heuristics of the path search (thesis 5.2.3, table G.1).
//!
//! A heuristic numbers some voxels around the current voxel (offsets
//! (dx, dy, dz), y up, the x–z plane horizontal), lists the numbered
//! voxels it tests, and gives each tested voxel a condition: a Boolean
//! expression over voxel numbers where `n` is true when voxel n is empty,
//! `!` is not, `*` and, `+` or (parentheses group). A search heuristic's
//! tested voxels are the candidates of Algorithm 1; a test heuristic (3,
//! 4, 6, 8, 11, 18) tests the path voxel itself, for `coll_test_func`.
//!
//! The table is kept as the thesis writes it (strings), so that it reads
//! against the scan; docs/actors.md ("Path search") gives the
//! reconstruction and every reading chosen where the scan is garbled.

use crate::actors::perception::octree::Voxel;

/// What a heuristic is for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    /// Chooses the neighbours of Algorithm 1 (`heuristic`).
    Search,
    /// Tests one path voxel for collisions (`coll_test_func`).
    Test,
}

/// One heuristic of table G.1.
#[derive(Debug)]
pub struct Heuristic {
    pub number: u32,
    pub kind: Kind,
    /// The offset of voxel n is `numbering[n - 1]`.
    pub numbering: &'static [[i32; 3]],
    /// The tested voxels, in the table's order, each with its condition.
    pub tested: &'static [(u8, &'static str)],
}

/// The x–z plane of heuristic 1 (voxels 1–12); +12 gives the plane below
/// (13–24) in heuristics 7 and 9.
macro_rules! plane {
    ($y:expr) => {
        [
            [1, $y, 0],
            [0, $y, -1],
            [-1, $y, 0],
            [0, $y, 1],
            [2, $y, 0],
            [0, $y, -2],
            [-2, $y, 0],
            [0, $y, 2],
            [1, $y, 1],
            [-1, $y, 1],
            [1, $y, -1],
            [-1, $y, -1],
        ]
    };
}

const CROSS: [[i32; 3]; 4] = [[1, 0, 0], [0, 0, -1], [-1, 0, 0], [0, 0, 1]];
/// Heuristics 5 and 8: the cross, the four voxels under it (their
/// supports, 5–8), then the path voxel itself (9, heuristic 8's test).
const CROSS_ON_SUPPORT: [[i32; 3]; 9] = [
    CROSS[0],
    CROSS[1],
    CROSS[2],
    CROSS[3],
    [1, -1, 0],
    [0, -1, -1],
    [-1, -1, 0],
    [0, -1, 1],
    [0, 0, 0],
];
const PLANE: [[i32; 3]; 12] = plane!(0);
const PLANE_BELOW: [[i32; 3]; 24] = {
    let (a, b) = (plane!(0), plane!(-1));
    let mut out = [[0; 3]; 24];
    let mut i = 0;
    while i < 12 {
        out[i] = a[i];
        out[i + 12] = b[i];
        i += 1;
    }
    out
};

/// Heuristic 9: the planes 0 and −1 of heuristic 7, the plane −2 (25–36,
/// numbered as the scan shows it: the far four, the near four, then the
/// corners) and the four side voxels one up (37–40).
const H9: [[i32; 3]; 40] = {
    let mut out = [[0; 3]; 40];
    let mut i = 0;
    while i < 24 {
        out[i] = PLANE_BELOW[i];
        i += 1;
    }
    let low: [[i32; 3]; 12] = [
        [2, -2, 0],
        [0, -2, -2],
        [-2, -2, 0],
        [0, -2, 2],
        [1, -2, 0],
        [0, -2, -1],
        [-1, -2, 0],
        [0, -2, 1],
        [1, -2, -1],
        [-1, -2, -1],
        [1, -2, 1],
        [-1, -2, 1],
    ];
    let up: [[i32; 3]; 4] = [[1, 1, 0], [0, 1, -1], [-1, 1, 0], [0, 1, 1]];
    let mut j = 0;
    while j < 12 {
        out[24 + j] = low[j];
        j += 1;
    }
    let mut k = 0;
    while k < 4 {
        out[36 + k] = up[k];
        k += 1;
    }
    out
};

/// Heuristic 15: the 26 neighbours, x slowest, then y, then z.
const H15: [[i32; 3]; 26] = {
    let mut out = [[0; 3]; 26];
    let mut n = 0;
    let mut x = -1;
    while x <= 1 {
        let mut y = -1;
        while y <= 1 {
            let mut z = -1;
            while z <= 1 {
                if x != 0 || y != 0 || z != 0 {
                    out[n] = [x, y, z];
                    n += 1;
                }
                z += 1;
            }
            y += 1;
        }
        x += 1;
    }
    out
};

const H15_TESTED: [(u8, &str); 26] = [
    (1, "1"),
    (2, "2"),
    (3, "3"),
    (4, "4"),
    (5, "5"),
    (6, "6"),
    (7, "7"),
    (8, "8"),
    (9, "9"),
    (10, "10"),
    (11, "11"),
    (12, "12"),
    (13, "13"),
    (14, "14"),
    (15, "15"),
    (16, "16"),
    (17, "17"),
    (18, "18"),
    (19, "19"),
    (20, "20"),
    (21, "21"),
    (22, "22"),
    (23, "23"),
    (24, "24"),
    (25, "25"),
    (26, "26"),
];

/// Table G.1 as reconstructed (docs/actors.md), by heuristic number.
pub const HEURISTICS: &[Heuristic] = &[
    Heuristic {
        number: 0,
        kind: Kind::Search,
        numbering: &CROSS,
        tested: &[(1, "1"), (2, "2"), (3, "3"), (4, "4")],
    },
    Heuristic {
        number: 1,
        kind: Kind::Search,
        numbering: &PLANE,
        tested: &[
            (1, "1*5*9*11"),
            (2, "2*11*6*12"),
            (3, "3*7*10*12"),
            (4, "4*8*9*10"),
        ],
    },
    Heuristic {
        number: 2,
        kind: Kind::Search,
        numbering: &[
            [1, 0, 0],
            [0, 0, -1],
            [-1, 0, 0],
            [0, 0, 1],
            [0, 1, 0],
            [0, -1, 0],
        ],
        tested: &[(1, "1"), (2, "2"), (3, "3"), (4, "4"), (5, "5"), (6, "6")],
    },
    Heuristic {
        number: 3,
        kind: Kind::Test,
        numbering: &[[0, 0, 0]],
        tested: &[(1, "1")],
    },
    Heuristic {
        number: 4,
        kind: Kind::Test,
        numbering: &[CROSS[0], CROSS[1], CROSS[2], CROSS[3], [0, 0, 0]],
        tested: &[(5, "5*1*2*3*4")],
    },
    Heuristic {
        number: 5,
        kind: Kind::Search,
        numbering: CROSS_ON_SUPPORT.split_at(8).0,
        tested: &[(1, "1*!5"), (2, "2*!6"), (3, "3*!7"), (4, "4*!8")],
    },
    Heuristic {
        number: 6,
        kind: Kind::Test,
        numbering: &[[0, -1, 0], [0, 0, 0]],
        tested: &[(2, "2*!1")],
    },
    Heuristic {
        number: 7,
        kind: Kind::Search,
        numbering: &PLANE_BELOW,
        tested: &[
            (1, "1*5*9*11*!13*!17*!23*!21"),
            (2, "2*11*6*12*!14*!18*!24*!23"),
            (3, "3*7*10*12*!15*!19*!22*!24"),
            (4, "4*8*9*10*!16*!20*!21*!22"),
        ],
    },
    Heuristic {
        number: 8,
        kind: Kind::Test,
        numbering: &CROSS_ON_SUPPORT,
        tested: &[(9, "9*1*2*3*4*!5*!6*!7*!8")],
    },
    Heuristic {
        number: 9,
        kind: Kind::Search,
        numbering: &H9,
        tested: &[
            (
                1,
                "1*(5*9*11*!13*!17*!23*!21 + 5*9*11*17*!13*!23*!21*!25 + !5*37*!13)",
            ),
            (
                2,
                "2*(6*12*11*!14*!18*!23*!24 + 6*12*11*18*!14*!24*!23*!26 + !6*38*!14)",
            ),
            (
                3,
                "3*(7*10*12*!15*!19*!22*!24 + 7*10*12*19*!15*!22*!24*!27 + !7*39*!15)",
            ),
            (
                4,
                "4*(8*9*10*!16*!20*!21*!22 + 8*9*10*20*!16*!21*!22*!28 + !8*40*!16)",
            ),
            (13, "13*!29"),
            (14, "14*!30"),
            (15, "15*!31"),
            (16, "16*!32"),
            (37, "37*!1"),
            (38, "38*!2"),
            (39, "39*!3"),
            (40, "40*!4"),
        ],
    },
    Heuristic {
        number: 10,
        kind: Kind::Search,
        numbering: &[
            PLANE[0],
            PLANE[1],
            PLANE[2],
            PLANE[3],
            PLANE[4],
            PLANE[5],
            PLANE[6],
            PLANE[7],
            PLANE[8],
            PLANE[9],
            PLANE[10],
            PLANE[11],
            [0, 1, 0],
            [0, 2, 0],
            [0, 3, 0],
            [0, 4, 0],
        ],
        tested: &[
            (1, "1*5*9*11*13*14*15*16"),
            (2, "2*11*6*12*13*14*15*16"),
            (3, "3*7*10*12*13*14*15*16"),
            (4, "4*8*9*10*13*14*15*16"),
        ],
    },
    Heuristic {
        number: 11,
        kind: Kind::Test,
        numbering: &[CROSS[0], CROSS[1], CROSS[2], CROSS[3], [0, 0, 0], [0, 1, 0]],
        tested: &[(5, "5*1*2*3*4*6")],
    },
    Heuristic {
        number: 15,
        kind: Kind::Search,
        numbering: &H15,
        tested: &H15_TESTED,
    },
    Heuristic {
        number: 18,
        kind: Kind::Test,
        numbering: &[
            [0, 0, 0],
            [0, 1, 0],
            [0, 2, 0],
            [0, 3, 0],
            [0, 4, 0],
            [0, 5, 0],
        ],
        tested: &[(1, "1*2*3*4*5*6")],
    },
];

/// The heuristic numbered `n` in table G.1, None for a number the table
/// lacks (12–14, 16, 17, past 18).
pub fn heuristic(n: u32) -> Option<&'static Heuristic> {
    HEURISTICS.iter().find(|h| h.number == n)
}

/// The voxel numbered `n` around `v`, None when it falls below the cube
/// (a coordinate under 0).
fn numbered(h: &Heuristic, v: Voxel, n: u8) -> Option<Voxel> {
    let d = h.numbering[usize::from(n) - 1];
    let mut out = [0u32; 3];
    for i in 0..3 {
        out[i] = u32::try_from(i64::from(v[i]) + i64::from(d[i])).ok()?;
    }
    Some(out)
}

/// Evaluates the conditions of `h` around `v`, asking `is_empty` each
/// numbered voxel at most once; a voxel below the cube counts as occupied
/// (the caller's `is_empty` says what lies past the cube's other faces).
struct Around<'a, F> {
    h: &'a Heuristic,
    v: Voxel,
    is_empty: F,
    /// Per voxel number: 0 not asked, 1 empty, 2 occupied.
    seen: [u8; 41],
}

impl<F: FnMut(Voxel) -> bool> Around<'_, F> {
    fn empty(&mut self, n: u8) -> bool {
        let i = usize::from(n);
        if self.seen[i] == 0 {
            let e = numbered(self.h, self.v, n).is_some_and(&mut self.is_empty);
            self.seen[i] = if e { 1 } else { 2 };
        }
        self.seen[i] == 1
    }

    /// Condition `c`; None when it does not parse or names a voxel the
    /// numbering lacks (the tests check that the table has none).
    fn holds(&mut self, c: &str) -> Option<bool> {
        let mut p = Parser {
            s: c.as_bytes(),
            at: 0,
        };
        let value = p.sum(self)?;
        p.skip();
        (p.at == p.s.len()).then_some(value)
    }
}

/// Recursive descent over a condition: sum := product ('+' product)*,
/// product := factor ('*' factor)*, factor := '!' factor | '(' sum ')' |
/// number. Every voxel is looked up (no short cut), so a malformed
/// condition fails the same way whatever the voxels hold.
struct Parser<'s> {
    s: &'s [u8],
    at: usize,
}

impl Parser<'_> {
    fn skip(&mut self) {
        while self.s.get(self.at) == Some(&b' ') {
            self.at += 1;
        }
    }

    fn eat(&mut self, b: u8) -> bool {
        self.skip();
        let hit = self.s.get(self.at) == Some(&b);
        if hit {
            self.at += 1;
        }
        hit
    }

    fn sum<F: FnMut(Voxel) -> bool>(&mut self, a: &mut Around<F>) -> Option<bool> {
        let mut v = self.product(a)?;
        while self.eat(b'+') {
            v |= self.product(a)?;
        }
        Some(v)
    }

    fn product<F: FnMut(Voxel) -> bool>(&mut self, a: &mut Around<F>) -> Option<bool> {
        let mut v = self.factor(a)?;
        while self.eat(b'*') {
            v &= self.factor(a)?;
        }
        Some(v)
    }

    fn factor<F: FnMut(Voxel) -> bool>(&mut self, a: &mut Around<F>) -> Option<bool> {
        if self.eat(b'!') {
            return self.factor(a).map(|v| !v);
        }
        if self.eat(b'(') {
            let v = self.sum(a)?;
            return self.eat(b')').then_some(v);
        }
        let start = self.at;
        while self.s.get(self.at).is_some_and(u8::is_ascii_digit) {
            self.at += 1;
        }
        let n: u8 = std::str::from_utf8(&self.s[start..self.at])
            .ok()?
            .parse()
            .ok()?;
        (1..=a.h.numbering.len())
            .contains(&usize::from(n))
            .then(|| a.empty(n))
    }
}

/// The tested voxels of `h` around `v` whose conditions hold, in the
/// table's order (Algorithm 1 sorts them by distance to the aim after).
pub fn candidates(h: &Heuristic, v: Voxel, is_empty: impl FnMut(Voxel) -> bool) -> Vec<Voxel> {
    let mut a = Around {
        h,
        v,
        is_empty,
        seen: [0; 41],
    };
    let mut out = Vec::with_capacity(h.tested.len());
    for &(n, c) in h.tested {
        if a.holds(c) == Some(true) {
            out.extend(numbered(h, v, n));
        }
    }
    out
}

/// Whether every tested condition of `h` holds around `v`: for a test
/// heuristic (3, 4, 6, 8, 11, 18), whose one tested voxel is `v` itself,
/// that the path voxel `v` is free of collisions.
pub fn collision_free(h: &Heuristic, v: Voxel, is_empty: impl FnMut(Voxel) -> bool) -> bool {
    let mut a = Around {
        h,
        v,
        is_empty,
        seen: [0; 41],
    };
    h.tested.iter().all(|&(_, c)| a.holds(c) == Some(true))
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::BTreeSet;

    const C: Voxel = [10, 10, 10];

    fn at(d: [i32; 3]) -> Voxel {
        [0, 1, 2].map(|i| (C[i] as i32 + d[i]) as u32)
    }

    /// The candidates of heuristic n around C with these offsets occupied.
    fn cands(n: u32, occupied: &[[i32; 3]]) -> Vec<Voxel> {
        let occ: BTreeSet<Voxel> = occupied.iter().map(|&d| at(d)).collect();
        candidates(heuristic(n).unwrap(), C, |v| !occ.contains(&v))
    }

    fn free(n: u32, occupied: &[[i32; 3]]) -> bool {
        let occ: BTreeSet<Voxel> = occupied.iter().map(|&d| at(d)).collect();
        collision_free(heuristic(n).unwrap(), C, |v| !occ.contains(&v))
    }

    /// Every condition parses, names only numbered voxels, and every
    /// numbering is distinct and leaves out the centre unless a test
    /// heuristic tests it.
    #[test]
    fn table_is_well_formed() {
        for h in HEURISTICS {
            let mut a = Around {
                h,
                v: C,
                is_empty: |_| true,
                seen: [0; 41],
            };
            for &(n, c) in h.tested {
                assert!(a.holds(c).is_some(), "heuristic {} `{c}`", h.number);
                assert!(usize::from(n) <= h.numbering.len());
                // A candidate's own voxel must be empty.
                let mut b = Around {
                    h,
                    v: C,
                    is_empty: |v| v != numbered(h, C, n).unwrap(),
                    seen: [0; 41],
                };
                assert_eq!(b.holds(c), Some(false), "heuristic {} `{c}`", h.number);
            }
            let set: BTreeSet<[i32; 3]> = h.numbering.iter().copied().collect();
            assert_eq!(set.len(), h.numbering.len(), "heuristic {}", h.number);
            let tests_centre = h
                .tested
                .iter()
                .any(|&(n, _)| h.numbering[usize::from(n) - 1] == [0, 0, 0]);
            assert_eq!(tests_centre, h.kind == Kind::Test, "heuristic {}", h.number);
            assert_eq!(set.contains(&[0, 0, 0]), tests_centre);
        }
        let numbers: Vec<u32> = HEURISTICS.iter().map(|h| h.number).collect();
        assert_eq!(numbers, [0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 15, 18]);
        assert!(heuristic(12).is_none());
    }

    #[test]
    fn heuristic_0_the_four_plane_neighbours() {
        assert_eq!(
            cands(0, &[]),
            [at([1, 0, 0]), at([0, 0, -1]), at([-1, 0, 0]), at([0, 0, 1])]
        );
        assert_eq!(cands(0, &[[0, 0, -1], [0, 1, 0], [1, 0, 1]]).len(), 3);
        // Below the cube counts as occupied.
        let c = candidates(heuristic(0).unwrap(), [0, 0, 0], |_| true);
        assert_eq!(c, [[1, 0, 0], [0, 0, 1]]);
    }

    #[test]
    fn heuristic_1_keeps_a_voxel_from_walls() {
        assert_eq!(cands(1, &[]).len(), 4);
        // (1,0,1) is a side of voxel 1 (+x) and of voxel 4 (+z).
        assert_eq!(cands(1, &[[1, 0, 1]]), [at([0, 0, -1]), at([-1, 0, 0])]);
        // (2,0,0) only bars voxel 1; (−1,0,−1) bars voxels 2 and 3 (the
        // reading 3*7*10*12 for the scan's 3*7*10*11).
        assert_eq!(cands(1, &[[2, 0, 0]]).len(), 3);
        assert_eq!(cands(1, &[[-1, 0, -1]]), [at([1, 0, 0]), at([0, 0, 1])]);
        // The centre's own state does not matter, nor other planes.
        assert_eq!(cands(1, &[[0, 0, 0], [1, 1, 0], [1, -1, 0]]).len(), 4);
    }

    #[test]
    fn heuristic_2_and_15_search_in_3d() {
        assert_eq!(
            cands(2, &[[0, 0, 1]]),
            [
                at([1, 0, 0]),
                at([0, 0, -1]),
                at([-1, 0, 0]),
                at([0, 1, 0]),
                at([0, -1, 0])
            ]
        );
        let all = cands(15, &[]);
        assert_eq!(all.len(), 26);
        assert_eq!(all[0], at([-1, -1, -1]));
        assert_eq!(all[12], at([0, 0, -1]));
        assert_eq!(all[25], at([1, 1, 1]));
        let some = cands(15, &[[1, 1, 1], [0, -1, 0]]);
        assert_eq!(some.len(), 24);
        assert!(!some.contains(&at([0, -1, 0])));
    }

    #[test]
    fn heuristic_5_and_7_need_a_support() {
        let floor: Vec<[i32; 3]> = (-2..=2)
            .flat_map(|x| (-2..=2).map(move |z| [x, -1, z]))
            .collect();
        assert!(cands(5, &[]).is_empty());
        assert!(cands(7, &[]).is_empty());
        assert_eq!(cands(5, &floor).len(), 4);
        assert_eq!(cands(7, &floor).len(), 4);
        // A hole under (2,0,0) bars voxel 1 for 7 (its neighbour 5 would
        // stand over nothing) but not for 5.
        let holed: Vec<[i32; 3]> = floor.iter().copied().filter(|&d| d != [2, -1, 0]).collect();
        assert_eq!(cands(5, &holed).len(), 4);
        assert_eq!(
            cands(7, &holed),
            [at([0, 0, -1]), at([-1, 0, 0]), at([0, 0, 1])]
        );
    }

    #[test]
    fn heuristic_9_walks_flat_up_and_down() {
        let floor = |y: i32, skip: &[[i32; 2]]| -> Vec<[i32; 3]> {
            (-2..=2)
                .flat_map(|x| (-2..=2).map(move |z| [x, y, z]))
                .filter(|d| !skip.contains(&[d[0], d[2]]))
                .collect()
        };
        // Flat ground: the four plane voxels only.
        assert_eq!(
            cands(9, &floor(-1, &[])),
            [at([1, 0, 0]), at([0, 0, -1]), at([-1, 0, 0]), at([0, 0, 1])]
        );
        // A step up at +x: voxel 1 is occupied, 37 above it is free.
        let mut step = floor(-1, &[]);
        step.push([1, 0, 0]);
        let c = cands(9, &step);
        assert!(c.contains(&at([1, 1, 0])));
        assert!(!c.contains(&at([1, 0, 0])));
        // A step whose top is blocked is no way up.
        step.push([1, 1, 0]);
        assert!(!cands(9, &step).contains(&at([1, 1, 0])));
        // A step up two voxels ahead: voxel 1 by its third term (!5*37*!13).
        let mut wall = floor(-1, &[]);
        wall.push([2, 0, 0]);
        assert!(cands(9, &wall).contains(&at([1, 0, 0])));
        // A step down at +x: the ground at x = 1 is one lower.
        let mut down = floor(-1, &[[1, 0], [2, 0]]);
        down.extend([[1, -2, 0], [2, -2, 0]]);
        let c = cands(9, &down);
        assert!(c.contains(&at([1, -1, 0])));
        assert!(!c.contains(&at([1, 0, 0])));
        // The ground drops past voxel 1 (17 free, 25 below it occupied):
        // voxel 1 by the second term.
        let mut ledge = floor(-1, &[[2, 0]]);
        ledge.push([2, -2, 0]);
        assert!(cands(9, &ledge).contains(&at([1, 0, 0])));
        // A cliff (nothing at 25 either) bars it.
        let cliff = floor(-1, &[[2, 0]]);
        assert!(!cands(9, &cliff).contains(&at([1, 0, 0])));
    }

    /// Heuristic 9 adds a voxel only above an occupied one (5.2.1: "only
    /// neighbors, above an occupied voxel"): the third terms (`!5*37`, a
    /// step up two voxels ahead) ask the support of the candidate too
    /// (`!13`, a reading), so a wall beyond a gap does not lure the actor
    /// over it. Checked on random neighbourhoods of every density.
    #[test]
    fn heuristic_9_never_adds_a_voxel_without_support() {
        // A wall two voxels ahead of a floor that ends under voxel 1.
        let mut gap: Vec<[i32; 3]> = (-2..=2)
            .flat_map(|x| (-2..=2).map(move |z| [x, -1, z]))
            .filter(|d| d[0] < 1)
            .collect();
        gap.extend([[2, 0, 0], [2, -1, 0], [2, 1, 0]]);
        assert!(!cands(9, &gap).contains(&at([1, 0, 0])));
        // The same wall with the floor under voxel 1: the step is near.
        gap.push([1, -1, 0]);
        assert!(cands(9, &gap).contains(&at([1, 0, 0])));
        // Random neighbourhoods (a small LCG: the same cases every run).
        let mut seed: u64 = 9;
        let mut next = || {
            seed = seed
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (seed >> 33) as u32
        };
        let mut moves = 0;
        for case in 0..20_000 {
            let density = 1 + case % 9;
            let occ: BTreeSet<Voxel> = (-3..=3)
                .flat_map(|x| (-3..=2).flat_map(move |y| (-3..=3).map(move |z| [x, y, z])))
                .filter(|_| next() % 10 < density)
                .map(at)
                .collect();
            for c in candidates(heuristic(9).unwrap(), C, |v| !occ.contains(&v)) {
                assert!(!occ.contains(&c));
                assert!(occ.contains(&[c[0], c[1] - 1, c[2]]), "{c:?} unsupported");
                moves += 1;
            }
        }
        assert!(moves > 1000, "{moves}");
    }

    #[test]
    fn heuristic_10_keeps_four_voxels_above_free() {
        assert_eq!(cands(10, &[]).len(), 4);
        for y in 1..=4 {
            assert!(cands(10, &[[0, y, 0]]).is_empty());
        }
        assert_eq!(cands(10, &[[0, 5, 0]]).len(), 4);
        assert_eq!(cands(10, &[[0, 0, -2]]).len(), 3);
    }

    #[test]
    fn collision_tests_3_4_6_8_11_18() {
        assert!(free(3, &[[1, 0, 0]]));
        assert!(!free(3, &[[0, 0, 0]]));
        assert!(free(4, &[[1, 1, 0]]));
        assert!(!free(4, &[[0, 0, 1]]));
        assert!(!free(6, &[]));
        assert!(free(6, &[[0, -1, 0]]));
        let support = [[1, -1, 0], [0, -1, -1], [-1, -1, 0], [0, -1, 1]];
        assert!(free(8, &support));
        assert!(!free(8, &support[..3]));
        let mut blocked = support.to_vec();
        blocked.push([-1, 0, 0]);
        assert!(!free(8, &blocked));
        assert!(free(11, &[[0, 2, 0]]));
        assert!(!free(11, &[[0, 1, 0]]));
        assert!(!free(11, &[[0, 0, -1]]));
        assert!(free(18, &[[0, 6, 0], [1, 0, 0]]));
        assert!(!free(18, &[[0, 5, 0]]));
        assert!(!free(18, &[[0, 0, 0]]));
    }
}
