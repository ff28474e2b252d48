//! `tress cards`, `tress bake-ao` and `tress render --technique patches` end to end: strands to
//! an OBJ of cards, AO baked into it, the OBJ rendered through the real GPU path (lavapipe in
//! CI). The render tests fail without an adapter unless TRESS_SKIP_GPU_TESTS=1.

mod common;

use std::process::Output;

use common::{assert_gpu_success, skip_gpu, straight_hair, tmp, tress};
use tress_hair::patches::PatchMesh;

#[track_caller]
fn ok(out: &Output) -> serde_json::Value {
    assert_gpu_success(out);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert_eq!(stdout.lines().count(), 1, "one JSON object: {stdout}");
    serde_json::from_str(&stdout).expect("JSON")
}

#[test]
fn cards_then_bake_ao_write_valid_patch_objs() {
    let hair = straight_hair("cards.hair", 300);
    let obj = tmp("cards.obj");
    let textures = tmp("textures");
    let report = ok(&tress(&[
        "cards",
        hair.to_str().unwrap(),
        "-o",
        obj.to_str().unwrap(),
        "--cards",
        "24",
        "--segments",
        "5",
        "--textures",
        textures.to_str().unwrap(),
        "--json",
    ]));
    assert_eq!(report["strands"], 300);
    let mesh = PatchMesh::read_obj(&obj).expect("cards OBJ reads back");
    assert_eq!(report["cards"], mesh.component_count());
    assert!(mesh.component_count() > 1 && mesh.component_count() <= 24);
    assert_eq!(report["triangles"], mesh.triangle_count());
    // 5 quads per card, two triangles each.
    assert_eq!(mesh.triangle_count(), mesh.component_count() * 10);
    assert!(
        mesh.ao().iter().all(|&a| a == 1.0),
        "no AO without --bake-ao"
    );
    for name in ["base", "alpha", "spec_shift", "spec_noise"] {
        let png = textures.join(format!("{name}.png"));
        image::open(&png).unwrap_or_else(|e| panic!("{}: {e}", png.display()));
    }

    let baked = tmp("baked.obj");
    let report = ok(&tress(&[
        "bake-ao",
        obj.to_str().unwrap(),
        "-o",
        baked.to_str().unwrap(),
        "--rays",
        "8",
        "--json",
    ]));
    let back = PatchMesh::read_obj(&baked).expect("baked OBJ reads back");
    assert_eq!(back.vertex_count(), mesh.vertex_count());
    assert_eq!(back.indices(), mesh.indices());
    assert!(back.ao().iter().all(|a| (0.0..=1.0).contains(a)));
    assert!(
        back.ao().iter().any(|&a| a < 1.0),
        "cards occlude each other"
    );
    let mean = back.ao().iter().map(|&a| f64::from(a)).sum::<f64>() / back.vertex_count() as f64;
    assert!((report["mean_ao"].as_f64().unwrap() - mean).abs() < 1e-3);
    assert_eq!(report["head_triangles"], 0);
}

#[test]
fn bad_arguments_are_one_line_errors() {
    for args in [
        vec!["cards", "missing.hair", "-o", "x.obj"],
        vec!["cards", "a.hair", "-o", "x.png"],
        vec!["bake-ao", "missing.obj", "-o", "x.obj"],
        vec!["bake-ao", "-o", "x.obj", "--sides", "both"],
        vec!["bake-ao", "-o", "x.obj", "--rays", "0"],
    ] {
        let out = tress(&args);
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(err.trim().lines().count(), 1, "{args:?}: {err}");
        assert!(err.starts_with("tress: "), "{err}");
    }
}

#[test]
fn render_patch_obj_lists_the_four_passes() {
    if skip_gpu() {
        return;
    }
    let hair = straight_hair("render.hair", 300);
    let obj = tmp("render.obj");
    ok(&tress(&[
        "cards",
        hair.to_str().unwrap(),
        "-o",
        obj.to_str().unwrap(),
        "--cards",
        "30",
        "--json",
    ]));
    let png = tmp("render.png");
    let report = ok(&tress(&[
        "render",
        obj.to_str().unwrap(),
        "-o",
        png.to_str().unwrap(),
        "--width",
        "64",
        "--height",
        "48",
        "--set",
        "patches.textures.width=32",
        "--set",
        "patches.textures.height=32",
        "--set",
        "patches.textures.strands=8",
        "--json",
    ]));
    assert_eq!(report["technique"], "patches");
    assert_eq!(report["patches"]["scheme"], "4-pass");
    assert_eq!(report["patches"]["source"], "obj");
    assert!(
        report["patches"]["ao_bake_s"].is_null(),
        "OBJ files keep their AO"
    );
    assert!(report["patches"]["triangles"].as_u64().unwrap() > 0);
    let passes: Vec<&str> = report["passes"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| p["name"].as_str().unwrap())
        .collect();
    if !passes.is_empty() {
        assert_eq!(
            passes,
            [
                "head",
                "patches/z_prime",
                "patches/opaque",
                "patches/back",
                "patches/front"
            ]
        );
    }
    // The framed cards cover part of the image.
    let img = image::open(&png).expect("png").to_rgb8();
    assert_eq!(img.dimensions(), (64, 48));
    let bg = *img.get_pixel(0, 0);
    assert!(img.pixels().filter(|p| **p != bg).count() > 64 * 48 / 20);
}

#[test]
fn render_generated_patches_three_pass() {
    if skip_gpu() {
        return;
    }
    let png = tmp("generated.png");
    let report = ok(&tress(&[
        "render",
        "--technique",
        "patches",
        "-o",
        png.to_str().unwrap(),
        "--width",
        "48",
        "--height",
        "32",
        "--set",
        "patches.source=generated",
        "--set",
        "patches.scheme=3-pass",
        "--set",
        "patches.generator.layers=1",
        "--set",
        "patches.generator.patches_per_layer=12",
        "--set",
        "patches.ao.rays=2",
        "--set",
        "patches.primary_shift=-0.2",
        "--json",
    ]));
    assert_eq!(report["patches"]["scheme"], "3-pass");
    assert_eq!(report["patches"]["components"], 12);
    assert!(report["patches"]["ao_bake_s"].as_f64().is_some());
    let names: Vec<&str> = report["passes"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| p["name"].as_str().unwrap())
        .collect();
    assert!(!names.contains(&"patches/z_prime"), "{names:?}");

    let out = tress(&[
        "render",
        "--technique",
        "patches",
        "-o",
        png.to_str().unwrap(),
        "--set",
        "patches.scheme=5-pass",
    ]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("5-pass") && err.trim().lines().count() == 1,
        "{err}"
    );
}
