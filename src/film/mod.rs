//! The film's simulation (DESIGN §1): the frame loop that ties the
//! L-systems, the turtle, the physics, the actors and the sound log
//! together (`Film`, `Frame`, the lower layers' window), the data it
//! imports and exports (channels, trajectories), what `trace` lists, and
//! the names of a film folder. The production pipeline that turns it
//! into a film folder is [`crate::production`].

pub mod frame;
mod view;
pub mod world;
pub use frame::Frame;
pub use world::Film;

pub mod channels;
pub mod names;
pub mod trace;
pub mod tracks;
