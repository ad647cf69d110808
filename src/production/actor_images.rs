//! What people look at, in the film folder (docs/actors.md, docs/film.md):
//! each actor's vision window per frame, `actors/N/vision.NNNN.png`, and
//! its memory display, `actors/N/memory.NNNN.png`, written by the derive
//! stage and listed in its record; and the inset of one actor's windows
//! into the rendered frames (`--inset N`), taken from those files only,
//! so a render on another machine needs nothing but the folder.

use crate::film::names::ACTORS_DIR;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use rayon::prelude::*;

use super::digest::{sha256_bytes, sha256_file};
use super::folder::unreadable;
use super::record::{DeriveRecord, FileHash};
use crate::actors::live::Living;
use crate::actors::perception::display;
use crate::atomic::write_atomic;
use crate::error::Error;
use crate::film::names::frame_number;
use crate::film::names::key;
use crate::film::names::DERIVE_RECORD;
use crate::render::output::{self, linear8, Image};
use crate::source::{read_file, refused};

/// `actors/N/vision.NNNN.png`, relative to the output folder.
pub fn vision_path(actor: usize, frame: u64) -> PathBuf {
    actor_path(actor, "vision", frame)
}

/// `actors/N/memory.NNNN.png`, relative to the output folder.
pub fn memory_path(actor: usize, frame: u64) -> PathBuf {
    actor_path(actor, "memory", frame)
}

fn actor_path(actor: usize, what: &str, frame: u64) -> PathBuf {
    PathBuf::from(ACTORS_DIR)
        .join(actor.to_string())
        .join(format!("{what}.{}.png", frame_number(frame)))
}

/// Writes frame `frame`'s images of every actor (the vision window of
/// each that saw, the memory of each whose display is on) into `dir`,
/// adding their paths and hashes to `out`. The images are made in
/// parallel, one actor per task, into fixed slots: the bytes do not
/// depend on the thread count. An identical file stays as it is.
pub fn write(
    dir: &Path,
    frame: u64,
    living: &[Living],
    out: &mut BTreeMap<String, String>,
) -> Result<(), Error> {
    let made: Vec<Vec<(PathBuf, std::io::Result<Vec<u8>>)>> = living
        .par_iter()
        .map(|a| {
            let mut files = Vec::new();
            if let Some(w) = &a.window {
                let img = display::vision_image(w);
                files.push((vision_path(a.id, frame), output::encode_png(&img)));
            }
            if let Some(img) = display::memory_image(a, frame) {
                files.push((memory_path(a.id, frame), output::encode_png(&img)));
            }
            files
        })
        .collect();
    for (rel, bytes) in made.into_iter().flatten() {
        let path = dir.join(&rel);
        let bytes = bytes.map_err(|e| Error::io(&path, e))?;
        let hash = sha256_bytes(&bytes);
        if !sha256_file(&path, max_bytes()).is_ok_and(|h| h == hash) {
            if let Some(parent) = path.parent() {
                std::fs::create_dir_all(parent).map_err(|e| Error::io(parent, e))?;
            }
            write_atomic(&path, &bytes).map_err(|e| Error::io(&path, e))?;
        }
        out.insert(key(&rel), hash);
    }
    Ok(())
}

/// Removes, under `actors/`, every file the record does not list (the
/// images of frames past the film's end, of actors it no longer has, of
/// displays now off) and the folders left empty.
pub fn prune(dir: &Path, keep: &BTreeMap<String, String>) -> Result<(), Error> {
    let root = dir.join(ACTORS_DIR);
    let Ok(actors) = std::fs::read_dir(&root) else {
        return Ok(());
    };
    for a in actors.flatten() {
        let sub = a.path();
        if !sub.is_dir() {
            std::fs::remove_file(&sub).map_err(|e| Error::io(&sub, e))?;
            continue;
        }
        let name = a.file_name().to_string_lossy().into_owned();
        for f in std::fs::read_dir(&sub)
            .map_err(|e| Error::io(&sub, e))?
            .flatten()
        {
            let rel = format!("{ACTORS_DIR}/{name}/{}", f.file_name().to_string_lossy());
            if !keep.contains_key(&rel) && f.path().is_file() {
                std::fs::remove_file(f.path()).map_err(|e| Error::io(&f.path(), e))?;
            }
        }
        // Fails, harmlessly, when something is left in it.
        let _ = std::fs::remove_dir(&sub);
    }
    let _ = std::fs::remove_dir(&root);
    Ok(())
}

/// Files under `actors/` that `listed` does not hold, relative to the
/// folder, sorted.
pub fn extra_files(dir: &Path, listed: &BTreeMap<String, String>) -> Vec<String> {
    let mut extra = Vec::new();
    let Ok(actors) = std::fs::read_dir(dir.join(ACTORS_DIR)) else {
        return extra;
    };
    for a in actors.flatten() {
        let name = a.file_name().to_string_lossy().into_owned();
        match std::fs::read_dir(a.path()) {
            Ok(files) => extra.extend(
                files
                    .flatten()
                    .map(|f| format!("{ACTORS_DIR}/{name}/{}", f.file_name().to_string_lossy()))
                    .filter(|rel| !listed.contains_key(rel)),
            ),
            Err(_) => extra.push(format!("{ACTORS_DIR}/{name}")),
        }
    }
    extra.sort();
    extra
}

/// The vision image of `actor` at each frame, from the derive record:
/// the inset's source. An actor without a window at one of the frames is
/// an input error naming it, raised before anything is rendered.
pub fn inset_sources(
    dir: &Path,
    rec: &DeriveRecord,
    actor: usize,
    frames: &[u64],
) -> Result<BTreeMap<u64, FileHash>, Error> {
    let mut sources = BTreeMap::new();
    for &k in frames {
        let file = key(&vision_path(actor, k));
        let Some(sha256) = rec.actors.get(&file) else {
            return Err(Error::input(format!(
                "{}: --inset {actor}: actor {actor} has no vision window at frame {k} ({file} is not in {DERIVE_RECORD}); \
                 the scene must declare it (`iVisionWinSize {actor} EDGE COLOURS`) and derive again",
                dir.display()
            )));
        };
        sources.insert(
            k,
            FileHash {
                file,
                sha256: sha256.clone(),
            },
        );
    }
    Ok(sources)
}

/// The most bytes of an actor's image read: an image of the default
/// `--max-pixels` (a vision window is at most 1024² pixels, scaled near
/// 256 a side; a memory display is smaller).
fn max_bytes() -> u64 {
    output::max_file_bytes(crate::lsys::Limits::default().pixels)
}

/// Reads the inset's PNG (a regular file of at most its bound), checked
/// against its hash.
pub fn read_inset(dir: &Path, source: &FileHash) -> Result<image::RgbImage, Error> {
    let path = dir.join(&source.file);
    let bytes = read_file(&path, max_bytes()).map_err(|e| match refused(&e) {
        Some(_) => unreadable(dir, &source.file, &e),
        None => Error::input(format!(
            "{}: {e}; derive again: lmfilm derive SCENE.lm -o {}",
            path.display(),
            dir.display()
        )),
    })?;
    if sha256_bytes(&bytes) != source.sha256 {
        return Err(Error::input(format!(
            "{}: does not match {DERIVE_RECORD} (damaged or from another derivation); derive again: lmfilm derive SCENE.lm -o {}",
            path.display(),
            dir.display()
        )));
    }
    image::load_from_memory_with_format(&bytes, image::ImageFormat::Png)
        .map(|i| i.to_rgb8())
        .map_err(|e| Error::input(format!("{}: {e}", path.display())))
}

/// The inset's side for a frame `height` pixels high: a quarter of it.
pub fn inset_side(height: u32) -> u32 {
    (height / 4).max(1)
}

/// Puts `inset` into the top-left corner of `img`: scaled (nearest
/// neighbour) to [`inset_side`] pixels a side, inside a 1-pixel white
/// border, clipped to the frame. Only the colour changes; the layers
/// stay those of the scene.
pub fn compose(img: &mut Image, inset: &image::RgbImage) {
    let side = inset_side(img.height);
    let (iw, ih) = (inset.width().max(1), inset.height().max(1));
    for y in 0..(side + 2).min(img.height) {
        for x in 0..(side + 2).min(img.width) {
            let border = x == 0 || y == 0 || x == side + 1 || y == side + 1;
            let rgb = if border {
                [1.0; 3]
            } else {
                let sx = (u64::from(x - 1) * u64::from(iw) / u64::from(side)) as u32;
                let sy = (u64::from(y - 1) * u64::from(ih) / u64::from(side)) as u32;
                inset.get_pixel(sx, sy).0.map(linear8)
            };
            img.rgba[(y * img.width + x) as usize] = [rgb[0], rgb[1], rgb[2], 1.0];
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn srgb_round_trips_through_linear() {
        for s in 0..=255u8 {
            assert_eq!(output::srgb8(linear8(s)), s);
        }
    }

    #[test]
    fn actor_paths_follow_the_frame_numbers() {
        assert_eq!(
            key(&vision_path(3, 7)),
            "actors/3/vision.0007.png".to_string()
        );
        assert_eq!(
            key(&memory_path(0, 12345)),
            "actors/0/memory.12345.png".to_string()
        );
    }

    #[test]
    fn the_inset_touches_the_corner_only() {
        let mut img = Image::new(40, 20);
        let inset = image::RgbImage::from_pixel(4, 4, image::Rgb([255, 0, 0]));
        compose(&mut img, &inset);
        let side = inset_side(20) as usize;
        for (i, p) in img.rgba.iter().enumerate() {
            let (x, y) = (i % 40, i / 40);
            let inside = x < side + 2 && y < side + 2;
            assert_eq!(p[3] == 1.0, inside, "pixel {x},{y}");
        }
        assert_eq!(img.rgba[41], [1.0, 0.0, 0.0, 1.0]);
        assert_eq!(img.rgba[0], [1.0; 4]);
    }
}
