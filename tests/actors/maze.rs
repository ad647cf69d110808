//! The maze film of thesis 7.3.1 (`scenes/actors/maze.lm`), judged from
//! its trace: the actor finds its goal, never walks into a wall, forgets
//! the door that sank away and goes through its gap, and comes home by a
//! shorter way than it went.

use super::support::trace;

/// A wall's extent in the floor plane, and the time it is there until.
struct Wall {
    x: [f64; 2],
    z: [f64; 2],
    until: f64,
}

const fn wall(x0: f64, x1: f64, z0: f64, z1: f64) -> Wall {
    Wall {
        x: [x0, x1],
        z: [z0, z1],
        until: f64::INFINITY,
    }
}

/// The scene's walls (outer, south, north, pillar, pocket) and the door,
/// as `c` draws them: x from the turtle along H, z centred on it.
const WALLS: [Wall; 11] = [
    wall(-12.2, 12.2, 11.8, 12.2),
    wall(-12.2, 12.2, -12.2, -11.8),
    wall(11.8, 12.2, -12.2, 12.2),
    wall(-12.2, -11.8, -12.2, 12.2),
    wall(-8.0, 12.0, -4.2, -3.8),
    wall(-12.0, -2.0, 3.8, 4.2),
    wall(2.0, 8.0, 3.8, 4.2),
    wall(-1.0, 1.0, -1.0, 1.0),
    wall(8.0, 8.4, 4.0, 8.0),
    wall(8.0, 12.0, 7.8, 8.2),
    // The door sinks away at T = 24.
    Wall {
        x: [-2.0, 2.0],
        z: [3.8, 4.2],
        until: 24.0,
    },
];

/// The flowers' stems (x, z).
const FLOWERS: [[f64; 2]; 9] = [
    [-7.0, 9.0],
    [-4.0, 10.5],
    [5.0, 10.0],
    [10.0, 6.5],
    [-6.0, -10.5],
    [7.0, -10.0],
    [10.0, -7.5],
    [6.0, -1.5],
    [-4.0, 0.5],
];

struct ExplorerStep {
    time: f64,
    x: f64,
    z: f64,
    goal: Option<[f64; 3]>,
    state: i64,
}

fn steps() -> Vec<ExplorerStep> {
    trace("scenes/actors/maze.lm")
        .iter()
        .map(|f| {
            let a = &f["actors"][0];
            let p = |v: &serde_json::Value, k: usize| v[k].as_f64().unwrap();
            let goal = a["goal"]
                .as_array()
                .map(|g| [0, 1, 2].map(|k| g[k].as_f64().unwrap()));
            ExplorerStep {
                time: f["time"].as_f64().unwrap(),
                x: p(&a["pos"], 0),
                z: p(&a["pos"], 2),
                goal,
                state: a["state"].as_i64().unwrap(),
            }
        })
        .collect()
}

fn length(steps: &[ExplorerStep]) -> f64 {
    steps
        .windows(2)
        .map(|w| (w[1].x - w[0].x).hypot(w[1].z - w[0].z))
        .sum()
}

/// Where the actor crosses the north wall's line z = 4 going north or
/// south: (time, x).
fn crossings(steps: &[ExplorerStep]) -> Vec<(f64, f64)> {
    steps
        .windows(2)
        .filter(|w| (w[0].z - 4.0).signum() != (w[1].z - 4.0).signum())
        .map(|w| (w[1].time, w[1].x))
        .collect()
}

#[test]
fn the_maze_actor_finds_its_goal_and_comes_home_by_a_shorter_way() {
    let steps = steps();
    // Never in a wall or a stem, its body (size_actor 0.8) included.
    let radius = 0.4;
    for s in &steps {
        for w in WALLS.iter().filter(|w| s.time < w.until) {
            let dx = (w.x[0] - s.x).max(s.x - w.x[1]).max(0.0);
            let dz = (w.z[0] - s.z).max(s.z - w.z[1]).max(0.0);
            assert!(dx.hypot(dz) >= radius, "T = {}: {} {}", s.time, s.x, s.z);
        }
        for [x, z] in FLOWERS {
            assert!((s.x - x).hypot(s.z - z) >= radius, "T = {}", s.time);
        }
    }
    // The way out ends where its goal changes to home.
    let home = Some([0.0, 1.0, -9.0]);
    let turn = steps
        .iter()
        .position(|s| s.goal == home)
        .expect("it reaches the north room");
    let at = &steps[turn];
    assert!(at.x.hypot(at.z - 9.0) < 0.1, "{} {}", at.x, at.z);
    assert!(
        at.time < 40.0,
        "the goal within the frame budget: {}",
        at.time
    );
    let (out, back) = steps.split_at(turn);
    // It saw the door closed, then, with no way left in its memory,
    // explored; it passed through the door's place only after the door
    // had gone, and never crossed the north wall elsewhere on its way out
    // (the pocket is closed).
    assert!(out.iter().any(|s| s.state == 11), "explore mode");
    let through = crossings(out);
    assert!(!through.is_empty());
    for (t, x) in through {
        assert!(t > 24.0 && x.abs() < 2.0 - radius, "T = {t}: x = {x}");
    }
    // Home on its memory alone: through the door's gap again, shorter.
    let last = back.last().unwrap();
    assert!(
        last.x.hypot(last.z + 9.0) < 0.1,
        "home: {} {}",
        last.x,
        last.z
    );
    assert!(crossings(back).iter().all(|&(_, x)| x.abs() < 2.0));
    assert!(
        back.iter().all(|s| s.state != 11),
        "no exploring on the way back"
    );
    let (way_out, way_back) = (length(out), length(back));
    assert!(way_back < 0.7 * way_out, "{way_back} against {way_out}");
}
