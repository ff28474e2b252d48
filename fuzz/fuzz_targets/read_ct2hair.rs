//! Fuzz the CT2Hair `.bin` reader: any input must give `Ok` or `Err`, never a panic.

#![no_main]

libfuzzer_sys::fuzz_target!(
    init: tress_hair_fuzz::abort_on_every_panic(),
    |data: &[u8]| tress_hair_fuzz::read_ct2hair_check(data)
);
