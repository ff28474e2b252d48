//! Fuzz the SATF HRIR database reader (`.satfdb`). The file ends with an FNV-1a checksum of the
//! rest, which random mutations would almost never match; the target writes the right one, so
//! the fuzzer explores the header and arrays behind it. Any input must give `Ok` or `Err`.

#![no_main]

libfuzzer_sys::fuzz_target!(
    init: tress_hair_fuzz::abort_on_every_panic(),
    |data: &[u8]| tress_hair_fuzz::read_satfdb_check(data)
);
