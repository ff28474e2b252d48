//! Speed of the CPU strand voxelizer ([`tress_shading::voxelize`], the reference of
//! `tress-render`'s GPU voxelizer, Jansson et al. 2019 §3.3). Run with
//! `cargo bench -p tress-shading --bench voxelize`.
//!
//! The asset is the demo ponytail: the generated ponytail at its default parameters, 10 % of its
//! strands (13,632 strands × 13 vertices, as a scene with `strand_ratio = 0.1` loads it). Each
//! benchmark voxelizes it over a grid fitted to its bounds at 64³, 128³ and 256³ voxels with the
//! paper's capacity (255), in both modes: `segments` (the renderer's default, sampled at voxel
//! frequency, so the work grows with the resolution) and `vertices` (the paper's, one deposit
//! per vertex). A run includes allocating and zeroing the `res³` counters and tangent sums
//! (16 bytes a voxel: 268 MB at 256³), as `voxelize` does; `counters_only` measures that part
//! alone (no segments). The segment list is built once, outside the timing.

use divan::{Bencher, black_box};
use tress_hair::HairAsset;
use tress_hair::generate::{Style, generate};
use tress_shading::voxelize::{MAX_CAPACITY, VoxelGrid, VoxelizeMode, strand_segments, voxelize};

fn main() {
    divan::main();
}

/// Grid resolutions (voxels per axis).
const RESOLUTIONS: [u32; 3] = [64, 128, 256];

/// The demo ponytail: 10 % of the default ponytail's strands, seed 0 (as `tress-scene` subsets).
fn demo_ponytail() -> HairAsset {
    generate(Style::Ponytail, &Style::Ponytail.default_params())
        .and_then(|a| a.subset(0.1, 0))
        .expect("valid defaults")
}

fn bench_mode(bencher: Bencher<'_, '_>, res: u32, mode: Option<VoxelizeMode>) {
    let asset = demo_ponytail();
    let b = asset.bounds();
    let grid = VoxelGrid::fit(b.min, b.max, res);
    let segments = match mode {
        Some(_) => strand_segments(asset.strand_offsets()),
        None => Vec::new(),
    };
    let mode = mode.unwrap_or_default();
    bencher.bench(|| {
        voxelize(
            black_box(asset.positions()),
            black_box(&segments),
            &grid,
            mode,
            MAX_CAPACITY,
            None,
        )
    });
}

#[divan::bench(args = RESOLUTIONS, sample_count = 10)]
fn segments(bencher: Bencher<'_, '_>, res: u32) {
    bench_mode(bencher, res, Some(VoxelizeMode::Segments));
}

#[divan::bench(args = RESOLUTIONS, sample_count = 10)]
fn vertices(bencher: Bencher<'_, '_>, res: u32) {
    bench_mode(bencher, res, Some(VoxelizeMode::Vertices));
}

/// The fixed cost: allocating and zeroing the counters and tangent sums, no segments.
#[divan::bench(args = RESOLUTIONS, sample_count = 10)]
fn counters_only(bencher: Bencher<'_, '_>, res: u32) {
    bench_mode(bencher, res, None);
}
