//! The 3D turtle (2.1.5, appendix C.1): position and the rows H, L, U.

use glam::{DMat3, DVec3};

/// Gravity direction of the `$` overloads (y up, thesis 5.2.3).
const DOWN: DVec3 = DVec3::new(0.0, -1.0, 0.0);

/// Position and orientation; H = heading, L = left, U = up.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Turtle {
    pub pos: DVec3,
    pub h: DVec3,
    pub l: DVec3,
    pub u: DVec3,
}

impl Default for Turtle {
    /// At the origin with H = +x, L = +y, U = +z (DESIGN §3).
    fn default() -> Self {
        Turtle {
            pos: DVec3::ZERO,
            h: DVec3::X,
            l: DVec3::Y,
            u: DVec3::Z,
        }
    }
}

/// Rotations by a non-finite angle are ignored: a NaN never enters the
/// turtle.
impl Turtle {
    /// The default orientation at `pos`.
    pub fn at(pos: DVec3) -> Self {
        Turtle {
            pos,
            ..Turtle::default()
        }
    }

    /// `+` (a > 0) and `-` (a < 0): R_U(a) of eq. 2.1.1 applied to the
    /// rows, H' = cos·H + sin·L.
    pub fn turn(&mut self, deg: f64) {
        if !deg.is_finite() {
            return;
        }
        let (s, c) = deg.to_radians().sin_cos();
        let (h, l) = (self.h, self.l);
        self.h = c * h + s * l;
        self.l = -s * h + c * l;
    }

    /// `&` (a > 0) and `^` (a < 0): R_L(a) of eq. 2.1.2, H' = cos·H − sin·U.
    pub fn pitch(&mut self, deg: f64) {
        if !deg.is_finite() {
            return;
        }
        let (s, c) = deg.to_radians().sin_cos();
        let (h, u) = (self.h, self.u);
        self.h = c * h - s * u;
        self.u = s * h + c * u;
    }

    /// `$` (a > 0) and `/` (a < 0): R_H(a) of eq. 2.1.3, L' = cos·L + sin·U.
    pub fn roll(&mut self, deg: f64) {
        if !deg.is_finite() {
            return;
        }
        let (s, c) = deg.to_radians().sin_cos();
        let (l, u) = (self.l, self.u);
        self.l = c * l + s * u;
        self.u = -s * l + c * u;
    }

    /// `$` par2 = 1: L horizontal, H unchanged (ABOP's L = V × H / |V × H|
    /// with V against gravity). Nothing changes when H is vertical.
    pub fn level(&mut self) {
        let l = (-DOWN).cross(self.h);
        if l.length_squared() > 1e-24 {
            self.l = l.normalize();
            self.u = self.h.cross(self.l);
        }
    }

    /// `$` par2 = 2: L made horizontal, then H rotated about L onto gravity.
    pub fn hang(&mut self) {
        self.level();
        self.h = DOWN;
        // Keep L horizontal and orthogonal to the new H.
        let l = self.l - self.l.dot(DOWN) * DOWN;
        self.l = if l.length_squared() > 1e-24 {
            l.normalize()
        } else {
            DVec3::Z
        };
        self.u = self.h.cross(self.l);
    }

    /// `$` par2 = 3: orientation back to the identity, position kept.
    pub fn reset_orientation(&mut self) {
        let pos = self.pos;
        *self = Turtle {
            pos,
            ..Turtle::default()
        };
    }

    /// `$` par2 = 6: H projected onto the horizontal plane, U vertical.
    pub fn horizontal(&mut self) {
        let h = DVec3::new(self.h.x, 0.0, self.h.z);
        if h.length_squared() > 1e-24 {
            self.h = h.normalize();
            self.u = DVec3::Y;
            self.l = self.u.cross(self.h);
        }
    }

    /// H along `dir` with U as close to vertical as H allows, the way
    /// an actor's eye stands (`M` par1 = 7); a vertical `dir` is aligned
    /// by the smallest rotation instead.
    pub fn look_along(&mut self, dir: DVec3) {
        let h = dir.normalize_or_zero();
        let l = DVec3::Y.cross(h);
        if l.length_squared() < 1e-18 {
            return self.align(dir);
        }
        self.h = h;
        self.l = l.normalize();
        self.u = self.h.cross(self.l);
    }

    /// H aligned with `dir` by the smallest rotation (`$` par2 = 4).
    pub fn align(&mut self, dir: DVec3) {
        if dir.length_squared() < 1e-24 {
            return;
        }
        let d = dir.normalize();
        let axis = self.h.cross(d);
        let angle = axis.length().atan2(self.h.dot(d));
        if axis.length_squared() > 1e-24 {
            self.rotate_about(axis.normalize(), angle);
        } else if self.h.dot(d) < 0.0 {
            // Opposite: half a turn about U (any axis ⟂ H is smallest).
            self.rotate_about(self.u, std::f64::consts::PI);
        }
    }

    /// Rotates H and L about the unit axis `a` by `angle` radians
    /// (Rodrigues, eq. 2.3.5) and rebuilds U = H × L.
    pub fn rotate_about(&mut self, a: DVec3, angle: f64) {
        let r = DMat3::from_axis_angle(a, angle);
        self.h = (r * self.h).normalize();
        self.l = (r * self.l).normalize();
        self.u = self.h.cross(self.l);
    }

    /// The turtle frame as columns (H, L, U).
    pub fn frame(&self) -> DMat3 {
        DMat3::from_cols(self.h, self.l, self.u)
    }
}

/// Tropism of eq. 2.3.4: the heading bends toward the force `f` by
/// α = β(1 − 1/(1 + m)), m = |H × F| / e, β the angle between H and F.
///
/// The printed β = sin⁻¹(|A|) uses the already normalised A, which is
/// always 1; the angle between H and F is meant (figure 2.3.2), taken with
/// atan2 so that forces behind the turtle work too.
pub fn bend(t: &mut Turtle, f: DVec3, elasticity: f64) {
    let hxf = t.h.cross(f);
    let n = hxf.length();
    if n < 1e-15 || elasticity <= 0.0 || !n.is_finite() {
        return;
    }
    let m = n / elasticity;
    let beta = n.atan2(t.h.dot(f));
    let alpha = beta * (1.0 - 1.0 / (1.0 + m));
    t.rotate_about(hxf / n, alpha);
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: DVec3, b: DVec3) -> bool {
        (a - b).length() < 1e-12
    }

    #[test]
    fn align_turns_round_to_the_opposite_direction() {
        let mut t = Turtle::default();
        t.align(-DVec3::X);
        assert!(close(t.h, -DVec3::X) && close(t.u, DVec3::Z), "{t:?}");
        assert!(close(t.h.cross(t.l), t.u));
        t.align(DVec3::Y);
        assert!(close(t.h, DVec3::Y));
    }

    #[test]
    fn rotations_follow_eq_2_1_1_to_2_1_4() {
        let mut t = Turtle::default();
        t.turn(90.0); // + : H toward L
        assert!(close(t.h, DVec3::Y) && close(t.l, -DVec3::X) && close(t.u, DVec3::Z));
        let mut t = Turtle::default();
        t.pitch(90.0); // & : H toward −U
        assert!(close(t.h, -DVec3::Z) && close(t.u, DVec3::X));
        let mut t = Turtle::default();
        t.roll(90.0); // $ : L toward U
        assert!(close(t.l, DVec3::Z) && close(t.u, -DVec3::Y) && close(t.h, DVec3::X));
        let mut t = Turtle::default();
        t.turn(-30.0);
        t.turn(30.0);
        assert!(close(t.h, DVec3::X));
    }

    #[test]
    fn overloads_of_dollar() {
        let mut t = Turtle::default();
        t.pitch(30.0);
        t.roll(40.0);
        t.level();
        assert!(t.l.y.abs() < 1e-12);
        t.hang();
        assert!(close(t.h, DOWN) && t.l.y.abs() < 1e-12);
        t.reset_orientation();
        assert!(close(t.h, DVec3::X));
        t.pitch(45.0);
        t.horizontal();
        assert!(close(t.u, DVec3::Y) && t.h.y.abs() < 1e-12);
    }

    #[test]
    fn tropism_bends_toward_the_force_but_not_past_it() {
        let mut t = Turtle::default();
        bend(&mut t, DVec3::new(0.0, -1.0, 0.0), 1.0);
        assert!(t.h.y < 0.0 && t.h.x > 0.0, "{:?}", t.h);
        let mut stiff = Turtle::default();
        bend(&mut stiff, DVec3::new(0.0, -1.0, 0.0), 100.0);
        assert!(stiff.h.y > t.h.y, "a stiffer branch bends less");
        let mut strong = Turtle::default();
        bend(&mut strong, DVec3::new(0.0, -1e9, 0.0), 1.0);
        assert!(
            strong.h.y > -1.0 - 1e-9 && strong.h.x > -1e-6,
            "never past the force"
        );
    }
}
