//! How an actor plans a way on what it remembers: the heuristics of
//! table G.1 (`heuristics`), Algorithms 1–4 over the memory's voxels
//! (`path`) and the path spline it walks (`spline`).

pub mod heuristics;
pub mod path;
pub mod spline;
