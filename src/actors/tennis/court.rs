//! The court as the referee judges it (figure C.6.2, `D` par1 = 41): the
//! two players' sides of the net, the singles courts and the service
//! boxes, with the lines as `D` 41 draws them.
//!
//! The court lies in the x–z plane, net at x = 0. Without change of ends
//! (C.6: "the green actor stays always at the left side") player green
//! plays on x < 0 and player blue on x > 0. A point on the ground is
//! `[x, z]`: where the ball touched it, under the ball's centre.

use crate::turtle::special::court::{LENGTH, LINE, SERVICE, SINGLES_WIDTH};

/// The base lines' outer edges: x = ±11.885.
pub const BASE_LINE: f64 = LENGTH / 2.0;

/// The singles sidelines' outer edges: z = ±4.115.
pub const SIDELINE: f64 = SINGLES_WIDTH / 2.0;

/// The far edge of a service line: `D` 41 draws it centred on ±6.40.
pub const SERVICE_LINE: f64 = SERVICE + LINE / 2.0;

/// Half the centre service line's width: the line is in both boxes.
pub const CENTRE_LINE: f64 = LINE / 2.0;

/// The height of the ball's centre at the bottom of a bounce, as the
/// players and the referee know it: the scenes' ball has a radius of 0.1
/// and the ground's field stops its centre about 0.14 up.
pub const BALL_LOW: f64 = 0.14;

/// A player, named by its colour (thesis 7.4: "the blue and the green
/// actors"). Green is player 0 and plays on x < 0, blue is player 1.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Side {
    Green,
    Blue,
}

impl Side {
    /// Both players, in player order.
    pub const BOTH: [Side; 2] = [Side::Green, Side::Blue];

    /// 0 for green, 1 for blue.
    pub fn index(self) -> usize {
        self as usize
    }

    /// The one across the net.
    pub fn opponent(self) -> Side {
        match self {
            Side::Green => Side::Blue,
            Side::Blue => Side::Green,
        }
    }

    /// The sign of x on this player's side of the net.
    fn x_sign(self) -> f64 {
        match self {
            Side::Green => -1.0,
            Side::Blue => 1.0,
        }
    }

    /// The sign of z on this player's right hand as it faces the net:
    /// green faces +x, so its right is +z (y up, right-handed); blue
    /// faces −x, so its right is −z.
    fn right_sign(self) -> f64 {
        -self.x_sign()
    }
}

/// The half of its court a server serves from, as it faces the net: the
/// right (deuce court) for the first point of a game, then alternately.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Half {
    Right,
    Left,
}

/// An axis-aligned rectangle of the ground, edges included.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rect {
    pub x: [f64; 2],
    pub z: [f64; 2],
}

impl Rect {
    /// Whether the point is inside or on an edge: a ball touching a
    /// line is in (ITF rule 12).
    pub fn contains(&self, [x, z]: [f64; 2]) -> bool {
        (self.x[0]..=self.x[1]).contains(&x) && (self.z[0]..=self.z[1]).contains(&z)
    }
}

/// The interval between two bounds given in either order.
fn span(a: f64, b: f64) -> [f64; 2] {
    [a.min(b), a.max(b)]
}

/// The player whose side of the net a ground point is on; the net plane
/// itself (x = 0) counts as blue's.
pub fn side_of([x, _]: [f64; 2]) -> Side {
    if x < 0.0 {
        Side::Green
    } else {
        Side::Blue
    }
}

/// A player's singles court, from the net to its base line.
pub fn court(p: Side) -> Rect {
    Rect {
        x: span(0.0, BASE_LINE * p.x_sign()),
        z: [-SIDELINE, SIDELINE],
    }
}

/// The box a service from `half` must land in: on the receiver's side,
/// diagonally opposite the server, so in the receiver's own half of the
/// same name (right to right).
pub fn service_box(server: Side, half: Half) -> Rect {
    let receiver = server.opponent();
    let z = match half {
        Half::Right => receiver.right_sign(),
        Half::Left => -receiver.right_sign(),
    };
    Rect {
        x: span(0.0, SERVICE_LINE * receiver.x_sign()),
        z: span(-CENTRE_LINE * z, SIDELINE * z),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use Half::{Left, Right};
    use Side::{Blue, Green};

    const EPS: f64 = 1e-9;

    #[test]
    fn sides_of_the_net() {
        assert_eq!(side_of([-0.01, 3.0]), Green);
        assert_eq!(side_of([-11.0, -3.0]), Green);
        assert_eq!(side_of([0.01, 0.0]), Blue);
        assert_eq!(side_of([0.0, 0.0]), Blue);
        assert_eq!(Green.opponent(), Blue);
        assert_eq!(Blue.opponent(), Green);
        assert_eq!([Green.index(), Blue.index()], [0, 1]);
    }

    #[test]
    fn singles_court_lines_are_in() {
        let g = court(Green);
        assert!(g.contains([-BASE_LINE, SIDELINE]));
        assert!(g.contains([-BASE_LINE, -SIDELINE]));
        assert!(g.contains([-5.0, 0.0]));
        assert!(!g.contains([-BASE_LINE - EPS, 0.0]));
        assert!(!g.contains([-5.0, SIDELINE + EPS]));
        assert!(!g.contains([-5.0, -SIDELINE - EPS]));
        assert!(!g.contains([1.0, 0.0]));
        let b = court(Blue);
        assert!(b.contains([BASE_LINE, -SIDELINE]));
        assert!(!b.contains([BASE_LINE + EPS, 0.0]));
        assert!(!b.contains([-1.0, 0.0]));
        // The doubles alleys are out in singles.
        assert!(!b.contains([5.0, 5.0]));
    }

    #[test]
    fn court_dimensions_are_the_itf_ones() {
        assert!((BASE_LINE - 11.885).abs() < EPS);
        assert!((SIDELINE - 4.115).abs() < EPS);
        assert!((SERVICE_LINE - 6.425).abs() < EPS);
    }

    /// Green serves from its right (+z) to blue's right (−z), from its
    /// left (−z) to blue's left (+z); blue's right is −z, so blue's
    /// right-half service goes to green's right (+z).
    #[test]
    fn service_boxes_are_diagonal() {
        let cases = [
            (Green, Right, [0.0, SERVICE_LINE], [-SIDELINE, CENTRE_LINE]),
            (Green, Left, [0.0, SERVICE_LINE], [-CENTRE_LINE, SIDELINE]),
            (Blue, Right, [-SERVICE_LINE, 0.0], [-CENTRE_LINE, SIDELINE]),
            (Blue, Left, [-SERVICE_LINE, 0.0], [-SIDELINE, CENTRE_LINE]),
        ];
        for (server, half, x, z) in cases {
            assert_eq!(
                service_box(server, half),
                Rect { x, z },
                "{server:?} {half:?}"
            );
        }
    }

    #[test]
    fn service_box_lines_are_in() {
        let b = service_box(Green, Right);
        assert!(b.contains([3.0, -2.0]));
        assert!(b.contains([SERVICE_LINE, -SIDELINE]));
        assert!(b.contains([6.40, 0.0]));
        assert!(!b.contains([SERVICE_LINE + EPS, -2.0]));
        assert!(!b.contains([3.0, -SIDELINE - EPS]));
        assert!(!b.contains([3.0, CENTRE_LINE + EPS]));
        assert!(!b.contains([-3.0, -2.0]));
        // The other box and the back court are faults.
        assert!(!b.contains([3.0, 2.0]));
        assert!(!b.contains([8.0, -2.0]));
        let g = service_box(Blue, Left);
        assert!(g.contains([-SERVICE_LINE, -SIDELINE]));
        assert!(!g.contains([-SERVICE_LINE - EPS, -1.0]));
        assert!(!g.contains([-1.0, 1.0]));
    }
}
