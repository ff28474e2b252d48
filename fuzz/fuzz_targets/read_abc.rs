//! Fuzz the Alembic reader: any input must give `Ok` or `Err`, never a panic or a huge
//! allocation, both for the raw curves (`tress_alembic::read`) and their tessellation.

#![no_main]

use libfuzzer_sys::fuzz_target;
use tress_hair::formats::{ReadOptions, read_abc};

fuzz_target!(|data: &[u8]| {
    let _ = tress_alembic::read(data);
    let _ = read_abc(data, &ReadOptions { cubic_segments: 2 });
});
