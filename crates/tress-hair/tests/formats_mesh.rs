//! Head and body meshes: glTF files made by tests/data/make_gltf.py with pygltflib read to the
//! counts and bounds the script states (node transforms applied); lies are errors; OBJ and USD
//! go through the same `read_mesh`.

mod common;

use common::{data, expected};
use tress_hair::formats::gltf::read_gltf;
use tress_hair::formats::read_mesh;

#[test]
fn pygltflib_files_read_as_stated() {
    for file in ["cube.glb", "cube.gltf", "cube_embedded.gltf"] {
        let e = expected("gltf_expected.json", file);
        let m = read_mesh(&data(file)).unwrap();
        assert_eq!(
            m.triangle_count() as u64,
            e["triangles"].as_u64().unwrap(),
            "{file}"
        );
        assert_eq!(
            m.positions.len() as u64,
            e["vertices"].as_u64().unwrap(),
            "{file}"
        );
        for i in 0..3 {
            let lo = m
                .positions
                .iter()
                .map(|p| p[i])
                .fold(f32::INFINITY, f32::min);
            let hi = m
                .positions
                .iter()
                .map(|p| p[i])
                .fold(f32::NEG_INFINITY, f32::max);
            assert!(
                (f64::from(lo) - e["min"][i].as_f64().unwrap()).abs() < 1e-6,
                "{file}"
            );
            assert!(
                (f64::from(hi) - e["max"][i].as_f64().unwrap()).abs() < 1e-6,
                "{file}"
            );
        }
        assert!(m.normals.iter().all(|n| (n.length() - 1.0).abs() < 1e-4));
    }
}

#[test]
fn lying_gltf_files_are_errors() {
    let e = read_mesh(&data("cube_lying.glb")).unwrap_err().to_string();
    assert!(
        e.contains("cube_lying.glb") && e.contains("declares"),
        "{e}"
    );
    // a .gltf read from memory cannot reach its external buffer
    let text = std::fs::read(data("cube.gltf")).unwrap();
    assert!(read_gltf(&text, None).is_err());
    let glb = std::fs::read(data("cube.glb")).unwrap();
    for cut in (0..glb.len()).step_by(5) {
        assert!(read_gltf(&glb[..cut], None).is_err(), "cut {cut}");
    }
    let e = read_mesh(&data("groom.abc")).unwrap_err().to_string();
    assert!(e.contains("unknown mesh extension"), "{e}");
}

#[test]
fn fuzz_findings_are_errors() {
    // float-indices: float indices, which the gltf crate's reader treats as unreachable.
    let input = std::fs::read(fuzz_regression("read_gltf", "float-indices")).unwrap();
    assert!(read_gltf(&input, None).is_err());
    // position-accessor-index: an accessor index past the accessors, on which gltf-json's validation panics.
    let input = std::fs::read(fuzz_regression("read_gltf", "position-accessor-index")).unwrap();
    assert!(read_gltf(&input, None).is_err());
}

/// A committed input of the fuzz target `target` (`fuzz/regressions/TARGET/NAME`).
fn fuzz_regression(target: &str, name: &str) -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../fuzz/regressions")
        .join(target)
        .join(name)
}
