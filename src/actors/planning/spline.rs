//! The path spline of a navigating actor (thesis 5.2.4, figure 5.2.4,
//! whose drawing the scan lost; the reading is in docs/actors.md): cubic
//! Hermite pieces through the planned path's key points, walked by arc
//! length at the actor's `speed`.
//!
//! The tangent at a key point is Catmull–Rom's, (next − previous) / 2, and
//! at the last key point the last chord; a piece leaving the actor (after
//! a plan, or at a key point) starts along its heading, with the length of
//! its chord. `inertia` scales every tangent: 0 gives straight lines
//! between the key points (the actor turns on the spot), 1 the full
//! Catmull–Rom curve (it keeps its way and swings into the turns).

use glam::Vec3;

/// Chords a piece is measured by for its arc length.
const CHORDS: usize = 16;

/// One Hermite piece from `p0` to `p1`, with its arc length table.
#[derive(Debug, Clone, PartialEq)]
pub struct Piece {
    p0: Vec3,
    m0: Vec3,
    p1: Vec3,
    m1: Vec3,
    /// The key point after `p1` that shaped `m1`, if any.
    next: Option<Vec3>,
    /// The curve at u = k / CHORDS, and the arc length from `p0` there
    /// (along the chords).
    points: [Vec3; CHORDS + 1],
    lengths: [f32; CHORDS + 1],
}

impl Piece {
    /// The piece from `from` to `keys[0]` leaving along `heading` (a unit
    /// vector, or zero for along the chord), `keys[1]` shaping the
    /// arrival; None without keys.
    pub fn new(from: Vec3, heading: Vec3, keys: &[Vec3], inertia: f32) -> Option<Self> {
        let p1 = *keys.first()?;
        let next = keys.get(1).copied();
        let chord = p1 - from;
        let k = inertia.clamp(0.0, 1.0);
        let m0 = if heading == Vec3::ZERO {
            chord * k
        } else {
            heading * chord.length() * k
        };
        let m1 = match next {
            Some(n) => (n - from) * 0.5 * k,
            None => chord * k,
        };
        let mut piece = Piece {
            p0: from,
            m0,
            p1,
            m1,
            next,
            points: [from; CHORDS + 1],
            lengths: [0.0; CHORDS + 1],
        };
        for i in 1..=CHORDS {
            piece.points[i] = piece.at(i as f32 / CHORDS as f32);
            let chord = piece.points[i] - piece.points[i - 1];
            piece.lengths[i] = piece.lengths[i - 1] + chord.length();
        }
        Some(piece)
    }

    /// Whether the piece still leads along `keys` (its end and the key
    /// point after it are theirs): else the path changed under it.
    pub fn leads_along(&self, keys: &[Vec3]) -> bool {
        keys.first() == Some(&self.p1) && keys.get(1).copied() == self.next
    }

    pub fn end(&self) -> Vec3 {
        self.p1
    }

    pub fn length(&self) -> f32 {
        self.lengths[CHORDS]
    }

    /// The point at parameter u ∈ [0, 1].
    fn at(&self, u: f32) -> Vec3 {
        let (u2, u3) = (u * u, u * u * u);
        self.p0 * (2.0 * u3 - 3.0 * u2 + 1.0)
            + self.m0 * (u3 - 2.0 * u2 + u)
            + self.p1 * (-2.0 * u3 + 3.0 * u2)
            + self.m1 * (u3 - u2)
    }

    /// The unit direction of travel at parameter u; the chord's where the
    /// curve stands still (zero tangents at the ends).
    fn heading(&self, u: f32) -> Vec3 {
        let u2 = u * u;
        let d = self.p0 * (6.0 * u2 - 6.0 * u)
            + self.m0 * (3.0 * u2 - 4.0 * u + 1.0)
            + self.p1 * (-6.0 * u2 + 6.0 * u)
            + self.m1 * (3.0 * u2 - 2.0 * u);
        d.try_normalize()
            .unwrap_or_else(|| (self.p1 - self.p0).normalize_or_zero())
    }

    /// The point `s` along the curve from its start (clamped to the piece;
    /// on its chords, so a straight piece is walked exactly) and the
    /// direction of travel there.
    pub fn along(&self, s: f32) -> (Vec3, Vec3) {
        let s = s.clamp(0.0, self.length());
        let i = self.lengths[1..]
            .iter()
            .position(|&l| l >= s)
            .unwrap_or(CHORDS - 1);
        let (l0, l1) = (self.lengths[i], self.lengths[i + 1]);
        let f = if l1 > l0 { (s - l0) / (l1 - l0) } else { 0.0 };
        let at = self.points[i].lerp(self.points[i + 1], f);
        (at, self.heading((i as f32 + f) / CHORDS as f32))
    }

    /// Points every `spacing` along the curve from `s` to its end; how
    /// far into the next piece the next point falls.
    fn sample(&self, s: f32, spacing: f32, out: &mut Vec<Vec3>) -> f32 {
        let mut d = s;
        while d < self.length() {
            out.push(self.along(d).0);
            d += spacing;
        }
        d - self.length()
    }
}

/// Points every `spacing` (> 0) along the whole spline ahead: what is left
/// of `current` after `travelled`, then the pieces through the remaining
/// `keys`, each leaving where the one before arrived; the last key point
/// closes it. Drawn for the viewer (`turtle` 3): the spacing runs on
/// across key points, so the count grows with the length in metres, not
/// with the count of key points.
pub fn ahead(
    current: Option<(&Piece, f32)>,
    from: Vec3,
    heading: Vec3,
    keys: &[Vec3],
    inertia: f32,
    spacing: f32,
) -> Vec<Vec3> {
    let mut out = Vec::new();
    let (mut at, mut dir, mut rest, mut next) = (from, heading, keys, 0.0);
    if let Some((piece, travelled)) = current.filter(|(p, _)| p.leads_along(keys)) {
        next = piece.sample(travelled, spacing, &mut out);
        (at, dir, rest) = (piece.p1, piece.heading(1.0), &keys[1..]);
    }
    for i in 0..rest.len() {
        if let Some(piece) = Piece::new(at, dir, &rest[i..], inertia) {
            next = piece.sample(next, spacing, &mut out);
            (at, dir) = (piece.p1, piece.heading(1.0));
        }
    }
    out.extend(keys.last());
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn keys() -> [Vec3; 2] {
        [Vec3::new(4.0, 0.0, 0.0), Vec3::new(4.0, 0.0, 4.0)]
    }

    /// Without inertia the piece is the chord, walked at even steps.
    #[test]
    fn no_inertia_is_a_straight_line() {
        let p = Piece::new(Vec3::ZERO, Vec3::Z, &keys(), 0.0).unwrap();
        assert!((p.length() - 4.0).abs() < 1e-4);
        let (at, dir) = p.along(1.0);
        assert!(at.distance(Vec3::X) < 1e-4 && dir.distance(Vec3::X) < 1e-4);
        assert_eq!(p.along(9.0).0, keys()[0]);
    }

    /// With inertia the actor leaves along its heading, swings into the
    /// turn (its way bends toward the next key point before it arrives)
    /// and arrives heading along the Catmull–Rom tangent.
    #[test]
    fn inertia_keeps_the_heading_and_rounds_the_turn() {
        let p = Piece::new(Vec3::ZERO, Vec3::NEG_Z, &keys(), 1.0).unwrap();
        assert!(p.heading(0.0).distance(Vec3::NEG_Z) < 1e-4);
        assert!(p.length() > 4.0);
        let end = p.heading(1.0);
        assert!(end.distance(Vec3::new(1.0, 0.0, 1.0).normalize()) < 1e-4);
        let (early, _) = p.along(0.5);
        assert!(early.z < -0.1, "keeps its way at first: {early}");
        assert!(p.along(p.length()).0.distance(keys()[0]) < 1e-5);
    }

    /// The path ahead is dotted evenly, continues smoothly at each key
    /// point and ends at the last.
    #[test]
    fn the_path_ahead_ends_at_the_last_key() {
        let dots = ahead(None, Vec3::ZERO, Vec3::X, &keys(), 1.0, 0.5);
        assert_eq!(dots.first(), Some(&Vec3::ZERO));
        assert_eq!(dots.last(), Some(&keys()[1]));
        assert!(dots.windows(2).all(|w| w[0].distance(w[1]) <= 0.5 + 1e-3));
        assert!(dots.len() >= 16);
    }
}
