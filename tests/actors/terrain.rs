//! The conditional 3D search (thesis 7.3.1, heuristic 9):
//! scenes/actors/terrain.lm, checked against its own boxes.

use super::support::trace;

const SCENE: &str = "scenes/actors/terrain.lm";

/// A box of the scene: x, y, z from min to max.
#[derive(Debug, Clone, Copy)]
struct Box3 {
    min: [f64; 3],
    max: [f64; 3],
}

/// A number of the scene's growth groups: `2.5`, or `2.5_` for −2.5.
fn number(s: &str) -> f64 {
    match s.strip_suffix('_') {
        Some(n) => -n.parse::<f64>().unwrap(),
        None => s.parse().unwrap(),
    }
}

/// The boxes of the scene: every `f () () () (2) (x) (y) (z) c () () ()
/// () (a) (b) (c)`, a box a long in x from (x, y, z), b high, c deep,
/// centred on y and z (the turtle's H = x, L = y, U = z).
fn boxes() -> Vec<Box3> {
    let text =
        std::fs::read_to_string(std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(SCENE))
            .unwrap();
    let mut out = Vec::new();
    for line in text.lines().filter(|l| l.contains(" c () () () () (")) {
        let groups: Vec<&str> = line
            .split(['(', ')'])
            .map(str::trim)
            .filter(|g| !g.is_empty() && !g.starts_with(['[', 'f', 'c', ']']))
            .collect();
        // (2) x y z, then a b c.
        assert_eq!(groups.len(), 7, "{line}");
        let v: Vec<f64> = groups[1..].iter().map(|g| number(g)).collect();
        out.push(Box3 {
            min: [v[0], v[1] - v[4] / 2.0, v[2] - v[5] / 2.0],
            max: [v[0] + v[3], v[1] + v[4] / 2.0, v[2] + v[5] / 2.0],
        });
    }
    assert!(out.len() > 15, "{}", out.len());
    out
}

/// The highest top of a box under (x, z) that is below `y`; the boxes
/// keep 0.01 inside their voxel columns, so the seams between them count
/// as the ground beside.
fn ground(boxes: &[Box3], x: f64, y: f64, z: f64) -> Option<f64> {
    let within = |p: f64, k: usize, b: &Box3| b.min[k] - 0.011 <= p && p <= b.max[k] + 0.011;
    boxes
        .iter()
        .filter(|b| within(x, 0, b) && within(z, 2, b))
        .map(|b| b.max[1])
        .filter(|&top| top <= y)
        .reduce(f64::max)
}

fn actor(f: &serde_json::Value) -> serde_json::Value {
    f["actors"][0].clone()
}

fn pos(f: &serde_json::Value) -> [f64; 3] {
    let p = actor(f)["pos"].clone();
    [0, 1, 2].map(|k| p[k].as_f64().unwrap())
}

fn near(p: [f64; 3], q: [f64; 3]) -> bool {
    (0..3).map(|k| (p[k] - q[k]).powi(2)).sum::<f64>().sqrt() < 0.1
}

const START: [f64; 3] = [-10.75, 0.75, 2.25];
const GOAL: [f64; 3] = [2.75, 2.75, 2.25];

#[test]
fn the_terrain_actor_explores_to_its_goal_then_plans_its_way_back() {
    let frames = trace(SCENE);
    // No path at first (no support seen): it observes, then explores.
    assert!(frames.iter().any(|f| actor(f)["automata"] == "observe"));
    let explored = frames
        .iter()
        .position(|f| actor(f)["state"] == 11)
        .expect("it explores");
    assert!(explored < 20, "{explored}");
    let there = frames
        .iter()
        .position(|f| near(pos(f), GOAL))
        .expect("it reaches its goal on the higher floor");
    assert!(there < 1200, "{there}");
    assert!(frames[..there].iter().any(|f| actor(f)["state"] == 11));
    // At the goal its memory holds the way: the way back is planned
    // (state 10, move) and walked without exploring.
    let back = &frames[there + 2..];
    assert!(back.iter().all(|f| actor(f)["state"] != 11));
    assert!(back.iter().any(|f| actor(f)["state"] == 10));
    let home = back
        .iter()
        .position(|f| actor(f)["automata"] == "watch")
        .expect("it comes back to its start");
    assert!(near(pos(&back[home]), START), "{:?}", pos(&back[home]));
    assert!(there + 2 + home < frames.len());
}

#[test]
fn the_terrain_actor_never_falls() {
    let boxes = boxes();
    let frames = trace(SCENE);
    let mut highest: f64 = 0.0;
    let mut on_bridge = 0;
    for f in &frames {
        let [x, y, z] = pos(f);
        let n = &f["frame"];
        highest = highest.max(y);
        // Its eye is in no box and stands 0.5 above the ground under it
        // (0.25–0.75 halfway up or down a step); under every corner of
        // its body (0.4 across) there is ground at most one step (0.5)
        // lower (its corners may reach over a step's edge as it climbs):
        // never over the void or an edge.
        assert!(
            !boxes.iter().any(|b| (0..3).all(|k| {
                let p = [x, y, z][k];
                b.min[k] < p && p < b.max[k]
            })),
            "frame {n}: the eye {x} {y} {z} is inside a box"
        );
        for (dx, dz) in [
            (0.0, 0.0),
            (-0.2, -0.2),
            (-0.2, 0.2),
            (0.2, -0.2),
            (0.2, 0.2),
        ] {
            let g = ground(&boxes, x + dx, y, z + dz);
            let h = g.map(|g| y - g);
            let range = if dx == 0.0 && dz == 0.0 {
                0.2..=0.8
            } else {
                0.0..=1.0
            };
            assert!(
                h.is_some_and(|h| range.contains(&h)),
                "frame {n}: at {x} {y} {z} (corner {dx} {dz}) the ground is {g:?}"
            );
        }
        // Over the gap between the plateaus (x from −1.5 to 1.5) only on
        // the bridge (z from −6 to −4).
        if (-1.5..1.5).contains(&x) {
            assert!(
                (-5.8..-4.2).contains(&z) && (y - 2.75).abs() < 1e-3,
                "frame {n}: {x} {y} {z}"
            );
            on_bridge += 1;
        }
    }
    // It did climb to the higher floor and cross the bridge.
    assert!((highest - 2.75).abs() < 1e-3, "{highest}");
    assert!(on_bridge > 10, "{on_bridge}");
}
