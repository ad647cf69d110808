//! Wavefront OBJ geometry, parsed in parallel: the text is cut into
//! chunks at line ends, rayon parses the chunks, and one sequential pass
//! resolves what depends on earlier chunks (vertex numbers, the current
//! `usemtl`). Only what a renderer of flat triangles needs is read —
//! `v`, `f`, `usemtl`, `mtllib`; normals, texture coordinates, groups,
//! lines and points are skipped. The result does not depend on the
//! thread count: chunks are cut by size and joined in order.

use std::borrow::Cow;
use std::fmt;

use glam::Vec3;
use rayon::prelude::*;

use super::MAX_COORDINATE;

use crate::source::Diagnostic;

/// Largest magnitude of a coordinate or material value: that of a scene.
pub const MAX_VALUE: f32 = super::MAX_MAGNITUDE;

/// A problem at a line (from 1) and byte column (from 0) of the text.
#[derive(Debug, Clone, PartialEq)]
pub struct LineError {
    pub line: u32,
    pub column: u32,
    pub message: String,
}

impl LineError {
    /// The error as `file:line:column: message` with the line and a caret.
    pub fn locate(&self, file: &str, text: &[u8]) -> Diagnostic {
        let raw = text
            .split(|&b| b == b'\n')
            .nth(self.line.saturating_sub(1) as usize)
            .unwrap_or_default();
        let line = String::from_utf8_lossy(raw)
            .trim_end_matches('\r')
            .to_string();
        let mut at = (self.column as usize).min(line.len());
        while !line.is_char_boundary(at) {
            at -= 1;
        }
        Diagnostic {
            file: file.to_string(),
            line: self.line as usize,
            column: line[..at].chars().count() + 1,
            message: self.message.clone(),
            source_line: line,
        }
    }
}

impl fmt::Display for LineError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "line {}: {}", self.line, self.message)
    }
}

/// Bytes per chunk: large enough that the per-chunk work is negligible.
const CHUNK: usize = 1 << 20;

/// The geometry of an OBJ file.
#[derive(Debug, Default, PartialEq)]
pub struct Obj {
    pub positions: Vec<Vec3>,
    /// Triangles as 0-based position indices (polygons fanned from their
    /// first vertex), each with its `usemtl` slot.
    pub triangles: Vec<([u32; 3], Option<u32>)>,
    /// Names given to `usemtl`, by slot.
    pub materials: Vec<String>,
    /// Files named by `mtllib`, in order.
    pub libraries: Vec<String>,
}

/// A face corner as written: 1-based, or negative counting back from the
/// vertices seen so far (`seen`, within the chunk).
#[derive(Clone, Copy)]
struct Corner {
    index: i32,
    seen: u32,
    /// Byte column of the corner in its line, for errors.
    column: u32,
}

#[derive(Default)]
struct Chunk {
    lines: u32,
    positions: Vec<Vec3>,
    /// Corners of each polygon, flattened, with (start, line, material
    /// name index in `names` or inherited).
    corners: Vec<Corner>,
    polygons: Vec<(u32, u32, Option<u32>)>,
    names: Vec<String>,
    libraries: Vec<String>,
    /// A `usemtl` after the chunk's last face: it applies to the next.
    trailing: Option<u32>,
    /// The first problem, its line counted in the chunk (from 1).
    error: Option<LineError>,
}

/// Parses `text`; errors name the line and column.
pub fn parse(text: &[u8]) -> Result<Obj, LineError> {
    let chunks: Vec<&[u8]> = split(text);
    let parsed: Vec<Chunk> = chunks.par_iter().map(|c| parse_chunk(c)).collect();
    let mut obj = Obj::default();
    let (mut line0, mut current) = (0u32, None::<u32>);
    for c in parsed {
        if let Some(e) = c.error {
            return Err(LineError {
                line: line0 + e.line,
                ..e
            });
        }
        let base = obj.positions.len() as i64;
        obj.positions.extend_from_slice(&c.positions);
        obj.libraries.extend(c.libraries);
        // Chunk-local material names to global slots.
        let slots: Vec<u32> = c
            .names
            .iter()
            .map(|n| match obj.materials.iter().position(|m| m == n) {
                Some(i) => i as u32,
                None => {
                    obj.materials.push(n.clone());
                    obj.materials.len() as u32 - 1
                }
            })
            .collect();
        let count = obj.positions.len() as i64;
        let mut idx = Vec::new();
        for (k, &(start, line, name)) in c.polygons.iter().enumerate() {
            let end = c
                .polygons
                .get(k + 1)
                .map_or(c.corners.len(), |p| p.0 as usize);
            if let Some(n) = name {
                current = Some(slots[n as usize]);
            }
            idx.clear();
            for corner in &c.corners[start as usize..end] {
                let written = i64::from(corner.index);
                let i = if written > 0 {
                    written - 1
                } else {
                    base + i64::from(corner.seen) + written
                };
                if !(0..count).contains(&i) {
                    return Err(LineError {
                        line: line0 + line,
                        column: corner.column,
                        message: format!(
                            "vertex {} does not exist ({} vertices so far)",
                            corner.index,
                            if written > 0 {
                                count
                            } else {
                                base + i64::from(corner.seen)
                            }
                        ),
                    });
                }
                idx.push(i as u32);
            }
            for j in 1..idx.len() - 1 {
                obj.triangles.push(([idx[0], idx[j], idx[j + 1]], current));
            }
        }
        if let Some(n) = c.trailing {
            current = Some(slots[n as usize]);
        }
        line0 += c.lines;
    }
    Ok(obj)
}

/// Cuts `text` into chunks of about [`CHUNK`] bytes that end at a line
/// end (not a continued one, `\` before the newline).
fn split(text: &[u8]) -> Vec<&[u8]> {
    let mut out = Vec::new();
    let mut rest = text;
    while rest.len() > CHUNK {
        let mut cut = CHUNK;
        while cut < rest.len() && !(rest[cut] == b'\n' && rest[cut - 1] != b'\\') {
            cut += 1;
        }
        let (a, b) = rest.split_at((cut + 1).min(rest.len()));
        out.push(a);
        rest = b;
    }
    out.push(rest);
    out
}

fn parse_chunk(text: &[u8]) -> Chunk {
    let mut c = Chunk::default();
    let mut pending = None;
    let mut joined = String::new();
    let mut number = 0u32;
    let mut lines = text.split(|&b| b == b'\n');
    while let Some(raw) = lines.next() {
        number += 1;
        let first = number;
        // Valid UTF-8 (nearly always) is borrowed as is: checking it is
        // much cheaper than the lossy conversion's walk.
        let mut line = match std::str::from_utf8(raw) {
            Ok(s) => Cow::Borrowed(s),
            Err(_) => String::from_utf8_lossy(raw),
        };
        // A trailing backslash continues the line.
        if line.trim_end().ends_with('\\') {
            joined.clear();
            joined.push_str(line.trim_end().trim_end_matches('\\'));
            for next in lines.by_ref() {
                number += 1;
                let next = String::from_utf8_lossy(next);
                let more = next.trim_end().ends_with('\\');
                joined.push(' ');
                joined.push_str(next.trim_end().trim_end_matches('\\'));
                if !more {
                    break;
                }
            }
            line = joined.clone().into();
        }
        if let Err((column, message)) = parse_line(&line, &mut c, &mut pending, first) {
            c.error = Some(LineError {
                line: first,
                column: column as u32,
                message,
            });
            return c;
        }
    }
    c.trailing = pending;
    // A final newline leaves an empty last piece: not a line.
    c.lines = number - u32::from(text.last() == Some(&b'\n'));
    c
}

/// Reads one line into the chunk; errors carry the byte column at fault.
fn parse_line(
    line: &str,
    c: &mut Chunk,
    material: &mut Option<u32>,
    number: u32,
) -> Result<(), (usize, String)> {
    // Up to a comment ('#' is one byte: a char boundary). A byte scan:
    // a `str` pattern search costs several times as much on short lines.
    let line = &line[..byte_position(line, b'#')];
    let column = |w: &str| w.as_ptr() as usize - line.as_ptr() as usize;
    let mut words = line.split_ascii_whitespace();
    match words.next() {
        Some("v") => {
            let mut p = [0f32; 3];
            for (k, v) in p.iter_mut().enumerate() {
                let w = words.next().ok_or((
                    line.trim_end().len(),
                    "a vertex needs three coordinates: v x y z".to_string(),
                ))?;
                *v = w
                    .parse::<f32>()
                    .ok()
                    .filter(|v| v.is_finite())
                    .ok_or_else(|| {
                        (
                            column(w),
                            format!("coordinate {} is not a finite number: '{w}'", k + 1),
                        )
                    })?;
                if v.abs() > MAX_COORDINATE {
                    return Err((
                        column(w),
                        format!(
                            "coordinate {} is beyond ±{MAX_COORDINATE:e}, the largest the renderer takes: '{w}'",
                            k + 1
                        ),
                    ));
                }
            }
            c.positions.push(Vec3::from(p));
        }
        Some("f") => {
            let start = c.corners.len() as u32;
            for w in words {
                let first = &w[..byte_position(w, b'/')];
                let index: i32 = first.parse().ok().filter(|&i| i != 0).ok_or_else(|| {
                    (
                        column(w),
                        format!("'{w}' is not a vertex number (1, 2, … or -1, -2, …)"),
                    )
                })?;
                c.corners.push(Corner {
                    index,
                    seen: c.positions.len() as u32,
                    column: column(w) as u32,
                });
            }
            if c.corners.len() - (start as usize) < 3 {
                return Err((
                    line.trim_end().len(),
                    "a face needs at least three vertices".into(),
                ));
            }
            c.polygons.push((start, number, material.take()));
        }
        Some("usemtl") => {
            let name = words.collect::<Vec<_>>().join(" ");
            let i = match c.names.iter().position(|n| *n == name) {
                Some(i) => i,
                None => {
                    c.names.push(name);
                    c.names.len() - 1
                }
            };
            *material = Some(i as u32);
        }
        // The rest of the line: file names may hold spaces.
        Some("mtllib") => c.libraries.push(words.collect::<Vec<_>>().join(" ")),
        _ => {}
    }
    Ok(())
}

/// Where the ASCII byte `b` first occurs in `s`, or its length.
fn byte_position(s: &str, b: u8) -> usize {
    s.bytes().position(|c| c == b).unwrap_or(s.len())
}
