//! The worlds of issue 36, written from the thesis and not from the
//! code, on which the actors failed: an actor blinded by its own body, a
//! goal dropped in a U-shaped trap, an empty foothold map on a plain
//! stepping-stone field, and a goal out of reach given up in silence.

use lmfilm::film::Film;

use super::support::film;

/// Runs `film` until `done` says so or the film ends; the frames run.
fn run_until(film: &mut Film, mut done: impl FnMut(&Film) -> bool) -> u64 {
    let mut frames = 0;
    while film.next_frame().unwrap().is_some() {
        frames += 1;
        if done(film) {
            break;
        }
    }
    frames
}

/// Runs `film` as [`run_until`] does; the warnings of every frame run
/// that hold `about`, in order.
fn warnings_until(
    film: &mut Film,
    about: &str,
    mut done: impl FnMut(&Film) -> bool,
) -> Vec<String> {
    let mut said = Vec::new();
    run_until(film, |f| {
        let frame = f.frame().expect("a frame was handed out");
        said.extend(
            frame
                .warnings()
                .iter()
                .filter(|w| w.contains(about))
                .cloned(),
        );
        done(f)
    });
    said
}

/// A room of 20 × 20 with a wall across its middle (x −6…6 at z = 0),
/// walls 3 high on a floor whose top is at y = 0.
const ROOM: &str = "\
[ f () () () (2) (11_) (0.5_) (0) c () () () () (22) (1) (22) ]
[ f () () () (2) (10_) (1.5) (10) c () () () () (20) (3) (0.4) ]
[ f () () () (2) (10_) (1.5) (10_) c () () () () (20) (3) (0.4) ]
[ f () () () (2) (9.8) (1.5) (0) c () () () () (0.4) (3) (20) ]
[ f () () () (2) (10.2_) (1.5) (0) c () () () () (0.4) (3) (20) ]
[ f () () () (2) (6_) (1.5) (0) c () () () () (12) (3) (0.4) ]
";

/// `[ M () (7) () (0) a () () () () (0.5) ]` with `vision_range 0.1 60
/// 60`: the eye inside its own sphere. It sees the room from frame 0 and
/// walks round the wall to its goal.
#[test]
fn an_actor_drawn_around_its_eye_sees_the_room() {
    let text = format!(
        "Camera_AnimationParameters\nt_final_interval 30.0 0.04\nOptions\nNBR_actors 1\n\
         iVisionWinSize 0 32 8\n\
         actorNbr_automata 0 walk_continuously init 5 -12 12 0.25 obs 0 1 -6 lat 0 1 0 fov 900 \
         vision_range 0.1 60 60 goal 0 1 6 speed 2 heuristic 1 coll_test_func 3 size_actor 0.8\n\
         Axiom\n{ROOM}[ M () (7) () (0) a () () () () (0.5) ]\nProductions\nEndProductions\n"
    );
    let mut f = film(&text);
    f.next_frame().unwrap();
    let seen = f.living()[0].memory.as_ref().unwrap().voxels();
    assert!(
        seen > 100,
        "it sees the room at once, not its sphere: {seen} voxels"
    );
    let mut through_wall = false;
    run_until(&mut f, |f| {
        let e = f.living()[0].eye;
        through_wall |= e.x.abs() < 6.2 && e.z.abs() < 0.3;
        e.distance(glam::Vec3::new(0.0, 1.0, 6.0)) < 0.2
    });
    let e = f.living()[0].eye;
    assert!(e.distance(glam::Vec3::new(0.0, 1.0, 6.0)) < 0.2, "{e}");
    assert!(!through_wall);
}

/// What two watchers see at the centres of their windows after one
/// frame: actor 0 at (0, 1, 0) looking along +z, actor 1 at (0, 1, −5)
/// looking at actor 0's eye, with `body` drawn in actor 0's `M` branch.
fn watchers_see(body: &str) -> (f32, f32) {
    let text = format!(
        "Camera_AnimationParameters\nt_final_interval 0.1 0.04\nOptions\nNBR_actors 2\n\
         iVisionWinSize 0 16 8\niVisionWinSize 1 16 8\n\
         actorNbr_automata 0 watch obs 0 1 0 lat 0 1 5 vision_range 0.1 60 60\n\
         actorNbr_automata 1 watch obs 0 1 -5 lat 0 1 0 vision_range 0.1 60 60\n\
         Axiom\n[ M () (7) () (0) {body} ]\nProductions\nEndProductions\n"
    );
    let mut f = film(&text);
    f.next_frame().unwrap();
    let d = |k: usize| f.living()[k].window.as_ref().unwrap().centre;
    (d(0), d(1))
}

/// Other actors, and the camera, still see an actor's body: actor 1
/// watching actor 0's sphere sees it.
#[test]
fn other_actors_see_its_body() {
    // `a` (0.5) is a sphere of diameter 0.5 about actor 0's eye.
    let (own, other) = watchers_see("m () (10) a () () () () (0.5)");
    assert!(
        (other - 4.75).abs() < 0.01,
        "actor 1 sees the sphere: {other}"
    );
    assert!(own.is_infinite(), "actor 0 sees through it: {own}");
}

/// An actor standing in a body of its own (`D` par1 = 50 in its `M`
/// branch, a humanoid around its eye) sees through every bone; another
/// actor sees the body.
#[test]
fn an_actor_sees_through_its_humanoid_body() {
    let (own, other) =
        watchers_see("f () () () (2) (0) (0) (0) ^ () () () () (90) D () (50) () () (0) (1.8)");
    assert!(
        other.is_finite() && other < 5.0,
        "actor 1 sees the body: {other}"
    );
    assert!(own.is_infinite(), "actor 0 sees through it: {own}");
}

/// The U of the issue: walls 2 high at x = 0 and x = 10 from z = 0 to
/// 15, closed at z = 15; the actor at (5, 0.75, 5) inside, its goal at
/// (5, 0.75, 25). With the floor under it (whose top fell in the search
/// layer of its eye), and without.
#[test]
fn the_u_trap_does_not_strand_the_navigator() {
    let u = "\
[ f () () () (2) (0.2_) (1) (7.5) c () () () () (0.4) (2) (15) ]
[ f () () () (2) (9.8) (1) (7.5) c () () () () (0.4) (2) (15) ]
[ f () () () (2) (0.2_) (1) (15) c () () () () (10.4) (2) (0.4) ]
";
    let floor = "[ f () () () (2) (12_) (0.5_) (20) c () () () () (64) (1) (64) ]\n";
    for with_floor in [true, false] {
        let axiom = if with_floor {
            format!("{floor}{u}")
        } else {
            u.to_string()
        };
        let text = format!(
            "Camera_AnimationParameters\nt_final_interval 80.0 0.04\nOptions\nNBR_actors 1\n\
             iVisionWinSize 0 33 8\n\
             actorNbr_automata 0 walk_continuously init 5 -12 52 0.5 obs 5 0.75 5 lat 5 0.75 6 \
             fov 600 goal 5 0.75 25 heuristic 1 coll_test_func 3\n\
             Axiom\n{axiom}Productions\nEndProductions\n"
        );
        let mut f = film(&text);
        let mut inside_wall = false;
        let goal = glam::Vec3::new(5.0, 0.75, 25.0);
        let frames = run_until(&mut f, |f| {
            let a = &f.living()[0];
            let e = a.eye;
            let walls = [
                (-0.2, 0.2, 0.0, 15.0),
                (9.8, 10.2, 0.0, 15.0),
                (-0.2, 10.2, 14.8, 15.2),
            ];
            inside_wall |= walls
                .iter()
                .any(|&(x0, x1, z0, z1)| e.x > x0 && e.x < x1 && e.z > z0 && e.z < z1);
            assert!(a.gave_up.is_none(), "{:?}", a.gave_up);
            e.distance(goal) < 0.2
        });
        assert!(
            f.living()[0].eye.distance(goal) < 0.2,
            "floor {with_floor}: {frames} frames"
        );
        assert!(!inside_wall);
    }
}

/// A closed room, its goal outside: the actor explores the room, then
/// says the goal is out of reach (a warning naming it, `gave_up` in
/// trace) instead of dropping it in silence.
#[test]
fn an_unreachable_goal_is_reported() {
    let text = "Camera_AnimationParameters\nt_final_interval 200.0 0.04\nOptions\nNBR_actors 1\n\
         iVisionWinSize 0 32 8\n\
         actorNbr_automata 0 walk_continuously init 0 -6 10 0.25 obs 0 1 0 lat 1 1 0 fov 900 \
         goal 6 1 0 speed 2 heuristic 1 coll_test_func 3\n\
         Axiom\n\
         [ f () () () (2) (5_) (0.5_) (0) c () () () () (10) (1) (10) ]\n\
         [ f () () () (2) (3_) (1) (3) c () () () () (6) (2) (0.2) ]\n\
         [ f () () () (2) (3_) (1) (3_) c () () () () (6) (2) (0.2) ]\n\
         [ f () () () (2) (3.1_) (1) (0) c () () () () (0.2) (2) (6.2) ]\n\
         [ f () () () (2) (2.9) (1) (0) c () () () () (0.2) (2) (6.2) ]\n\
         Productions\nEndProductions\n";
    let mut f = film(text);
    let warned = warnings_until(&mut f, "out of reach", |f| f.living()[0].gave_up.is_some());
    let why = f.living()[0]
        .gave_up
        .clone()
        .expect("the goal given up, with its reason");
    assert!(why.contains("(6.00, 1.00, 0.00) is out of reach"), "{why}");
    assert_eq!(warned.len(), 1, "{warned:?}");
    assert!(warned[0].contains("actor 0 (walk_continuously)") && warned[0].starts_with("frame "));
    // It explored the room; it never left it.
    let e = f.living()[0].eye;
    assert!(e.x.abs() < 3.0 && e.z.abs() < 3.0, "{e}");
}

/// The stepping stones: 0.3 × 0.05 × 0.3, tops near y = 0,
/// 0.6 apart from (0, 0) to (0, 1.8), a detour east and back, goal
/// (0, 0, 6); `walk_stepworthy`, eye at 1.6, fov 90°, memory voxels of
/// 0.05, the actor's head and body drawn around its eye, no near plane.
/// With and without `foothold_plane`, at windows of 40 to 64 pixels and
/// tops at several heights against the voxel boundaries, it maps the
/// stones and walks to the one nearest its goal.
#[test]
fn footholds_are_found_on_a_plain_stepping_stone_field() {
    let stones = [
        (0.0, 0.0),
        (0.0, 0.6),
        (0.0, 1.2),
        (0.0, 1.8),
        (0.45, 2.3),
        (0.9, 2.8),
        (0.9, 3.4),
        (0.6, 3.95),
        (0.3, 4.5),
        (0.0, 5.1),
        (0.0, 5.7),
    ];
    for (window, top, plane) in [
        (40, 0.0, false),
        (50, 0.0, false),
        (50, 0.013, true),
        (64, 0.024, false),
        (50, 0.025, true),
        (40, 0.037, true),
    ] {
        let mut axiom = String::from(
            "[ M () (7) () (0)\n  [ a () () () () (0.12) ]\n  \
             [ f () () () (3) (0.175_) (0.525_) (0) c () () () () (0.35) (0.35) (0.35) ] ]\n",
        );
        for (x, z) in stones {
            axiom += &format!(
                "[ f () () () (2) ({x}) ({}_) ({z}) + () () () () (90) c () () () () (0.05) (0.3) (0.3) ]\n",
                0.05 - top
            );
        }
        let text = format!(
            "Camera_AnimationParameters\nt_final_interval 14.0 0.04\nOptions\nNBR_actors 1\n\
             iVisionWinSize 0 {window} 8\n\
             actorNbr_automata 0 walk_stepworthy init 10 -6.4 6.4 0.05 obs 0 {} 0 lat 0 0 3.2 \
             fov 900 goal 0 0 6 speed 1.2 size_actor 0.35{}\n\
             Axiom\n{axiom}Productions\nEndProductions\n",
            1.6 + top,
            if plane { " foothold_plane 0" } else { "" }
        );
        let mut f = film(&text);
        let mut mapped = 0;
        run_until(&mut f, |f| {
            let a = &f.living()[0];
            assert!(
                a.gave_up.is_none(),
                "window {window}, top {top}: {:?}",
                a.gave_up
            );
            mapped = mapped.max(a.footing.map.len());
            a.footing.plans > 0 && a.footing.destination.is_none()
        });
        let e = f.living()[0].eye;
        assert!(
            mapped >= 6,
            "window {window}, top {top}: {mapped} stones mapped"
        );
        assert!(
            e.z > 5.3 && e.x.abs() < 0.3,
            "window {window}, top {top}: at {e}"
        );
    }
}

/// The memory keeps the static surroundings: a box is remembered, a
/// sphere in the ball's colour code (material 10) moving past it is not,
/// so no trail of it can block a plan.
#[test]
fn the_memory_keeps_what_stands_still() {
    let text = "Camera_AnimationParameters\nt_final_interval 2.0 0.04\nOptions\nNBR_actors 1\n\
         iVisionWinSize 0 32 8\n\
         actorNbr_automata 0 watch init 0 -10 10 0.25 obs 0 1 -5 lat 0 1 0 fov 900\n\
         Axiom\n\
         [ m () (3) f () () () (2) (1_) (0) (2) c () () () () (2) (2) (0.5) ]\n\
         [ m () (10) f () () () (2) (3 T 3 * -) (1) (0) a () () () () (0.5) ]\n\
         Productions\nEndProductions\n";
    let mut f = film(text);
    let mut seen_ball = false;
    run_until(&mut f, |f| {
        let a = &f.living()[0];
        let w = a.window.as_ref().unwrap();
        seen_ball |= w.pixels.iter().any(|p| p.material == 10);
        // Every voxel it remembers lies in the box (z 1.75…2.25).
        let m = a.memory.as_ref().unwrap().octree();
        for (v, _) in m.occupied_voxels() {
            let c = m.centre(v);
            assert!((1.5..2.5).contains(&c[2]), "a voxel off the box: {c:?}");
        }
        false
    });
    assert!(seen_ball, "the ball crossed its view");
    assert!(f.living()[0].memory.as_ref().unwrap().voxels() >= 15);
}

/// A turtle at 10⁶⁰ (finite as f64, infinite as the actor's f32) never
/// enters an actor: `g` is skipped with one warning, the eye stays.
#[test]
fn a_turtle_beyond_the_coordinates_never_enters_an_actor() {
    let text = "Camera_AnimationParameters\nt_final_interval 0.2 0.04\nOptions\nNBR_actors 1\n\
         iVisionWinSize 0 8 8\nactorNbr_automata 0 watch obs 0 1 0 lat 0 1 1\n\
         Axiom\n[ f () () () (2) (10 60 ^) (1) (0) g () (0) ]\n\
         [ f () () () (2) (0) (10 60 ^) (0) g () (1) ]\nProductions\nEndProductions\n";
    let mut f = film(text);
    let warnings = warnings_until(&mut f, "beyond", |f| {
        let a = &f.living()[0];
        assert_eq!(a.eye, glam::Vec3::new(0.0, 1.0, 0.0));
        assert!(a.local_goals.values().all(|g| g.is_finite()));
        false
    });
    assert_eq!(warnings.len(), 1, "{warnings:?}");
    assert!(warnings[0].contains("actor 0 (watch)") && warnings[0].contains("1e60"));
}

/// A navigator that cannot work says so once: without a memory it has
/// nothing to plan on; without a vision window its memory stays empty.
#[test]
fn a_navigator_that_cannot_work_says_so() {
    let text = "Camera_AnimationParameters\nt_final_interval 0.2 0.04\nOptions\nNBR_actors 3\n\
         actorNbr_automata 0 walk_continuously goal 1 1 1\n\
         actorNbr_automata 1 walk_continuously init 0 -5 5 0.25 goal 1 1 1\n\
         actorNbr_automata 2 walk_stepworthy goal 1 0 1\n\
         Axiom\nProductions\nEndProductions\n";
    let mut f = film(text);
    let warnings = warnings_until(&mut f, "", |_| false);
    let said = |actor: &str, what: &str| {
        warnings
            .iter()
            .filter(|w| w.contains(actor) && w.contains(what))
            .count()
    };
    assert_eq!(
        said("actor 0 (walk_continuously)", "without a visual memory"),
        1,
        "{warnings:?}"
    );
    assert_eq!(
        said("actor 1 (walk_continuously)", "without a vision window"),
        1,
        "{warnings:?}"
    );
    assert_eq!(
        said("actor 2 (walk_stepworthy)", "without a visual memory"),
        1,
        "{warnings:?}"
    );
}

/// Issue 43's unbounded cost, bounded: a memory cube of 2²⁰ voxels a
/// side, no geometry, the path shown (`turtle 3`), a goal far away. The
/// path search gives up at `--max-plan-voxels` and says so naming the
/// flag; the actor explores instead, and the display draws at most a
/// couple of thousand points whatever the path's length in voxels.
#[test]
fn a_plan_past_its_limit_says_so_and_the_display_stays_bounded() {
    let text = |goal: u32| {
        format!(
            "Camera_AnimationParameters\nt_final_interval 1 0.04\nOptions\nNBR_actors 1\n\
             iVisionWinSize 0 8 8\n\
             actorNbr_automata 0 walk_continuously init 0 -524288 524288 1 turtle 3 speed 5 goal {goal} 0 0\n\
             Axiom\n[ M () (7) () (0) ]\nProductions\nEndProductions\n"
        )
    };
    let limited = |goal: u32, plan_voxels: usize| {
        let mut opts = lmfilm::turtle::Options::default();
        opts.limits.plan_voxels = plan_voxels;
        Film::from_sources(
            &[lmfilm::lsys::Source::new("far.lm", text(goal))],
            None,
            opts,
        )
        .unwrap()
    };
    // Over the limit: one warning naming the flag, and it moves on.
    let mut f = limited(20_000, 5_000);
    let mut shapes = Vec::new();
    let warnings = warnings_until(&mut f, "", |f| {
        shapes.push(f.frame().unwrap().scene().geometries[0].shapes.len());
        false
    });
    let said: Vec<_> = warnings
        .iter()
        .filter(|w| w.contains("--max-plan-voxels"))
        .collect();
    assert_eq!(said.len(), 1, "{warnings:?}");
    assert!(said[0].contains("over the limit of 5000"), "{}", said[0]);
    let a = &f.living()[0];
    assert!(
        a.eye.x > 0.5,
        "it explores toward the goal: {:?} {} {:?}",
        a.eye,
        a.state,
        a.gave_up
    );
    // Under it: the plan holds 10,000 search voxels; the display draws
    // at most 2048 of its points.
    let mut f = limited(20_000, 1 << 18);
    let warnings = warnings_until(&mut f, "", |f| {
        let n = f.frame().unwrap().scene().geometries[0].shapes.len();
        assert!(n <= 2050, "{n} shapes drawn");
        false
    });
    assert!(warnings.is_empty(), "{warnings:?}");
    assert!(f.living()[0].navigation.path.len() > 9_000);
}

/// A goal outside the memory's cube is given up with a warning, also
/// when only its height is outside and the search is planar (it would
/// otherwise walk under it and count as arrived).
#[test]
fn a_goal_outside_the_memory_cube_is_given_up_with_a_warning() {
    for goal in ["50 0 0", "2 1000000000000000000000000000000 0", "2 -30 0"] {
        let text = format!(
            "Camera_AnimationParameters\nt_final_interval 0.2 0.04\nOptions\nNBR_actors 1\n\
             iVisionWinSize 0 8 8\n\
             actorNbr_automata 0 walk_continuously init 0 -20 20 0.5 goal {goal}\n\
             Axiom\nProductions\nEndProductions\n"
        );
        let mut f = film(&text);
        let warnings = warnings_until(&mut f, "outside its memory's cube", |_| false);
        assert_eq!(warnings.len(), 1, "{goal}: {warnings:?}");
        let a = &f.living()[0];
        assert!(a.gave_up.is_some(), "{goal}");
        assert_eq!(a.eye, glam::Vec3::ZERO, "{goal}: it stays where it is");
    }
}

/// A memory whose search voxels cut the cube into fewer than four per
/// edge is too coarse to plan in: said once, naming the numbers.
#[test]
fn a_memory_too_coarse_to_plan_in_says_so() {
    let text = "Camera_AnimationParameters\nt_final_interval 0.2 0.04\nOptions\nNBR_actors 1\n\
         iVisionWinSize 0 8 8\n\
         actorNbr_automata 0 walk_continuously init 0 -4 4 1 rel_search_level 2 goal 2 0 2\n\
         Axiom\nProductions\nEndProductions\n";
    let mut f = film(text);
    let warnings = warnings_until(&mut f, "too coarse", |_| false);
    assert_eq!(warnings.len(), 1, "{warnings:?}");
    assert!(warnings[0].contains("into 2 per edge"), "{}", warnings[0]);
}

/// The room's middle wall (x −6…6, z −0.2…0.2, up to y = 3) holds `e`.
fn in_middle_wall(e: glam::Vec3) -> bool {
    e.x > -6.0 && e.x < 6.0 && e.z > -0.2 && e.z < 0.2 && e.y < 3.0
}

/// `scenes/actors/navigate.lm`'s navigator with `setting` changed, in
/// the room: whether its eye entered the middle wall or crossed it
/// between two frames, whether it reached its goal (0 1 6), and the
/// warnings.
fn navigate_with(window: u32, setting: &str) -> (bool, bool, Vec<String>) {
    let text = format!(
        "Camera_AnimationParameters\nt_final_interval 16.0 0.04\nOptions\nNBR_actors 1\n\
         iVisionWinSize 0 {window} 8\n\
         actorNbr_automata 0 walk_continuously init 5 -12 12 0.25 obs 0 1 -6 lat 0 1 0 fov 900 \
         vision_range 0.5 30 30 goal 0 1 6 speed 2 heuristic 1 coll_test_func 3 ahead 4 \
         rel_search_level 1 optim_rate 5 optim_ahead 8 size_actor 0.8 {setting}\n\
         Axiom\n{ROOM}Productions\nEndProductions\n"
    );
    let mut f = film(&text);
    let goal = glam::Vec3::new(0.0, 1.0, 6.0);
    let mut last = f.living()[0].eye;
    let mut entered = false;
    let warnings = warnings_until(&mut f, "", |f| {
        let e = f.living()[0].eye;
        let crossed = (last.z < -0.2) != (e.z < -0.2) && (last.z > 0.2) != (e.z > 0.2);
        entered |= in_middle_wall(e) || (crossed && e.x.abs() < 6.0 && last.x.abs() < 6.0);
        last = e;
        e.distance(goal) < 0.2
    });
    let arrived = f.living()[0].eye.distance(goal) < 0.2;
    (entered, arrived, warnings)
}

/// Issue 54: at the edges of their ranges, `speed` (10³⁰ m/s jumped
/// the wall it saw in one step), the vision window (one pixel) and the
/// view angle (0.1°) took a navigator through the wall in silence. A
/// step now ends before what it sees or remembers, so the fast walker
/// goes round and arrives; a window or view that cannot see its way is
/// said, naming the setting and the value that works, and the values it
/// names keep the actor out of the wall.
#[test]
fn a_navigator_at_the_edges_of_its_settings_never_walks_through_a_wall() {
    let (entered, arrived, _) = navigate_with(32, "speed 1e30");
    assert!(
        !entered && arrived,
        "speed 1e30: entered {entered}, arrived {arrived}"
    );
    let (_, _, said) = navigate_with(32, "fov 1");
    assert!(
        said.iter()
            .any(|w| w.contains("fov 1 = 0.1°") && w.contains("fov 281 or more")),
        "{said:?}"
    );
    let (entered, arrived, said) = navigate_with(32, "fov 281");
    assert!(!entered && arrived && said.is_empty(), "fov 281: {said:?}");
    let (_, _, said) = navigate_with(1, "");
    assert!(
        said.iter()
            .any(|w| w.contains("window of 1×1 pixels") && w.contains("iVisionWinSize 9 or more")),
        "{said:?}"
    );
    // Rays as far apart as it is wide (a 4-pixel window) leave a wall's
    // edge unplaced by as much: said too.
    let (_, _, said) = navigate_with(4, "");
    assert!(
        said.iter().any(|w| w.contains("iVisionWinSize 9 or more")),
        "window 4: {said:?}"
    );
    let (entered, _, said) = navigate_with(9, "");
    assert!(!entered && said.is_empty(), "window 9: {said:?}");
    // Fast enough to end a piece of its path every frame (search voxels
    // of 0.25 at 0.8 a frame), it never turned its eyes to its way.
    let (entered, _, said) = navigate_with(32, "rel_search_level 0 speed 20");
    assert!(!entered, "speed 20 on 0.25 voxels: {said:?}");
    // Its visual memory off, only its window keeps it out: a wall that
    // came within its near clip (0.5) was no longer seen and it walked in.
    let (entered, arrived, said) = navigate_with(32, "vis_mem_off");
    assert!(!entered && !arrived, "vis_mem_off: entered {entered}");
    assert!(
        said.iter()
            .any(|w| w.contains("visual memory off (vis_mem_off)") && w.contains("vis_mem_on")),
        "{said:?}"
    );
}

/// Issue 54: a `walk_local` actor right over its goal (0.7 above it,
/// nearer than `eps_arrived` on the level) walked on the level, came no
/// nearer and stood there for the rest of the film in silence. It now
/// gives the goal up, saying why, and its next behaviour runs.
#[test]
fn a_walker_right_over_its_goal_gives_it_up_saying_why() {
    let text = "Camera_AnimationParameters\nt_final_interval 2.0 0.04\nOptions\nNBR_actors 1\n\
        iVisionWinSize 0 8 8\n\
        actorNbr_automata 0 walk_local obs 0 0.7 0 lat 1 0.7 0 goal 0 0 0 speed 1\n\
        actorNbr_automata 0 watch\n\
        Axiom\n[ f () () () (2) (0) (0.5_) (0) c () () () () (8) (1) (8) ]\nProductions\nEndProductions\n";
    let mut f = film(text);
    let said = warnings_until(&mut f, "walk_local", |f| f.living()[0].gave_up.is_some());
    let a = &f.living()[0];
    assert!(a.gave_up.is_some(), "{said:?}");
    assert!(
        said.iter()
            .any(|w| w.contains("0.700 below its eye") && w.contains("goal given up")),
        "{said:?}"
    );
}
