//! Integration tests of the actors: synthetic vision (issue 13).
//!
//! One test binary per layer (issue 12 §6): each test file is a module
//! here, so the layer links once.

mod behaviour;
mod memory_room;
mod path;
mod support;
mod symbols;
mod vision;
