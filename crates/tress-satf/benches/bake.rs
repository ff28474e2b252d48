//! HRIR database bake speed (Xu et al. 2006, §5). Run with
//! `cargo bench -p tress-satf --bench bake`.
//!
//! - `bake_default`: the default [`BakeSettings`] (target: under 60 s on a 2-core machine); the
//!   database's file size is printed once;
//! - `bake_per_sample`: a 64-sample bake, to compare settings quickly;
//! - `cluster_features`: the online index calculation (Table 1, I) for the clusters of the
//!   default clustered style;
//! - `fit_straight_50k`: fitting clusters to the default `straight` style (50,000 strands of 32
//!   vertices).

use divan::{Bencher, black_box};
use std::sync::OnceLock;

use tress_hair::HairAsset;
use tress_hair::generate::{Head, Style, generate};
use tress_satf::database::{BakeSettings, bake};
use tress_satf::fit::{FitSettings, fit_clusters};
use tress_satf::generate::{ClusterStyle, generate_clusters};
use tress_satf::shell::{ShellSampling, cluster_features};

fn main() {
    let db = bake(&BakeSettings::default(), |_, _| {}).expect("valid defaults");
    println!(
        "default database: {} samples, {} bytes ({:.1} MiB)",
        db.sample_count(),
        db.to_bytes().len(),
        db.to_bytes().len() as f64 / (1024.0 * 1024.0)
    );
    divan::main();
}

#[divan::bench(sample_count = 3, sample_size = 1)]
fn bake_default() -> usize {
    bake(black_box(&BakeSettings::default()), |_, _| {})
        .expect("valid defaults")
        .sample_count()
}

#[divan::bench(sample_count = 10)]
fn bake_64_samples() -> usize {
    let s = BakeSettings {
        samples: 64,
        ..BakeSettings::default()
    };
    bake(black_box(&s), |_, _| {})
        .expect("valid settings")
        .sample_count()
}

#[divan::bench(sample_count = 10)]
fn cluster_features_default_style(bencher: Bencher<'_, '_>) {
    let volume =
        generate_clusters(&Head::default(), &ClusterStyle::default()).expect("valid defaults");
    let sampling = ShellSampling::default();
    let density = BakeSettings::default().density;
    bencher.bench(|| {
        volume
            .clusters()
            .map(|(_, c)| cluster_features(c, &sampling, &density).len())
            .sum::<usize>()
    });
}

fn straight() -> &'static HairAsset {
    static ASSET: OnceLock<HairAsset> = OnceLock::new();
    ASSET.get_or_init(|| {
        generate(Style::Straight, &Style::Straight.default_params()).expect("valid defaults")
    })
}

#[divan::bench(sample_count = 5, sample_size = 1)]
fn fit_straight_50k(bencher: Bencher<'_, '_>) {
    let asset = straight();
    bencher.bench(|| {
        fit_clusters(black_box(asset), &FitSettings::default())
            .expect("fits")
            .macro_clusters
            .len()
    });
}
