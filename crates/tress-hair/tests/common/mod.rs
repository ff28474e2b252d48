//! Shared helpers for the format tests: the fixture folder and the scripts' expectations.

#![allow(dead_code)]

use std::path::PathBuf;

use tress_hair::HairAsset;

/// A file in `tests/data`.
pub(crate) fn data(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(name)
}

/// One entry of a `*_expected.json` written by a fixture script.
pub(crate) fn expected(json: &str, file: &str) -> serde_json::Value {
    let text = std::fs::read_to_string(data(json)).unwrap();
    let all: serde_json::Value = serde_json::from_str(&text).unwrap();
    all[file].clone()
}

fn vec3(v: &serde_json::Value) -> [f64; 3] {
    let a = v.as_array().unwrap();
    [0, 1, 2].map(|i| a[i].as_f64().unwrap())
}

/// Check an asset against a script's counts and bounds (and thickness range when stated).
pub(crate) fn check(asset: &HairAsset, e: &serde_json::Value, file: &str) {
    assert_eq!(
        asset.strand_count() as u64,
        e["strands"].as_u64().unwrap(),
        "{file}: strands"
    );
    assert_eq!(
        asset.vertex_count() as u64,
        e["vertices"].as_u64().unwrap(),
        "{file}: vertices"
    );
    let b = asset.bounds();
    let (lo, hi) = (vec3(&e["bbox_min"]), vec3(&e["bbox_max"]));
    for i in 0..3 {
        assert!(
            (f64::from(b.min[i]) - lo[i]).abs() < 1e-4,
            "{file}: min {:?} vs {lo:?}",
            b.min
        );
        assert!(
            (f64::from(b.max[i]) - hi[i]).abs() < 1e-4,
            "{file}: max {:?} vs {hi:?}",
            b.max
        );
    }
    if let Some(t) = e.get("thickness_min").and_then(|v| v.as_f64()) {
        let th = asset
            .thickness()
            .unwrap_or_else(|| panic!("{file}: no thickness"));
        let min = th.iter().copied().fold(f32::INFINITY, f32::min);
        let max = th.iter().copied().fold(0.0, f32::max);
        let tmax = e["thickness_max"].as_f64().unwrap();
        assert!(
            (f64::from(min) - t).abs() < 1e-5,
            "{file}: thickness min {min} vs {t}"
        );
        assert!(
            (f64::from(max) - tmax).abs() < 1e-5,
            "{file}: thickness max {max} vs {tmax}"
        );
    }
    if let Some(c) = e.get("has_color").and_then(|v| v.as_bool()) {
        assert_eq!(asset.color().is_some(), c, "{file}: color");
    }
    if let Some(c) = e.get("has_strand_uv").and_then(|v| v.as_bool()) {
        assert_eq!(asset.strand_uv().is_some(), c, "{file}: strand UV");
    }
}
