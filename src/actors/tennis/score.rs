//! The match score the referee keeps (thesis 5.7, "a subset of the
//! international tennis rules"): points, games, sets and the match, who
//! serves, from which half, first or second service. As in the thesis
//! there is no tie-break (a set goes on until a player leads by two
//! games) and no change of ends.

use super::court::{Half, Side};

/// Games that win a set, given a two-game lead.
pub const SET_GAMES: u32 = 6;

/// Points that win a game, given a two-point lead (love, fifteen,
/// thirty, forty, game).
pub const GAME_POINTS: u32 = 4;

/// The first or the second service of a point.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Service {
    First,
    Second,
}

/// The score of the game in play, as the referee says it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum GameScore {
    /// Both below forty or one at forty ahead: points won by
    /// [server, receiver], each 0..=3 (love, fifteen, thirty, forty).
    Points([u32; 2]),
    /// Forty all, or level again after an advantage.
    Deuce,
    /// One point ahead after deuce.
    Advantage(Side),
}

/// What a point changed beyond the game's score.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Scored {
    /// The game goes on.
    Point,
    /// The winner took the game; the set goes on.
    Game(Side),
    /// The winner took the game and the set; `games` is the set's final
    /// count by [green, blue].
    Set { winner: Side, games: [u32; 2] },
    /// The winner took the last set and the match.
    Match { winner: Side, games: [u32; 2] },
}

/// A match: its state is counts only, so every state is a pure function
/// of the sequence of points, faults and lets.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Match {
    best_of: u32,
    /// Points, games and sets won, by player index.
    points: [u32; 2],
    games: [u32; 2],
    sets: [u32; 2],
    server: Side,
    service: Service,
    winner: Option<Side>,
}

impl Default for Match {
    /// One set, green serves first.
    fn default() -> Self {
        Match::new(1, Side::Green)
    }
}

/// Whether a count wins against another: at least `target` and two
/// ahead.
fn wins(a: u32, b: u32, target: u32) -> bool {
    a >= target && a >= b + 2
}

impl Match {
    /// A match over the best of `best_of` sets (made odd, at least one,
    /// so that it always has a winner), `first_server` serving.
    pub fn new(best_of: u32, first_server: Side) -> Match {
        Match {
            best_of: best_of.max(1) | 1,
            points: [0; 2],
            games: [0; 2],
            sets: [0; 2],
            server: first_server,
            service: Service::First,
            winner: None,
        }
    }

    /// Sets the match is played over.
    pub fn best_of(&self) -> u32 {
        self.best_of
    }

    /// Who serves the next service.
    pub fn server(&self) -> Side {
        self.server
    }

    /// The receiver of the next service.
    pub fn receiver(&self) -> Side {
        self.server.opponent()
    }

    /// The half the server serves from: the right for the first point of
    /// a game, then alternately (ITF rule 9).
    pub fn half(&self) -> Half {
        if (self.points[0] + self.points[1]).is_multiple_of(2) {
            Half::Right
        } else {
            Half::Left
        }
    }

    /// First or second service.
    pub fn service(&self) -> Service {
        self.service
    }

    /// Points won in the game in play by [green, blue].
    pub fn points(&self) -> [u32; 2] {
        self.points
    }

    /// Games won in the set in play by [green, blue].
    pub fn games(&self) -> [u32; 2] {
        self.games
    }

    /// Sets won by [green, blue].
    pub fn sets(&self) -> [u32; 2] {
        self.sets
    }

    /// The match's winner, once it is over.
    pub fn winner(&self) -> Option<Side> {
        self.winner
    }

    /// Whether the match is over.
    pub fn finished(&self) -> bool {
        self.winner.is_some()
    }

    /// The game's score from the server's side.
    pub fn game_score(&self) -> GameScore {
        let s = self.points[self.server.index()];
        let r = self.points[self.receiver().index()];
        if s >= 3 && s == r {
            GameScore::Deuce
        } else if s >= 3 && r >= 3 {
            let ahead = if s > r { self.server } else { self.receiver() };
            GameScore::Advantage(ahead)
        } else {
            GameScore::Points([s, r])
        }
    }

    /// `by` won the point. After the match is over nothing changes.
    pub fn point_won(&mut self, by: Side) -> Scored {
        if let Some(winner) = self.winner {
            return Scored::Match {
                winner,
                games: self.games,
            };
        }
        self.service = Service::First;
        let (w, l) = (by.index(), by.opponent().index());
        self.points[w] += 1;
        if !wins(self.points[w], self.points[l], GAME_POINTS) {
            return Scored::Point;
        }
        self.points = [0; 2];
        self.server = self.server.opponent();
        self.games[w] += 1;
        if !wins(self.games[w], self.games[l], SET_GAMES) {
            return Scored::Game(by);
        }
        let games = std::mem::take(&mut self.games);
        self.sets[w] += 1;
        if self.sets[w] > self.best_of / 2 {
            self.winner = Some(by);
            Scored::Match { winner: by, games }
        } else {
            Scored::Set { winner: by, games }
        }
    }

    /// The service was a fault: the first one gives a second service,
    /// the second one (a double fault) the point to the receiver (ITF
    /// rule 17). `None` when the second service follows.
    pub fn fault(&mut self) -> Option<Scored> {
        match self.service {
            Service::First if !self.finished() => {
                self.service = Service::Second;
                None
            }
            _ => Some(self.point_won(self.receiver())),
        }
    }

    /// A let: the service is replayed, first or second as it was, and no
    /// fault counts (ITF rule 22). The score does not change.
    pub fn let_(&mut self) {}
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;
    use Side::{Blue, Green};

    /// Plays points won by the players named "g"/"b" in `seq`.
    fn play(m: &mut Match, seq: &str) -> Vec<Scored> {
        seq.chars()
            .map(|c| m.point_won(if c == 'g' { Green } else { Blue }))
            .collect()
    }

    /// Gives `p` a game from love (four straight points).
    fn game(m: &mut Match, p: Side) -> Scored {
        (0..4).map(|_| m.point_won(p)).last().unwrap()
    }

    #[test]
    fn points_love_to_game() {
        let mut m = Match::default();
        assert_eq!(m.game_score(), GameScore::Points([0, 0]));
        let scores: Vec<_> = "ggg"
            .chars()
            .map(|_| {
                m.point_won(Green);
                m.game_score()
            })
            .collect();
        use GameScore::Points;
        assert_eq!(scores, [Points([1, 0]), Points([2, 0]), Points([3, 0])]);
        assert_eq!(m.point_won(Green), Scored::Game(Green));
        assert_eq!(m.games(), [1, 0]);
        assert_eq!(m.points(), [0, 0]);
    }

    /// Every order of three points each reaches deuce, from the server's
    /// side whatever the order.
    #[test]
    fn every_way_to_deuce() {
        for bits in 0u32..64 {
            if bits.count_ones() != 3 {
                continue;
            }
            let seq: String = (0..6)
                .map(|i| if bits >> i & 1 == 1 { 'g' } else { 'b' })
                .collect();
            let mut m = Match::default();
            let scored = play(&mut m, &seq);
            assert!(scored.iter().all(|s| *s == Scored::Point), "{seq}");
            assert_eq!(m.game_score(), GameScore::Deuce, "{seq}");
        }
    }

    #[test]
    fn deuce_advantage_both_ways_then_game() {
        for p in Side::BOTH {
            let mut m = Match::default();
            play(&mut m, "gggbbb");
            assert_eq!(m.point_won(p), Scored::Point);
            assert_eq!(m.game_score(), GameScore::Advantage(p));
            assert_eq!(m.point_won(p.opponent()), Scored::Point);
            assert_eq!(m.game_score(), GameScore::Deuce);
            m.point_won(p.opponent());
            assert_eq!(m.game_score(), GameScore::Advantage(p.opponent()));
            m.point_won(p);
            assert_eq!(m.game_score(), GameScore::Deuce);
            m.point_won(p);
            assert_eq!(m.point_won(p), Scored::Game(p));
            assert_eq!(m.games()[p.index()], 1);
            assert_eq!(m.game_score(), GameScore::Points([0, 0]));
        }
    }

    /// Forty–thirty is not deuce; the trailing player levels to deuce.
    #[test]
    fn forty_thirty_is_not_deuce() {
        let mut m = Match::default();
        play(&mut m, "gggbb");
        assert_eq!(m.game_score(), GameScore::Points([3, 2]));
        play(&mut m, "b");
        assert_eq!(m.game_score(), GameScore::Deuce);
    }

    /// The score is said from the server's side: blue serves the second
    /// game.
    #[test]
    fn score_from_the_servers_side() {
        let mut m = Match::default();
        game(&mut m, Green);
        assert_eq!(m.server(), Blue);
        play(&mut m, "g");
        assert_eq!(m.game_score(), GameScore::Points([0, 1]));
    }

    #[test]
    fn server_changes_each_game_and_half_alternates() {
        let mut m = Match::new(1, Blue);
        let mut halves = Vec::new();
        for _ in 0..5 {
            halves.push(m.half());
            m.point_won(Green);
            m.point_won(Blue);
        }
        use Half::{Left, Right};
        assert_eq!(halves, [Right; 5]);
        assert_eq!(m.half(), Right);
        m.point_won(Blue);
        assert_eq!(m.half(), Left);
        assert_eq!(m.server(), Blue);
        m.point_won(Blue);
        assert_eq!(m.server(), Green);
        assert_eq!(m.half(), Right);
        for g in 1..8 {
            assert_eq!(m.server(), if g % 2 == 1 { Green } else { Blue });
            game(&mut m, Green);
        }
    }

    fn set_to(m: &mut Match, order: &str) -> Scored {
        order
            .chars()
            .map(|c| game(m, if c == 'g' { Green } else { Blue }))
            .last()
            .unwrap()
    }

    #[test]
    fn set_six_four() {
        let mut m = Match::default();
        let last = set_to(&mut m, "gbgbgbgbgg");
        assert_eq!(
            last,
            Scored::Match {
                winner: Green,
                games: [6, 4]
            }
        );
        assert!(m.finished());
        assert_eq!(m.sets(), [1, 0]);
    }

    #[test]
    fn set_seven_five_after_five_all() {
        let mut m = Match::new(3, Green);
        assert_eq!(set_to(&mut m, "gbgbgbgbgbb"), Scored::Game(Blue));
        assert_eq!(m.games(), [5, 6]);
        let last = set_to(&mut m, "b");
        assert_eq!(
            last,
            Scored::Set {
                winner: Blue,
                games: [5, 7]
            }
        );
        assert_eq!(m.games(), [0, 0]);
        assert_eq!(m.sets(), [0, 1]);
        assert!(!m.finished());
    }

    /// No tie-break: at six all the set goes on until two ahead.
    #[test]
    fn long_set_eight_six() {
        let mut m = Match::default();
        let out = set_to(&mut m, "gbgbgbgbgbgbgg");
        assert_eq!(
            out,
            Scored::Match {
                winner: Green,
                games: [8, 6]
            }
        );
        let mut m = Match::default();
        assert_eq!(set_to(&mut m, "gbgbgbgbgbgb"), Scored::Game(Blue));
        assert_eq!(m.games(), [6, 6]);
        assert_eq!(set_to(&mut m, "g"), Scored::Game(Green));
        assert_eq!(m.games(), [7, 6]);
    }

    #[test]
    fn best_of_three_match_ends_at_two_sets() {
        let mut m = Match::new(3, Green);
        let wins = |m: &mut Match, p| (0..6).map(|_| game(m, p)).last().unwrap();
        assert!(matches!(
            wins(&mut m, Green),
            Scored::Set { winner: Green, .. }
        ));
        assert!(matches!(
            wins(&mut m, Blue),
            Scored::Set { winner: Blue, .. }
        ));
        assert_eq!(
            wins(&mut m, Blue),
            Scored::Match {
                winner: Blue,
                games: [0, 6]
            }
        );
        assert_eq!(m.sets(), [1, 2]);
        assert_eq!(m.winner(), Some(Blue));
        // A finished match no longer scores.
        let before = m.clone();
        m.point_won(Green);
        assert_eq!(
            m.fault(),
            Some(Scored::Match {
                winner: Blue,
                games: [0, 0]
            })
        );
        assert_eq!(m, before);
    }

    #[test]
    fn best_of_is_odd_and_at_least_one() {
        assert_eq!(Match::new(0, Green).best_of(), 1);
        assert_eq!(Match::new(2, Green).best_of(), 3);
        assert_eq!(Match::new(5, Green).best_of(), 5);
    }

    /// ITF rule 17: two faults in a row lose the point; a let between
    /// them does not count; after a point the first service comes back.
    #[test]
    fn double_fault() {
        let mut m = Match::default();
        assert_eq!(m.fault(), None);
        assert_eq!(m.service(), Service::Second);
        assert_eq!(m.half(), Half::Right);
        assert_eq!(m.fault(), Some(Scored::Point));
        assert_eq!(m.points(), [0, 1]);
        assert_eq!(m.service(), Service::First);
        assert_eq!(m.half(), Half::Left);

        m.fault();
        m.let_();
        assert_eq!(m.service(), Service::Second);
        assert_eq!(m.fault(), Some(Scored::Point));
        assert_eq!(m.points(), [0, 2]);

        m.let_();
        assert_eq!(m.fault(), None);
        m.point_won(Green);
        assert_eq!(m.service(), Service::First);
        assert_eq!(m.fault(), None);
        assert_eq!(m.points(), [1, 2]);
    }

    #[test]
    fn double_fault_can_end_the_game() {
        let mut m = Match::default();
        play(&mut m, "bbb");
        m.fault();
        assert_eq!(m.fault(), Some(Scored::Game(Blue)));
        assert_eq!(m.server(), Blue);
        assert_eq!(m.service(), Service::First);
    }

    /// A score is valid when no count has already won.
    fn valid(m: &Match) -> bool {
        let [pg, pb] = m.points();
        let [gg, gb] = m.games();
        !wins(pg, pb, GAME_POINTS)
            && !wins(pb, pg, GAME_POINTS)
            && !wins(gg, gb, SET_GAMES)
            && !wins(gb, gg, SET_GAMES)
            && m.sets().iter().all(|&s| s <= m.best_of() / 2 + 1)
    }

    proptest! {
        #[test]
        fn random_matches_keep_valid_scores(
            events in proptest::collection::vec(0u8..4, 0..1500),
            best_of in 1u32..6,
        ) {
            let mut m = Match::new(best_of, Green);
            for e in events {
                let before = m.clone();
                let scored = match e {
                    0 => Some(m.point_won(Green)),
                    1 => Some(m.point_won(Blue)),
                    2 => m.fault(),
                    _ => { m.let_(); None }
                };
                if before.finished() {
                    prop_assert_eq!(&m, &before);
                    continue;
                }
                prop_assert!(valid(&m));
                match scored {
                    Some(Scored::Set { winner, games } | Scored::Match { winner, games }) => {
                        let (w, l) = (games[winner.index()], games[winner.opponent().index()]);
                        prop_assert!(w >= SET_GAMES && w >= l + 2 && (w == SET_GAMES || w == l + 2));
                        prop_assert_eq!(m.games(), [0, 0]);
                        prop_assert_eq!(m.finished(), matches!(scored, Some(Scored::Match { .. })));
                    }
                    Some(Scored::Game(_)) => prop_assert_eq!(m.server(), before.server().opponent()),
                    _ => prop_assert_eq!(m.server(), before.server()),
                }
            }
        }
    }
}
