//! `manifest.json` assembled from the folder's records (DESIGN §4): the
//! stage that finishes a film writes it, and `verify` compares it with
//! the one on disk. Only outputs whose records match their inputs are
//! listed, so the manifest never vouches for a stale file.

use std::collections::BTreeMap;
use std::path::Path;

use super::digest::{sha256_bytes, sha256_file};
use super::folder::{unreadable, MAX_RECORD};
use super::manifest::Manifest;
use super::record::open;
use super::record::{self, DeriveRecord, FrameRecord, MuxRecord, SoundRecord};
use crate::error::Error;
use crate::film::names::{self, key, AMBIX_FILE, EVENTS_FILE, SOUNDTRACK_FILE};
use crate::film::names::{frame_path, snapshot_path, FRAMES_DIR, SCENE_DIR};
use crate::film::names::{frame_record_path, mp4_paths, DERIVE_RECORD, SOUNDS_DIR, SOUND_RECORD};
use crate::render::ImageFormat;
use crate::source::refused;

/// Assembles `manifest.json` from the records and writes it: the stage
/// that finishes the film (and any single-process stage) calls it.
pub fn finish(dir: &Path) -> Result<Manifest, Error> {
    let m = assemble(dir)?;
    m.write(dir)?;
    Ok(m)
}

/// The manifest the records describe: the derivation's inputs and files,
/// every frame whose record matches its snapshot, the soundtrack and the
/// MP4 when their records match their inputs. Frames rendered with
/// different settings are an error: a film is rendered with one.
pub fn assemble(dir: &Path) -> Result<Manifest, Error> {
    let rec = open(dir)?;
    let name = rec.inputs.name.clone();
    let mut m = Manifest::new(&rec);
    m.files.insert(
        DERIVE_RECORD.into(),
        hash_record(dir, Path::new(DERIVE_RECORD))?,
    );
    if dir.join(names::SETTINGS_FILE).exists() {
        let hash = hash_record(dir, Path::new(names::SETTINGS_FILE))?;
        m.files.insert(names::SETTINGS_FILE.into(), hash);
    }
    m.files.insert(EVENTS_FILE.into(), rec.events.clone());
    m.files.extend(rec.sounds.clone());
    m.files.extend(rec.actors.clone());
    m.files.extend(rec.tracks.clone());
    for (k, h) in rec.snapshots.iter().enumerate() {
        m.files.insert(key(&snapshot_path(k as u64)), h.clone());
    }
    let frames = valid_frames(dir, &rec)?;
    let mut settings: BTreeMap<&BTreeMap<String, String>, Vec<u64>> = BTreeMap::new();
    for (k, f) in &frames {
        let rel = frame_record_path(&name, *k);
        m.files.insert(key(&rel), hash_record(dir, &rel)?);
        for (file, h) in &f.outputs {
            m.files.insert(file.clone(), h.clone());
        }
        settings.entry(&f.render).or_default().push(*k);
    }
    if settings.len() > 1 {
        let groups: Vec<String> = settings
            .iter()
            .map(|(s, frames)| {
                let s: Vec<String> = s.iter().map(|(k, v)| format!("{k}={v}")).collect();
                format!("frames {} with {}", list(frames), s.join(" "))
            })
            .collect();
        return Err(Error::input(format!(
            "{}: the frames were rendered with different settings ({}); render them again with one: lmfilm render {} [options]",
            dir.display(),
            groups.join("; "),
            dir.display()
        )));
    }
    if let Some(s) = settings.keys().next() {
        for (k, v) in *s {
            m.options.insert(format!("render.{k}"), v.clone());
        }
    }
    if let Some(s) = record::read_made::<SoundRecord>(dir, Path::new(SOUND_RECORD))? {
        if s.events == rec.events {
            m.files.insert(
                SOUND_RECORD.into(),
                hash_record(dir, Path::new(SOUND_RECORD))?,
            );
            m.files.insert(SOUNDTRACK_FILE.into(), s.soundtrack.clone());
            if let Some(h) = &s.ambix {
                m.files.insert(AMBIX_FILE.into(), h.clone());
            }
            for (k, v) in s.sound {
                m.options.insert(format!("sound.{k}"), v);
            }
        }
    }
    let (mp4, mp4_record) = mp4_paths(&name);
    if let Some(x) = record::read_made::<MuxRecord>(dir, &mp4_record)? {
        let track = m.files.get(SOUNDTRACK_FILE).cloned();
        if x.frames == digest(&name, &frames) && x.soundtrack == track {
            m.files
                .insert(key(&mp4_record), hash_record(dir, &mp4_record)?);
            m.files.insert(key(&mp4), x.mp4.clone());
        }
    }
    Ok(m)
}

/// The sha256 of the folder's record `rel`, read as a regular file of at
/// most [`MAX_RECORD`] bytes; what cannot be read is named, with the way
/// out.
fn hash_record(dir: &Path, rel: &Path) -> Result<String, Error> {
    let path = dir.join(rel);
    sha256_file(&path, MAX_RECORD).map_err(|e| match refused(&e) {
        Some(_) => unreadable(dir, &key(rel), &e),
        None => Error::io(&path, e),
    })
}

/// Frame numbers as short ranges: `0-3, 7, 9-12`.
pub fn list(frames: &[u64]) -> String {
    let mut parts: Vec<String> = Vec::new();
    let mut i = 0;
    while i < frames.len() {
        let mut j = i;
        while j + 1 < frames.len() && frames[j + 1] == frames[j] + 1 {
            j += 1;
        }
        parts.push(if i == j {
            frames[i].to_string()
        } else {
            format!("{}-{}", frames[i], frames[j])
        });
        i = j + 1;
    }
    parts.join(", ")
}

/// Files in `frames/`, `scene/`, `sounds/` and `actors/` that no record accounts for, relative
/// to the folder: frames past the film's end or of another name, stray
/// and temporary files.
pub fn extra_files(dir: &Path, m: &Manifest) -> Vec<String> {
    let mut extra = Vec::new();
    for sub in [SCENE_DIR, FRAMES_DIR, SOUNDS_DIR] {
        let Ok(entries) = std::fs::read_dir(dir.join(sub)) else {
            continue;
        };
        let mut names: Vec<String> = entries
            .flatten()
            .map(|e| format!("{sub}/{}", e.file_name().to_string_lossy()))
            .filter(|rel| !m.files.contains_key(rel))
            .collect();
        names.sort();
        extra.extend(names);
    }
    extra.extend(super::actor_images::extra_files(dir, &m.files));
    extra
}

/// The frames whose record says they were rendered from the derivation's
/// snapshot (and, blurred toward it, the next one), with their records,
/// in frame order; an error names a record that is not a regular file
/// (a folder, a device, a pipe).
pub(super) fn valid_frames(
    dir: &Path,
    rec: &DeriveRecord,
) -> Result<Vec<(u64, FrameRecord)>, Error> {
    let mut valid = Vec::new();
    for (k, snap) in (0..rec.frame_count).zip(&rec.snapshots) {
        let rel = frame_record_path(&rec.inputs.name, k);
        let Some(f) = record::read_made::<FrameRecord>(dir, &rel)? else {
            continue;
        };
        // An inset must show the derivation's own actor image.
        let inset_ok = f
            .inset
            .as_ref()
            .is_none_or(|i| rec.actors.get(&i.file) == Some(&i.sha256));
        let next_ok = f
            .next_snapshot
            .as_ref()
            .is_none_or(|n| rec.snapshots.get(k as usize + 1) == Some(n));
        if f.snapshot == *snap && f.frame == k && inset_ok && next_ok {
            valid.push((k, f));
        }
    }
    Ok(valid)
}

/// The PNG frames an MP4 is made of, as one hash over their names and
/// hashes, in frame order.
pub(super) fn digest(name: &str, frames: &[(u64, FrameRecord)]) -> String {
    let mut list = String::new();
    for (k, f) in frames {
        let png = key(&frame_path(name, *k, ImageFormat::Png.extension()));
        if let Some(h) = f.outputs.get(&png) {
            list.push_str(&format!("{png} {h}\n"));
        }
    }
    sha256_bytes(list.as_bytes())
}
