//! The tress viewer: a winit window showing a hair scene rendered by
//! [`tress_render::session::Session`], with an egui panel of the current technique's settings,
//! per-pass GPU timings and the GPU memory breakdown.
//!
//! The viewer has no rendering logic of its own. Each frame the session renders into an
//! offscreen target of the window's size ([`tress_render::OffscreenTargets`], linear half
//! floats), which is copied texel for texel onto the window's surface (sRGB encoded when the
//! surface format is plain 8-bit) and the panel is drawn over it. Screenshots are that target
//! read back ([`tress_render::read_texture`]), so they are exactly what `tress render` would
//! write for the same camera.
//!
//! The window's camera is an [`OrbitCamera`] about the scene camera's target, which needs no
//! window or GPU:
//!
//! ```
//! use tress_viewer::{OrbitCamera, ZOOM_PER_LINE};
//!
//! let scene = tress_scene::Scene::from_str("", ".")?; // the default scene
//! let mut orbit = OrbitCamera::from_scene(&scene.camera);
//! assert!(orbit.eye().abs_diff_eq(scene.camera.eye, 1e-3)); // the first frame: the scene's camera
//! let distance = orbit.distance;
//! orbit.orbit(120.0, 0.0); // a left drag 120 pixels to the right
//! orbit.zoom(1.0); // one wheel line towards the target
//! assert!((orbit.distance - ZOOM_PER_LINE * distance).abs() < 1e-4 * distance);
//! let camera = orbit.camera([1280, 720]); // what the session renders with
//! # Ok::<(), tress_scene::SceneError>(())
//! ```
//!
//! Controls: left drag orbits about the camera target, middle drag pans, the wheel zooms. Keys:
//! T the next technique ([`tress_render::session::TechniqueKind::NAMES`] order: the five, then
//! `auto`), L rotates the lights
//! about the up axis, S saves `tress-view-NNNN.png`, R reloads the shaders (see below), P pauses
//! or runs the simulation, Space plays or pauses an animated cache and `,` / `.` step it a frame
//! back / on, U hides the panel, Q or Esc quits. Files dropped on the window, or named in the
//! panel's Open field, are opened as a new session.
//!
//! An animated cache (Alembic `P` sampled once a frame, USD `points.timeSamples`, as `tress
//! simulate` writes them; [`tress_hair::formats::Details::frames`] above 1) plays in the panel's
//! playback section (`src/playback.rs`): play and pause, previous and next frame, a
//! frame slider, the frame rate (the file's where it says, else 24 fps) and loop. It opens
//! paused at the scene's frame (`hair.N.frame`, 0 unset); playing, the frame follows the clock.
//! Each frame is the one `tress render cache.abc --frame K` draws: the animated files read again
//! at `K`, and with strands, volume, hybrid and auto only the vertex positions replaced
//! ([`tress_render::session::Session::update_hair_positions`]); patches and SATF build from the
//! loaded hair, so for them a frame is the setting `hair.N.frame=K`, which reloads the session's
//! hair (as slow as opening the file). While the simulation runs it drives the hair and the
//! cache waits.
//!
//! The panel's simulation section simulates the hair on the GPU
//! ([`tress_render::session::Session::start_simulation`]; the techniques that draw strands):
//! on and off, pause, one step, reset, the head's motion (the scene's `[head.motion]`, still, or
//! a preset), and the local and global stiffness, damping and wind (strength, turbulence,
//! heading), which start the simulation again with the new values when a slider is released, the
//! clock and the head going on. While simulating, Shift + left drag moves the head in the view
//! plane and Ctrl + left drag turns it about the vertical; the hair follows
//! ([`tress_render::session::Session::simulate_to_with`]). Simulated time follows the clock (a
//! frame counts at most 0.1 s) and the hair steps at the fixed `simulation.rate_hz`, so the
//! display rate does not change it. The timings show the simulation's passes' GPU times for the
//! frame (`sim/integrate`, `sim/grid`, `sim/constraints`, `sim/output`, from timestamps where
//! the device has them), its steps and their CPU wall time (recording to the GPU's end), its
//! guides and strands, and its GPU memory. A scene with `[simulation] enabled = true` starts
//! simulating when it opens.
//!
//! R reloads the shaders: the renderer reads its WGSL from a checkout's
//! `crates/tress-render/src` for pipelines created from then on
//! ([`tress_render::shaders::set_source_dir`]) and the session is rebuilt, so every pipeline is
//! compiled again from the files on disk. The checkout is `TRESS_SOURCE_DIR` (a repository
//! root), else the first one from the working directory upwards, else the one the binary was
//! built from if it still exists; without one R rebuilds from the built-in WGSL. A shader that
//! does not compile leaves the running session alone and shows its error in the panel.
//!
//! ```no_run
//! let report = tress_viewer::run(tress_viewer::ViewerOptions {
//!     frames: Some(5),
//!     screenshot: Some("demo.png".into()),
//!     ..Default::default()
//! })?;
//! println!("{} frames, {:.1} ms each", report.frames, report.mean_interval_ms);
//! # Ok::<(), anyhow::Error>(())
//! ```

mod app;
mod display;
mod orbit;
mod panel;
mod playback;
mod present;
mod reload;
mod sim_controls;

use std::path::PathBuf;

use anyhow::{Context as _, Result, bail};
use tress_render::Timings;
use tress_render::session::{DatabaseLoader, technique_name};

pub use app::LIGHT_RADIANS_PER_SECOND;
pub use orbit::{OrbitCamera, RADIANS_PER_PIXEL, ZOOM_PER_LINE};
pub use reload::SOURCE_DIR_ENV;

/// How the viewer starts.
pub struct ViewerOptions {
    /// A scene file, hair files or a hair-card OBJ (as `tress render`); nothing opens the
    /// built-in demo.
    pub inputs: Vec<PathBuf>,
    /// Window size in physical pixels (the rendered frame's size).
    pub size: [u32; 2],
    /// Technique to start with (default: the scene's).
    pub technique: Option<String>,
    /// Dotted `key=value` settings applied to every scene opened (as `--set`).
    pub overrides: Vec<String>,
    /// Render this many frames, then exit.
    pub frames: Option<u32>,
    /// Save the last frame here (PNG) before exiting.
    pub screenshot: Option<PathBuf>,
    /// The SATF database source; without one the `satf` technique reports that it needs one.
    pub satf_database: Option<DatabaseLoader>,
}

impl Default for ViewerOptions {
    fn default() -> Self {
        ViewerOptions {
            inputs: Vec::new(),
            size: [1280, 720],
            technique: None,
            overrides: Vec::new(),
            frames: None,
            screenshot: None,
            satf_database: None,
        }
    }
}

impl std::fmt::Debug for ViewerOptions {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ViewerOptions")
            .field("inputs", &self.inputs)
            .field("size", &self.size)
            .field("technique", &self.technique)
            .field("overrides", &self.overrides)
            .field("frames", &self.frames)
            .field("screenshot", &self.screenshot)
            .field("satf_database", &self.satf_database.is_some())
            .finish()
    }
}

/// What a run measured.
#[derive(Clone, Debug, PartialEq)]
pub struct ViewerReport {
    /// Frames rendered.
    pub frames: u32,
    /// The technique at the end.
    pub technique: &'static str,
    /// The frame size at the end, pixels.
    pub size: [u32; 2],
    /// The adapter's name.
    pub adapter: String,
    /// CPU wall time of the first render call (pipelines and uploads on first use), ms.
    pub first_frame_ms: f64,
    /// Mean CPU wall time of the later render calls, ms (deferred readback: encoding and
    /// submission, and whatever waiting the driver does).
    pub mean_render_ms: f64,
    /// Mean time between later frames (render, presentation and UI), ms.
    pub mean_interval_ms: f64,
    /// The newest per-pass GPU times.
    pub timings: Option<Timings>,
    /// Seconds from the window's GPU setup to the end.
    pub seconds: f64,
}

impl std::fmt::Display for ViewerReport {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{} frames of {} at {}x{} on {}: first render call {:.1} ms, then {:.1} ms CPU wall \
             per render call, {:.1} ms per frame shown",
            self.frames,
            self.technique,
            self.size[0],
            self.size[1],
            self.adapter,
            self.first_frame_ms,
            self.mean_render_ms,
            self.mean_interval_ms
        )?;
        match &self.timings {
            Some(t @ Timings::Passes(_)) => {
                write!(f, "; GPU {:.1} ms ({t})", t.total_ms().unwrap_or(0.0))
            }
            Some(Timings::NotSupported) => write!(f, "; no GPU timestamps"),
            None => write!(f, "; no GPU timings back yet"),
        }
    }
}

/// The error when no display can be opened.
pub const NO_DISPLAY: &str = "no display (set DISPLAY or run under xvfb-run)";

/// Check the options before a window opens.
fn check(options: &ViewerOptions) -> Result<()> {
    if options.size.contains(&0) {
        bail!(
            "window size {}x{} must be at least 1x1",
            options.size[0],
            options.size[1]
        );
    }
    if options.frames == Some(0) {
        bail!("--frames must be at least 1");
    }
    if let Some(t) = &options.technique {
        technique_name(t)?;
    }
    if let Some(p) = &options.screenshot
        && !p.extension().is_some_and(|e| e.eq_ignore_ascii_case("png"))
    {
        bail!("{}: screenshots are PNG files (.png)", p.display());
    }
    Ok(())
}

/// Whether a display server is named in the environment (X11 is the backend compiled in;
/// Wayland desktops provide it through XWayland).
fn display_available() -> bool {
    if cfg!(all(
        unix,
        not(target_os = "macos"),
        not(target_os = "android")
    )) {
        std::env::var_os("DISPLAY").is_some_and(|d| !d.is_empty())
    } else {
        true
    }
}

/// Open the window and run until it is closed, or for `options.frames` frames. Errors before
/// the first frame (no display, no adapter, a file that does not load) end the run; later
/// errors show in the panel, except in a `frames` run, which they end.
pub fn run(options: ViewerOptions) -> Result<ViewerReport> {
    check(&options)?;
    if !display_available() {
        bail!(NO_DISPLAY);
    }
    let event_loop = winit::event_loop::EventLoop::new().map_err(|e| {
        anyhow::anyhow!(
            "cannot open display `{}` (is an X server running there? or run under xvfb-run): {e}",
            std::env::var("DISPLAY").unwrap_or_default()
        )
    })?;
    let mut app = app::App::new(options);
    event_loop
        .run_app(&mut app)
        .context("running the window's event loop")?;
    if let Some(e) = app.fatal {
        return Err(e);
    }
    app.report
        .context("the window closed before the viewer started")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn options_are_checked_before_a_window_opens() {
        assert!(check(&ViewerOptions::default()).is_ok());
        for (options, needle) in [
            (
                ViewerOptions {
                    size: [0, 10],
                    ..Default::default()
                },
                "0x10",
            ),
            (
                ViewerOptions {
                    frames: Some(0),
                    ..Default::default()
                },
                "--frames",
            ),
            (
                ViewerOptions {
                    technique: Some("raytrace".into()),
                    ..Default::default()
                },
                "raytrace",
            ),
            (
                ViewerOptions {
                    screenshot: Some("x.exr".into()),
                    ..Default::default()
                },
                "PNG",
            ),
        ] {
            let e = check(&options).unwrap_err().to_string();
            assert!(e.contains(needle), "{e} should name {needle}");
        }
    }

    #[test]
    fn screenshots_get_the_first_free_number() {
        let dir = std::env::temp_dir().join(format!("tress-viewer-shots-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let first = app::next_screenshot_path(&dir);
        assert!(first.ends_with("tress-view-0001.png"));
        std::fs::write(&first, b"x").unwrap();
        assert!(app::next_screenshot_path(&dir).ends_with("tress-view-0002.png"));
    }
}
