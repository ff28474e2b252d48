//! Fuzz the TressFX `.tfx` reader (3.x and 4.x): any input must give `Ok` or `Err`, never a
//! panic, and accepted guides must write back as 4.x and read again unchanged (less the
//! attributes 4.x does not hold).

#![no_main]

use libfuzzer_sys::fuzz_target;
use tress_hair::formats::{parse_tfx, read_tfx, write_tfx};

fuzz_target!(|data: &[u8]| {
    let _ = read_tfx(data);
    if let Ok(file) = parse_tfx(data) {
        let bytes = write_tfx(&file.guides).expect("guides of a .tfx file have equal strands");
        assert_eq!(read_tfx(&bytes).expect("re-read"), file.guides);
    }
});
