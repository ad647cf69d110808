//! Loudness normalisation of soundtracks, measured by an implementation
//! of ITU-R BS.1770-4 written here (the recommendation's 48 kHz K-weighting
//! table, blocks summed directly, a windowed-sinc true-peak meter), not by
//! the library's: the CLI's default −16 LUFS, `--loudness`,
//! `--no-normalize`, fades, silence, determinism, bad targets, and the
//! built-in sound library used from anywhere.

use std::f64::consts::PI;
use std::path::{Path, PathBuf};
use std::process::Command;

use crate::common::fresh_dir;
use lmfilm::sound::{self, EventsFile, SoundSettings, Sounds};

fn repo(path: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(path)
}

/// Runs `lmfilm` in `cwd` with `threads` rayon threads: (exit code, stderr).
fn lmfilm_in(cwd: &Path, args: &[&str], threads: &str) -> (i32, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_lmfilm"))
        .args(args)
        .current_dir(cwd)
        .env("RAYON_NUM_THREADS", threads)
        .output()
        .unwrap();
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

fn lmfilm(args: &[&str]) -> (i32, String) {
    lmfilm_in(Path::new(env!("CARGO_MANIFEST_DIR")), args, "2")
}

/// A WAV file's rate and channels in [-1, 1] (16-bit or float).
fn read(path: &Path) -> (u32, Vec<Vec<f64>>) {
    let mut r = hound::WavReader::open(path).unwrap_or_else(|e| panic!("{path:?}: {e}"));
    let spec = r.spec();
    let x: Vec<f64> = match spec.sample_format {
        hound::SampleFormat::Int => r
            .samples::<i16>()
            .map(|s| f64::from(s.unwrap()) / 32767.0)
            .collect(),
        hound::SampleFormat::Float => r.samples::<f32>().map(|s| f64::from(s.unwrap())).collect(),
    };
    let c = spec.channels as usize;
    let channels = (0..c)
        .map(|k| x.iter().skip(k).step_by(c).copied().collect())
        .collect();
    (spec.sample_rate, channels)
}

/// One biquad over `x`, direct form I.
fn biquad(x: &[f64], b: [f64; 3], a: [f64; 2]) -> Vec<f64> {
    let (mut x1, mut x2, mut y1, mut y2) = (0.0, 0.0, 0.0, 0.0);
    x.iter()
        .map(|&x0| {
            let y0 = b[0] * x0 + b[1] * x1 + b[2] * x2 - a[0] * y1 - a[1] * y2;
            (x2, x1, y2, y1) = (x1, x0, y1, y0);
            y0
        })
        .collect()
}

/// Integrated loudness (BS.1770-4) of 48 kHz channels, all weighted 1.0;
/// None below the absolute gate.
fn lufs(channels: &[Vec<f64>]) -> Option<f64> {
    // The recommendation's table 1 and 2 (48 kHz).
    let weighted: Vec<Vec<f64>> = channels
        .iter()
        .map(|x| {
            let pre = biquad(
                x,
                [1.53512485958697, -2.69169618940638, 1.19839281085285],
                [-1.69065929318241, 0.73248077421585],
            );
            biquad(
                &pre,
                [1.0, -2.0, 1.0],
                [-1.99004745483398, 0.99007225036621],
            )
        })
        .collect();
    let (block, hop) = (19_200, 4_800);
    let n = weighted[0].len();
    let mut z = Vec::new();
    let mut start = 0;
    while start + block <= n {
        z.push(
            weighted
                .iter()
                .map(|y| y[start..start + block].iter().map(|v| v * v).sum::<f64>() / block as f64)
                .sum::<f64>(),
        );
        start += hop;
    }
    let l = |p: f64| -0.691 + 10.0 * p.log10();
    let gated = |gate: f64| -> Option<f64> {
        let kept: Vec<f64> = z.iter().copied().filter(|&p| l(p) > gate).collect();
        (!kept.is_empty()).then(|| kept.iter().sum::<f64>() / kept.len() as f64)
    };
    let relative = l(gated(-70.0)?) - 10.0;
    gated(relative.max(-70.0)).map(l)
}

/// True peak in dBTP: the signal interpolated 8× with a Hann-windowed sinc
/// of ±32 samples (a finer meter than annex 2's 4×).
fn true_peak(channels: &[Vec<f64>]) -> f64 {
    const OVER: usize = 8;
    const HALF: isize = 32;
    let kernel: Vec<Vec<f64>> = (0..OVER)
        .map(|p| {
            let frac = p as f64 / OVER as f64;
            (-HALF + 1..=HALF)
                .map(|k| {
                    let t = k as f64 - frac;
                    let sinc = if t == 0.0 {
                        1.0
                    } else {
                        (PI * t).sin() / (PI * t)
                    };
                    let w = 0.5 + 0.5 * (PI * t / (HALF as f64 + 1.0)).cos();
                    sinc * w
                })
                .collect()
        })
        .collect();
    let mut peak = 0.0f64;
    for x in channels {
        for i in 0..x.len() as isize {
            for h in &kernel {
                // The value at i + frac: Σ x[i + k] · h(k − frac).
                let y: f64 = (-HALF + 1..=HALF)
                    .zip(h)
                    .filter_map(|(k, h)| x.get(usize::try_from(i + k).ok()?).map(|v| v * h))
                    .sum();
                peak = peak.max(y.abs());
            }
        }
    }
    20.0 * peak.log10()
}

/// Asserts a soundtrack's loudness is `target` within `within` LU and its
/// true peak at most −1 dBTP, by this file's meter (its 8× sinc sees a
/// little more between samples than annex 2's 4×, which the program
/// holds to −1.1 dBTP for that), and that the line the
/// user reads agrees to 0.2 LU.
fn assert_normalised(wav: &Path, target: f64, within: f64, stderr: &str) {
    let (rate, mut x) = read(wav);
    // The scenes here with more than two microphones have a listener's
    // ears as 0 and 1: the loudness is theirs (the stereo's).
    x.truncate(2);
    assert_eq!(rate, 48_000);
    let l = lufs(&x).expect("the soundtrack is heard");
    let tp = true_peak(&x);
    assert!((l - target).abs() <= within, "{wav:?}: {l} LUFS, {stderr}");
    assert!(tp <= -1.0, "{wav:?}: {tp} dBTP, {stderr}");
    assert!(!stderr.contains("warning"), "{stderr}");
    let said: f64 = stderr
        .split(": ")
        .nth(1)
        .and_then(|s| s.split(" LUFS").next())
        .and_then(|s| s.parse().ok())
        .unwrap_or_else(|| panic!("no loudness in {stderr:?}"));
    assert!((said - l).abs() <= 0.2, "said {said}, measured {l}");
}

#[test]
fn the_flyby_log_is_normalised_to_minus_16_lufs_with_fades() {
    let dir = fresh_dir("loudness", "flyby");
    let wav = dir.join("flyby.wav");
    let events = repo("scenes/examples/flyby.events");
    let args = [
        "sound",
        events.to_str().unwrap(),
        "-o",
        wav.to_str().unwrap(),
    ];
    let (code, err) = lmfilm_in(&dir, &args, "1");
    assert_eq!(code, 0, "{err}");
    // Its frog is close and loud: plain gain would stop at -21.6 LUFS.
    assert!(
        err.contains("flyby.wav: ") && err.contains("limited up to"),
        "{err}"
    );
    assert_normalised(&wav, -16.0, 0.2, &err);
    let (_, x) = read(&wav);
    for ch in &x {
        assert_eq!((ch[0], ch[ch.len() - 1]), (0.0, 0.0), "faded ends");
    }
    // Same bytes again, on two threads.
    let first = std::fs::read(&wav).unwrap();
    let (code, err) = lmfilm_in(&dir, &args, "2");
    assert_eq!(code, 0, "{err}");
    assert_eq!(first, std::fs::read(&wav).unwrap(), "not deterministic");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn scenes_are_normalised_and_a_target_can_be_chosen() {
    let dir = fresh_dir("loudness", "scenes");
    for (scene, target, limited) in [
        // Hits every 1.6 s: plain gain would stop at -24.1 LUFS.
        ("scenes/physics/bouncing_ball.lm", None, true),
        ("scenes/physics/bouncing_ball.lm", Some("-23"), true),
        // A steady engine heard by two ears, the head's shadow on one
        // side: limited by under 2 dB at -16, gain alone at -23.
        ("scenes/examples/airplane.lm", None, true),
        ("scenes/examples/airplane.lm", Some("-23"), false),
    ] {
        let name = Path::new(scene).file_stem().unwrap().to_str().unwrap();
        let wav = dir.join(format!("{name}{}.wav", target.unwrap_or("")));
        let scene = repo(scene);
        let mut args = vec![
            "sound",
            scene.to_str().unwrap(),
            "-o",
            wav.to_str().unwrap(),
        ];
        if let Some(t) = target {
            args.extend(["--loudness", t]);
        }
        let (code, err) = lmfilm(&args);
        assert_eq!(code, 0, "{err}");
        assert_eq!(err.contains("limited up to"), limited, "{err}");
        let target: f64 = target.map_or(-16.0, |t| t.parse().unwrap());
        assert_normalised(&wav, target, 0.2, &err);
        if limited {
            // The same bytes on one thread.
            let first = std::fs::read(&wav).unwrap();
            let (code, err) = lmfilm_in(&dir, &args, "1");
            assert_eq!(code, 0, "{err}");
            assert_eq!(first, std::fs::read(&wav).unwrap(), "not deterministic");
        }
    }
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn one_frog_next_to_one_microphone_reaches_the_target_and_a_lone_beep_says_why() {
    let dir = fresh_dir("loudness", "frog");
    // Pulses with silence between: the gentler limiter stays at -17.3
    // LUFS, the faster one gets there.
    for (sound, reached) in [("frog", true), ("start", false)] {
        let events = dir.join(format!("near_{sound}.events"));
        std::fs::write(
            &events,
            format!(
                "INIT_mic 0 0 1.7 0 0 0 0\nINIT_source 0 1 1.7 0 0 0 0\nTIME 0\nTIME 1\n\
                 PLAY 0 {sound}.wav\nTIME 3\nTIME 4\n"
            ),
        )
        .unwrap();
        let (code, err) = lmfilm(&["sound", events.to_str().unwrap()]);
        assert_eq!(code, 0, "{err}");
        assert!(err.contains("limited up to"), "{err}");
        let wav = events.with_extension("wav");
        if reached {
            assert_normalised(&wav, -16.0, 0.2, &err);
        } else {
            // A 10 ms beep, once: too sparse (docs/sound-events.md).
            let (_, x) = read(&wav);
            let (l, tp) = (lufs(&x).unwrap(), true_peak(&x));
            assert!(l < -16.5 && tp <= -1.0, "{l} LUFS, {tp} dBTP");
            assert!(
                err.contains("warning") && err.contains("not -16.0"),
                "{err}"
            );
        }
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// A mono 48 kHz track normalised to -16 LUFS by the library, as f64.
fn normalise(mut x: Vec<f32>) -> (sound::loudness::Normalization, Vec<Vec<f64>>) {
    let mut channels = vec![std::mem::take(&mut x)];
    let n = sound::loudness::normalize(&mut channels, 48_000, -16.0);
    let y = channels
        .iter()
        .map(|c| c.iter().map(|&v| f64::from(v)).collect())
        .collect();
    (n, y)
}

#[test]
fn hits_reach_the_target_and_lone_clicks_keep_the_ceiling_and_say_why() {
    // A hit every 0.8 s: a full-scale onset ringing down 4 dB per 10 ms,
    // like the ball's: limited to the target.
    let x: Vec<f32> = (0..48_000 * 4)
        .map(|i| {
            let t = (i % 38_400) as f64 / 48_000.0;
            ((-t / 0.02).exp() * (2.0 * PI * 300.0 * t + 1.0).sin()) as f32
        })
        .collect();
    let (n, y) = normalise(x);
    let l = lufs(&y).unwrap();
    assert!((l + 16.0).abs() <= 0.2, "{l} LUFS, {n:?}");
    assert!(true_peak(&y) <= -1.0, "{n:?}");
    assert!(n.limiting > 0.0 && n.warning().is_none(), "{n:?}");
    // A single full-scale sample in 3 s of silence, and a track of one
    // sample: the limiter cannot make a click louder (it cuts it as
    // much as it raises it), so it stays below the target at the
    // ceiling, and the warning says why.
    let mut click = vec![0.0f32; 48_000 * 3];
    click[70_000] = 1.0;
    let (n, y) = normalise(click);
    let l = lufs(&y).unwrap();
    assert!(l < -30.0, "{l} LUFS");
    let tp = true_peak(&y);
    assert!((-1.2..=-1.0).contains(&tp), "{tp} dBTP");
    let w = n.warning().expect("a warning");
    assert!(
        w.contains("not -16.0") && w.contains("true peak above -1 dBTP"),
        "{w}"
    );
    let (n, y) = normalise(vec![1.0]);
    assert_eq!((n.loudness, y), (None, vec![vec![0.0]]), "faded to silence");
}

/// The aeroplane's ambisonic master, beside its soundtrack: W at the
/// target by this file's own BS.1770 meter, every channel under the
/// true-peak ceiling, and X, Y, Z never louder than W (SN3D: a
/// direction's cosine).
#[test]
fn the_ambisonic_master_is_normalised_on_w() {
    let dir = fresh_dir("loudness", "ambix");
    let wav = dir.join("air.wav");
    let scene = repo("scenes/examples/airplane.lm");
    let (code, err) = lmfilm(&[
        "sound",
        scene.to_str().unwrap(),
        "-o",
        wav.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let master = dir.join("air.ambix.wav");
    assert!(err.contains("air.ambix.wav: the ambisonic master"), "{err}");
    let (rate, x) = read(&master);
    assert_eq!((rate, x.len()), (48_000, 4));
    let w = lufs(&x[..1]).expect("W is heard");
    assert!((w + 16.0).abs() <= 0.2, "W at {w} LUFS: {err}");
    assert!(true_peak(&x) <= -1.0, "{err}");
    let energy = |c: &[f64]| c.iter().map(|v| v * v).sum::<f64>();
    for (k, c) in x.iter().enumerate().skip(1) {
        assert!(
            energy(c) <= energy(&x[0]) * 1.0001,
            "channel {k} louder than W"
        );
    }
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn float_output_is_normalised_too() {
    let dir = fresh_dir("loudness", "float");
    let wav = dir.join("f.wav");
    let scene = repo("scenes/examples/airplane.lm");
    let (code, err) = lmfilm(&[
        "sound",
        scene.to_str().unwrap(),
        "-o",
        wav.to_str().unwrap(),
        "--float",
    ]);
    assert_eq!(code, 0, "{err}");
    assert_eq!(
        hound::WavReader::open(&wav).unwrap().spec().sample_format,
        hound::SampleFormat::Float
    );
    assert_normalised(&wav, -16.0, 0.2, &err);
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn no_normalize_writes_the_raw_mix_of_the_renderer() {
    let dir = fresh_dir("loudness", "raw");
    let events = repo("scenes/examples/flyby.events");
    let raw = dir.join("raw.wav");
    let (code, err) = lmfilm(&[
        "sound",
        events.to_str().unwrap(),
        "-o",
        raw.to_str().unwrap(),
        "--no-normalize",
    ]);
    assert_eq!(code, 0, "{err}");
    // The library's renderer with normalisation off, encoded as 16 bits.
    let text = std::fs::read_to_string(&events).unwrap();
    let file = EventsFile::parse(lmfilm::lsys::Source::new("flyby.events", text)).unwrap();
    let search = sound::library::search_path(None, None);
    let sounds = Sounds::load(&file.log, &search).unwrap();
    let settings = SoundSettings {
        loudness: None,
        ..SoundSettings::default()
    };
    let track = sound::render(&file.log, &sounds, &settings).unwrap();
    assert_eq!(track.loudness, None);
    let (bytes, _) = sound::wav::encode(&track.channels, track.rate, settings.format).unwrap();
    assert_eq!(std::fs::read(&raw).unwrap(), bytes);
    // Far below the target: the physics' own level.
    let l = lufs(&read(&raw).1).unwrap();
    assert!(l < -30.0, "{l}");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn a_log_that_plays_nothing_stays_silent() {
    let dir = fresh_dir("loudness", "silent");
    let events = dir.join("quiet.events");
    std::fs::write(
        &events,
        "INIT_mic 0 0 0 0 0 0 0\nINIT_mic 1 1 0 0 0 0 0\nTIME 0\nTIME 0.5\nTIME 1\n",
    )
    .unwrap();
    let (code, err) = lmfilm(&["sound", events.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    assert!(err.contains("silent"), "{err}");
    let (_, x) = read(&dir.join("quiet.wav"));
    assert_eq!(x.len(), 2);
    assert!(!x[0].is_empty() && x.iter().flatten().all(|&v| v == 0.0));
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn a_bad_target_is_a_usage_error_naming_the_option() {
    let events = repo("scenes/examples/flyby.events");
    let e = events.to_str().unwrap();
    for bad in ["NaN", "inf", "-inf", "0.5", "-71", "abc"] {
        let arg = format!("--loudness={bad}");
        let (code, err) = lmfilm(&["sound", e, "-o", "/nonexistent/x.wav", &arg]);
        assert_eq!(code, 2, "{bad}: {err}");
        assert!(err.contains("--loudness"), "{bad}: {err}");
    }
    let (code, err) = lmfilm(&["sound", e, "--loudness", "-20", "--no-normalize"]);
    assert_eq!(code, 2, "{err}");
    // The library refuses such a target too.
    let settings = SoundSettings {
        loudness: Some(f64::NAN),
        ..SoundSettings::default()
    };
    let r = sound::render(&sound::EventLog::new(), &Sounds::new(), &settings);
    assert!(r.is_err_and(|e| e.to_string().contains("loudness")));
}

#[test]
fn library_sounds_play_with_no_source_tree_at_hand() {
    // The log in one temporary folder, the current folder another: the
    // sounds can only come from the library built into the program.
    let dir = fresh_dir("loudness", "embedded");
    let (work, logs) = (dir.join("work"), dir.join("logs"));
    std::fs::create_dir_all(&work).unwrap();
    std::fs::create_dir_all(&logs).unwrap();
    let events = logs.join("flyby.events");
    std::fs::copy(repo("scenes/examples/flyby.events"), &events).unwrap();
    let (code, err) = lmfilm_in(&work, &["sound", events.to_str().unwrap()], "2");
    assert_eq!(code, 0, "{err}");
    let (_, x) = read(&logs.join("flyby.wav"));
    assert!(x.iter().flatten().any(|v| v.abs() > 0.1), "heard");
    // A folder given with --library still comes first: a broken frog.
    let lib = dir.join("lib");
    std::fs::create_dir_all(&lib).unwrap();
    std::fs::write(lib.join("frog.wav"), b"not a wav").unwrap();
    let (code, err) = lmfilm_in(
        &work,
        &[
            "sound",
            events.to_str().unwrap(),
            "--library",
            lib.to_str().unwrap(),
        ],
        "2",
    );
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("frog.wav") && err.contains("not a WAV"),
        "{err}"
    );
    std::fs::remove_dir_all(&dir).ok();
}
