//! Fuzz the Alembic reader: any input must give `Ok` or `Err`, never a panic or a huge
//! allocation, both for the raw curves (`tress_alembic::read`) and their tessellation.

#![no_main]

libfuzzer_sys::fuzz_target!(
    init: tress_hair_fuzz::abort_on_every_panic(),
    |data: &[u8]| tress_hair_fuzz::read_abc_check(data)
);
