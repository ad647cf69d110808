//! Synthetic vision (thesis 3.1.1, 3.1.2): an actor's vision window cast
//! into the frame's [`Accel`], colour recognition both ways, the thing of
//! interest with its area (eq. 3.1.5–3.1.8) and position (eq. 3.1.9), and
//! the percepts of the vision sensor functions `?30`–`?39` (table B5).
//!
//! Self-contained: nothing here is wired into the frame loop yet. A
//! window is computed read-only from the BVH, rows in parallel on rayon
//! into fixed slots, so it is identical for any thread count (DESIGN §4).
//! The readings of the thesis chosen here are in docs/actors.md,
//! "Synthetic vision".

use glam::{Vec3, Vec3A};
use rayon::prelude::*;

use super::memory::DepthView;
use crate::render::accel::Hit;
use crate::render::Settings;
use crate::render::{shade, Accel};
use crate::scene::material::chromatic_distance;
use crate::scene::shape::OVERLAY;
use crate::scene::Camera;

/// What `?30` returns when the centre pixel sees nothing.
pub const NOTHING: f64 = 1e30;

/// Chromatic distance threshold of the thesis's tennis ball (3.1.2).
pub const THESIS_THRESHOLD: f32 = 0.05;

/// The materials of the things of interest of `interest` (table B6):
/// 0 the ball, 1 player 0, 2 player 1.
pub const INTEREST_MATERIALS: [u32; 3] = [10, 11, 12];

/// Where an actor looks from and how: its eye (`obs`), look-at point
/// (`lat`), view angle and clipping range (`vision_range` near far).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct View {
    pub eye: Vec3,
    pub look_at: Vec3,
    /// Full view angle across the square window, degrees.
    pub fov: f32,
    /// Clipping planes, as eye-space depths (along the view axis).
    pub near: f32,
    pub far: f32,
}

impl View {
    /// A view with the angle of the `fov` command, in tenths of a degree.
    pub fn new(eye: Vec3, look_at: Vec3, fov_tenths: i64, near: f32, far: f32) -> View {
        View {
            eye,
            look_at,
            fov: fov_tenths as f32 / 10.0,
            near,
            far,
        }
    }

    /// Unit (right, up, forward) of the eye, as the film's camera builds
    /// its basis (no twist).
    pub fn basis(&self) -> (Vec3, Vec3, Vec3) {
        Camera {
            eye: self.eye,
            look_at: self.look_at,
            twist: 0.0,
            fov_y: self.fov,
            aspect: 1.0,
            near: self.near,
            far: self.far,
            width: 1,
            height: 1,
            lens: Default::default(),
        }
        .basis()
    }

    /// tan(viewAngle / 2).
    pub fn tan_half(&self) -> f32 {
        (self.fov.clamp(0.01, 179.9).to_radians() / 2.0).tan()
    }
}

/// One pixel of a vision window.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pixel {
    /// Distance from the eye to the surface seen; infinite when nothing
    /// lies within the clipping range.
    pub distance: f32,
    /// Its eye-space depth z_eye (along the view axis); infinite likewise.
    pub depth: f32,
    /// World position of the surface seen (the inverse of eq. 3.1.1–
    /// 3.1.2); the eye when nothing is seen.
    pub position: Vec3,
    /// Object id, `u32::MAX` when nothing is seen.
    pub object: u32,
    /// Material number, `u32::MAX` when nothing is seen.
    pub material: u32,
    /// Flat vision colour (non-shading rendering, 3.1.2); black when
    /// nothing is seen.
    pub vision: Vec3,
    /// Shaded colour (the renderer's preview shading); the background
    /// when nothing is seen.
    pub shaded: Vec3,
}

impl Pixel {
    pub fn hit(&self) -> bool {
        self.object != u32::MAX
    }

    /// Whether it shows one of the things of interest (the ball, a
    /// player: [`INTEREST_MATERIALS`]), the things that move.
    pub fn shows_a_thing(&self) -> bool {
        INTEREST_MATERIALS.contains(&self.material)
    }
}

/// An edge × edge image seen from a [`View`]. Pixel (x, y) is column x
/// from the left, row y from the top, at index y·edge + x.
#[derive(Debug, Clone, PartialEq)]
pub struct Window {
    pub view: View,
    pub edge: u32,
    pub pixels: Vec<Pixel>,
    /// Distance seen along the view axis itself (the window's centre;
    /// with an even edge it is a corner of the four centre pixels), as
    /// [`Pixel::distance`].
    pub centre: f32,
}

/// The unnormalised direction through pixel position (px, py) of an
/// edge-pixel window: forward + sx·right + sy·up, so its component along
/// the view axis is 1.
fn ray(basis: (Vec3, Vec3, Vec3), tan: f32, edge: u32, px: f32, py: f32) -> Vec3 {
    let (right, up, forward) = basis;
    let e = edge as f32;
    let sx = (2.0 * px / e - 1.0) * tan;
    let sy = (1.0 - 2.0 * py / e) * tan;
    forward + sx * right + sy * up
}

/// What an actor's `M` branch drew this frame: its own body, which its
/// vision looks through (an eye inside its own sphere sees the room, not
/// the sphere's inside). Other actors, the camera and shadows see it.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct OwnBody {
    /// Identifiers of the symbols that drew its primitives, sorted.
    symbols: Vec<u64>,
    /// Object ids of the instances placed in its branch, sorted.
    objects: Vec<u32>,
}

impl OwnBody {
    /// Forgets the last frame's body (before a frame is interpreted).
    pub fn clear(&mut self) {
        self.symbols.clear();
        self.objects.clear();
    }

    /// A primitive drawn by symbol `id` in the branch.
    pub fn add_symbol(&mut self, id: u64) {
        self.symbols.push(id);
    }

    /// An instance placed in the branch.
    pub fn add_object(&mut self, object: u32) {
        self.objects.push(object);
    }

    /// Sorts what was added, once the frame is interpreted.
    pub fn seal(&mut self) {
        self.symbols.sort_unstable();
        self.symbols.dedup();
        self.objects.sort_unstable();
        self.objects.dedup();
    }

    /// Whether a hit is of the body (after [`seal`](Self::seal)).
    fn holds(&self, h: &Hit) -> bool {
        self.symbols.binary_search(&h.symbol).is_ok()
            || self.objects.binary_search(&h.object).is_ok()
    }
}

/// The closest hit an actor sees along a ray: what is drawn for the
/// viewer only ([`OVERLAY`]) and the actor's own body are looked through.
fn cast_seen(
    accel: &Accel,
    body: &OwnBody,
    eye: Vec3A,
    d: Vec3A,
    tmin: f32,
    tmax: f32,
) -> Option<Hit> {
    let mut from = tmin;
    loop {
        let h = accel.cast(eye, d, from, tmax)?;
        if h.symbol != OVERLAY && !body.holds(&h) {
            return Some(h);
        }
        // Just past it; an overlay in front of another is passed too.
        from = h.t + h.t.abs().max(1.0) * 1e-4;
    }
}

/// Sees: casts the window's rays (one through each pixel centre) into
/// `accel`, between the near and far planes, through the actor's own
/// `body`, and shades each hit as the preview renderer does. Rows run in
/// parallel on the current rayon pool.
pub fn see(accel: &Accel, body: &OwnBody, view: &View, edge: u32) -> Window {
    let edge = edge.max(1);
    let basis = view.basis();
    let tan = view.tan_half();
    let st = Settings {
        layers: false,
        ..Settings::preview(edge, edge)
    };
    let eye = Vec3A::from(view.eye);
    let rows: Vec<Vec<Pixel>> = (0..edge)
        .into_par_iter()
        .map(|y| {
            (0..edge)
                .map(|x| {
                    let r = ray(basis, tan, edge, x as f32 + 0.5, y as f32 + 0.5);
                    let len = r.length();
                    let d = Vec3A::from(r / len);
                    // Depth z along the axis is distance / len.
                    let (tmin, tmax) = (view.near.max(0.0) * len, view.far * len);
                    match cast_seen(accel, body, eye, d, tmin, tmax) {
                        Some(h) => Pixel {
                            distance: h.t,
                            depth: h.t / len,
                            position: Vec3::from(eye + h.t * d),
                            object: h.object,
                            material: h.material,
                            vision: h.vision,
                            shaded: shade::shade_hit(accel, &h, eye, d, &st, 0, 0),
                        },
                        None => Pixel {
                            distance: f32::INFINITY,
                            depth: f32::INFINITY,
                            position: view.eye,
                            object: u32::MAX,
                            material: u32::MAX,
                            vision: Vec3::ZERO,
                            shaded: shade::background(accel, d),
                        },
                    }
                })
                .collect()
        })
        .collect();
    let forward = Vec3A::from(basis.2);
    let centre = cast_seen(accel, body, eye, forward, view.near.max(0.0), view.far)
        .map_or(f32::INFINITY, |h| h.t);
    Window {
        view: *view,
        edge,
        pixels: rows.into_iter().flatten().collect(),
        centre,
    }
}

/// What an actor looks for (table B6 `interest`, `rgb_interest`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Interest {
    /// Pixels whose flat vision colour is exactly this (non-shading
    /// colour coding, 3.1.2).
    Flat(Vec3),
    /// Pixels whose shaded colour is within `threshold` chromatic distance
    /// (eq. 3.1.3–3.1.4) of `rgb`.
    Shaded { rgb: Vec3, threshold: f32 },
}

impl Interest {
    /// `interest 1 thing`: the flat vision colour of material 10, 11 or
    /// 12 of `accel`'s scene; None for another thing or a table without it.
    pub fn thing(accel: &Accel, thing: i64) -> Option<Interest> {
        let m = *INTEREST_MATERIALS.get(usize::try_from(thing).ok()?)?;
        let mat = accel.scene.materials.get(m as usize)?;
        Some(Interest::Flat(mat.vision))
    }

    /// `rgb_interest r g b 1`: components 0..255, recognised on shaded
    /// colours within `threshold` ([`THESIS_THRESHOLD`] in the thesis).
    pub fn rgb(rgb: [i64; 3], threshold: f32) -> Interest {
        Interest::Shaded {
            rgb: Vec3::new(rgb[0] as f32, rgb[1] as f32, rgb[2] as f32) / 255.0,
            threshold,
        }
    }

    /// Whether pixel `p` shows the thing.
    pub fn matches(&self, p: &Pixel) -> bool {
        p.hit()
            && match *self {
                Interest::Flat(c) => p.vision == c,
                Interest::Shaded { rgb, threshold } => {
                    p.shaded.max_element() > 0.0 && chromatic_distance(p.shaded, rgb) < threshold
                }
            }
    }
}

/// The thing of interest as a window shows it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Found {
    /// Its pixels.
    pub pixels: u32,
    /// Area by eq. 3.1.5–3.1.7: pixel count times the area of one pixel at
    /// the object's distance (the mean distance of its pixels).
    pub area: f32,
    /// Area by eq. 3.1.8: the sum of each pixel's area at its own depth.
    pub area_sum: f32,
    /// Position by eq. 3.1.9: the mean world position of its pixels.
    pub position: Vec3,
    /// Mean distance of its pixels (the `dist` of eq. 3.1.5).
    pub distance: f32,
}

impl Window {
    /// The window as the visual memory reads it: the same camera (no
    /// twist) and each pixel's distance.
    pub fn depth_view(&self) -> DepthView {
        DepthView {
            eye: self.view.eye,
            look_at: self.view.look_at,
            twist: 0.0,
            fov_y: self.view.fov,
            near: self.view.near,
            far: self.view.far,
            edge: self.edge,
            distances: self.pixels.iter().map(|p| p.distance).collect(),
        }
    }

    pub fn pixel(&self, x: u32, y: u32) -> &Pixel {
        &self.pixels[(y * self.edge + x) as usize]
    }

    /// Side of one pixel's square footprint at eye-space depth `z`
    /// (x / Nbr_pixel_per_row of eq. 3.1.5–3.1.6).
    pub fn footprint(&self, z: f32) -> f32 {
        self.view.tan_half() * z * 2.0 / self.edge as f32
    }

    /// The distinct flat vision colours the window shows, in order of first
    /// appearance (row by row), with their pixel counts; at most
    /// `max_colors` colours (`iVisionWinSize`), the others are not told
    /// apart and left out.
    pub fn flat_colours(&self, max_colors: usize) -> Vec<(Vec3, u32)> {
        let mut out: Vec<(Vec3, u32)> = Vec::new();
        for p in self.pixels.iter().filter(|p| p.hit()) {
            if let Some(e) = out.iter_mut().find(|e| e.0 == p.vision) {
                e.1 += 1;
            } else if out.len() < max_colors {
                out.push((p.vision, 1));
            }
        }
        out
    }

    /// Which pixels show the thing.
    pub fn mask(&self, interest: &Interest) -> Vec<bool> {
        self.pixels.iter().map(|p| interest.matches(p)).collect()
    }

    /// The thing of interest: None when no pixel shows it.
    pub fn find(&self, interest: &Interest) -> Option<Found> {
        let (mut n, mut dist, mut z2, mut pos) = (0u32, 0.0f64, 0.0f64, [0.0f64; 3]);
        for p in self.pixels.iter().filter(|p| interest.matches(p)) {
            n += 1;
            dist += f64::from(p.distance);
            z2 += f64::from(p.depth) * f64::from(p.depth);
            for (s, v) in pos.iter_mut().zip(p.position.to_array()) {
                *s += f64::from(v);
            }
        }
        if n == 0 {
            return None;
        }
        let nf = f64::from(n);
        let distance = (dist / nf) as f32;
        // (2·tan(viewAngle/2) / Nbr_pixel_per_row)², the area factor of z².
        let k = f64::from(self.footprint(1.0)).powi(2);
        Some(Found {
            pixels: n,
            area: (k * f64::from(distance).powi(2) * nf) as f32,
            area_sum: (k * z2) as f32,
            position: Vec3::new(
                (pos[0] / nf) as f32,
                (pos[1] / nf) as f32,
                (pos[2] / nf) as f32,
            ),
            distance,
        })
    }

    /// `?30`: the distance at the centre pixel, [`NOTHING`] when it sees
    /// nothing: the distance along the view axis (one more ray, so that
    /// an even edge, which has four centre pixels, reads it exactly too).
    pub fn centre_distance(&self) -> f64 {
        if self.centre.is_finite() {
            f64::from(self.centre)
        } else {
            NOTHING
        }
    }

    /// `?31`: −1 when the closest obstacle in front of the actor is left of
    /// the centre, +1 when it is right of it, 0 when there is none. In
    /// front means in the corridor the actor sweeps moving along its view
    /// axis: eye-space depth below `dist_coll`, and its world position
    /// within `size_actor`/2 of the axis across and up (or in a centre
    /// pixel's footprint, so that a zero size still looks ahead). Left and
    /// right are the sign of the closest obstacle pixel's offset along the
    /// eye's right axis (0 counts as right).
    pub fn obstacle_side(&self, size_actor: f32, dist_coll: f32) -> i32 {
        let (right, up, _) = self.view.basis();
        let half = size_actor.max(0.0) / 2.0;
        let mut best: Option<(f32, f32)> = None;
        for p in self
            .pixels
            .iter()
            .filter(|p| p.hit() && p.depth < dist_coll)
        {
            let rel = p.position - self.view.eye;
            let (sx, sy) = (rel.dot(right), rel.dot(up));
            let reach = half.max(self.footprint(p.depth) / 2.0);
            let closer = match best {
                None => true,
                Some((d, _)) => p.depth < d,
            };
            if sx.abs() <= reach && sy.abs() <= reach && closer {
                best = Some((p.depth, sx));
            }
        }
        match best {
            None => 0,
            Some((_, sx)) if sx < 0.0 => -1,
            Some(_) => 1,
        }
    }

    /// The percepts of the vision sensor functions.
    pub fn percepts(&self, body: &Body) -> Percepts {
        let truth = |f: bool| if f { 1.0 } else { -1.0 };
        let thing = body.interest.and_then(|i| self.find(&i));
        let rgb = body.rgb_interest.and_then(|i| self.find(&i));
        Percepts {
            centre_distance: self.centre_distance(),
            obstacle: f64::from(self.obstacle_side(body.size_actor, body.dist_coll)),
            interest_found: truth(thing.is_some()),
            rgb_interest_found: truth(rgb.is_some()),
            thing,
            rgb,
        }
    }
}

/// What of an actor's state the vision percepts read (table B6).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Body {
    /// `size_actor`.
    pub size_actor: f32,
    /// `dist_coll`.
    pub dist_coll: f32,
    /// `interest 1 thing` ([`Interest::thing`]); None when off.
    pub interest: Option<Interest>,
    /// `rgb_interest r g b 1` ([`Interest::rgb`]); None when off.
    pub rgb_interest: Option<Interest>,
}

/// The values of the vision sensor functions for one window.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Percepts {
    /// `?30`.
    pub centre_distance: f64,
    /// `?31`: −1, 0 or +1.
    pub obstacle: f64,
    /// `?36`: 1 found, −1 not.
    pub interest_found: f64,
    /// `?37` (and `?38`): 1 found, −1 not.
    pub rgb_interest_found: f64,
    /// The thing of interest, for `?38`'s local goal 1 and the trace.
    pub thing: Option<Found>,
    pub rgb: Option<Found>,
}

/// `?32` (look_at_goal): 1 when the scalar product of the unit look-at
/// direction and the unit direction to the goal exceeds `eps_look_at`,
/// −1 otherwise (also when the goal is at the eye).
pub fn looks_at_goal(eye: Vec3, look_at: Vec3, goal: Vec3, eps_look_at: f64) -> f64 {
    let a = (look_at - eye).normalize_or_zero();
    let b = (goal - eye).normalize_or_zero();
    if a != Vec3::ZERO && b != Vec3::ZERO && f64::from(a.dot(b)) > eps_look_at {
        1.0
    } else {
        -1.0
    }
}

/// `?33` and `?39` (arrived_at_goal): 1 when the eye is closer to the goal
/// than `eps_arrived`, −1 otherwise.
pub fn arrived_at_goal(eye: Vec3, goal: Vec3, eps_arrived: f64) -> f64 {
    if f64::from(eye.distance(goal)) < eps_arrived {
        1.0
    } else {
        -1.0
    }
}
