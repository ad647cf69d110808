//! Materials (table C.2.2) with their flat vision colours (3.1.2).

use glam::Vec3;
use serde::{Deserialize, Serialize};

/// A procedural texture of the Rayshade directives (`D` par1 = 10, 11).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum Texture {
    Marble,
    Bump,
    /// Density of a cloud layer: thin parts let the sky through.
    Cloud,
}

/// A Rayshade-class surface.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Material {
    pub name: String,
    pub ambient: Vec3,
    pub diffuse: Vec3,
    pub specular: Vec3,
    /// Phong exponent.
    pub shininess: f32,
    /// Fraction of light mirrored.
    pub reflect: f32,
    /// Fraction of light transmitted.
    pub transmit: f32,
    /// Index of refraction for transmitted light.
    pub ior: f32,
    /// Flat colour for the colour coding of synthetic vision.
    pub vision: Vec3,
    pub texture: Option<Texture>,
}

/// Indices of refraction a material may have: the MTL range (`Ni`).
pub const IOR_RANGE: std::ops::RangeInclusive<f32> = 0.001..=10.0;

/// Number of table entries: the default (0) and materials 1..=27 of table C.2.2.
pub const COUNT: usize = 28;

/// Ambient as a fraction of diffuse: same normalized colour (rule 2 of 3.1.2),
/// so shadowed parts keep the chromaticity vision looks for.
const AMBIENT_FACTOR: f32 = 0.2;

/// Barycentric step of the vision lattice: neighbours lie √2/7 ≈ 0.202 apart,
/// just above the 0.2 minimal chromatic distance of rule 1 (3.1.2).
const LATTICE_STEPS: u32 = 7;

/// Table indices given their vision colour first: the ball and the two tennis
/// players are what actors look for, so the ball keeps its own normalized
/// colour (0.57, 0.29, 0.14) as vision colour and the players their hue.
const VISION_PRIORITY: [usize; 3] = [12, 10, 11];

impl Material {
    /// Diffuse animation of `m` par3 = 1: new diffuse (clamped to 0..1) with
    /// the ambient following it; the vision colour stays, so recognition holds.
    pub fn with_diffuse(&self, rgb: Vec3) -> Material {
        let diffuse = clamp01(rgb);
        Material {
            diffuse,
            ambient: diffuse * AMBIENT_FACTOR,
            ..self.clone()
        }
    }
}

/// The material table; index = material number of `m` par1.
pub fn table() -> Vec<Material> {
    let grey = Vec3::splat;
    let mut t = vec![
        plain("default", grey(0.75), 0.2, 10.0),
        plain("green", Vec3::new(0.1, 0.6, 0.1), 0.2, 10.0),
        plain("brown", Vec3::new(0.45, 0.27, 0.12), 0.1, 5.0),
        plain("blue", Vec3::new(0.1, 0.2, 0.7), 0.3, 20.0),
        plain("red", Vec3::new(0.7, 0.1, 0.1), 0.3, 20.0),
        plain("yellow", Vec3::new(0.8, 0.7, 0.1), 0.3, 20.0),
        plain("gray", grey(0.5), 0.2, 10.0),
        plain("white", grey(0.9), 0.3, 20.0),
        plain("earth", Vec3::new(0.40, 0.30, 0.18), 0.0, 1.0),
        plain("green2", Vec3::new(0.3, 0.6, 0.2), 0.1, 5.0),
        // 10, 11, 12: the ball and the two players, in the order of the
        // `interest` codes (C.6, docs/symbols.md §5 reading 8).
        Material {
            // The thesis's own tennis ball (3.1.2): ambient is half the diffuse.
            ambient: Vec3::new(0.4, 0.2, 0.1),
            ..plain("ball", Vec3::new(0.8, 0.4, 0.2), 0.0, 1.0)
        },
        plain("actor1", Vec3::new(0.1, 0.8, 0.2), 0.3, 30.0),
        plain("actor2", Vec3::new(0.1, 0.3, 0.9), 0.3, 30.0),
        Material {
            reflect: 0.9,
            ..plain("mirror", grey(0.05), 0.9, 200.0)
        },
        plain("skin", Vec3::new(0.85, 0.64, 0.52), 0.1, 10.0),
        plain("grey0", grey(0.2), 0.1, 10.0),
        plain("grey1", grey(0.4), 0.1, 10.0),
        plain("grey2", grey(0.6), 0.1, 10.0),
        plain("grey3", grey(0.8), 0.1, 10.0),
        crystal("cr_quartz", Vec3::new(0.10, 0.10, 0.11), 0.85, 1.544),
        Material {
            // Pyrite is an opaque brassy metal: mirrors a gold tint, transmits nothing.
            specular: Vec3::new(0.9, 0.8, 0.5),
            reflect: 0.5,
            ..plain("cr_pyrite", Vec3::new(0.35, 0.30, 0.12), 0.0, 80.0)
        },
        crystal("cr_emeraude", Vec3::new(0.05, 0.35, 0.15), 0.7, 1.58),
        // Hessonite, the common cinnamon-orange grossular garnet.
        crystal("cr_grossulaire", Vec3::new(0.35, 0.18, 0.06), 0.6, 1.74),
        crystal("cr_fluorine", Vec3::new(0.25, 0.12, 0.35), 0.75, 1.434),
        crystal("cr_rhodochrosite", Vec3::new(0.40, 0.15, 0.20), 0.5, 1.7),
        crystal("cr_natrolite", Vec3::new(0.12, 0.12, 0.11), 0.8, 1.48),
        crystal("cr_celestine", Vec3::new(0.12, 0.15, 0.22), 0.75, 1.62),
        crystal("cr_aigue_marine", Vec3::new(0.08, 0.20, 0.22), 0.75, 1.57),
    ];
    debug_assert_eq!(t.len(), COUNT);
    assign_vision(&mut t);
    t
}

/// The table index for an `m` par1 value: the nearest integer; values
/// outside 0..COUNT (and NaN) give the default material 0, so bad input
/// never panics.
pub fn by_number(n: f64) -> usize {
    let r = n.round();
    if r >= 0.0 && r < COUNT as f64 {
        r as usize
    } else {
        0
    }
}

/// Normalized colour of eq. 3.1.3 (r + g + b = 1). Black has no hue and
/// maps to the achromatic centre (1/3, 1/3, 1/3).
pub fn chromaticity(c: Vec3) -> Vec3 {
    let sum = c.x + c.y + c.z;
    if sum > 0.0 {
        c / sum
    } else {
        Vec3::splat(1.0 / 3.0)
    }
}

/// Chromatic distance of eq. 3.1.4: Euclidean distance of the normalized colours.
pub fn chromatic_distance(a: Vec3, b: Vec3) -> f32 {
    chromaticity(a).distance(chromaticity(b))
}

/// Plain diffuse material of the `r` symbol (components 0..255, clamped),
/// named `rgb(r,g,b)`; the caller picks a vision colour distinct from the table.
pub fn segment_colour(rgb255: [f64; 3], vision: Vec3) -> Material {
    let c = rgb255.map(|v| if v.is_nan() { 0.0 } else { v.clamp(0.0, 255.0) });
    let diffuse = Vec3::new(c[0] as f32, c[1] as f32, c[2] as f32) / 255.0;
    let name = format!(
        "rgb({},{},{})",
        c[0].round() as u8,
        c[1].round() as u8,
        c[2].round() as u8
    );
    Material {
        vision,
        ..plain(&name, diffuse, 0.0, 1.0)
    }
}

/// Opaque material with white-ish specular of the given strength.
fn plain(name: &str, diffuse: Vec3, specular: f32, shininess: f32) -> Material {
    Material {
        name: name.to_string(),
        ambient: diffuse * AMBIENT_FACTOR,
        diffuse,
        specular: Vec3::splat(specular),
        shininess,
        reflect: 0.0,
        transmit: 0.0,
        ior: 1.0,
        vision: Vec3::ZERO,
        texture: None,
    }
}

/// Transparent gem: faint body colour, sharp highlight, a little mirroring.
fn crystal(name: &str, diffuse: Vec3, transmit: f32, ior: f32) -> Material {
    Material {
        reflect: 0.1,
        transmit,
        ior,
        ..plain(name, diffuse, 0.8, 120.0)
    }
}

fn clamp01(c: Vec3) -> Vec3 {
    Vec3::from_array(
        c.to_array()
            .map(|v| if v.is_nan() { 0.0 } else { v.clamp(0.0, 1.0) }),
    )
}

/// Gives each material the free lattice point of the chromaticity triangle
/// nearest to its diffuse's normalized colour; distinct points are ≥ √2/7
/// apart, so rule 1 of 3.1.2 holds for every pair.
fn assign_vision(t: &mut [Material]) {
    let n = LATTICE_STEPS;
    // Fixed enumeration order: ties go to the first point, deterministically.
    let mut points: Vec<(Vec3, bool)> = (0..=n)
        .flat_map(|i| (0..=n - i).map(move |j| (i, j, n - i - j)))
        .map(|(i, j, k)| (Vec3::new(i as f32, j as f32, k as f32) / n as f32, false))
        .collect();
    debug_assert!(points.len() >= t.len());
    let order = VISION_PRIORITY
        .iter()
        .copied()
        .chain((0..t.len()).filter(|i| !VISION_PRIORITY.contains(i)));
    for m in order {
        let target = chromaticity(t[m].diffuse);
        let mut best: Option<(usize, f32)> = None;
        for (p, &(q, taken)) in points.iter().enumerate() {
            let d = q.distance_squared(target);
            if !taken && best.is_none_or(|(_, bd)| d < bd) {
                best = Some((p, d));
            }
        }
        let (p, _) = best.expect("more lattice points than materials");
        points[p].1 = true;
        let q = points[p].0;
        t[m].vision = q / q.max_element();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const NAMES: [&str; COUNT] = [
        "default",
        "green",
        "brown",
        "blue",
        "red",
        "yellow",
        "gray",
        "white",
        "earth",
        "green2",
        "ball",
        "actor1",
        "actor2",
        "mirror",
        "skin",
        "grey0",
        "grey1",
        "grey2",
        "grey3",
        "cr_quartz",
        "cr_pyrite",
        "cr_emeraude",
        "cr_grossulaire",
        "cr_fluorine",
        "cr_rhodochrosite",
        "cr_natrolite",
        "cr_celestine",
        "cr_aigue_marine",
    ];

    #[test]
    fn names_in_table_order() {
        let t = table();
        assert_eq!(t.len(), COUNT);
        let names: Vec<&str> = t.iter().map(|m| m.name.as_str()).collect();
        assert_eq!(names, NAMES);
    }

    #[test]
    fn vision_colours_are_distinct_and_not_black() {
        let t = table();
        for (i, a) in t.iter().enumerate() {
            assert!(
                a.vision.max_element() > 0.99,
                "{} vision {}",
                a.name,
                a.vision
            );
            assert!(a.vision.min_element() >= 0.0);
            for b in &t[i + 1..] {
                let d = chromatic_distance(a.vision, b.vision);
                assert!(d >= 0.2, "{} vs {}: {d}", a.name, b.name);
            }
        }
    }

    #[test]
    fn table_is_deterministic() {
        assert_eq!(table(), table());
    }

    #[test]
    fn ambient_has_diffuse_chromaticity() {
        for m in table() {
            if m.diffuse.max_element() > 0.0 {
                assert!(
                    chromatic_distance(m.ambient, m.diffuse) < 1e-5,
                    "{}",
                    m.name
                );
            }
        }
    }

    #[test]
    fn mirror_reflects() {
        let m = &table()[13];
        assert!(m.reflect >= 0.85);
        assert!(m.diffuse.max_element() < 0.1);
        assert_eq!(m.transmit, 0.0);
    }

    #[test]
    fn crystals_transmit_except_pyrite() {
        for m in table().iter().filter(|m| m.name.starts_with("cr_")) {
            if m.name == "cr_pyrite" {
                assert_eq!(m.transmit, 0.0);
                assert!(m.reflect > 0.0);
            } else {
                assert!(m.transmit > 0.0, "{}", m.name);
                assert!(m.ior > 1.3 && m.ior < 2.0, "{}", m.name);
            }
        }
    }

    #[test]
    fn ball_matches_thesis() {
        let m = &table()[10];
        assert_eq!(m.ambient, Vec3::new(0.4, 0.2, 0.1));
        assert_eq!(m.diffuse, Vec3::new(0.8, 0.4, 0.2));
        assert_eq!(m.specular, Vec3::ZERO);
        let n = chromaticity(m.diffuse);
        assert!(n.distance(Vec3::new(0.57, 0.29, 0.14)) < 0.01, "{n}");
        // Its vision colour has the same normalized colour (priority 1).
        assert!(chromatic_distance(m.vision, m.diffuse) < 1e-5);
    }

    #[test]
    fn greys_get_lighter() {
        let t = table();
        for w in t[15..=18].windows(2) {
            assert!(w[0].diffuse.x < w[1].diffuse.x);
        }
    }

    #[test]
    fn by_number_rounds_and_defaults() {
        assert_eq!(by_number(0.0), 0);
        assert_eq!(by_number(12.0), 12);
        assert_eq!(by_number(11.6), 12);
        assert_eq!(by_number(12.4), 12);
        assert_eq!(by_number(-0.4), 0);
        assert_eq!(by_number(27.4), 27);
        assert_eq!(by_number(27.6), 0);
        assert_eq!(by_number(28.0), 0);
        assert_eq!(by_number(-1.0), 0);
        assert_eq!(by_number(f64::NAN), 0);
        assert_eq!(by_number(f64::INFINITY), 0);
    }

    #[test]
    fn chromatic_distance_of_eq_3_1_4() {
        assert!(chromatic_distance(Vec3::ONE, Vec3::splat(0.2)) < 1e-6);
        let d = chromatic_distance(Vec3::X, Vec3::Y);
        assert!((d - 2f32.sqrt()).abs() < 1e-6);
        assert!(chromatic_distance(Vec3::ZERO, Vec3::ONE) < 1e-6);
    }

    #[test]
    fn with_diffuse_keeps_vision() {
        let t = table();
        let m = t[1].with_diffuse(Vec3::new(1.0, 0.5, 2.0));
        assert_eq!(m.diffuse, Vec3::new(1.0, 0.5, 1.0));
        assert!(m.ambient.distance(m.diffuse * 0.2) < 1e-6);
        assert_eq!(m.vision, t[1].vision);
        assert_eq!(m.name, t[1].name);
        assert_eq!(m.specular, t[1].specular);
    }

    #[test]
    fn segment_colour_is_plain() {
        let m = segment_colour([255.0, 127.6, -3.0], Vec3::Z);
        assert_eq!(m.name, "rgb(255,128,0)");
        assert!(m.diffuse.distance(Vec3::new(1.0, 127.6 / 255.0, 0.0)) < 1e-6);
        assert_eq!(m.vision, Vec3::Z);
        assert_eq!(m.transmit, 0.0);
        assert_eq!(m.reflect, 0.0);
    }
}
