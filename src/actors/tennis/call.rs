//! The referee's `update_tennis_game` (thesis 5.7): it applies a verdict
//! to the match, then "comments the error, announces the actual score
//! and indicates the server the place from where it has to play" — for
//! example "out, fault green, fifteen all, service blue, right" — as
//! sound numbers of appendix D for the `talk` automata.
//!
//! The players listen for "fault" (go back to the start), "service" and
//! the two words after it (server, half), and "finished" (5.6.1). The
//! library has no "finished"; the referee ends the match with "exit"
//! (58, table D.2).

use super::court::{Half, Side};
use super::judge::{Cause, Verdict};
use super::score::{GameScore, Match, Scored};

/// The referee's words: sound numbers of tables D.1 and D.2.
pub mod word {
    pub const ADVANTAGE: u32 = 10;
    pub const ALL: u32 = 11;
    pub const DEUCE: u32 = 12;
    pub const FAULT: u32 = 13;
    pub const FIFTEEN: u32 = 14;
    pub const FORTY: u32 = 15;
    pub const GAME: u32 = 16;
    pub const LET: u32 = 17;
    pub const LOVE: u32 = 18;
    pub const THIRTY: u32 = 21;
    pub const BLUE: u32 = 22;
    pub const GREEN: u32 = 23;
    pub const OUT: u32 = 24;
    pub const SERVICE: u32 = 25;
    pub const LEFT: u32 = 26;
    pub const RIGHT: u32 = 27;
    /// "one"; "two" … "ten" follow it (48–57).
    pub const ONE: u32 = 48;
    pub const EXIT: u32 = 58;
}

use word::*;

/// The words as text, for logs and tests.
const TEXT: &[(u32, &str)] = &[
    (ADVANTAGE, "advantage"),
    (ALL, "all"),
    (DEUCE, "deuce"),
    (FAULT, "fault"),
    (FIFTEEN, "fifteen"),
    (FORTY, "forty"),
    (GAME, "game"),
    (LET, "let"),
    (LOVE, "love"),
    (THIRTY, "thirty"),
    (BLUE, "blue"),
    (GREEN, "green"),
    (OUT, "out"),
    (SERVICE, "service"),
    (LEFT, "left"),
    (RIGHT, "right"),
    (ONE, "one"),
    (ONE + 1, "two"),
    (ONE + 2, "three"),
    (ONE + 3, "four"),
    (ONE + 4, "five"),
    (ONE + 5, "six"),
    (ONE + 6, "seven"),
    (ONE + 7, "eight"),
    (ONE + 8, "nine"),
    (ONE + 9, "ten"),
    (EXIT, "exit"),
];

/// Applies the verdict to the match and returns what the referee says:
/// the comment ("out", "let"), "fault" and the faulty player, the score
/// when it changed, then "service", the server and its half — or "exit"
/// when the match is over.
pub fn update(m: &mut Match, v: Verdict) -> Vec<u32> {
    let mut words = comment(v);
    if let Some(p) = v.faulty(m.server()) {
        words.extend([FAULT, colour(p)]);
    }
    let scored = match v {
        Verdict::Let => {
            m.let_();
            None
        }
        Verdict::Fault(_) => m.fault(),
        Verdict::Point { loser, .. } => Some(m.point_won(loser.opponent())),
    };
    if let Some(s) = scored {
        words.extend(score(m, s));
    }
    if m.finished() {
        words.push(EXIT);
    } else {
        words.extend(service(m));
    }
    words
}

/// "service", the server and its half: the players' cue for the next
/// service, and the referee's first words of the match.
pub fn service(m: &Match) -> [u32; 3] {
    let half = match m.half() {
        Half::Right => RIGHT,
        Half::Left => LEFT,
    };
    [SERVICE, colour(m.server()), half]
}

/// The words as text separated by spaces; a number with no word here
/// is written as `#n`.
pub fn text(words: &[u32]) -> String {
    words
        .iter()
        .map(|&n| match TEXT.iter().find(|(w, _)| *w == n) {
            Some((_, t)) => t.to_string(),
            None => format!("#{n}"),
        })
        .collect::<Vec<_>>()
        .join(" ")
}

/// The player's colour word.
pub fn colour(p: Side) -> u32 {
    match p {
        Side::Green => GREEN,
        Side::Blue => BLUE,
    }
}

/// The comment of the error: the library has words for "out" and "let"
/// only, so the other causes are said by "fault" and the player alone.
fn comment(v: Verdict) -> Vec<u32> {
    match v {
        Verdict::Let => vec![LET],
        Verdict::Fault(Cause::Out)
        | Verdict::Point {
            cause: Cause::Out, ..
        } => vec![OUT],
        _ => Vec::new(),
    }
}

/// The score after a point: the game's, or at a game's end "game", the
/// winner and the games.
fn score(m: &Match, s: Scored) -> Vec<u32> {
    match s {
        Scored::Point => game_score(m.game_score()),
        Scored::Game(winner) => [vec![GAME, colour(winner)], games(m.games())].concat(),
        Scored::Set { winner, games: g } | Scored::Match { winner, games: g } => {
            [vec![GAME, colour(winner)], games(g)].concat()
        }
    }
}

/// "fifteen all", "thirty fifteen" (the server's points first), "deuce",
/// "advantage blue".
fn game_score(g: GameScore) -> Vec<u32> {
    const POINTS: [u32; 4] = [LOVE, FIFTEEN, THIRTY, FORTY];
    match g {
        GameScore::Points([s, r]) if s == r => vec![POINTS[s as usize], ALL],
        GameScore::Points([s, r]) => vec![POINTS[s as usize], POINTS[r as usize]],
        GameScore::Deuce => vec![DEUCE],
        GameScore::Advantage(p) => vec![ADVANTAGE, colour(p)],
    }
}

/// The games by [green, blue]: "three all", or the leader and its games
/// first, "green four two".
fn games(g: [u32; 2]) -> Vec<u32> {
    let leader = if g[0] >= g[1] {
        Side::Green
    } else {
        Side::Blue
    };
    let (lead, trail) = (g[leader.index()], g[leader.opponent().index()]);
    if lead == trail {
        return [number(lead), vec![ALL]].concat();
    }
    [vec![colour(leader)], number(lead), number(trail)].concat()
}

/// A count in words: "love" for none, "one" … "ten", and above ten digit
/// by digit ("one two" for 12), as the library stops at ten.
fn number(n: u32) -> Vec<u32> {
    match n {
        0 => vec![LOVE],
        1..=10 => vec![ONE + n - 1],
        _ => n
            .to_string()
            .bytes()
            .flat_map(|d| number(u32::from(d - b'0')))
            .collect(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sound::Library;
    use proptest::prelude::*;
    use Side::{Blue, Green};

    fn point(loser: Side, cause: Cause) -> Verdict {
        Verdict::Point { loser, cause }
    }

    /// The thesis's call (5.7): blue serves; green won the first point
    /// and hits the second one out: fifteen all, blue serves from the
    /// right.
    #[test]
    fn the_thesis_example() {
        let mut m = Match::new(1, Blue);
        update(&mut m, point(Blue, Cause::DoubleBounce));
        let words = update(&mut m, point(Green, Cause::Out));
        assert_eq!(words, [24, 13, 23, 14, 11, 25, 22, 27]);
        assert_eq!(
            text(&words),
            "out, fault green, fifteen all, service blue, right".replace(',', "")
        );
    }

    #[test]
    fn the_words_are_the_librarys() {
        let lib = Library::default();
        for &(n, t) in TEXT {
            let file = if t == "forty" { "fourty" } else { t };
            assert_eq!(lib.file_name(n), Some(format!("{file}.wav").as_str()));
        }
        assert_eq!(text(&[19, 99]), "#19 #99");
    }

    #[test]
    fn faults_and_lets() {
        let mut m = Match::default();
        assert_eq!(text(&service(&m)), "service green right");
        let first = update(&mut m, Verdict::Fault(Cause::Out));
        assert_eq!(text(&first), "out fault green service green right");
        let replay = update(&mut m, Verdict::Let);
        assert_eq!(text(&replay), "let service green right");
        let double = update(&mut m, Verdict::Fault(Cause::Net));
        assert_eq!(text(&double), "fault green love fifteen service green left");
        let volley = update(&mut m, point(Blue, Cause::NotBounced));
        assert_eq!(text(&volley), "fault blue fifteen all service green right");
    }

    #[test]
    fn deuce_advantage_and_game_calls() {
        let mut m = Match::default();
        let mut calls = Vec::new();
        for loser in [
            Blue, Blue, Green, Green, Blue, Green, Blue, Green, Green, Green,
        ] {
            calls.push(text(&update(&mut m, point(loser, Cause::DoubleBounce))));
        }
        let expected = [
            "fault blue fifteen love service green left",
            "fault blue thirty love service green right",
            "fault green thirty fifteen service green left",
            "fault green thirty all service green right",
            "fault blue forty thirty service green left",
            "fault green deuce service green right",
            "fault blue advantage green service green left",
            "fault green deuce service green right",
            "fault green advantage blue service green left",
            "fault green game blue blue one love service blue right",
        ];
        assert_eq!(calls, expected);
    }

    #[test]
    fn games_and_the_match_end() {
        let mut m = Match::default();
        let mut last = Vec::new();
        for g in 0..10 {
            let winner = if g < 5 { Green } else { Blue };
            for _ in 0..4 {
                last = update(&mut m, point(winner.opponent(), Cause::Out));
            }
            if g == 4 {
                assert_eq!(
                    text(&last),
                    "out fault blue game green green five love service blue right"
                );
            }
        }
        assert_eq!(m.winner(), None);
        assert_eq!(
            text(&last),
            "out fault green game blue five all service green right"
        );
        for _ in 0..8 {
            last = update(&mut m, point(Blue, Cause::DoubleBounce));
        }
        assert_eq!(text(&last), "fault blue game green green seven five exit");
        assert!(m.finished());
    }

    fn verdict() -> impl Strategy<Value = Verdict> {
        let player = prop_oneof![Just(Green), Just(Blue)];
        let cause = prop_oneof![
            Just(Cause::Out),
            Just(Cause::Net),
            Just(Cause::DoubleBounce),
            Just(Cause::NotBounced),
        ];
        prop_oneof![
            Just(Verdict::Let),
            cause.clone().prop_map(Verdict::Fault),
            (player, cause).prop_map(|(loser, cause)| Verdict::Point { loser, cause }),
        ]
    }

    proptest! {
        /// Every call is in the library's words and ends with the next
        /// service, or with "exit" once, at the match's end.
        #[test]
        fn calls_end_with_the_service_or_exit(
            verdicts in proptest::collection::vec(verdict(), 0..400),
        ) {
            let mut m = Match::new(3, Green);
            for v in verdicts {
                if m.finished() {
                    break;
                }
                let words = update(&mut m, v);
                prop_assert!(!text(&words).contains('#'));
                if m.finished() {
                    prop_assert_eq!(words.last(), Some(&EXIT));
                } else {
                    prop_assert!(words.ends_with(&service(&m)));
                    prop_assert!(!words.contains(&EXIT));
                }
            }
        }
    }

    #[test]
    fn numbers_in_words() {
        assert_eq!(text(&number(0)), "love");
        assert_eq!(text(&number(7)), "seven");
        assert_eq!(text(&number(10)), "ten");
        assert_eq!(text(&number(12)), "one two");
        assert_eq!(text(&number(20)), "two love");
        assert_eq!(text(&games([3, 3])), "three all");
        assert_eq!(text(&games([2, 4])), "blue four two");
    }
}
