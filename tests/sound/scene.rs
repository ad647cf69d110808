//! Sound events from the L-system (issue 5): the `T` symbol, the
//! handler's table of on-going events behind `?60`–`?62`, the event log
//! of a scene, and its soundtrack through the command line.

use crate::common;

use std::path::{Path, PathBuf};
use std::process::Command;

use lmfilm::film::Film;
use lmfilm::lsys::print::Format;
use lmfilm::sound::air;
use lmfilm::sound::{self, Event};
use lmfilm::turtle::Options;

fn temp(name: &str) -> PathBuf {
    common::fresh_dir("sound-scene", name)
}

fn airplane() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/examples/airplane.lm")
}

/// Derives every frame and returns the film.
fn derive_all(scene: &Path) -> Film {
    let mut film = Film::load(&[scene], Options::default()).unwrap();
    while film.next_frame().unwrap().is_some() {}
    film
}

#[test]
fn the_aeroplane_logs_its_path_and_its_engine() {
    let film = derive_all(&airplane());
    let log = film.events();
    let frames = log.frames();
    assert_eq!(frames.len(), 151, "0 … 6 s every 40 ms");
    let mut plays = Vec::new();
    for (k, f) in frames.iter().enumerate() {
        assert!((f.time - k as f64 * 0.04).abs() < 1e-9);
        for e in &f.events {
            match e {
                Event::Play { n, file } => plays.push((k, *n, file.clone())),
                // The source follows x = 70 T − 210, 40 m up.
                Event::SourcePosition { n: 1, position } => {
                    let want = 70.0 * f.time - 210.0;
                    assert!((position.x - want).abs() < 1e-9, "frame {k}: {position}");
                    assert_eq!((position.y, position.z), (40.0, 0.0));
                }
                _ => {}
            }
        }
    }
    // Started at 0 and again when X reaches its age of 4 s.
    assert_eq!(
        plays,
        [
            (0, 1, "avion.wav".to_string()),
            (100, 1, "avion.wav".to_string())
        ]
    );
    // Two ears and the ambisonic microphone between them.
    assert_eq!(log.mic_numbers(), [0, 1, 2]);
    assert!(log.init().contains(&Event::Ears { left: 0, right: 1 }));
    assert_eq!(log.ambix(), Some(2));
    // The written log reads back the same.
    let text = sound::events::write(log);
    assert_eq!(&sound::events::parse(&text, "x.events").unwrap(), log);
}

#[test]
fn audition_functions_see_the_ongoing_events() {
    // Frame 0 starts sound 6 (start.wav, 10 ms) from source 3. At the step
    // after frame 0 the listener's conditions ask ?60, ?61 and ?62.
    let dir = temp("audition");
    let scene = dir.join("listen.lm");
    std::fs::write(
        &scene,
        "Camera_AnimationParameters\nt_final_interval 1 0.04\nAxiom\nT () (1) () () (6) (3) A () (3) B () (6) C () (4) D\n\
         Productions\nT (0)\n1.0 EndProb\nEnd\n\
         A (0) [(?60 1 -)=]\n1.0 a EndProb\nEnd\n\
         B (0) [(?62 3 -)=]\n1.0 b EndProb\nEnd\n\
         C (0) [(?61 1 +)=]\n1.0 c EndProb\nEnd\n\
         D (0) [(?60)=]\n1.0 d EndProb\nEnd\nEndProductions\n",
    )
    .unwrap();
    let mut film = Film::load(&[&scene], Options::default()).unwrap();
    film.next_frame().unwrap();
    assert_eq!(film.ongoing().len(), 1);
    assert_eq!(air::sound_of_source(film.ongoing(), 3), Some(6));
    assert_eq!(air::source_of_sound(film.ongoing(), 6), Some(3));
    assert_eq!(air::sound_of_source(film.ongoing(), 4), None);
    film.next_frame().unwrap();
    let word = film.words(Format::Symbols).remove(0);
    // One event on (A → a); sound 6 comes from source 3 (B → b);
    // source 4 is silent, ?61 = −1 (C → c); D waits for silence.
    assert_eq!(word, "abcD");
    // 10 ms later the sound has ended: at the next frame D hears nothing.
    assert_eq!(film.ongoing().len(), 0);
    film.next_frame().unwrap();
    let word = film.words(Format::Symbols).remove(0);
    assert_eq!(word, "abcd");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn sound_of_a_scene_from_the_command_line() {
    let dir = temp("cli");
    let wav = dir.join("plane.wav");
    let out = Command::new(env!("CARGO_BIN_EXE_lmfilm"))
        .args([
            "sound",
            airplane().to_str().unwrap(),
            "-o",
            wav.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(dir.join("soundtrack.events").exists());
    let r = hound::WavReader::open(&wav).unwrap();
    assert_eq!(r.spec().channels, 3, "one channel per microphone");
    assert!(dir.join("plane.ambix.wav").exists(), "the ambisonic master");
    // Exactly frames × Δt: 151 frames of 40 ms at 48 kHz.
    assert_eq!(r.duration(), 151 * 1920);
    let samples: Vec<i16> = r.into_samples::<i16>().map(Result::unwrap).collect();
    assert!(
        samples.iter().any(|&s| s.unsigned_abs() > 300),
        "the engine is heard"
    );
    // Nothing before the sound can arrive: the plane starts ~210 m away.
    let first = samples.iter().position(|&s| s != 0).unwrap() / 3;
    let arrival = (210f64.powi(2) + 40f64.powi(2) + 30f64.powi(2)).sqrt() / 343.0;
    assert!(
        (first as f64 / 48_000.0 - arrival).abs() < 0.01,
        "first sound at {first}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `sound_file N FILE` gives a scene its own sound for number N; the
/// event's length is that file's.
#[test]
fn a_scene_declares_its_own_sound_file() {
    let dir = temp("own");
    let spec = hound::WavSpec {
        channels: 1,
        sample_rate: 8000,
        bits_per_sample: 16,
        sample_format: hound::SampleFormat::Int,
    };
    let mut w = hound::WavWriter::create(dir.join("bell.wav"), spec).unwrap();
    for k in 0..4000 {
        w.write_sample(((k as f64 * 0.3).sin() * 9000.0) as i16)
            .unwrap();
    }
    w.finalize().unwrap();
    let scene = dir.join("bell.lm");
    std::fs::write(
        &scene,
        "Camera_AnimationParameters\nt_final_interval 1 0.04\nOptions\nsound_file 6 bell.wav\nAxiom\nT () (1) () () (6) (2)\nProductions\nT (0)\n1.0 EndProb\nEnd\nEndProductions\n",
    )
    .unwrap();
    let mut film = Film::load(&[&scene], Options::default()).unwrap();
    film.next_frame().unwrap();
    assert_eq!(film.ongoing()[0].end, 0.5, "bell.wav lasts 0.5 s");
    let text = sound::events::write(film.events());
    assert!(text.contains("PLAY 2 bell.wav"), "{text}");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A 0.2 s scene of one segment, the camera at (1, 2, 10) looking at
/// `look_at`, with the option line `sound`.
fn camera_scene(look_at: &str, sound: &str) -> String {
    format!(
        "Camera_AnimationParameters\nobserver 1 2 10\nlookatPoint {look_at}\n\
         t_final_interval 0.2 0.04\nOptions\n{sound}\nAxiom\nF\nProductions\nEndProductions\n"
    )
}

/// `Sound_event_file NAME INIT_ears 0 1` with no microphone puts two ears
/// on the camera: the log declares them as ears and places them each
/// frame 17.5 cm apart, either side of the eye along the image's right
/// (the camera here looks down −z, so right is +x); a scene whose ears
/// name a microphone it does not declare is refused, naming it.
#[test]
fn a_scene_listens_with_two_ears_on_the_camera() {
    let dir = temp("ears");
    let scene = dir.join("ears.lm");
    let text = |sound: &str| camera_scene("1 2 0", sound);
    std::fs::write(&scene, text("Sound_event_file e.events INIT_ears 0 1")).unwrap();
    let film = derive_all(&scene);
    let log = film.events();
    assert!(log.init().contains(&Event::Ears { left: 0, right: 1 }));
    let at = |n: u32| {
        log.frames()[2]
            .events
            .iter()
            .find_map(|e| match e {
                Event::MicPosition { n: m, position } if *m == n => Some(*position),
                _ => None,
            })
            .unwrap()
    };
    let (l, r) = (at(0), at(1));
    assert!(
        (l - glam::DVec3::new(1.0 - 0.0875, 2.0, 10.0)).length() < 1e-6,
        "{l}"
    );
    assert!(
        (r - glam::DVec3::new(1.0 + 0.0875, 2.0, 10.0)).length() < 1e-6,
        "{r}"
    );
    std::fs::write(
        &scene,
        text("Sound_event_file e.events INIT_mic 0 0 0 0 0 0 1 INIT_ears 0 3"),
    )
    .unwrap();
    let err = Film::load(&[&scene], Options::default())
        .err()
        .unwrap()
        .to_string();
    assert!(
        err.contains("INIT_ears: microphone 3 is not declared"),
        "{err}"
    );
    // Located at the item: the line and the column of `INIT_ears`.
    assert!(err.contains("ears.lm:6:50: "), "{err}");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `Sound_event_file NAME INIT_ears 0 1 INIT_ambix 2` with no microphone:
/// the ambisonic microphone is at the eye, facing where the camera looks
/// (`MO` each frame), beside the ears; without ears `INIT_ambix 0` is the
/// camera's own microphone. A second on the camera is refused.
#[test]
fn a_scene_s_ambisonic_microphone_faces_where_the_camera_looks() {
    let dir = temp("ambix");
    let scene = dir.join("ambix.lm");
    let text = |sound: &str| camera_scene("4 2 6", sound);
    for (sound, mics, n) in [
        (
            "Sound_event_file e.events INIT_ears 0 1 INIT_ambix 2",
            vec![0, 1, 2],
            2,
        ),
        ("Sound_event_file e.events INIT_ambix 0", vec![0], 0),
    ] {
        std::fs::write(&scene, text(sound)).unwrap();
        let film = derive_all(&scene);
        let log = film.events();
        assert_eq!(log.mic_numbers(), mics, "{sound}");
        assert_eq!(log.ambix(), Some(n));
        let frame = &log.frames()[2].events;
        let found = |f: &dyn Fn(&Event) -> Option<glam::DVec3>| frame.iter().find_map(f).unwrap();
        let facing = found(&|e| match e {
            Event::MicOrientation { n: m, orientation } if *m == n => Some(*orientation),
            _ => None,
        });
        let want = glam::DVec3::new(3.0, 0.0, -4.0) / 5.0;
        assert!((facing - want).length() < 1e-6, "{sound}: {facing}");
        let at = found(&|e| match e {
            Event::MicPosition { n: m, position } if *m == n => Some(*position),
            _ => None,
        });
        assert!(
            (at - glam::DVec3::new(1.0, 2.0, 10.0)).length() < 1e-6,
            "{at}"
        );
    }
    std::fs::write(
        &scene,
        text("Sound_event_file e.events INIT_ambix 0 INIT_ambix 3"),
    )
    .unwrap();
    let err = Film::load(&[&scene], Options::default())
        .err()
        .unwrap()
        .to_string();
    assert!(err.contains("already makes the ambisonic master"), "{err}");
    std::fs::remove_dir_all(&dir).unwrap();
}
