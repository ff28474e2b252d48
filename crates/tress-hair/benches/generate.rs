//! Generator and operation speed at the paper's scale. Run with
//! `cargo bench -p tress-hair --bench generate`.
//!
//! - every style at its default parameters (the ponytail: 136,320 strands × 13 vertices, the size
//!   of Jansson et al. 2019's test asset; target under 1 s);
//! - follow-hair expansion, both modes: 5,000 guides × 16 vertices with 27 followers each
//!   (140,000 strands, a TressFX ponytail's size; offset target under 100 ms) and 48,113 fur
//!   guides × 4 vertices with 19 followers each (962,260 strands, a TressFX bear's size);
//! - resampling and a level-of-detail subset of the default ponytail.

use divan::{Bencher, black_box};
use tress_hair::generate::{Style, StyleParams, generate};
use tress_hair::{FollowMode, FollowParams, HairAsset};

fn main() {
    divan::main();
}

#[divan::bench(args = Style::ALL, sample_count = 10)]
fn default_style(style: Style) -> HairAsset {
    generate(style, black_box(&style.default_params())).expect("valid defaults")
}

/// 5,000 straight guides of 16 vertices.
fn guides() -> HairAsset {
    let params = StyleParams {
        strands: 5_000,
        vertices: 16,
        ..Style::Straight.default_params()
    };
    generate(Style::Straight, &params).expect("valid parameters")
}

const MODES: [FollowMode; 2] = [FollowMode::Offset, FollowMode::Interpolate];

#[divan::bench(args = MODES, sample_count = 10)]
fn follow_hairs_5k_guides_x27(bencher: Bencher<'_, '_>, mode: FollowMode) {
    let guides = guides();
    let params = FollowParams {
        count: 27,
        mode,
        seed: 1,
        ..FollowParams::default()
    };
    bencher.bench(|| {
        black_box(&guides)
            .with_follow_hairs(&params)
            .expect("valid parameters")
    });
}

/// 48,113 fur guides of 4 vertices.
fn fur_guides() -> HairAsset {
    let params = StyleParams {
        strands: 48_113,
        vertices: 4,
        ..Style::Fur.default_params()
    };
    generate(Style::Fur, &params).expect("valid parameters")
}

#[divan::bench(args = MODES, sample_count = 3)]
fn follow_hairs_48k_fur_guides_x19(bencher: Bencher<'_, '_>, mode: FollowMode) {
    let guides = fur_guides();
    let params = FollowParams {
        count: 19,
        mode,
        seed: 1,
        ..FollowParams::default()
    };
    bencher.bench(|| {
        black_box(&guides)
            .with_follow_hairs(&params)
            .expect("valid parameters")
    });
}

fn ponytail() -> HairAsset {
    generate(Style::Ponytail, &Style::Ponytail.default_params()).expect("valid defaults")
}

#[divan::bench(sample_count = 10)]
fn resample_ponytail_to_32(bencher: Bencher<'_, '_>) {
    let asset = ponytail();
    bencher.bench(|| black_box(&asset).resample_count(32).expect("valid count"));
}

#[divan::bench(sample_count = 10)]
fn subset_ponytail_quarter(bencher: Bencher<'_, '_>) {
    let asset = ponytail();
    bencher.bench(|| black_box(&asset).subset(0.25, 7).expect("valid ratio"));
}
