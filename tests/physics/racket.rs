//! `C` par1 = 5 (C.4): a particle carried by a racket actor. The racket's
//! field (`?15`–`?17`, its normal the racket's motion) strikes a ball
//! while it moves, and the stroke is heard (ball_racket, sound 0).

use lmfilm::film::Film;
use lmfilm::lsys::Source;
use lmfilm::sound::events::Event;
use lmfilm::turtle::Options;

/// Actor 0, the racket, is placed by `g` at x = 3 − 5·T (moving −x at
/// 5 m/s, 1 m up); its particle (row 1) carries a disc of radius 0.5
/// whose normal is its motion (`fConst 0`'s normal 0 0 0), its force
/// 5000·3^(−30·|h|): it stops a ball coming at 15 m/s about 0.01 from
/// its face, deep enough to be heard (level 3^(−30·|h|) ≥ 0.5). The ball (row 0), mass 1, no other force,
/// leaves (−3 1 0) at +10 m/s: they meet at T = 0.4 s near x = 1.
fn scene(racket_speed: &str) -> String {
    format!(
        "Camera_AnimationParameters\nt_final_interval 1.0 0.04\nnbrCalcStep_seed 20 1\n\
         Options\nNBR_actors 1\nactorNbr_automata 0 watch obs 3 1 0 lat 0 1 0\n\
         fConst 0 0 0 0 0.5 5000 30 1\n\
         Axiom\n\
         [ f () () () (2) (3_) (1) (0) e () (11) () () (0) (0) (0) C () (0) (1) () (10) (0) (0) ]\n\
         [ f () () () (2) (3 T {racket_speed} * -) (1) (0) g () (0) ]\n\
         [ M () (7) () (0) e () (10) (1) () (?15) (?16) (?17) C () (5) () () (0) ]\n"
    )
}

/// The ball's velocity at the end and the PLAY events (time, source, file).
fn strike(text: &str) -> (glam::DVec3, Vec<(f64, u32, String)>) {
    let mut f =
        Film::from_sources(&[Source::new("racket.lm", text)], None, Options::default()).unwrap();
    while f.next_frame().unwrap().is_some() {}
    let plays = f
        .events()
        .events()
        .filter_map(|(t, e)| match e {
            Event::Play { n, file } => Some((t.unwrap(), *n, file.clone())),
            _ => None,
        })
        .collect();
    (f.particles()[0].vel, plays)
}

#[test]
fn a_moving_racket_strikes_the_ball() {
    let (v, plays) = strike(&scene("5"));
    // Seen from the racket the ball comes at 15 m/s and leaves at 15:
    // −20 m/s, the racket's velocity added twice (an elastic field).
    assert!(
        (v.x + 20.0).abs() < 1.0 && v.y.abs() < 0.1 && v.z.abs() < 0.1,
        "{v}"
    );
    assert_eq!(plays.len(), 1, "{plays:?}");
    let (t, source, file) = &plays[0];
    assert_eq!((*source, file.as_str()), (1000, "ball_racket.wav"));
    assert!((t - 0.44).abs() < 0.05, "{t}");
}

#[test]
fn a_racket_standing_still_has_no_face() {
    // Its normal is its motion: standing, it exerts no force.
    let (v, plays) = strike(&scene("0"));
    assert!((v.x - 10.0).abs() < 1e-9, "{v}");
    assert!(plays.is_empty(), "{plays:?}");
}
