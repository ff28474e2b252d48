//! The DCC and research formats end to end: `tress info` names the format and the prims or
//! objects read and counts an animated cache's frames, `tress convert` goes between formats, `tress render` draws a USD groom with the
//! head its stage carries, and bad files give one line and exit 2.

mod common;

use std::path::{Path, PathBuf};

use common::{assert_gpu_success, skip_gpu, tmp, tress};

fn data(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../tress-hair/tests/data")
        .join(name)
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

fn info(file: &Path) -> serde_json::Value {
    let out = tress(&["info", "--json", s(file)]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).expect("one JSON object")
}

#[test]
fn info_names_formats_prims_objects_and_skips() {
    let usd = info(&data("groom.usdc"));
    assert_eq!(usd["sources"][0]["format"], "USD binary (.usdc)");
    assert_eq!(usd["sources"][0]["objects"][2], "/World/Moved/Curves");
    assert_eq!(usd["sources"][0]["meshes"][0], "/World/Head");
    assert_eq!(usd["strands"], 6);
    let abc = info(&data("groom.abc"));
    assert_eq!(abc["sources"][0]["format"], "Alembic (Ogawa)");
    assert_eq!(abc["sources"][0]["guides_skipped"], 1);
    assert_eq!(abc["strands"], 7);
    let salon = info(&data("salon.data"));
    assert_eq!(salon["sources"][0]["single_vertex_skipped"], 2);
    let text = tress(&["info", s(&data("groom.abc"))]);
    let text = String::from_utf8_lossy(&text.stdout);
    assert!(
        text.contains("Alembic (Ogawa)")
            && text.contains("/groom/strands")
            && text.contains("guides skipped:    1"),
        "{text}"
    );
}

#[test]
fn info_counts_the_frames_of_an_animated_cache() {
    let asset = tress_hair::formats::read_path(&data("groom.usda")).unwrap();
    let frames: Vec<Vec<glam::Vec3>> = (0..5)
        .map(|k| {
            let dx = glam::Vec3::new(0.1 * k as f32, 0.0, 0.0);
            asset.positions().iter().map(|p| *p + dx).collect()
        })
        .collect();
    for ext in ["abc", "usda", "usdc"] {
        let cache = tmp(&format!("info_frames.{ext}"));
        tress_hair::formats::write_cache_path(&cache, &asset, &frames, 30.0).unwrap();
        let v = info(&cache);
        assert_eq!(v["frames"], 5, "{ext}");
        assert_eq!(v["sources"][0]["frames"], 5, "{ext}");
        let fps = v["sources"][0]["fps"].as_f64().unwrap();
        assert!((fps - 30.0).abs() < 1e-9, "{ext}: {fps}");
        let text = tress(&["info", s(&cache)]);
        let text = String::from_utf8_lossy(&text.stdout);
        assert!(
            text.contains("frames:            5 at 30 fps (an animated cache)")
                && text.contains("frames:              5"),
            "{ext}: {text}"
        );
    }
    let still = info(&data("groom.abc"));
    assert_eq!(still["frames"], 1);
    assert_eq!(still["sources"][0]["frames"], 1);
    assert!(still["sources"][0]["fps"].is_null());
}

#[test]
fn convert_between_formats_keeps_the_strands() {
    let usdc = tmp("from_abc.usdc");
    let out = tress(&["convert", s(&data("groom.abc")), s(&usdc)]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let a = info(&data("groom.abc"));
    let b = info(&usdc);
    for key in [
        "strands",
        "vertices",
        "bbox_min",
        "bbox_max",
        "has_thickness",
        "has_color",
        "has_strand_uv",
    ] {
        assert_eq!(a[key], b[key], "{key}");
    }
    let usda = tmp("from_usdc.usda");
    let hair = tmp("from_usda.hair");
    let data_file = tmp("from_hair.data");
    for (from, to) in [(&usdc, &usda), (&usda, &hair), (&hair, &data_file)] {
        let out = tress(&["convert", s(from), s(to)]);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        assert_eq!(info(to)["vertices"], a["vertices"], "{}", to.display());
    }
    let out = tress(&["convert", s(&data("groom.usda")), s(&tmp("x.usdz"))]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("does not write"));
}

#[test]
fn bad_files_are_one_line_errors() {
    for (file, needle) in [
        (
            "hdf5.abc",
            "HDF5 Alembic is not supported, re-export as Ogawa",
        ),
        ("truncated.usdc", "truncated.usdc"),
        ("cycle_a.usda", "cycle"),
        ("cube_lying.glb", "unknown extension"),
    ] {
        let out = tress(&["info", s(&data(file))]);
        assert_eq!(out.status.code(), Some(2), "{file}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(err.trim_end().lines().count(), 1, "{file}: {err}");
        assert!(
            err.starts_with("tress: ") && err.contains(needle),
            "{file}: {err}"
        );
    }
}

#[test]
fn render_draws_a_usd_groom_with_its_head() {
    if skip_gpu() {
        return;
    }
    let png = tmp("groom_usd.png");
    let out = tress(&[
        "render",
        s(&data("groom.usdz")),
        "-o",
        s(&png),
        "--width",
        "64",
        "--height",
        "48",
        "--set",
        "strands.k=4",
        "--json",
    ]);
    assert_gpu_success(&out);
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["strands"], 6);
    let img = image::open(&png).unwrap().to_rgba8();
    let bg = *img.get_pixel(0, 0);
    assert!(img.pixels().filter(|p| **p != bg).count() > 20);
    // the same through a scene file with a glTF head
    let scene = tmp("abc_scene.toml");
    std::fs::write(
        &scene,
        format!(
            "[[hair]]\nfiles = [\"{}\"]\ncubic_segments = 2\n[head]\nmesh = \"{}\"\n",
            s(&data("groom.abc")),
            s(&data("cube.glb"))
        ),
    )
    .unwrap();
    let out = tress(&[
        "render",
        s(&scene),
        "-o",
        s(&tmp("abc_scene.png")),
        "--width",
        "48",
        "--height",
        "32",
        "--json",
    ]);
    assert_gpu_success(&out);
}
