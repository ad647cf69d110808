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
use obvhs::BvhBuildParams;

use super::intersect;
use crate::scene::{Scene, Shape};

/// Depth below which a binary tree's wide form fits obvhs's 32-entry stack.
const WIDE_SAFE_DEPTH: usize = 32;

/// A built tree: wide (fast) or binary (any depth).
pub enum Tree {
    Wide(CwBvh),
    Binary(Bvh2),
}

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

impl Tree {
    /// Builds over `aabbs` (all finite) with the fast preset used for
    /// per-frame rebuilds. `None` when there is nothing to build.
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
        let d = depth(&b);
        if d < WIDE_SAFE_DEPTH {
            Some(Tree::Wide(bvh2_to_cwbvh(
                &b,
                p.max_prims_per_leaf.clamp(1, 3),
                true,
                false,
            )))
        } else {
            b.max_depth = Some(d + 2);
            Some(Tree::Binary(b))
        }
    }

    /// Closest hit: `f(ray, primitive)` returns the hit t or infinity.
    fn closest(&self, ray: Ray, mut f: impl FnMut(&Ray, usize) -> f32) -> bool {
        let mut hit = RayHit::none();
        match self {
            Tree::Wide(b) => b.ray_traverse(ray, &mut hit, |r, id| {
                f(r, b.primitive_indices[id] as usize)
            }),
            Tree::Binary(b) => b.ray_traverse(ray, &mut hit, |r, id| {
                f(r, b.primitive_indices[id] as usize)
            }),
        }
    }

    /// Any hit: stops at the first primitive hit.
    fn any(&self, ray: Ray, mut f: impl FnMut(&Ray, usize) -> f32) -> bool {
        let mut hit = RayHit::none();
        match self {
            Tree::Wide(b) => {
                let mut st = b.new_ray_traversal(ray);
                b.ray_traverse_dynamic(&mut st, &mut hit, |r, id| {
                    f(r, b.primitive_indices[id] as usize)
                })
            }
            Tree::Binary(b) => {
                let mut st = b.new_ray_traversal(ray);
                b.ray_traverse_dynamic(&mut st, &mut hit, |r, id| {
                    f(r, b.primitive_indices[id] as usize)
                })
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

struct Blas {
    tree: Tree,
    prims: Vec<Prim>,
    /// Inverse transforms of the shapes (local ← geometry).
    shape_inv: Vec<Affine3A>,
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
    /// Instance index of each top-level primitive.
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

impl<'a> Accel<'a> {
    /// Builds the bottom levels, then the top level. Primitives or
    /// instances with non-finite bounds are left out.
    pub fn new(scene: &'a Scene) -> Self {
        let blas: Vec<Option<Blas>> = scene
            .geometries
            .iter()
            .map(|g| {
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
                let shape_inv = g
                    .shapes
                    .iter()
                    .map(|s: &Shape| s.transform.inverse())
                    .collect();
                Tree::build(&boxes).map(|tree| Blas {
                    tree,
                    prims,
                    shape_inv,
                })
            })
            .collect();
        let mut tlas_inst = Vec::new();
        let mut boxes = Vec::new();
        for (k, inst) in scene.instances.iter().enumerate() {
            let Some(Some(b)) = blas.get(inst.geometry as usize) else {
                continue;
            };
            let total = match &b.tree {
                Tree::Wide(t) => t.total_aabb,
                Tree::Binary(t) => t.nodes[0].aabb,
            };
            if let Some(wb) = transformed(&total, &inst.transform) {
                tlas_inst.push(k as u32);
                boxes.push(wb);
            }
        }
        let inst_inv = scene
            .instances
            .iter()
            .map(|i| i.transform.inverse())
            .collect();
        Accel {
            scene,
            tlas: Tree::build(&boxes),
            tlas_inst,
            inst_inv,
            blas,
        }
    }

    /// Intersects primitive `p` of geometry `g` with the local ray.
    #[inline]
    fn prim_hit(&self, b: &Blas, g: usize, p: Prim, r: &Ray) -> Option<intersect::LocalHit> {
        let geo = &self.scene.geometries[g];
        match p {
            Prim::Shape(i) => {
                let inv = &b.shape_inv[i as usize];
                let o = inv.transform_point3a(r.origin);
                let d = inv.transform_vector3a(r.direction);
                intersect::shape(geo.shapes[i as usize].kind, o, d, r.tmin, r.tmax)
            }
            Prim::Triangle(i) => intersect::triangle(
                &geo.triangles[i as usize].v,
                r.origin,
                r.direction,
                r.tmin,
                r.tmax,
            ),
        }
    }

    fn local_ray(&self, k: usize, r: &Ray) -> Ray {
        let inv = &self.inst_inv[k];
        ray(
            inv.transform_point3a(r.origin),
            inv.transform_vector3a(r.direction),
            r.tmin,
            r.tmax,
        )
    }

    /// The closest hit of the ray `origin + t·dir` with t in (tmin, tmax).
    pub fn cast(&self, origin: Vec3A, dir: Vec3A, tmin: f32, tmax: f32) -> Option<Hit> {
        let tlas = self.tlas.as_ref()?;
        if !(origin.is_finite() && dir.is_finite()) || dir == Vec3A::ZERO {
            return None;
        }
        let mut best: Option<(u32, Prim, intersect::LocalHit)> = None;
        tlas.closest(ray(origin, dir, tmin, tmax), |r, ti| {
            let k = self.tlas_inst[ti] as usize;
            let g = self.scene.instances[k].geometry as usize;
            let Some(b) = &self.blas[g] else {
                return f32::INFINITY;
            };
            let lr = self.local_ray(k, r);
            let mut found = f32::INFINITY;
            b.tree.closest(lr, |r2, pi| {
                let p = b.prims[pi];
                match self.prim_hit(b, g, p, r2) {
                    Some(h) => {
                        best = Some((k as u32, p, h));
                        found = h.t;
                        h.t
                    }
                    None => f32::INFINITY,
                }
            });
            found
        });
        let (k, prim, h) = best?;
        Some(self.resolve(k, prim, h))
    }

    /// Whether anything blocks the ray within (tmin, tmax).
    pub fn occluded(&self, origin: Vec3A, dir: Vec3A, tmin: f32, tmax: f32) -> bool {
        let Some(tlas) = &self.tlas else { return false };
        if !(origin.is_finite() && dir.is_finite()) || dir == Vec3A::ZERO {
            return false;
        }
        tlas.any(ray(origin, dir, tmin, tmax), |r, ti| {
            let k = self.tlas_inst[ti] as usize;
            let g = self.scene.instances[k].geometry as usize;
            let Some(b) = &self.blas[g] else {
                return f32::INFINITY;
            };
            let lr = self.local_ray(k, r);
            let mut t = f32::INFINITY;
            b.tree
                .any(lr, |r2, pi| match self.prim_hit(b, g, b.prims[pi], r2) {
                    Some(h) => {
                        t = h.t;
                        h.t
                    }
                    None => f32::INFINITY,
                });
            t
        })
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
                (h.normal, t.material, t.symbol)
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
