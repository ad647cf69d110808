//! The set of the tennis match (`scenes/tennis/match.lm`'s court, chair
//! and sky, `scenes/tennis/landscape.lm`'s plants and camera), the
//! referee's head it imports (`scenes/meshes/head.obj`, written by
//! `scripts/head_mesh.py`), and the built-in film that shows them
//! (`scenes/tennis/showcase.lm` first).

use std::path::{Path, PathBuf};

use glam::Vec3;
use lmfilm::commands::scenes;
use lmfilm::film::Film;
use lmfilm::lsys::automata::Automata;
use lmfilm::lsys::Limits;
use lmfilm::scene::obj::read_obj;
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

/// Where the scene's header puts the neck of the referee's head.
const HEAD: Vec3 = Vec3::new(0.0, 2.6, -7.0);

/// The play area: nothing of the set stands in it but the court, the net
/// and the umpire's chair with the referee.
fn in_play_area(p: Vec3) -> bool {
    p.x.abs() < 18.0 && p.z.abs() < 10.0
}

#[test]
fn the_head_mesh_imports_with_its_own_colours() {
    let (tris, materials) = read_obj(&repo("scenes/meshes/head.obj"), 0).unwrap();
    assert!(tris.len() > 1000, "{} triangles", tris.len());
    assert!(tris.len() <= 8000, "{} triangles", tris.len());
    let names: Vec<&str> = materials.iter().map(|m| m.name.as_str()).collect();
    for name in ["head_skin", "head_hair", "head_eye_white", "head_iris"] {
        assert!(names.contains(&name), "{name} not in {names:?}");
    }
    // Every face names a material of head.mtl: no default grey appended.
    assert!(tris.iter().all(|t| {
        let m = &materials[t.material as usize];
        m.name.starts_with("head_")
    }));
    let skin = &materials[names.iter().position(|n| *n == "head_skin").unwrap()];
    assert!(skin.diffuse.x > skin.diffuse.y && skin.diffuse.y > skin.diffuse.z);
    // About 0.25 m wide, 0.3 m high, the neck's base at the origin; the
    // nose (the front) towards +z.
    let (mut lo, mut hi) = (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN));
    for t in &tris {
        for v in t.v {
            lo = lo.min(v);
            hi = hi.max(v);
        }
    }
    assert!((0.2..0.3).contains(&(hi.x - lo.x)), "{lo} {hi}");
    assert!(
        (0.27..0.34).contains(&hi.y) && lo.y.abs() < 1e-6,
        "{lo} {hi}"
    );
    assert!(hi.z > 0.1 && lo.z > -0.13, "{lo} {hi}");
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
    // The head is placed once, at the chair, with its colours.
    let heads: Vec<_> = scene
        .instances
        .iter()
        .filter(|i| {
            let g = &scene.geometries[i.geometry as usize];
            g.triangles.len() > 1000
        })
        .collect();
    assert_eq!(heads.len(), 1);
    assert!(Vec3::from(heads[0].transform.translation).distance(HEAD) < 1e-4);
    assert!(scene.materials.iter().any(|m| m.name == "head_skin"));
    // The plants (every instance but the main word and the head) stand
    // out of the play area: their shapes' origins, in the world.
    let mut plants = 0;
    for inst in &scene.instances {
        let at = Vec3::from(inst.transform.translation);
        if at == Vec3::ZERO || at.distance(HEAD) < 1e-4 {
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
    // The head is the built-in copy of head.obj, with its colours,
    // whatever the current folder holds.
    let frame = film.frame().unwrap();
    let scene = frame.scene();
    assert!(scene.geometries.iter().any(|g| g.triangles.len() > 1000));
    assert!(scene.materials.iter().any(|m| m.name == "head_skin"));
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
