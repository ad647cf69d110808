//! The production pipeline (DESIGN §4, §5): the stages that turn a film
//! into a film folder — derive, render frames, soundtrack, mux — each
//! writing a record of what made its outputs; the film's settings; the
//! frame selections and shards; the manifest assembled from the records;
//! `verify`, which checks the chain; the actors' images; the digests;
//! how the folder's files are read (each one's bound, never waited on).

pub mod actor_images;
pub mod assemble;
pub mod digest;
pub mod folder;
pub mod frames;
pub mod manifest;
pub mod mux;
pub mod pipeline;
pub mod record;
pub mod settings;
pub mod stages;
pub mod timings;
pub mod verify;
pub mod video;
pub mod video_groups;
