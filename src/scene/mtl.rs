//! Wavefront MTL materials: the statements a renderer of flat, untextured
//! surfaces uses (`newmtl`, `Ka`, `Kd`, `Ks`, `Ns`, `Ni`, `d`, `Tr`); the
//! others (`illum`, `Ke`, `map_*`, …) are skipped. Our own reader rather
//! than `tobj`'s, which panics on a colour with two components: every
//! problem is a located error, never a panic.

use glam::Vec3;

use super::material::{Material, IOR_RANGE};
use super::obj_parse::{LineError, MAX_VALUE};

/// The fields a statement may set; unset ones take neutral values.
#[derive(Default)]
struct Entry {
    name: String,
    ambient: Option<Vec3>,
    diffuse: Option<Vec3>,
    specular: Option<Vec3>,
    shininess: Option<f32>,
    ior: Option<f32>,
    dissolve: Option<f32>,
}

impl Entry {
    /// As a scene material: grey diffuse 0.75, ambient a fifth of the
    /// diffuse, no specular, opaque, no refraction, no mirroring (MTL has
    /// none); the vision colour is the diffuse.
    fn material(self) -> Material {
        let diffuse = self.diffuse.unwrap_or(Vec3::splat(0.75));
        Material {
            name: self.name,
            ambient: self.ambient.unwrap_or(diffuse * 0.2),
            diffuse,
            specular: self.specular.unwrap_or(Vec3::ZERO),
            shininess: self.shininess.unwrap_or(1.0),
            reflect: 0.0,
            transmit: (1.0 - self.dissolve.unwrap_or(1.0)).clamp(0.0, 1.0),
            ior: self.ior.unwrap_or(1.0),
            vision: diffuse,
            texture: None,
        }
    }
}

/// The materials of MTL `text`, in file order. Errors carry the line
/// (from 1) and the byte column in it of the word at fault.
pub fn parse(text: &[u8]) -> Result<Vec<Material>, LineError> {
    let mut out: Vec<Entry> = Vec::new();
    for (i, raw) in text.split(|&b| b == b'\n').enumerate() {
        let line = String::from_utf8_lossy(raw);
        let err = |column: usize, message: String| LineError {
            line: i as u32 + 1,
            column: column as u32,
            message,
        };
        let code = line.split('#').next().unwrap_or("");
        let mut words = code
            .split_ascii_whitespace()
            .map(|w| (w.as_ptr() as usize - code.as_ptr() as usize, w));
        let Some((at, key)) = words.next() else {
            continue;
        };
        if key == "newmtl" {
            let name = code[at + key.len()..].trim().to_string();
            if name.is_empty() {
                return Err(err(at, "`newmtl` needs a material name".into()));
            }
            out.push(Entry {
                name,
                ..Entry::default()
            });
            continue;
        }
        if !matches!(key, "Ka" | "Kd" | "Ks" | "Ns" | "Ni" | "d" | "Tr") {
            continue;
        }
        let Some(m) = out.last_mut() else {
            return Err(err(at, format!("`{key}` before the first `newmtl`")));
        };
        let mut values = Vec::new();
        for (wat, w) in words {
            let v = w
                .parse::<f32>()
                .ok()
                .filter(|v| v.is_finite() && v.abs() <= MAX_VALUE)
                .ok_or_else(|| {
                    err(
                        wat,
                        format!("`{w}` is not a finite number of at most {MAX_VALUE:e}"),
                    )
                })?;
            values.push(v);
        }
        let end = code.trim_end().len();
        match key {
            "Ka" | "Kd" | "Ks" => {
                // `Kd r` is grey r; `Kd r g b` a colour (the MTL spec).
                let c = match values[..] {
                    [r] => Vec3::splat(r),
                    [r, g, b] => Vec3::new(r, g, b),
                    _ => {
                        return Err(err(
                            end,
                            format!(
                                "`{key}` takes 1 or 3 numbers (r g b), found {}",
                                values.len()
                            ),
                        ))
                    }
                };
                let slot = match key {
                    "Ka" => &mut m.ambient,
                    "Kd" => &mut m.diffuse,
                    _ => &mut m.specular,
                };
                *slot = Some(c);
            }
            _ => {
                let [v] = values[..] else {
                    return Err(err(
                        end,
                        format!("`{key}` takes one number, found {}", values.len()),
                    ));
                };
                match key {
                    "Ns" => m.shininess = Some(v),
                    "Ni" if !IOR_RANGE.contains(&v) => {
                        return Err(err(
                            end,
                            format!(
                                "`Ni` (index of refraction) must be {}..={}, found {v}",
                                IOR_RANGE.start(),
                                IOR_RANGE.end()
                            ),
                        ))
                    }
                    "Ni" => m.ior = Some(v),
                    "d" => m.dissolve = Some(v),
                    _ => m.dissolve = Some(1.0 - v),
                }
            }
        }
    }
    Ok(out.into_iter().map(Entry::material).collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_colours_and_numbers() {
        let m = parse(b"newmtl a\nKd 0.2 0.7 0.2\nKs 0.5\nNs 20\nTr 0.25\nillum 2\nmap_Kd x.png\n")
            .unwrap();
        assert_eq!(m.len(), 1);
        assert_eq!(m[0].diffuse, Vec3::new(0.2, 0.7, 0.2));
        assert_eq!(m[0].specular, Vec3::splat(0.5));
        assert_eq!((m[0].shininess, m[0].transmit), (20.0, 0.25));
    }

    #[test]
    fn two_component_colour_is_a_located_error() {
        let e = parse(b"newmtl m\nKd 0.2 0.7\n").unwrap_err();
        assert_eq!((e.line, e.column), (2, 10));
        assert!(e.message.contains("1 or 3 numbers"), "{}", e.message);
        let e = parse(b"newmtl m\nNs nan\n").unwrap_err();
        assert_eq!((e.line, e.column), (2, 3));
        let e = parse(b"newmtl m\nd 0.5\nNi 0\n").unwrap_err();
        assert_eq!(e.line, 3);
        assert!(e.message.contains("must be 0.001..=10"), "{}", e.message);
    }
}
