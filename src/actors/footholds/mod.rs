//! Walking on sparse footholds (thesis 5.9.3, 7.3.2): stones in a river,
//! where each foot may land only on given points.

pub mod plan;
