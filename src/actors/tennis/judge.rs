//! The audition part of the `tennis_error_detection` automata (thesis
//! 5.7): the referee hears the ball's collisions one after the other and
//! decides when a service or a point ends, and why.
//!
//! "The `ball_racket` event only produces errors if the striker doesn't
//! let bounce the ball after the service. […] The `ball_ground` sound
//! event produces an error if the ball is out of the corresponding court
//! side or has bounced twice. […] The `ball_net` sound event produces an
//! error only after a service stroke." A service that touches the net
//! and then lands in the box is a let (ITF rule 22); on a rally the net
//! is no error by itself — the bounce that follows decides.

use super::court::{court, service_box, side_of, Half, Side};

/// A collision the referee hears (sound events 0, 1 and 9), the striker
/// and the landing point as its vision places them.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Heard {
    /// `ball_racket`: `striker` hit the ball.
    BallRacket { striker: Side },
    /// `ball_ground`: the ball bounced at `[x, z]`.
    BallGround { at: [f64; 2] },
    /// `ball_net`: the ball touched the net.
    BallNet,
}

/// Why a service or a point ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Cause {
    /// The ball's first bounce after a stroke was across the net but
    /// outside the singles court (the service box for a service).
    Out,
    /// The ball's first bounce after a stroke was on the striker's own
    /// side: it did not cross the net.
    Net,
    /// The ball bounced twice before the receiver returned it.
    DoubleBounce,
    /// The receiver hit a service before it bounced.
    NotBounced,
}

/// The referee's decision.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Verdict {
    /// The service is a fault (first or second: the score decides).
    Fault(Cause),
    /// The service touched the net and landed in the box: serve again.
    Let,
    /// The point is over: `loser` made the error.
    Point { loser: Side, cause: Cause },
}

impl Verdict {
    /// The player whose error it is (the server's, for a fault); nobody's
    /// for a let.
    pub fn faulty(self, server: Side) -> Option<Side> {
        match self {
            Verdict::Fault(_) => Some(server),
            Verdict::Let => None,
            Verdict::Point { loser, .. } => Some(loser),
        }
    }
}

/// The judge of one service and the rally after it.
#[derive(Debug, Clone, PartialEq)]
pub struct Judge {
    server: Side,
    half: Half,
    /// The last player to hit the ball; `None` until the service.
    striker: Option<Side>,
    /// On from the service until the receiver returns it.
    service_phase: bool,
    /// Bounces since the last stroke.
    bounces: u32,
    /// The service touched the net before its first bounce.
    net: bool,
    verdict: Option<Verdict>,
}

impl Judge {
    /// Ready for `server`'s service from `half`.
    pub fn new(server: Side, half: Half) -> Judge {
        Judge {
            server,
            half,
            striker: None,
            service_phase: true,
            bounces: 0,
            net: false,
            verdict: None,
        }
    }

    /// The decision, once there is one.
    pub fn verdict(&self) -> Option<Verdict> {
        self.verdict
    }

    /// Hears one collision; returns the decision when it ends the service
    /// or the point. Once decided, the judge hears nothing more; before
    /// the service, only the server's stroke counts.
    pub fn hear(&mut self, e: Heard) -> Option<Verdict> {
        if self.verdict.is_some() {
            return None;
        }
        let Some(striker) = self.striker else {
            if matches!(e, Heard::BallRacket { striker } if striker == self.server) {
                self.striker = Some(self.server);
            }
            return None;
        };
        self.verdict = match e {
            Heard::BallRacket { striker: p } => self.racket(striker, p),
            Heard::BallGround { at } => self.ground(striker, at),
            Heard::BallNet => {
                self.net |= self.bounces == 0;
                None
            }
        };
        self.verdict
    }

    /// A stroke by `p` after `striker`'s. The striker's racket again is
    /// the same stroke heard twice (the ball can touch a racket on two
    /// frames) and changes nothing.
    fn racket(&mut self, striker: Side, p: Side) -> Option<Verdict> {
        if p == striker {
            return None;
        }
        if self.service_phase && self.bounces == 0 {
            return Some(Verdict::Point {
                loser: p,
                cause: Cause::NotBounced,
            });
        }
        self.striker = Some(p);
        self.service_phase = false;
        self.bounces = 0;
        self.net = false;
        None
    }

    /// A bounce at `at` after `striker`'s stroke.
    fn ground(&mut self, striker: Side, at: [f64; 2]) -> Option<Verdict> {
        self.bounces += 1;
        if self.bounces > 1 {
            return Some(Verdict::Point {
                loser: striker.opponent(),
                cause: Cause::DoubleBounce,
            });
        }
        let target = if self.service_phase {
            service_box(self.server, self.half)
        } else {
            court(striker.opponent())
        };
        if target.contains(at) {
            return (self.service_phase && self.net).then_some(Verdict::Let);
        }
        let cause = if side_of(at) == striker {
            Cause::Net
        } else {
            Cause::Out
        };
        Some(if self.service_phase {
            Verdict::Fault(cause)
        } else {
            Verdict::Point {
                loser: striker,
                cause,
            }
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;
    use Heard::{BallGround, BallNet, BallRacket};
    use Side::{Blue, Green};

    fn hit(p: Side) -> Heard {
        BallRacket { striker: p }
    }

    fn at(x: f64, z: f64) -> Heard {
        BallGround { at: [x, z] }
    }

    /// The verdicts heard along `events`, with the index of each.
    fn judge(server: Side, half: Half, events: &[Heard]) -> Vec<(usize, Verdict)> {
        let mut j = Judge::new(server, half);
        events
            .iter()
            .enumerate()
            .filter_map(|(i, e)| j.hear(*e).map(|v| (i, v)))
            .collect()
    }

    #[test]
    fn a_good_rally_goes_on_until_a_double_bounce() {
        // Green serves from its right (+z) into blue's right box (−z).
        let rally = [
            hit(Green),
            at(4.0, -2.0),
            hit(Blue),
            BallNet, // a net cord on a rally is no error
            at(-9.0, 3.0),
            hit(Green),
            at(11.0, 4.0),
            hit(Blue),
            hit(Blue), // the same stroke heard twice
            at(-3.0, -1.0),
        ];
        assert_eq!(judge(Green, Half::Right, &rally), []);
        let mut two = rally.to_vec();
        two.push(at(-12.5, 0.0));
        assert_eq!(
            judge(Green, Half::Right, &two),
            [(
                10,
                Verdict::Point {
                    loser: Green,
                    cause: Cause::DoubleBounce
                }
            )]
        );
    }

    /// An ace: the service bounces in the box and again.
    #[test]
    fn an_ace_is_a_double_bounce() {
        let v = judge(
            Blue,
            Half::Left,
            &[hit(Blue), at(-5.0, -3.0), at(-14.0, -5.0)],
        );
        assert_eq!(
            v,
            [(
                2,
                Verdict::Point {
                    loser: Green,
                    cause: Cause::DoubleBounce
                }
            )]
        );
    }

    #[test]
    fn out_behind_the_base_line_and_wide() {
        for landing in [at(12.0, 0.0), at(8.0, 4.2)] {
            let v = judge(
                Blue,
                Half::Right,
                &[hit(Blue), at(-6.0, 1.0), hit(Green), landing],
            );
            let out = Verdict::Point {
                loser: Green,
                cause: Cause::Out,
            };
            assert_eq!(v, [(3, out)]);
        }
        // On the lines it is in.
        let v = judge(
            Blue,
            Half::Right,
            &[hit(Blue), at(-6.0, 1.0), hit(Green), at(11.885, -4.115)],
        );
        assert_eq!(v, []);
    }

    #[test]
    fn rally_into_the_net_loses_for_the_striker() {
        let v = judge(
            Green,
            Half::Left,
            &[hit(Green), at(2.0, 1.0), hit(Blue), BallNet, at(0.5, 0.0)],
        );
        let net = Verdict::Point {
            loser: Blue,
            cause: Cause::Net,
        };
        assert_eq!(v, [(4, net)]);
    }

    #[test]
    fn service_faults() {
        use Cause::{Net, Out};
        let cases = [
            // Long, wide, the wrong box, into the net.
            (vec![hit(Green), at(7.0, -2.0)], Out),
            (vec![hit(Green), at(3.0, -4.2)], Out),
            (vec![hit(Green), at(3.0, 2.0)], Out),
            (vec![hit(Green), BallNet, at(-0.3, 0.0)], Net),
            // Over the net cord but long.
            (vec![hit(Green), BallNet, at(8.0, -1.0)], Out),
        ];
        for (events, cause) in cases {
            let n = events.len() - 1;
            assert_eq!(
                judge(Green, Half::Right, &events),
                [(n, Verdict::Fault(cause))],
                "{events:?}"
            );
        }
    }

    #[test]
    fn let_is_the_net_then_the_box() {
        let v = judge(Blue, Half::Right, &[hit(Blue), BallNet, at(-4.0, 2.0)]);
        assert_eq!(v, [(2, Verdict::Let)]);
        // Without the net the same service is good.
        assert_eq!(judge(Blue, Half::Right, &[hit(Blue), at(-4.0, 2.0)]), []);
    }

    #[test]
    fn volleyed_service_loses_for_the_receiver() {
        let v = judge(Green, Half::Right, &[hit(Green), hit(Blue)]);
        let volley = Verdict::Point {
            loser: Blue,
            cause: Cause::NotBounced,
        };
        assert_eq!(v, [(1, volley)]);
        // After the return the service phase is over: volleys are fine.
        let rally = [
            hit(Green),
            at(3.0, -1.0),
            hit(Blue),
            hit(Green),
            at(9.0, 0.0),
        ];
        assert_eq!(judge(Green, Half::Right, &rally), []);
    }

    #[test]
    fn nothing_counts_before_the_service_or_after_the_verdict() {
        let events = [
            at(-11.0, 1.0),
            BallNet,
            hit(Blue),
            hit(Green),
            at(7.0, 0.0),
            at(3.0, -1.0),
        ];
        assert_eq!(
            judge(Green, Half::Right, &events),
            [(4, Verdict::Fault(Cause::Out))]
        );
        let mut j = Judge::new(Green, Half::Right);
        j.hear(hit(Green));
        j.hear(at(7.0, 0.0));
        assert_eq!(j.verdict(), Some(Verdict::Fault(Cause::Out)));
    }

    fn heard() -> impl Strategy<Value = Heard> {
        prop_oneof![
            Just(hit(Green)),
            Just(hit(Blue)),
            Just(BallNet),
            (-14.0..14.0, -6.0..6.0).prop_map(|(x, z)| at(x, z)),
        ]
    }

    proptest! {
        /// Whatever it hears, the judge decides at most once, and never
        /// lets the ball bounce twice after the service without a
        /// decision.
        #[test]
        fn one_verdict_and_no_third_bounce(
            events in proptest::collection::vec(heard(), 0..40),
        ) {
            let verdicts = judge(Green, Half::Left, &events);
            prop_assert!(verdicts.len() <= 1);
            let mut served = false;
            let mut bounces = 0;
            for (i, e) in events.iter().enumerate() {
                match e {
                    BallRacket { striker } => {
                        served |= *striker == Green;
                        bounces = 0;
                    }
                    BallGround { .. } if served => bounces += 1,
                    _ => {}
                }
                if bounces == 2 {
                    prop_assert!(verdicts.first().is_some_and(|&(j, _)| j <= i));
                    break;
                }
            }
        }
    }

    #[test]
    fn the_faulty_player() {
        let point = Verdict::Point {
            loser: Green,
            cause: Cause::Out,
        };
        assert_eq!(point.faulty(Blue), Some(Green));
        assert_eq!(Verdict::Fault(Cause::Net).faulty(Blue), Some(Blue));
        assert_eq!(Verdict::Let.faulty(Blue), None);
    }
}
