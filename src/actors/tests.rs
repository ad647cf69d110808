use super::*;
use crate::lsys::{Animation, NoSensors, Source};

/// A scene of one file whose Options section is `options`.
fn scene(options: &str) -> Result<Table, Diagnostic> {
    let text = format!(
        "Camera_AnimationParameters\nt_final_interval 2 1\nOptions\n{options}\nAxiom\nA\nProductions\nA (1)\n1.0 A EndProb\nEnd\nEndProductions\n"
    );
    let src = Source::new("a.lm", text);
    let anim = Animation::from_sources(&[src], &mut NoSensors)?;
    Table::from_animation(&anim)
}

/// The error of `options`, checked to point at line `line` (1-based in
/// the Options text), at the first occurrence of `word` in it, with a
/// caret under it.
fn refused(options: &str, line: usize, word: &str) -> Diagnostic {
    let d = scene(options).expect_err(options);
    // `word` may hold a `|` before the offending word: `fov |0`.
    let text = options.lines().nth(line - 1).unwrap();
    let skip = word.find('|').unwrap_or(0);
    let column = text.find(&word.replace('|', "")).unwrap() + skip + 1;
    // Three lines precede the Options text.
    let want = format!("a.lm:{}:{column}:", line + 3);
    let shown = d.to_string();
    assert!(shown.starts_with(&want), "want {want}, got\n{shown}");
    let caret = format!("\n  {}^", " ".repeat(column - 1));
    assert!(shown.ends_with(&caret), "{shown}");
    d
}

#[test]
fn the_thesis_line_gives_a_watching_actor_with_typed_commands() {
    let t = scene(
        "NBR_actors 1\niVisionWinSize 0 64 20\nactorNbr_automata 0 0 9 init 10 -20 300 2.0 obs 0 0 50 lat 0 0 0",
    )
    .unwrap();
    assert_eq!(t.len(), 1);
    let a = t.get(0).unwrap();
    assert_eq!(a.id(), 0);
    let v = a.vision().unwrap();
    assert_eq!((v.edge, v.max_colors), (64, 20));
    let [entry] = a.automata() else {
        panic!("{:?}", a.automata())
    };
    assert_eq!(entry.automata, Automata::Watch);
    let commands: Vec<_> = entry.commands.iter().map(|c| c.command.clone()).collect();
    assert_eq!(
        commands,
        [
            AutomataCommand::Init {
                display_every: 10,
                min: -20.0,
                max: 300.0,
                voxel_edge: 2.0
            },
            AutomataCommand::Obs([0.0, 0.0, 50.0]),
            AutomataCommand::Lat([0.0, 0.0, 0.0]),
        ]
    );
    // `obs` on line 6 of the file (3 lines before the Options text).
    let obs = &entry.commands[1];
    assert_eq!(
        obs.span.to_string(),
        format!(
            "a.lm:6:{}",
            "actorNbr_automata 0 0 9 init 10 -20 300 2.0 obs".len() - 2
        )
    );
}

#[test]
fn automata_by_name_or_number_and_in_declaration_order() {
    let t = scene(
        "NBR_actors 2\nactorNbr_automata 1 watch vis_mem_on\nactorNbr_automata 1 1 19 align 1 2 3\nactorNbr_automata 1 L-system",
    )
    .unwrap();
    assert!(t.get(0).unwrap().automata().is_empty());
    let stack: Vec<_> = t
        .get(1)
        .unwrap()
        .automata()
        .iter()
        .map(|e| e.automata)
        .collect();
    assert_eq!(
        stack,
        [Automata::Watch, Automata::AutoAlign, Automata::LSystem]
    );
}

#[test]
fn numbers_and_names_map_both_ways() {
    for a in Automata::ALL {
        assert_eq!(Automata::from_number(a.number()), Some(a));
        assert_eq!(Automata::from_name(a.name()), Some(a));
    }
    assert_eq!(Automata::AutoAlign.number(), 19);
    assert_eq!(Automata::from_number(13), None);
}

#[test]
fn a_scene_without_actors_has_an_empty_table() {
    assert!(scene("fConst 5 1").unwrap().is_empty());
    assert!(scene("NBR_actors 0").unwrap().is_empty());
}

#[test]
fn refuses_what_no_actor_can_run() {
    let d = refused("NBR_actors 2\nactorNbr_automata 2 9", 2, "2 9");
    assert!(d.message.contains("does not exist"), "{d}");
    refused("NBR_actors 2\niVisionWinSize -1 64 20", 2, "-1");
    refused("NBR_actors 2\nNBR_actors 3", 2, "3");
    refused("NBR_actors -1", 1, "-1");
    refused("NBR_actors 1\niVisionWinSize 0 0 20", 2, "0 20");
    refused("NBR_actors 1\niVisionWinSize 0 2048 20", 2, "2048");
    refused("NBR_actors 1\niVisionWinSize 0 64 -1", 2, "-1");
    refused(
        "NBR_actors 1\niVisionWinSize 0 64 2\niVisionWinSize 0 32 2",
        3,
        "0 32",
    );
    let d = refused("actorNbr_automata 0 9", 1, "0 9");
    assert!(d.message.contains("NBR_actors"), "{d}");
    // NBR_actors may come after the actors' options.
    assert_eq!(
        scene("iVisionWinSize 0 64 20\nNBR_actors 1").unwrap().len(),
        1
    );
    // Unknown automata, by number and by name.
    refused("NBR_actors 1\nactorNbr_automata 0 0 13", 2, "13");
    let d = refused("NBR_actors 1\nactorNbr_automata 0 wach", 2, "wach");
    assert!(d.message.contains("did you mean `watch`"), "{d}");
    refused("NBR_actors 1\nactorNbr_automata 0 0 wach", 2, "wach");
    // Arguments out of range point at the argument.
    refused(
        "NBR_actors 1\nactorNbr_automata 0 9 init 10 -20 300 -2",
        2,
        "300 |-2",
    );
    refused(
        "NBR_actors 1\nactorNbr_automata 0 9 init 10 300 -20 2",
        2,
        "-20",
    );
    refused("NBR_actors 1\nactorNbr_automata 0 9 fov 0", 2, "fov |0");
    // Issue 54: arrival is closer than the distance, so 0 lets none
    // arrive; a repeated actor number names the line's actor.
    let d = refused(
        "NBR_actors 1\nactorNbr_automata 0 9 eps_arrived 0",
        2,
        "eps_arrived |0",
    );
    assert!(d.message.contains("no actor ever arrives"), "{d}");
    refused(
        "NBR_actors 1\nactorNbr_automata 0 9 eps_arrived 2 0",
        2,
        "2 |0",
    );
    refused("NBR_actors 2\nactorNbr_automata 0 5 9", 2, "5 9");
    refused("NBR_actors 1\nactorNbr_automata 0 9 fov 1800", 2, "1800");
    refused("NBR_actors 1\nactorNbr_automata 0 9 fov 45.5", 2, "45.5");
    refused(
        "NBR_actors 1\nactorNbr_automata 0 9 vision_range 10 5 1",
        2,
        "5 1",
    );
    refused(
        "NBR_actors 1\nactorNbr_automata 0 9 rgb_interest 255 256 0 1",
        2,
        "256",
    );
    refused(
        "NBR_actors 1\nactorNbr_automata 0 9 local_goal -1 4 5 6",
        2,
        "-1",
    );
    refused("NBR_actors 1\nactorNbr_automata 0 9 turtle 5", 2, "5");
    // rel_search_level is a logarithmic level: 0, 1, 2, … (B.6).
    refused(
        "NBR_actors 1\nactorNbr_automata 0 4 rel_search_level -1",
        2,
        "-1",
    );
    refused(
        "NBR_actors 1\nactorNbr_automata 0 4 rel_search_level 0.5",
        2,
        "0.5",
    );
    refused(
        "NBR_actors 1\nactorNbr_automata 0 4 rel_search_level 21",
        2,
        "21",
    );
    refused("NBR_actors 1\nactorNbr_automata 0 9 interest 1 3", 2, "3");
    refused("NBR_actors 1\nactorNbr_automata 0 9 goal 1 2", 2, "goal");
    // walk_stepworthy's commands (docs/footholds.md).
    let w = "NBR_actors 1\nactorNbr_automata 0 8";
    refused(&format!("{w} foothold_step 0 0.5"), 2, "0 0.5");
    refused(&format!("{w} foothold_step 1 -0.5"), 2, "-0.5");
    refused(&format!("{w} step_weights 1 1 1 1 -5 2"), 2, "-5");
    refused(&format!("{w} step_weights 1 1 1 -1 5 2"), 2, "-1");
    refused(&format!("{w} foothold_map 0 4"), 2, "0 4");
    refused(&format!("{w} foothold_map 10 0"), 2, "10 |0");
    refused(&format!("{w} foothold_map 10 2.5"), 2, "2.5");
    refused(&format!("{w} foothold_plane"), 2, "foothold_plane");
    let t = scene(&format!(
        "{w} foothold_plane 0.2 foothold_step 0.8 0.3 step_weights 1 1 0 1 5 2 foothold_map 6 3"
    ))
    .unwrap();
    assert_eq!(t.get(0).unwrap().automata()[0].commands.len(), 4);
    let walker = &super::live::living(&t, &Default::default())[0]
        .footing
        .settings;
    assert_eq!(walker.plane, Some(0.2));
    assert_eq!((walker.gait.df_max, walker.gait.max_change), (0.8, 0.3));
    assert_eq!(walker.weights.p1, 0.0);
    assert_eq!((walker.range, walker.min_voxels), (6.0, 3));
}

#[test]
fn both_arities_where_bnf_and_table_b6_disagree() {
    let t = scene(
        "NBR_actors 1\nactorNbr_automata 0 9 local_goal 1 2 3 local_goal 2 1 2 3 eps_arrived 0.5 eps_arrived 1 0.5 rel_search_level rel_search_level 0",
    )
    .unwrap();
    let c: Vec<_> = t.get(0).unwrap().automata()[0]
        .commands
        .iter()
        .map(|c| c.command.clone())
        .collect();
    use AutomataCommand as C;
    assert_eq!(
        c,
        [
            C::LocalGoal {
                index: None,
                at: [1., 2., 3.]
            },
            C::LocalGoal {
                index: Some(2),
                at: [1., 2., 3.]
            },
            C::EpsArrived {
                index: None,
                distance: 0.5
            },
            C::EpsArrived {
                index: Some(1),
                distance: 0.5
            },
            C::RelSearchLevel(None),
            C::RelSearchLevel(Some(0.0)),
        ]
    );
}

#[test]
fn the_refusal_shown_in_docs_actors_md() {
    let d = scene("NBR_actors 1\nactorNbr_automata 0 9 obs 0 0 50 fov 0").unwrap_err();
    assert_eq!(
        d.to_string(),
        format!(
            "a.lm:5:38: `fov`: the view angle (tenths of a degree) must be 1..=1799, found 0\n  \
             actorNbr_automata 0 9 obs 0 0 50 fov 0\n  {}^",
            " ".repeat(37)
        )
    );
}
