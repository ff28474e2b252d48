//! Fuzz the USD reader (openusd, then tress's curves and meshes): the first byte picks the
//! flavour (`usda`, `usdc`, `usdz`), the rest is the file. Any input must give `Ok` or `Err`.

#![no_main]

use libfuzzer_sys::fuzz_target;
use tress_hair::formats::{ReadOptions, read_usd_bytes};

fuzz_target!(|data: &[u8]| {
    let Some((&pick, file)) = data.split_first() else { return };
    let ext = ["usda", "usdc", "usdz"][usize::from(pick % 3)];
    let _ = read_usd_bytes(file, ext, &ReadOptions { cubic_segments: 2 });
});
