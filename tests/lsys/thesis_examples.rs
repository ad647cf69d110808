//! The thesis's own worked examples (sections 2.1.2, 2.1.4, code 6.2.1).

use crate::common::*;
use lmfilm::lsys::NoSensors;

#[test]
fn a_to_b_example_of_2_1_4() {
    let mut a = load("ab.lm");
    a.advance_to(a.frame_at(0.5), &mut NoSensors).unwrap();
    assert_eq!(full(&mut a), "a(0.5,2,1,3,1,3,0.5)");
    a.advance_to(a.frame_at(1.5), &mut NoSensors).unwrap();
    assert_eq!(full(&mut a), "b(0.5,4,5,6,2,7,10)");
}

#[test]
fn growing_tree_of_2_1_2() {
    let mut a = load("growing_tree.lm");
    let mut at = |t: f64| {
        a.advance_to(a.frame_at(t), &mut NoSensors).unwrap();
        full(&mut a)
    };
    assert_eq!(at(0.5), "+(0.5,0,0,0,90,0,0) p(0.5,1,0,0,3,0,0)");
    assert_eq!(at(0.9), "+(0.9,0,0,0,90,0,0) p(0.9,1,0,0,5.4,0,0)");
    // (q, 0.5, 1, 6.5) [+ (p, 0.5, 0.5, 1.5)] [- (p, 0.5, 0.5, 1.5)]
    assert_eq!(
        at(1.5),
        "+(1.5,0,0,0,90,0,0) q(0.5,1,0,0,6.5,0,0) [(0.5,0,0,0,0,0,0) +(0.5,0,0,0,90,0,0) \
         p(0.5,0.5,0,0,1.5,0,0) ](0.5,0,0,0,0,0,0) [(0.5,0,0,0,0,0,0) -(0.5,0,0,0,90,0,0) \
         p(0.5,0.5,0,0,1.5,0,0) ](0.5,0,0,0,0,0,0)"
    );
}

#[test]
fn code_6_2_1_parses_and_derives() {
    let mut a = load("cours_tree3.lm");
    let cam = &a.camera;
    assert_eq!(cam.seed, 34743);
    assert_eq!(cam.nbr_calc_step, 4);
    assert_eq!((cam.t_final, cam.dt), (250.0, 0.04));
    assert_eq!(cam.observer, [0.0, 15.0, 130.0]);
    assert_eq!(cam.look_at, [0.0, 15.0, 0.0]);
    assert_eq!(cam.view_angle, 500.0);
    assert_eq!(cam.pref_pos, [0, 721, 0, 576]);
    assert_eq!(a.systems[0].def.productions.len(), 2);

    assert_eq!(at_frame(&mut a, 24), "vvmn+Nz");
    // z has maximal age 1: with Δt = 0.04 it is replaced in the 25th step.
    assert_eq!(at_frame(&mut a, 25), "vvmn+NN[&Nz]/[&Nz]/[&Nz]");
    for k in 2..=5u32 {
        let w = at_frame(&mut a, 25 * u64::from(k));
        assert_eq!(w.matches('z').count(), 3usize.pow(k), "generation {k}");
    }
    // The trunk N(10, 0.15) grows by p = 1.07 and e = 1.732 each unit.
    let trunk = a.systems[0].word()[5];
    assert_eq!(trunk.ch, b'N');
    assert!((trunk.par[0] - 10.0 * 1.07f64.powi(5)).abs() < 1e-9);
    assert!((trunk.par[1] - 0.15 * 1.732f64.powi(5)).abs() < 1e-9);
}

#[test]
fn replacement_happens_on_the_exact_tick() {
    for (dt, max_age) in [
        (0.04f64, 1.0f64),
        (0.1, 0.3),
        (0.1, 0.7),
        (0.01, 2.2),
        (1.0 / 30.0, 1.0),
        (0.04, 0.12),
    ] {
        let text = format!(
            "Camera_AnimationParameters\nt_final_interval 10 {dt}\nAxiom\na\n\
             Productions\na ({max_age})\n1.0 b EndProb\nEnd\nEndProductions\n"
        );
        let mut a = from_text(&text);
        let due = (max_age / dt).round() as u64;
        assert_eq!(at_frame(&mut a, due - 1), "a", "dt {dt} age {max_age}");
        assert_eq!(at_frame(&mut a, due), "b", "dt {dt} age {max_age}");
    }
}

#[test]
fn a_due_symbol_without_applicable_production_keeps_ageing() {
    // Axiom 2: the condition T > 2 holds only later; `a` ages past its max age.
    let mut a = from_text(
        "Camera_AnimationParameters\nt_final_interval 10 0.5\nAxiom\na\n\
         Productions\na (1) [(T2-)>]\n1.0 b EndProb\nEnd\nEndProductions\n",
    );
    a.advance_to(5, &mut NoSensors).unwrap();
    assert_eq!(full(&mut a), "a(2.5,0,0,0,0,0,0)");
    a.advance_to(6, &mut NoSensors).unwrap();
    assert_eq!(full(&mut a), "b(0,0,0,0,0,0,0)");
}
