//! Fuzz the TressFX `.tfx` reader (3.x and 4.x): any input must give `Ok` or `Err`, never a
//! panic, and accepted guides must write back as 4.x and read again unchanged (less the
//! attributes 4.x does not hold).
//!
//! The version is a float compare, which libFuzzer's comparison tracing does not see, so each
//! input is also tried with its first four bytes replaced by 3.0 and by 4.0 to reach both layouts.

#![no_main]

use libfuzzer_sys::fuzz_target;
use tress_hair::formats::{parse_tfx, read_tfx, write_tfx};

fn check(data: &[u8]) {
    let _ = read_tfx(data);
    if let Ok(file) = parse_tfx(data) {
        let bytes = write_tfx(&file.guides).expect("guides of a .tfx file have equal strands");
        assert_eq!(read_tfx(&bytes).expect("re-read"), file.guides);
    }
}

fuzz_target!(|data: &[u8]| {
    check(data);
    if data.len() >= 4 {
        for version in [3.0f32, 4.0] {
            let mut with_version = data.to_vec();
            with_version[..4].copy_from_slice(&version.to_le_bytes());
            check(&with_version);
        }
    }
});
