//! Wavefront OBJ export of a frame (for modelling tools) and import of OBJ
//! meshes into geometries.
//!
//! Export writes the expanded, tessellated frame ([`mesh::expand`]) with a
//! sibling `.mtl`. Numbers use a fixed `{:.6}` format and vertices are
//! numbered in order of first use, so the same scene gives the same bytes.

use std::collections::{BTreeMap, HashMap, HashSet};
use std::fmt::Write as _;
use std::io;
use std::path::Path;

use glam::Vec3;

use super::material::{self, Material};
use super::obj_parse::LineError;
use super::{mesh, Scene, Triangle};
use crate::source::read_file;

/// Writes the frame's triangles to `obj_path` and its materials to the
/// same path with extension `.mtl` (named by `mtllib`). One `usemtl` per
/// run of triangles with the same material; one flat normal per face.
/// Both files are written atomically (temporary file, then rename), the
/// MTL first so an OBJ never appears without its materials. Triangles
/// naming a material the scene lacks get a grey `missing_N` entry.
pub fn write_obj(scene: &Scene, obj_path: &Path) -> io::Result<()> {
    let invalid = || {
        io::Error::new(
            io::ErrorKind::InvalidInput,
            format!(
                "cannot write OBJ {}: needs a file name other than *.mtl",
                obj_path.display()
            ),
        )
    };
    let mtl_path = obj_path.with_extension("mtl");
    // Without a file name, or named `.mtl`, the two files cannot coexist.
    if obj_path.file_name().is_none() || mtl_path == obj_path {
        return Err(invalid());
    }
    let mtl_name = mtl_path.file_name().ok_or_else(invalid)?.to_string_lossy();

    let tris = mesh::expand(scene);
    let names = material_names(scene, &tris);
    crate::atomic::write_atomic(&mtl_path, mtl_text(scene, &names).as_bytes())?;
    crate::atomic::write_atomic(
        obj_path,
        obj_text(scene, &tris, &names, &mtl_name).as_bytes(),
    )
}

/// Largest OBJ or MTL file read: a bound on what a wrong path costs.
pub const MAX_MESH_BYTES: u64 = 4 << 30;

/// Loads the triangles and materials of an OBJ file (and of the MTL files
/// it names, looked up next to it), polygons fanned into triangles. The
/// geometry is parsed in parallel ([`super::obj_parse`]).
///
/// Materials are returned in MTL order; a triangle's material is
/// `material_base` + its index in the returned list. Faces without a usable
/// material (no `usemtl`, an unknown name, or a missing MTL file) get the
/// project's default grey, appended once at the end of the list — so a
/// file without any materials gives `material_base + 0` and one material.
/// Reflection is not part of MTL and comes back as 0. Only regular files
/// are read. Errors in either file are `file:line:column: message` with
/// the line and a caret; malformed input never panics.
pub fn read_obj(
    path: &Path,
    material_base: u32,
) -> Result<(Vec<Triangle>, Vec<Material>), MeshError> {
    let bytes = read_file(path, MAX_MESH_BYTES).map_err(|e| {
        MeshError::Read(format!("{}: cannot read the OBJ file: {e}", path.display()))
    })?;
    let (tris, materials) = parse_obj(&bytes, material_base, &|lib| {
        let lib_path = path.parent().unwrap_or(Path::new("")).join(lib);
        match read_file(&lib_path, MAX_MESH_BYTES) {
            Ok(b) => Ok(Some(b)),
            // A missing MTL leaves the faces grey rather than failing the import.
            Err(e) if e.kind() == io::ErrorKind::NotFound => Ok(None),
            Err(e) => Err(format!(
                "{}: cannot read the material library: {e}",
                lib_path.display()
            )),
        }
        .map(|b| b.map(|b| (lib_path.display().to_string(), b)))
    })
    .map_err(|e| {
        MeshError::Content(match e {
            ObjError::Obj(e) => e.locate(&path.display().to_string(), &bytes).to_string(),
            ObjError::Other(e) => e,
        })
    })?;
    Ok((tris, materials))
}

/// The folder part of the names of the built-in film's scenes
/// (`built-in:match.lm`): they name no file on disk.
pub const BUILT_IN_PREFIX: &str = "built-in:";

/// An imported mesh: its triangles and materials, as [`read_obj`] gives.
pub type ObjMesh = (Vec<Triangle>, Vec<Material>);

/// Why [`read_obj`] failed: the caller locates a file it cannot read at
/// the line that names it; problems inside are located in the file.
#[derive(Debug)]
pub enum MeshError {
    /// The OBJ file itself cannot be read (missing, a folder, a device):
    /// `path: cannot read the OBJ file: why`.
    Read(String),
    /// A problem in the OBJ or an MTL file, `file:line:column: message`
    /// with the line and a caret.
    Content(String),
}

impl std::fmt::Display for MeshError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            MeshError::Read(e) | MeshError::Content(e) => f.write_str(e),
        }
    }
}

/// Why [`parse_obj`] failed.
#[derive(Debug)]
pub enum ObjError {
    /// A problem in the OBJ text, at a line and column.
    Obj(LineError),
    /// A material library that cannot be read or parsed (already located).
    Other(String),
}

impl std::fmt::Display for ObjError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            ObjError::Obj(e) => e.fmt(f),
            ObjError::Other(e) => f.write_str(e),
        }
    }
}

/// A named MTL file's (display name, bytes), `None` when it is missing.
type MtlLoad<'a> = &'a dyn Fn(&str) -> Result<Option<(String, Vec<u8>)>, String>;

/// [`read_obj`] on OBJ bytes; `load_mtl` fetches the libraries it names
/// (the fuzz targets pass one that finds none or fixed bytes).
pub fn parse_obj(
    bytes: &[u8],
    material_base: u32,
    load_mtl: MtlLoad,
) -> Result<(Vec<Triangle>, Vec<Material>), ObjError> {
    let obj = super::obj_parse::parse(bytes).map_err(ObjError::Obj)?;
    let mut materials = Vec::new();
    for lib in &obj.libraries {
        if let Some((name, text)) = load_mtl(lib).map_err(ObjError::Other)? {
            let m = super::mtl::parse(&text)
                .map_err(|e| ObjError::Other(e.locate(&name, &text).to_string()))?;
            materials.extend(m);
        }
    }
    let known = materials.len();
    // `usemtl` slots to material indices; unknown names fall to grey.
    let slot: Vec<usize> = obj
        .materials
        .iter()
        .map(|n| materials.iter().position(|m| m.name == *n).unwrap_or(known))
        .collect();
    let base = |i: usize| material_base.saturating_add(u32::try_from(i).unwrap_or(u32::MAX));
    let mut needs_grey = false;
    let tris: Vec<Triangle> = obj
        .triangles
        .iter()
        .map(|&(v, m)| {
            let id = m.map_or(known, |m| slot[m as usize]);
            needs_grey |= id == known;
            Triangle {
                v: v.map(|i| obj.positions[i as usize]),
                material: base(id),
                symbol: 0,
            }
        })
        .collect();
    if needs_grey {
        materials.push(material::table().swap_remove(0));
    }
    Ok((tris, materials))
}

/// Unique MTL names by material number: index i of `scene.materials`
/// keeps its name with whitespace and control characters replaced by `_`
/// (MTL names are one word); empty or repeated names get `_i` appended.
/// Numbers used by triangles but absent from the scene are named
/// `missing_i` (a map, so a stray huge number costs one entry).
fn material_names(scene: &Scene, tris: &[Triangle]) -> BTreeMap<u32, String> {
    let mut wanted: BTreeMap<u32, String> = (0..)
        .zip(&scene.materials)
        .map(|(i, m)| (i, m.name.clone()))
        .collect();
    for t in tris {
        wanted
            .entry(t.material)
            .or_insert_with(|| format!("missing_{}", t.material));
    }
    let mut used = HashSet::new();
    for (i, name) in wanted.iter_mut() {
        let clean: String = name
            .chars()
            .map(|c| {
                if c.is_whitespace() || c.is_control() {
                    '_'
                } else {
                    c
                }
            })
            .collect();
        *name = if clean.is_empty() {
            format!("material_{i}")
        } else {
            clean
        };
        while !used.insert(name.clone()) {
            name.push_str(&format!("_{i}"));
        }
    }
    wanted
}

/// The MTL file: Ka Kd Ks Ns d Ni and an illumination model chosen from
/// the material's mirroring and transparency.
fn mtl_text(scene: &Scene, names: &BTreeMap<u32, String>) -> String {
    let grey = material::table().swap_remove(0);
    let mut s = String::from("# lmfilm materials\n");
    for (&i, name) in names {
        let m = scene.materials.get(i as usize).unwrap_or(&grey);
        let illum = match (m.reflect > 0.0, m.transmit > 0.0) {
            (_, true) if m.ior != 1.0 => 7,
            (_, true) => 4,
            (true, false) => 3,
            (false, false) => 2,
        };
        let _ = writeln!(s, "\nnewmtl {name}");
        let _ = writeln!(s, "Ka {}", vec3(m.ambient));
        let _ = writeln!(s, "Kd {}", vec3(m.diffuse));
        let _ = writeln!(s, "Ks {}", vec3(m.specular));
        let _ = writeln!(s, "Ns {}", num(m.shininess));
        let _ = writeln!(s, "d {}", num((1.0 - m.transmit).clamp(0.0, 1.0)));
        let _ = writeln!(s, "Ni {}", num(m.ior));
        let _ = writeln!(s, "illum {illum}");
    }
    s
}

/// The OBJ file: shared vertices and normals numbered in order of first
/// use, then the faces.
fn obj_text(
    scene: &Scene,
    tris: &[Triangle],
    names: &BTreeMap<u32, String>,
    mtllib: &str,
) -> String {
    let mut positions: Vec<Vec3> = Vec::new();
    let mut normals: Vec<Vec3> = Vec::new();
    let mut index: HashMap<[u32; 3], usize> = HashMap::new();
    let mut nindex: HashMap<[u32; 3], usize> = HashMap::new();
    let faces: Vec<([usize; 3], usize, u32)> = tris
        .iter()
        .map(|t| {
            let v = t.v.map(|p| id(&mut index, &mut positions, p));
            let n = id(&mut nindex, &mut normals, t.normal());
            (v, n, t.material)
        })
        .collect();

    let mut s = format!("# lmfilm frame {} time {}\n", scene.frame, scene.time);
    let _ = writeln!(s, "mtllib {mtllib}");
    let _ = writeln!(s, "o frame_{}", scene.frame);
    for p in &positions {
        let _ = writeln!(s, "v {}", vec3(*p));
    }
    for n in &normals {
        let _ = writeln!(s, "vn {}", vec3(*n));
    }
    let mut current = None;
    for (v, n, m) in faces {
        if current != Some(m) {
            current = Some(m);
            let name = names.get(&m).map_or("default", String::as_str);
            let _ = writeln!(s, "usemtl {name}");
        }
        let _ = writeln!(s, "f {}//{n} {}//{n} {}//{n}", v[0], v[1], v[2]);
    }
    s
}

/// 1-based OBJ number of `v` in `list`, added on first use. Keys are the
/// bits after +0.0, which folds −0 into 0 so equal points share a number.
fn id(map: &mut HashMap<[u32; 3], usize>, list: &mut Vec<Vec3>, v: Vec3) -> usize {
    let key = (v + Vec3::ZERO).to_array().map(f32::to_bits);
    *map.entry(key).or_insert_with(|| {
        list.push(v);
        list.len()
    })
}

/// Fixed-precision number; a negative zero prints as zero.
fn num(x: f32) -> String {
    let s = format!("{x:.6}");
    if s == "-0.000000" {
        "0.000000".into()
    } else {
        s
    }
}

fn vec3(v: Vec3) -> String {
    format!("{} {} {}", num(v.x), num(v.y), num(v.z))
}

/// The material libraries an OBJ file names (`mtllib` lines), read
/// without parsing its geometry: the film records their hashes as inputs.
/// An unreadable file names none (reading it for real reports the error).
pub fn mtl_libraries(path: &Path) -> Vec<String> {
    let Ok(bytes) = read_file(path, MAX_MESH_BYTES) else {
        return Vec::new();
    };
    bytes
        .split(|&b| b == b'\n')
        .filter_map(|line| line.trim_ascii().strip_prefix(b"mtllib"))
        .filter(|rest| rest.first().is_some_and(u8::is_ascii_whitespace))
        .flat_map(|rest| {
            String::from_utf8_lossy(rest)
                .split_ascii_whitespace()
                .map(str::to_string)
                .collect::<Vec<_>>()
        })
        .collect()
}
