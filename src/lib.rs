//! lmfilm: Noser's behavioural L-systems as a deterministic film pipeline.
//!
//! The layers, lowest first (docs/design.md; `tests/architecture` keeps
//! them): the tools (located source text and its diagnostics, the error
//! type, counter-based random numbers, atomic writes, boxes) → `lsys`,
//! `scene` → `physics`, `turtle`, `render`, `sound` → `actors` → `film`
//! (the simulation) → `production` (the pipeline that makes a film
//! folder) → `commands`. A module imports only lower layers, and no two
//! files import each other.

// The tools.
pub mod aabb;
pub mod atomic;
pub mod error;
pub mod random;
pub mod source;

// The language and the world it describes.
pub mod lsys;
pub mod scene;

// What the world does and how it looks and sounds.
pub mod physics;
pub mod render;
pub mod sound;
pub mod turtle;

pub mod actors;

pub mod film;

pub mod production;

pub mod commands;
