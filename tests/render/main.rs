//! Integration tests of the ray tracer: exact intersection, real scenes,
//! golden images and frame output.
//!
//! One test binary per layer (issue 12 §6): each former test file is a
//! module here, so the layer links once.

#[path = "../common/mod.rs"]
mod common;

mod golden;
mod intersect;
mod output;
mod scenes;
