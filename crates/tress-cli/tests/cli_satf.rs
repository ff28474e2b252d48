//! `tress satf-bake`: bakes a small database with a report, checks it, and rejects corrupt or
//! truncated files with one clear line (no GPU needed).

use std::path::PathBuf;
use std::process::{Command, Output};

fn tress(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_tress"))
        .args(args)
        .output()
        .expect("run tress")
}

fn tmp(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("tress-satf-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

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
