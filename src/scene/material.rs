//! Materials (table C.2.2) with their flat vision colours (3.1.2).

use glam::Vec3;
use serde::{Deserialize, Serialize};

/// A procedural texture of the Rayshade directives (`D` par1 = 10, 11).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum Texture {
    Marble,
    Bump,
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
