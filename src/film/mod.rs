//! The film driver (DESIGN §1, §5): the frame loop that ties the
//! L-systems, the turtle, the renderer and the sound log together, frame
//! ranges and shards, the manifest, resume and mux.

pub mod frame;
mod window;
pub mod world;
pub use frame::Frame;
pub use world::Film;

pub mod actor_images;
pub mod assemble;
pub mod channels;
pub mod frames;
pub mod job;
pub mod manifest;
pub mod mux;
pub mod names;
pub mod record;
pub mod settings;
pub mod trace;
pub mod tracks;
pub mod verify;
