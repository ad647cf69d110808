pub mod lsys;
pub mod scene;
pub mod turtle;
