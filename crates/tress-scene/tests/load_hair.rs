//! `Scene::load_hair`: files resolved against the scene's folder, generators, follow hairs,
//! strand subsets and transforms; errors name the entry and the file.

use std::path::PathBuf;

use glam::Vec3;
use serde::Deserialize;
use tress_hair::generate::{Style, StyleParams, generate};
use tress_hair::{FollowParams, HairAsset};
use tress_scene::{Scene, SceneError};

/// A fresh folder under cargo's per-test temporary directory.
fn temp_dir(name: &str) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR"))
        .join("tress-scene")
        .join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Two straight strands written by hand.
fn two_strands() -> HairAsset {
    let positions = vec![
        Vec3::new(0.0, 0.0, 0.0),
        Vec3::new(0.0, -1.0, 0.0),
        Vec3::new(0.0, -2.0, 0.0),
        Vec3::new(1.0, 0.0, 0.0),
        Vec3::new(1.0, -1.0, 0.0),
        Vec3::new(1.0, -2.0, 0.0),
    ];
    HairAsset::from_counts(positions, &[3, 3])
        .unwrap()
        .with_thickness(vec![0.1; 6])
        .unwrap()
}

#[test]
fn files_resolve_against_the_scene_folder_and_merge() {
    let dir = temp_dir("files");
    std::fs::create_dir_all(dir.join("assets")).unwrap();
    tress_hair::formats::write_path(&dir.join("assets/a.hair"), &two_strands()).unwrap();
    tress_hair::formats::write_path(&dir.join("b.hair"), &two_strands()).unwrap();
    let scene_path = dir.join("scene.toml");
    std::fs::write(
        &scene_path,
        "[[hair]]\nfiles = [\"assets/a.hair\", \"b.hair\"]\n",
    )
    .unwrap();
    let scene = Scene::from_path(&scene_path).unwrap();
    let assets = scene.load_hair().unwrap();
    assert_eq!(assets.len(), 1);
    assert_eq!(assets[0].strand_count(), 4);
    assert_eq!(&assets[0].positions()[..6], two_strands().positions());
    assert_eq!(&assets[0].positions()[6..], two_strands().positions());
}

#[test]
fn missing_files_name_the_entry_and_file() {
    let scene = Scene::from_str("[[hair]]\ngenerator = { style = \"fur\", strands = 4 }\n[[hair]]\nfiles = [\"nope.tfx\"]\n", temp_dir("missing")).unwrap();
    let e = scene.load_hair().unwrap_err();
    assert!(matches!(e, SceneError::Hair { index: 1, .. }), "{e:?}");
    let m = e.to_string();
    assert!(m.starts_with("hair.1: ") && m.contains("nope.tfx"), "{m}");
}

#[test]
fn generator_matches_a_direct_call() {
    let scene = Scene::from_str(
        "[[hair]]\ngenerator = { style = \"wavy\", strands = 20, vertices = 8, length = 10, seed = 4, noise = 0 }\n",
        ".",
    )
    .unwrap();
    let params = StyleParams {
        strands: 20,
        vertices: 8,
        length: 10.0,
        seed: 4,
        noise: 0.0,
        ..Style::Wavy.default_params()
    };
    assert_eq!(
        scene.load_hair().unwrap(),
        vec![generate(Style::Wavy, &params).unwrap()]
    );
}

#[test]
fn follow_hairs_then_subset_then_transform() {
    let dir = temp_dir("pipeline");
    tress_hair::formats::write_path(&dir.join("a.hair"), &two_strands()).unwrap();
    let base = "[[hair]]\nfiles = [\"a.hair\"]\nfollow = { count = 4, seed = 2 }\n";
    let followed = Scene::from_str(base, &dir)
        .unwrap()
        .load_hair()
        .unwrap()
        .remove(0);
    let expected = two_strands()
        .with_follow_hairs(&FollowParams {
            count: 4,
            seed: 2,
            ..Default::default()
        })
        .unwrap();
    assert_eq!(followed, expected);
    assert_eq!(followed.strand_count(), 10);

    let halved = Scene::from_str(&format!("{base}strand_ratio = 0.5\n"), &dir)
        .unwrap()
        .load_hair()
        .unwrap()
        .remove(0);
    assert_eq!(halved.strand_count(), 5);

    let moved = Scene::from_str(
        &format!(
            "{base}transform = {{ translate = [0, 10, 0], rotate_deg = [0, 0, 90], scale = 2 }}\n"
        ),
        &dir,
    )
    .unwrap()
    .load_hair()
    .unwrap()
    .remove(0);
    // Rz(90°) maps (x, y, z) to (-y, x, z); then ×2 and +10 in y.
    for (p, q) in moved.positions().iter().zip(expected.positions()) {
        let want = Vec3::new(-q.y, q.x, q.z) * 2.0 + Vec3::new(0.0, 10.0, 0.0);
        assert!((*p - want).length() < 1e-4, "{p} vs {want}");
    }
    assert!(
        moved
            .thickness()
            .unwrap()
            .iter()
            .all(|&t| (t - 0.2).abs() < 1e-6),
        "thickness scales with the transform"
    );
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct Settings {
    #[allow(dead_code)]
    k: u32,
}

#[test]
fn technique_errors_name_the_scene_file_and_line() {
    let dir = temp_dir("technique");
    let path = dir.join("scene.toml");
    std::fs::write(&path, "[strands]\nk = 4\nkay = 5\n").unwrap();
    let scene = Scene::from_path(&path).unwrap();
    let m = scene
        .technique_settings::<Settings>("strands")
        .unwrap_err()
        .to_string();
    assert!(
        m.contains("scene.toml") && m.contains("line 3,") && m.contains("`kay`"),
        "{m}"
    );
}
