//! Axis-aligned boxes shared by the layers: the renderer's BVH builds on
//! them, and they bound what a scene may hold. The type is obvhs's
//! ([`Aabb`], f32 on `Vec3A`, min and max corners); this module adds the
//! operations the layers share: the box of a few points, the box of a box
//! under an affine map, and the check that a box is one the renderer can
//! hold (finite, within ±[`MAX_COORDINATE`]). They serve build time, never
//! a ray.

use glam::{Affine3A, Vec3A};

pub use obvhs::aabb::Aabb;

/// Largest |coordinate| a primitive's bounds may reach; farther ones are
/// refused by the turtle, the OBJ reader and the renderer. The renderer's
/// boxes are f32 and its BVH builder (PLOC) sums surface areas and maps
/// centres to Morton codes over the scene's extent: past about 1e19 the
/// areas overflow f32 to infinity and the build fails. At 1e15 an area
/// stays below 1e32 (f32 reaches 3e38), and 1e15 m is still 6,700 times
/// the Earth–Sun distance.
pub const MAX_COORDINATE: f32 = 1e15;

/// Whether `b` is finite and within ±[`MAX_COORDINATE`] (NaN is not).
pub fn within(b: &Aabb) -> bool {
    let m = Vec3A::splat(MAX_COORDINATE);
    b.min.cmpge(-m).all() && b.max.cmple(m).all()
}

/// `b` when it is [`within`] bounds.
pub fn checked(b: Aabb) -> Option<Aabb> {
    within(&b).then_some(b)
}

/// The box around `points`; None when a coordinate is not finite or
/// beyond ±[`MAX_COORDINATE`].
pub fn around(points: &[Vec3A]) -> Option<Aabb> {
    let (&first, rest) = points.split_first()?;
    let (lo, hi) = rest
        .iter()
        .fold((first, first), |(lo, hi), &p| (lo.min(p), hi.max(p)));
    // min and max may drop a NaN: the points are checked themselves.
    let finite = points.iter().all(|p| p.is_finite());
    if !finite {
        return None;
    }
    checked(Aabb::new(lo, hi))
}

/// The box around the 8 corners of `a` transformed by `m`; None when not
/// finite or beyond ±[`MAX_COORDINATE`].
pub fn transformed(a: &Aabb, m: &Affine3A) -> Option<Aabb> {
    // `extend` may drop a NaN corner: the transform is checked itself.
    if !m.is_finite() {
        return None;
    }
    let mut out = Aabb::empty();
    for i in 0..8 {
        let c = Vec3A::new(
            if i & 1 == 0 { a.min.x } else { a.max.x },
            if i & 2 == 0 { a.min.y } else { a.max.y },
            if i & 4 == 0 { a.min.z } else { a.max.z },
        );
        out.extend(m.transform_point3a(c));
    }
    checked(out)
}

/// A conservative box around `a` transformed by `m`, from its centre and
/// half extent, padded by a few ulps against rounding; None when `m` or
/// `a` is not finite, or the result beyond ±[`MAX_COORDINATE`].
pub fn transformed_padded(a: &Aabb, m: &Affine3A) -> Option<Aabb> {
    let (lo, hi) = (a.min, a.max);
    if !(m.is_finite() && lo.is_finite() && hi.is_finite()) {
        return None;
    }
    let c = (lo + hi) * 0.5;
    let e = (hi - lo) * 0.5;
    let m3 = &m.matrix3;
    let wc = m.transform_point3a(c);
    let we = m3.x_axis.abs() * e.x + m3.y_axis.abs() * e.y + m3.z_axis.abs() * e.z;
    let pad = (wc.abs() + we) * (4.0 * f32::EPSILON);
    checked(Aabb::new(wc - we - pad, wc + we + pad))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn within_rejects_nan_and_far_boxes() {
        assert!(within(&Aabb::new(Vec3A::ZERO, Vec3A::ONE)));
        assert!(!within(&Aabb::new(Vec3A::NAN, Vec3A::ONE)));
        let far = Vec3A::splat(2.0 * MAX_COORDINATE);
        assert!(!within(&Aabb::new(Vec3A::ZERO, far)));
    }

    #[test]
    fn transformed_boxes_hold_the_moved_corners() {
        let a = Aabb::new(Vec3A::new(0.0, -0.5, -0.5), Vec3A::new(1.0, 0.5, 0.5));
        let m = Affine3A::from_rotation_z(0.7) * Affine3A::from_translation([3.0, 1.0, 2.0].into());
        let exact = transformed(&a, &m).unwrap();
        let padded = transformed_padded(&a, &m).unwrap();
        assert!(padded.min.cmple(exact.min).all() && padded.max.cmpge(exact.max).all());
        assert_eq!(
            transformed(&a, &Affine3A::from_scale(Vec3A::NAN.into())),
            None
        );
    }
}
