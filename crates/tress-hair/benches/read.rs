//! Reader throughput: a 136k-strand × 16-vertex asset (the scale of the paper's test models) read
//! from memory as `.hair` and as `.tfx` 4.x. Run with `cargo bench -p tress-hair --bench read`;
//! divan reports bytes per second of file read.

use divan::counter::BytesCount;
use divan::{Bencher, black_box};
use glam::{Vec2, Vec3};
use tress_hair::HairAsset;
use tress_hair::formats::{read_hair, read_tfx, write_hair, write_tfx};

const STRANDS: usize = 136_000;
const VERTICES: usize = 16;

fn main() {
    divan::main();
}

/// Strands hanging down from a ring of roots, with a little curl so the data is not constant.
fn asset() -> HairAsset {
    let mut positions = Vec::with_capacity(STRANDS * VERTICES);
    for s in 0..STRANDS {
        let a = s as f32 * 0.618;
        let root = Vec3::new(a.cos(), 1.0, a.sin()) * 10.0;
        for v in 0..VERTICES {
            let t = v as f32;
            positions
                .push(root + Vec3::new((t * 0.7 + a).sin() * 0.1, -t, (t * 0.7 + a).cos() * 0.1));
        }
    }
    HairAsset::from_counts(positions, &vec![VERTICES as u32; STRANDS]).expect("valid asset")
}

#[divan::bench]
fn hair_points(bencher: Bencher<'_, '_>) {
    let bytes = write_hair(&asset()).expect("writable");
    bencher
        .counter(BytesCount::of_slice(&bytes))
        .bench(|| read_hair(black_box(&bytes)).expect("readable"));
}

#[divan::bench]
fn hair_all_arrays(bencher: Bencher<'_, '_>) {
    let a = asset();
    let n = a.vertex_count();
    let a = a
        .with_thickness(vec![0.01; n])
        .and_then(|a| a.with_transparency(vec![0.2; n]))
        .and_then(|a| a.with_color(vec![Vec3::new(0.3, 0.2, 0.1); n]))
        .expect("valid attributes");
    let bytes = write_hair(&a).expect("writable");
    bencher
        .counter(BytesCount::of_slice(&bytes))
        .bench(|| read_hair(black_box(&bytes)).expect("readable"));
}

#[divan::bench]
fn tfx_v4(bencher: Bencher<'_, '_>) {
    let a = asset();
    let uv = (0..a.strand_count())
        .map(|s| Vec2::new(s as f32 / STRANDS as f32, 0.5))
        .collect();
    let a = a.with_strand_uv(uv).expect("valid UVs");
    let bytes = write_tfx(&a).expect("writable");
    bencher
        .counter(BytesCount::of_slice(&bytes))
        .bench(|| read_tfx(black_box(&bytes)).expect("readable"));
}
