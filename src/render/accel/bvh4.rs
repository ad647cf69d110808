//! A 4-wide BVH with uncompressed boxes, collapsed from the binary tree
//! obvhs builds (its fast preset: PLOC + reinsertion).
//!
//! Why not obvhs's CWBVH for traversal: its 8-bit quantised child boxes
//! must be widened to floats one byte at a time on baseline x86-64
//! (SSE2), and converting the binary tree into it took ~40 % of the build.
//! Four float boxes in structure-of-arrays form are tested with one
//! 4-wide slab test (glam's `Vec4`: SSE2 on x86-64, NEON or scalar
//! elsewhere, the same IEEE operations everywhere), and the collapse is a
//! single pass. The traversal stack is sized from the tree's measured
//! depth, so no tree is too deep for it.

use super::hull::Hull;
use super::packet::{Bits, RayPacket};
use super::ray::Ray;
use crate::aabb::Aabb;
use crate::render::simd::wide::{Mask, Wide};
use crate::render::simd::Lanes;
use glam::Vec4;
use obvhs::bvh2::reinsertion::ReinsertionOptimizer;
use obvhs::bvh2::{Bvh2, Bvh2Node};
use obvhs::ploc::build_ploc_from_leafs;
use obvhs::BvhBuildParams;
use rayon::slice::ParallelSliceMut;

/// Child slot tag: a leaf (index into `leaves`) rather than a node.
const LEAF: u32 = 1 << 31;
/// An unused child slot (its box is inverted, so no ray enters it).
const EMPTY: u32 = u32::MAX;
/// Traversal stacks up to this size live on the call stack.
const INLINE_STACK: usize = 64;

/// Four children's boxes, one `Vec4` per side and axis: `side[0]` the
/// least corners, `side[1]` the greatest. A ray picks its near and far
/// side per axis by its direction's sign, so the walk indexes the sides
/// by that sign (one offset per ray, no selection per node).
#[derive(Clone, Copy)]
#[repr(C, align(64))]
struct Node {
    side: [[Vec4; 3]; 2],
    child: [u32; 4],
}

impl Node {
    fn empty() -> Node {
        Node {
            side: [[Vec4::INFINITY; 3], [Vec4::NEG_INFINITY; 3]],
            child: [EMPTY; 4],
        }
    }

    fn set(&mut self, lane: usize, b: &Aabb, child: u32) {
        for a in 0..3 {
            self.side[0][a][lane] = b.min[a];
            self.side[1][a][lane] = b.max[a];
        }
        self.child[lane] = child;
    }
}

/// A built tree: nodes, and leaves as ranges of input indices.
pub struct Bvh4 {
    nodes: Vec<Node>,
    root: u32,
    /// `(first, count)` into `prims` per leaf.
    leaves: Vec<(u32, u32)>,
    /// Input indices, leaf after leaf.
    prims: Vec<u32>,
    /// Entries a traversal can need at most (3 per level + 1).
    stack_size: usize,
    bounds: Aabb,
}

/// The nodes renumbered depth-first from the root (at 0), sibling pairs
/// kept together: children come after their parent, so the passes below
/// read the nodes mostly in sequence instead of missing the cache.
/// (obvhs's own reordering assumes the root's children sit at 1 and 2,
/// which its reinsertion pass does not keep.)
fn depth_first(nodes: &[Bvh2Node]) -> Vec<Bvh2Node> {
    let mut out = Vec::with_capacity(nodes.len());
    out.push(nodes[0]);
    let mut todo = if nodes[0].is_leaf() {
        vec![]
    } else {
        vec![0usize]
    };
    while let Some(p) = todo.pop() {
        let old = out[p].first_index as usize;
        let first = out.len();
        out[p].first_index = first as u32;
        out.push(nodes[old]);
        out.push(nodes[old + 1]);
        for k in [first + 1, first] {
            if !out[k].is_leaf() {
                todo.push(k);
            }
        }
    }
    out
}

/// Relative costs of one 4-wide node test and one packed leaf test (of
/// up to four primitives) for the surface-area heuristic.
const NODE_COST: f32 = 1.0;
const PACK_COST: f32 = 1.0;

/// Which binary nodes become leaves, bottom-up: a subtree of at most
/// `max_leaf` primitives is a leaf when the surface-area heuristic says
/// testing all its primitives beats descending. A 4-wide
/// node stands for about three binary ones, so each binary node is
/// charged a third of a node test. Also returns each node's primitive
/// count.
fn leaf_choice(b: &Bvh2, max_leaf: u32) -> (Vec<bool>, Vec<u32>) {
    let mut count = vec![0u32; b.nodes.len()];
    let mut cost = vec![0f32; b.nodes.len()];
    let mut leaf = vec![false; b.nodes.len()];
    // Children come after their parent (depth-first order): a backward
    // scan meets them first.
    for (i, n) in b.nodes.iter().enumerate().rev() {
        let area = n.aabb.half_area();
        if n.is_leaf() {
            count[i] = n.prim_count;
            cost[i] = area * PACK_COST * n.prim_count.div_ceil(4) as f32;
            leaf[i] = true;
            continue;
        }
        let (l, r) = (n.first_index as usize, n.first_index as usize + 1);
        debug_assert!(l > i, "nodes in depth-first order");
        count[i] = count[l] + count[r];
        let split = area * NODE_COST / 3.0 + cost[l] + cost[r];
        let whole = area * PACK_COST * count[i].div_ceil(4) as f32;
        leaf[i] = count[i] <= max_leaf && whole <= split;
        cost[i] = if leaf[i] { whole } else { split };
    }
    (leaf, count)
}

/// Most boxes with one centre left to PLOC, which merges such a run in
/// as many extra passes. Each quad of a mesh is two triangles with one
/// box: grouping those pairs took a third of the forest's build and gave
/// the very same tree.
const SMALL_RUN: usize = 8;

/// Primitives whose boxes share a centre, grouped: PLOC pairs nodes by
/// their Morton codes and merges only mutual nearest pairs, so n
/// coincident boxes (all one code, all one merged area) merged one pair
/// per pass: O(n²), minutes for 10⁵ identical faces. Each group becomes
/// one leaf node for PLOC (its members in `order`, smallest box first,
/// then input order), which [`split_leaves`] divides afterwards. None
/// when no more than [`SMALL_RUN`] centres coincide: the plain build.
fn coincident(aabbs: &[Aabb]) -> Option<(Vec<Bvh2Node>, Vec<u32>)> {
    let key = |b: &Aabb| b.center().to_array().map(f32::to_bits);
    // First a sort of 64-bit digests of the centres, a few percent of the
    // build (a hash map of every primitive cost a third of it); equal
    // digests are then told apart exactly.
    let mut digests: Vec<u64> = aabbs
        .iter()
        .map(|b| {
            let [x, y, z] = key(b).map(u64::from);
            (x << 32 | y).wrapping_mul(0x9e37_79b9_7f4a_7c15) ^ z
        })
        .collect();
    // Equal keys are equal bits: any sort gives the same order, so the
    // parallel one is deterministic.
    digests.par_sort_unstable();
    if digests
        .chunk_by(|a, b| a == b)
        .all(|r| r.len() <= SMALL_RUN)
    {
        return None;
    }
    // Sorted by centre, then index.
    let mut keyed: Vec<([u32; 3], u32)> = aabbs
        .iter()
        .enumerate()
        .map(|(i, b)| (key(b), i as u32))
        .collect();
    keyed.sort_unstable();
    if keyed.windows(2).all(|w| w[0].0 != w[1].0) {
        return None;
    }
    // One run per centre, in the order of its first member.
    let mut runs: Vec<&[([u32; 3], u32)]> = keyed.chunk_by(|a, b| a.0 == b.0).collect();
    runs.sort_unstable_by_key(|r| r[0].1);
    let mut leaves = Vec::with_capacity(runs.len());
    let mut order = Vec::with_capacity(aabbs.len());
    let area = |k: u32| aabbs[k as usize].half_area();
    for run in runs {
        let start = order.len();
        order.extend(run.iter().map(|&(_, i)| i));
        order[start..].sort_by(|&a, &b| area(a).total_cmp(&area(b)).then(a.cmp(&b)));
        let aabb = order[start..]
            .iter()
            .fold(Aabb::empty(), |t, &k| t.union(&aabbs[k as usize]));
        leaves.push(Bvh2Node::new(aabb, run.len() as u32, start as u32));
    }
    Some((leaves, order))
}

/// Halves every leaf of more than `max_leaf` primitives (in their
/// order) until none is: a balanced subtree, so a group of coincident
/// boxes is as deep as log₂ of its size, and no leaf holds more than
/// `max_leaf`. New nodes go at the end (children after their parent).
fn split_leaves(b: &mut Bvh2, aabbs: &[Aabb], max_leaf: u32) {
    let max_leaf = max_leaf.max(1);
    let mut todo: Vec<usize> = (0..b.nodes.len())
        .filter(|&i| b.nodes[i].prim_count > max_leaf)
        .collect();
    while let Some(i) = todo.pop() {
        let n = b.nodes[i];
        let half = n.prim_count / 2;
        let first = b.nodes.len();
        for (start, count) in [
            (n.first_index, half),
            (n.first_index + half, n.prim_count - half),
        ] {
            let members = &b.primitive_indices[start as usize..(start + count) as usize];
            let aabb = members
                .iter()
                .fold(Aabb::empty(), |t, &k| t.union(&aabbs[k as usize]));
            if count > max_leaf {
                todo.push(b.nodes.len());
            }
            b.nodes.push(Bvh2Node::new(aabb, count, start));
        }
        b.nodes[i] = Bvh2Node::new(n.aabb, 0, first as u32);
    }
}

impl Bvh4 {
    /// Builds over `aabbs` (all finite); leaves hold at most `max_leaf`
    /// primitives (more only where obvhs made a bigger leaf). `None` when
    /// empty.
    pub fn build(aabbs: &[Aabb], max_leaf: u32) -> Option<Bvh4> {
        if aabbs.is_empty() {
            return None;
        }
        let p = BvhBuildParams::fast_build();
        let mut b = match coincident(aabbs) {
            None => p.ploc_search_distance.build(
                aabbs,
                (0..aabbs.len() as u32).collect(),
                p.sort_precision,
                p.search_depth_threshold,
            ),
            Some((leaves, order)) => {
                let total = leaves.iter().fold(Aabb::empty(), |t, n| t.union(&n.aabb));
                Bvh2 {
                    // 6: fast_build's search distance (PlocSearchDistance::Low).
                    nodes: build_ploc_from_leafs::<6>(
                        leaves,
                        total,
                        p.sort_precision,
                        p.search_depth_threshold,
                    ),
                    primitive_indices: order,
                    max_depth: None,
                }
            }
        };
        ReinsertionOptimizer::run(&mut b, p.reinsertion_batch_ratio, None);
        split_leaves(&mut b, aabbs, max_leaf);
        b.nodes = depth_first(&b.nodes);
        Some(Self::collapse(&b, max_leaf))
    }

    fn collapse(b: &Bvh2, max_leaf: u32) -> Bvh4 {
        let (leaf, count) = leaf_choice(b, max_leaf);
        let is_leaf = |i: usize| leaf[i];
        let mut out = Bvh4 {
            nodes: Vec::with_capacity(b.nodes.len() / 3 + 1),
            root: 0,
            leaves: Vec::new(),
            prims: Vec::with_capacity(b.primitive_indices.len()),
            stack_size: 1,
            bounds: b.nodes[0].aabb,
        };
        // (binary node, depth, slot to fill: node and lane, or the root)
        let mut todo = vec![(0usize, 1usize, None::<(usize, usize)>)];
        let mut gather = Vec::new();
        while let Some((i, depth, slot)) = todo.pop() {
            out.stack_size = out.stack_size.max(3 * depth + 1);
            let code = if is_leaf(i) {
                let first = out.prims.len() as u32;
                gather.push(i);
                while let Some(j) = gather.pop() {
                    let n = &b.nodes[j];
                    if n.is_leaf() {
                        let r = n.first_index as usize..(n.first_index + n.prim_count) as usize;
                        out.prims.extend_from_slice(&b.primitive_indices[r]);
                    } else {
                        gather.push(n.first_index as usize + 1);
                        gather.push(n.first_index as usize);
                    }
                }
                out.leaves.push((first, out.prims.len() as u32 - first));
                LEAF | (out.leaves.len() as u32 - 1)
            } else {
                // Open the largest inner child until there are four.
                let f = b.nodes[i].first_index as usize;
                let (mut kids, mut len) = ([f, f + 1, 0, 0], 2);
                while len < 4 {
                    // Equal areas (coincident boxes): the fuller child, so
                    // a balanced tree stays balanced.
                    let widest = (0..len).filter(|&k| !is_leaf(kids[k])).max_by(|&a, &c| {
                        let (sa, sc) = (b.nodes[kids[a]].aabb, b.nodes[kids[c]].aabb);
                        let fuller = count[kids[a]].cmp(&count[kids[c]]);
                        sa.half_area().total_cmp(&sc.half_area()).then(fuller)
                    });
                    let Some(w) = widest else { break };
                    let f = b.nodes[kids[w]].first_index as usize;
                    kids.copy_within(w + 1..len, w + 2);
                    kids[w] = f;
                    kids[w + 1] = f + 1;
                    len += 1;
                }
                let mut node = Node::empty();
                let at = out.nodes.len();
                for (lane, &k) in kids[..len].iter().enumerate() {
                    node.set(lane, &b.nodes[k].aabb, EMPTY);
                    todo.push((k, depth + 1, Some((at, lane))));
                }
                out.nodes.push(node);
                at as u32
            };
            match slot {
                Some((n, lane)) => out.nodes[n].child[lane] = code,
                None => out.root = code,
            }
        }
        out
    }

    /// Gives leaf `l` the code `code(l)` (below 2³¹), which traversals
    /// hand to their leaf callback instead of `l`: the owner's own handle
    /// on the leaf's data, so a leaf visit needs no lookup table.
    pub fn set_leaf_codes(&mut self, code: impl Fn(u32) -> u32) {
        let mut relabel = |c: &mut u32| {
            if *c != EMPTY && *c & LEAF != 0 {
                let new = code(*c & !LEAF);
                assert!(new < LEAF, "leaf code {new} out of range");
                *c = LEAF | new;
            }
        };
        relabel(&mut self.root);
        for n in &mut self.nodes {
            n.child.iter_mut().for_each(&mut relabel);
        }
    }

    /// Input indices of leaf `l`.
    pub fn leaf(&self, l: u32) -> &[u32] {
        let (first, count) = self.leaves[l as usize];
        &self.prims[first as usize..(first + count) as usize]
    }

    pub fn leaf_count(&self) -> u32 {
        self.leaves.len() as u32
    }

    pub fn bounds(&self) -> Aabb {
        self.bounds
    }

    /// The largest coordinate of the tree's boxes.
    pub fn scale(&self) -> f32 {
        self.bounds
            .min
            .abs()
            .max(self.bounds.max.abs())
            .max_element()
    }

    /// Starts fetching child `code` into the cache as a walk enters it,
    /// so that its load overlaps the tests before its visit: a node's
    /// two cache lines, or (through `leaf`, which knows their layout) a
    /// leaf's primitives. On the forest most visits wait on such loads.
    #[inline(always)]
    fn fetch(&self, code: u32, leaf: &impl Fn(u32)) {
        if code & LEAF == 0 {
            if let Some(node) = self.nodes.get(code as usize) {
                prefetch(node);
            }
        } else {
            leaf(code & !LEAF);
        }
    }

    /// Levels of the tree (tests of deep scenes).
    pub fn depth(&self) -> usize {
        (self.stack_size - 1) / 3
    }

    /// Visits the leaves the ray enters with t in (tmin, `tmax`), nearest
    /// box first, by their codes (see [`Self::set_leaf_codes`]).
    /// `leaf(code, &mut tmax)` may lower `tmax` (closest hit) or return
    /// true to stop; the result is whether it stopped. `fetch(code)`
    /// starts loading a leaf's data when the walk enters it (see
    /// [`Self::fetch`]).
    #[inline]
    pub fn traverse(
        &self,
        ray: &Ray,
        tmax: f32,
        fetch: impl Fn(u32),
        leaf: impl FnMut(u32, &mut f32) -> bool,
    ) -> bool {
        self.with_stack::<true>(ray, tmax, fetch, leaf)
    }

    /// As [`Self::traverse`] but in no particular order (still the same
    /// every time): for any-hit queries, which stop at the first hit.
    #[inline]
    pub fn traverse_any(
        &self,
        ray: &Ray,
        tmax: f32,
        fetch: impl Fn(u32),
        leaf: impl FnMut(u32, &mut f32) -> bool,
    ) -> bool {
        self.with_stack::<false>(ray, tmax, fetch, leaf)
    }

    #[inline(always)]
    fn with_stack<const NEAREST_FIRST: bool>(
        &self,
        ray: &Ray,
        tmax: f32,
        fetch: impl Fn(u32),
        leaf: impl FnMut(u32, &mut f32) -> bool,
    ) -> bool {
        if self.stack_size <= INLINE_STACK {
            let mut stack = [(0u32, 0f32); INLINE_STACK];
            self.walk::<NEAREST_FIRST>(&mut stack, ray, tmax, fetch, leaf)
        } else {
            let mut stack = vec![(0u32, 0f32); self.stack_size];
            self.walk::<NEAREST_FIRST>(&mut stack, ray, tmax, fetch, leaf)
        }
    }

    #[inline(always)]
    fn walk<const NEAREST_FIRST: bool>(
        &self,
        stack: &mut [(u32, f32)],
        ray: &Ray,
        mut tmax: f32,
        fetch: impl Fn(u32),
        mut leaf: impl FnMut(u32, &mut f32) -> bool,
    ) -> bool {
        let (inv, oinv) = (ray.inv, ray.origin_inv);
        let (ix, iy, iz) = (Vec4::splat(inv.x), Vec4::splat(inv.y), Vec4::splat(inv.z));
        let (ox, oy, oz) = (
            Vec4::splat(oinv.x),
            Vec4::splat(oinv.y),
            Vec4::splat(oinv.z),
        );
        let tmin = Vec4::splat(ray.tmin);
        let [nx, ny, nz] = ray.negative;
        // The node or leaf being visited stays out of the stack: a node
        // with one entered child goes straight on to it, and of several
        // the nearest is not pushed (Embree's walk; fewer stack round
        // trips and mispredicted branches than pushing every child).
        let mut cur = self.root;
        let mut sp = 0;
        loop {
            if cur & LEAF != 0 {
                if leaf(cur & !LEAF, &mut tmax) {
                    return true;
                }
            } else {
                let n = &self.nodes[cur as usize];
                let (near_x, far_x) = (n.side[usize::from(nx)][0], n.side[usize::from(!nx)][0]);
                let (near_y, far_y) = (n.side[usize::from(ny)][1], n.side[usize::from(!ny)][1]);
                let (near_z, far_z) = (n.side[usize::from(nz)][2], n.side[usize::from(!nz)][2]);
                let t0 = (near_x * ix - ox)
                    .max(near_y * iy - oy)
                    .max(near_z * iz - oz)
                    .max(tmin);
                let t1 = (far_x * ix - ox)
                    .min(far_y * iy - oy)
                    .min(far_z * iz - oz)
                    .min(Vec4::splat(tmax));
                let mut mask = t0.cmple(t1).bitmask();
                // An array, not the `Vec4`: indexing a `Vec4` by a run-time
                // lane compiles to a jump table.
                let t0 = t0.to_array();
                if mask != 0 {
                    let first = mask.trailing_zeros() as usize;
                    mask &= mask - 1;
                    if mask == 0 {
                        cur = n.child[first];
                        continue;
                    }
                    // Push the entered children farthest first, then take
                    // the nearest back (ties keep slot order: deterministic).
                    let base = sp;
                    let mut lane = first;
                    loop {
                        let e = (n.child[lane], t0[lane]);
                        self.fetch(e.0, &fetch);
                        let mut k = sp;
                        while NEAREST_FIRST && k > base && stack[k - 1].1 < e.1 {
                            stack[k] = stack[k - 1];
                            k -= 1;
                        }
                        stack[k] = e;
                        sp += 1;
                        if mask == 0 {
                            break;
                        }
                        lane = mask.trailing_zeros() as usize;
                        mask &= mask - 1;
                    }
                    sp -= 1;
                    cur = stack[sp].0;
                    continue;
                }
            }
            // Next from the stack, skipping boxes beyond the nearest hit.
            loop {
                if sp == 0 {
                    return false;
                }
                sp -= 1;
                let (code, tnear) = stack[sp];
                if tnear <= tmax {
                    cur = code;
                    break;
                }
            }
        }
    }

    /// A walk of the rays of `live` through the tree for any hit: see
    /// [`BundleWalk`].
    pub fn bundle_walk(&self, live: u32) -> BundleWalk {
        let mut stack = Vec::with_capacity(self.stack_size);
        stack.push((self.root, live));
        BundleWalk { stack, open: live }
    }

    /// A walk of packet `p`'s rays of `live` through the tree: see
    /// [`PacketWalk`].
    #[inline(always)]
    pub fn packet_walk<W: Wide>(&self, p: &RayPacket, live: u32) -> PacketWalk {
        PacketWalk {
            stack: Vec::with_capacity(self.stack_size),
            cur: (self.root, f32::NEG_INFINITY, live),
            pop: false,
            span: PacketBounds::of::<W>(p, self.scale()),
        }
    }
}

/// The leaves that a packet's rays enter before their `tmax`, in no
/// particular order (the same every time), one by one from
/// [`BundleWalk::next`] (a loop, as [`PacketWalk`]). Each ray's box tests
/// are its single walk's; given a region around the rays (see [`Hull`]),
/// they are made only in boxes that may meet it: a node's boxes cost one
/// test for the bundle, and a ray's own test only where the region
/// reaches.
pub struct BundleWalk {
    /// Nodes to visit, with the rays that entered them.
    stack: Vec<(u32, u32)>,
    /// The rays not yet done with.
    open: u32,
}

impl BundleWalk {
    /// Offers later leaves no more to `rays` (those found blocked).
    pub fn close(&mut self, rays: u32) {
        self.open &= !rays;
    }

    /// The next leaf that some open ray of packet `p` enters before its
    /// `tmax`, with the mask of those rays; the tests run in the lane
    /// form `W`. `fetch(code)` starts loading a leaf's data as the walk
    /// enters it.
    #[inline(always)]
    pub fn next<W: Wide>(
        &mut self,
        tree: &Bvh4,
        hull: Option<&Hull>,
        p: &RayPacket,
        tmax: &Lanes,
        fetch: impl Fn(u32),
    ) -> Option<(u32, u32)> {
        let [nx, ny, nz] = p.negative.map(usize::from);
        loop {
            if self.open == 0 {
                return None;
            }
            let (code, rays) = self.stack.pop()?;
            let rays = rays & self.open;
            if rays == 0 {
                continue;
            }
            if code & LEAF != 0 {
                return Some((code & !LEAF, rays));
            }
            let n = &tree.nodes[code as usize];
            let side = |s: usize, a: usize| n.side[s][a].to_array();
            let (near_x, far_x) = (side(nx, 0), side(1 - nx, 0));
            let (near_y, far_y) = (side(ny, 1), side(1 - ny, 1));
            let (near_z, far_z) = (side(nz, 2), side(1 - nz, 2));
            let met = match hull {
                Some(h) => h.meets(&n.side[0], &n.side[1]),
                None => 0b1111,
            };
            // The boxes tested first, then the entered ones pushed:
            // a branch per entered box rather than per test, whose outcome
            // is hard to predict (4–10 % of the forest's render in paired runs).
            let mut entered = [0u32; 4];
            for c in Bits(met) {
                let near = [near_x[c], near_y[c], near_z[c]];
                let far = [far_x[c], far_y[c], far_z[c]];
                entered[c] = enters::<W>(p, near, far, tmax) & rays;
            }
            let pushed = u32::from(entered[0] != 0)
                | u32::from(entered[1] != 0) << 1
                | u32::from(entered[2] != 0) << 2
                | u32::from(entered[3] != 0) << 3;
            for c in Bits(pushed) {
                tree.fetch(n.child[c], &fetch);
                self.stack.push((n.child[c], entered[c]));
            }
        }
    }
}

/// The leaves a packet's rays enter, one by one from [`PacketWalk::next`]
/// (a loop, not a callback, so that the caller's leaf tests are compiled
/// into the same function and with the same SIMD width as the walk).
/// Nearer boxes come first for the packet as a whole.
///
/// An inner node's four boxes are tested once for the whole packet, with
/// bounds on its rays' entry and exit distances ([`PacketBounds`]) that never
/// exclude a box some ray enters; a leaf's box is tested lane by lane,
/// exactly as each ray's single walk tests it. So each ray meets the
/// triangles of the leaves its own walk enters (a box containing a leaf
/// contains its box, and the slab test is monotonic in the box's sides),
/// while the packet's coherent rays share one test per node: the
/// forest's camera packets tested 58 boxes lane by lane per packet, and
/// entered 17 of them.
pub struct PacketWalk {
    /// Nodes to visit: code, the least entry distance of the packet, and
    /// the rays of the packet (of a leaf: those that enter it).
    stack: Vec<(u32, f32, u32)>,
    cur: (u32, f32, u32),
    /// Whether `cur` is done with (the next visit pops the stack).
    pop: bool,
    span: PacketBounds,
}

impl PacketWalk {
    /// The next leaf some ray enters within its `tfar` (which the caller
    /// lowers as it finds hits), with the mask of those rays; the tests
    /// run in the lane form `W`. `fetch(code)` starts loading a leaf's
    /// data as the walk enters it.
    #[inline(always)]
    pub fn next<W: Wide>(
        &mut self,
        tree: &Bvh4,
        p: &RayPacket,
        tfar: &Lanes,
        fetch: impl Fn(u32),
    ) -> Option<(u32, u32)> {
        let [nx, ny, nz] = p.negative.map(usize::from);
        // Over all the lanes: other lanes' distances only loosen it.
        let far = greatest(W::load(tfar));
        loop {
            if self.pop {
                self.cur = self.stack.pop()?;
            }
            self.pop = true;
            let (code, near, rays) = self.cur;
            if near > far {
                continue;
            }
            if code & LEAF != 0 {
                return Some((code & !LEAF, rays));
            }
            let n = &tree.nodes[code as usize];
            let near_sides = [n.side[nx][0], n.side[ny][1], n.side[nz][2]];
            let far_sides = [n.side[1 - nx][0], n.side[1 - ny][1], n.side[1 - nz][2]];
            let (t0, t1) = self.span.entry_exit(&near_sides, &far_sides, far);
            // (`!(t0 > t1)`: a NaN bound excludes nothing.)
            let maybe = !t0.cmpgt(t1).bitmask() & 0b1111;
            let t0 = t0.to_array();
            // Entered children, kept farthest first (ties in slot order).
            let mut kids = [(0u32, 0f32, 0u32); 4];
            let mut count = 0;
            for c in Bits(maybe) {
                let child = n.child[c];
                let mut lanes = rays;
                if child & LEAF != 0 {
                    let side = |s: usize, a: usize| n.side[s][a].to_array()[c];
                    let near = [side(nx, 0), side(ny, 1), side(nz, 2)];
                    let far = [side(1 - nx, 0), side(1 - ny, 1), side(1 - nz, 2)];
                    lanes &= enters::<W>(p, near, far, tfar);
                }
                if child == EMPTY || lanes == 0 {
                    continue;
                }
                let mut k = count;
                while k > 0 && kids[k - 1].1 < t0[c] {
                    kids[k] = kids[k - 1];
                    k -= 1;
                }
                kids[k] = (child, t0[c], lanes);
                tree.fetch(child, &fetch);
                count += 1;
            }
            if count > 0 {
                // The farther onto the stack, the nearest visited next.
                self.stack.extend_from_slice(&kids[..count - 1]);
                self.cur = kids[count - 1];
                self.pop = false;
            }
        }
    }
}

/// The rays of packet `p` that enter the box with sides `near` and `far`
/// (per axis, as the rays' signs pick them) before their `tfar`: each
/// lane the single walk's slab test.
#[inline(always)]
fn enters<W: Wide>(p: &RayPacket, near: [f32; 3], far: [f32; 3], tfar: &Lanes) -> u32 {
    let [ix, iy, iz] = p.inv.each_ref().map(W::load);
    let [ox, oy, oz] = p.origin_inv.each_ref().map(W::load);
    let t0 = slab(near[0], ix, ox)
        .max(slab(near[1], iy, oy))
        .max(slab(near[2], iz, oz))
        .max(W::load(&p.tmin));
    let t1 = slab(far[0], ix, ox)
        .min(slab(far[1], iy, oy))
        .min(slab(far[2], iz, oz))
        .min(W::load(tfar));
    t0.le(t1).bits()
}

/// Bounds on a packet's rays for the node test of [`PacketWalk`]: per
/// axis the least and greatest inverse direction (all of one sign) and
/// origin, and a margin for rounding.
///
/// A ray's slab distance `side·inv − origin·inv` is, but for rounding,
/// `(side − origin)·inv`, which over the packet lies between the products
/// of the bounds. The rays' rounding differs from the bounds' by at most
/// a few units of 2⁻²⁴ of `(|side| + |origin|)·|inv|`: `pad` is 2⁻²⁰ of
/// it, with `|side|` at most the tree's largest coordinate. (With 0·∞ or
/// ∞ − ∞ a bound is NaN, and a NaN bound excludes nothing.)
#[derive(Clone, Copy, Debug)]
pub struct PacketBounds {
    inv: [[f32; 2]; 3],
    origin: [[f32; 2]; 3],
    pad: [f32; 3],
    tmin: f32,
    /// All the rays leave from one point (a camera's): two products per
    /// bound instead of four.
    common: bool,
}

impl PacketBounds {
    /// The span of packet `p` (all its lanes) for a tree whose largest
    /// coordinate is `scale`.
    #[inline(always)]
    fn of<W: Wide>(p: &RayPacket, scale: f32) -> PacketBounds {
        // Loops, not `map`: its closure would call the lane form's
        // instructions out of line (see `super::wide`).
        let (mut inv, mut origin) = ([[0.0; 2]; 3], [[0.0; 2]; 3]);
        for a in 0..3 {
            inv[a] = range::<W>(&p.inv[a]);
            origin[p.axes[a].min(2)] = range::<W>(&p.permuted_origin[a]);
        }
        let pad = std::array::from_fn(|a| {
            let i = inv[a][0].abs().max(inv[a][1].abs());
            let o = origin[a][0].abs().max(origin[a][1].abs());
            (scale + o) * i * (1.0 / 1_048_576.0)
        });
        PacketBounds {
            inv,
            origin,
            pad,
            tmin: W::load(&p.tmin).least(),
            common: origin.iter().all(|[lo, hi]| lo == hi),
        }
    }

    /// For four boxes (`near` and `far` sides per axis, a box per lane),
    /// at most the least entry distance of any ray, and at least the
    /// greatest exit distance short of `far`.
    #[inline(always)]
    fn entry_exit(&self, near: &[Vec4; 3], far: &[Vec4; 3], tfar: f32) -> (Vec4, Vec4) {
        let s = Vec4::splat;
        let mut t0 = s(self.tmin);
        let mut t1 = s(tfar);
        for a in 0..3 {
            let ([ilo, ihi], [olo, ohi], pad) =
                (self.inv[a].map(s), self.origin[a].map(s), s(self.pad[a]));
            let (n, f) = (near[a], far[a]);
            let (lo, hi) = if self.common {
                let (n, f) = (n - olo, f - olo);
                ((n * ilo).min(n * ihi), (f * ilo).max(f * ihi))
            } else {
                let (n0, n1, f0, f1) = (n - ohi, n - olo, f - ohi, f - olo);
                (
                    (n0 * ilo).min(n0 * ihi).min(n1 * ilo).min(n1 * ihi),
                    (f0 * ilo).max(f0 * ihi).max(f1 * ilo).max(f1 * ihi),
                )
            };
            // The axis's bound first: where it is NaN, `max` takes the
            // other operand.
            t0 = (lo - pad).max(t0);
            t1 = (hi + pad).min(t1);
        }
        (t0, t1)
    }
}

/// The least and greatest of a value's lanes (a function, not a closure:
/// see [`crate::render::simd::wide`]).
#[inline(always)]
fn range<W: Wide>(v: &Lanes) -> [f32; 2] {
    let v = W::load(v);
    [v.least(), greatest(v)]
}

/// The greatest lane (no lane NaN).
#[inline(always)]
fn greatest<W: Wide>(v: W) -> f32 {
    -W::splat(0.0).sub(v).least()
}

/// Starts fetching every cache line `data` spans (a hint: it reads
/// nothing and cannot fault): a node, a leaf's packs, a triangle's record.
#[inline(always)]
pub fn prefetch<T: ?Sized>(data: &T) {
    let start = (data as *const T).cast::<u8>();
    let len = std::mem::size_of_val(data);
    // From the line of the first byte to the line of the last.
    let skip = start as usize % 64;
    for off in (0..skip + len).step_by(64) {
        let line = start.wrapping_sub(skip).wrapping_add(off);
        #[cfg(target_arch = "x86_64")]
        // SAFETY: a prefetch reads nothing and cannot fault; SSE is part
        // of the x86-64 baseline.
        unsafe {
            use std::arch::x86_64::{_mm_prefetch, _MM_HINT_T0};
            _mm_prefetch::<_MM_HINT_T0>(line.cast());
        }
        #[cfg(not(target_arch = "x86_64"))]
        let _ = line;
    }
}

/// The distance along each ray of a packet to the plane `side` of an
/// axis, from the ray's `inv` and `origin·inv` on that axis (a function,
/// not a closure: see [`crate::render::simd::wide`]).
#[inline(always)]
fn slab<W: Wide>(side: f32, inv: W, o: W) -> W {
    W::splat(side).mul(inv).sub(o)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::simd::wide::Scalar;
    use crate::render::simd::LANES;
    use glam::Vec3A;

    /// A packet's bounds never exclude a box that one of its rays enters:
    /// packets from one point and from points apart, directions with tiny
    /// and zero components, boxes big and small, near and far, thin and
    /// flat, with bounds `tfar` that stop short.
    #[test]
    fn span_bounds_exclude_no_box_a_ray_enters() {
        let mut seed = 7u64;
        let mut unit = move || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 40) as f32 / (1u64 << 24) as f32
        };
        let (mut tested, mut entered) = (0, 0);
        for k in 0..4000 {
            let o = Vec3A::new(unit(), unit(), unit()) * 40.0 - 20.0;
            let aim = Vec3A::new(unit(), unit(), unit()) * 2.0 - 1.0;
            // Some components tiny or zero, some spreads wide.
            let aim = Vec3A::select(
                aim.abs().cmplt(Vec3A::splat(0.15)),
                aim * 1e-6 * (k % 3) as f32,
                aim,
            );
            let spread = [1e-3, 0.05, 0.5][k % 3];
            let rays: [Ray; LANES] = std::array::from_fn(|_| {
                let jitter = Vec3A::new(unit(), unit(), unit()) * spread;
                // The same signs as the aim, as a packet's rays share.
                let d = (aim.abs() + jitter).copysign(aim);
                let o = if k % 4 == 1 {
                    o + Vec3A::new(unit(), unit(), unit())
                } else {
                    o
                };
                Ray::new(o, d, if k % 5 == 0 { unit() } else { 0.0 })
            });
            let p = RayPacket::new(&rays, u32::MAX >> 16);
            let tfar: Lanes = std::array::from_fn(|i| {
                if i % 3 == 0 {
                    unit() * 30.0
                } else {
                    f32::INFINITY
                }
            });
            let span = PacketBounds::of::<Scalar>(&p, 25.0);
            let far = greatest(Scalar::load(&tfar));
            for _ in 0..8 {
                // Near the packet's way, mostly.
                let r = &rays[(unit() * 15.0) as usize];
                // A point of a ray, or a box flat or pointlike around it,
                // decides by rounding: the pad must cover it.
                let off = (Vec3A::new(unit(), unit(), unit()) - 0.5) * [0.0, 1.0, 6.0][k % 3];
                let c = r.origin + r.direction * unit() * 30.0 + off;
                let size = Vec3A::new(unit(), unit(), unit()) * [0.0, 0.01, 3.0][k % 3];
                let size = if k % 6 == 3 { size * Vec3A::X } else { size };
                // Within the scale given to the span.
                let (lo, hi) = (
                    (c - size).clamp(Vec3A::splat(-25.0), Vec3A::splat(25.0)),
                    (c + size).clamp(Vec3A::splat(-25.0), Vec3A::splat(25.0)),
                );
                let [nx, ny, nz] = p.negative.map(usize::from);
                let sides = [lo.to_array(), hi.to_array()];
                let near = [sides[nx][0], sides[ny][1], sides[nz][2]];
                let farside = [sides[1 - nx][0], sides[1 - ny][1], sides[1 - nz][2]];
                let lanes = enters::<Scalar>(&p, near, farside, &tfar);
                let (t0, t1) =
                    span.entry_exit(&near.map(Vec4::splat), &farside.map(Vec4::splat), far);
                let kept = !t0.cmpgt(t1).all();
                assert!(
                    lanes == 0 || kept,
                    "packet {k}: rays {lanes:b} enter {lo} – {hi}"
                );
                tested += 1;
                entered += usize::from(lanes != 0);
            }
        }
        assert!(entered > tested / 10, "{entered} of {tested} boxes entered");
    }

    fn leaf(p: u32) -> Bvh2Node {
        let b = Aabb::new(Vec3A::splat(p as f32), Vec3A::splat(p as f32 + 1.0));
        Bvh2Node::new(b, 1, p)
    }

    fn inner(first: u32, lo: f32, hi: f32) -> Bvh2Node {
        Bvh2Node::new(Aabb::new(Vec3A::splat(lo), Vec3A::splat(hi)), 0, first)
    }

    /// obvhs's reinsertion can leave the root's children anywhere (seen:
    /// at 3 and 4); the depth-first renumbering must follow the links.
    #[test]
    fn root_children_anywhere() {
        let b = Bvh2 {
            nodes: depth_first(&[
                inner(3, 0.0, 3.0),
                leaf(0),
                leaf(1),
                inner(1, 0.0, 2.0),
                leaf(2),
            ]),
            primitive_indices: vec![0, 1, 2],
            max_depth: None,
        };
        for (i, n) in b.nodes.iter().enumerate() {
            assert!(n.is_leaf() || n.first_index as usize > i);
        }
        for max_leaf in [1, 16] {
            let t = Bvh4::collapse(&b, max_leaf);
            let mut all: Vec<u32> = (0..t.leaf_count())
                .flat_map(|l| t.leaf(l).to_vec())
                .collect();
            all.sort();
            assert_eq!(all, [0, 1, 2]);
        }
    }

    /// Every input index once, in some leaf of at most `max_leaf`.
    fn check_leaves(t: &Bvh4, n: usize, max_leaf: usize) {
        let mut all: Vec<u32> = (0..t.leaf_count())
            .flat_map(|l| {
                assert!(t.leaf(l).len() <= max_leaf, "leaf of {}", t.leaf(l).len());
                t.leaf(l).to_vec()
            })
            .collect();
        all.sort();
        assert_eq!(all, (0..n as u32).collect::<Vec<_>>());
    }

    #[test]
    fn coincident_boxes_build_a_balanced_tree_fast() {
        // 10⁵ identical faces: PLOC merged one pair per pass (minutes).
        let b = Aabb::new(Vec3A::new(0.0, 0.0, 0.0), Vec3A::new(1.0, 1.0, 0.0));
        let boxes = vec![b; 100_000];
        let start = std::time::Instant::now();
        let t = Bvh4::build(&boxes, 16).unwrap();
        let took = start.elapsed();
        check_leaves(&t, boxes.len(), 16);
        // 6,250 leaves of 16: 13 binary levels, 7 four-wide ones.
        assert!(t.depth() <= 8, "depth {}", t.depth());
        assert!(took.as_secs_f64() < 10.0, "{took:?}");
        // The top level: one instance per leaf.
        let t = Bvh4::build(&boxes[..20_000], 1).unwrap();
        check_leaves(&t, 20_000, 1);
        assert!(t.depth() <= 9, "depth {}", t.depth());
    }

    #[test]
    fn pairs_of_coincident_boxes_are_left_to_ploc() {
        // A mesh's quads: two triangles with one box each.
        let boxes: Vec<Aabb> = (0..20_000)
            .map(|k| {
                let p = Vec3A::new((k / 2 % 100) as f32, (k / 200) as f32, 0.0);
                Aabb::new(p, p + Vec3A::ONE)
            })
            .collect();
        assert!(coincident(&boxes).is_none());
        let t = Bvh4::build(&boxes, 4).unwrap();
        check_leaves(&t, boxes.len(), 4);
        assert!(t.depth() <= 12, "depth {}", t.depth());
        // Past `SMALL_RUN` they are grouped.
        let many: Vec<Aabb> = boxes.iter().flat_map(|b| [*b; 5]).collect();
        assert!(coincident(&many).is_some());
    }

    #[test]
    fn concentric_and_scattered_boxes_mixed() {
        // Nested boxes around one centre among distinct ones.
        let mut boxes: Vec<Aabb> = (1..=5000)
            .map(|k| Aabb::new(Vec3A::splat(-(k as f32)), Vec3A::splat(k as f32)))
            .collect();
        boxes.extend((0..5000).map(|k| {
            let p = Vec3A::new(k as f32 * 3.0, 1.0, 2.0);
            Aabb::new(p, p + Vec3A::ONE)
        }));
        let t = Bvh4::build(&boxes, 4).unwrap();
        check_leaves(&t, boxes.len(), 4);
        assert!(t.depth() <= 20, "depth {}", t.depth());
    }

    #[test]
    fn root_leaf() {
        let nodes = depth_first(&[leaf(0)]);
        assert_eq!(nodes.len(), 1);
        let b = Bvh2 {
            nodes,
            primitive_indices: vec![0],
            max_depth: None,
        };
        assert_eq!(Bvh4::collapse(&b, 4).leaf(0), [0]);
    }
}
