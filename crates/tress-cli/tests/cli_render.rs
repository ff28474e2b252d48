//! `tress render` end to end on a tiny generated asset, through the real GPU path (lavapipe in
//! CI). Like every GPU test here it fails without an adapter unless TRESS_SKIP_GPU_TESTS=1.

mod common;

use common::{assert_gpu_success, skip_gpu, straight_hair, tmp, tress};

#[test]
fn render_hair_file_writes_png_and_one_json_object() {
    if skip_gpu() {
        return;
    }
    let hair = straight_hair("tiny.hair", 200);
    let png = tmp("tiny.png");
    let out = tress(&[
        "render",
        hair.to_str().unwrap(),
        "-o",
        png.to_str().unwrap(),
        "--width",
        "96",
        "--height",
        "64",
        "--set",
        "strands.k=4",
        "--json",
    ]);
    assert_gpu_success(&out);
    let v: serde_json::Value =
        serde_json::from_slice(&out.stdout).expect("exactly one JSON object");
    assert_eq!(v["technique"], "strands");
    assert_eq!(
        (v["width"].as_u64(), v["height"].as_u64()),
        (Some(96), Some(64))
    );
    assert_eq!(v["strands"], 200);
    assert_eq!(v["segments"], 200 * 7);
    assert!(v["adapter"]["name"].is_string() && v["adapter"]["backend"].is_string());
    assert!(v["passes"].is_array());
    if let Some(passes) = v["passes"].as_array().filter(|p| !p.is_empty()) {
        let sum: f64 = passes.iter().map(|p| p["gpu_ms"].as_f64().unwrap()).sum();
        assert!((sum - v["frame_gpu_ms"].as_f64().unwrap()).abs() < 1e-6);
    }
    let used = v["ppll"]["used"].as_u64().unwrap();
    assert!(used > 0 && used <= v["ppll"]["capacity"].as_u64().unwrap());
    assert_eq!(v["ppll"]["dropped"], 0);
    assert_eq!(v["output"], png.to_str().unwrap());

    // The image has the requested size and shows hair: pixels differ from the flat background.
    let img = image::open(&png).unwrap().to_rgba8();
    assert_eq!(img.dimensions(), (96, 64));
    let bg = *img.get_pixel(0, 0);
    let differing = img.pixels().filter(|p| **p != bg).count();
    assert!(
        differing > 96 * 64 / 50,
        "only {differing} pixels differ from the background"
    );
}

#[test]
fn render_rejects_bad_settings_with_one_line() {
    let png = tmp("x.png");
    for (set, needle) in [
        ("strands.k=0", "strands.k"),
        ("strands.kk=3", "kk"),
        ("camera.fov_y_deg=abc", "fov_y_deg"),
    ] {
        let out = tress(&["render", "-o", png.to_str().unwrap(), "--set", set]);
        assert_eq!(out.status.code(), Some(2), "{set}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(err.trim_end().lines().count(), 1, "{err}");
        assert!(err.contains(needle), "{err} should name {needle}");
    }
    let out = tress(&["render", "-o", tmp("x.jpg").to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("x.jpg"));
}

#[test]
fn exact_oit_renders_what_sorting_every_fragment_draws() {
    if skip_gpu() {
        return;
    }
    let hair = straight_hair("exact.hair", 300);
    let render = |name: &str, extra: &[&str]| {
        let png = tmp(name);
        let mut args = vec![
            "render",
            hair.to_str().unwrap(),
            "-o",
            png.to_str().unwrap(),
            "--width",
            "96",
            "--height",
            "64",
        ];
        args.extend_from_slice(extra);
        let out = tress(&args);
        assert_gpu_success(&out);
        image::open(&png).unwrap().to_rgb8()
    };
    // The exact reference of a k = 1 frame is the frame of a k-buffer that holds every
    // fragment (this asset has far fewer than 32 a pixel), and not the k = 1 frame.
    let exact = render("exact.png", &["--exact-oit", "--set", "strands.k=1"]);
    let all_sorted = render(
        "k32.png",
        &["--set", "strands.oit=\"ppll\"", "--set", "strands.k=32"],
    );
    let k1 = render(
        "k1.png",
        &["--set", "strands.oit=\"ppll\"", "--set", "strands.k=1"],
    );
    let max_diff = |a: &image::RgbImage, b: &image::RgbImage| {
        a.as_raw()
            .iter()
            .zip(b.as_raw())
            .map(|(x, y)| x.abs_diff(*y))
            .max()
            .unwrap()
    };
    assert!(
        max_diff(&exact, &all_sorted) <= 1,
        "{}",
        max_diff(&exact, &all_sorted)
    );
    assert!(max_diff(&exact, &k1) > 8, "{}", max_diff(&exact, &k1));

    let out = tress(&[
        "render",
        hair.to_str().unwrap(),
        "-o",
        tmp("exact-volume.png").to_str().unwrap(),
        "--technique",
        "volume",
        "--exact-oit",
    ]);
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.trim().lines().count() == 1 && err.contains("--exact-oit"),
        "{err}"
    );
}
