//! Fuzz the TressFX `.tfx` reader (3.x and 4.x): any input must give `Ok` or `Err`, never a
//! panic, and accepted guides must write back as 4.x and read again unchanged (less the
//! attributes 4.x does not hold).
//!
//! The version is a float compare, which libFuzzer's comparison tracing does not see, so each
//! input is also tried with its first four bytes replaced by 3.0 and by 4.0 to reach both layouts.

#![no_main]

libfuzzer_sys::fuzz_target!(
    init: tress_hair_fuzz::abort_on_every_panic(),
    |data: &[u8]| tress_hair_fuzz::read_tfx_check(data)
);
