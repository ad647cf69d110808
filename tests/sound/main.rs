//! Integration tests of the sound layer: events, rendering, loudness and
//! the sound of a scene.
//!
//! One test binary per layer (issue 12 §6): each former test file is a
//! module here, so the layer links once.

#[path = "../common/mod.rs"]
mod common;

mod events;
mod loudness;
mod render;
mod scene;
