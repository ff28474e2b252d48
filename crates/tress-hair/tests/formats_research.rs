//! USC-HairSalon `.data` and CT2Hair `.bin`: files written by tests/data/make_research.py from the
//! published layouts read as the script states; `.data` round-trips; lying counts are errors.

mod common;

use common::{check, data, expected};
use glam::Vec3;
use proptest::prelude::*;
use tress_hair::HairAsset;
use tress_hair::formats::{ReadOptions, load_path, read_ct2hair, read_data, write_data};

#[test]
fn script_files_read_as_stated() {
    for file in ["salon.data", "ct2hair.bin"] {
        let e = expected("research_expected.json", file);
        let loaded = load_path(&data(file), &ReadOptions::default()).unwrap();
        check(&loaded.asset, &e, file);
        if let Some(s) = e.get("single_vertex_skipped") {
            assert_eq!(
                loaded.details.single_vertex_skipped as u64,
                s.as_u64().unwrap()
            );
        }
    }
}

#[test]
fn lying_counts_are_errors_before_allocating() {
    let mut huge = i32::MAX.to_le_bytes().to_vec();
    huge.extend_from_slice(&[0; 8]);
    assert!(
        read_data(&huge)
            .unwrap_err()
            .to_string()
            .contains("at most")
    );
    assert!(read_ct2hair(&huge).is_err());
    let mut strand = 1i32.to_le_bytes().to_vec();
    strand.extend_from_slice(&1_000_000i32.to_le_bytes());
    strand.extend_from_slice(&[0; 24]);
    assert!(
        read_data(&strand)
            .unwrap_err()
            .to_string()
            .contains("room for 2")
    );
    assert!(read_ct2hair(&strand).is_err());
    assert!(read_data(&[]).is_err() && read_ct2hair(&[1, 0]).is_err());
    let bytes = std::fs::read(data("salon.data")).unwrap();
    for cut in 0..bytes.len() {
        assert!(read_data(&bytes[..cut]).is_err(), "cut {cut}");
    }
    let mut extra = bytes.clone();
    extra.push(0);
    assert!(
        read_data(&extra)
            .unwrap_err()
            .to_string()
            .contains("follow")
    );
}

proptest! {
    #[test]
    fn data_round_trips(counts in prop::collection::vec(2u32..20, 1..30), x in -10.0f32..10.0) {
        let n: u32 = counts.iter().sum();
        let p: Vec<Vec3> = (0..n).map(|i| Vec3::new(x, i as f32, -(i as f32) * 0.5)).collect();
        let a = HairAsset::from_counts(p, &counts).unwrap();
        let (back, info) = read_data(&write_data(&a).unwrap()).unwrap();
        prop_assert_eq!(back, a);
        prop_assert_eq!(info.single_vertex_skipped, 0);
    }

    #[test]
    fn readers_never_panic(bytes in prop::collection::vec(any::<u8>(), 0..200)) {
        let _ = read_data(&bytes);
        let _ = read_ct2hair(&bytes);
    }
}
