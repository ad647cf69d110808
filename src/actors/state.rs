//! The values of an actor's `state` (table B6) that the automata set,
//! in one place: a file of its own, so that every automaton reads them
//! without importing the actor's state type (issue 55).

pub const LOOK_AROUND: i64 = 6;
pub const SEARCH_NEW_PATH: i64 = 7;
pub const ALIGN: i64 = 8;
pub const WALK: i64 = 10;
pub const EXPLORE: i64 = 11;
pub const STOP: i64 = 12;
pub const FIX_THING: i64 = 16;
pub const INIT_TENNIS_GAME: i64 = 19;
pub const UPDATE_TENNIS_GAME: i64 = 20;
pub const LISTEN_WORDS: i64 = 23;
pub const TALK: i64 = 25;
