//! An actor's visual memory (thesis 3.1.3, 3.1.4): the octree of the
//! voxels its vision has seen occupied, stamped with the frame that last
//! saw them, and the forgetting of the voxels that disappeared.
//!
//! Each image: every seen pixel's world position is inserted with the
//! frame as its label ([`VisualMemory::insert`]); then
//! [`VisualMemory::forget`] tests every occupied voxel in the vision
//! volume. A voxel whose centre is closer to the eye than what the window
//! pixel it projects to shows (eq. 3.1.16, d_scene > d_octree + margin) —
//! it should have been seen there but was not — and that was not stamped
//! recently is counted in the auxiliary octree X. Every n images the
//! voxels of X counted more than m times are removed from the memory and X
//! is emptied. A voxel hidden behind another object projects to a pixel
//! that shows the nearer object, so it is never counted.
//!
//! The view is a [`DepthView`], what an actor's vision window produces: the
//! camera model is the renderer's ([`crate::render::camera::CameraRays`]
//! with a square window), so the point a pixel's centre ray hits projects
//! back to that pixel.

use glam::Vec3;

use super::octree::{Cube, Octree, Voxel};
use crate::render::camera::CameraRays;
use crate::scene::Camera;

/// One image of a vision window, as the forgetting needs it: a square
/// window of edge × edge pixels looking from `eye` at `look_at`.
#[derive(Debug, Clone, PartialEq)]
pub struct DepthView {
    pub eye: Vec3,
    pub look_at: Vec3,
    /// Rotation about the viewing axis, degrees (as [`Camera::twist`]).
    pub twist: f32,
    /// Vertical (and horizontal: the window is square) field of view in
    /// degrees, as [`Camera::fov_y`]; the `fov` command's tenths of a
    /// degree divided by 10.
    pub fov_y: f32,
    /// The vision range (`vision_range near far`): voxels whose distance
    /// from the eye lies outside [near, far] are not tested.
    pub near: f32,
    pub far: f32,
    pub edge: u32,
    /// Distance from the eye to what each pixel's centre ray hits, row
    /// by row from the top-left corner; infinity for a miss.
    pub distances: Vec<f32>,
}

impl DepthView {
    /// The renderer's camera for this window (aspect 1).
    pub fn camera(&self) -> Camera {
        Camera {
            eye: self.eye,
            look_at: self.look_at,
            twist: self.twist,
            fov_y: self.fov_y,
            aspect: 1.0,
            near: self.near,
            far: self.far,
            width: self.edge,
            height: self.edge,
            lens: Default::default(),
        }
    }

    /// The rays of the window's pixels, as the renderer casts them.
    pub fn rays(&self) -> CameraRays {
        CameraRays::new(&self.camera(), self.edge, self.edge)
    }

    /// The world point pixel (x, y)'s centre ray hits, None on a miss.
    pub fn point(&self, x: u32, y: u32) -> Option<Vec3> {
        let d = *self.distances.get((y * self.edge + x) as usize)?;
        d.is_finite().then(|| {
            let dir = self.rays().dir(x as f32 + 0.5, y as f32 + 0.5);
            self.eye + Vec3::from(dir) * d
        })
    }

    /// The pixel world point p projects to and its distance from the eye;
    /// None when p is behind the eye or outside the window.
    pub fn project(&self, p: Vec3) -> Option<((u32, u32), f32)> {
        Projector::new(self).project(p)
    }

    /// [`DepthView::project`] for many points, the camera's basis found
    /// once.
    pub fn projector(&self) -> impl Fn(Vec3) -> Option<((u32, u32), f32)> {
        let projector = Projector::new(self);
        move |p| projector.project(p)
    }
}

/// The inverse of [`CameraRays::dir`] for a square window.
#[derive(Debug, Clone, Copy)]
struct Projector {
    eye: Vec3,
    right: Vec3,
    up: Vec3,
    forward: Vec3,
    tan: f32,
    half: f32,
}

impl Projector {
    fn new(view: &DepthView) -> Self {
        let (right, up, forward) = view.camera().basis();
        Projector {
            eye: view.eye,
            right,
            up,
            forward,
            // As CameraRays::new.
            tan: (view.fov_y.clamp(0.01, 179.0).to_radians() / 2.0).tan(),
            half: view.edge as f32 / 2.0,
        }
    }

    #[inline]
    fn project(&self, p: Vec3) -> Option<((u32, u32), f32)> {
        let v = p - self.eye;
        let z = v.dot(self.forward);
        if z <= 0.0 {
            return None;
        }
        // CameraRays::dir: sx = (2 px / w − 1)·tan, sy = (1 − 2 py / h)·tan.
        let px = (v.dot(self.right) / (z * self.tan) + 1.0) * self.half;
        let py = (1.0 - v.dot(self.up) / (z * self.tan)) * self.half;
        let edge = 2.0 * self.half;
        if !(px >= 0.0 && px < edge && py >= 0.0 && py < edge) {
            return None;
        }
        Some(((px as u32, py as u32), v.length()))
    }

    /// Whether a sphere (centre c, radius r) may meet the window's pyramid
    /// between distances near and far.
    #[inline]
    fn may_see(&self, c: Vec3, r: f32, near: f32, far: f32) -> bool {
        let v = c - self.eye;
        let dist = v.length();
        if dist - r > far || dist + r < near {
            return false;
        }
        let z = v.dot(self.forward);
        let x = v.dot(self.right);
        let y = v.dot(self.up);
        let norm = (1.0 + self.tan * self.tan).sqrt();
        let lim = r * norm;
        x - self.tan * z <= lim
            && -x - self.tan * z <= lim
            && y - self.tan * z <= lim
            && -y - self.tan * z <= lim
    }
}

/// The rule of 3.1.4.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Forgetting {
    /// Eliminate every n images (the thesis's typical 5).
    pub n: u32,
    /// Eliminate the voxels of X counted more than m times (typical 3).
    pub m: u32,
    /// A voxel stamped fewer than `min_age` frames ago is "recently seen"
    /// and not counted (1: only the current frame's stamps protect).
    pub min_age: u32,
    /// Eq. 3.1.16 with a tolerance: a voxel is counted when d_scene >
    /// d_voxel + margin (world units). Default: half the voxel's diagonal,
    /// so a voxel the surface passes through is not counted.
    pub margin: f32,
    /// The memory update range (`vision_range`'s third value): voxels
    /// farther from the eye are not tested.
    pub range: f32,
}

impl Forgetting {
    /// n = 5, m = 3, min_age = 1, margin = half the voxel diagonal, no
    /// update range beyond the view's far.
    pub fn thesis(voxel_edge: f64) -> Self {
        Forgetting {
            n: 5,
            m: 3,
            min_age: 1,
            margin: (voxel_edge * 3f64.sqrt() / 2.0) as f32,
            range: f32::INFINITY,
        }
    }
}

/// What one [`VisualMemory::forget`] did.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct ForgetStats {
    /// Voxels tested (inside the vision volume).
    pub tested: u64,
    /// Voxels counted in X this image.
    pub counted: u64,
    /// Whether this image ended a sequence of n (X was then emptied).
    pub eliminated: bool,
    /// Voxels removed from the memory.
    pub removed: u64,
}

/// An actor's visual memory: the octree, the auxiliary octree X, the rule.
#[derive(Debug, Clone)]
pub struct VisualMemory {
    tree: Octree,
    x: Octree,
    rule: Forgetting,
    /// Images since the last elimination.
    images: u32,
}

impl VisualMemory {
    /// An empty memory over `cube` (merging on) with the given rule.
    pub fn new(cube: Cube, rule: Forgetting) -> Self {
        VisualMemory {
            tree: Octree::new(cube, true),
            x: Octree::new(cube, false),
            rule,
            images: 0,
        }
    }

    /// An empty memory with the thesis's rule ([`Forgetting::thesis`]).
    pub fn with_thesis_rule(cube: Cube) -> Self {
        Self::new(cube, Forgetting::thesis(cube.voxel_edge))
    }

    pub fn rule(&self) -> Forgetting {
        self.rule
    }

    pub fn set_rule(&mut self, rule: Forgetting) {
        self.rule = rule;
    }

    /// The memory octree.
    pub fn octree(&self) -> &Octree {
        &self.tree
    }

    /// The auxiliary octree X: the voxels suspected to have disappeared,
    /// labelled with how often they were.
    pub fn suspects(&self) -> &Octree {
        &self.x
    }

    /// Occupied voxels at the finest level: `memory_voxels`.
    pub fn voxels(&self) -> u64 {
        self.tree.voxel_count()
    }

    /// Bytes held by the memory and X.
    pub fn memory_bytes(&self) -> usize {
        self.tree.memory_bytes() + self.x.memory_bytes()
    }

    /// Inserts world point p stamped with `frame`; false outside the cube.
    #[inline]
    pub fn insert(&mut self, p: [f64; 3], frame: u32) -> bool {
        self.tree.insert_point(p, frame)
    }

    /// Inserts the point every pixel of `view` hits, stamped with `frame`,
    /// but those of the pixels (row by row) `keep` refuses.
    pub fn insert_view(&mut self, view: &DepthView, frame: u32, keep: impl Fn(usize) -> bool) {
        let rays = view.rays();
        for y in 0..view.edge {
            for x in 0..view.edge {
                let i = (y * view.edge + x) as usize;
                let d = view.distances[i];
                if d.is_finite() && keep(i) {
                    let p = view.eye + Vec3::from(rays.dir(x as f32 + 0.5, y as f32 + 0.5)) * d;
                    self.tree.insert_point(p.as_dvec3().to_array(), frame);
                }
            }
        }
    }

    /// One image: [`VisualMemory::insert_view`] of every pixel, then
    /// [`VisualMemory::forget`].
    pub fn integrate(&mut self, view: &DepthView, frame: u32) -> ForgetStats {
        self.integrate_static(view, frame, |_| true)
    }

    /// One image, remembering only the pixels `keep` finds static (what
    /// the others show moves: it hides what lies behind it, so the
    /// forgetting still counts their distances).
    pub fn integrate_static(
        &mut self,
        view: &DepthView,
        frame: u32,
        keep: impl Fn(usize) -> bool,
    ) -> ForgetStats {
        self.insert_view(view, frame, keep);
        self.forget(view, frame)
    }

    /// The forgetting of 3.1.4 after the image `view` of `frame` was
    /// inserted: counts the voxels that should have been seen but were
    /// not in X, and every n images removes those counted more than m
    /// times and empties X.
    pub fn forget(&mut self, view: &DepthView, frame: u32) -> ForgetStats {
        let mut stats = ForgetStats::default();
        let proj = Projector::new(view);
        let cube = self.tree.cube();
        let e = cube.voxel_edge;
        let near = view.near;
        let far = view.far.min(self.rule.range);
        let rule = self.rule;
        let mut suspects: Vec<Voxel> = Vec::new();
        let centre = |v: Voxel, span: u32| {
            let h = f64::from(span) * 0.5;
            Vec3::new(
                (cube.min + (f64::from(v[0]) + h) * e) as f32,
                (cube.min + (f64::from(v[1]) + h) * e) as f32,
                (cube.min + (f64::from(v[2]) + h) * e) as f32,
            )
        };
        let half_diag = (e * 3f64.sqrt() / 2.0) as f32;
        let window = view.edge as usize;
        self.tree.for_each_voxel(
            |v, label| {
                let c = centre(v, 1);
                let Some(((px, py), d)) = proj.project(c) else {
                    return;
                };
                if d < near || d > far {
                    return;
                }
                stats.tested += 1;
                if frame.saturating_sub(label) < rule.min_age {
                    return;
                }
                let scene = view.distances[py as usize * window + px as usize];
                // Eq. 3.1.16 (a miss shows the background: infinity).
                if scene > d + rule.margin {
                    suspects.push(v);
                }
            },
            |v, span| {
                let r = half_diag * span as f32;
                proj.may_see(centre(v, span), r, near, far)
            },
        );
        stats.counted = suspects.len() as u64;
        for v in suspects {
            self.x.count(v);
        }
        self.images += 1;
        if self.images >= self.rule.n.max(1) {
            stats.eliminated = true;
            let m = self.rule.m;
            for (v, count) in self.x.occupied_voxels() {
                if count > m && self.tree.remove(v) {
                    stats.removed += 1;
                }
            }
            self.x.clear();
            self.images = 0;
        }
        stats
    }
}
