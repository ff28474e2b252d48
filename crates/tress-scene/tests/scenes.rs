//! Every example scene in `scenes/` parses, its hair loads (at a reduced strand count), and its
//! camera sees that hair.

use std::path::PathBuf;

use tress_scene::{HeadSource, Scene};

fn scene_files() -> Vec<PathBuf> {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../scenes");
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|entry| entry.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    files.sort();
    files
}

#[test]
fn the_four_example_scenes_exist() {
    let names: Vec<String> = scene_files()
        .iter()
        .map(|p| p.file_name().unwrap().to_string_lossy().into_owned())
        .collect();
    for name in ["curly.toml", "fur.toml", "ponytail.toml", "straight.toml"] {
        assert!(
            names.iter().any(|n| n == name),
            "scenes/{name} is missing: {names:?}"
        );
    }
}

#[test]
fn every_scene_parses() {
    for path in scene_files() {
        let scene = Scene::from_path(&path).unwrap_or_else(|e| panic!("{e}"));
        assert!(!scene.hair.is_empty(), "{}: no hair", path.display());
        assert!(
            scene.hair.iter().all(|h| h.generator.is_some()),
            "{}: example scenes use generated hair only",
            path.display()
        );
    }
}

#[test]
fn every_scene_loads_and_frames_its_hair() {
    for path in scene_files() {
        let mut scene = Scene::from_path(&path).unwrap();
        for i in 0..scene.hair.len() {
            scene
                .apply_override(&format!("hair.{i}.generator.strands=64"))
                .unwrap();
        }
        let assets = scene
            .load_hair()
            .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        assert_eq!(assets.len(), scene.hair.len());
        let clip_from_world = scene.camera.clip_from_world(scene.output.aspect());
        for asset in &assets {
            // The hair's centre is in view and at least half the vertices project into the image.
            let inside = |p: glam::Vec3| {
                let c = clip_from_world * p.extend(1.0);
                let ndc = c.truncate() / c.w;
                c.w > 0.0
                    && ndc.x.abs() <= 1.0
                    && ndc.y.abs() <= 1.0
                    && (0.0..=1.0).contains(&ndc.z)
            };
            assert!(
                inside(asset.bounds().center()),
                "{}: hair centre out of view",
                path.display()
            );
            let seen = asset.positions().iter().filter(|&&p| inside(p)).count();
            assert!(
                seen * 2 >= asset.vertex_count(),
                "{}: {seen} of {} vertices in view",
                path.display(),
                asset.vertex_count()
            );
        }
        assert!(
            matches!(scene.head_source(), HeadSource::Generated(..)),
            "{}",
            path.display()
        );
    }
}
