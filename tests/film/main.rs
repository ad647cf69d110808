//! Integration tests of the film driver and the command line: run, records,
//! support modules, determinism and limits.
//!
//! One test binary per layer (issue 12 §6): each former test file is a
//! module here, so the layer links once.

#[path = "../common/mod.rs"]
mod common;

mod actor_images;
mod cli;
mod determinism;
mod farm;
mod film;
mod frame_loop;
mod hostile_folders;
mod limits;
mod lsp;
mod mp4;
mod path;
mod readable;
mod records;
mod settings;
mod support;
mod tracks;
mod watch;
