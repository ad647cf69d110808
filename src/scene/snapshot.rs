//! Scene snapshots: one [`Scene`] per file, so `derive` runs the simulation
//! once and any number of `render` processes on any machines ray-trace the
//! frames (DESIGN §1, §5, `DIR/scene/NNNN.snap`).
//!
//! Layout (all integers little-endian):
//!
//! | bytes | content |
//! |---|---|
//! | 8 | magic `LMSNAP\0\0` |
//! | 4 | format version, u32 ([`VERSION`]) |
//! | 8 | payload length, u64 |
//! | n | payload: the postcard encoding of the [`Scene`] |
//! | 8 | FNV-1a 64 hash of the payload, u64 |
//!
//! postcard writes floats as their raw bits and has a single encoding per
//! value, so a round trip is bit-exact and the same scene always gives the
//! same bytes (DESIGN §4). The trailing hash catches files cut short or
//! damaged in transit between machines, which postcard alone might decode
//! into a plausible but wrong scene.

use std::fmt;
use std::io;
use std::path::{Path, PathBuf};

use glam::{Affine3A, Vec3};

use super::material::IOR_RANGE;
use super::{Geometry, LightKind, Material, Scene, Shape, ShapeKind, MAX_MAGNITUDE};
use crate::source::read_file;

/// First bytes of every snapshot, to reject other files early.
pub const MAGIC: [u8; 8] = *b"LMSNAP\0\0";

/// Format version written by this build; bump it whenever `Scene` or any
/// type inside it changes shape, since postcard is not self-describing.
pub const VERSION: u32 = 3;

/// Bytes before the payload: magic, version, payload length.
const HEADER_LEN: usize = 8 + 4 + 8;
/// Bytes after the payload: the hash.
const TRAILER_LEN: usize = 8;

/// Why a snapshot could not be read.
#[derive(Debug)]
pub enum SnapshotError {
    /// The file could not be opened or read.
    Io(io::Error),
    /// The bytes do not start with [`MAGIC`].
    NotASnapshot,
    /// The file has a format version this build cannot read.
    Version { found: u32, supported: u32 },
    /// The bytes end before the length the header announces.
    Truncated,
    /// The payload does not match its hash, or bytes follow the hash.
    Corrupt,
    /// The payload is intact but is not a `Scene` of this build (a build
    /// that changed `Scene` without bumping [`VERSION`]).
    Decode(String),
    /// The scene decodes but is not one `derive` writes: an index out of
    /// range, a number that is not finite or beyond
    /// [`super::MAX_MAGNITUDE`], a transform the renderer cannot invert
    /// (see [`validate`]).
    Invalid(String),
    /// Any of the above, in the named file (what [`read`] returns).
    File {
        path: PathBuf,
        error: Box<SnapshotError>,
    },
}

impl SnapshotError {
    /// The error itself, without the [`SnapshotError::File`] wrapper, so
    /// callers can match on the cause whether or not a file was involved.
    pub fn kind(&self) -> &SnapshotError {
        match self {
            SnapshotError::File { error, .. } => error.kind(),
            other => other,
        }
    }

    /// The file the error happened in, if it came from [`read`].
    pub fn path(&self) -> Option<&Path> {
        match self {
            SnapshotError::File { path, .. } => Some(path),
            _ => None,
        }
    }

    fn in_file(self, path: &Path) -> SnapshotError {
        SnapshotError::File {
            path: path.to_path_buf(),
            error: Box::new(self),
        }
    }
}

impl fmt::Display for SnapshotError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SnapshotError::Io(e) => write!(f, "cannot read scene snapshot: {e}"),
            SnapshotError::NotASnapshot => f.write_str(
                "not an lmfilm scene snapshot (bad magic bytes); \
                 expected a `.snap` file written by `lmfilm derive`",
            ),
            SnapshotError::Version { found, supported } if found > supported => write!(
                f,
                "scene snapshot has format version {found}, newer than the version \
                 {supported} this lmfilm reads; use the lmfilm that wrote it, or re-run \
                 `lmfilm derive` with this one"
            ),
            SnapshotError::Version { found, supported } => write!(
                f,
                "scene snapshot has old format version {found} (this lmfilm reads \
                 version {supported}); re-run `lmfilm derive` to regenerate it"
            ),
            SnapshotError::Truncated => f.write_str(
                "scene snapshot is truncated (an interrupted copy?); copy it again or \
                 re-run `lmfilm derive` to regenerate it",
            ),
            SnapshotError::Corrupt => f.write_str(
                "scene snapshot is corrupt (checksum mismatch or data after its end); \
                 copy it again or re-run `lmfilm derive` to regenerate it",
            ),
            SnapshotError::Decode(e) => write!(
                f,
                "scene snapshot does not decode as a scene of this lmfilm ({e}); it was \
                 probably written by an incompatible build: re-run `lmfilm derive`"
            ),
            SnapshotError::Invalid(e) => write!(
                f,
                "scene snapshot holds an impossible scene ({e}); it was damaged or \
                 edited: re-run `lmfilm derive` to regenerate it"
            ),
            SnapshotError::File { path, error } => write!(f, "{}: {error}", path.display()),
        }
    }
}

impl std::error::Error for SnapshotError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            SnapshotError::Io(e) => Some(e),
            SnapshotError::File { error, .. } => error.source(),
            _ => None,
        }
    }
}

impl From<io::Error> for SnapshotError {
    fn from(e: io::Error) -> Self {
        SnapshotError::Io(e)
    }
}

/// FNV-1a 64: tiny, dependency-free and enough to detect accidental damage
/// (this is not a defence against deliberate tampering).
fn fnv1a64(bytes: &[u8]) -> u64 {
    const OFFSET: u64 = 0xcbf2_9ce4_8422_2325;
    const PRIME: u64 = 0x0000_0100_0000_01b3;
    bytes
        .iter()
        .fold(OFFSET, |h, &b| (h ^ u64::from(b)).wrapping_mul(PRIME))
}

/// The snapshot bytes of `scene`; equal scenes (bit for bit) give equal bytes.
pub fn encode(scene: &Scene) -> Vec<u8> {
    // Serializing plain data into a Vec cannot fail: every type in `Scene`
    // is a struct, enum, sequence or primitive that postcard supports.
    let payload = postcard::to_stdvec(scene).expect("postcard encodes every Scene");
    let mut out = Vec::with_capacity(HEADER_LEN + payload.len() + TRAILER_LEN);
    out.extend_from_slice(&MAGIC);
    out.extend_from_slice(&VERSION.to_le_bytes());
    out.extend_from_slice(&(payload.len() as u64).to_le_bytes());
    out.extend_from_slice(&payload);
    out.extend_from_slice(&fnv1a64(&payload).to_le_bytes());
    out
}

/// Reads `N` bytes at `at`, or reports the file as truncated.
fn take<const N: usize>(bytes: &[u8], at: usize) -> Result<[u8; N], SnapshotError> {
    bytes
        .get(at..at + N)
        .and_then(|s| s.try_into().ok())
        .ok_or(SnapshotError::Truncated)
}

/// The scene in snapshot bytes, checked by [`validate`]: what `render`
/// reads. Never panics, whatever the bytes.
pub fn decode(bytes: &[u8]) -> Result<Scene, SnapshotError> {
    let scene = decode_unchecked(bytes)?;
    validate(&scene).map_err(SnapshotError::Invalid)?;
    Ok(scene)
}

/// The scene in snapshot bytes, bit for bit, without [`validate`] (a
/// matching hash only proves the bytes were not damaged in transit, not
/// that the scene is one the renderer can use). Checks magic, then version
/// (before anything else, so a future layout still reports its version),
/// then length and hash, and only then decodes. Never panics.
pub fn decode_unchecked(bytes: &[u8]) -> Result<Scene, SnapshotError> {
    let magic_seen = &bytes[..bytes.len().min(MAGIC.len())];
    if magic_seen != &MAGIC[..magic_seen.len()] {
        return Err(SnapshotError::NotASnapshot);
    }
    let _: [u8; 8] = take(bytes, 0)?;
    let found = u32::from_le_bytes(take(bytes, 8)?);
    if found != VERSION {
        return Err(SnapshotError::Version {
            found,
            supported: VERSION,
        });
    }
    let len = u64::from_le_bytes(take(bytes, 12)?);
    let rest = &bytes[HEADER_LEN..];
    // Compare in u64 so a huge announced length cannot overflow usize.
    let needed = len.checked_add(TRAILER_LEN as u64);
    match needed {
        Some(n) if (rest.len() as u64) < n => return Err(SnapshotError::Truncated),
        None => return Err(SnapshotError::Truncated),
        Some(n) if (rest.len() as u64) > n => return Err(SnapshotError::Corrupt),
        Some(_) => {}
    }
    // `len` fits in usize now: it is at most `rest.len()`.
    let (payload, trailer) = rest.split_at(len as usize);
    let stored = u64::from_le_bytes(take(trailer, 0)?);
    if stored != fnv1a64(payload) {
        return Err(SnapshotError::Corrupt);
    }
    let (scene, unused) = postcard::take_from_bytes::<Scene>(payload)
        .map_err(|e| SnapshotError::Decode(e.to_string()))?;
    if !unused.is_empty() {
        return Err(SnapshotError::Decode(format!(
            "{} unused bytes after the scene",
            unused.len()
        )));
    }
    Ok(scene)
}

/// Largest image side a snapshot's camera may ask for (the turtle's clamp).
pub const MAX_SIDE: u32 = 16384;

/// Checks that `scene` is one the renderer can use: every geometry and
/// material index in range, every number finite and within
/// [`MAX_MAGNITUDE`] — every instance's placed bounds too — every
/// transform of an instance or shape invertible, the camera's image size
/// in 1..=[`MAX_SIDE`]. The error says what is wrong and where.
pub fn validate(scene: &Scene) -> Result<(), String> {
    let c = &scene.camera;
    vec3(c.eye, "the camera position")?;
    vec3(c.look_at, "the camera's look-at point")?;
    for (x, what) in [
        (c.twist, "twist"),
        (c.fov_y, "field of view"),
        (c.aspect, "aspect ratio"),
        (c.near, "near distance"),
        (c.far, "far distance"),
        (c.lens.radius, "aperture radius"),
        (c.lens.focus, "focus distance"),
    ] {
        number(x, &format!("the camera's {what}"))?;
    }
    if c.lens.radius < 0.0 || c.lens.focus < 0.0 {
        return Err("the camera's aperture radius and focus distance must be ≥ 0".into());
    }
    for (side, what) in [(c.width, "width"), (c.height, "height")] {
        if !(1..=MAX_SIDE).contains(&side) {
            return Err(format!(
                "the camera's image {what} is {side}, not 1..={MAX_SIDE}"
            ));
        }
    }
    if !scene.time.is_finite() {
        return Err(format!("the frame's time is {}", scene.time));
    }
    vec3(scene.background, "the background colour")?;
    for (i, l) in scene.lights.iter().enumerate() {
        let what = format!("light {i}");
        vec3(l.position, &format!("the position of {what}"))?;
        vec3(l.color, &format!("the colour of {what}"))?;
        match l.kind {
            LightKind::Point => {}
            LightKind::Directional { direction } => {
                vec3(direction, &format!("the direction of {what}"))?
            }
            LightKind::Sphere { radius } => number(radius, &format!("the radius of {what}"))?,
        }
    }
    for (i, m) in scene.materials.iter().enumerate() {
        material(m).map_err(|e| format!("material {i} ({:?}): {e}", m.name))?;
    }
    for (g, geo) in scene.geometries.iter().enumerate() {
        for (k, s) in geo.shapes.iter().enumerate() {
            let what = format!("shape {k} of geometry {g}");
            material_index(s.material, scene, &what)?;
            transform(&s.transform, &what)?;
            match s.kind {
                ShapeKind::Capsule { length } => number(length, &format!("the length of {what}"))?,
                ShapeKind::Trunk { length, r0, r1 } => {
                    for x in [length, r0, r1] {
                        number(x, &format!("the size of {what}"))?;
                    }
                }
                ShapeKind::Box | ShapeKind::Sphere | ShapeKind::Cylinder => {}
            }
            for c in corners(local_box(s)) {
                vec3(
                    s.transform.transform_point3(c),
                    &format!("a corner of {what}"),
                )?;
            }
        }
        for (k, t) in geo.triangles.iter().enumerate() {
            material_index(t.material, scene, &format!("triangle {k} of geometry {g}"))?;
            for v in t.v {
                vec3(v, &format!("a corner of triangle {k} of geometry {g}"))?;
            }
        }
    }
    let bounds: Vec<Option<[Vec3; 2]>> = scene.geometries.iter().map(geometry_bounds).collect();
    for (i, inst) in scene.instances.iter().enumerate() {
        let Some(b) = bounds.get(inst.geometry as usize) else {
            return Err(format!(
                "instance {i} places geometry {}, but the scene has {} geometries",
                inst.geometry,
                scene.geometries.len()
            ));
        };
        transform(&inst.transform, &format!("the transform of instance {i}"))?;
        if let Some(b) = b {
            for c in corners(*b) {
                vec3(
                    inst.transform.transform_point3(c),
                    &format!("a corner of instance {i} (geometry {})", inst.geometry),
                )?;
            }
        }
    }
    Ok(())
}

/// The 8 corners of the box `[min, max]`.
fn corners([min, max]: [Vec3; 2]) -> [Vec3; 8] {
    std::array::from_fn(|k| {
        Vec3::new(
            if k & 1 == 0 { min.x } else { max.x },
            if k & 2 == 0 { min.y } else { max.y },
            if k & 4 == 0 { min.z } else { max.z },
        )
    })
}

/// A box around a unit shape in its local frame (the shape kinds' docs).
fn local_box(s: &Shape) -> [Vec3; 2] {
    let x = |a: f32, b: f32, r: f32| [Vec3::new(a, -r, -r), Vec3::new(b, r, r)];
    match s.kind {
        ShapeKind::Box => x(0.0, 1.0, 0.5),
        ShapeKind::Sphere => x(-1.0, 1.0, 1.0),
        ShapeKind::Cylinder => x(0.0, 1.0, 1.0),
        ShapeKind::Capsule { length } => x(-1.0, length.abs() + 1.0, 1.0),
        ShapeKind::Trunk { length, r0, r1 } => {
            let r = r0.abs().max(r1.abs());
            x(-r, length.abs() + r, r)
        }
    }
}

/// Bounds of a geometry's shapes and triangles in its own frame (`None`
/// when empty); the numbers are already checked finite and bounded.
fn geometry_bounds(g: &Geometry) -> Option<[Vec3; 2]> {
    let shapes = g
        .shapes
        .iter()
        .flat_map(|s| corners(local_box(s)).map(|c| s.transform.transform_point3(c)));
    let points = shapes.chain(g.triangles.iter().flat_map(|t| t.v));
    points.fold(None, |b, p| match b {
        None => Some([p, p]),
        Some([lo, hi]) => Some([lo.min(p), hi.max(p)]),
    })
}

fn material_index(m: u32, scene: &Scene, what: &str) -> Result<(), String> {
    if (m as usize) < scene.materials.len() {
        Ok(())
    } else {
        Err(format!(
            "{what} has material {m}, but the scene has {} materials",
            scene.materials.len()
        ))
    }
}

/// A finite number within [`MAX_MAGNITUDE`].
fn number(x: f32, what: &str) -> Result<(), String> {
    if x.is_finite() && x.abs() <= MAX_MAGNITUDE {
        Ok(())
    } else {
        Err(format!(
            "{what} is {x}, not a finite number within ±{MAX_MAGNITUDE:e}"
        ))
    }
}

fn vec3(v: Vec3, what: &str) -> Result<(), String> {
    v.to_array().iter().try_for_each(|&x| number(x, what))
}

/// Entries within [`MAX_MAGNITUDE`], and an inverse whose entries are
/// too: the renderer moves rays into the local frame with the inverse, and
/// a nearly singular transform (an axis of 6e-39) gave it rays of 1e38
/// whose traversal indexed out of bounds (accel.rs:58).
fn transform(m: &Affine3A, what: &str) -> Result<(), String> {
    m.to_cols_array()
        .iter()
        .try_for_each(|&x| number(x, what))?;
    let det = m.matrix3.determinant();
    let inverse_bounded = m
        .inverse()
        .to_cols_array()
        .iter()
        .all(|x| x.is_finite() && x.abs() <= MAX_MAGNITUDE);
    if det == 0.0 || !det.is_finite() || !inverse_bounded {
        return Err(format!(
            "{what} cannot be inverted in f32 (determinant {det:e}, nearly flat)"
        ));
    }
    Ok(())
}

/// Colours and the Phong exponent bounded; mirroring and transmission
/// fractions in 0..=1; an index of refraction in [`IOR_RANGE`] (an index
/// of 0 made the refracted ray of a glass surface reach `accel.rs:58`).
fn material(m: &Material) -> Result<(), String> {
    for (v, what) in [
        (m.ambient, "ambient"),
        (m.diffuse, "diffuse"),
        (m.specular, "specular"),
        (m.vision, "vision colour"),
    ] {
        vec3(v, what)?;
    }
    number(m.shininess, "shininess")?;
    for (x, what) in [(m.reflect, "reflection"), (m.transmit, "transmission")] {
        if !(0.0..=1.0).contains(&x) {
            return Err(format!("{what} is {x}, not a fraction 0..=1"));
        }
    }
    if !IOR_RANGE.contains(&m.ior) {
        return Err(format!(
            "index of refraction is {}, not {}..={}",
            m.ior,
            IOR_RANGE.start(),
            IOR_RANGE.end()
        ));
    }
    Ok(())
}

/// Writes the snapshot of `scene` to `path` atomically, so a killed run
/// never leaves a half-written snapshot that a `render` process could pick
/// up. Errors name the file.
pub fn write(scene: &Scene, path: &Path) -> io::Result<()> {
    crate::atomic::write_atomic(path, &encode(scene))
}

/// Largest snapshot read: a bound on what a wrong path costs.
pub const MAX_SNAPSHOT_BYTES: u64 = 16 << 30;

/// Reads the snapshot at `path` (a regular file only); every error names
/// the file.
pub fn read(path: &Path) -> Result<Scene, SnapshotError> {
    let bytes =
        read_file(path, MAX_SNAPSHOT_BYTES).map_err(|e| SnapshotError::Io(e).in_file(path))?;
    decode(&bytes).map_err(|e| e.in_file(path))
}
