//! Two-level BVH: a top level over instances and one bottom level per
//! shared geometry (4-wide trees built by obvhs, see [`super::bvh4`]),
//! with exact intersection of every primitive.

pub mod bvh4;
pub mod hull;
pub mod packet;
pub mod ray;
pub mod shapes;
pub mod tri4;

use std::sync::Arc;

use crate::aabb::{self, Aabb};
use crate::render::motion::{self, Motion};
use glam::{Affine3A, Mat3A, Vec3, Vec3A};

#[cfg(not(target_arch = "x86_64"))]
use crate::render::simd::wide::Scalar as Base;
use crate::render::simd::wide::Wide;
#[cfg(target_arch = "x86_64")]
use crate::render::simd::wide::{Avx, Avx512, Sse as Base};
use crate::render::simd::{Lanes, LANES};
use crate::scene::material::Texture;
use crate::scene::{Geometry, Material, Scene, Shape};
use bvh4::{prefetch, Bvh4};
use hull::Hull;
use packet::{Bits, RayPacket, Rays};
use ray::Ray;
use tri4::{Simd, Tri4};

/// Most primitives a bottom-level leaf may hold (the surface-area
/// heuristic decides below that; measured best on the forest).
const BLAS_LEAF: u32 = 16;

/// A primitive of a geometry: an analytic shape or a triangle (shapes
/// order first: the tie-break between equally near hits).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum Prim {
    Shape(u32),
    Triangle(u32),
}

/// An analytic shape as a leaf meets it: its index, its inverse transform
/// (local ← geometry), and whether it casts shadows (cloud layers do not).
struct ShapeLeaf {
    index: u32,
    inverse: Affine3A,
    shadows: bool,
    /// Its transform at shutter close, where it moves (see
    /// [`crate::render::motion`]).
    end: Option<Affine3A>,
}

impl ShapeLeaf {
    /// The ray `r` (in its geometry's space) against the shape, in its
    /// local space.
    #[inline(always)]
    fn hit(&self, geo: &Geometry, r: &Ray, tmax: f32) -> Option<shapes::LocalHit> {
        let s = &geo.shapes[self.index as usize];
        let moving = match self.end {
            Some(end) if r.time > 0.0 => Some(motion::lerp(&s.transform, &end, r.time).inverse()),
            _ => None,
        };
        let inverse = moving.as_ref().unwrap_or(&self.inverse);
        let o = inverse.transform_point3a(r.origin);
        let d = inverse.transform_vector3a(r.direction);
        shapes::shape(s.kind, o, d, r.tmin, tmax)
    }
}

/// One geometry's tree. A leaf's code (see [`Bvh4::set_leaf_codes`])
/// locates its primitives itself, so a visit reads no table first: one
/// to four triangle packs and no shape is `first << 2 | (count - 1)`,
/// the packs `tris[first..first + count]`; any other leaf is `SIDE | k`,
/// its packs and shapes the ranges `sides[k]`.
struct Blas {
    tree: Bvh4,
    tris: Vec<Tri4>,
    /// The triangles' indices in their geometry, per pack and lane.
    ids: Vec<[u32; 4]>,
    shapes: Vec<ShapeLeaf>,
    sides: Vec<[(u32, u32); 2]>,
}

/// Whether a leaf tests the rays of `lanes` together, a triangle at a
/// time in lane form `W`, rather than one by one with the single ray's
/// test (eight triangles per AVX test): from five rays per register a
/// value of `W` takes, so never with SSE. Measured on the forest's camera
/// rays in 4 × 4 pixel packets: +7 % over testing together always; for
/// a pixel's shadow bundles, about 1 % of the frame over one by one. Both
/// find the same hits.
#[inline(always)]
fn together<W: Wide>(lanes: u32) -> bool {
    lanes.count_ones() >= 5 * W::REGISTERS
}

/// The tag of a leaf code that indexes [`Blas::sides`].
const SIDE: u32 = 1 << 30;

impl Blas {
    /// Starts fetching leaf `code`'s triangle packs into the cache (a
    /// walk's `fetch`: see [`Bvh4::fetch`]).
    #[inline(always)]
    fn fetch(&self, code: u32) {
        prefetch(self.leaf(code).1);
    }

    /// The leaf with code `code`: the index of its first triangle pack,
    /// its packs and its shapes.
    #[inline(always)]
    fn leaf(&self, code: u32) -> (usize, &[Tri4], &[ShapeLeaf]) {
        if code & SIDE == 0 {
            let first = (code >> 2) as usize;
            (first, &self.tris[first..=first + (code & 3) as usize], &[])
        } else {
            let [(a, b), (c, d)] = self.sides[(code & !SIDE) as usize];
            (
                a as usize,
                &self.tris[a as usize..b as usize],
                &self.shapes[c as usize..d as usize],
            )
        }
    }
}

/// Whether the leaf `code` of `b` (geometry `geo`) has anything but a
/// cloud layer on the ray (in its space) before `tmax`.
#[inline(always)]
fn blocks(b: &Blas, geo: &Geometry, code: u32, r: &Ray, tmax: f32, simd: Simd) -> bool {
    let (_, packs, shapes) = b.leaf(code);
    tri4::any_hit(packs, r, tmax, simd) || shapes_block(shapes, geo, r, tmax)
}

/// Whether one of `shapes` that casts shadows is on the ray before `tmax`.
#[inline(always)]
fn shapes_block(shapes: &[ShapeLeaf], geo: &Geometry, r: &Ray, tmax: f32) -> bool {
    shapes
        .iter()
        .any(|s| s.shadows && s.hit(geo, r, tmax).is_some())
}

/// [`blocks`] for the rays of `rays` in packet `p` at once, a triangle
/// at a time in lane form `W` (the same answers).
#[inline(always)]
fn blocks_together<W: Wide>(
    b: &Blas,
    geo: &Geometry,
    code: u32,
    p: &RayPacket,
    rays: u32,
    tmax: &Lanes,
) -> u32 {
    let (_, packs, shapes) = b.leaf(code);
    let mut hit = 0;
    for pack in packs {
        for j in 0..pack.count() {
            hit |= pack.packet_lanes::<W>(j, p, rays & !hit, tmax).0;
            if hit == rays {
                return hit;
            }
        }
    }
    hit | packet::keep(rays & !hit, |i| {
        shapes_block(shapes, geo, &p.ray(i), tmax[i])
    })
}

/// Fewest rays traced as a bundle.
const MIN_BUNDLE: u32 = 4;

/// The region around the segments (tmin, tmax) of the rays of `lanes`,
/// along their mean direction, for a walk of `tree`; None where a segment
/// is unbounded. A segment ends where its ray leaves the tree's box at
/// the latest (nothing beyond it is hit): the shadow rays toward a sun,
/// unbounded, went one by one, a quarter of a film frame's render.
fn bundle(rays: &Rays, lanes: u32, tmax: &Lanes, tree: &Bvh4) -> Option<Hull> {
    let bounds = tree.bounds();
    let mut ends = [Vec3A::ZERO; 2 * LANES];
    let mut n = 0;
    let mut along = Vec3A::ZERO;
    for i in Bits(lanes) {
        let (origin, direction, tmin) = rays.segment(i);
        let end = tmax[i].min(leaves(origin, direction, &bounds)).max(tmin);
        ends[n] = origin + tmin * direction;
        ends[n + 1] = origin + end * direction;
        n += 2;
        along += direction.normalize_or_zero();
    }
    Hull::around(&ends[..n], along, tree.scale())
}

/// A t at or beyond which the ray from `origin` along `direction` is out
/// of box `b` for good (infinite where it runs along a slab for ever);
/// a little beyond the exit, for the rounding of the division (the
/// hull's padding covers the ends' rounding).
fn leaves(origin: Vec3A, direction: Vec3A, b: &Aabb) -> f32 {
    let far = Vec3A::select(direction.cmpge(Vec3A::ZERO), b.max, b.min);
    let t = Vec3A::select(
        direction.cmpeq(Vec3A::ZERO),
        Vec3A::INFINITY,
        (far - origin) / direction,
    );
    let t = t.min_element();
    t + t.abs() / 4096.0
}

/// The ray from `origin` along `direction` from `tmin` in the space that
/// `inv` maps world space to (the same t).
fn local(inv: &Affine3A, origin: Vec3A, direction: Vec3A, tmin: f32) -> Ray {
    Ray::new(
        inv.transform_point3a(origin),
        inv.transform_vector3a(direction) + Vec3A::ZERO,
        tmin,
    )
}

/// The rays of `lanes` (not empty) of packet `p` in the space that
/// `inv` maps world space to; the other lanes repeat the first of
/// them. (Made from the lanes' origins and directions: a whole single
/// ray per lane first cost the instanced forest 7 %.)
fn local_rays(inv: &Affine3A, p: &RayPacket, lanes: u32) -> [Ray; LANES] {
    let ray = |i: usize| {
        let (origin, direction, tmin) = p.segment(i);
        local(inv, origin, direction, tmin)
    };
    let first = lanes.trailing_zeros() as usize;
    let mut out = [ray(first); LANES];
    for i in Bits(lanes & !(1 << first)) {
        out[i] = ray(i);
    }
    out
}

/// Starts fetching the record of triangle `id` of `geo`, hit by a ray:
/// [`Accel::resolve`] reads it if the hit stays the nearest, and the
/// walk's remaining tests hide its load (on the forest, a cache miss per
/// ray otherwise).
#[inline(always)]
fn fetch_triangle(geo: &Geometry, id: u32) {
    if let Some(t) = geo.triangles.get(id as usize) {
        prefetch(t);
    }
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

/// A ray to cast: `origin + t·dir` with t in (tmin, tmax).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Query {
    pub origin: Vec3A,
    pub dir: Vec3A,
    pub tmin: f32,
    pub tmax: f32,
}

/// The nearest hit found so far: among equally near hits, the lowest
/// (instance, primitive) wins, so the result does not depend on the
/// order the traversal met them in (one ray or a packet, DESIGN §4).
#[derive(Clone, Copy)]
struct Closest {
    k: u32,
    prim: Prim,
    hit: shapes::LocalHit,
}

/// A packet's closest-hit search: each ray's best hit so far and the
/// bound a hit must stay under.
struct Search<'a> {
    best: [Option<Closest>; LANES],
    /// Each ray's bound: its `tmax`, then just above its best hit.
    tfar: Lanes,
    tmax: &'a Lanes,
}

impl Search<'_> {
    /// [`offer`]s `c` to ray `i`; returns its new bound.
    #[inline(always)]
    fn offer(&mut self, i: usize, c: Closest) -> f32 {
        offer(&mut self.best[i], c);
        self.tfar[i] = limit(&self.best[i], self.tmax[i]);
        self.tfar[i]
    }
}

/// Keeps `c` in `best` when it is nearer, or as near with a lower key.
#[inline(always)]
fn offer(best: &mut Option<Closest>, c: Closest) {
    let better = match best {
        Some(b) => {
            let (t, bt) = (c.hit.t, b.hit.t);
            t < bt || (t == bt && (c.k, c.prim) < (b.k, b.prim))
        }
        None => true,
    };
    if better {
        *best = Some(c);
    }
}

/// The bound a hit must stay under to matter: `tmax` before any hit, then
/// just above the best one, so an equally near hit is still tested.
#[inline(always)]
fn limit(best: &Option<Closest>, tmax: f32) -> f32 {
    match best {
        Some(b) => b.hit.t.next_up().min(tmax),
        None => tmax,
    }
}

/// `Accel::any_bundle` compiled for the instructions of a lane form, to be
/// called where the CPU has them (chosen at run time).
macro_rules! any_with {
    ($name:ident, $feature:literal, $form:ty) => {
        #[cfg(target_arch = "x86_64")]
        #[target_feature(enable = $feature)]
        unsafe fn $name(&self, rays: &[Ray; LANES], valid: u32, tmax: &Lanes) -> u32 {
            self.any_bundle::<$form>(Rays::Mixed(rays), valid, tmax)
        }
    };
}

/// `Accel::closest` compiled for the instructions of a lane form, to be
/// called where the CPU has them (chosen at run time).
macro_rules! closest_with {
    ($name:ident, $feature:literal, $form:ty) => {
        #[cfg(target_arch = "x86_64")]
        #[target_feature(enable = $feature)]
        unsafe fn $name(&self, rays: &[Ray; LANES], valid: u32, search: &mut Search) {
            self.closest::<$form>(rays, valid, search)
        }
    };
}

/// The ray-casting structure of one frame's scene. It shares the scene
/// (an [`Arc`]), so the frame that owns both can hand it to vision and to
/// the camera alike.
pub struct Accel {
    pub scene: Arc<Scene>,
    tlas: Option<Bvh4>,
    /// The only instance, when there is one (no top level to walk); the
    /// top level's leaf codes are instance indices.
    single: Option<u32>,
    /// Each instance's inverse transform; None for the identity (its
    /// rays are the world's).
    inst_inv: Vec<Option<Affine3A>>,
    /// Each instance's normal matrix (inverse transpose).
    inst_normal: Vec<Mat3A>,
    /// Each instance's transform at shutter close, where it moves.
    inst_end: Vec<Option<Affine3A>>,
    /// Whether anything moves over the shutter.
    moves: bool,
    blas: Vec<Option<Blas>>,
    /// The instructions the tests run (the same bits every way).
    simd: Simd,
}

/// The bottom level of one geometry; primitives with bounds that are not
/// finite or beyond ±[`crate::scene::MAX_COORDINATE`] never reach the
/// builder (its surface areas would overflow).
fn blas(g: &Geometry, materials: &[Material], ends: &[Option<Affine3A>]) -> Option<Blas> {
    let mut prims = Vec::with_capacity(g.shapes.len() + g.triangles.len());
    let mut boxes = Vec::with_capacity(prims.capacity());
    let end = |i: usize| ends.get(i).copied().flatten();
    for (i, s) in g.shapes.iter().enumerate() {
        // A moving shape's box holds it at both ends, so all the time.
        let at_end = |b: Aabb| match end(i) {
            Some(transform) => shapes::bounds(&Shape { transform, ..*s }).map(|e| b.union(&e)),
            None => Some(b),
        };
        if let Some(b) = shapes::bounds(s).and_then(at_end) {
            prims.push(Prim::Shape(i as u32));
            boxes.push(b);
        }
    }
    for (i, t) in g.triangles.iter().enumerate() {
        if let Some(b) = shapes::triangle_bounds(&t.v) {
            prims.push(Prim::Triangle(i as u32));
            boxes.push(b);
        }
    }
    let tree = Bvh4::build(&boxes, BLAS_LEAF)?;
    let mut b = Blas {
        tris: Vec::new(),
        ids: Vec::new(),
        shapes: Vec::new(),
        sides: Vec::new(),
        tree,
    };
    let mut codes = Vec::with_capacity(b.tree.leaf_count() as usize);
    let mut tris = Vec::new();
    for l in 0..b.tree.leaf_count() {
        tris.clear();
        let shapes_from = b.shapes.len() as u32;
        for &p in b.tree.leaf(l) {
            match prims[p as usize] {
                Prim::Shape(i) => {
                    let s = &g.shapes[i as usize];
                    let cloud = materials
                        .get(s.material as usize)
                        .is_some_and(|m| m.texture == Some(Texture::Cloud));
                    b.shapes.push(ShapeLeaf {
                        index: i,
                        inverse: s.transform.inverse(),
                        shadows: !cloud,
                        end: end(i as usize),
                    });
                }
                Prim::Triangle(i) => tris.push((i, g.triangles[i as usize].v)),
            }
        }
        // In index order: a pack's lowest lane among equally near hits
        // is then its lowest index (the tie-break).
        tris.sort_unstable_by_key(|&(i, _)| i);
        let packs_from = b.tris.len() as u32;
        for chunk in tris.chunks(4) {
            let (mut v, mut ids) = ([[Vec3::ZERO; 3]; 4], [u32::MAX; 4]);
            for (lane, &(i, t)) in chunk.iter().enumerate() {
                (v[lane], ids[lane]) = (t, i);
            }
            b.tris.push(Tri4::pack(&v[..chunk.len()]));
            b.ids.push(ids);
        }
        let (packs, shapes) = (
            (packs_from, b.tris.len() as u32),
            (shapes_from, b.shapes.len() as u32),
        );
        let count = packs.1 - packs.0;
        codes.push(
            if shapes.0 == shapes.1 && (1..=4).contains(&count) && packs.0 < SIDE >> 2 {
                packs.0 << 2 | (count - 1)
            } else {
                b.sides.push([packs, shapes]);
                SIDE | (b.sides.len() as u32 - 1)
            },
        );
    }
    b.tree.set_leaf_codes(|l| codes[l as usize]);
    Some(b)
}

impl Accel {
    /// Builds the bottom levels, then the top level over the instances
    /// whose bounds are finite.
    pub fn new(scene: impl Into<Arc<Scene>>) -> Self {
        Accel::moving(scene, &Motion::default())
    }

    /// [`Accel::new`] for a scene whose shapes and instances move over
    /// the shutter as `motion` says: their boxes hold them at both ends,
    /// and a ray meets them at its [`Ray::time`].
    pub fn moving(scene: impl Into<Arc<Scene>>, motion: &Motion) -> Self {
        let scene: Arc<Scene> = scene.into();
        let blas: Vec<Option<Blas>> = scene
            .geometries
            .iter()
            .enumerate()
            .map(|(k, g)| {
                let ends = motion.shapes.get(k).map_or(&[][..], Vec::as_slice);
                blas(g, &scene.materials, ends)
            })
            .collect();
        let inst_end: Vec<Option<Affine3A>> = (0..scene.instances.len())
            .map(|k| motion.instances.get(k).copied().flatten())
            .collect();
        let mut inst = Vec::new();
        let mut boxes = Vec::new();
        for (k, i) in scene.instances.iter().enumerate() {
            let Some(Some(b)) = blas.get(i.geometry as usize) else {
                continue;
            };
            let placed = |t: &Affine3A| aabb::transformed(&b.tree.bounds(), t);
            let wb = match &inst_end[k] {
                Some(end) => placed(&i.transform)
                    .zip(placed(end))
                    .map(|(a, e)| a.union(&e)),
                None => placed(&i.transform),
            };
            if let Some(wb) = wb {
                inst.push(k as u32);
                boxes.push(wb);
            }
        }
        let mut tlas = Bvh4::build(&boxes, 1);
        if let Some(t) = &mut tlas {
            let codes: Vec<u32> = (0..t.leaf_count())
                .map(|l| inst[t.leaf(l)[0] as usize])
                .collect();
            t.set_leaf_codes(|l| codes[l as usize]);
        }
        let single = match inst[..] {
            [k] => Some(k),
            _ => None,
        };
        let inverse: Vec<Affine3A> = scene
            .instances
            .iter()
            .map(|i| i.transform.inverse())
            .collect();
        let inst_normal = inverse.iter().map(|m| m.matrix3.transpose()).collect();
        let inst_inv = inverse
            .into_iter()
            .map(|m| (m != Affine3A::IDENTITY).then_some(m))
            .collect();
        Accel {
            scene,
            tlas,
            single,
            inst_inv,
            inst_normal,
            inst_end,
            moves: !motion.is_still(),
            blas,
            simd: Simd::detect(),
        }
    }

    /// The same structure with the instructions `simd` for its tests,
    /// single rays and packets (tests compare them; [`Accel::new`] takes
    /// the widest the machine has).
    pub fn with_simd(mut self, simd: Simd) -> Self {
        self.simd = simd;
        self
    }

    /// Whether anything moves over the shutter (then only the single
    /// rays' `cast_at` and `occluded_at` see it).
    pub fn moves(&self) -> bool {
        self.moves
    }

    /// The instructions its tests run.
    pub(super) fn simd(&self) -> Simd {
        self.simd
    }

    /// The ray in instance `k`'s geometry space (same t).
    fn local_ray(&self, k: usize, r: &Ray) -> Ray {
        if let Some(end) = self.inst_end[k].filter(|_| r.time > 0.0) {
            let now = motion::lerp(&self.scene.instances[k].transform, &end, r.time);
            let mut local = local(&now.inverse(), r.origin, r.direction, r.tmin);
            local.time = r.time;
            return local;
        }
        match &self.inst_inv[k] {
            Some(inv) => {
                let mut local = local(inv, r.origin, r.direction, r.tmin);
                local.time = r.time;
                local
            }
            None => *r,
        }
    }

    /// Closest hit within instance `k` under `tmax`, offered to `best`;
    /// returns the new bound.
    #[inline]
    fn instance_closest(&self, k: usize, r: &Ray, tmax: f32, best: &mut Option<Closest>) -> f32 {
        let Some((b, geo, r)) = self.instance(k, r) else {
            return tmax;
        };
        let k = k as u32;
        let mut bound = tmax;
        b.tree.traverse(
            &r,
            tmax,
            |code| b.fetch(code),
            |l, tmax| {
                let (first, packs, shapes) = b.leaf(l);
                let incoming = *tmax;
                *tmax = tri4::nearest_each(packs, &r, incoming, self.simd, |j, t, lane| {
                    // The normal is computed for the closest only.
                    let hit = shapes::LocalHit {
                        t,
                        normal: Vec3A::ZERO,
                    };
                    let id = b.ids[first + j][lane];
                    fetch_triangle(geo, id);
                    let prim = Prim::Triangle(id);
                    offer(best, Closest { k, prim, hit });
                    limit(best, incoming)
                });
                for s in shapes {
                    if let Some(hit) = s.hit(geo, &r, *tmax) {
                        let prim = Prim::Shape(s.index);
                        offer(best, Closest { k, prim, hit });
                        *tmax = limit(best, *tmax);
                    }
                }
                bound = *tmax;
                false
            },
        );
        bound
    }

    /// Whether anything in instance `k` but a cloud layer blocks the ray
    /// before `tmax`.
    #[inline]
    fn instance_any(&self, k: usize, r: &Ray, tmax: f32) -> bool {
        let Some((b, geo, r)) = self.instance(k, r) else {
            return false;
        };
        b.tree.traverse_any(
            &r,
            tmax,
            |code| b.fetch(code),
            |l, tmax| blocks(b, geo, l, &r, *tmax, self.simd),
        )
    }

    /// Instance `k`'s tree and geometry, and the ray in its space (same
    /// t); None when its geometry has nothing to hit.
    #[inline]
    fn instance(&self, k: usize, r: &Ray) -> Option<(&Blas, &Geometry, Ray)> {
        let g = self.scene.instances[k].geometry as usize;
        let b = self.blas[g].as_ref()?;
        Some((b, &self.scene.geometries[g], self.local_ray(k, r)))
    }

    /// The ray, or None when it cannot hit anything. Negative zeros in the
    /// direction are made positive so the slab tests see one sign.
    fn ray(&self, origin: Vec3A, dir: Vec3A, tmin: f32) -> Option<Ray> {
        let ok = self.tlas.is_some() && origin.is_finite() && dir.is_finite() && dir != Vec3A::ZERO;
        ok.then(|| Ray::new(origin, dir + Vec3A::ZERO, tmin))
    }

    /// The closest hit of the ray `origin + t·dir` with t in (tmin, tmax).
    pub fn cast(&self, origin: Vec3A, dir: Vec3A, tmin: f32, tmax: f32) -> Option<Hit> {
        self.cast_at(origin, dir, tmin, tmax, 0.0)
    }

    /// [`Accel::cast`] at the instant `time` (0..1) of the shutter.
    pub fn cast_at(
        &self,
        origin: Vec3A,
        dir: Vec3A,
        tmin: f32,
        tmax: f32,
        time: f32,
    ) -> Option<Hit> {
        let mut r = self.ray(origin, dir, tmin)?;
        r.time = time;
        let tlas = self.tlas.as_ref()?;
        let mut best = None;
        // One instance (a scene without repetitions): no top level to walk.
        if let Some(k) = self.single {
            self.instance_closest(k as usize, &r, tmax, &mut best);
        } else {
            tlas.traverse(
                &r,
                tmax,
                |_| {},
                |k, tmax| {
                    *tmax = self.instance_closest(k as usize, &r, *tmax, &mut best);
                    false
                },
            );
        }
        let c = best?;
        Some(self.resolve(c.k, c.prim, c.hit))
    }

    /// Whether anything but a cloud layer blocks the ray within (tmin, tmax).
    pub fn occluded(&self, origin: Vec3A, dir: Vec3A, tmin: f32, tmax: f32) -> bool {
        self.occluded_at(origin, dir, tmin, tmax, 0.0)
    }

    /// [`Accel::occluded`] at the instant `time` (0..1) of the shutter.
    pub fn occluded_at(&self, origin: Vec3A, dir: Vec3A, tmin: f32, tmax: f32, time: f32) -> bool {
        self.ray(origin, dir, tmin).is_some_and(|mut r| {
            r.time = time;
            self.any_one(&r, tmax)
        })
    }

    /// Whether anything but a cloud layer blocks `r` before `tmax`.
    fn any_one(&self, r: &Ray, tmax: f32) -> bool {
        let Some(tlas) = &self.tlas else { return false };
        if let Some(k) = self.single {
            return self.instance_any(k as usize, r, tmax);
        }
        tlas.traverse_any(
            r,
            tmax,
            |_| {},
            |k, tmax| self.instance_any(k as usize, r, *tmax),
        )
    }

    /// [`Accel::occluded`] of each query, the same answers, into `out`:
    /// in bundles of up to [`LANES`], whose walk tests each box once for
    /// the bundle before it tests it for each ray (see [`super::hull`]):
    /// a pixel's shadow rays toward one light run close together.
    pub fn occluded_all(&self, queries: &[Query], out: &mut Vec<bool>) {
        out.clear();
        let mut rays = [Ray::new(Vec3A::ZERO, Vec3A::X, 0.0); LANES];
        for chunk in queries.chunks(LANES) {
            let blocked = self
                .chunk(chunk, &mut rays)
                .map_or(0, |(valid, tmax)| match self.simd {
                    // SAFETY: each is chosen only where the CPU has it.
                    #[cfg(target_arch = "x86_64")]
                    Simd::Avx => unsafe { self.any_avx(&rays, valid, &tmax) },
                    #[cfg(target_arch = "x86_64")]
                    Simd::Avx512 => unsafe { self.any_avx512(&rays, valid, &tmax) },
                    _ => self.any_bundle::<Base>(Rays::Mixed(&rays), valid, &tmax),
                });
            out.extend((0..chunk.len()).map(|i| blocked >> i & 1 != 0));
        }
    }

    any_with!(any_avx512, "avx512f", Avx512);
    any_with!(any_avx, "avx", Avx);

    /// The mask of the rays of `valid` that something but a cloud layer
    /// blocks before their `tmax`.
    #[inline(always)]
    pub(super) fn any_bundle<W: Wide>(&self, rays: Rays, valid: u32, tmax: &Lanes) -> u32 {
        let Some(tlas) = &self.tlas else { return 0 };
        // The region is made for a top level's walk only: in a scene of
        // one instance, making it cost more than it spared (see
        // `instance_bundle`).
        let hull = match self.single {
            Some(_) => None,
            None => match bundle(&rays, valid, tmax, tlas) {
                Some(hull) => Some(hull),
                None => return self.one_by_one(&rays, valid, tmax),
            },
        };
        let hull = hull.as_ref();
        match rays {
            Rays::Packet(p) if valid.count_ones() >= MIN_BUNDLE => {
                self.any_packet::<W>(p, valid, tmax, hull)
            }
            Rays::Packet(_) => self.one_by_one(&rays, valid, tmax),
            Rays::Mixed(rays) => {
                let mut blocked = 0;
                for group in packet::groups(rays, valid) {
                    blocked |= if group.count_ones() < MIN_BUNDLE {
                        self.one_by_one(&Rays::Mixed(rays), group, tmax)
                    } else {
                        self.any_packet::<W>(&RayPacket::new(rays, group), group, tmax, hull)
                    };
                }
                blocked
            }
        }
    }

    /// [`Accel::any_bundle`] of the rays of `lanes` in packet `p`.
    #[inline(always)]
    fn any_packet<W: Wide>(
        &self,
        p: &RayPacket,
        lanes: u32,
        tmax: &Lanes,
        hull: Option<&Hull>,
    ) -> u32 {
        let Some(tlas) = &self.tlas else { return 0 };
        if let Some(k) = self.single {
            return self.instance_bundle::<W>(k, p, lanes, tmax, None);
        }
        let mut blocked = 0;
        let mut walk = tlas.bundle_walk(lanes);
        while let Some((k, lanes)) = walk.next::<W>(tlas, hull, p, tmax, |_| {}) {
            let done = self.instance_bundle::<W>(k, p, lanes, tmax, hull);
            walk.close(done);
            blocked |= done;
        }
        blocked
    }

    /// The mask of the rays of `lanes` that something blocks, each traced
    /// on its own.
    fn one_by_one(&self, rays: &Rays, lanes: u32, tmax: &Lanes) -> u32 {
        packet::keep(lanes, |i| self.any_one(&rays.ray(i), tmax[i]))
    }

    /// The mask of the rays of `lanes` in packet `p` that something in
    /// instance `k` blocks; `hull`, where the top level's walk made one,
    /// bounds them in world space (and a region in the instance's space
    /// is made for its tree: on the instanced forest that paid, while a
    /// scene of one instance, walked without a region, was 2.4 % faster
    /// for not making one).
    #[inline(always)]
    fn instance_bundle<W: Wide>(
        &self,
        k: u32,
        p: &RayPacket,
        lanes: u32,
        tmax: &Lanes,
        hull: Option<&Hull>,
    ) -> u32 {
        let g = self.scene.instances[k as usize].geometry as usize;
        let Some(b) = &self.blas[g] else { return 0 };
        let geo = &self.scene.geometries[g];
        let Some(inv) = &self.inst_inv[k as usize] else {
            return self.blas_any::<W>(b, geo, p, lanes, tmax, hull);
        };
        let one_by_one =
            || packet::keep(lanes, |i| self.instance_any(k as usize, &p.ray(i), tmax[i]));
        if lanes.count_ones() < MIN_BUNDLE {
            return one_by_one();
        }
        let local = local_rays(inv, p, lanes);
        let hull = match hull {
            None => None,
            Some(_) => match bundle(&Rays::Mixed(&local), lanes, tmax, &b.tree) {
                Some(hull) => Some(hull),
                None => return one_by_one(),
            },
        };
        // A transform may turn the rays apart: one packet per key. (A
        // loop, not a closure, which would not take the lane form's
        // instructions.)
        let mut blocked = 0;
        for group in packet::groups(&local, lanes) {
            let lp = RayPacket::new(&local, group);
            blocked |= self.blas_any::<W>(b, geo, &lp, group, tmax, hull.as_ref());
        }
        blocked
    }

    /// The mask of the rays of `lanes` in packet `p` (in the bottom
    /// level's space) that something in it blocks.
    #[inline(always)]
    fn blas_any<W: Wide>(
        &self,
        b: &Blas,
        geo: &Geometry,
        p: &RayPacket,
        lanes: u32,
        tmax: &Lanes,
        hull: Option<&Hull>,
    ) -> u32 {
        let mut blocked = 0;
        let mut walk = b.tree.bundle_walk(lanes);
        while let Some((code, rays)) = walk.next::<W>(&b.tree, hull, p, tmax, |code| b.fetch(code))
        {
            let done = if together::<W>(rays) {
                blocks_together::<W>(b, geo, code, p, rays, tmax)
            } else {
                packet::keep(rays, |i| {
                    blocks(b, geo, code, &p.ray(i), tmax[i], self.simd)
                })
            };
            walk.close(done);
            blocked |= done;
        }
        blocked
    }

    /// [`Accel::cast`] of each query, the same hits, into `out`: traced
    /// in packets of up to [`LANES`] (coherent rays, such as a pixel's
    /// samples, share their node and triangle fetches and tests).
    pub fn cast_all(&self, queries: &[Query], out: &mut Vec<Option<Hit>>) {
        out.clear();
        let mut rays = [Ray::new(Vec3A::ZERO, Vec3A::X, 0.0); LANES];
        for chunk in queries.chunks(LANES) {
            let Some((valid, tmax)) = self.chunk(chunk, &mut rays) else {
                out.extend(chunk.iter().map(|_| None));
                continue;
            };
            let mut search = Search {
                tfar: tmax,
                tmax: &tmax,
                best: [None; LANES],
            };
            match self.simd {
                // SAFETY: each is chosen only where the CPU has it.
                #[cfg(target_arch = "x86_64")]
                Simd::Avx => unsafe { self.closest_avx(&rays, valid, &mut search) },
                #[cfg(target_arch = "x86_64")]
                Simd::Avx512 => unsafe { self.closest_avx512(&rays, valid, &mut search) },
                _ => self.closest::<Base>(&rays, valid, &mut search),
            }
            let n = out.len();
            out.resize(n + chunk.len(), None);
            self.resolve_into(&search.best[..chunk.len()], &mut out[n..]);
        }
    }

    /// The closest hits of the rays of `valid` into `out` (the others'
    /// are None), as [`Accel::cast_all`] finds them: for a pixel's samples
    /// cast and shaded together ([`super::batch`]).
    #[inline(always)]
    pub(super) fn closest_hits<W: Wide>(
        &self,
        rays: Rays,
        valid: u32,
        out: &mut [Option<Hit>; LANES],
    ) {
        let tmax = [f32::INFINITY; LANES];
        let mut search = Search {
            tfar: tmax,
            tmax: &tmax,
            best: [None; LANES],
        };
        match rays {
            Rays::Packet(p) => self.closest_packet::<W>(p, valid, &mut search),
            Rays::Mixed(rays) => self.closest::<W>(rays, valid, &mut search),
        }
        self.resolve_into(&search.best, out);
    }

    /// The hits of a packet's closest-hit search into `out`. A pixel's
    /// samples mostly meet one triangle: its details are found once (a
    /// triangle's do not depend on the hit point). (Written in place: an
    /// iterator of hits copied each in pieces, and reading the pieces
    /// back whole stalled, 4 % of the forest's render.)
    fn resolve_into(&self, best: &[Option<Closest>], out: &mut [Option<Hit>]) {
        let mut last: Option<usize> = None;
        for (i, c) in best.iter().enumerate() {
            let Some(c) = c else {
                out[i] = None;
                continue;
            };
            if let Some(h) = last.and_then(|j| out[j].as_ref()) {
                if h.instance == c.k && h.prim == c.prim && matches!(c.prim, Prim::Triangle(_)) {
                    out[i] = Some(Hit { t: c.hit.t, ..*h });
                    continue;
                }
            }
            out[i] = Some(self.resolve(c.k, c.prim, c.hit));
            last = Some(i);
        }
    }

    /// The rays of up to [`LANES`] queries into `rays` (in place: a
    /// returned array was copied twice, 2.5 KB each), the mask of those
    /// that can hit anything, and their `tmax`; None when none can. The
    /// other lanes keep the rays they held (masked out: any ray will do).
    fn chunk(&self, queries: &[Query], rays: &mut [Ray; LANES]) -> Option<(u32, Lanes)> {
        let mut valid = 0;
        for (i, q) in queries.iter().enumerate().take(LANES) {
            if let Some(ray) = self.ray(q.origin, q.dir, q.tmin) {
                rays[i] = ray;
                valid |= 1 << i;
            }
        }
        let tmax = std::array::from_fn(|i| queries.get(i).map_or(0.0, |q| q.tmax));
        (valid != 0).then_some((valid, tmax))
    }

    closest_with!(closest_avx512, "avx512f", Avx512);
    closest_with!(closest_avx, "avx", Avx);

    /// The closest hits of the rays of `valid` (one ray's walk per lane,
    /// so each finds what [`Accel::cast`] finds).
    #[inline(always)]
    fn closest<W: Wide>(&self, rays: &[Ray; LANES], valid: u32, search: &mut Search) {
        for group in packet::groups(rays, valid) {
            self.closest_packet::<W>(&RayPacket::new(rays, group), group, search);
        }
    }

    /// The closest hits of the rays of `lanes` in packet `p`.
    #[inline(always)]
    fn closest_packet<W: Wide>(&self, p: &RayPacket, lanes: u32, search: &mut Search) {
        let Some(tlas) = &self.tlas else { return };
        if let Some(k) = self.single {
            return self.instance_closest_packet::<W>(k, p, lanes, search);
        }
        let mut walk = tlas.packet_walk::<W>(p, lanes);
        while let Some((k, lanes)) = walk.next::<W>(tlas, p, &search.tfar, |_| {}) {
            self.instance_closest_packet::<W>(k, p, lanes, search);
        }
    }

    /// [`Accel::instance_closest`] for the rays of `lanes` in packet `p`.
    #[inline(always)]
    fn instance_closest_packet<W: Wide>(
        &self,
        k: u32,
        p: &RayPacket,
        lanes: u32,
        search: &mut Search,
    ) {
        let g = self.scene.instances[k as usize].geometry as usize;
        let Some(b) = &self.blas[g] else { return };
        let geo = &self.scene.geometries[g];
        let Some(inv) = &self.inst_inv[k as usize] else {
            return self.blas_closest::<W>(b, geo, k, p, lanes, search);
        };
        let local = local_rays(inv, p, lanes);
        // A transform may turn the rays apart: one packet per key.
        for group in packet::groups(&local, lanes) {
            let lp = RayPacket::new(&local, group);
            self.blas_closest::<W>(b, geo, k, &lp, group, search);
        }
    }

    /// The closest hits in one bottom level of the rays of `lanes` (in
    /// its space).
    #[inline(always)]
    fn blas_closest<W: Wide>(
        &self,
        b: &Blas,
        geo: &Geometry,
        k: u32,
        p: &RayPacket,
        lanes: u32,
        search: &mut Search,
    ) {
        let mut walk = b.tree.packet_walk::<W>(p, lanes);
        while let Some((code, lanes)) =
            walk.next::<W>(&b.tree, p, &search.tfar, |code| b.fetch(code))
        {
            let (first, packs, shapes) = b.leaf(code);
            let triangle = |j: usize, lane: usize, t: f32| {
                let id = b.ids[first + j][lane];
                fetch_triangle(geo, id);
                Closest {
                    k,
                    prim: Prim::Triangle(id),
                    hit: shapes::LocalHit {
                        t,
                        normal: Vec3A::ZERO,
                    },
                }
            };
            if together::<W>(lanes) {
                for (j, pack) in packs.iter().enumerate() {
                    for lane in 0..pack.count() {
                        let (hit, t) = pack.packet_lanes::<W>(lane, p, lanes, &search.tfar);
                        for i in Bits(hit) {
                            search.offer(i, triangle(j, lane, t[i]));
                        }
                    }
                }
            } else {
                for i in Bits(lanes) {
                    let tfar = search.tfar[i];
                    tri4::nearest_each(packs, &p.ray(i), tfar, self.simd, |j, t, lane| {
                        search.offer(i, triangle(j, lane, t))
                    });
                }
            }
            for s in shapes {
                for i in Bits(lanes) {
                    if let Some(hit) = s.hit(geo, &p.ray(i), search.tfar[i]) {
                        let prim = Prim::Shape(s.index);
                        search.offer(i, Closest { k, prim, hit });
                    }
                }
            }
        }
    }

    /// World-space details of a local hit.
    fn resolve(&self, k: u32, prim: Prim, h: shapes::LocalHit) -> Hit {
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
            normal: (self.inst_normal[k as usize] * n_geo).normalize_or(Vec3A::Y),
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

    /// Levels of the deepest tree, top plus bottom (tests of deep
    /// scenes: the traversal stack is sized from it).
    pub fn depth(&self) -> usize {
        let top = self.tlas.as_ref().map_or(0, Bvh4::depth);
        top + self
            .blas
            .iter()
            .flatten()
            .map(|b| b.tree.depth())
            .max()
            .unwrap_or(0)
    }
}

/// A normal carried through the linear part `m` (inverse transpose).
#[inline]
fn normal_to(m: &Mat3A, n: Vec3A) -> Vec3A {
    m.inverse().transpose() * n
}
