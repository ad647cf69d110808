pub mod film;
pub mod lsys;
pub mod physics;
pub mod render;
pub mod scene;
pub mod sound;
pub mod turtle;
