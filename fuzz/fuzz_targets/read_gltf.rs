//! Fuzz the glTF mesh reader (`.gltf` JSON or `.glb`; no external buffers): any input must give
//! `Ok` or `Err`, never a panic or an out-of-range read.

#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let _ = tress_hair::formats::gltf::read_gltf(data, None);
});
