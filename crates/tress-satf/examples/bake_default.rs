//! Bake the default HRIR database, print its time and size, and optionally write it:
//! `cargo run -p tress-satf --release --example bake_default [-- OUT.satfdb]`.

use std::time::Instant;

use tress_satf::database::{BakeSettings, bake};

fn main() -> Result<(), tress_satf::SatfError> {
    let settings = BakeSettings::default();
    let start = Instant::now();
    let db = bake(&settings, |_, _| {})?;
    let secs = start.elapsed().as_secs_f64();
    let bytes = db.to_bytes();
    println!(
        "{} samples, {}x{} angles, {} pixels: {:.2} s, {} bytes ({:.2} MiB), {} threads",
        db.sample_count(),
        settings.hrir.view_angles,
        settings.hrir.light_angles,
        settings.hrir.pixels,
        secs,
        bytes.len(),
        bytes.len() as f64 / (1024.0 * 1024.0),
        rayon::current_num_threads()
    );
    if let Some(path) = std::env::args_os().nth(1) {
        db.save(std::path::Path::new(&path))?;
        println!("wrote {}", std::path::Path::new(&path).display());
    }
    Ok(())
}
