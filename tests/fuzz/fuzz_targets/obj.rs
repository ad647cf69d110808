//! An OBJ file whose `mtllib` finds the repository's leaf material.
#![no_main]

use libfuzzer_sys::fuzz_target;
use lmfilm::scene::obj::parse_obj;

const LEAF_MTL: &[u8] = include_bytes!("../../../scenes/meshes/leaf.mtl");

fuzz_target!(|data: &[u8]| {
    let found = |_: &str| Ok(Some(("leaf.mtl".to_string(), LEAF_MTL.to_vec())));
    let _ = parse_obj(data, 0, &found);
});
