//! Fuzz the SATF HRIR database reader (`.satfdb`). The file ends with an FNV-1a checksum of the
//! rest, which random mutations would almost never match; the target writes the right one, so
//! the fuzzer explores the header and arrays behind it. Any input must give `Ok` or `Err`.

#![no_main]

use libfuzzer_sys::fuzz_target;
use tress_satf::database::Database;

fuzz_target!(|data: &[u8]| {
    let _ = Database::from_bytes(data);
    if data.len() >= 8 {
        let mut fixed = data.to_vec();
        let body = fixed.len() - 8;
        let sum = tress_satf::format::fnv1a64(&fixed[..body]);
        fixed[body..].copy_from_slice(&sum.to_le_bytes());
        let _ = Database::from_bytes(&fixed);
    }
});
