//! `tress reference` and `tress compare-images` end to end on tiny scenes (CPU only: no GPU
//! needed).

mod common;

use std::path::PathBuf;
use std::process::Output;

use common::{tmp, tress};

fn ok(out: &Output) -> String {
    assert!(
        out.status.success(),
        "tress failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout.clone()).unwrap()
}

/// A one-line error on stderr and exit status 2.
fn fails_with(out: &Output, needle: &str) {
    assert_eq!(out.status.code(), Some(2), "{out:?}");
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    assert!(err.contains(needle), "{err}");
}

/// A small straight-hair scene on the generated head: a few hundred thick strands (1.5 mm, so
/// they show at 48x32 pixels).
fn scene_file() -> PathBuf {
    // The tests run in parallel and share the file: write a private copy and rename it into
    // place, so a `tress` process never reads a file another test has just truncated.
    let path = tmp("tiny.toml");
    let private = tmp(&format!("tiny-{:?}.toml", std::thread::current().id()));
    std::fs::write(
        &private,
        "[[hair]]\ngenerator = { style = \"straight\", strands = 300, vertices = 8, thickness = 0.15 }\n\
         [output]\nwidth = 48\nheight = 32\n",
    )
    .unwrap();
    std::fs::rename(&private, &path).unwrap();
    path
}

#[test]
fn reference_writes_png_and_exr_and_one_json_object() {
    let scene = scene_file();
    let png = tmp("ref.png");
    let out = tress(&[
        "reference",
        scene.to_str().unwrap(),
        "-o",
        png.to_str().unwrap(),
        "--spp",
        "4",
        "--json",
    ]);
    let stdout = ok(&out);
    assert_eq!(stdout.trim_end().lines().count(), 1, "{stdout}");
    let json: serde_json::Value = serde_json::from_str(&stdout).unwrap();
    assert_eq!(json["width"], 48);
    assert_eq!(json["height"], 32);
    assert_eq!(json["spp"], 4);
    assert_eq!(json["aov"], "color");
    assert_eq!(json["strands"], 300);
    assert_eq!(json["segments"], 300 * 7);
    assert!(
        json["triangles"].as_u64().unwrap() > 0,
        "the generated head"
    );
    assert_eq!(json["samples"], 48 * 32 * 4);
    assert!(json["rays"].as_u64().unwrap() >= 48 * 32 * 4);
    let img = image::open(&png).unwrap();
    assert_eq!((img.width(), img.height()), (48, 32));

    // The AO image is grey, 1 (white) on the background, darker on the head and hair.
    let ao = tmp("ao.exr");
    ok(&tress(&[
        "reference",
        scene.to_str().unwrap(),
        "-o",
        ao.to_str().unwrap(),
        "--spp",
        "4",
        "--aov",
        "ao",
        "--set",
        "trace.ao_samples=2",
    ]));
    let ao = image::open(&ao).unwrap().into_rgb32f();
    let values: Vec<f32> = ao.pixels().map(|p| p.0[0]).collect();
    assert!(ao.pixels().all(|p| p.0[0] == p.0[1] && p.0[1] == p.0[2]));
    assert!(values.iter().all(|v| (0.0..=1.0).contains(v)));
    assert!(values.contains(&1.0), "background");
    assert!(values.iter().any(|&v| v < 0.9), "occluded hair or head");
}

#[test]
fn reference_is_deterministic_and_compare_images_scores_it() {
    let scene = scene_file();
    let (a, b, c) = (tmp("a.png"), tmp("b.png"), tmp("c.png"));
    for (path, seed) in [(&a, "1"), (&b, "1"), (&c, "2")] {
        ok(&tress(&[
            "reference",
            scene.to_str().unwrap(),
            "-o",
            path.to_str().unwrap(),
            "--spp",
            "2",
            "--seed",
            seed,
        ]));
    }
    assert_eq!(std::fs::read(&a).unwrap(), std::fs::read(&b).unwrap());

    let heat = tmp("heat.png");
    let same = ok(&tress(&[
        "compare-images",
        a.to_str().unwrap(),
        b.to_str().unwrap(),
        "--json",
        "--heatmap",
        heat.to_str().unwrap(),
    ]));
    let same: serde_json::Value = serde_json::from_str(same.trim_end()).unwrap();
    assert_eq!(same.as_object().unwrap().len(), 4);
    assert_eq!(same["flip"], 0.0);
    assert_eq!(same["matched"]["flip"], 0.0);
    assert_eq!(same["matched"]["scale"], 3);
    assert_eq!(
        same["matched"]["color_ratio"],
        serde_json::json!([1.0, 1.0, 1.0])
    );
    assert_eq!(same["rmse"], 0.0);
    assert_eq!(same["ssim"], 1.0);
    let heat = image::open(&heat).unwrap();
    assert_eq!((heat.width(), heat.height()), (48, 32));

    let other = ok(&tress(&[
        "compare-images",
        a.to_str().unwrap(),
        c.to_str().unwrap(),
        "--json",
    ]));
    let other: serde_json::Value = serde_json::from_str(other.trim_end()).unwrap();
    let flip = other["flip"].as_f64().unwrap();
    let ssim = other["ssim"].as_f64().unwrap();
    assert!(flip > 0.0 && flip < 0.5, "{other}");
    assert!(other["rmse"].as_f64().unwrap() > 0.0);
    assert!(ssim < 1.0 && ssim > 0.3, "{other}");

    // At the matched scale the seed pair's noise mostly averages out; `--floor` scores the
    // second image against the reference the same way.
    let matched = other["matched"]["flip"].as_f64().unwrap();
    assert!(matched < flip, "{other}");
    let floored = ok(&tress(&[
        "compare-images",
        a.to_str().unwrap(),
        b.to_str().unwrap(),
        "--json",
        "--floor",
        c.to_str().unwrap(),
        "--scale",
        "2",
    ]));
    let floored: serde_json::Value = serde_json::from_str(floored.trim_end()).unwrap();
    assert_eq!(floored["floor"]["scale"], 2);
    let floor = floored["floor"]["flip"].as_f64().unwrap();
    assert!(floor > 0.0 && floor < flip, "{floored}");

    let text = ok(&tress(&[
        "compare-images",
        a.to_str().unwrap(),
        c.to_str().unwrap(),
    ]));
    assert!(text.starts_with("FLIP ") && text.contains("SSIM"), "{text}");
    assert!(
        text.contains("at scale 3: FLIP") && text.contains("ratio ("),
        "{text}"
    );
}

#[test]
fn errors_are_one_line_with_status_2() {
    let scene = scene_file();
    let s = scene.to_str().unwrap();
    let png = tmp("err.png");
    let p = png.to_str().unwrap();
    fails_with(&tress(&["reference", s, "-o", "out.jpg"]), "out.jpg");
    fails_with(
        &tress(&["reference", s, "-o", p, "--spp", "0"]),
        "trace.spp",
    );
    fails_with(
        &tress(&["reference", s, "-o", p, "--aov", "normal"]),
        "normal",
    );
    fails_with(
        &tress(&["reference", s, "-o", p, "--set", "trace.nope=1"]),
        "trace.nope",
    );
    fails_with(
        &tress(&["reference", s, "-o", p, "--set", "camera.fov=1"]),
        "fov",
    );
    fails_with(
        &tress(&["reference", "missing.toml", "-o", p]),
        "missing.toml",
    );

    let small = tmp("small.png");
    let large = tmp("large.png");
    image::RgbImage::new(4, 4).save(&small).unwrap();
    image::RgbImage::new(5, 4).save(&large).unwrap();
    let (sm, lg) = (small.to_str().unwrap(), large.to_str().unwrap());
    fails_with(&tress(&["compare-images", sm, lg]), "4x4 and 5x4");
    fails_with(
        &tress(&["compare-images", sm, sm, "--scale", "0"]),
        "--scale",
    );
    fails_with(
        &tress(&["compare-images", sm, sm, "--floor", lg]),
        "large.png",
    );
    fails_with(
        &tress(&["compare-images", sm, "missing.png"]),
        "missing.png",
    );
    let garbage = tmp("garbage.png");
    std::fs::write(&garbage, b"not an image").unwrap();
    fails_with(
        &tress(&["compare-images", sm, garbage.to_str().unwrap()]),
        "garbage.png",
    );
    fails_with(
        &tress(&["compare-images", sm, sm, "--heatmap", "heat.exr"]),
        "heat.exr",
    );
}
