//! Fuzz the USC-HairSalon `.data` reader: any input must give `Ok` or `Err`, and an accepted
//! file must write back and read again to the same asset.

#![no_main]

libfuzzer_sys::fuzz_target!(
    init: tress_hair_fuzz::abort_on_every_panic(),
    |data: &[u8]| tress_hair_fuzz::read_data_check(data)
);
