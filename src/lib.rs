pub mod lsys;
