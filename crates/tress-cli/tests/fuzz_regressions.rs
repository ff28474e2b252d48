//! The fuzzers' findings, kept fixed without running a fuzzer.
//!
//! - Every committed seed (`fuzz/seeds/TARGET/`) and regression input (`fuzz/regressions/TARGET/`)
//!   of every fuzz target goes through that target's own check (`fuzz/src/checks.rs`, the code
//!   the fuzz target runs), and the test fails if anything panics at all, a panic that tress
//!   catches and turns into an error included: a hook outside tress's own counts every panic.
//! - Each regression input, written as the file a user would have, goes through the CLI with
//!   `RUST_BACKTRACE=1`: the command exits with status 2 and prints exactly one line.

use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};

mod common;
use common::tmp;

#[allow(dead_code, unreachable_pub)]
#[path = "../../../fuzz/src/checks.rs"]
mod checks;

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// The files of `dir`, sorted (none when it does not exist).
fn files_in(dir: &Path) -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .map(|d| d.filter_map(|e| Some(e.ok()?.path())).collect())
        .unwrap_or_default();
    files.retain(|p| p.is_file());
    files.sort();
    files
}

/// `damaged-*.usdc`: the `.usdc` files the USD property test found (`formats_usd.rs`), fed to
/// the `read_usd` target as `.usdc` inputs.
fn damaged_usdc() -> Vec<PathBuf> {
    let mut files = files_in(&repo().join("crates/tress-hair/tests/data/fuzz"));
    files.retain(|p| p.extension().is_some_and(|e| e == "usdc"));
    files
}

/// Every input of every target: (target, file, the bytes the target is given).
fn inputs() -> Vec<(&'static str, PathBuf, Vec<u8>)> {
    let mut all = Vec::new();
    for &(target, _) in checks::TARGETS {
        for kind in ["seeds", "regressions"] {
            for file in files_in(&repo().join("fuzz").join(kind).join(target)) {
                let bytes = std::fs::read(&file).unwrap();
                all.push((target, file, bytes));
            }
        }
    }
    for file in damaged_usdc() {
        // The first byte picks the flavour: 1 is `usdc`.
        let mut bytes = vec![1u8];
        bytes.extend(std::fs::read(&file).unwrap());
        all.push(("read_usd", file, bytes));
    }
    all
}

static PANICS: AtomicUsize = AtomicUsize::new(0);
static LAST_PANIC: Mutex<String> = Mutex::new(String::new());

#[test]
fn every_seed_and_regression_input_passes_its_fuzz_check_without_any_panic() {
    // Outside tress's own hook, so this one sees the panics tress silences too.
    tress_hair::panic_guard::install();
    let inner = std::panic::take_hook();
    std::panic::set_hook(Box::new(move |info| {
        PANICS.fetch_add(1, Ordering::SeqCst);
        *LAST_PANIC.lock().unwrap_or_else(|e| e.into_inner()) = info.to_string();
        inner(info);
    }));
    let inputs = inputs();
    let mut failures = Vec::new();
    let mut per_target = std::collections::BTreeMap::new();
    for (target, file, bytes) in &inputs {
        let check = checks::TARGETS.iter().find(|(t, _)| t == target).unwrap().1;
        let before = PANICS.load(Ordering::SeqCst);
        let unwound = std::panic::catch_unwind(|| check(bytes)).is_err();
        let panics = PANICS.load(Ordering::SeqCst) - before;
        if panics > 0 || unwound {
            let what = LAST_PANIC.lock().unwrap().clone();
            failures.push(format!(
                "{target} {}: {panics} panic(s): {what}",
                file.display()
            ));
        }
        *per_target.entry(*target).or_insert(0) += 1;
    }
    assert!(failures.is_empty(), "panics:\n{}", failures.join("\n"));
    // Every target has inputs, and the known crashers are among them.
    for &(target, _) in checks::TARGETS {
        assert!(
            per_target.get(target).is_some_and(|&n| n > 0),
            "{target} has no inputs"
        );
    }
    let regressions = |t: &str| files_in(&repo().join("fuzz/regressions").join(t)).len();
    assert!(regressions("read_usd") >= 3 && regressions("read_gltf") >= 3);
}

/// The file a user would have for a regression input of `target`, and the `tress` arguments
/// that read it (`None`: the target has no command of its own here).
fn cli_case(target: &str, name: &str, bytes: &[u8]) -> Option<Vec<String>> {
    let write = |file: &str, data: &[u8]| {
        let path = tmp(file);
        std::fs::write(&path, data).unwrap();
        path.display().to_string()
    };
    // A scene whose head mesh is `mesh`, traced on the CPU: the mesh is read before anything
    // is drawn.
    let head_scene = |mesh: String| {
        let scene = write(
            &format!("{name}.toml"),
            format!("[head]\nmesh = \"{mesh}\"\n").as_bytes(),
        );
        let png = tmp(&format!("{name}.png")).display().to_string();
        [
            "reference",
            &scene,
            "-o",
            &png,
            "--width",
            "8",
            "--height",
            "8",
            "--spp",
            "1",
        ]
        .map(String::from)
        .to_vec()
    };
    let info = |file: String| vec!["info".to_string(), file];
    Some(match target {
        "read_usd" => {
            let (ext, file) = checks::usd_flavour(bytes)?;
            info(write(&format!("{name}.{ext}"), file))
        }
        "read_gltf" => {
            let ext = if bytes.starts_with(b"glTF") {
                "glb"
            } else {
                "gltf"
            };
            head_scene(write(&format!("{name}.{ext}"), bytes))
        }
        "read_obj" => head_scene(write(&format!("{name}.obj"), bytes)),
        "read_hair" => info(write(&format!("{name}.hair"), bytes)),
        "read_tfx" => info(write(&format!("{name}.tfx"), bytes)),
        "read_abc" => info(write(&format!("{name}.abc"), bytes)),
        "read_data" => info(write(&format!("{name}.data"), bytes)),
        "read_ct2hair" => info(write(&format!("{name}.bin"), bytes)),
        "read_satfdb" => vec![
            "satf-bake".into(),
            "--check".into(),
            write(&format!("{name}.satfdb"), bytes),
        ],
        "read_scene" => {
            let scene = write(&format!("{name}.toml"), bytes);
            let png = tmp(&format!("{name}.png")).display().to_string();
            [
                "reference",
                &scene,
                "-o",
                &png,
                "--width",
                "8",
                "--height",
                "8",
                "--spp",
                "1",
            ]
            .map(String::from)
            .to_vec()
        }
        _ => return None,
    })
}

#[test]
fn every_regression_input_gives_one_error_line_and_status_2_even_with_rust_backtrace() {
    let mut cases = 0;
    for (target, file, bytes) in inputs() {
        if file.starts_with(repo().join("fuzz/seeds")) {
            continue;
        }
        let name = format!(
            "{target}-{}",
            file.file_name()
                .unwrap()
                .to_string_lossy()
                .replace('.', "_")
        );
        let args = cli_case(target, &name, &bytes)
            .unwrap_or_else(|| panic!("no CLI case for target {target}"));
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_tress"))
            .args(&args)
            .env("RUST_BACKTRACE", "1")
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        let lines: Vec<&str> = stderr.lines().filter(|l| !l.trim().is_empty()).collect();
        assert_eq!(
            out.status.code(),
            Some(2),
            "{} ({target}): tress {args:?}: {stderr}",
            file.display()
        );
        assert_eq!(
            lines.len(),
            1,
            "{} ({target}): tress {args:?} printed {} lines:\n{stderr}",
            file.display(),
            lines.len()
        );
        assert!(lines[0].starts_with("tress: "), "{}", lines[0]);
        cases += 1;
    }
    assert!(
        cases >= 11,
        "only {cases} regression inputs ran through the CLI"
    );
}
