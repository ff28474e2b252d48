//! End-to-end tests of the hair subcommands (`info`, `generate`, `convert`) and of the CLI's
//! error contract: one line on stderr naming the file and the problem, exit status 2.

mod common;

use std::path::Path;
use std::process::Output;

use common::{tmp, tress};

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

fn info_json(files: &[&Path]) -> serde_json::Value {
    let mut args = vec!["info", "--json"];
    args.extend(files.iter().map(|p| s(p)));
    let out = tress(&args);
    assert!(
        out.status.success(),
        "info failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8(out.stdout).unwrap();
    // Exactly one JSON object on stdout.
    let mut stream = serde_json::Deserializer::from_str(&text).into_iter::<serde_json::Value>();
    let v = stream.next().expect("one object").expect("valid JSON");
    assert!(stream.next().is_none(), "more than one JSON value: {text}");
    v
}

/// The error contract: non-zero (2), exactly one line on stderr, naming `needle`.
fn assert_one_line_error(out: &Output, needle: &str) {
    assert_eq!(
        out.status.code(),
        Some(2),
        "stderr: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(
        err.trim_end().lines().count(),
        1,
        "one line expected, got: {err}"
    );
    assert!(err.contains(needle), "{err:?} should name {needle:?}");
    assert!(!err.contains("panicked"), "{err}");
}

#[test]
fn generate_then_info_reports_counts_and_bounds() {
    let path = tmp("straight.hair");
    let out = tress(&[
        "generate",
        "straight",
        "-o",
        s(&path),
        "--strands",
        "300",
        "--vertices",
        "12",
        "--seed",
        "3",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v = info_json(&[&path]);
    assert_eq!(v["strands"], 300);
    assert_eq!(v["vertices"], 300 * 12);
    assert_eq!(v["segments"], 300 * 11);
    assert_eq!(v["vertices_per_strand_min"], 12);
    assert_eq!(v["vertices_per_strand_max"], 12);
    assert_eq!(v["has_thickness"], true);
    assert!(v["has_color"].is_boolean());
    for i in 0..3 {
        assert!(v["bbox_min"][i].as_f64().unwrap() <= v["bbox_max"][i].as_f64().unwrap());
    }
}

#[test]
fn generate_is_deterministic_for_a_seed() {
    let a = tmp("det-a.hair");
    let b = tmp("det-b.hair");
    for p in [&a, &b] {
        let out = tress(&[
            "generate",
            "curly",
            "-o",
            s(p),
            "--strands",
            "50",
            "--seed",
            "11",
        ]);
        assert!(out.status.success());
    }
    assert_eq!(std::fs::read(&a).unwrap(), std::fs::read(&b).unwrap());
}

#[test]
fn convert_merges_and_adds_follow_hairs() {
    let a = tmp("guides-a.tfx");
    let b = tmp("guides-b.hair");
    let out_path = tmp("merged.hair");
    assert!(
        tress(&[
            "generate",
            "wavy",
            "-o",
            s(&a),
            "--strands",
            "20",
            "--vertices",
            "16"
        ])
        .status
        .success()
    );
    assert!(
        tress(&[
            "generate",
            "straight",
            "-o",
            s(&b),
            "--strands",
            "30",
            "--vertices",
            "16"
        ])
        .status
        .success()
    );
    let out = tress(&[
        "convert",
        s(&a),
        s(&b),
        s(&out_path),
        "--follow",
        "3",
        "--seed",
        "5",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v = info_json(&[&out_path]);
    assert_eq!(v["strands"], (20 + 30) * 4);
    assert_eq!(v["vertices"], (20 + 30) * 4 * 16);
    // info merges several inputs the same way.
    let both = info_json(&[&a, &b]);
    assert_eq!(both["strands"], 50);
}

#[test]
fn convert_round_trips_between_formats() {
    let hair = tmp("rt.hair");
    let tfx = tmp("rt.tfx");
    let back = tmp("rt-back.hair");
    assert!(
        tress(&[
            "generate",
            "ponytail",
            "-o",
            s(&hair),
            "--strands",
            "64",
            "--vertices",
            "8"
        ])
        .status
        .success()
    );
    assert!(tress(&["convert", s(&hair), s(&tfx)]).status.success());
    assert!(tress(&["convert", s(&tfx), s(&back)]).status.success());
    let (x, y) = (info_json(&[&hair]), info_json(&[&back]));
    for key in ["strands", "vertices", "bbox_min", "bbox_max"] {
        assert_eq!(x[key], y[key], "{key}");
    }
}

#[test]
fn bad_inputs_give_one_line_and_exit_2() {
    let missing = tmp("does-not-exist.hair");
    assert_one_line_error(&tress(&["info", s(&missing)]), "does-not-exist.hair");

    let garbage = tmp("garbage.hair");
    std::fs::write(&garbage, b"NOPE this is not a hair file at all").unwrap();
    assert_one_line_error(&tress(&["info", s(&garbage)]), "garbage.hair");

    let truncated = tmp("truncated.tfx");
    let good = tmp("good.tfx");
    assert!(
        tress(&["generate", "straight", "-o", s(&good), "--strands", "10"])
            .status
            .success()
    );
    let bytes = std::fs::read(&good).unwrap();
    std::fs::write(&truncated, &bytes[..bytes.len() / 2]).unwrap();
    assert_one_line_error(&tress(&["info", s(&truncated)]), "truncated.tfx");

    let unknown = tmp("hair.xyz");
    std::fs::write(&unknown, b"x").unwrap();
    assert_one_line_error(&tress(&["info", s(&unknown)]), "hair.xyz");

    // A huge count in a tiny .hair file: header says 2^32-1 strands and points.
    let mut lie = vec![0u8; 128];
    lie[..4].copy_from_slice(b"HAIR");
    lie[4..8].copy_from_slice(&u32::MAX.to_le_bytes());
    lie[8..12].copy_from_slice(&u32::MAX.to_le_bytes());
    lie[12..16].copy_from_slice(&0b10u32.to_le_bytes());
    let liar = tmp("liar.hair");
    std::fs::write(&liar, &lie).unwrap();
    assert_one_line_error(&tress(&["info", s(&liar)]), "liar.hair");

    let bad_param = tress(&[
        "generate",
        "straight",
        "-o",
        s(&tmp("x.hair")),
        "--vertices",
        "1",
    ]);
    assert_one_line_error(&bad_param, "vert");
}
