//! A row's samples shaded together, one sample per lane of a [`Wide`]
//! value, several pixels to a value: the points where their camera rays
//! meet surfaces, the hard
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

use super::accel::packet::{Bits, RayPacket, Rays};
use super::accel::ray::{frame, largest_axis, Ray};
use super::accel::tri4::Simd;
use super::accel::{Accel, Hit};
use super::camera::CameraRays;
use super::settings::Settings;
use super::shade::{self, EPS};
use super::simd::v3::V3;
#[cfg(not(target_arch = "x86_64"))]
use super::simd::wide::Scalar as Base;
#[cfg(target_arch = "x86_64")]
use super::simd::wide::{Avx, Avx512, Sse as Base};
use super::simd::wide::{Mask, Wide};
use crate::random::{self, Stream};
use crate::render::simd::{at, Lanes, LANES};
use crate::scene::material::Texture;
use crate::scene::{LightKind, Material};

/// Whether [`pixel`] serves the scene: it has no sphere light.
pub fn applies(accel: &Accel) -> bool {
    !accel
        .scene
        .lights
        .iter()
        .any(|l| matches!(l.kind, LightKind::Sphere { .. }))
}

/// One camera ray of a row's: sample `sample` of pixel `x` at `offset`
/// in the pixel, whose key is `key` (each sample's own keys the bounces'
/// soft shadows, as [`super::whitted::Whitted`] keys them one at a time); or, where
/// `sample` is None, the pixel's centre ray, cast for the layers (depth,
/// normal, object) and not shaded.
#[derive(Clone, Copy)]
pub struct Lane {
    pub x: u32,
    pub offset: (f32, f32),
    pub key: u64,
    pub sample: Option<u32>,
}

/// The rays of `lanes` (row `y`), cast and shaded [`LANES`] at a time
/// whatever pixel each belongs to, into `out` as (colour, hit): a
/// centre ray's colour is zero. A lane's results do not depend on the
/// lanes beside it, so a pixel of three samples and its centre ray fill
/// a quarter of a 16-lane packet, and four pixels fill it: one pixel
/// per packet left three quarters of the lanes empty (a 1080p film frame
/// at 3 spp cost 3.9× the forest still per sample). Only for scenes it
/// [`applies`] to.
pub fn row(
    accel: &Accel,
    cam: &CameraRays,
    st: &Settings,
    y: u32,
    lanes: &[Lane],
    buffers: &mut Buffers,
    out: &mut Vec<(Vec3, Option<Hit>)>,
) {
    out.clear();
    let rays = &mut buffers.cast;
    for lanes in lanes.chunks(LANES) {
        let mut chunk = Chunk {
            eye: cam.eye(),
            dir: [[0.0; LANES]; 3],
            hits: &mut buffers.hits,
            lanes,
        };
        let colours = match accel.simd() {
            // SAFETY: each is chosen only where the CPU has it.
            #[cfg(target_arch = "x86_64")]
            Simd::Avx => unsafe { chunk.pixel_avx(accel, cam, st, y, rays) },
            #[cfg(target_arch = "x86_64")]
            Simd::Avx512 => unsafe { chunk.pixel_avx512(accel, cam, st, y, rays) },
            _ => chunk.pixel::<Base>(accel, cam, st, y, rays),
        };
        out.extend(colours.into_iter().zip(*chunk.hits).take(lanes.len()));
    }
}

/// The lanes' rays and hits, kept from pixel to pixel: made anew, each
/// pixel's placeholder rays (2.3 KB per cast) and hits cost about 3 % of
/// the forest's render.
#[derive(Default)]
pub struct Buffers {
    cast: Cast,
    hits: [Option<Hit>; LANES],
}

/// Where [`ray_lanes`] makes a cast's rays: their packet, written in
/// place (returned, its 1.7 KB were copied per cast), or the single rays
/// of mixed keys. The lanes a cast does not use keep earlier rays, which
/// it masks out.
pub struct Cast {
    rays: [Ray; LANES],
    packet: RayPacket,
}

impl Default for Cast {
    fn default() -> Self {
        let rays = [Ray::new(Vec3A::ZERO, Vec3A::X, 0.0); LANES];
        Cast {
            packet: RayPacket::new(&rays, 1),
            rays,
        }
    }
}

/// Up to [`LANES`] rays of a row.
struct Chunk<'a> {
    eye: Vec3A,
    /// The rays' directions, a lane each.
    dir: [Lanes; 3],
    hits: &'a mut [Option<Hit>; LANES],
    lanes: &'a [Lane],
}

/// A material's values, a lane each.
struct Materials<W> {
    ambient: V3<W>,
    diffuse: V3<W>,
    specular: V3<W>,
    transmit: W,
}

/// `Chunk::pixel` compiled for the instructions of a lane form, to be
/// called where the CPU has them (chosen at run time).
macro_rules! pixel_with {
    ($name:ident, $feature:literal, $form:ty) => {
        #[cfg(target_arch = "x86_64")]
        #[target_feature(enable = $feature)]
        #[allow(clippy::too_many_arguments)]
        unsafe fn $name(
            &mut self,
            accel: &Accel,
            cam: &CameraRays,
            st: &Settings,
            y: u32,
            rays: &mut Cast,
        ) -> [Vec3; LANES] {
            self.pixel::<$form>(accel, cam, st, y, rays)
        }
    };
}

impl Chunk<'_> {
    pixel_with!(pixel_avx512, "avx512f", Avx512);
    pixel_with!(pixel_avx, "avx", Avx);

    /// Lane `i`'s key for its soft shadows (a sample's).
    fn key(&self, i: usize) -> u64 {
        let lane = &self.lanes[i];
        let sample = lane.sample.unwrap_or_default();
        random::key(lane.key, Stream::Pixel, u64::from(sample), 1)
    }

    /// The colours of the chunk's samples (the other lanes' are zero);
    /// the hits of all its rays into `self.hits`. `rays` holds the rays
    /// cast.
    #[inline(always)]
    fn pixel<W: Wide>(
        &mut self,
        accel: &Accel,
        cam: &CameraRays,
        st: &Settings,
        y: u32,
        rays: &mut Cast,
    ) -> [Vec3; LANES] {
        // `x as f32 + ox` lane by lane: the bits of the single ray's sum.
        let (mut px, mut py) = ([0.5; LANES], [0.5; LANES]);
        let mut samples = 0;
        for (i, lane) in self.lanes.iter().enumerate() {
            px[i] = lane.x as f32 + lane.offset.0;
            py[i] = y as f32 + lane.offset.1;
            samples |= u32::from(lane.sample.is_some()) << i;
        }
        let d = cam.dirs(W::load(&px), W::load(&py));
        self.dir = d.store();
        let lanes = ((1u64 << self.lanes.len()) - 1) as u32;
        let (valid, cast) = ray_lanes(V3::splat(self.eye), d, 0.0, lanes, rays);
        accel.closest_hits::<W>(cast, valid, self.hits);
        self.shade::<W>(accel, st, d, samples, rays)
    }

    /// The colours of the samples of `samples` along `d` (lane by lane
    /// `shade::shade_seen` of their hits; the other lanes' are zero).
    /// `rays` holds the shadow rays cast.
    #[inline(always)]
    fn shade<W: Wide>(
        &self,
        accel: &Accel,
        st: &Settings,
        d: V3<W>,
        samples: u32,
        rays: &mut Cast,
    ) -> [Vec3; LANES] {
        let mut colour = [Vec3::ZERO; LANES];
        let materials = &accel.scene.materials;
        // The samples taken here (`fast`), their hits and materials.
        // Other lanes hold a harmless hit.
        let mut normal = [[0.0; LANES]; 3];
        let mut t = [0.0; LANES];
        let mut material = [0usize; LANES];
        let mut fast = 0u32;
        for i in Bits(samples) {
            let dir = at(&self.dir, i);
            let Some(hit) = &self.hits[i] else {
                colour[i] = shade::background(accel, dir);
                continue;
            };
            let Some(m) = materials.get(hit.material as usize) else {
                // A surface without a material is black.
                continue;
            };
            if m.texture == Some(Texture::Cloud) {
                if let Some(pt) = shade::point(accel, hit, self.eye, dir) {
                    colour[i] = shade::shade_seen(accel, &pt, dir, st, 0, self.key(i), &[]);
                }
                continue;
            }
            fast |= 1 << i;
            for (lanes, c) in normal.iter_mut().zip(hit.normal.to_array()) {
                lanes[i] = c;
            }
            t[i] = hit.t;
            material[i] = hit.material as usize;
        }
        if fast == 0 {
            return colour;
        }
        let zero = W::splat(0.0);
        let one = W::splat(1.0);
        let normal = V3::<W>::load(&normal);
        // `shade::point`: the point, and the normal facing the ray.
        let p = V3::splat(self.eye) + d.scale(W::load(&t));
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
                    let (l, dist) = shade::lights::toward(light, Vec3A::ZERO);
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
                lit & !self.blocked::<W>(accel, lift, l, dist, cast, lit & !cast, rays)
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
            let dir = at(&self.dir, i);
            if let Some(pt) = self.hits[i].and_then(|h| shade::point(accel, &h, self.eye, dir)) {
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
    /// within `dist`: those of `cast` as one bundle (made in `rays`),
    /// those of `alone` one by one.
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    fn blocked<W: Wide>(
        &self,
        accel: &Accel,
        lift: V3<W>,
        l: V3<W>,
        dist: W,
        cast: u32,
        alone: u32,
        rays: &mut Cast,
    ) -> u32 {
        let (from, dir, dist) = (lift.store(), l.store(), dist.store());
        let (valid, rays) = ray_lanes(lift, l, 0.0, cast, rays);
        let mut blocked = if valid == 0 {
            0
        } else {
            accel.any_bundle::<W>(rays, valid, &dist)
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

/// The rays from `origin` along `dir` of the lanes of `lanes`, as
/// `Accel::ray` makes them one at a time (the same bits: `Ray::new`'s
/// operations lane by lane); returns the lanes whose origin and direction
/// are finite and the direction not zero (the others are masked out),
/// and the rays, made in `cast`: where those share one [`Ray::key`] (a
/// pixel's rays mostly do), their packet, made from the lanes rather than
/// gathered from single rays (`RayPacket::new` and the split by key took
/// 5 % of the forest's render); otherwise the single rays (the other
/// lanes left as they were).
#[inline(always)]
fn ray_lanes<'a, W: Wide>(
    origin: V3<W>,
    dir: V3<W>,
    tmin: f32,
    lanes: u32,
    cast: &'a mut Cast,
) -> (u32, Rays<'a>) {
    let Cast { rays, packet: p } = cast;
    let zero = W::splat(0.0);
    // Negative zeros made positive, so the slab tests see one sign.
    let d = dir + V3::splat(Vec3A::ZERO);
    let valid = origin.finite().and(d.finite()).and(d.nonzero()).bits() & lanes;
    if valid == 0 {
        return (0, Rays::Mixed(rays));
    }
    let inv = d.recip_clamped();
    let origin_inv = origin * inv;
    let negative = [
        d.x.lt(zero).bits(),
        d.y.lt(zero).bits(),
        d.z.lt(zero).bits(),
    ];
    // The axis of the largest component last (z), the frame kept
    // right-handed (`Ray::new`'s choice, lane by lane).
    let abs = d.abs();
    let x_over_y = abs.x.gt(abs.y);
    let x_over_z = abs.x.gt(abs.z);
    let y_over_z = abs.y.gt(abs.z);
    let masks = [x_over_y, x_over_z, y_over_z];
    let flip = pick(masks, d.x, d.y, d.z).lt(zero);
    let pd = permuted(d, masks, flip);
    let po = permuted(origin, masks, flip);
    let shear = V3 {
        x: pd.x,
        y: pd.y,
        z: W::splat(1.0),
    }
    .over(pd.z);
    // Stored in the packet one by one: `array::map` would take the lane
    // form's instructions out of line (see `super::wide`).
    (p.origin, p.direction, p.inv) = (origin.store(), d.store(), inv.store());
    (p.origin_inv, p.shear, p.permuted_origin) = (origin_inv.store(), shear.store(), po.store());
    p.tmin = [tmin; LANES];
    let (bits_xy, bits_xz, bits_yz, bits_flip) = (
        x_over_y.bits(),
        x_over_z.bits(),
        y_over_z.bits(),
        flip.bits(),
    );
    // One key: each of the choices `Ray::new` makes alike in every lane.
    let alike = |m: u32| m & valid == 0 || m & valid == valid;
    let one_key = negative.iter().all(|&m| alike(m))
        && [bits_xy, bits_xz, bits_yz, bits_flip]
            .into_iter()
            .all(alike);
    // Lane i's signs and axes, as its `Ray::new` chooses them.
    let key = |i: usize| {
        let bit = |m: u32| m >> i & 1 != 0;
        let kz = largest_axis(bit(bits_xy), bit(bits_xz), bit(bits_yz));
        (negative.map(bit), frame(kz, bit(bits_flip)))
    };
    if !one_key {
        // The rays made one by one, to be split by key.
        for i in Bits(valid) {
            (p.negative, p.axes) = key(i);
            rays[i] = p.ray(i);
        }
        return (valid, Rays::Mixed(rays));
    }
    // The lanes outside the packet repeat one of its rays (see `RayPacket`).
    let first = valid.trailing_zeros() as usize;
    for i in Bits(!valid & ((1 << LANES) - 1) as u32) {
        for v in [
            &mut p.origin,
            &mut p.direction,
            &mut p.inv,
            &mut p.origin_inv,
            &mut p.shear,
            &mut p.permuted_origin,
        ] {
            for lanes in v.iter_mut() {
                lanes[i] = lanes[first];
            }
        }
    }
    // Its single rays are made only where a test needs one (`RayPacket::ray`).
    (p.negative, p.axes) = key(first);
    (valid, Rays::Packet(p))
}

/// Each lane's `(v[kx], v[ky], v[kz])` for the axes `Ray::new` picks
/// from the comparisons of the direction's magnitudes (`masks`: |x| > |y|,
/// |x| > |z|, |y| > |z|; `flip`: the largest component is negative, and x
/// and y swap).
#[inline(always)]
fn permuted<W: Wide>(v: V3<W>, masks: [W::Mask; 3], flip: W::Mask) -> V3<W> {
    // kz = 0: (y, z, x); kz = 1: (z, x, y); kz = 2: (x, y, z).
    let x = pick(masks, v.y, v.z, v.x);
    let y = pick(masks, v.z, v.x, v.y);
    V3 {
        x: W::select(flip, y, x),
        y: W::select(flip, x, y),
        z: pick(masks, v.x, v.y, v.z),
    }
}

/// Each lane's `a`, `b` or `c` as its largest axis is x, y or z (see
/// [`permuted`]).
#[inline(always)]
fn pick<W: Wide>([x_over_y, x_over_z, y_over_z]: [W::Mask; 3], a: W, b: W, c: W) -> W {
    W::select(
        x_over_y,
        W::select(x_over_z, a, c),
        W::select(y_over_z, b, c),
    )
}

#[cfg(all(test, target_arch = "x86_64"))]
mod tests {
    use super::*;
    use crate::render::simd::wide::{Scalar, Sse};

    /// What `ray_lanes` made: the mask, the rays (a packet's made from
    /// its lanes), and its packet's bits where it made one.
    type Made = (u32, [Ray; LANES], Option<Vec<u32>>);

    fn lanes<W: Wide>(o: &[Lanes; 3], d: &[Lanes; 3], lanes: u32) -> Made {
        let mut cast = Cast::default();
        let (valid, made) = ray_lanes(V3::<W>::load(o), V3::<W>::load(d), 0.5, lanes, &mut cast);
        let (singles, packet) = match made {
            Rays::Packet(p) => (std::array::from_fn(|i| p.ray(i)), Some(packet_bits(p))),
            Rays::Mixed(r) => (*r, None),
        };
        (valid, singles, packet)
    }

    #[target_feature(enable = "avx")]
    unsafe fn avx(o: &[Lanes; 3], d: &[Lanes; 3], m: u32) -> Made {
        lanes::<Avx>(o, d, m)
    }

    #[target_feature(enable = "avx512f")]
    unsafe fn avx512(o: &[Lanes; 3], d: &[Lanes; 3], m: u32) -> Made {
        lanes::<Avx512>(o, d, m)
    }

    /// A packet's every lane, as bits.
    fn packet_bits(p: &RayPacket) -> Vec<u32> {
        let mut b = vec![];
        for v in [
            &p.origin,
            &p.direction,
            &p.inv,
            &p.origin_inv,
            &p.shear,
            &p.permuted_origin,
        ] {
            b.extend(v.iter().flatten().map(|x| x.to_bits()));
        }
        b.extend(p.tmin.map(f32::to_bits));
        b.extend(p.negative.map(u32::from));
        b.extend(p.axes.map(|a| a as u32));
        b
    }

    /// A ray's every field, as bits.
    fn bits(r: &Ray) -> Vec<u32> {
        let v = |v: Vec3A| v.to_array().map(f32::to_bits);
        let mut b = [r.origin, r.direction, r.inv, r.origin_inv, r.shear]
            .into_iter()
            .flat_map(v)
            .collect::<Vec<_>>();
        b.extend(v(r.permuted_origin));
        b.push(r.tmin.to_bits());
        b.extend(r.negative.map(u32::from));
        b.extend(r.axes.map(|a| a as u32));
        b
    }

    /// `ray_lanes` makes, lane by lane, the rays `Accel::ray` makes one
    /// at a time (`Ray::new` of the direction with its zeros made
    /// positive), and refuses the same ones, in every lane form: axis
    /// directions, ties between the largest components, negative zeros,
    /// components so small their reciprocal overflows, NaN and infinite
    /// ones, zero directions. Where it makes their packet too (rays of
    /// one key), that is the packet `RayPacket::new` gathers from them.
    #[test]
    fn lanes_make_the_rays_made_one_at_a_time() {
        let special = [
            0.0,
            -0.0,
            1.0,
            -1.0,
            0.5,
            -0.5,
            1e-39,
            -1e-39,
            3.0e38,
            -2.5,
            f32::NAN,
            f32::INFINITY,
        ];
        let mut seed = 0x2545_f491_4f6c_dd1du64;
        let mut next = || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            seed
        };
        let (mut checked, mut packets) = (0, 0);
        for round in 0..3000 {
            let (mut o, mut d) = ([[0.0; LANES]; 3], [[0.0; LANES]; 3]);
            for i in 0..LANES {
                for a in 0..3 {
                    let r = next();
                    let small = (r >> 40) as f32 / (1u64 << 23) as f32 - 1.0;
                    d[a][i] = match round % 3 {
                        0 => special[(r % special.len() as u64) as usize],
                        1 => small,
                        // Close to one direction, as a pixel's rays: one key.
                        _ => [0.3, -0.5, 0.8][a] + small / 64.0,
                    };
                    if round % 3 == 2 && r % 97 == 0 {
                        // Now and then a lane that is not a ray.
                        d[a][i] = special[(r % special.len() as u64) as usize];
                    }
                    o[a][i] = ((r >> 20) & 0xffff) as f32 / 256.0 - 128.0;
                }
            }
            let mask = (next() as u32) | 1;
            let want: Vec<Option<Vec<u32>>> = (0..LANES)
                .map(|i| {
                    let (o, d) = (
                        Vec3A::new(o[0][i], o[1][i], o[2][i]),
                        Vec3A::new(d[0][i], d[1][i], d[2][i]),
                    );
                    let ok =
                        mask >> i & 1 != 0 && o.is_finite() && d.is_finite() && d != Vec3A::ZERO;
                    ok.then(|| bits(&Ray::new(o, d + Vec3A::ZERO, 0.5)))
                })
                .collect();
            let mut got = vec![lanes::<Scalar>(&o, &d, mask), lanes::<Sse>(&o, &d, mask)];
            if std::arch::is_x86_feature_detected!("avx") {
                // SAFETY: the CPU has AVX.
                got.push(unsafe { avx(&o, &d, mask) });
            }
            if std::arch::is_x86_feature_detected!("avx512f") {
                // SAFETY: the CPU has AVX-512F.
                got.push(unsafe { avx512(&o, &d, mask) });
            }
            for (form, (valid, rays, packet)) in got.iter().enumerate() {
                for (i, w) in want.iter().enumerate() {
                    let g = (valid >> i & 1 != 0).then(|| bits(&rays[i]));
                    assert_eq!(&g, w, "form {form}, lane {i}: {:?}", d.map(|a| a[i]));
                    checked += usize::from(w.is_some());
                }
                if let Some(packet) = packet {
                    assert_eq!(super::super::accel::packet::groups(rays, *valid).count(), 1);
                    let gathered = packet_bits(&RayPacket::new(rays, *valid));
                    assert_eq!(packet, &gathered, "form {form}, round {round}");
                    packets += 1;
                }
            }
        }
        assert!(checked > 50_000, "{checked}");
        assert!(packets > 1_000, "{packets}");
    }
}
