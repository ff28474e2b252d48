//! Tests of OBJ hair-card import and export.

use glam::{Vec2, Vec3};
use proptest::prelude::*;
use tress_hair::HairError;
use tress_hair::patches::{PatchMesh, PatchParams, generate_patches};

/// One card hanging from y = 0 to y = -2 in the z = 0 plane, `v` growing downward (root at the
/// top), as a quad.
const CARD: &str = "\
v 0 0 0
v 1 0 0
v 1 -2 0
v 0 -2 0
vt 0 0
vt 1 0
vt 1 1
vt 0 1
f 1/1 2/2 3/3 4/4
";

#[test]
fn a_card_gets_its_tangent_from_v_and_its_normal_from_the_face() {
    let m = PatchMesh::from_obj(CARD.as_bytes()).unwrap();
    assert_eq!(m.vertex_count(), 4);
    assert_eq!(m.triangle_count(), 2);
    assert_eq!(m.component_count(), 1);
    // The face winds clockwise seen from +z: its normal is -z.
    for (t, n) in m.tangents().iter().zip(m.normals()) {
        assert!(t.distance(Vec3::NEG_Y) < 1e-6, "tangent {t}");
        assert!(n.distance(Vec3::NEG_Z) < 1e-6, "normal {n}");
    }
    assert_eq!(m.uvs()[2], Vec2::new(1.0, 1.0));
    assert_eq!(m.ao(), &[1.0; 4]);
}

#[test]
fn tangents_follow_the_uv_layout_not_the_vertex_order() {
    // The same quad with v growing along +x instead, and the file's own normals (not unit).
    let obj = "\
v 0 0 0
v 1 0 0
v 1 -2 0
v 0 -2 0
vt 0 0
vt 0 1
vt 1 1
vt 1 0
vn 0 0 3
f 1/1/1 2/2/1 3/3/1 4/4/1
";
    let m = PatchMesh::from_obj(obj.as_bytes()).unwrap();
    for (t, n) in m.tangents().iter().zip(m.normals()) {
        assert!(t.distance(Vec3::X) < 1e-6, "tangent {t}");
        assert_eq!(*n, Vec3::Z, "the file's normal, normalized");
    }
}

#[test]
fn relative_indices_count_back_from_the_last_element() {
    let obj = CARD.replace("f 1/1 2/2 3/3 4/4", "f -4/-4 -3/-3 -2/-2 -1/-1");
    let m = PatchMesh::from_obj(obj.as_bytes()).unwrap();
    assert_eq!(m, PatchMesh::from_obj(CARD.as_bytes()).unwrap());
    let err = PatchMesh::from_obj(&[b'v', b' ', 0xff, b'\n']).unwrap_err();
    assert!(err.to_string().contains("UTF-8"), "{err}");
}

#[test]
fn components_come_from_connectivity() {
    // Two cards apart, and a third made of two triangles that share an edge's positions but not
    // its texture coordinates (a UV seam): three cards in all.
    let obj = format!(
        "{CARD}\
v 5 0 0
v 6 0 0
v 6 -2 0
v 5 -2 0
f 5/1 6/2 7/3
f 5/4 7/2 8/1
v 9 0 0
v 10 0 0
v 10 -2 0
f 9/1 10/2 11/3
"
    );
    let m = PatchMesh::from_obj(obj.as_bytes()).unwrap();
    assert_eq!(m.triangle_count(), 5);
    assert_eq!(m.component_count(), 3);
    assert_eq!(m.components(), &[0, 0, 1, 1, 2]);
}

#[test]
fn bad_files_are_clear_errors() {
    let cases: &[(&str, &str)] = &[
        (
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
            "texture coordinates",
        ),
        (
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/1 7/1\n",
            "(v) that does not exist",
        ),
        (
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/1 3/4\n",
            "(vt) that does not exist",
        ),
        (
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/x 3/1\n",
            "line 5: 'x' is not a face index",
        ),
        ("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\n", "no faces"),
        (
            "v 0 0 nan\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/1 3/1\n",
            "non-finite",
        ),
        (
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt inf 0\nf 1/1 2/1 3/1\n",
            "non-finite",
        ),
        ("", "no faces"),
        (
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\nf 1/1/1 2/1/-5 3/1/1\n",
            "line 6: a face names a normal (vn) that does not exist (index -5 of 1)",
        ),
        (
            "v 0 0 0\nv 1 0 0\nvt 0 0\nf 1/1 2/1 3/1\nv 0 1 0\n",
            "vertex (v) that does not exist (index 3 of 2)",
        ),
        (
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 0/1 2/1 3/1\n",
            "index 0",
        ),
        (
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nl 1/1 2/1 9/1\n",
            "does not exist",
        ),
        ("v 0 0 0\nf 1/1/1/1\n", "more than 3 indices"),
    ];
    for (obj, expected) in cases {
        let err = PatchMesh::from_obj(obj.as_bytes()).unwrap_err();
        assert!(
            matches!(err, HairError::Format { format: "OBJ", .. }),
            "{err:?}"
        );
        assert!(err.to_string().contains(expected), "{obj:?}: {err}");
    }
}

#[test]
fn obj_mesh_obj_round_trip_keeps_everything() {
    let params = PatchParams {
        patches_per_layer: 30,
        segments: 5,
        ..PatchParams::default()
    };
    let mut mesh = generate_patches(&params).unwrap();
    let ao: Vec<f32> = (0..mesh.vertex_count())
        .map(|i| (i % 17) as f32 / 16.0)
        .collect();
    mesh.set_ao(ao).unwrap();

    // mesh -> OBJ -> mesh
    let text = mesh.to_obj();
    let back = PatchMesh::from_obj(text.as_bytes()).unwrap();
    assert_eq!(back.positions(), mesh.positions());
    assert_eq!(back.uvs(), mesh.uvs());
    assert_eq!(back.indices(), mesh.indices());
    assert_eq!(back.ao(), mesh.ao(), "AO travels as vertex colors");
    assert_eq!(back.components(), mesh.components());
    for (a, b) in back.normals().iter().zip(mesh.normals()) {
        assert!(a.distance(*b) < 1e-6);
    }
    // Tangents are rebuilt from the UVs: along the strip, as the generator made them.
    for (a, b) in back.tangents().iter().zip(mesh.tangents()) {
        assert!(a.dot(*b) > 0.95, "{a} vs {b}");
    }

    // OBJ -> mesh -> OBJ: the text comes back the same.
    let again = back.to_obj();
    let third = PatchMesh::from_obj(again.as_bytes()).unwrap();
    assert_eq!(third, back);
    assert_eq!(again, third.to_obj());
}

#[test]
fn export_numbers_vertices_by_first_use_and_drops_unused_ones() {
    let positions = vec![
        Vec3::new(9.0, 9.0, 9.0), // unused
        Vec3::ZERO,
        Vec3::X,
        Vec3::Y,
    ];
    let n = positions.len();
    let mesh = PatchMesh::new(
        positions,
        vec![Vec3::Z; n],
        vec![Vec3::Y; n],
        vec![Vec2::ZERO, Vec2::ZERO, Vec2::X, Vec2::Y],
        vec![3, 1, 2],
    )
    .unwrap();
    let back = PatchMesh::from_obj(mesh.to_obj().as_bytes()).unwrap();
    assert_eq!(back.positions(), &[Vec3::Y, Vec3::ZERO, Vec3::X]);
    assert_eq!(back.indices(), &[0, 1, 2]);
    assert_eq!(back.uvs(), &[Vec2::Y, Vec2::ZERO, Vec2::X]);
}

#[test]
fn foreign_vertex_colors_are_not_ao() {
    let obj = CARD.replace("v 1 0 0\n", "v 1 0 0 0.2 0.2 0.2\n");
    let obj = obj.replacen("v 0 0 0\n", "v 0 0 0 0.5 0.5 0.5\n", 1);
    let obj = obj.replace("v 1 -2 0\n", "v 1 -2 0 0 0 0\n");
    let obj = obj.replace("v 0 -2 0\n", "v 0 -2 0 0 0 0\n");
    let m = PatchMesh::from_obj(obj.as_bytes()).unwrap();
    assert_eq!(m.ao(), &[1.0; 4]);
    let ours = format!("# tress patch mesh\n{obj}");
    let m = PatchMesh::from_obj(ours.as_bytes()).unwrap();
    assert_eq!(m.ao(), &[0.5, 0.2, 0.0, 0.0]);
}

#[test]
fn files_round_trip_and_errors_name_them() {
    let dir = std::env::temp_dir().join(format!("tress-patches-obj-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("card.obj");
    let mesh = PatchMesh::from_obj(CARD.as_bytes()).unwrap();
    mesh.write_obj(&path).unwrap();
    assert_eq!(PatchMesh::read_obj(&path).unwrap(), mesh);
    let missing = dir.join("missing.obj");
    let err = PatchMesh::read_obj(&missing).unwrap_err().to_string();
    assert!(err.contains("missing.obj"), "{err}");
    std::fs::write(&path, "v 0 0 0\nf 1 1 1\n").unwrap();
    let err = PatchMesh::read_obj(&path).unwrap_err().to_string();
    assert!(
        err.contains("card.obj") && err.contains("texture coordinates"),
        "{err}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// Any bytes: an error or a valid mesh, never a panic; accepted files round-trip.
    #[test]
    fn arbitrary_input_never_panics(
        lines in proptest::collection::vec(
            prop_oneof![
                "v( -?[0-9]{1,3}(\\.[0-9])?){3}",
                "vt( -?[0-9](\\.[0-9])?){2}",
                "vn( -?[0-9]){3}",
                "f( -?[0-9]{1,2}(/-?[0-9]{0,2}){0,2}){1,5}",
                "[a-z#]{0,3}[ -~]{0,12}",
            ],
            0..24,
        )
    ) {
        let text = lines.join("\n");
        if let Ok(mesh) = PatchMesh::from_obj(text.as_bytes()) {
            let back = PatchMesh::from_obj(mesh.to_obj().as_bytes()).unwrap();
            prop_assert_eq!(back.positions().len(), mesh.positions().len());
            prop_assert_eq!(back.indices(), mesh.indices());
        }
    }
}

#[test]
fn tri_meshes_read_with_or_without_normals_and_reject_hostile_indices() {
    use tress_hair::generate::TriMesh;
    let m = TriMesh::from_obj(b"v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 4 3\n").unwrap();
    assert_eq!(m.indices.len(), 6, "the quad is two triangles");
    assert!(
        m.normals
            .iter()
            .all(|n| (*n - glam::Vec3::Z).length() < 1e-6)
    );
    let with_normals = b"v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 -1\nf 1//1 2//1 3//1\n";
    let m = TriMesh::from_obj(with_normals).unwrap();
    assert!(
        m.normals
            .iter()
            .all(|n| (*n - glam::Vec3::NEG_Z).length() < 1e-6)
    );
    let hostile: [&[u8]; 3] = [
        b"v 0 0 0\nf 1 2 3\n",
        b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf -4 -1 -2\n",
        b"v 0 0 0\n",
    ];
    for bad in hostile {
        assert!(TriMesh::from_obj(bad).is_err());
    }
}
