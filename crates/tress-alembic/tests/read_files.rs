//! The Alembic library's own files (written by `crates/tress-hair/tests/data/make_abc.py` with
//! PyAlembic) read to what the script wrote; hostile files give errors.

use std::path::PathBuf;

use tress_alembic::{AlembicError, Basis, CurveType, Scope, read};

fn data(name: &str) -> Vec<u8> {
    let p = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../tress-hair/tests/data")
        .join(name);
    std::fs::read(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

#[test]
fn pyalembic_groom_reads_every_curves_object() {
    let c = read(&data("groom.abc")).unwrap();
    let paths: Vec<&str> = c.curves.iter().map(|c| c.path.as_str()).collect();
    assert_eq!(
        paths,
        [
            "/groom/strands",
            "/groom/inner/bspline",
            "/catmull",
            "/bezier"
        ]
    );
    let s = &c.curves[0];
    assert_eq!(s.vertex_counts, [3, 4, 2]);
    assert_eq!(s.kind, CurveType::Linear);
    assert_eq!(s.positions[4], [0.5 + 0.3 / 9.0, -0.5, 0.0]);
    let w = s.widths.as_ref().unwrap();
    assert_eq!(w.scope, Scope::Vertex);
    assert_eq!(w.values.len(), 9);
    assert!((w.values[8] - 0.09).abs() < 1e-7);
    let colors = s.colors.as_ref().unwrap();
    assert_eq!((colors.scope, colors.values.len()), (Scope::Vertex, 9));
    assert_eq!(
        s.root_uv.as_ref().unwrap().values,
        [[0.0, 0.5], [0.25, 0.5], [0.5, 0.5]]
    );
    assert_eq!(s.guide.as_ref().unwrap().values, [0, 0, 1]);
    // translate (1, 2, 3) . rotate y 90 . scale 2: x maps to -2z, the origin to (1, 2, 3)
    let m = s.world;
    assert!(
        (m[12] - 1.0).abs() < 1e-12 && (m[13] - 2.0).abs() < 1e-12 && (m[14] - 3.0).abs() < 1e-12
    );
    assert!(m[0].abs() < 1e-12 && (m[2] + 2.0).abs() < 1e-12 && (m[5] - 2.0).abs() < 1e-12);
    let b = &c.curves[1];
    assert_eq!((b.kind, b.basis), (CurveType::Cubic, Basis::Bspline));
    assert_eq!(b.widths.as_ref().unwrap().scope, Scope::Constant);
    // the inner Xform adds translate (0, -1, 0), scaled by 2 below the outer one
    assert!((b.world[13] - 0.0).abs() < 1e-12, "{:?}", b.world);
    assert_eq!(c.curves[2].basis, Basis::CatmullRom);
    assert_eq!(c.curves[3].basis, Basis::Bezier);
    assert!(c.curves[3].widths.is_none());
}

#[test]
fn hostile_files_are_errors() {
    assert!(matches!(read(&data("hdf5.abc")), Err(AlembicError::Hdf5)));
    assert_eq!(
        read(&data("hdf5.abc")).unwrap_err().to_string(),
        "HDF5 Alembic is not supported, re-export as Ogawa"
    );
    assert!(matches!(
        read(&data("bad_magic.abc")),
        Err(AlembicError::NotAlembic(_))
    ));
    let e = read(&data("truncated.abc")).unwrap_err();
    assert!(matches!(e, AlembicError::Malformed(_)), "{e}");
    let full = data("groom.abc");
    for cut in (0..full.len()).step_by(7) {
        assert!(read(&full[..cut]).is_err(), "cut at {cut}");
    }
}
