//! `tress satf-bake`: bakes a small database with a report, checks it, and rejects corrupt or
//! truncated files with one clear line (no GPU needed).

mod common;

use std::path::PathBuf;
use std::process::Output;

use common::{skip_gpu, tmp, tress};

fn one_error_line(out: &Output) -> String {
    assert_eq!(out.status.code(), Some(2), "expected failure: {out:?}");
    let err = String::from_utf8_lossy(&out.stderr).to_string();
    assert_eq!(err.trim_end().lines().count(), 1, "one line: {err}");
    assert!(err.starts_with("tress: "), "{err}");
    err
}

#[test]
fn bake_reports_and_check_validates() {
    let db = tmp("small.satfdb");
    let out = tress(&[
        "satf-bake",
        "-o",
        db.to_str().unwrap(),
        "--samples",
        "24",
        "--angles",
        "4",
        "--pixels",
        "8",
        "--json",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).expect("one JSON object");
    let bytes = std::fs::metadata(&db).unwrap().len();
    // Header 100 + 24 features of 12 bytes + alpha 24·4·8 and re 24·4·4·8 unorm16 + checksum 8.
    assert_eq!(
        bytes,
        100 + 24 * 12 + 2 * 24 * 4 * 8 + 2 * 24 * 4 * 4 * 8 + 8
    );
    assert_eq!(v["bytes"], bytes);
    assert_eq!(v["samples"], 24);
    assert_eq!(
        (v["view_angles"].clone(), v["light_angles"].clone()),
        (4.into(), 4.into())
    );
    assert!(v["seconds"].as_f64().is_some_and(|s| s >= 0.0));
    assert!(!db.with_extension("satfdb.partial").exists());

    let out = tress(&["satf-bake", "--check", db.to_str().unwrap()]);
    assert!(out.status.success());
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.contains("valid HRIR database") && text.contains("24 samples"),
        "{text}"
    );

    // A flipped payload byte: checksum error naming the file.
    let mut bytes = std::fs::read(&db).unwrap();
    bytes[300] ^= 0x40;
    let bad = tmp("flipped.satfdb");
    std::fs::write(&bad, &bytes).unwrap();
    let err = one_error_line(&tress(&["satf-bake", "--check", bad.to_str().unwrap()]));
    assert!(
        err.contains("flipped.satfdb") && err.contains("corrupt"),
        "{err}"
    );
    // Truncated.
    std::fs::write(&bad, &bytes[..bytes.len() / 2]).unwrap();
    let err = one_error_line(&tress(&["satf-bake", "--check", bad.to_str().unwrap()]));
    assert!(err.contains("truncated"), "{err}");
    // Not a database at all.
    std::fs::write(&bad, b"hello").unwrap();
    let err = one_error_line(&tress(&["satf-bake", "--check", bad.to_str().unwrap()]));
    assert!(err.contains("not an HRIR database"), "{err}");
    // Missing file.
    let err = one_error_line(&tress(&[
        "satf-bake",
        "--check",
        tmp("none.satfdb").to_str().unwrap(),
    ]));
    assert!(err.contains("none.satfdb"), "{err}");
}

#[test]
fn bad_settings_are_one_line_errors() {
    let db = tmp("never.satfdb");
    let err = one_error_line(&tress(&[
        "satf-bake",
        "-o",
        db.to_str().unwrap(),
        "--samples",
        "0",
    ]));
    assert!(err.contains("samples"), "{err}");
    let err = one_error_line(&tress(&[
        "satf-bake",
        "-o",
        db.to_str().unwrap(),
        "--pixels",
        "1",
    ]));
    assert!(err.contains("pixels"), "{err}");
    assert!(!db.exists());
}

/// A tiny SATF scene in its own folder: generated clusters, a database `db.satfdb` beside it
/// baked with `samples` samples.
fn satf_scene(name: &str, samples: u32) -> PathBuf {
    let dir = tmp(name);
    std::fs::create_dir_all(&dir).unwrap();
    let scene = dir.join("scene.toml");
    std::fs::write(
        &scene,
        format!(
            "technique = \"satf\"\n\
             [camera]\neye = [38.0, 8.0, 52.0]\ntarget = [0.0, -6.0, 0.0]\n\
             [output]\nwidth = 96\nheight = 64\n\
             [satf]\ndatabase = \"db.satfdb\"\nclusters = \"generate\"\n\
             st = 6\nsu = 6\nshadow_map_size = 128\n\
             generate = {{ macro_clusters = 2, clusters_per_macro = 2, strands_per_cluster = 40, samples = 8 }}\n\
             bake = {{ samples = {samples}, angles = 4, pixels = 8 }}\n"
        ),
    )
    .unwrap();
    scene
}

#[test]
fn render_satf_bakes_on_first_use_and_reports_table_1_stages() {
    if skip_gpu() {
        return;
    }
    let scene = satf_scene("first-use", 32);
    let png = scene.with_file_name("out.png");
    let args = [
        "render",
        scene.to_str().unwrap(),
        "-o",
        png.to_str().unwrap(),
        "--json",
    ];
    let out = tress(&args);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        out.status.success(),
        "tress render failed (GPU tests need a Vulkan adapter: install mesa-vulkan-drivers for \
         lavapipe, or set TRESS_SKIP_GPU_TESTS=1 to skip on purpose): {stderr}"
    );
    assert!(stderr.contains("not found: baking it"), "{stderr}");
    assert!(scene.with_file_name("db.satfdb").exists());
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).expect("one JSON object");
    assert_eq!(v["technique"], "satf");
    assert_eq!(
        (v["width"].clone(), v["height"].clone()),
        (96.into(), 64.into())
    );
    let s = &v["satf"];
    assert_eq!(s["clusters"], 4);
    assert_eq!(s["database_samples"], 32);
    assert_eq!(s["cluster_source"], "generate");
    // H# = clusters · s_t · layers · s_u = 4 · 6 · 3 · 6.
    assert_eq!(s["hsvs"], 4 * 6 * 3 * 6);
    assert_eq!(
        s["uniform_hsvs"].as_u64().unwrap() + s["interpolated_hsvs"].as_u64().unwrap(),
        4 * 6 * 3 * 6
    );
    for stage in [
        "index_calculation",
        "map_construction",
        "texture_mapping",
        "lighting",
        "shadowing",
    ] {
        let ms = &s["stages_ms"][stage];
        assert!(
            ms.is_null() || ms.as_f64().is_some_and(|x| x >= 0.0),
            "{stage}: {ms}"
        );
    }
    let img = image::open(&png).expect("png written").to_rgb8();
    assert_eq!(img.dimensions(), (96, 64));
    // Second run: the database exists, nothing is baked.
    let out = tress(&args);
    assert!(out.status.success());
    assert!(!String::from_utf8_lossy(&out.stderr).contains("baking"));
}

#[test]
fn render_satf_database_errors_are_one_line() {
    if skip_gpu() {
        return;
    }
    let scene = satf_scene("db-errors", 24);
    let db = scene.with_file_name("db.satfdb");
    let png = scene.with_file_name("out.png");
    let render = |extra: &[&str]| {
        let mut args = vec![
            "render",
            scene.to_str().unwrap(),
            "-o",
            png.to_str().unwrap(),
        ];
        args.extend_from_slice(extra);
        tress(&args)
    };
    // A database baked with other settings than the scene's [satf.bake].
    let out = tress(&[
        "satf-bake",
        "-o",
        db.to_str().unwrap(),
        "--samples",
        "16",
        "--angles",
        "4",
        "--pixels",
        "8",
    ]);
    assert!(out.status.success());
    let err = one_error_line(&render(&[]));
    assert!(
        err.contains("db.satfdb") && err.contains("samples = 16") && err.contains("re-bake"),
        "{err}"
    );
    // Without [satf.bake] any valid database is accepted.
    let out = render(&["--set", "satf.bake={}"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    // Corrupt.
    let mut bytes = std::fs::read(&db).unwrap();
    let last = bytes.len() - 20;
    bytes[last] ^= 1;
    std::fs::write(&db, &bytes).unwrap();
    let err = one_error_line(&render(&[]));
    assert!(
        err.contains("db.satfdb") && err.contains("corrupt"),
        "{err}"
    );
    // A folder where the file should be.
    let err = one_error_line(&render(&[
        "--set",
        &format!("satf.database=\"{}\"", scene.parent().unwrap().display()),
    ]));
    assert!(err.contains("db-errors"), "{err}");
    // A bad setting names itself.
    let err = one_error_line(&render(&["--set", "satf.k_threshold=-1"]));
    assert!(err.contains("k_threshold"), "{err}");
}

#[test]
fn render_satf_counts_the_strands_the_fit_skips() {
    if skip_gpu() {
        return;
    }
    // 60 straight strands in a bundle and 3 that are single points: the 60 are drawn, the
    // 3 are counted and reported, not dropped silently.
    use glam::Vec3;
    let dir = tmp("fit-skips");
    std::fs::create_dir_all(&dir).unwrap();
    let mut positions = Vec::new();
    let mut counts = Vec::new();
    for i in 0..60 {
        let (x, z) = ((i % 8) as f32 * 0.3, (i / 8) as f32 * 0.3);
        positions.extend((0..8).map(|k| Vec3::new(x, -(k as f32), z)));
        counts.push(8);
    }
    for i in 0..3 {
        positions.extend([Vec3::new(i as f32, 1.0, 0.0); 2]);
        counts.push(2);
    }
    let hair = tress_hair::HairAsset::from_counts(positions, &counts).unwrap();
    tress_hair::formats::write_path(&dir.join("bundle.hair"), &hair).unwrap();
    let scene = dir.join("scene.toml");
    std::fs::write(
        &scene,
        "technique = \"satf\"\n\
         [camera]\neye = [20.0, -3.0, 20.0]\ntarget = [1.0, -3.5, 1.0]\n\
         [output]\nwidth = 64\nheight = 48\n\
         [[hair]]\nfiles = [\"bundle.hair\"]\n\
         [satf]\ndatabase = \"db.satfdb\"\nclusters = \"fit\"\nst = 6\nsu = 6\n\
         bake = { samples = 16, angles = 4, pixels = 8 }\n",
    )
    .unwrap();
    let png = dir.join("out.png");
    let out = tress(&[
        "render",
        scene.to_str().unwrap(),
        "-o",
        png.to_str().unwrap(),
        "--json",
    ]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert!(
        stderr.contains("3 of the hair's strands are in no cluster (3 too short"),
        "{stderr}"
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).expect("one JSON object");
    let s = &v["satf"];
    assert_eq!(s["cluster_strands"], 60);
    assert_eq!(s["skipped_strands"]["total"], 3);
    assert_eq!(s["skipped_strands"]["too_short"], 3);
    assert_eq!(s["skipped_strands"]["degenerate"], 0);
}
