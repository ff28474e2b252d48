//! USD: Pixar's own files (made by tests/data/make_usd.py with usd-core) read to the counts and
//! bounds the script states; our writer round-trips; hostile files are clean errors.

mod common;

use common::{check, data, expected};
use glam::{Vec2, Vec3};
use proptest::prelude::*;
use tress_hair::HairAsset;
use tress_hair::formats::{
    Format, ReadOptions, UsdFlavor, load_path, read_mesh, read_usd_bytes, write_usd,
};

#[test]
fn usd_core_files_read_as_the_script_states() {
    for file in [
        "groom.usda",
        "groom.usdc",
        "groom.usdz",
        "cubic.usda",
        "nurbs.usda",
    ] {
        let e = expected("usd_expected.json", file);
        let loaded = load_path(&data(file), &ReadOptions::default()).unwrap();
        check(&loaded.asset, &e, file);
        let prims: Vec<String> = e["prims"]
            .as_array()
            .unwrap()
            .iter()
            .map(|p| p.as_str().unwrap().to_string())
            .collect();
        assert_eq!(loaded.details.objects, prims, "{file}");
    }
}

#[test]
fn usd_mesh_prims_are_the_head() {
    for file in ["groom.usda", "groom.usdc", "groom.usdz"] {
        let e = expected("usd_expected.json", file);
        let m = read_mesh(&data(file)).unwrap();
        assert_eq!(
            m.triangle_count() as u64,
            e["mesh_triangles"].as_u64().unwrap()
        );
        assert_eq!(
            m.positions.len() as u64,
            e["mesh_vertices"].as_u64().unwrap()
        );
        let lo = e["mesh_min"][1].as_f64().unwrap() as f32;
        assert!(m.positions.iter().all(|p| p.y >= lo - 1e-5));
        assert!(m.normals.iter().all(|n| (n.length() - 1.0).abs() < 1e-4));
    }
    let e = read_mesh(&data("nurbs.usda")).unwrap_err().to_string();
    assert!(e.contains("nurbs.usda") && e.contains("no Mesh"), "{e}");
}

#[test]
fn cubic_density_is_a_setting() {
    // 8 curves; at 1 segment per span the vertices are the span ends: spans + 1 per curve.
    // bezier 4, 7 -> 1, 2 spans; bspline pinned 4, 6 -> 3, 5; bspline 5 -> 2; catmullRom 5 -> 2;
    // catmullRom pinned 3, 4 -> 2, 3. Spans: 20, so 28 vertices.
    let one = load_path(
        &data("cubic.usda"),
        &ReadOptions {
            cubic_segments: 1,
            ..ReadOptions::default()
        },
    )
    .unwrap();
    assert_eq!(one.asset.vertex_count(), 28);
    let eight = load_path(
        &data("cubic.usda"),
        &ReadOptions {
            cubic_segments: 8,
            ..ReadOptions::default()
        },
    )
    .unwrap();
    assert_eq!(eight.asset.vertex_count(), 20 * 8 + 8);
    assert!(
        load_path(
            &data("cubic.usda"),
            &ReadOptions {
                cubic_segments: 0,
                ..ReadOptions::default()
            }
        )
        .is_err()
    );
}

fn full_asset() -> HairAsset {
    let p: Vec<Vec3> = (0..7)
        .map(|i| Vec3::new(i as f32 * 0.5, -(i as f32), 0.25))
        .collect();
    HairAsset::from_counts(p, &[3, 4])
        .unwrap()
        .with_thickness((0..7).map(|i| 0.01 * i as f32).collect())
        .unwrap()
        .with_color(
            (0..7)
                .map(|i| Vec3::new(0.1 * i as f32, 0.5, 0.2))
                .collect(),
        )
        .unwrap()
        .with_strand_uv(vec![Vec2::new(0.25, 0.5), Vec2::new(0.75, 0.125)])
        .unwrap()
}

#[test]
fn usda_and_usdc_round_trip() {
    let a = full_asset();
    for (flavor, ext) in [(UsdFlavor::Text, "usda"), (UsdFlavor::Binary, "usdc")] {
        let bytes = write_usd(&a, flavor).unwrap();
        let back = read_usd_bytes(&bytes, ext, &ReadOptions::default()).unwrap();
        assert_eq!(back.hair.unwrap(), a, "{ext}");
        assert_eq!(back.info.prims, ["/Hair"]);
    }
    let t = full_asset().with_transparency(vec![0.25; 7]).unwrap();
    let back = Format::Usdc.read(&Format::Usdc.write(&t).unwrap()).unwrap();
    let tr = back.transparency().unwrap();
    assert!(tr.iter().all(|x| (x - 0.25).abs() < 1e-6));
}

#[test]
fn hostile_usd_files_are_one_line_errors() {
    for (file, needle) in [
        ("truncated.usdc", "truncated.usdc"),
        ("bad_magic.usdc", "bad_magic.usdc"),
        ("cycle_a.usda", "cycle"),
        ("self_ref.usda", "cycle"),
        ("missing.usda", "missing.usda"),
    ] {
        let e = load_path(&data(file), &ReadOptions::default())
            .unwrap_err()
            .to_string();
        assert!(e.contains(needle), "{file}: {e}");
        assert!(!e.contains('\n'), "{file}: {e}");
    }
    // Lies the composed stage can hold: counts past the points, bad bases.
    let lying = "#usda 1.0\ndef BasisCurves \"C\" {\n int[] curveVertexCounts = [2, 900000000]\n \
                 point3f[] points = [(0,0,0), (1,1,1), (2,2,2)]\n uniform token type = \"linear\"\n}\n";
    let e = read_usd_bytes(lying.as_bytes(), "usda", &ReadOptions::default()).unwrap_err();
    assert!(e.to_string().contains("add up to"), "{e}");
    let bezier = lying
        .replace("[2, 900000000]", "[3]")
        .replace("\"linear\"", "\"cubic\"");
    let e = read_usd_bytes(bezier.as_bytes(), "usda", &ReadOptions::default()).unwrap_err();
    assert!(e.to_string().contains("3k + 1"), "{e}");
    let negative = lying.replace("[2, 900000000]", "[-1, 4]");
    assert!(read_usd_bytes(negative.as_bytes(), "usda", &ReadOptions::default()).is_err());
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn usdc_round_trips_any_asset(
        counts in prop::collection::vec(1u32..6, 1..8),
        seed in 0u32..1000,
    ) {
        let n: u32 = counts.iter().sum();
        let p: Vec<Vec3> = (0..n).map(|i| Vec3::new(i as f32 * 0.37 + seed as f32, (i * 7 % 5) as f32, -0.5)).collect();
        let a = HairAsset::from_counts(p, &counts).unwrap()
            .with_thickness((0..n).map(|i| i as f32 * 0.001).collect()).unwrap();
        let bytes = write_usd(&a, UsdFlavor::Binary).unwrap();
        let back = read_usd_bytes(&bytes, "usdc", &ReadOptions::default()).unwrap();
        prop_assert_eq!(back.hair.unwrap(), a);
    }

    #[test]
    fn damaged_usdc_never_panics(cut in 0usize..4000, flip in 0usize..4000, byte in any::<u8>()) {
        let mut bytes = std::fs::read(data("groom.usdc")).unwrap();
        if flip < bytes.len() { bytes[flip] = byte; }
        bytes.truncate(cut);
        let _ = read_usd_bytes(&bytes, "usdc", &ReadOptions::default());
    }
}

#[test]
fn a_damaged_child_list_is_an_error_not_an_endless_traversal() {
    // groom.usdc with one byte changed (byte 88, in its value data: 20 -> 1), found by
    // damaged_usdc_never_panics: openusd's traversal then went round a cycle of prim paths
    // forever (10 GB after 30 minutes).
    let bytes = std::fs::read(data("fuzz/damaged-child-list.usdc")).unwrap();
    let good = std::fs::read(data("groom.usdc")).unwrap();
    let changed: Vec<usize> = (0..good.len()).filter(|&i| bytes[i] != good[i]).collect();
    assert_eq!(
        changed,
        [88],
        "the fixture differs from groom.usdc in one byte"
    );
    let e = read_usd_bytes(&bytes, "usdc", &ReadOptions::default()).unwrap_err();
    assert!(e.to_string().contains("not a prim name"), "{e}");
}

#[test]
fn a_compressed_block_larger_than_the_file_is_an_error() {
    // groom.usdc with byte 324 (in the size of an integer array's compressed block) set to 255,
    // found by damaged_usdc_never_panics: openusd allocated the stated 1 TB and aborted.
    let bytes = std::fs::read(data("fuzz/damaged-block-size.usdc")).unwrap();
    let good = std::fs::read(data("groom.usdc")).unwrap();
    let changed: Vec<usize> = (0..good.len()).filter(|&i| bytes[i] != good[i]).collect();
    assert_eq!(
        changed,
        [324],
        "the fixture differs from groom.usdc in one byte"
    );
    let e = read_usd_bytes(&bytes, "usdc", &ReadOptions::default()).unwrap_err();
    assert!(e.to_string().contains("compressed array at byte"), "{e}");
}

#[test]
fn one_changed_byte_never_aborts_or_hangs_the_reader() {
    // groom.usdc with one byte changed, found by damaged_usdc_never_panics at 100,000 cases:
    // a value representation turned into a token list op with its array bit set (openusd read
    // it as a list op, the check as an array) and one whose payload moved to 0 (read from the
    // header): both allocated petabytes and aborted; `xformOp:rotateY` renamed
    // `xformOp}rotateY`: openusd's property path parsing never returned.
    let good = std::fs::read(data("groom.usdc")).unwrap();
    for (file, at, message) in [
        ("damaged-list-op-kind.usdc", 1559, "list op"),
        ("damaged-list-op-header.usdc", 1674, "list op"),
        ("damaged-op-order.usdc", 1220, "not a property name"),
    ] {
        let bytes = std::fs::read(data(&format!("fuzz/{file}"))).unwrap();
        let changed: Vec<usize> = (0..good.len()).filter(|&i| bytes[i] != good[i]).collect();
        assert_eq!(changed, [at], "{file} differs from groom.usdc in one byte");
        let e = read_usd_bytes(&bytes, "usdc", &ReadOptions::default()).unwrap_err();
        assert!(e.to_string().contains(message), "{file}: {e}");
    }
}

#[test]
fn fuzz_findings_are_errors() {
    // huge-token-vector: a token vector claiming 2^60 tokens (openusd allocated it unchecked).
    let input = std::fs::read(fuzz_regression("read_usd", "huge-token-vector")).unwrap();
    let ext = ["usda", "usdc", "usdz"][usize::from(input[0] % 3)];
    assert!(read_usd_bytes(&input[1..], ext, &ReadOptions::default()).is_err());
    // token-vector-index: a token index past the token table (openusd panicked).
    let input = std::fs::read(fuzz_regression("read_usd", "token-vector-index")).unwrap();
    let ext = ["usda", "usdc", "usdz"][usize::from(input[0] % 3)];
    assert!(read_usd_bytes(&input[1..], ext, &ReadOptions::default()).is_err());
    // short-fields-block: a FIELDS section whose value reps decode to fewer than its field
    // count (a debug assertion in openusd: a panic in test and fuzzing builds).
    let input = std::fs::read(fuzz_regression("read_usd", "short-fields-block")).unwrap();
    let ext = ["usda", "usdc", "usdz"][usize::from(input[0] % 3)];
    let e = read_usd_bytes(&input[1..], ext, &ReadOptions::default()).unwrap_err();
    assert!(!e.to_string().is_empty());
}

/// A committed input of the fuzz target `target` (`fuzz/regressions/TARGET/NAME`).
fn fuzz_regression(target: &str, name: &str) -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../fuzz/regressions")
        .join(target)
        .join(name)
}
