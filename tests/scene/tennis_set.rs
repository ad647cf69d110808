//! The set of the tennis match (`scenes/tennis/match.lm`'s court, chair
//! and sky, `scenes/tennis/landscape.lm`'s plants and camera), its
//! people (two players and the seated referee), and the built-in film
//! that shows them (`scenes/tennis/showcase.lm` first).

use std::path::{Path, PathBuf};

use glam::Vec3;
use lmfilm::commands::scenes;
use lmfilm::film::Film;
use lmfilm::lsys::automata::Automata;
use lmfilm::lsys::Limits;
use lmfilm::turtle::Options;

/// The built-in film's files, in order.
const SHOWCASE: [&str; 3] = [
    "scenes/tennis/showcase.lm",
    "scenes/tennis/match.lm",
    "scenes/tennis/landscape.lm",
];

fn repo(path: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(path)
}

/// The referee actor's eye, over the umpire's chair.
const REFEREE: Vec3 = Vec3::new(0.0, 3.0, -7.0);

/// The hips joints of the bodies a scene draws: the start of each
/// thigh's capsule (joint 14, LeftLeg, drawn from LeftUpLeg).
fn hips(scene: &lmfilm::scene::Scene) -> Vec<Vec3> {
    scene
        .geometries
        .iter()
        .flat_map(|g| &g.shapes)
        .filter(|s| s.symbol >> 48 == 15)
        .map(|s| s.transform.transform_point3(Vec3::ZERO))
        .collect()
}

/// The play area: nothing of the set stands in it but the court, the net
/// and the umpire's chair with the referee.
fn in_play_area(p: Vec3) -> bool {
    p.x.abs() < 18.0 && p.z.abs() < 10.0
}

#[test]
fn the_landscape_leaves_the_players_colours_alone() {
    // No material of the landscape is the ball's or a player's (table
    // entries 10, 11, 12); alone it has no camera section, so it is
    // derived after a file that has one.
    let mut film = Film::load(&[repo(SHOWCASE[0]), repo(SHOWCASE[2])], Options::default()).unwrap();
    for _ in 0..=100 {
        let frame = film.next_frame().unwrap().unwrap();
        assert!(frame.warnings().is_empty(), "{:?}", frame.warnings());
        if frame.number().is_multiple_of(50) {
            let scene = frame.scene();
            for i in scene
                .geometries
                .iter()
                .flat_map(|g| g.shapes.iter().map(|s| s.material))
            {
                let name = scene.materials[i as usize].name.as_str();
                assert!(!["actor1", "actor2", "ball"].contains(&name), "{name}");
            }
        }
    }
}

#[test]
fn the_showcase_derives_every_frame_without_warnings() {
    let files: Vec<PathBuf> = SHOWCASE.iter().map(|f| repo(f)).collect();
    let mut film = Film::load(&files, Options::default()).unwrap();
    assert_eq!(film.frame_count(), 351, "14 s at 25 frames per second");
    while let Some(frame) = film.next_frame().unwrap() {
        no_warnings(frame);
    }
    let frame = film.frame().unwrap();
    let scene = frame.scene();
    // The camera ends beside and behind the referee's side, 6–9 m up,
    // looking at the court.
    let eye = scene.camera.eye;
    assert!(eye.z < -20.0 && (6.0..=9.0).contains(&eye.y), "{eye}");
    assert!(scene.camera.look_at.length() < 2.0);
    // Three people: the two players on their sides of the net, and the
    // referee seated on the chair under its eye.
    let people = hips(scene);
    assert_eq!(people.len(), 3, "{people:?}");
    assert!(people.iter().any(|p| p.x < -5.0) && people.iter().any(|p| p.x > 5.0));
    let seated = people
        .iter()
        .find(|p| p.distance(REFEREE) < 1.0)
        .expect("the referee on its chair");
    assert!((2.1..2.5).contains(&seated.y), "{seated}");
    // The plants (every instance but the main word) stand
    // out of the play area: their shapes' origins, in the world.
    let mut plants = 0;
    for inst in &scene.instances {
        let at = Vec3::from(inst.transform.translation);
        if at == Vec3::ZERO {
            continue;
        }
        plants += 1;
        for s in &scene.geometries[inst.geometry as usize].shapes {
            let p = inst
                .transform
                .transform_point3(s.transform.translation.into());
            assert!(!in_play_area(p), "a plant's shape at {p}");
        }
    }
    assert!(plants > 100, "{plants} plants");
}

#[test]
fn the_built_in_film_is_the_tennis_showcase() {
    let mut loaded = scenes::load(&[], false, Limits::default()).unwrap();
    assert_eq!(loaded.name, "lmfilm");
    let names: Vec<&str> = loaded.texts.iter().map(|t| t.name.as_str()).collect();
    assert_eq!(
        names,
        [
            "built-in:showcase.lm",
            "built-in:match.lm",
            "built-in:landscape.lm"
        ]
    );
    // The texts built into the program are the scene files.
    for (text, file) in loaded.texts.iter().zip(SHOWCASE) {
        assert_eq!(text.bytes, std::fs::read(repo(file)).unwrap(), "{file}");
    }
    let film = &mut loaded.film;
    assert_eq!(film.frame_count(), 351, "14 s at 25 frames per second");
    // The two players and the referee.
    let automata: Vec<_> = film.living().iter().map(|l| l.automata).collect();
    assert_eq!(
        automata,
        [
            Some(Automata::PlayTennis),
            Some(Automata::PlayTennis),
            Some(Automata::Referee)
        ]
    );
    for _ in 0..5 {
        let frame = film.next_frame().unwrap().unwrap();
        no_warnings(frame);
    }
    // It reads no file: its people are built in.
    let frame = film.frame().unwrap();
    assert_eq!(hips(frame.scene()).len(), 3);
    assert!(
        film.referenced_files().is_empty(),
        "{:?}",
        film.referenced_files()
    );
}

/// A frame derived without warnings.
fn no_warnings(frame: &lmfilm::film::Frame) {
    assert!(
        frame.warnings().is_empty(),
        "frame {}: {:?}",
        frame.number(),
        frame.warnings()
    );
}
