//! Fuzz the glTF mesh reader (`.gltf` JSON or `.glb`; no external buffers): any input must give
//! `Ok` or `Err`, never a panic or an out-of-range read.

#![no_main]

libfuzzer_sys::fuzz_target!(
    init: tress_hair_fuzz::abort_on_every_panic(),
    |data: &[u8]| tress_hair_fuzz::read_gltf_check(data)
);
