//! Several characters in one scene (issue 14): `scenes/crowd.toml` through `tress render`, each
//! `[[hair]]` entry reported under `objects` with what drew it, and `--technique` drawing every
//! one with the technique named.

mod common;

use common::{assert_gpu_success, skip_gpu, tmp, tress};

const CROWD: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../../scenes/crowd.toml");

fn render(name: &str, extra: &[&str]) -> serde_json::Value {
    let png = tmp(name);
    let mut args = vec![
        "render",
        CROWD,
        "-o",
        png.to_str().unwrap(),
        "--width",
        "320",
        "--height",
        "180",
        // Few strands: this is about the objects, not the asset.
        "--set",
        "hair.0.strand_ratio=0.01",
        "--set",
        "hair.4.strand_ratio=0.01",
        "--set",
        "volume.resolution=64",
        "--json",
    ];
    args.extend_from_slice(extra);
    let out = tress(&args);
    assert_gpu_success(&out);
    serde_json::from_slice(&out.stdout).expect("exactly one JSON object")
}

#[test]
fn the_crowd_reports_each_character_drawn_by_its_size() {
    if skip_gpu() {
        return;
    }
    // The auto thresholds at this size: the front characters rasterized, the far ones
    // raymarched.
    let v = render(
        "crowd.png",
        &[
            "--set",
            "hybrid.auto_near_px=120",
            "--set",
            "hybrid.auto_far_px=60",
        ],
    );
    assert_eq!(v["technique"], "auto");
    let objects = v["objects"].as_array().expect("objects");
    assert_eq!(objects.len(), 6, "one per [[hair]] entry");
    let size = |o: &serde_json::Value| o["size_px"].as_f64().unwrap();
    let mut segments = 0;
    for o in objects {
        let (t, lod, px) = (
            o["technique"].as_str().unwrap(),
            o["lod"].as_f64().unwrap(),
            size(o),
        );
        eprintln!("{t} lod {lod:.3} at {px:.0} px, coverage {}", o["coverage"]);
        match t {
            "strands" => assert!(px >= 120.0 && lod == 0.0, "{o}"),
            "volume" => assert!(px <= 60.0 + 1e-3 || lod > 15.5 / 16.0, "{o}"),
            "hybrid" => assert!(px > 60.0 && px < 120.0, "{o}"),
            other => panic!("drawn as {other}"),
        }
        let voxelized = t != "strands";
        assert_eq!(o["volume_bytes"].as_u64().unwrap() > 0, voxelized, "{o}");
        let c = o["coverage"].as_f64().unwrap();
        assert!(c > 0.0 && c <= 1.0, "{o}");
        segments += o["segments"].as_u64().unwrap();
    }
    assert_eq!(segments, v["segments"].as_u64().unwrap());
    // The scene is laid out nearest first: sizes fall, and both ends of the range are drawn.
    assert!(objects.windows(2).all(|w| size(&w[0]) > size(&w[1])));
    assert_eq!(objects[0]["technique"], "strands");
    assert_eq!(objects[5]["technique"], "volume");
    // One volume per voxelized character, sized by the character on screen: two voxels a
    // pixel across it (`volume.voxels_per_px`), the next of the steps 32, 48, 64 (`volume.min_resolution` 32 to the
    // scene's `volume.resolution` 64); 8 bytes a voxel and 4 an 8³ block. Beside them the shared
    // counters, 20 bytes a voxel of the largest.
    let mut largest = 0;
    let mut volumes = 0;
    for o in objects.iter().filter(|o| o["technique"] != "strands") {
        let r = o["volume_resolution"].as_u64().unwrap();
        let px = o["size_px"].as_f64().unwrap();
        let expected = [32, 48, 64]
            .into_iter()
            .find(|&s| s as f64 >= 2.0 * px)
            .unwrap_or(64);
        assert_eq!(r, expected, "{o}");
        let bytes = o["volume_bytes"].as_u64().unwrap();
        assert_eq!(bytes, r.pow(3) * 8 + r.div_ceil(8).pow(3) * 4, "{o}");
        largest = largest.max(r);
        volumes += bytes;
    }
    assert!(largest > 0);
    assert_eq!(
        v["volume"]["bytes"].as_u64().unwrap(),
        largest.pow(3) * 20 + volumes
    );
    assert_eq!(v["volume"]["resolution"].as_u64().unwrap(), largest);
    assert!(v["oit"]["fragments"].as_u64().unwrap() > 0 && v["oit"]["lost"] == 0);

    // The frame's GPU memory: the total is its parts; the volumes part is the volume report's
    // (counters and every character's volume); each character's own memory is its strand
    // buffers (at least a 4-byte index a segment) and its volume, and what the characters do not
    // own of the geometry is the heads'.
    let m = &v["memory"];
    let part = |k: &str| m[k].as_u64().unwrap_or_else(|| panic!("memory.{k}: {m}"));
    let parts = [
        "geometry",
        "oit",
        "volumes",
        "shadow_maps",
        "textures",
        "database",
    ];
    assert_eq!(
        part("total"),
        parts.iter().map(|k| part(k)).sum::<u64>(),
        "{m}"
    );
    assert_eq!(part("volumes"), v["volume"]["bytes"].as_u64().unwrap());
    assert!(part("oit") > 0 && part("shadow_maps") > 0, "{m}");
    let mut own_geometry = 0;
    for o in objects {
        let om = &o["memory"];
        let (total, geometry, volume) = (
            om["total"].as_u64().unwrap(),
            om["geometry"].as_u64().unwrap(),
            om["volume"].as_u64().unwrap(),
        );
        assert_eq!(total, geometry + volume, "{o}");
        assert_eq!(volume, o["volume_bytes"].as_u64().unwrap(), "{o}");
        assert!(geometry >= 4 * o["segments"].as_u64().unwrap(), "{o}");
        own_geometry += geometry;
    }
    assert!(
        own_geometry < part("geometry"),
        "the heads' meshes are the frame's: {m}"
    );
}

#[test]
fn a_technique_on_the_command_line_draws_every_character() {
    if skip_gpu() {
        return;
    }
    let v = render("crowd-strands.png", &["--technique", "strands"]);
    assert_eq!(v["technique"], "strands");
    let objects = v["objects"].as_array().expect("objects");
    assert!(
        objects
            .iter()
            .all(|o| o["technique"] == "strands" && o["lod"] == 0.0)
    );
    assert!(v.get("volume").is_none(), "nothing voxelized");
}

/// `hybrid.budget_ms` under `auto`: a generous budget picks what the sizes pick, a budget no
/// frame can meet draws every character with one renderer only (a hybrid pays for both), and
/// never more characters as hybrids than without a budget.
#[test]
fn a_frame_budget_drops_hybrids_before_it_is_exceeded() {
    if skip_gpu() {
        return;
    }
    let thresholds = [
        "--set",
        "hybrid.auto_near_px=120",
        "--set",
        "hybrid.auto_far_px=60",
    ];
    let techniques = |extra: &[&str]| -> Vec<String> {
        let mut args = thresholds.to_vec();
        args.extend_from_slice(extra);
        let v = render("crowd-budget.png", &args);
        v["objects"]
            .as_array()
            .unwrap()
            .iter()
            .map(|o| o["technique"].as_str().unwrap().to_string())
            .collect()
    };
    let by_size = techniques(&[]);
    assert!(by_size.iter().any(|t| t == "hybrid"), "{by_size:?}");
    assert_eq!(techniques(&["--set", "hybrid.budget_ms=1e9"]), by_size);
    let tight = techniques(&["--set", "hybrid.budget_ms=0.001"]);
    assert!(tight.iter().all(|t| t != "hybrid"), "{tight:?}");
    assert_eq!(tight.len(), by_size.len());
}
