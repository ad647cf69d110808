//! The Doppler sound renderer against exact geometry: propagation delay,
//! Doppler shift, attenuation, silence, interaural time difference,
//! length, the supersonic limit, determinism, and `lmfilm sound` end to end.

use std::f64::consts::PI;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::mpsc;
use std::time::Duration;

use glam::DVec3;
use lmfilm::sound::events::write;
use lmfilm::sound::render::sample_count;
use lmfilm::sound::{render, Attenuation, EventLog, Signal, SoundSettings, Sounds, Soundtrack};

const C: f64 = 343.0;
const RATE: f64 = 48_000.0;

fn tone(freq: f64, secs: f64, rate: u32) -> Signal {
    let n = (secs * rate as f64).round() as usize;
    Signal {
        rate,
        samples: (0..n)
            .map(|i| (2.0 * PI * freq * i as f64 / rate as f64).sin() as f32)
            .collect(),
    }
}

/// A Gaussian pulse of standard deviation `sigma` seconds, centred at 5σ.
fn pulse(sigma: f64) -> Signal {
    let n = (10.0 * sigma * RATE) as usize;
    Signal {
        rate: RATE as u32,
        samples: (0..n)
            .map(|i| {
                let x = (i as f64 / RATE - 5.0 * sigma) / sigma;
                (-0.5 * x * x).exp() as f32
            })
            .collect(),
    }
}

/// Frames every 40 ms from 0 to `last` inclusive; `each(log, t)` fills them.
fn frames(log: &mut EventLog, last: f64, mut each: impl FnMut(&mut EventLog, f64)) {
    let n = (last / 0.04).round() as usize;
    for k in 0..=n {
        let t = k as f64 * 0.04;
        log.frame(t).unwrap();
        each(log, t);
    }
}

fn sounds(list: &[(&str, Signal)]) -> Sounds {
    let mut s = Sounds::new();
    for (name, sig) in list {
        s.insert(*name, sig.clone());
    }
    s
}

/// The raw mix (no loudness normalisation): these tests check the physics.
fn run(log: &EventLog, sounds: &Sounds, attenuation: Attenuation) -> Soundtrack {
    let settings = SoundSettings {
        attenuation,
        loudness: None,
        ..SoundSettings::default()
    };
    render(log, sounds, &settings).unwrap_or_else(|e| panic!("{e}"))
}

/// Times of the upward zero crossings of `x` in samples [from, to), each
/// placed by linear interpolation between its two samples.
fn crossings(x: &[f32], from: usize, to: usize) -> Vec<f64> {
    (from..to.min(x.len() - 1))
        .filter(|&i| x[i] < 0.0 && x[i + 1] >= 0.0)
        .map(|i| {
            let (a, b) = (x[i] as f64, x[i + 1] as f64);
            (i as f64 + a / (a - b)) / RATE
        })
        .collect()
}

fn rms(x: &[f32]) -> f64 {
    (x.iter().map(|&v| (v as f64).powi(2)).sum::<f64>() / x.len() as f64).sqrt()
}

/// Emission time of the sound heard at `t` at the origin from a source at
/// p0 + v·τ: the root τ ≤ t of |p0 + vτ|² = c²(t − τ)².
fn exact_tau(p0: DVec3, v: DVec3, t: f64) -> f64 {
    let a = v.dot(v) - C * C;
    let b = 2.0 * (p0.dot(v) + C * C * t);
    let cc = p0.dot(p0) - C * C * t * t;
    let disc = (b * b - 4.0 * a * cc).sqrt();
    // a < 0 (subsonic): the smaller root is the one in the past.
    let r1 = (-b + disc) / (2.0 * a);
    let r2 = (-b - disc) / (2.0 * a);
    if r1 <= t {
        r1.max(if r2 <= t { r2 } else { f64::MIN })
    } else {
        r2
    }
}

#[test]
fn doppler_tone_has_the_frequency_of_the_exact_geometry() {
    // A 1 kHz tone (a 44.1 kHz file: resampled too) passes 5 m from the
    // microphone at 40 m/s: the pitch falls by ~23 % as it goes by.
    let (f0, p0, v) = (
        1000.0,
        DVec3::new(-60.0, 5.0, 0.0),
        DVec3::new(40.0, 0.0, 0.0),
    );
    let mut log = EventLog::new();
    log.declare_mic(0, [0.0, 0.0, 0.0]).unwrap();
    log.declare_source(1, p0).unwrap();
    frames(&mut log, 3.0, |log, t| {
        log.source_position(1, p0 + v * t).unwrap();
        if t == 0.0 {
            log.play(1, "tone.wav").unwrap();
        }
    });
    let track = run(
        &log,
        &sounds(&[("tone.wav", tone(f0, 4.0, 44_100))]),
        Attenuation::Inverse,
    );
    let x = &track.channels[0];
    let window = (0.05 * RATE) as usize;
    let mut checked = 0;
    let (mut lowest, mut highest) = (f64::MAX, 0.0f64);
    for w in (0.25 * RATE) as usize / window..(3.0 * RATE) as usize / window {
        let z = crossings(x, w * window, (w + 1) * window);
        let (t1, t2) = (z[0], z[z.len() - 1]);
        let measured = (z.len() - 1) as f64 / (t2 - t1);
        let predicted = f0 * (exact_tau(p0, v, t2) - exact_tau(p0, v, t1)) / (t2 - t1);
        assert!(
            (measured / predicted - 1.0).abs() < 0.003,
            "window at {:.2} s: measured {measured:.2} Hz, predicted {predicted:.2} Hz",
            w as f64 * 0.05
        );
        lowest = lowest.min(measured);
        highest = highest.max(measured);
        checked += 1;
    }
    assert_eq!(checked, 55);
    // The shift is really there: c/(c ∓ v) at the far ends.
    assert!(highest > 1100.0 && lowest < 910.0, "{lowest} .. {highest}");
}

#[test]
fn a_moving_microphone_hears_the_doppler_of_a_moving_observer() {
    // Toward a still source at 30 m/s: f = f0 (c + v) / c.
    let mut log = EventLog::new();
    log.declare_constant_source(0, [100.0, 0.0, 0.0]).unwrap();
    log.declare_mic(0, [0.0, 0.0, 0.0]).unwrap();
    frames(&mut log, 2.0, |log, t| {
        log.mic_position(0, [30.0 * t, 0.0, 0.0]).unwrap();
        if t == 0.0 {
            log.play(0, "tone.wav").unwrap();
        }
    });
    let track = run(
        &log,
        &sounds(&[("tone.wav", tone(500.0, 3.0, 48_000))]),
        Attenuation::None,
    );
    let z = crossings(
        &track.channels[0],
        (0.6 * RATE) as usize,
        (1.9 * RATE) as usize,
    );
    let measured = (z.len() - 1) as f64 / (z[z.len() - 1] - z[0]);
    let predicted = 500.0 * (C + 30.0) / C;
    assert!(
        (measured / predicted - 1.0).abs() < 1e-4,
        "{measured} vs {predicted}"
    );
}

#[test]
fn a_click_343_m_away_is_heard_one_second_later() {
    let mut log = EventLog::new();
    log.declare_mic(0, [0.0, 0.0, 0.0]).unwrap();
    log.declare_constant_source(0, [0.0, 0.0, 343.0]).unwrap();
    frames(&mut log, 1.2, |log, t| {
        if t == 0.0 {
            log.play(0, "click.wav").unwrap();
        }
    });
    let mut click = vec![0.0f32; 48];
    click[0] = 1.0;
    let click = Signal {
        rate: 48_000,
        samples: click,
    };
    let x = &run(&log, &sounds(&[("click.wav", click)]), Attenuation::Inverse).channels[0];
    let peak = (0..x.len())
        .max_by(|&a, &b| x[a].abs().total_cmp(&x[b].abs()))
        .unwrap();
    assert!((47_999..=48_001).contains(&peak), "heard at sample {peak}");
    assert!(
        x[..47_999].iter().all(|&v| v == 0.0),
        "nothing before the sound arrives"
    );
    assert!((x[peak] as f64 - 1.0 / 343.0).abs() < 1e-6, "{}", x[peak]);
}

#[test]
fn amplitudes_follow_each_attenuation_model() {
    // Microphones 0.5, 2 and 8 m from a still source; a 500 Hz tone.
    let mut log = EventLog::new();
    log.declare_constant_source(0, [0.0, 0.0, 0.0]).unwrap();
    log.declare_mic(0, [0.5, 0.0, 0.0]).unwrap();
    log.declare_mic(1, [0.0, 2.0, 0.0]).unwrap();
    log.declare_mic(2, [0.0, 0.0, -8.0]).unwrap();
    frames(&mut log, 1.0, |log, t| {
        if t == 0.0 {
            log.play(0, "tone.wav").unwrap();
        }
    });
    let s = sounds(&[("tone.wav", tone(500.0, 1.0, 48_000))]);
    let expect = |g: &dyn Fn(f64) -> f64| [g(0.5), g(2.0), g(8.0)];
    for (model, gains) in [
        (Attenuation::Inverse, expect(&|d: f64| 1.0 / d.max(1.0))),
        (
            Attenuation::Thesis,
            expect(&|d: f64| (1.0 / (1.0 + d)).powi(2)),
        ),
        (Attenuation::None, [1.0; 3]),
    ] {
        let track = run(&log, &s, model);
        // 0.1 .. 0.6 s: every microphone hears the tone, 250 whole periods.
        let level: Vec<f64> = track
            .channels
            .iter()
            .map(|ch| rms(&ch[4800..28_800]) * 2f64.sqrt())
            .collect();
        for (m, (l, g)) in level.iter().zip(gains).enumerate() {
            assert!((l / g - 1.0).abs() < 1e-3, "{model:?} mic {m}: {l} vs {g}");
        }
    }
}

#[test]
fn silent_before_the_sound_can_arrive_and_after_it_ends() {
    // 34.3 m: 0.1 s of flight. The tone plays from 0.2 s for 0.3 s.
    let mut log = EventLog::new();
    log.declare_mic(0, [34.3, 0.0, 0.0]).unwrap();
    log.declare_source(0, [0.0, 0.0, 0.0]).unwrap();
    frames(&mut log, 1.0, |log, t| {
        if (t - 0.2).abs() < 1e-9 {
            log.play(0, "tone.wav").unwrap();
        }
    });
    let sig = tone(440.0, 0.3, 48_000);
    let last = sig.samples.len() - 1;
    let x = &run(&log, &sounds(&[("tone.wav", sig)]), Attenuation::Inverse).channels[0];
    let first = (0.3 * RATE).round() as usize;
    let end = first + last;
    assert!(x[..first].iter().all(|&v| v == 0.0), "before arrival");
    assert!(x[end + 1..].iter().all(|&v| v == 0.0), "after the end");
    let heard = x[first..=end].iter().filter(|&&v| v != 0.0).count();
    assert!(
        heard > last * 9 / 10,
        "only {heard} of {last} samples heard"
    );
}

#[test]
fn two_ears_hear_the_interaural_time_and_intensity_difference() {
    // Ears 18 cm apart on the x axis, a pulse 10 m away along it.
    let mut log = EventLog::new();
    log.declare_mic(0, [-0.09, 1.7, 0.0]).unwrap();
    log.declare_mic(1, [0.09, 1.7, 0.0]).unwrap();
    log.declare_constant_source(4, [10.0, 1.7, 0.0]).unwrap();
    frames(&mut log, 0.2, |log, t| {
        if t == 0.0 {
            log.play(4, "pulse.wav").unwrap();
        }
    });
    let sigma = 2.5e-4;
    let track = run(
        &log,
        &sounds(&[("pulse.wav", pulse(sigma))]),
        Attenuation::Inverse,
    );
    // The pulse's centre by a parabola through the peak and its neighbours.
    let arrival = |x: &[f32]| {
        let i = (1..x.len() - 1)
            .max_by(|&a, &b| x[a].total_cmp(&x[b]))
            .unwrap();
        let (a, b, c) = (x[i - 1] as f64, x[i] as f64, x[i + 1] as f64);
        let frac = 0.5 * (a - c) / (a - 2.0 * b + c);
        ((i as f64 + frac) / RATE, x[i] as f64)
    };
    let (left_t, left_peak) = arrival(&track.channels[0]);
    let (right_t, right_peak) = arrival(&track.channels[1]);
    let itd = left_t - right_t;
    let expected = 0.18 / C;
    assert!(
        (itd - expected).abs() < 0.1 / RATE,
        "ITD {itd} s vs {expected} s"
    );
    assert!(
        (right_t - (5.0 * sigma + 9.91 / C)).abs() < 0.1 / RATE,
        "{right_t}"
    );
    let iid = right_peak / left_peak;
    assert!((iid / (10.09 / 9.91) - 1.0).abs() < 1e-3, "IID {iid}");
    assert_eq!(track.mics, vec![0, 1], "channels in microphone order");
}

#[test]
fn length_is_last_time_plus_one_frame_interval_to_the_sample() {
    for (rate, last, expected) in [
        (48_000, 0.96, 48_000),
        (44_100, 0.96, 44_100),
        (22_050, 2.0, 44_982),
        (8_000, 0.0, 320),
    ] {
        let mut log = EventLog::new();
        log.declare_mic(0, [0.0, 0.0, 0.0]).unwrap();
        frames(&mut log, last, |_, _| {});
        assert_eq!(sample_count(&log, rate), expected);
        let settings = SoundSettings {
            rate,
            ..SoundSettings::default()
        };
        let track = render(&log, &Sounds::new(), &settings).unwrap();
        assert_eq!(
            track.channels[0].len(),
            expected,
            "rate {rate}, last {last}"
        );
        assert_eq!(
            expected,
            ((last + 0.04) * rate as f64).round() as usize,
            "the documented rule"
        );
    }
}

/// A log with a source approaching the microphone at `speed` while playing.
fn approaching(speed: f64) -> EventLog {
    let mut log = EventLog::new();
    log.declare_mic(0, [0.0, 0.0, 0.0]).unwrap();
    log.declare_source(0, [-600.0, 0.0, 0.0]).unwrap();
    frames(&mut log, 1.0, |log, t| {
        log.source_position(0, [-600.0 + speed * t, 1.0, 0.0])
            .unwrap();
        if t == 0.0 {
            log.play(0, "tone.wav").unwrap();
        }
    });
    log
}

#[test]
fn a_supersonic_source_is_an_error_naming_the_time_not_a_hang() {
    let (tx, rx) = mpsc::channel();
    std::thread::spawn(move || {
        let s = sounds(&[("tone.wav", tone(200.0, 2.0, 8000))]);
        let fast = render(&approaching(400.0), &s, &SoundSettings::default()).map(|_| ());
        let slow = render(&approaching(300.0), &s, &SoundSettings::default()).map(|_| ());
        tx.send((fast, slow)).unwrap();
    });
    let (fast, slow) = rx
        .recv_timeout(Duration::from_secs(60))
        .expect("the renderer hangs on a supersonic source");
    let e = fast
        .expect_err("a source at 400 m/s must be refused")
        .to_string();
    assert!(e.contains("400.0 m/s") && e.contains("t = 0.0000 s"), "{e}");
    assert!(e.contains("not slower than sound"), "{e}");
    slow.expect("300 m/s is subsonic");
}

fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("lmfilm-sound-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Writes `sig` as a 16-bit WAV with `channels` identical channels.
fn write_wav(path: &Path, sig: &Signal, channels: u16) {
    let spec = hound::WavSpec {
        channels,
        sample_rate: sig.rate,
        bits_per_sample: 16,
        sample_format: hound::SampleFormat::Int,
    };
    let mut w = hound::WavWriter::create(path, spec).unwrap();
    for &s in &sig.samples {
        for _ in 0..channels {
            w.write_sample((s * 0.5 * 32767.0).round() as i16).unwrap();
        }
    }
    w.finalize().unwrap();
}

fn lmfilm(args: &[&str], threads: &str) -> (i32, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_lmfilm"))
        .args(args)
        .env("RAYON_NUM_THREADS", threads)
        .output()
        .unwrap();
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// Four moving sources around two moving microphones, from files of
/// several rates and channel counts, over a few render blocks.
fn busy_scene(dir: &Path) -> PathBuf {
    write_wav(&dir.join("a.wav"), &tone(330.0, 1.5, 44_100), 2);
    write_wav(&dir.join("b.wav"), &tone(1250.0, 0.7, 22_050), 1);
    let mut log = EventLog::new();
    log.declare_mic(0, [-0.1, 0.0, 0.0]).unwrap();
    log.declare_mic(1, [0.1, 0.0, 0.0]).unwrap();
    for s in 0..4u32 {
        log.declare_source(s, [s as f64, 0.0, 5.0]).unwrap();
    }
    frames(&mut log, 1.6, |log, t| {
        log.mic_position(0, [-0.1 + t, 0.0, 0.0]).unwrap();
        log.mic_position(1, [0.1 + t, 0.0, 0.0]).unwrap();
        for s in 0..4u32 {
            let a = t * (1.0 + s as f64);
            let p = DVec3::new(4.0 * a.cos(), 1.0, 4.0 * a.sin());
            log.source_position(s, p).unwrap();
        }
        let k = (t / 0.04).round() as u32;
        if k.is_multiple_of(10) {
            log.play(
                k / 10 % 4,
                if k.is_multiple_of(20) {
                    "a.wav"
                } else {
                    "b.wav"
                },
            )
            .unwrap();
        }
    });
    let path = dir.join("soundtrack.events");
    std::fs::write(&path, write(&log)).unwrap();
    path
}

#[test]
fn same_bytes_for_one_and_two_threads_and_cli_writes_the_folder_soundtrack() {
    let dir = temp_dir("threads");
    let events = busy_scene(&dir);
    let d = dir.to_str().unwrap();
    let (code, err) = lmfilm(&["sound", d], "1");
    assert_eq!(code, 0, "{err}");
    let one = std::fs::read(dir.join("soundtrack.wav")).unwrap();
    let out2 = dir.join("two.wav");
    let (code, err) = lmfilm(
        &[
            "sound",
            events.to_str().unwrap(),
            "-o",
            out2.to_str().unwrap(),
        ],
        "2",
    );
    assert_eq!(code, 0, "{err}");
    assert_eq!(
        one,
        std::fs::read(&out2).unwrap(),
        "bytes differ with the thread count"
    );
    let r = hound::WavReader::open(dir.join("soundtrack.wav")).unwrap();
    let spec = r.spec();
    assert_eq!(
        (spec.channels, spec.sample_rate, spec.bits_per_sample),
        (2, 48_000, 16)
    );
    assert_eq!(r.duration(), 78_720, "1.6 s + 0.04 s at 48 kHz");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn cli_resamples_stereo_files_and_writes_float() {
    // A 44.1 kHz stereo 1 kHz tone from a still source: 1 kHz at 48 kHz.
    let dir = temp_dir("float");
    let lib = dir.join("lib");
    std::fs::create_dir_all(&lib).unwrap();
    write_wav(&lib.join("t.wav"), &tone(1000.0, 1.0, 44_100), 2);
    let events = dir.join("e.events");
    std::fs::write(
        &events,
        "INIT_mic 0 0 0 0 0 0 0\nCONST_S 0 3 0 0 0 0 0\nTIME 0\nPLAY 0 t.wav\nTIME 0.5\n",
    )
    .unwrap();
    let out = dir.join("out/f.wav");
    let (code, err) = lmfilm(
        &[
            "sound",
            events.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
            "--float",
            "--no-normalize",
            "--attenuation",
            "none",
            "--library",
            lib.to_str().unwrap(),
        ],
        "2",
    );
    assert_eq!(code, 0, "{err}");
    let mut r = hound::WavReader::open(&out).unwrap();
    assert_eq!(r.spec().sample_format, hound::SampleFormat::Float);
    let x: Vec<f32> = r.samples::<f32>().map(Result::unwrap).collect();
    assert_eq!(x.len(), 48_000);
    let z = crossings(&x, 4800, 48_000);
    let f = (z.len() - 1) as f64 / (z[z.len() - 1] - z[0]);
    assert!((f - 1000.0).abs() < 0.05, "{f} Hz");
    assert!(
        (rms(&x[4800..]) * 2f64.sqrt() - 0.5).abs() < 1e-3,
        "amplitude"
    );
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn cli_bad_input_exits_2_with_file_and_line() {
    let dir = temp_dir("bad");
    let events = dir.join("bad.events");
    let e = events.to_str().unwrap();
    let cases = [
        (
            "INIT_mic 0 0 0 0 0 0 0\nINIT_source 0 0 0 0 0 0 0\nTIME 0\n\nPLAY 0 no_such_sound.wav\n",
            "bad.events:5:8: sound file \"no_such_sound.wav\" not found",
        ),
        ("INIT_mic 0 0 0 0 0 0 0\nTIME 0\nSP 3 0 0 0\n", "bad.events:3:4: SP: source 3 is not declared"),
        ("TIME 0\nTIME 1\n", "declares no microphone"),
    ];
    for (text, needle) in cases {
        std::fs::write(&events, text).unwrap();
        let (code, err) = lmfilm(&["sound", e], "1");
        assert_eq!(code, 2, "{err}");
        assert!(err.contains(needle), "{err}");
    }
    std::fs::write(&events, "INIT_mic 0 0 0 0 0 0 0\nTIME 1e7\n").unwrap();
    let (code, err) = lmfilm(&["sound", e], "1");
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("does not fit in a WAV file"), "{err}");
    // Beyond a year, the reader refuses the time where it is written.
    std::fs::write(&events, "INIT_mic 0 0 0 0 0 0 0\nTIME 1e300\n").unwrap();
    let (code, err) = lmfilm(&["sound", e], "1");
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("bad.events:2:6: TIME must be a time ≥ 0"),
        "{err}"
    );
    let (code, err) = lmfilm(&["sound", e, "--speed-of-sound", "0"], "1");
    assert_eq!(code, 2, "{err}");
    let (code, err) = lmfilm(&["sound", dir.join("none.events").to_str().unwrap()], "1");
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("cannot read"), "{err}");
    assert!(!dir.join("bad.wav").exists(), "no output after an error");
    std::fs::remove_dir_all(&dir).ok();
}

/// A listener's two ears (`INIT_ears`): for sources placed at random
/// around a head turned at random, each ear hears the sound after its
/// own exact propagation delay (the interaural difference has the
/// geometry's sign and size, within a sample at 48 kHz), and the ear
/// facing the source hears it louder, by the distances and the head's
/// shadow (`head_shadow`) computed here from the geometry alone.
#[test]
fn two_ears_hear_the_nearer_side_first_and_louder() {
    use lmfilm::sound::air::HALF_HEAD;
    use lmfilm::sound::render::head_shadow;
    use lmfilm::sound::Event;
    let mut rng = crate::common::Rng(0x9e37_79b9_7f4a_7c15u64);
    let mut unit = || rng.uniform(0.0, 1.0);
    let sigma = 2e-4;
    for case in 0..12 {
        let centre = DVec3::new(unit() * 20.0 - 10.0, 1.0 + unit(), unit() * 20.0 - 10.0);
        let yaw = unit() * 2.0 * PI;
        let right = DVec3::new(yaw.cos(), 0.0, yaw.sin());
        let (left_ear, right_ear) = (centre - right * HALF_HEAD, centre + right * HALF_HEAD);
        // The source 3–30 m away in any direction, sides included.
        let bearing = unit() * 2.0 * PI;
        let dist = 3.0 + unit() * 27.0;
        let dir = DVec3::new(bearing.cos(), (unit() - 0.5) * 0.6, bearing.sin()).normalize();
        let source = centre + dir * dist;
        let mut log = EventLog::new();
        log.declare_mic(0, left_ear).unwrap();
        log.declare_mic(1, right_ear).unwrap();
        log.push(Event::Ears { left: 0, right: 1 }).unwrap();
        log.declare_source(5, source).unwrap();
        frames(&mut log, 0.2, |log, t| {
            if t == 0.0 {
                log.play(5, "p.wav").unwrap();
            }
        });
        let out = run(
            &log,
            &sounds(&[("p.wav", pulse(sigma))]),
            Attenuation::Inverse,
        );
        assert_eq!(out.mics, [0, 1]);
        // Each ear's pulse peak: its arrival time, found by a parabola
        // through the largest sample and its neighbours.
        let peak = |x: &[f32]| {
            let i = (1..x.len() - 1)
                .max_by(|&a, &b| x[a].total_cmp(&x[b]))
                .unwrap();
            let (a, b, c) = (x[i - 1] as f64, x[i] as f64, x[i + 1] as f64);
            let off = 0.5 * (a - c) / (a - 2.0 * b + c);
            ((i as f64 + off) / RATE, b)
        };
        let ((tl, al), (tr, ar)) = (peak(&out.channels[0]), peak(&out.channels[1]));
        let (dl, dr) = (source.distance(left_ear), source.distance(right_ear));
        let want_itd = (dl - dr) / C;
        assert!(
            ((tl - tr) - want_itd).abs() < 1.0 / RATE,
            "case {case}: interaural delay {} s, the geometry's {want_itd} s",
            tl - tr
        );
        // The level each ear hears, from the geometry: spherical
        // attenuation and the shadow for the angle between the ear's
        // outward axis and the direction of the source.
        let level = |ear: DVec3, other: DVec3, d: f64| {
            let cos = (ear - other).normalize().dot((source - ear).normalize());
            head_shadow(cos) / d.max(1.0)
        };
        let (wl, wr) = (
            level(left_ear, right_ear, dl),
            level(right_ear, left_ear, dr),
        );
        assert!(
            ((al / ar) / (wl / wr) - 1.0).abs() < 0.01,
            "case {case}: level ratio {} against the geometry's {}",
            al / ar,
            wl / wr
        );
        // The nearer ear: first and louder.
        if (dl - dr).abs() > 0.05 {
            assert_eq!(dl < dr, tl < tr, "case {case}: the nearer ear hears first");
            assert_eq!(dl < dr, al > ar, "case {case}: the nearer ear hears louder");
        }
    }
}

/// The ambisonic master (`INIT_ambix`): for sources placed at random
/// around a microphone facing at random (and turned by `MO` on the way),
/// each of AmbiX's channels is W times the cosine of the sound's direction
/// with the microphone's front (X), left (Y) and up (Z), SN3D, in ACN
/// order W Y Z X. The axes here come from Gram–Schmidt on the world's up
/// (+y), not from the renderer's cross products; the cardinal directions
/// of a microphone facing −z are checked by name.
#[test]
fn the_ambisonic_master_points_each_channel_along_its_axis() {
    use lmfilm::sound::Event;
    let mut rng = crate::common::Rng(0x2545_f491_4f6c_dd1du64);
    let mut unit = || rng.uniform(0.0, 1.0);
    let sigma = 2e-4;
    let axes = |front: DVec3| {
        let f = front.normalize();
        let up = (DVec3::Y - DVec3::Y.dot(f) * f).normalize();
        let left = up.cross(f); // z × x = y in AmbiX's right-handed frame
        (f, left, up)
    };
    let mut cases: Vec<(DVec3, DVec3, DVec3)> = vec![
        // (front, where the source is from the microphone, [X, Y, Z]/W)
        (DVec3::NEG_Z, DVec3::NEG_Z, DVec3::X),
        (DVec3::NEG_Z, DVec3::NEG_X, DVec3::Y),
        (DVec3::NEG_Z, DVec3::X, DVec3::NEG_Y),
        (DVec3::NEG_Z, DVec3::Y, DVec3::Z),
        (DVec3::ZERO, DVec3::NEG_X, DVec3::Y),
    ];
    for _ in 0..16 {
        let yaw = unit() * 2.0 * PI;
        let pitch = (unit() - 0.5) * 2.4;
        let front = DVec3::new(
            yaw.cos() * pitch.cos(),
            pitch.sin(),
            yaw.sin() * pitch.cos(),
        );
        let dir = DVec3::new(unit() - 0.5, unit() - 0.5, unit() - 0.5).normalize();
        let (f, l, u) = axes(front);
        cases.push((front, dir, DVec3::new(dir.dot(f), dir.dot(l), dir.dot(u))));
    }
    for (case, (front, dir, want)) in cases.into_iter().enumerate() {
        let mic = DVec3::new(unit() * 10.0, 1.0, unit() * 10.0);
        let source = mic + dir * (3.0 + unit() * 20.0);
        let mut log = EventLog::new();
        // Declared facing elsewhere, turned to `front` by MO from the
        // first frame: the orientation the master follows is the log's.
        log.push(Event::Mic {
            n: 0,
            position: mic,
            orientation: DVec3::X,
        })
        .unwrap();
        log.push(Event::Ambix { n: 0 }).unwrap();
        log.declare_source(5, source).unwrap();
        frames(&mut log, 0.2, |log, t| {
            log.push(Event::MicOrientation {
                n: 0,
                orientation: front,
            })
            .unwrap();
            if t == 0.0 {
                log.play(5, "p.wav").unwrap();
            }
        });
        let out = run(
            &log,
            &sounds(&[("p.wav", pulse(sigma))]),
            Attenuation::Inverse,
        );
        let master = out.ambix.as_ref().expect("an ambisonic master");
        assert_eq!(master.mic, 0);
        let [w, y, z, x] = &master.channels;
        assert_eq!(
            w, &out.channels[0],
            "case {case}: W is the microphone's pressure"
        );
        let i = (0..w.len())
            .max_by(|&a, &b| w[a].abs().total_cmp(&w[b].abs()))
            .unwrap();
        let got = DVec3::new(x[i] as f64, y[i] as f64, z[i] as f64) / w[i] as f64;
        assert!(
            (got - want).length() < 1e-4,
            "case {case}: [X Y Z]/W = {got}, the geometry's {want} (front {front}, from {dir})"
        );
    }
}
