//! Integration tests of the physics layer: particles, fields on the grid,
//! collisions and the physics scenes.
//!
//! One test binary per layer (issue 12 §6): each former test file is a
//! module here, so the layer links once.

mod collisions;
mod grid;
mod particles;
mod racket;
mod scenes;
