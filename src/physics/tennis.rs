//! The tennis force fields of thesis 7.1 that table B5 offers as special
//! functions: the racket (`?15`), the net (`?19`), the ground (`?26`) and
//! the ball–ground ramp (`?27`). Each is a plain function of what the
//! L-system knows (the query symbol's x y z, the field values X Y Z u v w r
//! and its `fConst` row) and also returns how deep the query is in the
//! repelling field, for the peak detectors (thesis 7.4, [`super::peaks`]).

use crate::lsys::functions::hermite;
use crate::lsys::{FieldQuery, FieldValue};

/// A field's value and the contact level it reports (1 at full contact,
/// 0 outside).
#[derive(Debug, Default, Clone, Copy, PartialEq)]
pub struct Felt {
    pub field: FieldValue,
    pub level: f64,
}

/// Answers `?15`, `?19`, `?26` or `?27` (any other code is the wall,
/// `?27`, as [`FieldQuery::row_of`] reads).
pub fn field(q: &FieldQuery) -> Felt {
    match q.code {
        15 => racket(q.at, q.field, &q.row),
        19 => net(q.at, q.field, &q.row),
        26 => ground(q.at, &q.row),
        _ => wall(q.at, &q.row),
    }
}

/// `?15`: the racket, a disc of normal n = c0..c2 and radius c3 centred on
/// the carrier X Y Z; within the disc's cylinder the force along n is
/// F = c4·3^(−c5·|h|^c6)·sign(h), h the height above the disc. Eq. 7.1.5
/// is lost in the scan: docs/language.md has the reconstruction. The value
/// is F·n_x; `force` is F, which `?16`, `?17` scale by n_y, n_z.
/// With c0..c2 all 0 the normal is the carrier's direction of motion
/// u v w (5.6.6: "the racket normal is always aligned with the direction
/// of its movement"), so each racket of a match has its own; a racket
/// standing still then has no face.
pub fn racket(at: [f64; 3], field: [f64; 7], c: &[f64; 8]) -> Felt {
    let [x, y, z] = at;
    let [ox, oy, oz, u, v, w, _] = field;
    let nrm = if c[..3] == [0.0; 3] {
        let speed = (u * u + v * v + w * w).sqrt();
        if speed == 0.0 || !speed.is_finite() {
            return Felt::default();
        }
        [u / speed, v / speed, w / speed]
    } else {
        [c[0], c[1], c[2]]
    };
    let d = [x - ox, y - oy, z - oz];
    let h = d[0] * nrm[0] + d[1] * nrm[1] + d[2] * nrm[2];
    let lat2 = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2] - h * h).max(0.0);
    let radius = c[3];
    let level = if lat2 <= radius * radius {
        3f64.powf(-c[5] * h.abs().powf(c[6]))
    } else {
        0.0
    };
    let force = c[4] * level * h.signum();
    Felt {
        field: FieldValue {
            value: force * nrm[0],
            force,
            normal: nrm,
        },
        level,
    }
}

/// `?19`: the net of eq. 7.1.3 with f = 1, ((x−a) − u·e) / (((x−a)/b)^c + d)
/// with a…e = c0..c4; its level is d over the shape, 1 in the net's plane.
/// The thesis's bounds test: with c5 > 0 the net acts only for
/// 0 ≤ y ≤ c5 (its height), and with c6 > 0 only for |z| ≤ c6 (half its
/// length); a ball passing over or beside it feels nothing.
pub fn net(at: [f64; 3], field: [f64; 7], c: &[f64; 8]) -> Felt {
    let [x, y, z] = at;
    let below = c[5] <= 0.0 || (0.0..=c[5]).contains(&y);
    let beside = c[6] > 0.0 && z.abs() > c[6];
    if !below || beside {
        return Felt::default();
    }
    let u = field[3];
    let (a, b, cc, d, e) = (c[0], c[1], c[2], c[3], c[4]);
    let shape = ((x - a) / b).powf(cc) + d;
    let level = if d > 0.0 { d / shape } else { 0.0 };
    Felt {
        field: FieldValue {
            value: ((x - a) - u * e) / shape,
            ..FieldValue::default()
        },
        level,
    }
}

/// `?26`: the ground's repulsion, Hermite(c0 + c3 − y; c0, c1, c2).
pub fn ground(at: [f64; 3], c: &[f64; 8]) -> Felt {
    ramp(c[0] + c[3] - at[1], c)
}

/// `?27`: the ball–ground ramp, Hermite(c3 − y; c0, c1, c2).
pub fn wall(at: [f64; 3], c: &[f64; 8]) -> Felt {
    ramp(c[3] - at[1], c)
}

/// Hermite(arg; c0, c1, c2), and its level Hermite(arg; c0, 0, 1).
fn ramp(arg: f64, c: &[f64; 8]) -> Felt {
    Felt {
        field: FieldValue {
            value: hermite(arg, c[0], c[1], c[2]),
            ..FieldValue::default()
        },
        level: hermite(arg, c[0], 0.0, 1.0),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// With a height and a half length (c5, c6), the net acts below and
    /// beside nothing else: a ball over it or past its post feels nothing
    /// and is not heard; without them it acts everywhere.
    #[test]
    fn the_net_acts_only_within_its_bounds() {
        let bounded = [0.0, 0.1, 4.0, 1.0, 1.0, 0.95, 6.4, 0.0];
        let field = [0.0, 0.0, 0.0, -20.0, 0.0, 0.0, 0.0];
        let at = |y: f64, z: f64| net([0.02, y, z], field, &bounded);
        assert!(at(0.5, 2.0).field.value > 1.0);
        assert!(at(0.5, 2.0).level > 0.5);
        assert_eq!(at(1.2, 2.0), Felt::default());
        assert_eq!(at(0.5, 7.0), Felt::default());
        assert_eq!(at(-0.1, 0.0), Felt::default());
        let mut unbounded = bounded;
        unbounded[5..7].copy_from_slice(&[0.0, 0.0]);
        assert!(net([0.02, 30.0, 50.0], field, &unbounded).level > 0.5);
    }
}
