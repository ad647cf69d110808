//! Integration tests of the L-system layer: grammars, the thesis' examples,
//! the force functions, and hostile input (every reader).
//!
//! One test binary per layer (issue 12 §6): each former test file is a
//! module here, so the layer links once.

#[path = "../common/mod.rs"]
mod common;

mod bad_input;
mod classic_grammars;
mod fuzz_mutation;
mod grammar;
mod infix;
mod readable;
mod special_functions;
mod thesis_examples;
