//! Walking on sparse foothold locations (issue 17, thesis 5.9): the map
//! an actor extracts from its own vision, and `walk_stepworthy` on the
//! stepping stones of scenes/actors/footholds.lm — both destinations
//! reached, never a step where there is no stone, the sunk stone seen and
//! walked around, turtle 1's colours, and the same walk for 1 and 2
//! threads.

use glam::{Vec2, Vec3};
use lmfilm::actors::footholds::map::{local_map, Region};
use lmfilm::actors::footholds::plan::Foot;

use super::support::{film, same_for_one_and_two_threads, scene, trace_bytes, written};

const SCENE: &str = "scenes/actors/footholds.lm";
/// The stones' half edge, and the memory's voxel edge, in the scene.
const HALF: f32 = 0.15;
const VOXEL: f32 = 0.05;

/// A stepping stone of the scene: its centre (x, z), and when it starts
/// to sink (None: never).
#[derive(Debug, Clone, Copy)]
struct Stone {
    at: Vec2,
    sinks: Option<f64>,
}

/// A number of the scene: `1.5_` is −1.5.
fn number(s: &str) -> f32 {
    match s.strip_suffix('_') {
        Some(n) => -n.parse::<f32>().unwrap(),
        None => s.parse().unwrap(),
    }
}

/// The stones of a scene text: its `f () () () (2) (x) (y) (z)` lines
/// drawn in material 16; a sinking one has `T ts -` in its y.
fn stones(text: &str) -> Vec<Stone> {
    text.lines()
        .filter(|l| l.starts_with("[ m () (16) $ () () (3) f () () () (2) ("))
        .map(|l| {
            let groups: Vec<&str> = l.split('(').map(|g| g.split(')').next().unwrap()).collect();
            // groups: "[ m ", "", "16", …: x, y, z follow "2".
            let at = groups.iter().position(|g| *g == "2").unwrap();
            let y = groups[at + 2];
            Stone {
                at: Vec2::new(number(groups[at + 1]), number(groups[at + 3])),
                sinks: y
                    .strip_prefix("T ")
                    .map(|r| r.split(' ').next().unwrap().parse().unwrap()),
            }
        })
        .collect()
}

fn scene_text() -> String {
    std::fs::read_to_string(std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(SCENE)).unwrap()
}

/// The scene's trace, as JSON values, for a scene text written beside it.
fn trace_of(text: &str, name: &str) -> Vec<serde_json::Value> {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("footholds");
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    String::from_utf8(trace_bytes(path.to_str().unwrap(), &[], None))
        .unwrap()
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect()
}

fn v3(v: &serde_json::Value) -> Vec3 {
    Vec3::new(
        v[0].as_f64().unwrap() as f32,
        v[1].as_f64().unwrap() as f32,
        v[2].as_f64().unwrap() as f32,
    )
}

/// The footholds the actor stood on, in order, with the frame's time.
fn stood_on(frames: &[serde_json::Value]) -> Vec<(f64, Vec3)> {
    let mut on: Vec<(f64, Vec3)> = Vec::new();
    for f in frames {
        let p = &f["actors"][0]["footing"]["on"];
        if p.is_null() {
            continue;
        }
        let p = v3(p);
        if on.last().is_none_or(|l| l.1 != p) {
            on.push((f["time"].as_f64().unwrap(), p));
        }
    }
    on
}

fn ground(p: Vec3) -> Vec2 {
    Vec2::new(p.x, p.z)
}

#[test]
fn the_actor_reaches_both_destinations_stepping_on_stones_only() {
    let text = scene_text();
    let field = stones(&text);
    assert!(field.len() > 80, "{}", field.len());
    let frames = trace_of(&text, "walk.lm");
    let on = stood_on(&frames);
    assert!(on.len() > 15, "{on:?}");
    for &(t, p) in &on {
        // On a stone that has not sunk: within its top (one voxel of slack
        // for the map's mean).
        let under = field.iter().find(|s| {
            let d = (ground(p) - s.at).abs();
            d.x <= HALF + VOXEL && d.y <= HALF + VOXEL
        });
        let stone = under.unwrap_or_else(|| panic!("a step at {p} (T = {t}) on no stone"));
        assert!(
            stone.sinks.is_none_or(|ts| t < ts),
            "on the sunk stone at {t}"
        );
    }
    // Steps are shorter than Df_max (1), and the feet alternate.
    for w in on.windows(2) {
        assert!(ground(w[0].1).distance(ground(w[1].1)) < 1.0, "{w:?}");
    }
    // Both destinations, in the order of the goal stack (the last given
    // is popped first): it stands within a longest step of each.
    let near = |g: Vec2| on.iter().position(|&(_, p)| ground(p).distance(g) < 1.0);
    let first = near(Vec2::new(3.1, 0.6)).expect("the first destination");
    let second = near(Vec2::new(-2.5, 3.5)).expect("the second destination");
    assert!(first < second);
    // Then the next behaviour runs.
    let last = frames.last().unwrap();
    assert_eq!(last["actors"][0]["automata"], "watch");
}

#[test]
fn the_sunk_stone_makes_the_actor_plan_again() {
    let text = scene_text();
    let field = stones(&text);
    let sunk = field.iter().find(|s| s.sinks.is_some()).unwrap();
    let replans = |frames: &[serde_json::Value]| {
        frames.last().unwrap()["actors"][0]["footing"]["replans"]
            .as_u64()
            .unwrap()
    };
    let planned_over = |frames: &[serde_json::Value]| {
        frames.iter().any(|f| {
            let ahead = f["actors"][0]["footing"]["ahead"].as_array().cloned();
            ahead
                .unwrap_or_default()
                .iter()
                .any(|p| ground(v3(p)).distance(sunk.at) < HALF)
        })
    };
    // With the stone staying, the plan crosses it and nothing interrupts
    // the walk.
    let start = text.find("(T ").unwrap();
    let end = start + text[start..].find(')').unwrap() + 1;
    let still = format!("{}(1.5_){}", &text[..start], &text[end..]);
    let calm = trace_of(&still, "still.lm");
    assert!(planned_over(&calm));
    assert_eq!(replans(&calm), 0);
    let calm_on = stood_on(&calm);
    assert!(calm_on
        .iter()
        .any(|(_, p)| ground(*p).distance(sunk.at) < HALF + VOXEL));
    // Sunk: the memory forgets it, the path has an obstacle, the actor
    // looks around and plans a way that does not use it.
    let frames = trace_of(&text, "sinks.lm");
    assert!(replans(&frames) >= 1);
    let on = stood_on(&frames);
    assert!(on
        .iter()
        .all(|(_, p)| ground(*p).distance(sunk.at) > HALF + VOXEL));
    let replanned = frames
        .iter()
        .position(|f| f["actors"][0]["footing"]["replans"] == 1)
        .unwrap();
    let t = frames[replanned]["time"].as_f64().unwrap();
    assert!(
        t > sunk.sinks.unwrap(),
        "re-planned at {t}, before the stone sank"
    );
    assert!(frames[replanned..replanned + 30]
        .iter()
        .any(|f| f["actors"][0]["automata"] == "observe"));
}

#[test]
fn a_box_set_on_a_planned_stone_makes_the_actor_plan_around_it() {
    // The sinking stone stays, and at T = 3.8 a crate rises onto it from
    // the water: a foothold blocked during the film.
    let text = scene_text();
    let stone = stones(&text)
        .into_iter()
        .find(|s| s.sinks.is_some())
        .unwrap();
    let start = text.find("(T ").unwrap();
    let end = start + text[start..].find(')').unwrap() + 1;
    let crate_line = format!(
        "[ m () (2) $ () () (3) f () () () (2) ({}) (T 3.8 - 0.5 / ?08 0.9 * 0.5 - ) ({}) + () () () () (90) c () () () () (0.5) (0.24) (0.24) ]\n",
        written(stone.at.x),
        written(stone.at.y)
    );
    let text = format!("{}(1.5_){}", &text[..start], &text[end..]).replace(
        "/* the stepping stones */\n",
        &format!("/* the stepping stones */\n{crate_line}"),
    );
    let frames = trace_of(&text, "crate.lm");
    let footing = &frames.last().unwrap()["actors"][0]["footing"];
    assert!(footing["replans"].as_u64().unwrap() >= 1, "{footing}");
    let on = stood_on(&frames);
    assert!(on
        .iter()
        .all(|(_, p)| ground(*p).distance(stone.at) > HALF + VOXEL));
    assert_eq!(frames.last().unwrap()["actors"][0]["automata"], "watch");
}

#[test]
fn the_map_from_the_actors_own_vision_holds_every_stone_and_no_phantom() {
    // Nine stones (0.3 × 0.3, tops at y = 0) around an actor whose eye is
    // 1.5 above the field; it looks around once (observe), then watches.
    let stones: Vec<Vec2> = [
        (1.2, 0.0),
        (-1.1, 0.3),
        (0.2, 1.4),
        (-0.4, -1.3),
        (1.5, 1.2),
        (-1.6, -1.0),
        (1.0, -1.6),
        (-1.3, 1.7),
        (2.2, -0.4),
    ]
    .iter()
    .map(|&(x, z)| Vec2::new(x, z))
    .collect();
    let mut axiom = String::from("D () (15)\n");
    for s in &stones {
        axiom += &format!(
            "[ $ () () (3) f () () () (2) ({}) (0.4_) ({}) + () () () () (90) c () () () () (0.4) (0.3) (0.3) ]\n",
            written(s.x),
            written(s.y)
        );
    }
    let options = "NBR_actors 1\niVisionWinSize 0 96 8\n\
        actorNbr_automata 0 observe init 10 -6.425 6.375 0.05 obs 0 1.5 0 lat 0 0 1.5 fov 900 vision_range 0.3 12 12\n\
        actorNbr_automata 0 watch";
    let mut f = film(&scene(1.0, options, &axiom, ""));
    while f.next_frame().unwrap().is_some() {}
    let actor = &f.living()[0];
    assert_eq!(actor.automata.map(|a| a.name()), Some("watch"));
    let memory = actor.memory.as_ref().unwrap().octree();
    let region = Region {
        centre: actor.eye,
        range: 3.0,
        plane: 0.0,
    };
    let map = local_map(memory, &region, 4, 0.3);
    for s in &stones {
        let found = map.iter().find(|m| {
            let d = (m.ground() - *s).abs();
            d.x <= VOXEL && d.y <= VOXEL
        });
        assert!(found.is_some(), "stone {s} not within a voxel: {map:?}");
    }
    assert_eq!(map.len(), stones.len(), "phantom stones: {map:?}");
}

#[test]
fn every_map_of_the_walk_holds_each_stone_once_and_nothing_else() {
    // Far stones seen at a grazing angle come in pieces; the map joins
    // them (docs/footholds.md), so no map holds a phantom or a stone twice.
    let text = scene_text();
    let field = stones(&text);
    let frames = trace_of(&text, "maps.lm");
    let mut maps = 0;
    let mut last = serde_json::Value::Null;
    for f in &frames {
        let map = &f["actors"][0]["footing"]["map"];
        if map.is_null() || *map == last {
            continue;
        }
        last = map.clone();
        maps += 1;
        let mut on = vec![0; field.len()];
        for m in map.as_array().unwrap() {
            let p = Vec2::new(m[0].as_f64().unwrap() as f32, m[2].as_f64().unwrap() as f32);
            let k = field
                .iter()
                .position(|s| {
                    let d = (p - s.at).abs();
                    d.x <= HALF + VOXEL && d.y <= HALF + VOXEL
                })
                .unwrap_or_else(|| panic!("frame {}: a phantom at {p}", f["frame"]));
            on[k] += 1;
        }
        assert!(
            on.iter().all(|&n| n <= 1),
            "frame {}: a stone in pieces",
            f["frame"]
        );
    }
    assert!(maps >= 3, "{maps}");
    // By the end it has seen the whole field.
    assert!(
        last.as_array().unwrap().len() >= field.len() - 1,
        "{}",
        last.as_array().unwrap().len()
    );
}

#[test]
fn turtle_1_colours_the_actor_by_its_feet() {
    let mut f = film(&scene_text());
    let (mut white, mut yellow, mut red) = (0, 0, 0);
    for n in (40..400).step_by(9) {
        // A frame draws the actor as the frame before left it.
        f.seek(n - 1, |_, _| {}).unwrap();
        let a = &f.living()[0];
        let eye = a.eye;
        let want = if a.footing.turning() {
            red += 1;
            4
        } else {
            match a.footing.foot {
                Some(Foot::Right) => {
                    white += 1;
                    7
                }
                Some(Foot::Left) => {
                    yellow += 1;
                    5
                }
                None => continue,
            }
        };
        // What is drawn: (a point of it, its material).
        let drawn: Vec<(Vec3, u32)> = {
            let frame = f.seek(n, |_, _| {}).unwrap();
            let g = &frame.scene().geometries[0];
            g.shapes
                .iter()
                .map(|s| (Vec3::from(s.transform.translation), s.material))
                .chain(g.triangles.iter().map(|t| (t.v[0], t.material)))
                .collect()
        };
        // The body: what is drawn in its box under the eye.
        let body: Vec<u32> = drawn
            .iter()
            .filter(|(p, _)| p.distance(eye) < 0.8 && p.y < eye.y + 0.1 && p.y > eye.y - 0.75)
            .map(|d| d.1)
            .collect();
        assert!(!body.is_empty(), "frame {n}: no body drawn near {eye}");
        assert!(
            body.iter().all(|&m| m == want),
            "frame {n}: {body:?}, want {want}"
        );
    }
    assert!(white > 3 && yellow > 3 && red > 0, "{white} {yellow} {red}");
}

#[test]
fn the_walk_is_the_same_for_one_and_two_threads() {
    same_for_one_and_two_threads(SCENE, &["--frames", "0..220"], "\"replans\": 1");
}
