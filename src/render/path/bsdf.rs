//! The thesis's Rayshade materials as physically plausible BSDFs
//! (docs/rendering.md, "Materials as BSDFs"): a Lambertian lobe from
//! the diffuse colour, a normalized Phong lobe from the specular colour
//! and exponent, a mirror from `reflect` and a Fresnel dielectric from
//! `transmit` and the index of refraction. Their sum is scaled down to
//! conserve energy where a table entry's weights pass 1.

use std::f32::consts::{FRAC_1_PI, TAU};

use glam::{Vec3, Vec3A};

use crate::render::shade::{reflect, refract};
use crate::scene::Material;

/// A direction chosen by [`Bsdf::sample`].
pub struct Sampled {
    /// The unit direction the light comes from.
    pub wi: Vec3A,
    /// f·cos/pdf: what the path's throughput is multiplied by.
    pub weight: Vec3,
    /// The solid-angle pdf of the smooth lobes (0 for a mirror or glass,
    /// whose directions no light sample can find).
    pub pdf: f32,
    /// Whether the direction went through the surface.
    pub through: bool,
}

/// The scattering at one surface point, in world space.
pub struct Bsdf {
    /// The unit shading normal, facing the incoming ray.
    n: Vec3A,
    diffuse: Vec3,
    glossy: Vec3,
    exponent: f32,
    mirror: f32,
    glass: f32,
    /// n1/n2 across the surface in the ray's direction.
    eta: f32,
    /// Chances of picking each lobe: diffuse, glossy, mirror, glass.
    chance: [f32; 4],
}

/// The mean of a colour's components: a lobe's weight when one is picked.
fn mean(c: Vec3) -> f32 {
    (c.x + c.y + c.z) / 3.0
}

impl Bsdf {
    /// The BSDF of material `m` with (textured) diffuse colour `diffuse`
    /// at normal `n` (facing the ray), the ray arriving from outside the
    /// surface or not.
    pub fn new(m: &Material, diffuse: Vec3, n: Vec3A, outside: bool) -> Bsdf {
        let clean = |v: f32| {
            if v.is_finite() {
                v.clamp(0.0, 1.0)
            } else {
                0.0
            }
        };
        let glass = clean(m.transmit);
        let opaque = 1.0 - glass;
        let exponent = if m.shininess.is_finite() {
            m.shininess.clamp(1.0, 1e4)
        } else {
            1.0
        };
        let mut d = diffuse.clamp(Vec3::ZERO, Vec3::ONE) * opaque;
        // The normalized lobe's peak under a light of colour c is
        // g·(n + 2)/2·c; Rayshade's highlight peaks at specular·c: the
        // same highlight for g = specular·2/(n + 2). (The specular
        // colour as the lobe's albedo put a white sheen of sky on every
        // plant: Rayshade's broad, weak highlights are not mirrors.)
        let mut g = m.specular.clamp(Vec3::ZERO, Vec3::ONE) * (opaque * 2.0 / (exponent + 2.0));
        let mut r = clean(m.reflect);
        let mut t = glass;
        // Energy: the lobes together reflect at most all the light.
        let total = (d + g + Vec3::splat(r + t)).max_element();
        if total > 1.0 {
            (d, g, r, t) = (d / total, g / total, r / total, t / total);
        }
        let ior = if m.ior.is_finite() {
            m.ior.max(1e-3)
        } else {
            1.0
        };
        let weights = [mean(d), mean(g), r, t];
        let sum: f32 = weights.iter().sum();
        let chance = if sum > 0.0 {
            weights.map(|w| w / sum)
        } else {
            [0.0; 4]
        };
        Bsdf {
            n,
            diffuse: d,
            glossy: g,
            exponent,
            mirror: r,
            glass: t,
            eta: if outside { 1.0 / ior } else { ior },
            chance,
        }
    }

    /// The unit shading normal, facing the incoming ray.
    /// The fraction of light it scatters, all lobes together (each at
    /// most 1): the albedo a denoiser divides the light by.
    pub fn albedo(&self) -> Vec3 {
        (self.diffuse + self.glossy + Vec3::splat(self.mirror + self.glass)).min(Vec3::ONE)
    }

    pub fn normal(&self) -> Vec3A {
        self.n
    }

    /// Whether a light sample can find any of its directions (a diffuse
    /// or glossy lobe).
    pub fn smooth(&self) -> bool {
        self.chance[0] + self.chance[1] > 0.0
    }

    /// f(wo, wi) of the smooth lobes (mirror and glass have no value in
    /// any given direction); `wo` toward the viewer, `wi` toward the light.
    pub fn eval(&self, wo: Vec3A, wi: Vec3A) -> Vec3 {
        if self.n.dot(wi) <= 0.0 {
            return Vec3::ZERO;
        }
        let mut f = self.diffuse * FRAC_1_PI;
        if self.chance[1] > 0.0 {
            let c = mirrored(wo, self.n).dot(wi);
            if c > 0.0 {
                f += self.glossy * ((self.exponent + 2.0) / TAU * c.powf(self.exponent));
            }
        }
        f
    }

    /// The pdf with which [`Bsdf::sample`] picks `wi` through a smooth
    /// lobe (solid angle, lobe chances included).
    pub fn pdf(&self, wo: Vec3A, wi: Vec3A) -> f32 {
        let cos = self.n.dot(wi);
        if cos <= 0.0 {
            return 0.0;
        }
        let mut p = self.chance[0] * cos * FRAC_1_PI;
        if self.chance[1] > 0.0 {
            let c = mirrored(wo, self.n).dot(wi);
            if c > 0.0 {
                p += self.chance[1] * (self.exponent + 1.0) / TAU * c.powf(self.exponent);
            }
        }
        p
    }

    /// Picks a lobe with `pick` and a direction in it with `u`; None
    /// where the path ends (a black surface, a direction under it).
    pub fn sample(&self, wo: Vec3A, pick: f32, u: (f32, f32)) -> Option<Sampled> {
        let [cd, cg, cm, _] = self.chance;
        let n = self.n;
        if pick < cd + cg {
            let wi = if pick < cd {
                around(n, cosine(u))
            } else {
                around(mirrored(wo, n), phong(u, self.exponent))
            };
            let pdf = self.pdf(wo, wi);
            if pdf <= 0.0 {
                return None;
            }
            let weight = self.eval(wo, wi) * (n.dot(wi) / pdf);
            return Some(Sampled {
                wi,
                weight,
                pdf,
                through: false,
            });
        }
        if pick < cd + cg + cm {
            return Some(Sampled {
                wi: mirrored(wo, n),
                weight: Vec3::splat(self.mirror / cm),
                pdf: 0.0,
                through: false,
            });
        }
        if self.chance[3] <= 0.0 {
            return None;
        }
        // Glass: reflected with the Fresnel chance, else refracted (the
        // chance cancels the Fresnel factor).
        let weight = Vec3::splat(self.glass / self.chance[3]);
        let cos_i = n.dot(wo).clamp(0.0, 1.0);
        let (through, wi) = match refract(-wo, n, self.eta) {
            Some(t) if u.0 >= fresnel(cos_i, n.dot(-t), self.eta) => (true, t),
            _ => (false, mirrored(wo, n)),
        };
        Some(Sampled {
            wi,
            weight,
            pdf: 0.0,
            through,
        })
    }
}

/// The mirror direction of `w` (pointing away from the surface) about
/// `n`: [`reflect`] takes the direction toward the surface.
fn mirrored(w: Vec3A, n: Vec3A) -> Vec3A {
    reflect(-w, n).normalize()
}

/// The Fresnel reflectance of unpolarized light from a dielectric, for
/// incident and transmitted cosines and η = n1/n2.
fn fresnel(cos_i: f32, cos_t: f32, eta: f32) -> f32 {
    let rs = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    let rp = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    (0.5 * (rs * rs + rp * rp)).clamp(0.0, 1.0)
}

/// A cosine-weighted direction about +z.
fn cosine(u: (f32, f32)) -> Vec3A {
    let r = u.0.sqrt();
    let phi = TAU * u.1;
    Vec3A::new(r * phi.cos(), r * phi.sin(), (1.0 - u.0).max(0.0).sqrt())
}

/// A direction about +z with density ∝ cosⁿ.
fn phong(u: (f32, f32), n: f32) -> Vec3A {
    let z = u.0.powf(1.0 / (n + 1.0));
    let r = (1.0 - z * z).max(0.0).sqrt();
    let phi = TAU * u.1;
    Vec3A::new(r * phi.cos(), r * phi.sin(), z)
}

/// `local` (about +z) turned to lie about the unit `axis`.
fn around(axis: Vec3A, local: Vec3A) -> Vec3A {
    // Frisvad's basis, Duff et al.'s branchless form.
    let s = if axis.z >= 0.0 { 1.0 } else { -1.0 };
    let a = -1.0 / (s + axis.z);
    let b = axis.x * axis.y * a;
    let t = Vec3A::new(1.0 + s * axis.x * axis.x * a, s * b, -s * axis.x);
    let bt = Vec3A::new(b, s + axis.y * axis.y * a, -axis.y);
    (local.x * t + local.y * bt + local.z * axis).normalize()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::random;
    use crate::render::shade::lights::{uniform_sphere, SPHERE_PDF};

    fn uniform(k: u64) -> (f32, f32) {
        (
            random::unit(7, 2 * k) as f32,
            random::unit(7, 2 * k + 1) as f32,
        )
    }

    /// A BSDF's directional albedo estimated from its own samples equals
    /// the one from uniform directions over the hemisphere (sampling and
    /// pdf agree with `eval`), and stays ≤ 1.
    #[test]
    fn sampling_agrees_with_eval_and_conserves_energy() {
        let table = crate::scene::material::table();
        let n = Vec3A::new(0.3, 0.9, -0.2).normalize();
        let wo = Vec3A::new(-0.5, 0.6, 0.4).normalize();
        for m in table
            .iter()
            .filter(|m| m.transmit == 0.0 && m.reflect == 0.0)
        {
            let b = Bsdf::new(m, m.diffuse, n, true);
            let count = 200_000;
            let (mut by_sample, mut by_uniform) = (Vec3::ZERO, Vec3::ZERO);
            for k in 0..count {
                let pick = random::unit(9, k) as f32;
                if let Some(s) = b.sample(wo, pick, uniform(k)) {
                    by_sample += s.weight;
                }
                let wi = uniform_sphere(uniform(k + count));
                by_uniform += b.eval(wo, wi) * n.dot(wi).max(0.0) / SPHERE_PDF;
            }
            let (a, u) = (by_sample / count as f32, by_uniform / count as f32);
            assert!(a.max_element() <= 1.0 + 1e-3, "{}: albedo {a}", m.name);
            assert!(
                (a - u).abs().max_element() < 0.03 * u.max_element().max(0.1),
                "{}: sampled albedo {a}, integrated {u}",
                m.name
            );
        }
    }

    /// Glass reflects the Fresnel share: at normal incidence from air
    /// into η = 1.5, 4 %.
    #[test]
    fn glass_reflects_the_fresnel_share() {
        let m = Material {
            transmit: 1.0,
            ior: 1.5,
            ..crate::scene::material::table()[0].clone()
        };
        let n = Vec3A::Y;
        let b = Bsdf::new(&m, Vec3::ZERO, n, true);
        let count = 100_000;
        let reflected = (0..count)
            .filter(|&k| {
                let s = b.sample(n, 0.999, uniform(k)).unwrap();
                !s.through
            })
            .count();
        let share = reflected as f32 / count as f32;
        assert!((share - 0.04).abs() < 0.003, "{share}");
    }
}
