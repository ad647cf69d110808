//! The force functions of table B5 (`?09`, `?12`–`?19`, `?23`–`?29`),
//! each against its formula, and the contact levels they report to the
//! peak detectors (thesis 7.4).

use lmfilm::lsys::eval::{Bindings, Machine, State};
use lmfilm::lsys::functions::hermite;
use lmfilm::lsys::{Animation, FieldQuery, FieldValue, NoSensors, Sensors, Source, Who};
use lmfilm::physics::tennis;

/// Options of every test: the coefficient arrays the functions read.
const OPTIONS: &str = "fConst 0 0 1 0 2 5 0.5 2\n\
    fConst 1 3 0.5 2 0.25 0.1\n\
    fConst 4 2 3 -0.5 2 1\n\
    fConst 5 0.4 10 110 0.1\n\
    fConst 6 0.2 1 5 0.5\n";

/// Feels the tennis fields of the physics layer and records the contact
/// levels they report.
#[derive(Default)]
struct Ear(Vec<(u8, f64)>);

impl Sensors for Ear {
    fn tennis(&mut self, q: &FieldQuery) -> FieldValue {
        let felt = tennis::field(q);
        self.0.push((q.code, felt.level));
        felt.field
    }
}

/// Value of `expr` at x y z = `at`, X Y Z u v w r = `field`, age `t`,
/// and what it reported.
fn eval(expr: &str, at: [f64; 3], field: [f64; 7], t: f64) -> (f64, Vec<(u8, f64)>) {
    let text = format!(
        "Camera_AnimationParameters\nt_final_interval 1 0.04\n\nOptions\n{OPTIONS}\n\
         Constants\nP 1 4 2\n\nAxiom\nA () () () () ({expr})\n"
    );
    let anim = Animation::from_sources(&[Source::new("f.lm", text)], &mut NoSensors).unwrap();
    let ls = &anim.systems[0];
    let s = &ls.word()[0];
    let f = ls.def.growth[s.growth as usize].f[0].expect("an expression");
    let mut state = State::new(&ls.def);
    let mut ear = Ear::default();
    let mut m = Machine::new(&ls.def, &mut state, &mut ear, 1);
    let frame = Bindings {
        time: 0.0,
        age: t,
        par: at,
        field,
        key: 0,
        who: Who {
            lsys: 0,
            symbol: s.id,
            actor: None,
        },
        growth: s.growth,
    };
    let v = m.eval(f, &frame);
    (v, ear.0)
}

fn close(a: f64, b: f64) {
    assert!((a - b).abs() < 1e-12, "{a} ≠ {b}");
}

const NONE: [f64; 7] = [0.0; 7];

#[test]
fn q09_is_the_x_direction_to_the_carrier() {
    close(
        eval(
            "?09",
            [1.0, 0.0, 0.0],
            [4.0, 4.0, 0.0, 0.0, 0.0, 0.0, 5.0],
            0.0,
        )
        .0,
        0.6,
    );
    close(
        eval(
            "?09",
            [1.0, 0.0, 0.0],
            [1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
            0.0,
        )
        .0,
        1.0,
    );
}

#[test]
fn q12_to_q14_are_walls_from_the_p_coefficients() {
    // P0 = 1, P1 = 4, P2 = 2: P2 below P0, −P2 above P1, 0 between.
    for (n, axis) in [(12, 0), (13, 1), (14, 2)] {
        let at = |q: f64| {
            let mut p = [2.0; 3];
            p[axis] = q;
            eval(&format!("?{n}"), p, NONE, 0.0).0
        };
        assert_eq!((at(0.5), at(2.0), at(5.0)), (2.0, 0.0, -2.0), "?{n}");
    }
}

#[test]
fn q15_to_q17_are_the_racket_force_along_its_normal() {
    // n = (0, 1, 0), radius 2, a = 5, b = 0.5, p = 2: F = 5·3^(−0.5 h²).
    let racket = [0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0];
    let f = 5.0 * 3f64.powf(-0.5 * 0.25);
    let (x, heard) = eval("?15", [1.0, 1.5, 0.0], racket, 0.0);
    close(x, 0.0);
    assert_eq!(heard, vec![(15, f / 5.0)]);
    close(eval("?15 ?16 +", [1.0, 1.5, 0.0], racket, 0.0).0, f);
    close(eval("?15 ?16 +", [1.0, 0.5, 0.0], racket, 0.0).0, -f);
    close(eval("?15 ?17 +", [1.0, 1.5, 0.0], racket, 0.0).0, 0.0);
    // Beyond the radius: no force, no contact.
    let (v, heard) = eval("?15 ?16 +", [3.0, 1.5, 0.0], racket, 0.0);
    close(v, 0.0);
    assert_eq!(heard, vec![(15, 0.0)]);
}

#[test]
fn q18_is_the_weight_of_the_particle() {
    close(eval("?18", [0.0; 3], NONE, 0.0).0, -9.81);
}

#[test]
fn q19_is_the_net_of_eq_7_1_3() {
    // a = 3, b = 0.5, c = 2, d = 0.25, e = 0.1, f = 1.
    let (x, u) = (3.2, 4.0);
    let shape = ((x - 3.0) / 0.5f64).powf(2.0) + 0.25;
    let (v, heard) = eval("?19", [x, 1.0, 1.0], [0.0, 0.0, 0.0, u, 0.0, 0.0, 0.0], 0.0);
    close(v, ((x - 3.0) - u * 0.1) / shape);
    assert_eq!(heard, vec![(19, 0.25 / shape)]);
}

#[test]
fn q23_and_q24_are_the_exponential_field() {
    // c = (2, 3, −0.5, 2, 1): 2·3^(−0.5 r²) / (r + 1).
    let r = 1.5;
    let want = 2.0 * 3f64.powf(-0.5 * r * r) / (r + 1.0);
    let field = [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, r];
    close(eval("?23", [0.0; 3], field, 0.0).0, want);
    close(eval("?23 ?24 +", [0.0; 3], field, 0.0).0, 2.0 * want);
}

#[test]
fn q26_is_the_ground_ramp_of_const5() {
    // TT = 0.4, min 10, max 110, offset 0.1: Hermite(0.5 − y).
    for y in [1.0, 0.45, 0.3, 0.15, -1.0] {
        let (v, heard) = eval("?26", [0.0, y, 0.0], NONE, 0.0);
        close(v, hermite(0.5 - y, 0.4, 10.0, 110.0));
        assert_eq!(heard, vec![(26, hermite(0.5 - y, 0.4, 0.0, 1.0))]);
    }
}

#[test]
fn q27_is_the_ball_ground_ramp_of_const6() {
    // TT = 0.2, min 1, max 5, offset 0.5: Hermite(0.5 − y).
    for y in [1.0, 0.45, 0.4, 0.2] {
        let (v, heard) = eval("?27", [0.0, y, 0.0], NONE, 0.0);
        close(v, hermite(0.5 - y, 0.2, 1.0, 5.0));
        assert_eq!(heard, vec![(27, hermite(0.5 - y, 0.2, 0.0, 1.0))]);
    }
}

#[test]
fn q28_and_q29_are_hermite_of_the_age_and_of_the_stack() {
    // Const[5]: TT = 0.4, min 10, max 110, offset 0.1.
    close(
        eval("?28", [0.0; 3], NONE, 0.1).0,
        hermite(0.2, 0.4, 10.0, 110.0),
    );
    close(
        eval("0.05 ?29", [0.0; 3], NONE, 0.0).0,
        hermite(0.15, 0.4, 10.0, 110.0),
    );
}

#[test]
fn tennis_fields_are_zero_without_physics() {
    // NoSensors: a world without physics has no field, and ?15 stores
    // a zero force for ?16, ?17.
    let text = format!(
        "Camera_AnimationParameters\nt_final_interval 1 0.04\n\nOptions\n{OPTIONS}\n\
         Axiom\nA () () () () (?15 ?16 + ?19 + ?26 + ?27 + 1 +)\n"
    );
    let anim = Animation::from_sources(&[Source::new("f.lm", text)], &mut NoSensors).unwrap();
    let ls = &anim.systems[0];
    let s = &ls.word()[0];
    let f = ls.def.growth[s.growth as usize].f[0].expect("an expression");
    let mut state = State::new(&ls.def);
    let mut none = NoSensors;
    let mut m = Machine::new(&ls.def, &mut state, &mut none, 1);
    let frame = Bindings {
        time: 0.0,
        age: 0.0,
        par: [1.0, 0.45, 0.0],
        field: [0.0, 1.0, 0.0, 4.0, 0.0, 0.0, 0.0],
        key: 0,
        who: Who {
            lsys: 0,
            symbol: s.id,
            actor: None,
        },
        growth: s.growth,
    };
    assert_eq!(m.eval(f, &frame), 1.0);
}
