//! The behaviour stack and the simple automata (thesis 5.1, 5.3–5.5,
//! 6.3.4, C.6): scripts popped in order, `observe` turning once around,
//! `walk_local`, `auto_align`, `talk` and `listen` through the sound
//! events, `e` par1 = 0 switching control, `?35` seeing it.

use lmfilm::film::Film;
use lmfilm::lsys::print::Format;
use lmfilm::lsys::Source;
use lmfilm::sound::events::Event;
use lmfilm::turtle::Options;

use super::support::{film, same_for_one_and_two_threads, scene, trace};

/// A closed room 20 × 4 × 20 around the origin, floor at y = 0.
const ROOM: &str = "[ f () () () (2) (10_) (2) (10) c () () () () (20) (4) (0.4) ] \
    [ f () () () (2) (10_) (2) (10_) c () () () () (20) (4) (0.4) ] \
    [ f () () () (2) (10) (2) (0) c () () () () (0.4) (4) (20) ] \
    [ f () () () (2) (10_) (2) (0) c () () () () (0.4) (4) (20) ] \
    [ f () () () (2) (10_) (0.5_) (0) c () () () () (20) (1) (20) ]";

fn automata(f: &Film) -> Option<&'static str> {
    f.living()[0].automata.map(|a| a.name())
}

#[test]
fn observe_turns_once_around_then_the_next_script_runs() {
    // 60° view: 30° a frame, 12 frames for the turn.
    let options = "NBR_actors 1\niVisionWinSize 0 32 8\n\
        actorNbr_automata 0 observe init 1 -16 16 0.5 obs 0 1 0 lat 0 1 1 fov 600\n\
        actorNbr_automata 0 watch";
    let mut f = film(&scene(1.0, options, ROOM, ""));
    let mut seen = Vec::new();
    while let Some(frame) = f.next_frame().unwrap() {
        let n = frame.number();
        let a = &f.living()[0];
        seen.push((n, a.automata.unwrap().name(), a.look_at - a.eye));
    }
    let turning: Vec<_> = seen.iter().filter(|s| s.1 == "observe").collect();
    assert_eq!(turning.len(), 12, "{seen:?}");
    assert_eq!(seen[12].1, "watch");
    // Back where it looked first.
    assert!(
        (seen[12].2 - glam::Vec3::Z).length() < 1e-4,
        "{:?}",
        seen[12].2
    );
    // It saw all four walls: its memory holds voxels on each.
    let memory = f.living()[0].memory.as_ref().unwrap().octree();
    // Inner faces: x = 10 and −9.6, z = 9.8 and −9.8.
    let walls = [
        [10.05, 2.0, 0.0],
        [-9.65, 2.0, 0.0],
        [0.0, 2.0, 9.85],
        [0.0, 2.0, -9.85],
    ];
    for w in walls {
        let v = memory.voxel(w).unwrap();
        assert!(memory.get(v).is_some(), "wall at {w:?} not memorised");
    }
}

#[test]
fn walk_local_reaches_its_goal_around_a_post() {
    // A post stands between the actor and its local goal.
    let options = "NBR_actors 1\niVisionWinSize 0 32 8\n\
        actorNbr_automata 0 walk_local obs 0 1 -6 lat 0 1 0 local_goal 0 1 6 \
        eps_arrived 0.3 dist_coll 2 size_actor 1 speed 2";
    let post = "[ f () () () (2) (0) (0) (0) + () () () () (90) c () () () () (3) (1) (1) ]";
    let mut f = film(&scene(12.0, options, post, ""));
    let mut closest = f32::MAX;
    while f.next_frame().unwrap().is_some() {
        let a = &f.living()[0];
        // Never inside the post (half an edge 0.5, plus a margin).
        assert!(a.eye.x.abs() > 0.5 || a.eye.z.abs() > 0.5, "{}", a.eye);
        closest = closest.min(a.eye.distance(glam::Vec3::new(0.0, 1.0, 6.0)));
        if a.automata.is_none() {
            break;
        }
    }
    assert!(
        automata(&f).is_none(),
        "still walking at {}",
        f.living()[0].eye
    );
    assert!(closest < 0.3, "{closest}");
}

#[test]
fn auto_align_turns_to_the_align_point() {
    let options = "NBR_actors 1\nactorNbr_automata 0 19 obs 0 1 0 lat 0 1 1 align -5 1 0\n\
        actorNbr_automata 0 watch";
    let mut f = film(&scene(2.0, options, "F", ""));
    f.seek(40, |_, _| {}).unwrap();
    let a = &f.living()[0];
    assert_eq!(automata(&f), Some("watch"));
    let d = (a.look_at - a.eye).normalize();
    assert!((d - glam::Vec3::new(-1.0, 0.0, 0.0)).length() < 1e-3, "{d}");
}

#[test]
fn talk_says_its_words_in_turn_and_listen_hears_them() {
    // Actor 0 says sounds 6 (start, 0.05 s) and 2 (cricket) one after
    // the other; actor 1 listens to actor 0's voice (source 2000).
    let options = "NBR_actors 2\n\
        actorNbr_automata 0 talk words_to_speak 6 2 6 obs 0 1 0\n\
        actorNbr_automata 1 listen listen_to 2000 3 obs 2 1 0\n\
        actorNbr_automata 1 watch";
    let mut f = film(&scene(8.0, options, "F", ""));
    while f.next_frame().unwrap().is_some() {}
    let said: Vec<(String, u32, f64)> = f
        .events()
        .events()
        .filter_map(|(t, e)| match e {
            Event::Play { n, file } => Some((file.clone(), *n, t.unwrap())),
            _ => None,
        })
        .collect();
    let files: Vec<&str> = said
        .iter()
        .map(|e| e.0.split('.').next().unwrap())
        .collect();
    assert_eq!(files, ["start", "cricket", "start"], "{said:?}");
    assert!(said.iter().all(|e| e.1 == 2000));
    // No overlap: each word starts once the one before has ended.
    assert!(
        said[1].2 >= said[0].2 + 0.04 && said[2].2 > said[1].2 + 1.0,
        "{said:?}"
    );
    let a = &f.living()[0];
    assert!(a.automata.is_none() && a.conversation.words.is_empty());
    let b = &f.living()[1];
    assert_eq!(b.conversation.heard_words, [6, 2, 6]);
    assert_eq!(b.automata.map(|a| a.name()), Some("watch"));
}

#[test]
fn e_switches_control_and_the_productions_see_it() {
    // The actor starts under the productions (L-system, 11); at 0.2 s an
    // `e` hands it to observe (2), which ?35 then reads.
    let options = "NBR_actors 1\niVisionWinSize 0 8 4\n\
        actorNbr_automata 0 L-system obs 0 1 0 lat 0 1 1";
    let prods = "A (0.2)\n1.0 e () (0) () () (observe fov 900) B EndProb\nEnd\n\
                 B (0) [(?35 2 -)=]\n1.0 C EndProb\nEnd\n";
    let mut f = film(&scene(1.0, options, "[ M () (7) () (0) A ]", prods));
    f.seek(4, |_, _| {}).unwrap();
    assert_eq!(automata(&f), Some("L-system"));
    assert_eq!(f.words(Format::Symbols), ["[MA]"]);
    f.seek(6, |_, _| {}).unwrap();
    assert_eq!(automata(&f), Some("observe"));
    assert_eq!(f.living()[0].fov, 900);
    f.next_frame().unwrap();
    assert_eq!(f.words(Format::Symbols), ["[MC]"]);
}

#[test]
fn a_behaviour_for_no_actor_is_refused_where_it_stands() {
    let text = scene(1.0, "NBR_actors 1", "e () (0) () () (3 observe) A", "");
    let e = Film::from_sources(&[Source::new("b.lm", &text)], None, Options::default())
        .err()
        .unwrap()
        .to_string();
    assert!(
        e.contains("b.lm:6:17:") && e.contains("actor 3 does not exist"),
        "{e}"
    );
    let text = scene(1.0, "", "e () (0) () () (observe) A", "");
    let e = Film::from_sources(&[Source::new("b.lm", &text)], None, Options::default())
        .err()
        .unwrap()
        .to_string();
    assert!(e.contains("b.lm:6:17:") && e.contains("has none"), "{e}");
}

#[test]
fn the_random_walker_hears_each_collision_once() {
    // Code 5.10.3: ?40 on the walls' field (10 N beyond |x| or |z| = 8.5).
    let frames = trace("scenes/actors/random_walk.lm");
    let hits: Vec<(u64, [f64; 3])> = frames
        .iter()
        .flat_map(|f| {
            let n = f["frame"].as_u64().unwrap();
            f["sound_events"].as_array().unwrap().iter().map(move |e| {
                let p = e["pos"].as_array().unwrap();
                (n, [0, 1, 2].map(|k| p[k].as_f64().unwrap()))
            })
        })
        .collect();
    assert!(hits.len() >= 2, "{hits:?}");
    for w in hits.windows(2) {
        assert!(w[1].0 > w[0].0 + 5, "one collision, one sound: {hits:?}");
    }
    for (_, p) in &hits {
        let edge = p[0].abs().max(p[2].abs());
        assert!((8.5..8.8).contains(&edge), "heard at {p:?}");
    }
}

#[test]
fn the_pledge_actor_escapes_the_room() {
    // Code 5.10.2: it leaves through the gap in the east wall (x = 9.8),
    // never crossing a wall on the way.
    let frames = trace("scenes/actors/pledge.lm");
    let pos = |f: &serde_json::Value| -> [f64; 3] {
        let p = f["actors"][0]["pos"].as_array().unwrap();
        [0, 1, 2].map(|k| p[k].as_f64().unwrap())
    };
    let last = pos(frames.last().unwrap());
    assert!(last[0] > 10.5, "{last:?}");
    for f in &frames {
        let [x, _, z] = pos(f);
        let inside = x < 9.3;
        let in_gap = (1.5..5.5).contains(&z);
        assert!(
            inside || in_gap || x > 10.5,
            "in a wall at frame {}: {x} {z}",
            f["frame"]
        );
        assert!(
            x > -9.7 && z.abs() < 9.7,
            "in a wall at frame {}: {x} {z}",
            f["frame"]
        );
    }
}

#[test]
fn follow_turtle_goes_where_the_turtle_is() {
    // The turtle moves along x at 2 units a second; the actor follows it.
    let options = "NBR_actors 1\nactorNbr_automata 0 follow_turtle obs 5 5 5";
    let axiom =
        "[ f () () () (2) (T 2 *) (1) (0) M () (7) () (0) c () () () () (0.5) (0.2) (0.2) ]";
    let mut f = film(&scene(1.0, options, axiom, ""));
    let frame = f.seek(10, |_, _| {}).unwrap();
    // The turtle stayed: the box is drawn where the turtle was.
    let box_at = frame.scene().geometries[0].shapes[0].transform.translation;
    assert!(
        (box_at - glam::Vec3A::new(0.8, 1.0, 0.0)).length() < 1e-5,
        "{box_at}"
    );
    let a = &f.living()[0];
    assert!(
        (a.eye - glam::Vec3::new(0.8, 1.0, 0.0)).length() < 1e-5,
        "{}",
        a.eye
    );
    assert!((a.look_at - a.eye - glam::Vec3::X).length() < 1e-5);
}

#[test]
fn the_interactive_racket_is_driven_by_the_turtle() {
    // turtle 4 (6.3.4), offline: whatever drives the turtle (here the
    // time; in a film an imported trajectory) drives the actor.
    let options = "NBR_actors 1\nactorNbr_automata 0 watch turtle 4 obs 5 5 5";
    let axiom = "[ f () () () (2) (T 2 *) (1) (0) M () (7) () (0) ]";
    let mut f = film(&scene(1.0, options, axiom, ""));
    f.seek(10, |_, _| {}).unwrap();
    let a = &f.living()[0];
    assert!(
        (a.eye - glam::Vec3::new(0.8, 1.0, 0.0)).length() < 1e-5,
        "{}",
        a.eye
    );
    // With turtle 0 the actor leads: it stays where it was.
    let mut f = film(&scene(
        1.0,
        &options.replace("turtle 4", "turtle 0"),
        axiom,
        "",
    ));
    f.seek(10, |_, _| {}).unwrap();
    assert_eq!(f.living()[0].eye, glam::Vec3::new(5.0, 5.0, 5.0));
}

#[test]
fn the_navigating_actor_plans_around_the_wall_to_its_goal() {
    // scenes/actors/navigate.lm: from (0 1 −6) to (0 1 6) around a wall
    // x ∈ [−6, 6], z ∈ [−0.2, 0.2], through a room it has not seen.
    let frames = trace("scenes/actors/navigate.lm");
    let pos = |f: &serde_json::Value| -> [f64; 3] {
        let p = f["actors"][0]["pos"].as_array().unwrap();
        [0, 1, 2].map(|k| p[k].as_f64().unwrap())
    };
    for f in &frames {
        let [x, _, z] = pos(f);
        // Never in the wall, its body (radius 0.3) included.
        assert!(
            x.abs() > 6.3 || z.abs() > 0.5,
            "frame {}: {x} {z}",
            f["frame"]
        );
        assert!(
            x.abs() < 9.5 && z.abs() < 9.5,
            "frame {}: {x} {z}",
            f["frame"]
        );
    }
    let arrived = frames
        .iter()
        .position(|f| f["actors"][0]["automata"] == "watch")
        .expect("it reaches its goal");
    let [x, _, z] = pos(&frames[arrived]);
    assert!(x.abs() < 0.1 && (z - 6.0).abs() < 0.1, "{x} {z}");
    // About 20 m around the wall at up to 2 m/s: within the film's 16 s.
    assert!(arrived < 400, "{arrived}");
}

#[test]
fn the_shown_path_is_drawn_for_the_viewer_only() {
    let text = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/actors/navigate.lm"),
    )
    .unwrap();
    let mut f = film(&text);
    let frame = f.seek(5, |_, _| {}).unwrap();
    let overlay = lmfilm::scene::shape::OVERLAY;
    let shown = frame.scene().geometries[0]
        .shapes
        .iter()
        .filter(|s| s.symbol == overlay)
        .count();
    assert!(shown > 10, "{shown}");
    // The actor's window never shows them: no pixel at a key point.
    let a = &f.living()[0];
    let window = a.window.as_ref().unwrap();
    for p in window.pixels.iter().filter(|p| p.hit()) {
        assert_ne!(p.object, u32::MAX);
        let near_key = a
            .navigation
            .path
            .iter()
            .any(|k| k.distance(p.position) < 0.09);
        assert!(!near_key, "the actor sees its path at {}", p.position);
    }
}

#[test]
fn without_a_path_the_actor_explores_to_its_goal() {
    // scenes/actors/explore.lm: heuristic 7 needs a known support, so
    // no plan exists at first; it observes, then explores (state 11).
    let frames = trace("scenes/actors/explore.lm");
    let actor = |f: &serde_json::Value| f["actors"][0].clone();
    assert!(frames.iter().any(|f| actor(f)["state"] == 11));
    assert!(frames.iter().any(|f| actor(f)["automata"] == "observe"));
    let done = frames
        .iter()
        .position(|f| actor(f)["automata"] == "watch")
        .expect("it reaches its goal");
    let p = actor(&frames[done])["pos"].clone();
    let [x, z] = [0, 2].map(|k| p[k].as_f64().unwrap());
    assert!(x.abs() < 0.1 && (z - 6.0).abs() < 0.1, "{x} {z}");
    for f in &frames {
        let p = actor(f)["pos"].clone();
        let [x, z] = [0, 2].map(|k| p[k].as_f64().unwrap());
        assert!(x.abs() > 6.3 || z.abs() > 0.5, "in the wall: {x} {z}");
    }
}

#[test]
fn navigation_is_the_same_for_one_and_two_threads() {
    same_for_one_and_two_threads(
        "scenes/bench/maze_20_actors.lm",
        &["--frames", "0..80"],
        "walk_continuously",
    );
}

/// The positions of actor 0 in each frame of `text`, derived in-process.
fn walk(text: &str) -> Vec<glam::Vec3> {
    let mut f = film(text);
    let mut out = Vec::new();
    while f.next_frame().unwrap().is_some() {
        out.push(f.living()[0].eye);
    }
    out
}

#[test]
fn local_optimisation_shortens_the_way_and_keeps_clear_of_the_wall() {
    // navigate.lm with and without Algorithm 5 (optim_rate 5).
    let text = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/actors/navigate.lm"),
    )
    .unwrap();
    assert!(text.contains("optim_rate 5"));
    let plain = text.replace("optim_rate 5 ", "");
    let length = |w: &[glam::Vec3]| w.windows(2).map(|p| p[0].distance(p[1])).sum::<f32>();
    let (short, long) = (walk(&text), walk(&plain));
    assert!(
        length(&short) < 0.85 * length(&long),
        "{} {}",
        length(&short),
        length(&long)
    );
    // The wall x ∈ [−6, 6], z ∈ [−0.2, 0.2]; the actor is 0.8 wide.
    for p in &short {
        let (dx, dz) = ((p.x.abs() - 6.0).max(0.0), (p.z.abs() - 0.2).max(0.0));
        assert!(dx.hypot(dz) > 0.4, "{p}");
    }
    assert!(
        short
            .last()
            .unwrap()
            .distance(glam::Vec3::new(0.0, 1.0, 6.0))
            < 0.01
    );
}

#[test]
fn heuristics_are_those_of_table_g1() {
    let refused = |command: &str| {
        let options = format!("NBR_actors 1\nactorNbr_automata 0 walk_continuously {command}");
        let text = scene(1.0, &options, "F", "");
        Film::from_sources(&[Source::new("h.lm", &text)], None, Options::default())
            .err()
            .map(|e| e.to_string())
    };
    let e = refused("heuristic 12").unwrap();
    assert!(
        e.contains("12 is not a search heuristic of table G.1"),
        "{e}"
    );
    let e = refused("coll_test_func 1").unwrap();
    assert!(
        e.contains("1 is not a collision test of table G.1: 3, 4, 6, 8, 11, 18"),
        "{e}"
    );
    assert!(refused("heuristic 9 coll_test_func 11").is_none());
}
