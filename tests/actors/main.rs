//! Integration tests of the actors: synthetic vision and memory (issue
//! 13), behaviours and navigation (issue 14).
//!
//! One test binary per layer (issue 12 §6): each test file is a module
//! here, so the layer links once.

#[path = "../common/mod.rs"]
mod common;

mod behaviour;
mod bodies;
mod footholds;
mod maze;
mod memory_room;
mod mutation;
mod path;
mod regressions;
mod stones;
mod support;
mod symbols;
mod tennis;
mod tennis_match;
mod terraces;
mod terrain;
mod vision;
mod worlds;
