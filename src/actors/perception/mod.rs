//! What an actor knows of the world, and only through its senses: the
//! vision window cast into the frame's BVH (`vision`), the visual memory
//! it feeds (`memory` over an `octree`), and their images (`display`).

pub mod display;
pub mod memory;
pub mod octree;
pub mod vision;

#[cfg(test)]
mod memory_tests;
