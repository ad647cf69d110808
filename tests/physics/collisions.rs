//! Peak detectors (thesis 7.4, fig. 7.4.1) on the bouncing ball of
//! 7.1.2/7.1.4 (`scenes/physics/bouncing_ball.lm`): each bounce loses
//! energy and is heard once, at its frame.

use lmfilm::film::Film;
use lmfilm::sound::events::Event;
use lmfilm::turtle::Options;

const SCENE: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/scenes/physics/bouncing_ball.lm"
);

/// The ball's height each frame and the frames of its PLAY events, as
/// (frame, source, file).
fn bounce(threads: usize) -> (Vec<f64>, Vec<(usize, u32, String)>) {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    pool.install(|| {
        let mut film = Film::load(&[SCENE], Options::default()).unwrap();
        let mut heights = Vec::new();
        while film.next_frame().unwrap().is_some() {
            heights.push(film.particles()[0].pos.y);
        }
        let plays = film
            .events()
            .frames()
            .iter()
            .enumerate()
            .flat_map(|(k, f)| {
                f.events.iter().filter_map(move |e| match e {
                    Event::Play { n, file } => Some((k, *n, file.clone())),
                    _ => None,
                })
            })
            .collect();
        (heights, plays)
    })
}

/// Frames of the local minima (bounces) and maxima (apexes) of `y`.
fn extrema(y: &[f64]) -> (Vec<usize>, Vec<f64>) {
    let (mut lows, mut apexes) = (Vec::new(), Vec::new());
    for k in 1..y.len() - 1 {
        if y[k] < y[k - 1] && y[k] <= y[k + 1] {
            lows.push(k);
        }
        if y[k] > y[k - 1] && y[k] >= y[k + 1] {
            apexes.push(y[k]);
        }
    }
    (lows, apexes)
}

#[test]
fn each_bounce_loses_energy_and_is_heard_once_at_its_frame() {
    let (y, plays) = bounce(1);
    let (lows, apexes) = extrema(&y);
    assert!(lows.len() >= 3, "bounces at {lows:?}");
    assert!(apexes.len() >= 2, "apexes {apexes:?}");
    // Successive apex heights strictly decrease, below the 4 m drop.
    let mut last = y[0];
    for &a in &apexes {
        assert!(a < last, "apex {a} after {last}");
        last = a;
    }
    // One ball_ground (table D.1, sound 1) from the ball's source per
    // bounce, logged within a frame of the lowest point.
    assert_eq!(plays.len(), lows.len(), "plays {plays:?}, bounces {lows:?}");
    for (&(frame, source, ref file), &low) in plays.iter().zip(&lows) {
        assert_eq!(file, "ball_ground.wav");
        assert_eq!(source, 1000);
        assert!(frame.abs_diff(low) <= 1, "PLAY at {frame}, bounce at {low}");
    }
}

#[test]
fn one_or_two_threads_hear_the_same_bounces() {
    let one = bounce(1);
    let two = bounce(2);
    assert_eq!(one.1, two.1);
    assert!(one
        .0
        .iter()
        .zip(&two.0)
        .all(|(a, b)| a.to_bits() == b.to_bits()));
}
