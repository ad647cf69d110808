//! A pixel's samples shaded together, one sample per lane of a [`Wide`]
//! value: the points where their camera rays meet surfaces, the hard
//! shadow rays toward each point and directional light (one bundle per
//! light), and the local light. It computes what [`shade::shade_seen`]
//! computes one sample at a time, with the same operations in the same
//! order (see [`super::v3`]), so each sample gets the same bits on every
//! path; the test below compares them. One at a time, it took a third of
//! the forest's render besides the casting (docs/performance.md).
//!
//! The samples it does not take — misses, surfaces without a material,
//! cloud layers — and the bounces off mirrors and glass go through the
//! one-at-a-time shading; scenes with sphere lights (soft shadows, many
//! rays per sample) shade one at a time throughout ([`applies`]).

use glam::{Vec3, Vec3A};

use super::accel::{Accel, Hit, Query};
use super::bvh4::Ray;
use super::packet::{Bits, Lanes, LANES};
use super::sample::Settings;
use super::shade::{self, EPS};
use super::tri4::Simd;
use super::v3::V3;
#[cfg(not(target_arch = "x86_64"))]
use super::wide::Scalar as Base;
#[cfg(target_arch = "x86_64")]
use super::wide::{Avx, Avx512, Sse as Base};
use super::wide::{Mask, Wide};
use crate::random::{self, Stream};
use crate::scene::material::Texture;
use crate::scene::{LightKind, Material};

/// Whether [`shade`] serves the scene: it has no sphere light.
pub fn applies(accel: &Accel) -> bool {
    !accel
        .scene
        .lights
        .iter()
        .any(|l| matches!(l.kind, LightKind::Sphere { .. }))
}

/// The colours of a pixel's samples into `out`: sample `s` casts
/// `queries[s]`, which met `hits[s]`; `key` is the pixel's (each sample's
/// own keys the bounces' soft shadows, as [`super::sample::pixel`] keys
/// them). Only for scenes it [`applies`] to.
pub fn shade(
    accel: &Accel,
    st: &Settings,
    queries: &[Query],
    hits: &[Option<Hit>],
    key: u64,
    out: &mut Vec<Vec3>,
) {
    out.clear();
    for (c, (q, h)) in queries.chunks(LANES).zip(hits.chunks(LANES)).enumerate() {
        let chunk = Chunk {
            queries: q,
            hits: h,
            key,
            first: c * LANES,
        };
        let colours = match accel.simd() {
            // SAFETY: each is chosen only where the CPU has it.
            #[cfg(target_arch = "x86_64")]
            Simd::Avx => unsafe { chunk.shade_avx(accel, st) },
            #[cfg(target_arch = "x86_64")]
            Simd::Avx512 => unsafe { chunk.shade_avx512(accel, st) },
            _ => chunk.shade::<Base>(accel, st),
        };
        out.extend_from_slice(&colours[..q.len()]);
    }
}

/// Up to [`LANES`] samples of a pixel, from its sample `first` on.
struct Chunk<'a> {
    queries: &'a [Query],
    hits: &'a [Option<Hit>],
    key: u64,
    first: usize,
}

/// A material's values, a lane each.
struct Materials<W> {
    ambient: V3<W>,
    diffuse: V3<W>,
    specular: V3<W>,
    transmit: W,
}

/// `Chunk::shade` compiled for the instructions of a lane form, to be
/// called where the CPU has them (chosen at run time).
macro_rules! shade_with {
    ($name:ident, $feature:literal, $form:ty) => {
        #[cfg(target_arch = "x86_64")]
        #[target_feature(enable = $feature)]
        unsafe fn $name(&self, accel: &Accel, st: &Settings) -> [Vec3; LANES] {
            self.shade::<$form>(accel, st)
        }
    };
}

impl Chunk<'_> {
    shade_with!(shade_avx512, "avx512f", Avx512);
    shade_with!(shade_avx, "avx", Avx);

    /// Sample `i`'s key for its soft shadows.
    fn key(&self, i: usize) -> u64 {
        random::key(self.key, Stream::Pixel, (self.first + i) as u64, 1)
    }

    /// The samples' colours (lanes past the chunk's samples are zero).
    #[inline(always)]
    fn shade<W: Wide>(&self, accel: &Accel, st: &Settings) -> [Vec3; LANES] {
        let mut colour = [Vec3::ZERO; LANES];
        let materials = &accel.scene.materials;
        // The samples taken here (`fast`), their rays, hits and materials.
        // Other lanes hold a harmless ray and hit.
        let (mut o, mut d, mut normal) = ([[0.0; LANES]; 3], [[0.0; LANES]; 3], [[0.0; LANES]; 3]);
        let mut t = [0.0; LANES];
        let mut material = [0usize; LANES];
        let mut fast = 0u32;
        for (i, (q, hit)) in self.queries.iter().zip(self.hits).enumerate() {
            let Some(hit) = hit else {
                colour[i] = shade::background(accel, q.dir);
                continue;
            };
            let Some(m) = materials.get(hit.material as usize) else {
                // A surface without a material is black.
                continue;
            };
            if m.texture == Some(Texture::Cloud) {
                if let Some(pt) = shade::point(accel, hit, q.origin, q.dir) {
                    colour[i] = shade::shade_seen(accel, &pt, q.dir, st, 0, self.key(i), &[]);
                }
                continue;
            }
            fast |= 1 << i;
            for a in 0..3 {
                o[a][i] = q.origin[a];
                d[a][i] = q.dir[a];
                normal[a][i] = hit.normal[a];
            }
            t[i] = hit.t;
            material[i] = hit.material as usize;
        }
        if fast == 0 {
            return colour;
        }
        let zero = W::splat(0.0);
        let one = W::splat(1.0);
        let (o, d, normal) = (V3::<W>::load(&o), V3::<W>::load(&d), V3::<W>::load(&normal));
        // `shade::point`: the point, and the normal facing the ray.
        let p = o + d.scale(W::load(&t));
        let outside = normal.dot(d).lt(zero);
        let mut n = V3::select(outside, normal, -normal);
        let mut m = self.materials::<W>(materials, &material, fast);
        self.textures(accel, &mut n, &mut m, fast);
        let lift = p + n.scale(W::splat(EPS)).scale(one.add(p.max_abs()));
        // `shade_surface`: ambient, then each light's diffuse and specular.
        let mut local = m.ambient;
        let back = -d;
        for light in &accel.scene.lights {
            let (l, dist) = match light.kind {
                LightKind::Directional { .. } => {
                    let (l, dist) = shade::toward(light, Vec3A::ZERO);
                    (V3::splat(l), W::splat(dist))
                }
                // (No sphere lights: `applies`.)
                _ => {
                    let to = V3::splat(light.position.into()) - p;
                    (to.normalize_or_zero(), to.length())
                }
            };
            let ndl = n.dot(l);
            let facing = l.nonzero();
            // `shade_surface` goes on where `!(ndl <= 0)`, `shadow_rays`
            // casts where `ndl > 0`: the same but for a NaN.
            let lit = ndl.le(zero).andnot(facing).bits() & fast;
            let visible = if st.shadows {
                let cast = ndl.gt(zero).and(facing).bits() & fast;
                lit & !self.blocked::<W>(accel, lift, l, dist, cast, lit & !cast)
            } else {
                lit
            };
            if visible == 0 {
                continue;
            }
            // `reflect(-l, n)`.
            let r = -l;
            let r = r - n.scale(W::splat(2.0).mul(r.dot(n)));
            let cosine = r.dot(back).store();
            let mut spec = [0.0; LANES];
            for i in Bits(visible) {
                let shininess = materials[material[i]].shininess;
                spec[i] = cosine[i].max(0.0).powf(shininess.max(1.0));
            }
            let spec = W::load(&spec);
            let term = (m.diffuse.scale(ndl) + m.specular.scale(spec)) * V3::splat3(light.color);
            let visible = W::flags(visible);
            local = V3::select(visible, local + term, local);
        }
        let lanes = local.scale(one.sub(m.transmit)).store();
        let (p, n, d, lift) = (p.store(), n.store(), d.store(), lift.store());
        for i in Bits(fast) {
            let c = Vec3::new(lanes[0][i], lanes[1][i], lanes[2][i]);
            let mt = &materials[material[i]];
            colour[i] = if mt.reflect > 0.0 || mt.transmit > 0.0 {
                let outside = outside.bits() >> i & 1 != 0;
                let (p, n, d, lift) = (at(&p, i), at(&n, i), at(&d, i), at(&lift, i));
                shade::bounces(accel, mt, c, p, n, d, lift, outside, st, 0, self.key(i))
            } else {
                c
            };
        }
        colour
    }

    /// Where a sample's material has a texture (marble, bump), its
    /// normal and diffuse colour as [`shade::point`] finds them.
    #[inline(always)]
    fn textures<W: Wide>(&self, accel: &Accel, n: &mut V3<W>, m: &mut Materials<W>, fast: u32) {
        let materials = &accel.scene.materials;
        let mut textured = 0;
        for i in Bits(fast) {
            if let Some(h) = &self.hits[i] {
                if materials[h.material as usize].texture.is_some() {
                    textured |= 1 << i;
                }
            }
        }
        if textured == 0 {
            return;
        }
        let (mut normal, mut diffuse) = (n.store(), m.diffuse.store());
        for i in Bits(textured) {
            let (q, hit) = (&self.queries[i], &self.hits[i]);
            if let Some(pt) = hit.and_then(|h| shade::point(accel, &h, q.origin, q.dir)) {
                for a in 0..3 {
                    normal[a][i] = pt.n[a];
                    diffuse[a][i] = pt.diffuse[a];
                }
            }
        }
        *n = V3::load(&normal);
        m.diffuse = V3::load(&diffuse);
    }

    /// Which samples' hard shadow rays from `lift` along `l` are blocked
    /// within `dist`: those of `cast` as one bundle, those of `alone` one
    /// by one.
    #[inline(always)]
    fn blocked<W: Wide>(
        &self,
        accel: &Accel,
        lift: V3<W>,
        l: V3<W>,
        dist: W,
        cast: u32,
        alone: u32,
    ) -> u32 {
        let (from, dir, dist) = (lift.store(), l.store(), dist.store());
        let mut rays = [Ray::new(Vec3A::ZERO, Vec3A::X, 0.0); LANES];
        let mut valid = 0;
        for i in Bits(cast) {
            if let Some(r) = accel.ray(at(&from, i), at(&dir, i), 0.0) {
                rays[i] = r;
                valid |= 1 << i;
            }
        }
        let mut blocked = if valid == 0 {
            0
        } else {
            accel.any_bundle::<W>(&rays, valid, &dist)
        };
        for i in Bits(alone) {
            if accel.occluded(at(&from, i), at(&dir, i), 0.0, dist[i]) {
                blocked |= 1 << i;
            }
        }
        blocked
    }

    /// The lanes' materials' values (one splat when they share one).
    #[inline(always)]
    fn materials<W: Wide>(
        &self,
        all: &[Material],
        index: &[usize; LANES],
        fast: u32,
    ) -> Materials<W> {
        let first = index[fast.trailing_zeros() as usize];
        if Bits(fast).all(|i| index[i] == first) {
            let m = &all[first];
            return Materials {
                ambient: V3::splat3(m.ambient),
                diffuse: V3::splat3(m.diffuse),
                specular: V3::splat3(m.specular),
                transmit: W::splat(m.transmit),
            };
        }
        let (mut ambient, mut diffuse, mut specular) =
            ([[0.0; LANES]; 3], [[0.0; LANES]; 3], [[0.0; LANES]; 3]);
        let mut transmit = [0.0; LANES];
        for i in Bits(fast) {
            let m = &all[index[i]];
            for a in 0..3 {
                ambient[a][i] = m.ambient[a];
                diffuse[a][i] = m.diffuse[a];
                specular[a][i] = m.specular[a];
            }
            transmit[i] = m.transmit;
        }
        Materials {
            ambient: V3::load(&ambient),
            diffuse: V3::load(&diffuse),
            specular: V3::load(&specular),
            transmit: W::load(&transmit),
        }
    }
}

/// Lane `i`'s vector.
#[inline(always)]
fn at(v: &[Lanes; 3], i: usize) -> Vec3A {
    Vec3A::new(v[0][i], v[1][i], v[2][i])
}
