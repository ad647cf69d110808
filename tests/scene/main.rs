//! Integration tests of the scene layer: the turtle, meshes, OBJ output and
//! snapshots.
//!
//! One test binary per layer (issue 12 §6): each former test file is a
//! module here, so the layer links once.

#[path = "../common/mod.rs"]
mod common;

mod body;
mod gait;
mod mesh;
mod mocap;
mod obj;
mod snapshot;
mod tennis_set;
mod turtle;
