//! The film driver's support modules: frame ranges, shards, file names,
//! the manifest with `verify`, and the video.

use crate::mp4;

use crate::common;

use std::fs;
use std::path::{Path, PathBuf};

use lmfilm::film::names::{frame_number, frame_path, snapshot_path};
use lmfilm::lsys::options::rs_switch;

use lmfilm::film::names::MANIFEST_FILE;
use lmfilm::lsys::options::OptionItem;
use lmfilm::production::digest::{sha256_bytes, sha256_file};
use lmfilm::production::frames::{FrameRange, FrameSelection, RangeError, Shard, ShardError};
use lmfilm::production::manifest::{Error, Manifest};
use lmfilm::production::mux::{mux, FramePng, FrameRate, MuxError};
use lmfilm::production::timings::Timings;
use lmfilm::production::verify::verify;
use lmfilm::production::video_groups::{GroupTap, TappedFrame};

fn temp_dir(name: &str) -> PathBuf {
    common::fresh_dir("film-support", name)
}

fn range(text: &str) -> FrameRange {
    text.parse().unwrap()
}

// ---- frame ranges ----

#[test]
fn range_forms() {
    let r = |start, end| FrameRange { start, end };
    assert_eq!(range("10..20"), r(10, Some(20)));
    assert_eq!(range("10..=20"), r(10, Some(21)));
    assert_eq!(range("10.."), r(10, None));
    assert_eq!(range("..5"), r(0, Some(5)));
    assert_eq!(range("..=5"), r(0, Some(6)));
    assert_eq!(range(".."), r(0, None));
    assert_eq!(range("7"), r(7, Some(8)));
    assert_eq!(range(" 3 .. 9 "), r(3, Some(9)));
    assert_eq!(range("10..20").to_string(), "10..20");
    assert_eq!(range("10..").to_string(), "10..");
}

#[test]
fn range_end_is_exclusive_and_clipped_to_the_film() {
    let r = range("2..5");
    assert!(!r.contains(1) && r.contains(2) && r.contains(4) && !r.contains(5));
    assert_eq!(r.within(100), 2..5);
    assert_eq!(r.within(4), 2..4);
    assert_eq!(r.within(1), 1..1);
    assert_eq!(range("3..").within(10), 3..10);
    assert_eq!(range("3..").within(0), 0..0);
}

#[test]
fn range_errors_say_what_to_write() {
    for text in ["", "abc", "3-10", "-3", "5..=", "x..3"] {
        let err = text.parse::<FrameRange>().unwrap_err();
        let msg = err.to_string();
        assert!(
            msg.contains("A..B") || msg.contains("frame number"),
            "{text}: {msg}"
        );
    }
    assert!(matches!(
        "3-10".parse::<FrameRange>(),
        Err(RangeError::Syntax { .. })
    ));
    let err = "a..9".parse::<FrameRange>().unwrap_err();
    assert_eq!(
        err,
        RangeError::Number {
            text: "a..9".into(),
            bound: "a".into()
        }
    );
    assert!(err.to_string().contains("`a` is not a frame number"));
    assert!(matches!(
        "99999999999999999999..".parse::<FrameRange>(),
        Err(RangeError::Number { .. })
    ));
    for text in ["5..5", "7..3", "7..=6"] {
        let err = text.parse::<FrameRange>().unwrap_err();
        assert!(matches!(err, RangeError::Empty { .. }), "{text}");
        assert!(err.to_string().contains("selects no frame"));
    }
}

// ---- shards ----

#[test]
fn shards_cover_every_frame_exactly_once() {
    for n in 1..=7 {
        for count in 0..50 {
            let mut seen = vec![0u32; count as usize];
            for k in 1..=n {
                let shard = Shard::new(k, n).unwrap();
                for f in FrameSelection::all().frames(count, shard) {
                    assert_eq!(f % n + 1, k, "frame {f} in shard {k}/{n}");
                    seen[f as usize] += 1;
                }
            }
            assert!(seen.iter().all(|&s| s == 1), "N = {n}, {count} frames");
        }
    }
}

#[test]
fn shard_parsing_and_errors() {
    let s: Shard = "2/4".parse().unwrap();
    assert_eq!((s.index(), s.count(), s.to_string()), (2, 4, "2/4".into()));
    assert!(s.contains(1) && s.contains(5) && !s.contains(2));
    assert_eq!(Shard::all(), "1/1".parse().unwrap());
    assert!(matches!(
        "3".parse::<Shard>(),
        Err(ShardError::Syntax { .. })
    ));
    assert!(matches!(
        "a/3".parse::<Shard>(),
        Err(ShardError::Number { .. })
    ));
    for (text, needle) in [
        ("0/4", "write one of 1/4"),
        ("5/4", "write one of 1/4"),
        ("1/0", "at least 1"),
        ("2", "`K/N`"),
        ("2/x", "not a whole number"),
    ] {
        let msg = text.parse::<Shard>().unwrap_err().to_string();
        assert!(msg.contains(needle), "{text}: {msg}");
    }
}

#[test]
fn shards_split_a_range_selection() {
    let sel = FrameSelection::range(range("3..=9"));
    assert_eq!(sel.frames(100, "1/2".parse().unwrap()), [4, 6, 8]);
    assert_eq!(sel.frames(100, "2/2".parse().unwrap()), [3, 5, 7, 9]);
    assert_eq!(sel.frames(6, Shard::all()), [3, 4, 5]);
    assert!(sel.frames(2, Shard::all()).is_empty());
}

// ---- rs_switch ----

#[test]
fn rs_switch_intervals_are_inclusive_and_may_overlap() {
    let sel = FrameSelection::from_rs_switch(&[0, 2, 10, 12, 11, 13]);
    assert_eq!(sel.frames(100, Shard::all()), [0, 1, 2, 10, 11, 12, 13]);
    assert_eq!(sel.frames(12, Shard::all()), [0, 1, 2, 10, 11]);
    assert!(sel.contains(13) && !sel.contains(14));
}

#[test]
fn rs_switch_odd_reversed_and_negative_values() {
    assert_eq!(
        FrameSelection::from_rs_switch(&[5, 6, 9]).frames(100, Shard::all()),
        [5, 6, 9]
    );
    // max < min switches an interval off; negative mins start at 0.
    let sel = FrameSelection::from_rs_switch(&[4, 3, -1, -1, -5, 1]);
    assert_eq!(sel.frames(100, Shard::all()), [0, 1]);
    assert!(FrameSelection::from_rs_switch(&[])
        .frames(10, Shard::all())
        .is_empty());
}

#[test]
fn command_line_overrides_rs_switch() {
    let options = vec![
        OptionItem::MaxPart(10),
        OptionItem::RsSwitch(vec![0, 1]),
        OptionItem::RsSwitch(vec![5, 6]),
    ];
    let switch = rs_switch(&options);
    assert_eq!(switch, Some(&[5i64, 6][..]), "the last rs_switch wins");
    let all = Shard::all();
    assert_eq!(
        FrameSelection::resolve(None, switch).frames(10, all),
        [5, 6]
    );
    assert_eq!(
        FrameSelection::resolve(Some(range("1..3")), switch).frames(10, all),
        [1, 2]
    );
    assert_eq!(
        FrameSelection::resolve(None, None).frames(4, all),
        [0, 1, 2, 3]
    );
    assert_eq!(rs_switch(&[OptionItem::MaxPart(1)]), None);
}

// ---- names ----

#[test]
fn frame_and_snapshot_names() {
    assert_eq!(frame_number(0), "0000");
    assert_eq!(frame_number(42), "0042");
    assert_eq!(frame_number(9999), "9999");
    assert_eq!(frame_number(12345), "12345");
    assert_eq!(
        frame_path("tree", 7, "png"),
        Path::new("frames/tree.0007.png")
    );
    assert_eq!(
        frame_path("tree", 10000, "exr"),
        Path::new("frames/tree.10000.exr")
    );
    assert_eq!(snapshot_path(3), Path::new("scene/0003.snap"));
    assert_eq!(snapshot_path(123456), Path::new("scene/123456.snap"));
}

// ---- manifest ----

#[test]
fn sha256_of_bytes_and_streamed_files() {
    assert_eq!(
        sha256_bytes(b"abc"),
        "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad"
    );
    let dir = temp_dir("sha");
    let big: Vec<u8> = (0..300_001u32).map(|i| (i * 31 % 251) as u8).collect();
    fs::write(dir.join("big"), &big).unwrap();
    assert_eq!(
        sha256_file(&dir.join("big"), 300_001).unwrap(),
        sha256_bytes(&big)
    );
    // Never past its bound, never a device that has no end.
    assert!(sha256_file(&dir.join("big"), 300_000).is_err());
    assert!(sha256_file(Path::new("/dev/zero"), 1 << 20).is_err());
    fs::remove_dir_all(&dir).unwrap();
}

/// A manifest's JSON with one field replaced.
fn manifest_text(name: &str, dt: &str, file: &str) -> String {
    format!(
        r#"{{"dt": {dt}, "files": {{"{file}": "00"}}, "frame_count": 1, "inputs": [],
        "lmfilm_version": "0", "name": "{name}", "options": {{}}, "scenes": [], "selection": []}}"#
    )
}

#[test]
fn manifest_refuses_paths_outside_the_folder() {
    assert!(Manifest::parse(&manifest_text("f", "0.04", "frames/f.0000.png")).is_ok());
    for bad in ["../x", "/etc/passwd", "", "./a/../b", "../../etc/passwd"] {
        let err = Manifest::parse(&manifest_text("f", "0.04", bad)).unwrap_err();
        assert!(matches!(err, Error::UnsafePath { .. }), "{bad}: {err}");
    }
    for name in ["../../X", "/abs", "a/b", "..", ""] {
        let err = Manifest::parse(&manifest_text(name, "0.04", "a")).unwrap_err();
        assert!(matches!(err, Error::UnsafePath { .. }), "{name}: {err}");
    }
    for dt in ["0", "-1", "1e999"] {
        assert!(
            Manifest::parse(&manifest_text("f", dt, "a")).is_err(),
            "{dt}"
        );
    }
    let dir = temp_dir("man-unsafe");
    fs::write(
        dir.join(MANIFEST_FILE),
        manifest_text("f", "0.04", "../../etc/passwd"),
    )
    .unwrap();
    let err = verify(&dir).unwrap_err();
    assert!(err.to_string().contains("../../etc/passwd"), "{err}");
    fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn verify_without_or_with_a_broken_manifest_is_an_error() {
    let dir = temp_dir("verify-none");
    let err = verify(&dir).unwrap_err();
    assert!(matches!(err, Error::Io { .. }));
    assert!(err.to_string().contains(MANIFEST_FILE), "{err}");
    fs::write(dir.join(MANIFEST_FILE), "{ not json").unwrap();
    let err = verify(&dir).unwrap_err();
    assert!(matches!(err, Error::Json { .. }));
    assert!(
        err.to_string().contains("not a valid lmfilm manifest"),
        "{err}"
    );
    fs::remove_dir_all(&dir).unwrap();
}

// ---- mux ----

#[test]
fn frame_rates_are_exact_fractions() {
    let rate = |dt| FrameRate::from_dt(dt).unwrap();
    assert_eq!(rate(0.04), FrameRate { num: 25, den: 1 });
    assert_eq!(rate(0.04).to_string(), "25/1");
    assert_eq!(rate(1.0 / 30.0), FrameRate { num: 30, den: 1 });
    assert_eq!(
        rate(1001.0 / 30000.0),
        FrameRate {
            num: 30000,
            den: 1001
        }
    );
    assert_eq!(
        rate(1001.0 / 24000.0),
        FrameRate {
            num: 24000,
            den: 1001
        }
    );
    assert_eq!(rate(10.0), FrameRate { num: 1, den: 10 });
    assert_eq!(rate(0.4), FrameRate { num: 5, den: 2 });
    assert_eq!(rate(0.0416667), FrameRate { num: 24, den: 1 });
    for dt in [0.0, -0.04, f64::NAN, f64::INFINITY, 1e-12] {
        let err = FrameRate::from_dt(dt).unwrap_err();
        assert!(matches!(err, MuxError::FrameRate { .. }), "{dt}");
    }
}

#[test]
fn mux_refuses_a_missing_frame_or_soundtrack() {
    let rate = FrameRate { num: 25, den: 1 };
    let nowhere = std::env::temp_dir().join("lmfilm-film-no-such-folder");
    let frame = png("f", 0, String::new());
    let err = mux(
        &nowhere,
        "f",
        (rate, 20),
        std::slice::from_ref(&frame),
        &[],
        None,
    )
    .unwrap_err();
    assert!(matches!(err, MuxError::Io { .. }), "{err}");
    assert!(err.to_string().contains("f.0000.png"), "{err}");
    let dir = temp_dir("mux-nosound");
    tiny_film(&dir);
    let frames = [png("tiny", 0, String::new())];
    let gone = Some((Path::new("gone.wav"), None));
    let err = mux(&dir, "tiny", (rate, 20), &frames, &[], gone).unwrap_err();
    assert!(err.to_string().contains("gone.wav"), "{err}");
    fs::remove_dir_all(&dir).unwrap();
}

/// Frame `k` of film `name` as the mux reads it, with the PNG hash `hash`.
fn png(name: &str, k: u64, hash: String) -> FramePng {
    FramePng {
        frame: k,
        rel: frame_path(name, k, "png"),
        limit: 1 << 20,
        hash,
    }
}

/// The tiny film's three PNG frames, with their hashes.
fn tiny_pngs(dir: &Path) -> Vec<FramePng> {
    (0..3)
        .map(|k| {
            let hash = sha256_file(&dir.join(frame_path("tiny", k, "png")), 1 << 20).unwrap();
            png("tiny", k, hash)
        })
        .collect()
}

/// The video's groups encoded as the frames come (the tap of `run`) and
/// the mux's own from the PNGs are the same bytes: at 2 frames a second
/// (groups of 2) the tiny film's first group is taken from the tap, its
/// second (frame 2 alone, the film's last) too; a group whose frames'
/// PNG hashes are not the folder's is not taken, nor one that missed a
/// frame.
#[test]
fn groups_encoded_as_frames_come_make_the_mp4_of_the_pngs() {
    let dir = temp_dir("tap");
    tiny_film(&dir);
    let rate = FrameRate::from_dt(0.5).unwrap();
    let frames = tiny_pngs(&dir);
    let sound = Some((Path::new("soundtrack.wav"), None));
    let from_pngs = mux(&dir, "tiny", (rate, 20), &frames, &[], sound).unwrap();
    assert_eq!(from_pngs.groups, (0, 2));
    let reference = fs::read(&from_pngs.mp4).unwrap();
    let tapped = |hash_of: &dyn Fn(u64) -> String, skip: Option<u64>| {
        let tap = GroupTap::new(rate.fps(), 20, 3);
        let (written, frames) = std::sync::mpsc::sync_channel(3);
        for k in 0..3 {
            if skip == Some(k) {
                written.send(None).unwrap();
                continue;
            }
            let image = image::open(dir.join(frame_path("tiny", k, "png")))
                .unwrap()
                .into_rgb8();
            written
                .send(Some(TappedFrame {
                    frame: k,
                    png: hash_of(k),
                    size: image.dimensions(),
                    rgb: image.into_raw(),
                }))
                .unwrap();
        }
        drop(written);
        tap.encode(frames, &Timings::start());
        tap.groups()
    };
    let same = tapped(&|k| frames[k as usize].hash.clone(), None);
    let out = mux(&dir, "tiny", (rate, 20), &frames, &same, sound).unwrap();
    assert_eq!(out.groups, (2, 2));
    assert_eq!(
        fs::read(&out.mp4).unwrap(),
        reference,
        "the tap's groups, other bytes"
    );
    let other = tapped(
        &|k| match k {
            1 => "0".repeat(64),
            _ => frames[k as usize].hash.clone(),
        },
        None,
    );
    let out = mux(&dir, "tiny", (rate, 20), &frames, &other, sound).unwrap();
    assert_eq!(out.groups, (1, 2), "a group of other frames was taken");
    assert_eq!(fs::read(&out.mp4).unwrap(), reference);
    let missed = tapped(&|k| frames[k as usize].hash.clone(), Some(1));
    assert_eq!(missed.len(), 1, "a group that missed a frame was kept");
    let out = mux(&dir, "tiny", (rate, 20), &frames, &missed, sound).unwrap();
    assert_eq!(out.groups, (1, 2));
    assert_eq!(fs::read(&out.mp4).unwrap(), reference);
    fs::remove_dir_all(&dir).unwrap();
}

/// Three 17×9 PNG frames (odd sizes, which 4:2:0 video cannot take
/// unpadded, and under H.264's 16) and a mono soundtrack of exactly three frames at 25 fps.
fn tiny_film(dir: &Path) {
    fs::create_dir_all(dir.join("frames")).unwrap();
    for n in 0..3u8 {
        image::RgbImage::from_fn(17, 9, |x, y| {
            image::Rgb([80 * n, (x * 15) as u8, (y * 28) as u8])
        })
        .save(dir.join(frame_path("tiny", n.into(), "png")))
        .unwrap();
    }
    let spec = hound::WavSpec {
        channels: 1,
        sample_rate: 48_000,
        bits_per_sample: 16,
        sample_format: hound::SampleFormat::Int,
    };
    let mut wav = hound::WavWriter::create(dir.join("soundtrack.wav"), spec).unwrap();
    for i in 0..5_760i32 {
        wav.write_sample(((i % 100) * 300 - 15_000) as i16).unwrap();
    }
    wav.finalize().unwrap();
}

/// The MP4 is made in-process (no ffmpeg on the PATH of the test
/// process matters), and read back by this test's own reader: two
/// tracks, H.264 of the padded size with every frame, decoded by
/// OpenH264's decoder to pictures near the frames; Opus; the video's
/// duration three frames at 25 fps. Made twice, the same bytes.
#[test]
fn mux_makes_an_mp4_that_decodes_back_to_the_frames() {
    let dir = temp_dir("mux");
    tiny_film(&dir);
    let rate = FrameRate::from_dt(0.04).unwrap();
    let frames = tiny_pngs(&dir);
    let sound = Some((Path::new("soundtrack.wav"), None));
    let out = mux(&dir, "tiny", (rate, 20), &frames, &[], sound).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(out.mp4, dir.join("tiny.mp4"));
    assert!(out.note.is_none(), "{:?}", out.note);
    let bytes = fs::read(&out.mp4).unwrap();
    let movie = mp4::Movie::read(&bytes);
    assert_eq!(movie.tracks.len(), 2, "video and sound");
    let video = movie.track(b"vide");
    assert_eq!(
        (video.width, video.height),
        (18, 16),
        "17×9 padded to even, and 16 high at least"
    );
    assert_eq!(video.samples.len(), 3);
    assert_eq!(video.duration_seconds(), 0.12);
    assert_eq!(movie.track(b"soun").codec, *b"Opus");
    let pictures = mp4::decode_h264(&bytes, video);
    assert_eq!(pictures.len(), 3);
    for (k, y) in pictures.iter().enumerate() {
        let png = image::open(dir.join(frame_path("tiny", k as u64, "png")))
            .unwrap()
            .into_rgb8();
        // Luma of the top-left pixel, BT.709 limited range.
        let p = png.get_pixel(0, 0).0.map(f32::from);
        let want = 16.0 + (0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2]) * 219.0 / 255.0;
        assert!(
            (f32::from(y[0]) - want).abs() < 6.0,
            "frame {k}: {} against {want}",
            y[0]
        );
    }
    let again = mux(&dir, "tiny", (rate, 20), &frames, &[], sound).unwrap();
    assert_eq!(
        fs::read(&again.mp4).unwrap(),
        bytes,
        "the same frames, other bytes"
    );
    let temps = fs::read_dir(&dir)
        .unwrap()
        .filter(|e| {
            e.as_ref()
                .unwrap()
                .file_name()
                .to_string_lossy()
                .ends_with(".tmp")
        })
        .count();
    assert_eq!(temps, 0, "a temporary file was left behind");
    fs::remove_dir_all(&dir).unwrap();
}
