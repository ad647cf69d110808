pub mod lsys;
pub mod scene;
