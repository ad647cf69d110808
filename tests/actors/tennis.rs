//! The referee of thesis 5.7 (`scenes/tennis/referee.lm`): it follows the
//! ball with its eyes, judges the collisions it hears and says its calls
//! in appendix D's words, in order, through `talk`.

use lmfilm::sound::events::Event;

use super::support::{film, same_for_one_and_two_threads, trace};

const SCENE: &str = "scenes/tennis/referee.lm";

/// The words the referee said (its voice is source 2000), in order.
fn calls(text: &str) -> Vec<String> {
    let mut f = film(text);
    while f.next_frame().unwrap().is_some() {}
    f.events()
        .events()
        .filter_map(|(_, e)| match e {
            Event::Play { n: 2000, file } => Some(file.trim_end_matches(".wav").to_string()),
            _ => None,
        })
        .collect()
}

fn scene() -> String {
    std::fs::read_to_string(SCENE).unwrap()
}

#[test]
fn a_service_out_is_a_fault_and_called() {
    // "service green, right"; the ball lands beyond the service line:
    // "out, fault green, service green, right" (the second service).
    let service = ["service", "green", "right"];
    let fault = ["out", "fault", "green", "service", "green", "right"];
    assert_eq!(calls(&scene()), [&service[..], &fault].concat());
    // It was following the ball when it bounced.
    let frames = trace(SCENE);
    let bounce = frames
        .iter()
        .find(|f| {
            f["sound_events"]
                .as_array()
                .unwrap()
                .iter()
                .any(|e| e["sound"] == 1)
        })
        .unwrap();
    assert_eq!(bounce["actors"][0]["found"], true);
}

#[test]
fn an_ace_wins_the_point() {
    // Slower, the service lands in blue's right box and bounces again
    // beyond the base line: blue did not return it. "fault blue, fifteen
    // love, service green, left".
    let text = scene().replace("(26) (1) (1.5_)", "(22) (1) (1.5_)");
    let words = "service green right fault blue fifteen love service green left";
    assert_eq!(calls(&text), words.split(' ').collect::<Vec<_>>());
}

#[test]
fn a_referee_who_cannot_see_the_ball_judges_by_ear() {
    // Its eyes reach 1 m: it places the bounce where it heard it.
    let text = scene().replace("vision_range 0.3 60 60", "vision_range 0.3 1 1");
    let words = "service green right out fault green service green right";
    assert_eq!(calls(&text), words.split(' ').collect::<Vec<_>>());
}

#[test]
fn the_ball_is_heard_from_where_it_flies() {
    // Once it has sounded, the ball's source (1000) is placed with it
    // every frame it does not sound, so it never jumps from one bounce
    // to the next (which the soundtrack would refuse as faster than
    // sound): one position a frame from its first sound on.
    let mut f = film(&scene());
    while f.next_frame().unwrap().is_some() {}
    let mut keys = Vec::new();
    for (t, e) in f.events().events() {
        if let Event::SourcePosition { n: 1000, position } = e {
            keys.push((t.unwrap(), *position));
        }
    }
    // From its first bounce (2.84 s) to the film's end (8 s), a frame
    // apart, never faster than the ball's 30 m/s by much (a bounce is
    // heard where the ball was when it hit, up to a frame earlier).
    assert!(keys.len() > 120, "{}", keys.len());
    for w in keys.windows(2) {
        let (dt, d) = (w[1].0 - w[0].0, w[1].1.distance(w[0].1));
        assert!(dt < 0.041 && d / dt < 60.0, "{w:?}");
    }
}

#[test]
fn the_referee_is_the_same_for_one_and_two_threads() {
    same_for_one_and_two_threads(SCENE, &[], "tennis_error_detection");
}
