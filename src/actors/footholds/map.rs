//! Map extraction (thesis 5.9.2): the foothold locations an actor's
//! visual memory holds around it.
//!
//! The auxiliary map octree of figure 5.9.1 is kept as what it is used
//! for, a set of 2D cells: in the region of interest (voxel centres within
//! `range` of the actor, horizontally), a cell is full when the memory
//! holds a full voxel in the foothold plane's layer or in the layer just
//! under or over it (their projections), which makes up for a surface that
//! voxelization put on either side of a layer boundary. Its 4-connected
//! components (figure 5.9.2) smaller than `min_voxels` are dropped; each
//! other one is a foothold at the mean of its cells' centres, its cell
//! count its size: the `local_map`.

use std::collections::{BTreeMap, BTreeSet};

use glam::{Vec2, Vec3};

use crate::actors::perception::octree::{Octree, Voxel};

/// A foothold location: where (on the plane) and how big, in cells.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Foothold {
    pub at: Vec3,
    pub voxels: u32,
}

impl Foothold {
    /// Its position on the ground: (x, z).
    pub fn ground(&self) -> Vec2 {
        Vec2::new(self.at.x, self.at.z)
    }
}

/// Where a map is made: around `centre`, within `range` of it
/// horizontally, on the plane of height `plane`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Region {
    pub centre: Vec3,
    pub range: f32,
    pub plane: f32,
}

/// A 2D cell of the map: voxel x and z.
type Cell = (u32, u32);

/// The memory layer (voxel y) holding height `y`, None outside the cube.
pub fn layer(memory: &Octree, y: f32) -> Option<u32> {
    let c = memory.cube();
    let q = (f64::from(y) - c.min) / c.voxel_edge;
    (q >= 0.0 && q < f64::from(memory.voxels_per_edge())).then_some(q as u32)
}

/// The height of layer `k`'s centre.
pub fn layer_height(memory: &Octree, k: u32) -> f32 {
    let c = memory.cube();
    (c.min + (f64::from(k) + 0.5) * c.voxel_edge) as f32
}

/// The voxels of the memory in layers `lo..=hi` whose centres lie within
/// the region's range of its centre, horizontally, in son order.
fn voxels_in(memory: &Octree, region: &Region, lo: u32, hi: u32, mut f: impl FnMut(Voxel)) {
    let c = memory.cube();
    let e = c.voxel_edge;
    let centre = Vec2::new(region.centre.x, region.centre.z);
    let range = f64::from(region.range.max(0.0));
    // The region's box in voxel coordinates, for pruning the walk.
    let span = |p: f32| {
        let lo = ((f64::from(p) - range - c.min) / e).floor().max(0.0);
        let hi = ((f64::from(p) + range - c.min) / e).ceil().max(0.0);
        (
            lo.min(f64::from(u32::MAX)) as u32,
            hi.min(f64::from(u32::MAX)) as u32,
        )
    };
    let (x0, x1) = span(region.centre.x);
    let (z0, z1) = span(region.centre.z);
    let enter = |v: Voxel, edge: u32| {
        let meets = |a: u32, lo: u32, hi: u32| a <= hi && a.saturating_add(edge) > lo;
        meets(v[0], x0, x1) && meets(v[1], lo, hi) && meets(v[2], z0, z1)
    };
    memory.for_each_voxel(
        |v, _| {
            let p = memory.centre(v);
            let d = Vec2::new(p[0] as f32, p[2] as f32).distance(centre);
            if d <= region.range {
                f(v);
            }
        },
        enter,
    );
}

/// The auxiliary map's full cells: the plane's layer and its two
/// neighbours projected onto it.
fn map_cells(memory: &Octree, region: &Region) -> BTreeSet<Cell> {
    let mut cells = BTreeSet::new();
    if let Some(k) = layer(memory, region.plane) {
        voxels_in(memory, region, k.saturating_sub(1), k + 1, |v| {
            cells.insert((v[0], v[2]));
        });
    }
    cells
}

/// A 4-connected component of the map: its cell count, the sums of its
/// cells' coordinates, and its bounding box in cells.
#[derive(Debug, Clone, Copy)]
struct Part {
    n: u32,
    sx: f64,
    sz: f64,
    lo: Cell,
    hi: Cell,
}

impl Part {
    fn join(&self, o: &Part) -> Part {
        Part {
            n: self.n + o.n,
            sx: self.sx + o.sx,
            sz: self.sz + o.sz,
            lo: (self.lo.0.min(o.lo.0), self.lo.1.min(o.lo.1)),
            hi: (self.hi.0.max(o.hi.0), self.hi.1.max(o.hi.1)),
        }
    }

    /// Its larger extent, in cells.
    fn extent(&self) -> u32 {
        (self.hi.0 - self.lo.0).max(self.hi.1 - self.lo.1) + 1
    }
}

/// The 4-connected components of `cells`, in the order of their first
/// cell (x, then z).
fn components(mut left: BTreeSet<Cell>) -> Vec<Part> {
    let mut parts = Vec::new();
    while let Some(first) = left.pop_first() {
        // One component, by a flood from its first cell.
        let mut todo = vec![first];
        let mut p = Part {
            n: 0,
            sx: 0.0,
            sz: 0.0,
            lo: first,
            hi: first,
        };
        while let Some((x, z)) = todo.pop() {
            p = p.join(&Part {
                n: 1,
                sx: f64::from(x),
                sz: f64::from(z),
                lo: (x, z),
                hi: (x, z),
            });
            let four = [
                x.checked_sub(1).map(|x| (x, z)),
                x.checked_add(1).map(|x| (x, z)),
                z.checked_sub(1).map(|z| (x, z)),
                z.checked_add(1).map(|z| (x, z)),
            ];
            for c in four.into_iter().flatten() {
                if left.remove(&c) {
                    todo.push(c);
                }
            }
        }
        parts.push(p);
    }
    parts
}

/// The local map of the region: its foothold locations of at least
/// `min_voxels` cells, in the order of their first cell (x, then z).
///
/// Components that together fit in a square of side `foot` (plus a cell
/// on each side for a stone's rim) are one foothold seen in pieces: a
/// stone far away, seen at a grazing angle, shows its far edge and its
/// near rim with cells not yet seen between. Two footholds cannot fit
/// there: each is the size of a foot and empty space lies between them
/// (5.9.1).
pub fn local_map(memory: &Octree, region: &Region, min_voxels: u32, foot: f32) -> Vec<Foothold> {
    let e = memory.cube().voxel_edge;
    let min = memory.cube().min;
    // foot ≤ 0: no joining.
    let fits = if foot > 0.0 {
        (f64::from(foot) / e).floor() as u32 + 2
    } else {
        0
    };
    let mut parts = components(map_cells(memory, region));
    // Join pieces, first pair first, until none fit together.
    'join: loop {
        for i in 0..parts.len() {
            for j in i + 1..parts.len() {
                let u = parts[i].join(&parts[j]);
                if u.extent() <= fits {
                    parts[i] = u;
                    parts.remove(j);
                    continue 'join;
                }
            }
        }
        break;
    }
    parts
        .iter()
        .filter(|p| p.n >= min_voxels.max(1))
        .map(|p| {
            let mean = |s: f64| (min + (s / f64::from(p.n) + 0.5) * e) as f32;
            Foothold {
                at: Vec3::new(mean(p.sx), region.plane, mean(p.sz)),
                voxels: p.n,
            }
        })
        .collect()
}

/// The foothold plane an actor stands on when the scene does not say:
/// the height of the memory layer, among those under `below` within the
/// region's range, that holds the most full voxels (on a tie, the
/// higher). Stone tops fill a layer; their sides only ring the layers
/// under it.
pub fn busiest_layer(memory: &Octree, region: &Region, below: f32) -> Option<f32> {
    let top = layer(memory, below)?;
    busiest_in(memory, region, 0, top)
}

/// The plane a scene gives (`foothold_plane`) as the memory holds it:
/// the busiest layer within two of the plane's (a stone's top a little
/// off the given height, or on a layer boundary); the plane itself when
/// those layers hold nothing.
pub fn plane_near(memory: &Octree, region: &Region, plane: f32) -> f32 {
    layer(memory, plane)
        .and_then(|k| busiest_in(memory, region, k.saturating_sub(2), k + 2))
        .unwrap_or(plane)
}

/// The height of the layer among `lo..=hi` with the most full voxels
/// within the region's range (on a tie, the higher).
fn busiest_in(memory: &Octree, region: &Region, lo: u32, hi: u32) -> Option<f32> {
    let mut counts: BTreeMap<u32, u64> = BTreeMap::new();
    voxels_in(memory, region, lo, hi, |v| {
        *counts.entry(v[1]).or_default() += 1;
    });
    let (k, _) = counts
        .iter()
        .max_by(|a, b| a.1.cmp(b.1).then(a.0.cmp(b.0)))?;
    Some(layer_height(memory, *k))
}

/// Why a local map holds what it holds, for the film maker: the full
/// voxels of the plane's layer and its neighbours within the range, the
/// components they make and their sizes against `min_voxels`.
pub fn explain(memory: &Octree, region: &Region, min_voxels: u32) -> String {
    let Some(k) = layer(memory, region.plane) else {
        return format!(
            "its plane y = {} lies outside its memory's cube",
            region.plane
        );
    };
    let mut counts: BTreeMap<u32, u64> = BTreeMap::new();
    voxels_in(memory, region, k.saturating_sub(1), k + 1, |v| {
        *counts.entry(v[1]).or_default() += 1;
    });
    let layers: Vec<String> = (k.saturating_sub(1)..=k + 1)
        .map(|l| format!("{}", counts.get(&l).copied().unwrap_or(0)))
        .collect();
    let mut sizes: Vec<u32> = components(map_cells(memory, region))
        .iter()
        .map(|p| p.n)
        .collect();
    sizes.sort_unstable_by(|a, b| b.cmp(a));
    let shown: Vec<String> = sizes.iter().take(12).map(u32::to_string).collect();
    format!(
        "plane y = {:.3} (memory layer {k}); the layers under, at and over it hold {} full voxels within {} of the eye; {} components of sizes [{}{}], min_voxels {min_voxels}",
        region.plane,
        layers.join(" / "),
        region.range,
        sizes.len(),
        shown.join(", "),
        if sizes.len() > 12 { ", …" } else { "" }
    )
}

/// The ground under an eye in memory layer `eye`: a surface the walls
/// stand on, told from them by its extent — of the memory layers under
/// the eye or at it (an eye less than a voxel over the ground) within
/// the region's range, the pair of neighbouring layers (a floor on a
/// layer boundary fills two) whose full voxels, projected together, hold
/// the most cells whose four neighbours are full too: a wall, a line a
/// voxel or two thick, holds none, nor does the band the lower edge of a
/// window cuts out of the walls. At least [`MIN_GROUND`] such cells.
/// Returns (lowest, busiest, highest) of the pair's layers that hold a
/// quarter of its voxels; None when no surface is seen.
pub fn ground_layers(memory: &Octree, region: &Region, eye: u32) -> Option<(u32, u32, u32)> {
    let mut layers: BTreeMap<u32, BTreeSet<Cell>> = BTreeMap::new();
    voxels_in(memory, region, 0, eye, |v| {
        layers.entry(v[1]).or_default().insert((v[0], v[2]));
    });
    let empty = BTreeSet::new();
    let cells = |k: u32| layers.get(&k).unwrap_or(&empty);
    let inner = |k: u32| {
        let both: BTreeSet<Cell> = cells(k).union(cells(k + 1)).copied().collect();
        let full = |c: Option<Cell>| c.is_some_and(|c| both.contains(&c));
        both.iter()
            .filter(|&&(x, z)| {
                full(x.checked_sub(1).map(|x| (x, z)))
                    && full(Some((x + 1, z)))
                    && full(z.checked_sub(1).map(|z| (x, z)))
                    && full(Some((x, z + 1)))
            })
            .count()
    };
    let (k, n) = layers
        .keys()
        .map(|&k| (k, inner(k)))
        .max_by(|a, b| a.1.cmp(&b.1).then(a.0.cmp(&b.0)))?;
    if n < MIN_GROUND {
        return None;
    }
    let (a, b) = (cells(k).len(), cells(k + 1).len());
    let total = a + b;
    let lo = if 4 * a >= total { k } else { k + 1 };
    let hi = if 4 * b >= total { k + 1 } else { k };
    let floor = if b > a { k + 1 } else { k };
    Some((lo, floor, hi))
}

/// Cells a surface must show, full with their four neighbours, to be
/// taken for the ground.
pub const MIN_GROUND: usize = 8;

/// How many of the map's full cells lie within `radius` of `at`: a
/// foothold the memory still holds there, or no longer.
pub fn cells_near(memory: &Octree, plane: f32, at: Vec3, radius: f32) -> u32 {
    let region = Region {
        centre: at,
        range: radius,
        plane,
    };
    map_cells(memory, &region).len() as u32
}

/// Whether the memory holds a full voxel over the straight way from `a`
/// to `b` (on the plane), from two layers above the plane's up to height
/// `top`: something the actor would walk into, or set its foot on.
pub fn way_blocked(memory: &Octree, plane: f32, a: Vec3, b: Vec3, top: f32) -> bool {
    let (Some(k), Some(t)) = (layer(memory, plane), layer(memory, top)) else {
        return false;
    };
    let lo = k + 2;
    if t < lo {
        return false;
    }
    let e = memory.cube().voxel_edge as f32;
    let n = (a.distance(b) / (0.5 * e)).ceil().max(1.0) as u32;
    (0..=n).any(|i| {
        let p = a.lerp(b, i as f32 / n as f32);
        (lo..=t).any(|y| {
            let q = [
                f64::from(p.x),
                layer_height(memory, y).into(),
                f64::from(p.z),
            ];
            memory.voxel(q).is_some_and(|v| memory.get(v).is_some())
        })
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::actors::perception::octree::Cube;

    /// A memory of voxel 0.1 over −8..8 with square stones (centre x, z
    /// and n cells a side) whose tops fill layer 79 (y −0.1..0), their
    /// sides ringing the two layers under it.
    pub(super) fn field(stones: &[(f32, f32, u32)]) -> Octree {
        let mut t = Octree::new(Cube::new(-8.0, 8.0, 0.1), true);
        for &(x, z, n) in stones {
            let half = 0.1 * (n as f32 - 1.0) / 2.0;
            let [vx, _, vz] = t
                .voxel([f64::from(x - half), -0.05, f64::from(z - half)])
                .expect("inside");
            for i in 0..n {
                for j in 0..n {
                    t.insert([vx + i, 79, vz + j], 1);
                    if i == 0 || j == 0 || i == n - 1 || j == n - 1 {
                        t.insert([vx + i, 78, vz + j], 1);
                        t.insert([vx + i, 77, vz + j], 1);
                    }
                }
            }
        }
        t
    }

    fn region(range: f32) -> Region {
        Region {
            centre: Vec3::ZERO,
            range,
            plane: -0.01,
        }
    }

    /// A floor of 20 × 20 voxels in layer 40 (some of it spilt into 41,
    /// a surface on a layer boundary), a wall of 20 voxels in every layer
    /// 41..=60: the ground is 40 with 41, under an eye in layer 55.
    fn floor_and_wall(spilt: u32) -> Octree {
        let mut t = Octree::new(Cube::new(-8.0, 8.0, 0.1), false);
        for x in 70..90 {
            for z in 70..90 {
                let y = if (x - 70) * 20 + (z - 70) < spilt {
                    41
                } else {
                    40
                };
                t.insert([x, y, z], 1);
            }
            for y in 41..=60 {
                t.insert([x, y, 95], 1);
            }
        }
        t
    }

    #[test]
    fn the_ground_stands_out_of_the_walls() {
        let r = region(5.0);
        assert_eq!(
            ground_layers(&floor_and_wall(0), &r, 55),
            Some((40, 40, 40))
        );
        assert_eq!(
            ground_layers(&floor_and_wall(150), &r, 55),
            Some((40, 40, 41))
        );
        // Walls alone: no layer stands out, no ground.
        let mut walls = Octree::new(Cube::new(-8.0, 8.0, 0.1), false);
        for y in 30..=60 {
            for x in 70..90 {
                walls.insert([x, y, 95], 1);
            }
        }
        assert_eq!(ground_layers(&walls, &r, 55), None);
        // The eye's own layer counts; nothing over it does.
        assert_eq!(
            ground_layers(&floor_and_wall(0), &r, 40),
            Some((40, 40, 40))
        );
        assert_eq!(ground_layers(&floor_and_wall(0), &r, 39), None);
    }

    #[test]
    fn every_stone_is_found_at_its_centre() {
        let stones = [(0.0, 0.0, 3), (1.0, 0.3, 3), (-1.2, 2.0, 4)];
        let map = local_map(&field(&stones), &region(5.0), 4, 0.3);
        assert_eq!(map.len(), 3, "{map:?}");
        for &(x, z, n) in &stones {
            let f = map
                .iter()
                .find(|f| f.ground().distance(Vec2::new(x, z)) < 0.1)
                .unwrap_or_else(|| panic!("no foothold at {x} {z}: {map:?}"));
            assert_eq!(f.voxels, n * n);
            assert_eq!(f.at.y, -0.01);
        }
    }

    #[test]
    fn diagonal_cells_are_apart_and_small_ones_dropped() {
        let mut t = Octree::new(Cube::new(-8.0, 8.0, 0.1), true);
        // Two cells touching at a corner only: two components of one cell.
        t.insert_point([0.05, -0.01, 0.05], 1);
        t.insert_point([0.15, -0.01, 0.15], 1);
        assert!(local_map(&t, &region(5.0), 2, 0.0).is_empty());
        assert_eq!(local_map(&t, &region(5.0), 1, 0.0).len(), 2);
        // Joined as pieces of one foot-sized foothold.
        assert_eq!(local_map(&t, &region(5.0), 1, 0.3).len(), 1);
        // A third joins them by an edge: one component of three.
        t.insert_point([0.15, -0.01, 0.05], 1);
        let map = local_map(&t, &region(5.0), 2, 0.0);
        assert_eq!(map.len(), 1);
        assert_eq!(map[0].voxels, 3);
    }

    #[test]
    fn other_layers_and_far_voxels_are_left_out() {
        let mut t = field(&[(0.0, 0.0, 3)]);
        // The ground far under the stones, and a stone out of range.
        for i in 0..40 {
            t.insert_point([f64::from(i) * 0.1 - 2.0, -1.5, 1.0], 1);
        }
        let far = field(&[(6.0, 0.0, 3)]);
        for (v, l) in far.occupied_voxels() {
            t.insert(v, l);
        }
        let map = local_map(&t, &region(3.0), 4, 0.3);
        assert_eq!(map.len(), 1, "{map:?}");
        assert!(map[0].ground().length() < 0.1);
    }

    #[test]
    fn the_busiest_layer_is_the_stones_tops() {
        let t = field(&[(0.0, 0.0, 3), (1.0, 1.0, 3), (2.0, 0.0, 3)]);
        let y = busiest_layer(&t, &region(5.0), 1.0).unwrap();
        assert!((-0.1..0.0).contains(&y), "{y}");
    }

    #[test]
    fn a_way_is_blocked_by_what_stands_on_it() {
        let mut t = field(&[(0.0, 0.0, 3), (1.0, 0.0, 3)]);
        let (a, b) = (Vec3::new(0.0, 0.0, 0.0), Vec3::new(1.0, 0.0, 0.0));
        assert!(!way_blocked(&t, -0.01, a, b, 1.0));
        t.insert_point([0.5, 0.55, 0.02], 1);
        assert!(way_blocked(&t, -0.01, a, b, 1.0));
        assert!(!way_blocked(&t, -0.01, a, b, 0.4));
        assert_eq!(cells_near(&t, -0.01, b, 0.3), 9);
        assert_eq!(cells_near(&t, -0.01, Vec3::new(0.5, 0.0, 0.0), 0.2), 0);
    }
}
