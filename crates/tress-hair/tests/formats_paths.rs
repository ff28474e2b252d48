//! The path-level API: format by extension, reading and writing files, merging several files,
//! and error messages that name the file.

use std::path::{Path, PathBuf};

use glam::{Vec2, Vec3};
use tress_hair::formats::{Format, read_path, read_paths, write_hair, write_path};
use tress_hair::{HairAsset, HairError};

/// A fresh directory under the system temp dir for one test.
fn temp_dir(test: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("tress-formats-{}-{test}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn asset(strands: u32, vps: u32, x: f32) -> HairAsset {
    let positions = (0..strands * vps)
        .map(|i| Vec3::new(x, -((i % vps) as f32), (i / vps) as f32))
        .collect();
    HairAsset::from_counts(positions, &vec![vps; strands as usize]).unwrap()
}

#[test]
fn format_from_extension() {
    assert_eq!(
        Format::from_path(Path::new("a/b/long.hair")).unwrap(),
        Format::Hair
    );
    assert_eq!(
        Format::from_path(Path::new("LONG.HAIR")).unwrap(),
        Format::Hair
    );
    assert_eq!(
        Format::from_path(Path::new("ratboy.Tfx")).unwrap(),
        Format::Tfx
    );
    for f in Format::ALL {
        let name = format!("x.{}", f.extension());
        assert_eq!(Format::from_path(Path::new(&name)).unwrap(), f);
    }
    let e = Format::from_path(Path::new("dir/head.obj")).unwrap_err();
    assert!(matches!(&e, HairError::File { path, .. } if path == Path::new("dir/head.obj")));
    let text = e.to_string();
    assert!(
        text.starts_with("dir/head.obj: ") && text.contains("unknown extension `.obj`"),
        "{text}"
    );
    let text = Format::from_path(Path::new("hair"))
        .unwrap_err()
        .to_string();
    assert!(
        text.starts_with("hair: ") && text.contains("no file extension"),
        "{text}"
    );
}

#[test]
fn write_then_read_each_format() {
    let dir = temp_dir("round-trip");
    let a = asset(3, 4, 1.0)
        .with_strand_uv(vec![Vec2::new(0.1, 0.9); 3])
        .unwrap();
    let hair = dir.join("a.hair");
    write_path(&hair, &a).unwrap();
    assert_eq!(std::fs::read(&hair).unwrap(), write_hair(&a).unwrap());
    // .hair has no strand UVs.
    assert_eq!(read_path(&hair).unwrap(), a.clone().without_attributes());
    let tfx = dir.join("a.tfx");
    write_path(&tfx, &a).unwrap();
    assert_eq!(read_path(&tfx).unwrap(), a);
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn read_paths_merges_in_order() {
    let dir = temp_dir("merge");
    let (a, b) = (asset(2, 3, 1.0), asset(1, 5, 2.0));
    let (pa, pb) = (dir.join("a.hair"), dir.join("b.tfx"));
    write_path(&pa, &a).unwrap();
    write_path(&pb, &b).unwrap();
    let m = read_paths(&[pa.clone(), pb.clone()]).unwrap();
    assert_eq!(m.strand_count(), 3);
    assert_eq!(m.strand_offsets(), &[0, 3, 6, 11]);
    assert_eq!(m.strand(2), b.strand(0));
    assert_eq!(read_paths(std::slice::from_ref(&pa)).unwrap(), a);
    let m = read_paths(&[pb.clone(), pa.clone()]).unwrap();
    assert_eq!(m.strand(0), b.strand(0));

    // One bad file in the list: the error names it.
    let bad = dir.join("bad.hair");
    std::fs::write(&bad, b"HAIR but far too short").unwrap();
    let e = read_paths(&[pa, bad.clone(), pb]).unwrap_err().to_string();
    assert!(
        e.starts_with(&format!("{}: .hair: truncated", bad.display())),
        "{e}"
    );
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn errors_name_the_file() {
    let dir = temp_dir("errors");
    let missing = dir.join("missing.tfx");
    let e = read_path(&missing).unwrap_err();
    assert!(matches!(&e, HairError::File { source, .. } if matches!(**source, HairError::Io(_))));
    assert!(
        e.to_string()
            .starts_with(&format!("{}: ", missing.display()))
    );

    let garbage = dir.join("garbage.tfx");
    std::fs::write(&garbage, [0u8; 300]).unwrap();
    let e = read_path(&garbage).unwrap_err().to_string();
    let expected = format!("{}: .tfx: unsupported TressFX version 0", garbage.display());
    assert_eq!(e, format!("{expected} (tress reads 3.x and 4.x)"));

    // Writing: an unknown extension, a format that cannot hold the asset, an unwritable path.
    let a = asset(1, 3, 0.0);
    assert!(
        write_path(&dir.join("x.fbx"), &a)
            .unwrap_err()
            .to_string()
            .contains("unknown extension")
    );
    let e = write_path(&dir.join("x.usdz"), &a).unwrap_err().to_string();
    assert!(e.contains("x.usdz") && e.contains("does not write"), "{e}");
    let uneven = HairAsset::from_counts(vec![Vec3::ZERO; 5], &[2, 3]).unwrap();
    let out = dir.join("uneven.tfx");
    let e = write_path(&out, &uneven).unwrap_err().to_string();
    assert!(e.starts_with(&format!("{}: .tfx: ", out.display())), "{e}");
    assert!(!out.exists(), "nothing is written when encoding fails");
    let nowhere = dir.join("no-such-dir").join("a.hair");
    let e = write_path(&nowhere, &a).unwrap_err().to_string();
    assert!(e.starts_with(&format!("{}: ", nowhere.display())), "{e}");

    let e = read_paths(&[]).unwrap_err().to_string();
    assert!(e.contains("no hair files given"), "{e}");
    std::fs::remove_dir_all(dir).unwrap();
}
