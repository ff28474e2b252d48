//! The PPLL's overflow at a user's scale: the built-in demo at 1920x1080 with a 16 MiB node
//! pool (`strands.oit = "ppll"`, so nothing switches to ShortCut) loses exactly what does not
//! fit, renders at most `MAX_ATTEMPTS` times and leaves finite pixels; a target too large for
//! the device's limits is a `RenderError::Limit`, not a crash.

mod common;

use tress_render::session::{FrameDetail, Session, SessionOptions, scene_from_inputs};
use tress_render::strands::NODE_BYTES;
use tress_render::{
    COLOR_FORMAT, GpuContext, MAX_ATTEMPTS, OffscreenTargets, RenderError, TargetFormats,
    read_texture,
};

/// The demo with 2% of the ponytail's strands (2,726) and the PPLL capped at 16 MiB.
fn session(ctx: &GpuContext) -> Session {
    let (scene, auto_frame) = scene_from_inputs(&[]).unwrap();
    let options = SessionOptions {
        auto_frame,
        overrides: vec![
            "hair.0.strand_ratio=0.02".into(),
            "strands.oit=\"ppll\"".into(),
            "strands.ppll_max_mib=16".into(),
        ],
        ..SessionOptions::default()
    };
    Session::new(ctx, TargetFormats::default(), scene, options).unwrap()
}

#[test]
fn a_full_hd_demo_frame_loses_exactly_what_a_16_mib_pool_cannot_hold() {
    let Some(ctx) = common::gpu() else { return };
    let mut s = session(&ctx);
    let size = [1920, 1080];
    let targets = OffscreenTargets::new(&ctx, size, COLOR_FORMAT).unwrap();
    let camera = s.camera(size);
    let f = s.render(&ctx, &targets.targets(), &camera, None).unwrap();
    let FrameDetail::Strands(stats) = &f.detail else {
        panic!("a strands frame expected, got {:?}", f.detail);
    };
    let gpu = stats
        .gpu
        .as_ref()
        .expect("offline frames wait for their statistics");
    let capacity = ((16u64 << 20) / NODE_BYTES) as u32;
    eprintln!(
        "{} fragments, {} nodes, {} dropped, {} attempts",
        gpu.ppll.requested, gpu.ppll.capacity, gpu.ppll.dropped, stats.attempts
    );
    assert!(
        (1..=MAX_ATTEMPTS).contains(&stats.attempts),
        "{} attempts",
        stats.attempts
    );
    assert_eq!(gpu.ppll.capacity, capacity, "the pool grew to its cap");
    assert_eq!(gpu.ppll.used, capacity, "a full pool");
    assert!(
        gpu.ppll.requested > 2 * capacity,
        "the frame must overflow the pool well: {} fragments",
        gpu.ppll.requested
    );
    assert_eq!(gpu.ppll.dropped, gpu.ppll.requested - capacity);
    let oit = gpu.oit.expect("strands were drawn");
    assert_eq!(
        (oit.fragments, oit.lost),
        (gpu.ppll.requested, gpu.ppll.requested - capacity)
    );
    let img = read_texture(&ctx, &targets.color).unwrap();
    assert_eq!((img.width, img.height), (size[0], size[1]));
    for p in &img.pixels {
        assert!(p.iter().all(|c| c.is_finite()), "a non-finite pixel {p:?}");
        assert!(p[3] <= 1.0 + 1e-3, "alpha above 1: {p:?}");
    }
}

#[test]
fn a_target_beyond_the_devices_limits_is_a_limit_error() {
    let Some(ctx) = common::gpu() else { return };
    let mut s = session(&ctx);
    // The smallest square target whose PPLL heads (4 bytes a pixel) exceed the device's
    // storage-binding limit (5,793² on lavapipe's 128 MiB), if the device can draw one.
    let limit = ctx.caps.max_storage_binding.min(ctx.caps.max_buffer_size);
    let side = ((limit / 4) as f64).sqrt().floor() as u32 + 1;
    assert!(
        side <= ctx.device.limits().max_texture_dimension_2d,
        "this device cannot draw a target large enough to exceed its limits"
    );
    let targets = OffscreenTargets::new(&ctx, [side, side], COLOR_FORMAT).unwrap();
    let camera = s.camera([side, side]);
    match s.render(&ctx, &targets.targets(), &camera, None) {
        Err(RenderError::Limit { .. }) => {}
        other => panic!("expected a limit error, got {other:?}"),
    }
}
