//! Polygons `{ . }` (appendix C.3, figure C.3.6): a stack of open
//! polygons, triangulated by ear clipping when drawn, so concave outlines
//! (leaves) come out right.

use glam::DVec3;

/// The stack of polygons under construction.
#[derive(Debug, Default)]
pub struct PolygonStack {
    current: Vec<DVec3>,
    stack: Vec<Vec<DVec3>>,
}

impl PolygonStack {
    /// `{`: the current polygon is pushed and a new one begins.
    pub fn open(&mut self) {
        let cur = std::mem::take(&mut self.current);
        self.stack.push(cur);
    }

    /// `.` (and `]` with a position table): a vertex.
    pub fn vertex(&mut self, p: DVec3) {
        if self.current.last() != Some(&p) {
            self.current.push(p);
        }
    }

    /// `}`: the current polygon is finished; the one below becomes current.
    pub fn close(&mut self) -> Vec<DVec3> {
        let done = std::mem::take(&mut self.current);
        self.current = self.stack.pop().unwrap_or_default();
        done
    }
}

/// Newell's normal of a polygon (not normalised; zero when degenerate).
pub fn newell(p: &[DVec3]) -> DVec3 {
    let mut n = DVec3::ZERO;
    for (i, a) in p.iter().enumerate() {
        let b = p[(i + 1) % p.len()];
        n += DVec3::new(
            (a.y - b.y) * (a.z + b.z),
            (a.z - b.z) * (a.x + b.x),
            (a.x - b.x) * (a.y + b.y),
        );
    }
    n
}

/// Triangulates a simple polygon (convex or concave) by ear clipping in
/// its plane; triangles keep the polygon's winding. Returns index triples.
pub fn triangulate(p: &[DVec3]) -> Vec<[usize; 3]> {
    let n = newell(p);
    if p.len() < 3 || n.length_squared() < 1e-30 {
        return Vec::new();
    }
    let n = n.normalize();
    let mut idx: Vec<usize> = (0..p.len()).collect();
    let mut out = Vec::with_capacity(p.len() - 2);
    let convex = |a: DVec3, b: DVec3, c: DVec3| (b - a).cross(c - b).dot(n) > 1e-15;
    let inside = |q: DVec3, a: DVec3, b: DVec3, c: DVec3| {
        (b - a).cross(q - a).dot(n) >= 0.0
            && (c - b).cross(q - b).dot(n) >= 0.0
            && (a - c).cross(q - c).dot(n) >= 0.0
    };
    let mut guard = 0;
    while idx.len() > 3 && guard < 4 * p.len() * p.len() {
        guard += 1;
        let m = idx.len();
        let ear = (0..m).find(|&k| {
            let (ia, ib, ic) = (idx[(k + m - 1) % m], idx[k], idx[(k + 1) % m]);
            let (a, b, c) = (p[ia], p[ib], p[ic]);
            convex(a, b, c)
                && idx
                    .iter()
                    .filter(|&&j| j != ia && j != ib && j != ic)
                    .all(|&j| !inside(p[j], a, b, c) || p[j] == a || p[j] == b || p[j] == c)
        });
        // A self-intersecting outline has no ear: fan out what is left.
        let k = ear.unwrap_or(0);
        out.push([idx[(k + m - 1) % m], idx[k], idx[(k + 1) % m]]);
        idx.remove(k);
    }
    if idx.len() == 3 {
        out.push([idx[0], idx[1], idx[2]]);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn area(p: &[DVec3], tris: &[[usize; 3]]) -> f64 {
        tris.iter()
            .map(|t| (p[t[1]] - p[t[0]]).cross(p[t[2]] - p[t[0]]).length() / 2.0)
            .sum()
    }

    #[test]
    fn concave_polygon_area_is_kept() {
        // An L shape of area 3.
        let p: Vec<DVec3> = [(0., 0.), (2., 0.), (2., 1.), (1., 1.), (1., 2.), (0., 2.)]
            .iter()
            .map(|&(x, z)| DVec3::new(x, 0.0, z))
            .collect();
        let t = triangulate(&p);
        assert_eq!(t.len(), 4);
        assert!((area(&p, &t) - 3.0).abs() < 1e-12);
    }

    #[test]
    fn nested_polygons() {
        let mut s = PolygonStack::default();
        s.open();
        s.vertex(DVec3::X);
        s.open();
        s.vertex(DVec3::Y);
        assert_eq!(s.close(), [DVec3::Y]);
        s.vertex(DVec3::Z);
        assert_eq!(s.close(), [DVec3::X, DVec3::Z]);
    }
}
