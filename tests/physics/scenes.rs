//! The force-field films of scenes/physics (issue 7) derive, and do what
//! their headers say.

use std::path::{Path, PathBuf};

use lmfilm::film::Film;
use lmfilm::turtle::Options;

fn scene(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("scenes/physics")
        .join(name)
}

/// Derives `files` to time `t` and returns the film at that frame.
fn at(files: &[&str], t: f64) -> Film {
    let paths: Vec<PathBuf> = files.iter().map(|f| scene(f)).collect();
    let mut film = Film::load(&paths, Options::default()).unwrap();
    let target = film.frame_at(t);
    film.seek(target, |_, _| {}).unwrap();
    film
}

/// Mean x of the shapes of the tree (its first L-system's geometry).
fn mean_x(film: &mut Film) -> f64 {
    let scene = film.frame().unwrap().scene();
    let g = &scene.geometries[0];
    let xs: Vec<f64> = g
        .shapes
        .iter()
        .map(|s| f64::from(s.transform.translation.x))
        .collect();
    xs.iter().sum::<f64>() / xs.len() as f64
}

#[test]
fn the_ball_s_wind_bends_the_tree_its_way() {
    // The ball flies towards +x: its velocity field pushes the crown +x.
    let calm = mean_x(&mut at(&["tree.lm"], 7.0));
    let mut windy = at(&["tree.lm", "ball.lm"], 7.0);
    let bent = mean_x(&mut windy);
    assert!(bent > calm + 1.0, "calm {calm} bent {bent}");
    let p = windy
        .particles()
        .iter()
        .find(|p| p.pos.is_finite())
        .map(|p| p.pos)
        .unwrap();
    // Launched at 4 s from x = −70 at 20 m/s, 45 m up, nothing else on it.
    assert!(
        (p.x - (-70.0 + 20.0 * 3.0)).abs() < 1e-6 && (p.y - 45.0).abs() < 1e-9,
        "{p}"
    );
}

#[test]
fn the_fish_school_follows_the_bait() {
    let film = at(&["fish.lm"], 8.0);
    let ps = film.particles();
    let bait = ps[0].pos;
    // A fish is born every second at the spawn point: the one the frame
    // at 8 s just placed there has not swum yet.
    let now = film.frame().unwrap().time();
    let fish: Vec<_> = ps[1..]
        .iter()
        .filter(|p| p.pos.is_finite() && p.born < now)
        .collect();
    assert!(fish.len() >= 6, "{} fish", fish.len());
    for f in &fish {
        let d = f.pos.distance(bait);
        assert!(d < 120.0, "a fish strayed {d} from the bait");
    }
    // Fish keep apart: the short-range repulsion prevents collisions.
    for (i, a) in fish.iter().enumerate() {
        for b in &fish[i + 1..] {
            assert!(a.pos.distance(b.pos) > 2.0, "{} {}", a.pos, b.pos);
        }
    }
}

#[test]
fn the_trees_bend_with_their_tropism_force() {
    // Gravity pulls the crown down (y), the strong wind along −x.
    let mut gravity = at(&["tree_gravity.lm"], 5.0);
    let mut weak = at(&["tree_weak_wind.lm"], 5.0);
    let mut strong = at(&["tree_strong_wind.lm"], 5.0);
    let (g, w, s) = (mean_x(&mut gravity), mean_x(&mut weak), mean_x(&mut strong));
    assert!(s < w && w < g + 1.0, "gravity {g} weak {w} strong {s}");
}

#[test]
fn butterflies_circle_the_flower() {
    let film = at(&["butterflies.lm"], 9.0);
    let ps = film.particles();
    let flower = ps[0].pos;
    let flying: Vec<_> = ps[1..].iter().filter(|p| p.pos.is_finite()).collect();
    assert_eq!(flying.len(), 8);
    for b in flying {
        let d = b.pos.distance(flower);
        assert!(
            (3.0..20.0).contains(&d),
            "a butterfly at {d} from the flower"
        );
        // Turning about the stem: mostly horizontal speed, not at rest.
        assert!(
            b.vel.length() > 1.0 && b.vel.y.abs() < b.vel.length() / 2.0,
            "{}",
            b.vel
        );
    }
}

/// `?34` and `?20`: the swim phase of code 4.1.1 grows by 0.2·speed per
/// second, so a particle at 10 m/s has phase 2T radians at time T.
#[test]
fn the_swim_motor_follows_the_speed() {
    let dir = std::env::temp_dir().join(format!("lmfilm_swim_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let scene = dir.join("swim.lm");
    std::fs::write(
        &scene,
        "Camera_AnimationParameters\nt_final_interval 2 0.04\nAxiom\ne () (11) () () (0) (0) (0) C () () (1) () (10) (0) (0) Y () () () () (?34) (?20)\n",
    )
    .unwrap();
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_lmfilm"))
        .args([
            "print",
            scene.to_str().unwrap(),
            "--frame",
            "13",
            "--format",
            "full",
        ])
        .output()
        .unwrap();
    let text = String::from_utf8(out.stdout).unwrap();
    let phase = 2.0f64 * 0.52;
    let want = format!(
        "Y(0.52,0,0,0,{:.6},{:.6},0)",
        phase.to_degrees(),
        phase.sin() * 5.0
    );
    assert!(text.contains(&want), "{text} lacks {want}");
    std::fs::remove_dir_all(&dir).unwrap();
}
