//! The controls driving a real session, as the viewer does (`app/running.rs`): the dragged head
//! carries the simulated hair's roots, a settings edit restarts with the head held where it was
//! and the clock going on, Step runs one step, Reset puts the hair back at rest. Needs a GPU
//! adapter (lavapipe will do); `TRESS_SKIP_GPU_TESTS=1` skips it where there is none.

use std::sync::OnceLock;

use tress_render::session::{Session, SessionOptions};
use tress_render::{GpuContext, TargetFormats};

use super::*;

/// The GPU context, or `None` when `TRESS_SKIP_GPU_TESTS=1` and there is no adapter (as
/// tress-render's GPU tests).
fn gpu() -> Option<GpuContext> {
    static CTX: OnceLock<Result<GpuContext, String>> = OnceLock::new();
    match CTX.get_or_init(|| GpuContext::headless().map_err(|e| e.to_string())) {
        Ok(ctx) => Some(ctx.clone()),
        Err(e) if std::env::var("TRESS_SKIP_GPU_TESTS").is_ok_and(|v| v == "1") => {
            eprintln!("TRESS_SKIP_GPU_TESTS=1: skipping a GPU test ({e})");
            None
        }
        Err(e) => panic!(
            "this test needs a GPU adapter: {e} (lavapipe will do: \
             VK_DRIVER_FILES=/usr/share/vulkan/icd.d/lvp_icd.x86_64.json WGPU_BACKEND=vulkan; \
             TRESS_SKIP_GPU_TESTS=1 skips GPU tests on purpose)"
        ),
    }
}

/// Short straight hair on the generated head.
const SCENE: &str = "technique = \"strands\"\n\
    [[hair]]\n\
    generator = { style = \"straight\", strands = 96, vertices = 8, length = 10.0 }\n\
    [head]\n\
    generated = true\n\
    [simulation]\n\
    guides = 0.25\n";

/// Run a command on the session as the viewer does.
fn run(c: &mut SimControls, s: &mut Session, ctx: &GpuContext, command: Command) {
    match command {
        Command::None => {}
        Command::Stop => s.stop_simulation(ctx).unwrap(),
        Command::Start { settings, motion } => {
            s.start_simulation(ctx, settings, motion).unwrap();
            c.started(s.simulation().unwrap().pivots().collect());
        }
        Command::Restart { settings, motion } => s.start_simulation(ctx, settings, motion).unwrap(),
    }
}

/// A frame `dt` seconds on: the steps run.
fn frame(c: &mut SimControls, s: &mut Session, ctx: &GpuContext, dt: f64) -> u64 {
    let t = c.advance(dt).unwrap();
    s.simulate_to_with(ctx, t, false, |k, time| c.head(k, time))
        .unwrap()
        .steps
}

/// Each strand's root as the frames draw it.
fn roots(s: &mut Session, ctx: &GpuContext) -> Vec<Vec3> {
    let p = s.read_hair_positions(ctx).unwrap();
    let asset = &s.prepared().objects[0].asset;
    (0..asset.strand_count())
        .map(|k| p[asset.strand_range(k).start])
        .collect()
}

fn max_distance(a: &[Vec3], b: &[Vec3], by: Vec3) -> f32 {
    assert_eq!(a.len(), b.len());
    a.iter()
        .zip(b)
        .map(|(a, b)| a.distance(*b + by))
        .fold(0.0, f32::max)
}

#[test]
fn the_controls_drive_a_session_and_the_hair_follows_the_dragged_head() {
    let Some(ctx) = gpu() else { return };
    let scene = tress_scene::Scene::from_str(SCENE, ".").unwrap();
    let mut s = Session::new(
        &ctx,
        TargetFormats::default(),
        scene,
        SessionOptions::default(),
    )
    .unwrap();
    let rest = roots(&mut s, &ctx);
    let base = s.scene().simulation_settings().unwrap();
    let mut c = SimControls::new(base, None);
    let command = c.apply(SimAction::Enable(true));
    run(&mut c, &mut s, &ctx, command);
    assert_eq!(c.pivots.len(), 1);

    // The head dragged 3 units along +x: the roots move with it, a frame of steps at once.
    c.drag_move(3.0, 0.0, Vec3::X, Vec3::Y, 1.0);
    assert_eq!(frame(&mut c, &mut s, &ctx, 0.05), 3);
    let moved = Vec3::new(3.0, 0.0, 0.0);
    assert!(max_distance(&roots(&mut s, &ctx), &rest, moved) < 1e-3);

    // A settings edit restarts the simulation with the head where it was, the clock going on.
    let mut e = c.edit;
    e.wind_strength = 400.0;
    e.global_stiffness = 0.1;
    let command = c.apply(SimAction::Edit(e));
    assert!(matches!(command, Command::Restart { .. }));
    run(&mut c, &mut s, &ctx, command);
    assert_eq!(s.simulation().unwrap().settings().wind.strength, 400.0);
    assert!(max_distance(&roots(&mut s, &ctx), &rest, moved) < 1e-3);
    assert!((c.time() - 0.05).abs() < 1e-9);
    assert_eq!(frame(&mut c, &mut s, &ctx, 0.05), 3);
    assert!(max_distance(&roots(&mut s, &ctx), &rest, moved) < 1e-3);

    // Paused, frames run nothing; Step runs exactly one step.
    c.apply(SimAction::Pause(true));
    assert_eq!(frame(&mut c, &mut s, &ctx, 0.05), 0);
    c.apply(SimAction::Step);
    assert_eq!(frame(&mut c, &mut s, &ctx, 0.05), 1);

    // Reset: back at 0 s with the head and the hair at rest.
    let command = c.apply(SimAction::Reset);
    run(&mut c, &mut s, &ctx, command);
    assert!(max_distance(&roots(&mut s, &ctx), &rest, Vec3::ZERO) < 1e-3);
    let command = c.apply(SimAction::Enable(false));
    run(&mut c, &mut s, &ctx, command);
    assert!(s.simulation().is_none());
}
