//! Fuzz the scene TOML reader: any text must give `Ok` or `Err`, never a panic; an accepted
//! scene must serialize and read back equal.

#![no_main]

libfuzzer_sys::fuzz_target!(
    init: tress_hair_fuzz::abort_on_every_panic(),
    |data: &[u8]| tress_hair_fuzz::read_scene_check(data)
);
