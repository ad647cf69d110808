//! lmfilm: Noser's behavioural L-systems as a deterministic film pipeline.
//!
//! The layers follow the frame loop's data flow (DESIGN §2): `lsys` →
//! `turtle` → `scene` → `physics` → `sound` → `render` → `actors` → `film`;
//! a module imports only the ones before it. The tools below the layers
//! (located source text and its diagnostics, counter-based random
//! numbers, atomic writes, boxes, the error type) serve them all.

pub mod aabb;
pub mod atomic;
pub mod error;
pub mod random;
pub mod source;

pub mod commands;
pub mod film;
pub mod lsys;
pub mod physics;
pub mod production;
pub mod render;

pub mod actors;
pub mod scene;
pub mod sound;
pub mod turtle;
