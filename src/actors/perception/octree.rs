//! The octree of an actor's visual memory (thesis 3.1.3, 6.3.1).
//!
//! A world point p becomes integer voxel coordinates by eq. 6.3.1,
//! `P_octree(i) = trunc((translation(i) + p(i)) · scaling)` with
//! translation = −min and scaling = 1 / voxel edge. The cube holds
//! `range = 2^levels` voxels along each edge (eq. 6.3.2, Hbit = levels + 1);
//! a voxel at depth d (the root is depth 0) has an edge of
//! `2^(levels − d)` voxels (eq. 6.3.3 with depth_level = d + 1). The son of
//! a depth-d node that holds a point is chosen by bit `levels − 1 − d` of
//! its x, y and z coordinates: son = 4·x_bit + 2·y_bit + z_bit (one octal
//! digit per level, most significant level first).
//!
//! Storage follows figure 6.3.2: a node has 8 son pointers, each with a
//! label, a father pointer and a depth. A pointer is 0 (NIL, free), 1
//! (occupied) or the index (≥ 2) of the node that subdivides the son.
//! Nodes live in one flat `Vec` (indices 0 and 1 are never nodes: slot 0
//! is the root, and index 1 is reserved so that 1 can mean "occupied");
//! freed nodes go on a free list and are reused last-freed-first, so the
//! layout depends only on the sequence of operations (DESIGN §4).
//!
//! When a node's eight sons are all occupied and merging is on, the node is
//! deleted and its father's pointer set to 1, recursively toward the root;
//! the merged voxel's label is the largest of its sons' labels.

/// Integer voxel coordinates in the cube, 0 ≤ x, y, z < 2^levels.
pub type Voxel = [u32; 3];

/// Pointer value of a free son.
const FREE: u32 = 0;
/// Pointer value of an occupied son.
const FULL: u32 = 1;
/// Index of the root node.
const ROOT: u32 = 0;
/// Most levels an octree may have (`MAX_VOXELS_PER_EDGE` = 2^20).
pub const MAX_LEVELS: u32 = 20;

/// One node: a voxel subdivided into eight sons.
#[derive(Debug, Clone, Copy)]
struct Node {
    son: [u32; 8],
    label: [u32; 8],
    father: u32,
    /// Which son of its father this node is.
    slot: u8,
    depth: u8,
}

impl Node {
    fn new(father: u32, slot: u8, depth: u8) -> Self {
        Node {
            son: [FREE; 8],
            label: [0; 8],
            father,
            slot,
            depth,
        }
    }
}

/// The world cube of `init min max voxel_edge`: the cube from
/// (min, min, min) to (max, max, max) cut into voxels of the given edge.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Cube {
    pub min: f64,
    pub max: f64,
    pub voxel_edge: f64,
}

impl Cube {
    pub fn new(min: f64, max: f64, voxel_edge: f64) -> Self {
        Cube {
            min,
            max,
            voxel_edge,
        }
    }

    /// Levels of subdivision: the least L with 2^L voxels ≥ the cube's
    /// edge in voxels (at least 1, at most [`MAX_LEVELS`]).
    pub fn levels(&self) -> u32 {
        let n = ((self.max - self.min) / self.voxel_edge).ceil();
        let mut l = 1;
        while l < MAX_LEVELS && ((1u64 << l) as f64) < n {
            l += 1;
        }
        l
    }
}

/// An octree of occupied voxels over a [`Cube`], each occupied voxel with
/// a `u32` label (the frame it was last seen in, or a counter).
#[derive(Debug, Clone)]
pub struct Octree {
    cube: Cube,
    scaling: f64,
    levels: u32,
    /// Voxels per edge the cube really holds (the `init` max bounds it).
    limit: u32,
    merge: bool,
    nodes: Vec<Node>,
    free: Vec<u32>,
    /// Occupied voxels, counted at the finest level.
    voxels: u64,
    /// Occupied pointers (a merged father counts once).
    occupied: u64,
    /// The last finest-level node touched and its coordinates >> 1: most
    /// consecutive points of a scan fall into the same node.
    cache: Option<(Voxel, u32)>,
}

impl Octree {
    /// An empty octree over `cube`; `merge` says whether eight occupied
    /// sons are merged into their father.
    pub fn new(cube: Cube, merge: bool) -> Self {
        let levels = cube.levels();
        let n = ((cube.max - cube.min) / cube.voxel_edge).ceil();
        let limit = if n.is_finite() && n >= 1.0 {
            (n as u64).min(1u64 << levels) as u32
        } else {
            1
        };
        Octree {
            cube,
            scaling: 1.0 / cube.voxel_edge,
            levels,
            limit,
            merge,
            nodes: vec![Node::new(ROOT, 0, 0), Node::new(ROOT, 0, 0)],
            free: Vec::new(),
            voxels: 0,
            occupied: 0,
            cache: None,
        }
    }

    pub fn cube(&self) -> Cube {
        self.cube
    }

    /// Levels of subdivision below the root.
    pub fn levels(&self) -> u32 {
        self.levels
    }

    /// Voxels along an edge of the cube (a voxel coordinate is below it).
    pub fn voxels_per_edge(&self) -> u32 {
        self.limit
    }

    /// Eq. 6.3.1: the voxel holding world point p, None outside the cube.
    pub fn voxel(&self, p: [f64; 3]) -> Option<Voxel> {
        let mut v = [0u32; 3];
        for i in 0..3 {
            let q = (p[i] - self.cube.min) * self.scaling;
            // trunc equals floor here: q ≥ 0 (NaN fails the test).
            if !(q >= 0.0 && q < f64::from(self.limit)) {
                return None;
            }
            v[i] = q as u32;
        }
        Some(v)
    }

    /// The world box of voxel v at the finest level: (min corner, edge).
    pub fn voxel_box(&self, v: Voxel) -> ([f64; 3], f64) {
        let e = self.cube.voxel_edge;
        (v.map(|c| self.cube.min + f64::from(c) * e), e)
    }

    /// The world centre of voxel v.
    pub fn centre(&self, v: Voxel) -> [f64; 3] {
        let e = self.cube.voxel_edge;
        v.map(|c| self.cube.min + (f64::from(c) + 0.5) * e)
    }

    /// Son index of v at depth d (the son of a depth-d node).
    #[inline]
    pub fn son_at(&self, v: Voxel, d: u32) -> usize {
        let b = self.levels - 1 - d;
        (((v[0] >> b) & 1) << 2 | ((v[1] >> b) & 1) << 1 | ((v[2] >> b) & 1)) as usize
    }

    /// The path of sons from the root to voxel v, one octal digit per level.
    pub fn path(&self, v: Voxel) -> Vec<u8> {
        (0..self.levels).map(|d| self.son_at(v, d) as u8).collect()
    }

    /// The voxel a path of sons leads to (the inverse of [`Octree::path`]
    /// for a full path; a shorter path gives the min corner of its voxel).
    pub fn voxel_of_path(&self, path: &[u8]) -> Voxel {
        let mut v = [0u32; 3];
        for (d, &s) in path.iter().enumerate() {
            let b = self.levels - 1 - d as u32;
            v[0] |= u32::from(s >> 2 & 1) << b;
            v[1] |= u32::from(s >> 1 & 1) << b;
            v[2] |= u32::from(s & 1) << b;
        }
        v
    }

    /// Eq. 6.3.4–6.3.6: the neighbours of v at the finest level (edge_size
    /// 1), in the order i, j, k = −1, 0, 1 (k fastest); 26 inside the
    /// cube, fewer at its faces.
    pub fn neighbours(&self, v: Voxel) -> Vec<Voxel> {
        self.neighbours_at(v, self.levels)
    }

    /// The neighbours of the voxel holding v at depth `depth`
    /// (edge_size = 2^(levels − depth)), as their min corners.
    pub fn neighbours_at(&self, v: Voxel, depth: u32) -> Vec<Voxel> {
        let shift = self.levels - depth.min(self.levels);
        let edge = 1i64 << shift;
        let base = v.map(|c| i64::from(c >> shift << shift));
        let mut out = Vec::with_capacity(26);
        for i in -1..=1i64 {
            for j in -1..=1i64 {
                for k in -1..=1i64 {
                    if i == 0 && j == 0 && k == 0 {
                        continue;
                    }
                    let n = [base[0] + i * edge, base[1] + j * edge, base[2] + k * edge];
                    if n.iter().all(|&c| c >= 0 && c < i64::from(self.limit)) {
                        out.push(n.map(|c| c as u32));
                    }
                }
            }
        }
        out
    }

    fn alloc(&mut self, father: u32, slot: u8, depth: u8) -> u32 {
        let node = Node::new(father, slot, depth);
        if let Some(i) = self.free.pop() {
            self.nodes[i as usize] = node;
            i
        } else {
            self.nodes.push(node);
            (self.nodes.len() - 1) as u32
        }
    }

    fn release(&mut self, i: u32) {
        self.free.push(i);
        if matches!(self.cache, Some((_, c)) if c == i) {
            self.cache = None;
        }
    }

    /// Marks the voxel holding world point p occupied with `label` (the
    /// frame number); false when p is outside the cube.
    #[inline]
    pub fn insert_point(&mut self, p: [f64; 3], label: u32) -> bool {
        match self.voxel(p) {
            Some(v) => {
                self.insert(v, label);
                true
            }
            None => false,
        }
    }

    /// Marks voxel v occupied with `label`; a voxel already occupied takes
    /// the new label (a merged voxel holding v is relabelled as a whole).
    #[inline]
    pub fn insert(&mut self, v: Voxel, label: u32) {
        self.update(v, |l| *l = label, label);
    }

    /// Adds one to the label of voxel v, occupying it with label 1 if it
    /// was free (the auxiliary octree X of 3.1.4).
    pub fn count(&mut self, v: Voxel) {
        self.update(v, |l| *l = l.saturating_add(1), 1);
    }

    fn update(&mut self, v: Voxel, touch: impl Fn(&mut u32), fresh: u32) {
        let key = v.map(|c| c >> 1);
        let last = self.levels - 1;
        let mut n = match self.cache {
            Some((k, n)) if k == key => n,
            _ => {
                let mut n = ROOT;
                for d in 0..last {
                    let s = self.son_at(v, d);
                    let p = self.nodes[n as usize].son[s];
                    n = match p {
                        FREE => {
                            let c = self.alloc(n, s as u8, d as u8 + 1);
                            self.nodes[n as usize].son[s] = c;
                            c
                        }
                        FULL => {
                            touch(&mut self.nodes[n as usize].label[s]);
                            return;
                        }
                        c => c,
                    };
                }
                self.cache = Some((key, n));
                n
            }
        };
        let s = self.son_at(v, last);
        let node = &mut self.nodes[n as usize];
        if node.son[s] == FULL {
            touch(&mut node.label[s]);
            return;
        }
        node.son[s] = FULL;
        node.label[s] = fresh;
        self.voxels += 1;
        self.occupied += 1;
        // Merge eight occupied sons into their father, toward the root.
        while self.merge && n != ROOT && self.nodes[n as usize].son == [FULL; 8] {
            let node = self.nodes[n as usize];
            let label = node.label.iter().copied().max().unwrap_or(0);
            let (f, slot) = (node.father, node.slot as usize);
            self.nodes[f as usize].son[slot] = FULL;
            self.nodes[f as usize].label[slot] = label;
            self.occupied -= 7;
            self.release(n);
            n = f;
        }
    }

    /// The label of voxel v if it is occupied (that of the merged voxel
    /// holding it, if merged).
    pub fn get(&self, v: Voxel) -> Option<u32> {
        let mut n = ROOT;
        for d in 0..self.levels {
            let s = self.son_at(v, d);
            let node = &self.nodes[n as usize];
            match node.son[s] {
                FREE => return None,
                FULL => return Some(node.label[s]),
                c => n = c,
            }
        }
        None
    }

    /// Frees voxel v, splitting the merged voxels that hold it; returns
    /// whether it was occupied. A node left with no occupied son is
    /// deleted, toward the root.
    pub fn remove(&mut self, v: Voxel) -> bool {
        let mut n = ROOT;
        for d in 0..self.levels {
            let s = self.son_at(v, d);
            let p = self.nodes[n as usize].son[s];
            match p {
                FREE => return false,
                FULL if d + 1 < self.levels => {
                    // Split the merged voxel into eight occupied sons.
                    let label = self.nodes[n as usize].label[s];
                    let c = self.alloc(n, s as u8, d as u8 + 1);
                    self.nodes[c as usize].son = [FULL; 8];
                    self.nodes[c as usize].label = [label; 8];
                    self.nodes[n as usize].son[s] = c;
                    self.occupied += 7;
                    n = c;
                }
                FULL => {
                    self.nodes[n as usize].son[s] = FREE;
                    self.nodes[n as usize].label[s] = 0;
                    self.voxels -= 1;
                    self.occupied -= 1;
                    while n != ROOT && self.nodes[n as usize].son == [FREE; 8] {
                        let node = self.nodes[n as usize];
                        self.nodes[node.father as usize].son[node.slot as usize] = FREE;
                        self.release(n);
                        n = node.father;
                    }
                    return true;
                }
                c => n = c,
            }
        }
        false
    }

    /// Empties the tree (the reinitialisation of X after an elimination).
    pub fn clear(&mut self) {
        self.nodes.truncate(2);
        self.nodes[0] = Node::new(ROOT, 0, 0);
        self.free.clear();
        self.voxels = 0;
        self.occupied = 0;
        self.cache = None;
    }

    /// Occupied voxels counted at the finest level (a merged voxel of
    /// depth d counts 8^(levels − d)): `memory_voxels`.
    pub fn voxel_count(&self) -> u64 {
        self.voxels
    }

    /// Occupied voxels as stored (a merged voxel counts once).
    pub fn stored_count(&self) -> u64 {
        self.occupied
    }

    /// Bytes the tree holds: its node array's capacity and free list.
    pub fn memory_bytes(&self) -> usize {
        std::mem::size_of::<Self>()
            + self.nodes.capacity() * std::mem::size_of::<Node>()
            + self.free.capacity() * std::mem::size_of::<u32>()
    }

    /// Every occupied voxel as stored, in son order (depth first, son 0
    /// first): (min corner, depth, label). A voxel of depth d spans
    /// 2^(levels − d) finest voxels along each edge.
    pub fn occupied(&self) -> Vec<(Voxel, u32, u32)> {
        let mut out = Vec::with_capacity(self.occupied as usize);
        self.walk(|v, d, l| out.push((v, d, l)), |_, _| true);
        out
    }

    /// Every occupied voxel at the finest level (merged voxels expanded),
    /// in son order, with its label.
    pub fn occupied_voxels(&self) -> Vec<(Voxel, u32)> {
        let mut out = Vec::with_capacity(self.voxels as usize);
        self.for_each_voxel(|v, l| out.push((v, l)), |_, _| true);
        out
    }

    /// Calls `f(voxel, label)` for every occupied finest-level voxel
    /// (merged voxels expanded) in son order, skipping the subtrees whose
    /// cube (min corner, edge in voxels) `enter` refuses.
    pub fn for_each_voxel(
        &self,
        mut f: impl FnMut(Voxel, u32),
        mut enter: impl FnMut(Voxel, u32) -> bool,
    ) {
        self.walk_node(ROOT, [0; 3], true, &mut |v, _, l| f(v, l), &mut enter);
    }

    /// Depth-first walk of the occupied pointers in son order: `f(min
    /// corner, depth, label)`; `enter(min corner, edge)` prunes subtrees
    /// and voxels.
    fn walk(&self, mut f: impl FnMut(Voxel, u32, u32), mut enter: impl FnMut(Voxel, u32) -> bool) {
        self.walk_node(ROOT, [0; 3], false, &mut f, &mut enter);
    }

    /// The walk below node `n` (min corner `base`); with `expand`, an
    /// occupied voxel above the finest level is reported as its finest
    /// voxels.
    fn walk_node(
        &self,
        n: u32,
        base: Voxel,
        expand: bool,
        f: &mut impl FnMut(Voxel, u32, u32),
        enter: &mut impl FnMut(Voxel, u32) -> bool,
    ) {
        let node = &self.nodes[n as usize];
        let d = u32::from(node.depth);
        let e = 1u32 << (self.levels - d - 1);
        for s in 0..8u32 {
            let p = node.son[s as usize];
            if p == FREE {
                continue;
            }
            let v = son_corner(base, s, e);
            if !enter(v, e) {
                continue;
            }
            let label = node.label[s as usize];
            if p != FULL {
                self.walk_node(p, v, expand, f, enter);
            } else if expand && e > 1 {
                expand_cube(v, e, self.levels, label, f, enter);
            } else {
                f(v, d + 1, label);
            }
        }
    }
}

/// The min corner of son `s` of the cube at `base` whose sons have edge
/// `e` (son = 4·x_bit + 2·y_bit + z_bit).
fn son_corner(base: Voxel, s: u32, e: u32) -> Voxel {
    [
        base[0] + ((s >> 2) & 1) * e,
        base[1] + ((s >> 1) & 1) * e,
        base[2] + (s & 1) * e,
    ]
}

/// Calls `f(voxel, depth, l)` for each finest voxel (depth `levels`) of
/// the occupied cube (v, edge e), pruning with `enter`.
fn expand_cube(
    v: Voxel,
    e: u32,
    levels: u32,
    l: u32,
    f: &mut impl FnMut(Voxel, u32, u32),
    enter: &mut impl FnMut(Voxel, u32) -> bool,
) {
    let h = e / 2;
    for s in 0..8u32 {
        let c = son_corner(v, s, h);
        if !enter(c, h) {
            continue;
        }
        if h == 1 {
            f(c, levels, l);
        } else {
            expand_cube(c, h, levels, l, f, enter);
        }
    }
}
