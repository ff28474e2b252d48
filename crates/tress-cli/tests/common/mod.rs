//! Shared helpers of the CLI's end-to-end tests: running the `tress` binary, a scratch folder per
//! test binary, and the GPU-test conventions (fail without an adapter unless
//! `TRESS_SKIP_GPU_TESTS=1`).

#![allow(dead_code, unreachable_pub)]

use std::path::PathBuf;
use std::process::{Command, Output};

/// Run the `tress` binary built for these tests with `args` (in this process's environment, so
/// `VK_DRIVER_FILES` / `WGPU_BACKEND` reach it) and return its status and output.
pub fn tress(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_tress"))
        .args(args)
        .output()
        .expect("run tress")
}

/// `name` in a scratch folder of this test binary and process (created if missing):
/// `$TMPDIR/tress-{test binary}-{pid}/name`.
pub fn tmp(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!(
        "tress-{}-{}",
        env!("CARGO_CRATE_NAME"),
        std::process::id()
    ));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

/// Whether GPU tests are skipped on purpose (`TRESS_SKIP_GPU_TESTS=1`).
pub fn skip_gpu() -> bool {
    std::env::var("TRESS_SKIP_GPU_TESTS").is_ok_and(|v| v == "1")
}

/// Assert that a `tress` command succeeded; the failure message names stderr and how to get a
/// GPU adapter, since a missing one is the usual cause.
#[track_caller]
pub fn assert_gpu_success(out: &Output) {
    assert!(
        out.status.success(),
        "tress failed (GPU commands need a Vulkan adapter: install mesa-vulkan-drivers for \
         lavapipe, or set TRESS_SKIP_GPU_TESTS=1 to skip on purpose): {}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// Generate a straight-hair asset of `strands` strands of 8 vertices into the scratch file
/// `name` (`tress generate straight`), asserting that it worked, and return its path.
pub fn straight_hair(name: &str, strands: u32) -> PathBuf {
    let hair = tmp(name);
    let strands = strands.to_string();
    let out = tress(&[
        "generate",
        "straight",
        "-o",
        hair.to_str().unwrap(),
        "--strands",
        &strands,
        "--vertices",
        "8",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    hair
}
