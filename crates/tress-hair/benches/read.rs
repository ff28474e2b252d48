//! Reader throughput: a 136k-strand × 16-vertex asset (the scale of the paper's test models) read
//! from memory as `.hair`, `.tfx` 4.x, `.usdc` (written by our USD writer through openusd),
//! `.abc` (written by `tress-alembic`'s minimal Ogawa writer) and `.data`. Run with
//! `cargo bench -p tress-hair --bench read`; divan reports bytes per second of file read.
//! `read_hair_ponytail` reads the generated ponytail (136,320 × 16), the Python package's
//! load benchmark's file, from memory; `read_hair_ponytail_file` from the file.

use divan::counter::BytesCount;
use divan::{Bencher, black_box};
use glam::{Vec2, Vec3};
use tress_alembic::Scope;
use tress_alembic::write::{CurvesOut, write};
use tress_hair::HairAsset;
use tress_hair::formats::{
    Format, ReadOptions, UsdFlavor, load_paths, read_abc, read_data, read_hair, read_tfx,
    read_usd_bytes, write_data, write_hair, write_path, write_tfx, write_usd,
};
use tress_hair::generate::{Style, StyleParams, generate};

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

/// The generated ponytail at the scale of the paper's test asset (136,320 strands, here with 16
/// vertices each, plus per-vertex thickness): exactly the file `crates/tress-py/bench/bench_load.py`
/// writes with `tress.generate("ponytail", vertices=16)` and reads through `tress.load`, so the two
/// times compare (this one reads from memory; the Python one also reads the file).
#[divan::bench(sample_count = 20)]
fn read_hair_ponytail(bencher: Bencher<'_, '_>) {
    let params = StyleParams {
        vertices: 16,
        ..Style::Ponytail.default_params()
    };
    let asset = generate(Style::Ponytail, &params).expect("valid parameters");
    let bytes = Format::Hair.write(&asset).expect("writable");
    bencher
        .counter(BytesCount::of_slice(&bytes))
        .bench(|| Format::Hair.read(black_box(&bytes)).expect("readable"));
}

/// The same ponytail read from a file (the page cache warm) by `load_paths`, the call
/// `tress.load` makes: the file read and the parse, no Python.
#[divan::bench(sample_count = 20)]
fn read_hair_ponytail_file(bencher: Bencher<'_, '_>) {
    let params = StyleParams {
        vertices: 16,
        ..Style::Ponytail.default_params()
    };
    let asset = generate(Style::Ponytail, &params).expect("valid parameters");
    let path =
        std::env::temp_dir().join(format!("tress-bench-{}-ponytail.hair", std::process::id()));
    write_path(&path, &asset).expect("writable");
    let paths = [path.clone()];
    let options = ReadOptions::default();
    bencher.bench(|| load_paths(black_box(&paths), &options).expect("readable"));
    let _ = std::fs::remove_file(&path);
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

fn with_thickness(a: HairAsset) -> HairAsset {
    let n = a.vertex_count();
    a.with_thickness((0..n).map(|i| 0.01 + (i % 16) as f32 * 1e-4).collect())
        .expect("valid thickness")
}

#[divan::bench]
fn hair_thickness(bencher: Bencher<'_, '_>) {
    let bytes = write_hair(&with_thickness(asset())).expect("writable");
    bencher
        .counter(BytesCount::of_slice(&bytes))
        .bench(|| read_hair(black_box(&bytes)).expect("readable"));
}

#[divan::bench(args = [false, true])]
fn usdc(bencher: Bencher<'_, '_>, widths: bool) {
    let a = if widths {
        with_thickness(asset())
    } else {
        asset()
    };
    let bytes = write_usd(&a, UsdFlavor::Binary).expect("writable");
    let options = ReadOptions::default();
    bencher.counter(BytesCount::of_slice(&bytes)).bench(|| {
        read_usd_bytes(black_box(&bytes), "usdc", &options)
            .expect("readable")
            .hair
            .expect("curves")
    });
}

#[divan::bench(args = [false, true])]
fn abc(bencher: Bencher<'_, '_>, widths: bool) {
    let a = if widths {
        with_thickness(asset())
    } else {
        asset()
    };
    let curves = CurvesOut {
        name: "hair".into(),
        positions: a.positions().iter().map(|p| p.to_array()).collect(),
        vertex_counts: a.vertex_counts().map(|c| c as i32).collect(),
        widths: a.thickness().map(|t| (Scope::Vertex, t.to_vec())),
        ..CurvesOut::default()
    };
    let bytes = write(&[curves]);
    let options = ReadOptions::default();
    bencher
        .counter(BytesCount::of_slice(&bytes))
        .bench(|| read_abc(black_box(&bytes), &options).expect("readable"));
}

#[divan::bench]
fn data(bencher: Bencher<'_, '_>) {
    let bytes = write_data(&asset()).expect("writable");
    bencher
        .counter(BytesCount::of_slice(&bytes))
        .bench(|| read_data(black_box(&bytes)).expect("readable"));
}
