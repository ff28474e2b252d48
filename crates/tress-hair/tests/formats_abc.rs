//! Alembic: the Alembic library's own file (made by tests/data/make_abc.py with PyAlembic) reads
//! to the counts and bounds the script states; files of our minimal writer round-trip; hostile
//! files are clean errors.

mod common;

use common::{check, data, expected};
use glam::Vec3;
use proptest::prelude::*;
use tress_alembic::write::{CurvesOut, write};
use tress_alembic::{Basis, CurveType, Scope, Wrap};
use tress_hair::formats::{ReadOptions, load_path, read_abc};

#[test]
fn pyalembic_groom_reads_as_the_script_states() {
    let e = expected("abc_expected.json", "groom.abc");
    let loaded = load_path(&data("groom.abc"), &ReadOptions::default()).unwrap();
    check(&loaded.asset, &e, "groom.abc");
    let objects: Vec<&str> = e["objects"]
        .as_array()
        .unwrap()
        .iter()
        .map(|o| o.as_str().unwrap())
        .collect();
    assert_eq!(loaded.details.objects, objects);
    assert_eq!(
        loaded.details.guides_skipped as u64,
        e["guides_skipped"].as_u64().unwrap()
    );
    // groom_root_uv of the first two (non-guide) curves, the others filled with 0
    let uv = loaded.asset.strand_uv().unwrap();
    assert_eq!((uv[0].x, uv[1].x, uv[1].y), (0.0, 0.25, 0.5));
}

#[test]
fn hostile_alembic_files_are_one_line_errors() {
    let e = load_path(&data("hdf5.abc"), &ReadOptions::default())
        .unwrap_err()
        .to_string();
    assert!(
        e.ends_with("HDF5 Alembic is not supported, re-export as Ogawa"),
        "{e}"
    );
    assert!(e.contains("hdf5.abc"), "{e}");
    for file in ["truncated.abc", "bad_magic.abc"] {
        let e = load_path(&data(file), &ReadOptions::default())
            .unwrap_err()
            .to_string();
        assert!(e.contains(file) && !e.contains('\n'), "{e}");
    }
}

fn linear(name: &str, counts: &[i32], seed: f32) -> CurvesOut {
    let n: i32 = counts.iter().sum();
    CurvesOut {
        name: name.into(),
        positions: (0..n)
            .map(|i| [i as f32 * 0.25 + seed, -(i as f32), seed])
            .collect(),
        vertex_counts: counts.to_vec(),
        widths: Some((Scope::Vertex, (0..n).map(|i| 0.001 * i as f32).collect())),
        ..CurvesOut::default()
    }
}

#[test]
fn our_writer_round_trips_with_transforms_and_guides() {
    let mut a = linear("a", &[3, 2], 0.0);
    a.xform = Some([
        2.0, 0.0, 0.0, 0.0, 0.0, 2.0, 0.0, 0.0, 0.0, 0.0, 2.0, 0.0, 1.0, 0.0, 0.0, 1.0,
    ]);
    a.guide = Some(vec![0, 1]);
    let mut b = linear("b", &[5], 3.0);
    b.kind = Some((CurveType::Cubic, Wrap::NonPeriodic, Basis::CatmullRom));
    b.colors = Some((Scope::Uniform, vec![[1.0, 0.5, 0.25]]));
    let bytes = write(&[a, b]);
    let (asset, info) = read_abc(&bytes, &ReadOptions::default()).unwrap();
    assert_eq!(info.objects, ["/a_xform/a", "/b"]);
    assert_eq!(info.guides_skipped, 1);
    // a: one strand of 3 (scaled by 2, moved by x + 1); b: catmull-rom 5 -> 2 spans -> 9 vertices
    assert_eq!(asset.vertex_counts().collect::<Vec<_>>(), [3, 9]);
    assert_eq!(asset.strand(0)[2], Vec3::new(2.0, -4.0, 0.0));
    assert!((asset.thickness().unwrap()[2] - 0.004).abs() < 1e-7);
    assert_eq!(asset.color().unwrap()[5], Vec3::new(1.0, 0.5, 0.25));
}

#[test]
fn whole_linear_curves_expand_primvars_and_refuse_non_finite_points() {
    // Every curve is kept, so the arrays move into the asset; uniform and constant values are
    // still expanded per vertex, and widths scaled by the transform.
    let mut c = linear("c", &[2, 3], 0.0);
    c.widths = Some((Scope::Uniform, vec![0.5, 0.25]));
    c.colors = Some((Scope::Constant, vec![[0.1, 0.2, 0.3]]));
    c.xform = Some([
        2.0, 0.0, 0.0, 0.0, 0.0, 2.0, 0.0, 0.0, 0.0, 0.0, 2.0, 0.0, 0.0, 0.0, 0.0, 1.0,
    ]);
    let (asset, _) = read_abc(&write(std::slice::from_ref(&c)), &ReadOptions::default()).unwrap();
    assert_eq!(asset.thickness().unwrap(), [1.0, 1.0, 0.5, 0.5, 0.5]);
    assert_eq!(asset.color().unwrap(), [Vec3::new(0.1, 0.2, 0.3); 5]);
    assert_eq!(asset.strand(1)[0], Vec3::new(1.0, -4.0, 0.0));
    c.positions[3][1] = f32::NAN;
    let e = read_abc(&write(&[c]), &ReadOptions::default())
        .unwrap_err()
        .to_string();
    assert_eq!(e, ".abc: /c_xform/c: vertex 3 has a non-finite position");
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn linear_curves_round_trip(counts in prop::collection::vec(1i32..8, 1..10), seed in -5.0f32..5.0) {
        let c = linear("c", &counts, seed);
        let (asset, _) = read_abc(&write(std::slice::from_ref(&c)), &ReadOptions::default()).unwrap();
        let want: Vec<Vec3> = c.positions.iter().map(|&p| Vec3::from_array(p)).collect();
        prop_assert_eq!(asset.positions(), want.as_slice());
        let widths = c.widths.unwrap().1;
        prop_assert_eq!(asset.thickness().unwrap(), widths.as_slice());
    }

    #[test]
    fn damaged_alembic_never_panics(cut in 0usize..6000, flip in 0usize..6000, byte in any::<u8>()) {
        let mut bytes = std::fs::read(data("groom.abc")).unwrap();
        if flip < bytes.len() { bytes[flip] = byte; }
        bytes.truncate(cut);
        let _ = read_abc(&bytes, &ReadOptions::default());
    }
}
