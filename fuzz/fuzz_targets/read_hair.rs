//! Fuzz the Cem Yuksel `.hair` reader: any input must give `Ok` or `Err`, never a panic, and an
//! accepted file must write back and read again to the same asset.

#![no_main]

use libfuzzer_sys::fuzz_target;
use tress_hair::formats::{read_hair, write_hair};

fuzz_target!(|data: &[u8]| {
    if let Ok(asset) = read_hair(data) {
        let bytes = write_hair(&asset).expect("an asset read from .hair can be written as .hair");
        assert_eq!(read_hair(&bytes).expect("re-read"), asset);
    }
});
