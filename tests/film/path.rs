//! The path-traced look of a film (issue 38): `--integrator path` and
//! `--shutter` recorded with the frames, the motion toward the next
//! frame's snapshot blurring what moves, the same bytes for 1 and 2
//! threads, and a changed integrator rendering the film again.

use std::collections::BTreeMap;
use std::path::Path;

use crate::cli::lmfilm;

fn ok(args: &[&str]) -> String {
    let (code, out, err) = lmfilm(args);
    assert_eq!(code, 0, "{args:?}: {out}{err}");
    out + &err
}

/// Frame `k`'s record and PNG bytes in film folder `dir`.
fn frame(dir: &Path, k: u64) -> (serde_json::Value, Vec<u8>) {
    let file = |ext: &str| dir.join(format!("frames/bouncing_ball.{k:04}.{ext}"));
    let record = std::fs::read_to_string(file("json")).unwrap();
    (
        serde_json::from_str(&record).unwrap(),
        std::fs::read(file("png")).unwrap(),
    )
}

#[test]
fn a_path_traced_film_blurs_what_moves_and_keeps_its_bytes() {
    let scene = format!(
        "{}/scenes/physics/bouncing_ball.lm",
        env!("CARGO_MANIFEST_DIR")
    );
    let root = crate::common::fresh_dir("film", "path_look");
    // The frames and settings every render here takes, but the shutter.
    let settings = [
        "--frames",
        "20..23",
        "--width",
        "64",
        "--spp",
        "4",
        "--format",
        "both",
        "--integrator",
        "path",
    ];
    let with = |head: &[&str], tail: &[&str]| ok(&[head, &settings[..], tail].concat());
    let run = |name: &str, threads: &str, shutter: &str| {
        let dir = root.join(name);
        let out = dir.to_str().unwrap();
        with(
            &["run", &scene, "-o", out],
            &[
                "--shutter",
                shutter,
                "--threads",
                threads,
                "--samples",
                "pcm16",
            ],
        );
        dir
    };
    let (one, two, still) = (
        run("one", "1", "0.5"),
        run("two", "2", "0.5"),
        run("still", "2", "0"),
    );
    // The same frames rendered in two shards of a derived folder.
    let shards = root.join("shards");
    let dir = shards.to_str().unwrap();
    ok(&["derive", &scene, "-o", dir]);
    for shard in ["1/2", "2/2"] {
        with(&["render", dir], &["--shard", shard, "--shutter", "0.5"]);
    }
    let mut blurred = 0;
    for k in 20..23 {
        let (record, png) = frame(&one, k);
        assert_eq!(
            frame(&two, k),
            (record.clone(), png.clone()),
            "frame {k}: 1 and 2 threads"
        );
        assert_eq!(frame(&shards, k).1, png, "frame {k}: shards");
        let render: BTreeMap<String, String> =
            serde_json::from_value(record["render"].clone()).unwrap();
        assert_eq!(render["integrator"], "path");
        assert_eq!(render["shutter"], "0.5");
        assert!(
            record["next_snapshot"].is_string(),
            "frame {k} names the next snapshot"
        );
        let (frozen, frozen_png) = frame(&still, k);
        assert!(
            frozen.get("next_snapshot").is_none(),
            "a closed shutter needs no next frame"
        );
        blurred += usize::from(frozen_png != png);
    }
    assert_eq!(blurred, 3, "the falling ball is blurred in every frame");
    // The whole film rendered, `verify` finds each frame made from its
    // snapshot and the next one.
    let whole = still.to_str().unwrap();
    ok(&["render", whole, "--shutter", "0.5"]);
    assert!(ok(&["verify", whole]).contains("ok"), "verify");
    // Back to the Whitted look: every frame again, and said.
    let dir = one.to_str().unwrap();
    let said = ok(&["render", dir, "--integrator", "whitted"]);
    assert!(said.contains("integrator path → whitted"), "{said}");
    assert_eq!(frame(&one, 21).0["render"]["integrator"], "whitted");
}
