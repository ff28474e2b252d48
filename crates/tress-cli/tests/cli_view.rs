//! `tress view` end to end: the viewer opens a window on an X server started here (Xvfb),
//! renders a few frames of the demo through the real GPU path (lavapipe in CI) and saves the
//! last one. Fails without Xvfb or without an adapter, unless `TRESS_SKIP_GPU_TESTS=1`.

use std::io::{BufRead, BufReader};
use std::path::PathBuf;
use std::process::{Child, Command, Output, Stdio};
use std::time::{Duration, Instant};

/// Longest a viewer run may take before the test kills it.
const TIMEOUT: Duration = Duration::from_secs(600);

fn skip_gpu() -> bool {
    std::env::var("TRESS_SKIP_GPU_TESTS").is_ok_and(|v| v == "1")
}

fn tmp(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("tress-view-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

/// An Xvfb server on a display it picked itself (`-displayfd`), stopped when dropped.
struct Xvfb {
    child: Child,
    display: String,
}

impl Xvfb {
    fn start() -> Xvfb {
        let mut child = Command::new("Xvfb")
            .args([
                "-displayfd",
                "1",
                "-screen",
                "0",
                "1024x768x24",
                "-nolisten",
                "tcp",
            ])
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .unwrap_or_else(|e| {
                panic!(
                    "cannot start Xvfb ({e}): the viewer test needs an X server; install it \
                     (Debian: apt-get install xvfb xauth), or set TRESS_SKIP_GPU_TESTS=1 to skip \
                     GPU tests on purpose"
                )
            });
        let mut line = String::new();
        BufReader::new(child.stdout.take().unwrap())
            .read_line(&mut line)
            .unwrap();
        let number = line.trim();
        assert!(
            !number.is_empty() && number.chars().all(|c| c.is_ascii_digit()),
            "Xvfb did not report its display (got {line:?})"
        );
        Xvfb {
            display: format!(":{number}"),
            child,
        }
    }
}

impl Drop for Xvfb {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// Run `tress view` with `args` and `env` changes, killing it after [`TIMEOUT`].
fn tress_view(args: &[&str], display: Option<&str>) -> Output {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_tress"));
    cmd.arg("view")
        .args(args)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped());
    match display {
        Some(d) => cmd.env("DISPLAY", d),
        None => cmd.env_remove("DISPLAY"),
    };
    let mut child = cmd.spawn().expect("run tress view");
    let start = Instant::now();
    while child.try_wait().unwrap().is_none() {
        if start.elapsed() > TIMEOUT {
            let _ = child.kill();
            panic!("tress view ran longer than {TIMEOUT:?}");
        }
        std::thread::sleep(Duration::from_millis(100));
    }
    child.wait_with_output().unwrap()
}

#[test]
fn view_renders_frames_and_saves_the_last_one() {
    if skip_gpu() {
        return;
    }
    let xvfb = Xvfb::start();
    let png = tmp("view.png");
    let out = tress_view(
        &[
            "--frames",
            "5",
            "--screenshot",
            png.to_str().unwrap(),
            "--width",
            "320",
            "--height",
            "240",
        ],
        Some(&xvfb.display),
    );
    assert!(
        out.status.success(),
        "tress view failed (it needs a Vulkan adapter that can present to X11: install \
         mesa-vulkan-drivers for lavapipe, or set TRESS_SKIP_GPU_TESTS=1 to skip on purpose): {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        stdout.contains("5 frames of strands at 320x240"),
        "{stdout}"
    );

    // The frame has the window's size and shows the demo: many pixels differ from the flat
    // background (the top-left corner).
    let img = image::open(&png).unwrap().to_rgba8();
    assert_eq!(img.dimensions(), (320, 240));
    let bg = *img.get_pixel(0, 0);
    let differing = img
        .pixels()
        .filter(|p| p.0.iter().zip(bg.0).any(|(a, b)| a.abs_diff(b) > 8))
        .count();
    assert!(
        differing > 320 * 240 / 20,
        "only {differing} pixels differ from the background"
    );

    // The screenshot is what the window shows (the presentation shader's output, without the
    // panel), and that is `tress render`'s image of the same scene and size: measured 0.00006
    // RMSE on lavapipe, a few pixels one level apart.
    let rendered = tmp("view-render.png");
    let out = Command::new(env!("CARGO_BIN_EXE_tress"))
        .args(["render", "-o", rendered.to_str().unwrap()])
        .args(["--width", "320", "--height", "240"])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let want = image::open(&rendered).unwrap().to_rgba8();
    let off: Vec<u8> = img
        .pixels()
        .zip(want.pixels())
        .map(|(a, b)| (0..3).map(|c| a.0[c].abs_diff(b.0[c])).max().unwrap())
        .collect();
    let worst = off.iter().copied().max().unwrap();
    let apart = off.iter().filter(|&&d| d > 1).count();
    assert!(
        worst <= 8 && apart <= 320 * 240 / 1000,
        "the screenshot differs from tress render: {apart} pixels by more than a level, \
         the worst by {worst}"
    );
}

#[test]
fn view_without_a_display_says_so_in_one_line() {
    let out = tress_view(&["--frames", "1"], None);
    assert_eq!(out.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("no display (set DISPLAY or run under xvfb-run)"),
        "{stderr}"
    );
    assert_eq!(stderr.trim_end().lines().count(), 1, "{stderr}");
}

#[test]
fn view_rejects_bad_options_before_opening_a_window() {
    for (args, needle) in [
        (&["--frames", "0"][..], "--frames"),
        (&["--technique", "raytrace"][..], "raytrace"),
        (&["--screenshot", "x.exr"][..], "PNG"),
    ] {
        let out = tress_view(args, Some(":none"));
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(stderr.contains(needle), "{args:?}: {stderr}");
    }
}
