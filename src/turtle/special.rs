//! The special symbol `D` (appendix C.6): planes, the tennis court, sky
//! and clouds, bounding boxes, and the Rayshade directives mapped to what
//! this renderer has (named objects become instances).

use glam::{Affine3A, DVec3, EulerRot, Quat, Vec3};

use super::interpret::Interpreter;
use super::state::Turtle;
use crate::lsys::Symbol;
use crate::scene::material::Texture;
use crate::scene::ShapeKind;

/// Half the side of the `D` ground squares (thesis: ±1000).
const GROUND: f64 = 1000.0;

/// Tennis court (figure C.6.2, ITF dimensions in metres): length along x,
/// net in the y–z plane at x = 0, court in the x–z plane at y = 0.
pub mod court {
    pub const LENGTH: f64 = 23.77;
    pub const DOUBLES_WIDTH: f64 = 10.97;
    pub const SINGLES_WIDTH: f64 = 8.23;
    /// Distance of the service lines from the net.
    pub const SERVICE: f64 = 6.40;
    pub const LINE: f64 = 0.05;
    /// Net height at the centre (thesis: 0.91 m).
    pub const NET_HEIGHT: f64 = 0.91;
    /// Net posts stand 0.914 m outside the doubles sidelines.
    pub const NET_LENGTH: f64 = DOUBLES_WIDTH + 2.0 * 0.914;
}

impl Interpreter<'_> {
    /// `D` (C.5): the special objects of the thesis's worlds.
    pub(super) fn d_symbol(&mut self, s: &Symbol) {
        d_symbol(self, s);
    }
}

fn d_symbol(it: &mut Interpreter, s: &Symbol) {
    let [x, y, _] = s.par;
    let g = it.growth_of(s);
    let pos = it.turtle().pos;
    match x as i64 {
        // Rayshade `plane 0 par4 0 0 1 0` and the GL ground square.
        2 => ground(it, s, g[0], it.material()),
        3 => ground(it, s, g[1], it.material()),
        // `end` of a named object, `name objN [list]`, `object objN`.
        1 => it.end_named(),
        6 | 13 => it.begin_named(g[0] as i64),
        7 => it.place_named(g[0] as i64),
        10 => textured(it, Texture::Marble),
        11 => textured(it, Texture::Bump),
        15 => it.builder().sky(DVec3::from_array(g)),
        50 => it.body(s, g, true),
        51 => it.turtle_to_joint(g),
        52 => it.body(s, g, false),
        16 => clouds(it, s, g),
        18 => it.builder().observer_light(),
        20 => {
            let n = it.geometry_bounds();
            it.builder().bbox_begin(n);
        }
        21 => {
            let n = it.geometry_bounds();
            let g = it.geometry_ref().clone();
            if !it.builder().bbox_end(&g, n) {
                it.warn("`D` par1 = 21 without a `D` par1 = 20 before it");
            }
        }
        30 => it.builder().print(format!(
            "turtle position {:.6} {:.6} {:.6}",
            pos.x, pos.y, pos.z
        )),
        40 => it.builder().lookat_global = Some(pos),
        41 => tennis_court(it, s, y == 1.0),
        // Rayshade's `scale`, `rotate`, `translate` transform the object
        // just placed: here the last instance placed by `D` par1 = 7.
        4 | 8 | 9 => {
            let m = match x as i64 {
                4 => Affine3A::from_scale(DVec3::from_array(g).as_vec3()),
                8 => Affine3A::from_translation(DVec3::from_array(g).as_vec3()),
                _ => Affine3A::from_quat(Quat::from_euler(
                    EulerRot::ZYX,
                    g[2].to_radians() as f32,
                    g[1].to_radians() as f32,
                    g[0].to_radians() as f32,
                )),
            };
            it.transform_last_placement(m);
        }
        // grid, window, list: layout directives with no equivalent here
        // (the BVH replaces the grid; the image size comes from the camera).
        0 | 5 | 12 | 14 => {}
        17 => it
            .warn("`D` par1 = 17 includes the thesis's plane.ray, which is not available; skipped"),
        _ => {}
    }
}

fn textured(it: &mut Interpreter, t: Texture) {
    let m = it.material();
    let m = it.builder().textured(m, t);
    it.set_material(m);
}

/// A horizontal square of side 2000 at height `h`, normal +y.
fn ground(it: &mut Interpreter, s: &Symbol, h: f64, m: u32) {
    let c = |x: f64, z: f64| DVec3::new(x * GROUND, h, z * GROUND);
    let (a, b, cc, d) = (c(-1.0, -1.0), c(1.0, -1.0), c(1.0, 1.0), c(-1.0, 1.0));
    // Counter-clockwise seen from above (+y).
    it.push_triangle([a, d, cc], m, s);
    it.push_triangle([a, cc, b], m, s);
}

/// A flat box in the x–z plane: [x0,x1] × [y, y+h] × [z0,z1].
fn slab(it: &mut Interpreter, s: &Symbol, lo: DVec3, hi: DVec3, m: u32) {
    let t = Turtle::at(DVec3::new(lo.x, (lo.y + hi.y) / 2.0, (lo.z + hi.z) / 2.0));
    let size = hi - lo;
    // Box: x along H (= +x), y along L (= +y), z along U (= +z).
    it.push_shape(s, ShapeKind::Box, &size.to_array(), &t, size.to_array(), m);
}

/// `D` par1 = 41: the court at real dimensions with its lines and the
/// net; `par2 = 1` adds the surrounding grey ground.
fn tennis_court(it: &mut Interpreter, s: &Symbol, surround: bool) {
    use court::*;
    let b = it.builder();
    let green = b.builtin_material(Vec3::new(0.15, 0.45, 0.2), "court", 1);
    let white = b.builtin_material(Vec3::new(0.95, 0.95, 0.95), "court_line", 7);
    let net = b.builtin_material(Vec3::new(0.1, 0.1, 0.1), "court_net", 18);
    let grey = b.builtin_material(Vec3::new(0.5, 0.5, 0.5), "court_surround", 6);
    let (hl, hw) = (LENGTH / 2.0, DOUBLES_WIDTH / 2.0);
    let margin = (6.4, 3.66);
    let th = 0.01;
    slab(
        it,
        s,
        DVec3::new(-hl - margin.0, -th, -hw - margin.1),
        DVec3::new(hl + margin.0, 0.0, hw + margin.1),
        green,
    );
    if surround {
        let e = 20.0;
        slab(
            it,
            s,
            DVec3::new(-hl - e, -2.0 * th, -hw - e),
            DVec3::new(hl + e, -th, hw + e),
            grey,
        );
    }
    let lw = LINE;
    let mut line = |x0: f64, z0: f64, x1: f64, z1: f64| {
        slab(
            it,
            s,
            DVec3::new(x0, 0.0, z0),
            DVec3::new(x1, 0.002, z1),
            white,
        );
    };
    let hs = SINGLES_WIDTH / 2.0;
    // Base lines and side lines (doubles and singles).
    line(-hl, -hw, -hl + lw, hw);
    line(hl - lw, -hw, hl, hw);
    for z in [-hw, hw - lw, -hs, hs - lw] {
        line(-hl, z, hl, z + lw);
    }
    // Service lines and the centre service line.
    line(-SERVICE - lw / 2.0, -hs, -SERVICE + lw / 2.0, hs);
    line(SERVICE - lw / 2.0, -hs, SERVICE + lw / 2.0, hs);
    line(-SERVICE, -lw / 2.0, SERVICE, lw / 2.0);
    // The net: a thin dark panel in the y–z plane.
    let hn = NET_LENGTH / 2.0;
    slab(
        it,
        s,
        DVec3::new(-0.01, 0.0, -hn),
        DVec3::new(0.01, NET_HEIGHT, hn),
        net,
    );
}

/// `D` par1 = 16: a cloud layer, a flattened white ellipsoid high above
/// the turtle (Rayshade's `texture cloud` … `scale 0.5 1 1`).
fn clouds(it: &mut Interpreter, s: &Symbol, g: [f64; 3]) {
    let b = it.builder();
    let plain = b.builtin_material(Vec3::new(0.95, 0.95, 0.97), "cloud", 7);
    let m = b.textured(plain, Texture::Cloud);
    let scale = if g.iter().all(|v| v.is_finite() && *v > 0.0) {
        g
    } else {
        [500.0, 20.0, 500.0]
    };
    let t = Turtle::at(it.turtle().pos + DVec3::new(0.0, 200.0, 0.0));
    it.push_shape(
        s,
        ShapeKind::Sphere,
        &scale,
        &t,
        [scale[0], scale[1], scale[2]],
        m,
    );
}
