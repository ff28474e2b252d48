//! Fuzz the USD reader (openusd, then tress's curves and meshes): the first byte picks the
//! flavour (`usda`, `usdc`, `usdz`), the rest is the file. Any input must give `Ok` or `Err`.

#![no_main]

libfuzzer_sys::fuzz_target!(
    init: tress_hair_fuzz::abort_on_every_panic(),
    |data: &[u8]| tress_hair_fuzz::read_usd_check(data)
);
