//! Two-level BVH on obvhs: a top level over instances and one bottom level
//! per shared geometry, with exact intersection of every primitive.
//!
//! obvhs's wide-BVH traversal keeps a fixed stack of 32 entries and
//! silently overwrites its last slot when full; a tree that deep would
//! lose nodes. Every tree is therefore built as a binary BVH first; when it
//! is deeper than the wide stack could ever need, it is traversed as a
//! binary BVH with a heap stack sized to its depth instead.

use glam::{Affine3A, Mat3A, Vec3, Vec3A};
use obvhs::aabb::Aabb;
use obvhs::bvh2::reinsertion::ReinsertionOptimizer;
use obvhs::bvh2::Bvh2;
use obvhs::cwbvh::bvh2_to_cwbvh::bvh2_to_cwbvh;
use obvhs::cwbvh::CwBvh;
use obvhs::ray::{Ray, RayHit};
use obvhs::rt_triangle::RtTriangle;
use obvhs::BvhBuildParams;

use super::intersect;
use crate::scene::material::Texture;
use crate::scene::{Geometry, Material, Scene};

/// Levels the wide traversal may use: obvhs's stack has 32 slots and
/// its own validation asserts a depth below 32; two are kept spare.
const WIDE_MAX_DEPTH: usize = 30;

/// A built tree: wide (fast) or binary (any depth).
pub enum Tree {
    Wide(CwBvh),
    Binary(Bvh2),
}

/// Deepest level of a binary tree (iterative: deep trees are the point).
fn depth(b: &Bvh2) -> usize {
    let mut max = 0;
    let mut stack = vec![(0usize, 1usize)];
    while let Some((i, d)) = stack.pop() {
        let n = &b.nodes[i];
        max = max.max(d);
        if !n.is_leaf() {
            stack.push((n.first_index as usize, d + 1));
            stack.push((n.first_index as usize + 1, d + 1));
        }
    }
    max
}

/// Deepest level of a wide tree.
fn wide_depth(b: &CwBvh) -> usize {
    let mut max = 0;
    let mut stack = vec![(0usize, 1usize)];
    while let Some((i, d)) = stack.pop() {
        let n = &b.nodes[i];
        max = max.max(d);
        for ch in 0..8 {
            if !n.is_child_empty(ch) && !n.is_leaf(ch) {
                stack.push((n.child_node_index(ch) as usize, d + 1));
            }
        }
    }
    max
}

impl Tree {
    /// Builds over `aabbs` (all finite) with obvhs's fast preset: the tree
    /// is rebuilt every frame. `None` when empty.
    pub fn build(aabbs: &[Aabb]) -> Option<Tree> {
        if aabbs.is_empty() {
            return None;
        }
        let p = BvhBuildParams::fast_build();
        let indices = (0..aabbs.len() as u32).collect();
        let mut b = p.ploc_search_distance.build(
            aabbs,
            indices,
            p.sort_precision,
            p.search_depth_threshold,
        );
        ReinsertionOptimizer::run(&mut b, p.reinsertion_batch_ratio, None);
        let wide = bvh2_to_cwbvh(&b, p.max_prims_per_leaf.clamp(1, 3), true, false);
        if wide_depth(&wide) <= WIDE_MAX_DEPTH {
            Some(Tree::Wide(wide))
        } else {
            b.max_depth = Some(depth(&b) + 2);
            Some(Tree::Binary(b))
        }
    }

    /// Input index of each primitive in traversal order: `f` below gets
    /// positions in this list.
    fn order(&self) -> &[u32] {
        match self {
            Tree::Wide(b) => &b.primitive_indices,
            Tree::Binary(b) => &b.primitive_indices,
        }
    }

    /// Closest hit: `f(ray, position)` returns the hit t or infinity.
    fn closest(&self, ray: Ray, mut f: impl FnMut(&Ray, usize) -> f32) -> bool {
        let mut hit = RayHit::none();
        match self {
            Tree::Wide(b) => b.ray_traverse(ray, &mut hit, |r, id| f(r, id)),
            Tree::Binary(b) => b.ray_traverse(ray, &mut hit, |r, id| f(r, id)),
        }
    }

    /// Any hit: stops at the first primitive hit.
    fn any(&self, ray: Ray, mut f: impl FnMut(&Ray, usize) -> f32) -> bool {
        let mut hit = RayHit::none();
        match self {
            Tree::Wide(b) => {
                let mut st = b.new_ray_traversal(ray);
                b.ray_traverse_dynamic(&mut st, &mut hit, |r, id| f(r, id))
            }
            Tree::Binary(b) => {
                let mut st = b.new_ray_traversal(ray);
                b.ray_traverse_dynamic(&mut st, &mut hit, |r, id| f(r, id))
            }
        }
    }

    /// Whether the tree had to fall back to the binary form.
    pub fn is_binary(&self) -> bool {
        matches!(self, Tree::Binary(_))
    }
}

/// A primitive of a geometry: an analytic shape or a triangle.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Prim {
    Shape(u32),
    Triangle(u32),
}

/// A primitive as the traversal meets it, stored in traversal order so a
/// leaf needs no index lookups.
enum Leaf {
    /// Precomputed edges for Möller–Trumbore, and the triangle's index.
    Triangle(RtTriangle, u32),
    /// The shape's index, its inverse transform (local ← geometry), and
    /// whether it casts shadows (cloud layers do not).
    Shape(u32, Affine3A, bool),
}

struct Blas {
    tree: Tree,
    leaves: Vec<Leaf>,
}

/// The nearest surface a ray meets.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Hit {
    pub t: f32,
    pub instance: u32,
    pub geometry: u32,
    pub prim: Prim,
    /// Unit geometric normal in world space, facing outward.
    pub normal: Vec3A,
    pub material: u32,
    /// Object id (of the instance).
    pub object: u32,
    /// Identifier of the symbol that drew the primitive.
    pub symbol: u64,
    /// Flat colour of the material for synthetic vision (3.1.2).
    pub vision: Vec3,
}

/// The ray-casting structure of one frame's scene.
pub struct Accel<'a> {
    pub scene: &'a Scene,
    tlas: Option<Tree>,
    /// Instance index of each top-level primitive, in traversal order.
    tlas_inst: Vec<u32>,
    inst_inv: Vec<Affine3A>,
    blas: Vec<Option<Blas>>,
}

/// An obvhs ray. Negative zeros in the direction are made positive: the
/// wide traversal picks child order from the sign bits and misses boxes
/// for a −0 component (seen with `-Vec3A::Z`).
fn ray(o: Vec3A, d: Vec3A, tmin: f32, tmax: f32) -> Ray {
    Ray::new(o, d + Vec3A::ZERO, tmin, tmax)
}

fn aabb(b: (Vec3A, Vec3A)) -> Aabb {
    Aabb::new(b.0, b.1)
}

fn transformed(a: &Aabb, m: &Affine3A) -> Option<Aabb> {
    let mut out = Aabb::empty();
    for i in 0..8 {
        let c = Vec3A::new(
            if i & 1 == 0 { a.min.x } else { a.max.x },
            if i & 2 == 0 { a.min.y } else { a.max.y },
            if i & 4 == 0 { a.min.z } else { a.max.z },
        );
        out.extend(m.transform_point3a(c));
    }
    (out.min.is_finite() && out.max.is_finite()).then_some(out)
}

/// The bottom level of one geometry; primitives with non-finite bounds
/// never reach the builder.
fn blas(g: &Geometry, materials: &[Material]) -> Option<Blas> {
    let mut prims = Vec::with_capacity(g.shapes.len() + g.triangles.len());
    let mut boxes = Vec::with_capacity(prims.capacity());
    for (i, s) in g.shapes.iter().enumerate() {
        if let Some(b) = intersect::bounds(s) {
            prims.push(Prim::Shape(i as u32));
            boxes.push(aabb(b));
        }
    }
    for (i, t) in g.triangles.iter().enumerate() {
        if let Some(b) = intersect::triangle_bounds(&t.v) {
            prims.push(Prim::Triangle(i as u32));
            boxes.push(aabb(b));
        }
    }
    let tree = Tree::build(&boxes)?;
    let leaves = tree
        .order()
        .iter()
        .map(|&p| match prims[p as usize] {
            Prim::Shape(i) => {
                let s = &g.shapes[i as usize];
                let cloud = materials
                    .get(s.material as usize)
                    .is_some_and(|m| m.texture == Some(Texture::Cloud));
                Leaf::Shape(i, s.transform.inverse(), !cloud)
            }
            Prim::Triangle(i) => {
                let v = g.triangles[i as usize].v.map(Vec3A::from);
                Leaf::Triangle(RtTriangle::new(v[0], v[1], v[2]), i)
            }
        })
        .collect();
    Some(Blas { tree, leaves })
}

impl<'a> Accel<'a> {
    /// Builds the bottom levels, then the top level over the instances
    /// whose bounds are finite.
    pub fn new(scene: &'a Scene) -> Self {
        let blas: Vec<Option<Blas>> = scene
            .geometries
            .iter()
            .map(|g| blas(g, &scene.materials))
            .collect();
        let mut inst = Vec::new();
        let mut boxes = Vec::new();
        for (k, i) in scene.instances.iter().enumerate() {
            let Some(Some(b)) = blas.get(i.geometry as usize) else {
                continue;
            };
            let total = match &b.tree {
                Tree::Wide(t) => t.total_aabb,
                Tree::Binary(t) => t.nodes[0].aabb,
            };
            if let Some(wb) = transformed(&total, &i.transform) {
                inst.push(k as u32);
                boxes.push(wb);
            }
        }
        let tlas = Tree::build(&boxes);
        let tlas_inst = tlas.as_ref().map_or(Vec::new(), |t| {
            t.order().iter().map(|&p| inst[p as usize]).collect()
        });
        let inst_inv = scene
            .instances
            .iter()
            .map(|i| i.transform.inverse())
            .collect();
        Accel {
            scene,
            tlas,
            tlas_inst,
            inst_inv,
            blas,
        }
    }

    /// Intersects a leaf with the local ray: the primitive and its hit
    /// (triangle normals are computed only for the closest hit).
    #[inline(always)]
    fn leaf_hit(leaf: &Leaf, g: &Geometry, r: &Ray) -> Option<(Prim, intersect::LocalHit)> {
        match leaf {
            Leaf::Triangle(rt, i) => {
                let t = rt.intersect(r);
                (t.is_finite() && t > r.tmin).then_some((
                    Prim::Triangle(*i),
                    intersect::LocalHit {
                        t,
                        normal: Vec3A::ZERO,
                    },
                ))
            }
            Leaf::Shape(i, inv, _) => {
                let o = inv.transform_point3a(r.origin);
                let d = inv.transform_vector3a(r.direction);
                intersect::shape(g.shapes[*i as usize].kind, o, d, r.tmin, r.tmax)
                    .map(|h| (Prim::Shape(*i), h))
            }
        }
    }

    fn local_ray(&self, k: usize, r: &Ray) -> Ray {
        let inv = &self.inst_inv[k];
        if *inv == Affine3A::IDENTITY {
            return *r;
        }
        ray(
            inv.transform_point3a(r.origin),
            inv.transform_vector3a(r.direction),
            r.tmin,
            r.tmax,
        )
    }

    /// Closest hit within instance `k` (its t, or infinity), kept in `best`.
    #[inline]
    fn instance_closest(
        &self,
        k: usize,
        r: &Ray,
        best: &mut Option<(u32, Prim, intersect::LocalHit)>,
    ) -> f32 {
        let g = self.scene.instances[k].geometry as usize;
        let Some(b) = &self.blas[g] else {
            return f32::INFINITY;
        };
        let geo = &self.scene.geometries[g];
        let mut found = f32::INFINITY;
        b.tree.closest(self.local_ray(k, r), |r2, pi| {
            match Self::leaf_hit(&b.leaves[pi], geo, r2) {
                Some((p, h)) => {
                    *best = Some((k as u32, p, h));
                    found = h.t;
                    h.t
                }
                None => f32::INFINITY,
            }
        });
        found
    }

    /// Any hit within instance `k`: its t, or infinity.
    #[inline]
    fn instance_any(&self, k: usize, r: &Ray) -> f32 {
        let g = self.scene.instances[k].geometry as usize;
        let Some(b) = &self.blas[g] else {
            return f32::INFINITY;
        };
        let geo = &self.scene.geometries[g];
        let mut t = f32::INFINITY;
        b.tree.any(self.local_ray(k, r), |r2, pi| {
            let leaf = &b.leaves[pi];
            if let Leaf::Shape(_, _, false) = leaf {
                return f32::INFINITY;
            }
            match Self::leaf_hit(leaf, geo, r2) {
                Some((_, h)) => {
                    t = h.t;
                    h.t
                }
                None => f32::INFINITY,
            }
        });
        t
    }

    /// The closest hit of the ray `origin + t·dir` with t in (tmin, tmax).
    pub fn cast(&self, origin: Vec3A, dir: Vec3A, tmin: f32, tmax: f32) -> Option<Hit> {
        let tlas = self.tlas.as_ref()?;
        if !(origin.is_finite() && dir.is_finite()) || dir == Vec3A::ZERO {
            return None;
        }
        let r = ray(origin, dir, tmin, tmax);
        let mut best = None;
        // One instance (a scene without repetitions): no top level to walk.
        if let [k] = self.tlas_inst[..] {
            self.instance_closest(k as usize, &r, &mut best);
        } else {
            tlas.closest(r, |r, ti| {
                self.instance_closest(self.tlas_inst[ti] as usize, r, &mut best)
            });
        }
        let (k, prim, h) = best?;
        Some(self.resolve(k, prim, h))
    }

    /// Whether anything but a cloud layer blocks the ray within (tmin, tmax).
    pub fn occluded(&self, origin: Vec3A, dir: Vec3A, tmin: f32, tmax: f32) -> bool {
        let Some(tlas) = &self.tlas else { return false };
        if !(origin.is_finite() && dir.is_finite()) || dir == Vec3A::ZERO {
            return false;
        }
        let r = ray(origin, dir, tmin, tmax);
        if let [k] = self.tlas_inst[..] {
            return self.instance_any(k as usize, &r) < f32::INFINITY;
        }
        tlas.any(r, |r, ti| self.instance_any(self.tlas_inst[ti] as usize, r))
    }

    /// World-space details of a local hit.
    fn resolve(&self, k: u32, prim: Prim, h: intersect::LocalHit) -> Hit {
        let inst = &self.scene.instances[k as usize];
        let geo = &self.scene.geometries[inst.geometry as usize];
        let (n_geo, material, symbol) = match prim {
            Prim::Shape(i) => {
                let s = &geo.shapes[i as usize];
                (
                    normal_to(&s.transform.matrix3, h.normal),
                    s.material,
                    s.symbol,
                )
            }
            Prim::Triangle(i) => {
                let t = &geo.triangles[i as usize];
                let n = (t.v[1] - t.v[0]).cross(t.v[2] - t.v[0]);
                (Vec3A::from(n), t.material, t.symbol)
            }
        };
        Hit {
            t: h.t,
            instance: k,
            geometry: inst.geometry,
            prim,
            normal: normal_to(&inst.transform.matrix3, n_geo).normalize_or(Vec3A::Y),
            material,
            object: inst.object,
            symbol,
            vision: self
                .scene
                .materials
                .get(material as usize)
                .map_or(Vec3::ZERO, |m| m.vision),
        }
    }

    /// True when some top- or bottom-level tree had to use the binary
    /// fallback (tests of pathological scenes).
    pub fn uses_fallback(&self) -> bool {
        self.tlas.as_ref().is_some_and(Tree::is_binary)
            || self.blas.iter().flatten().any(|b| b.tree.is_binary())
    }
}

/// A normal carried through the linear part `m` (inverse transpose).
#[inline]
fn normal_to(m: &Mat3A, n: Vec3A) -> Vec3A {
    m.inverse().transpose() * n
}
