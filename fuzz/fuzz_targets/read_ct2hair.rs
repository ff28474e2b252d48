//! Fuzz the CT2Hair `.bin` reader: any input must give `Ok` or `Err`, never a panic.

#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let _ = tress_hair::formats::read_ct2hair(data);
});
