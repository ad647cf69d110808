//! The integrators by name: the one place that turns an [`Integrator`]
//! of the settings into the type that renders it. A new integrator is a
//! file with a type implementing [`Integrate`], its variant (and name)
//! in [`Integrator`], and its line here.

use super::path::PathTracer;
use super::sample::Integrate;
use super::settings::Integrator;
use super::whitted::Whitted;

/// A fresh `kind` integrator, its buffers empty, for a row.
pub fn start(kind: Integrator) -> Box<dyn Integrate> {
    match kind {
        Integrator::Whitted => Box::<Whitted>::default(),
        Integrator::Path => Box::<PathTracer>::default(),
    }
}
