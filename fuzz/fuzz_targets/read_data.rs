//! Fuzz the USC-HairSalon `.data` reader: any input must give `Ok` or `Err`, and an accepted
//! file must write back and read again to the same asset.

#![no_main]

use libfuzzer_sys::fuzz_target;
use tress_hair::formats::{read_data, write_data};

fuzz_target!(|data: &[u8]| {
    if let Ok((asset, _)) = read_data(data) {
        let bytes = write_data(&asset).expect("an asset read from .data can be written");
        assert_eq!(read_data(&bytes).expect("re-read").0, asset);
    }
});
