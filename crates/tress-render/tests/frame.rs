//! Whole frames: the head occludes hair, caller targets are checked (errors, not panics),
//! timestamps are reported per pass, deferred statistics arrive, sRGB targets work.

mod common;

use glam::Vec3;
use tress_render::{
    COLOR_FORMAT, DirectionalLight, FrameInputs, HeadGeometry, Material, OffscreenTargets,
    PASS_NAMES, RenderError, Renderer, SharedInputs, StatsReadback, StrandSettings, TargetFormats,
    Targets, Timings, TriMesh, read_texture,
};

const SIZE: u32 = 48;

fn inputs<'a>(
    hair: Option<&'a tress_render::StrandGeometry>,
    head: Option<&'a HeadGeometry>,
    lights: &'a [DirectionalLight],
) -> FrameInputs<'a> {
    FrameInputs {
        shared: SharedInputs {
            camera: common::ortho_camera(SIZE),
            lights,
            ambient: Vec3::ONE,
            head,
            clear: Some(wgpu::Color::BLACK),
        },
        material: Material {
            head_color: Vec3::new(0.0, 1.0, 0.0),
            ..Default::default()
        },
        hair,
        objects: &[],
    }
}

#[test]
fn head_in_front_hides_hair_behind_it() {
    let Some(ctx) = common::gpu() else { return };
    let settings = StrandSettings {
        alpha: 1.0,
        coverage: false,
        width_px: 24.0,
        ..Default::default()
    };
    let mut r = Renderer::new(&ctx, TargetFormats::default(), settings).expect("renderer");
    let red = [(0.0, Vec3::X, 1.0)];
    let hair = r
        .upload_hair(&ctx, &common::layer_strands(&red))
        .expect("hair");
    let head = HeadGeometry::new(
        &ctx,
        &TriMesh::uv_sphere(Vec3::new(0.0, 0.0, 2.0), 0.3, 16, 24),
    )
    .expect("head");
    let t = OffscreenTargets::new(&ctx, [SIZE, SIZE], COLOR_FORMAT).expect("targets");
    r.render(&ctx, &t.targets(), &inputs(Some(&hair), Some(&head), &[]))
        .expect("frame");
    let img = read_texture(&ctx, &t.color).expect("readback");
    let centre = img.get(SIZE / 2, SIZE / 2).expect("pixel");
    assert!(
        centre[1] > 0.9 && centre[0] < 0.05,
        "head (green) in front: {centre:?}"
    );
    let side = img.get(3, SIZE / 2).expect("pixel");
    assert!(
        side[0] > 0.9 && side[1] < 0.05,
        "hair (red) beside the head: {side:?}"
    );

    // Hair in front of the head covers it.
    let head_behind = HeadGeometry::new(
        &ctx,
        &TriMesh::uv_sphere(Vec3::new(0.0, 0.0, -2.0), 0.3, 16, 24),
    )
    .expect("head");
    r.render(
        &ctx,
        &t.targets(),
        &inputs(Some(&hair), Some(&head_behind), &[]),
    )
    .expect("frame");
    let img = read_texture(&ctx, &t.color).expect("readback");
    let centre = img.get(SIZE / 2, SIZE / 2).expect("pixel");
    assert!(
        centre[0] > 0.9 && centre[1] < 0.05,
        "hair in front: {centre:?}"
    );
}

#[test]
fn bad_targets_and_inputs_are_errors() {
    let Some(ctx) = common::gpu() else { return };
    let mut r =
        Renderer::new(&ctx, TargetFormats::default(), StrandSettings::default()).expect("renderer");
    let t = OffscreenTargets::new(&ctx, [SIZE, SIZE], COLOR_FORMAT).expect("targets");
    let mut wrong_viewport = inputs(None, None, &[]);
    wrong_viewport.shared.camera.viewport = [SIZE + 1, SIZE];
    assert!(matches!(
        r.render(&ctx, &t.targets(), &wrong_viewport),
        Err(RenderError::Target(_))
    ));

    let lights = [DirectionalLight::default(); 5];
    assert!(matches!(
        r.render(&ctx, &t.targets(), &inputs(None, None, &lights)),
        Err(RenderError::Invalid(_))
    ));

    let srgb = OffscreenTargets::new(&ctx, [SIZE, SIZE], wgpu::TextureFormat::Rgba8UnormSrgb)
        .expect("targets");
    let e = r
        .render(&ctx, &srgb.targets(), &inputs(None, None, &[]))
        .expect_err("format");
    assert!(e.to_string().contains("Rgba8UnormSrgb"), "{e}");

    let small = OffscreenTargets::new(&ctx, [SIZE, SIZE / 2], COLOR_FORMAT).expect("targets");
    let mixed = Targets {
        color: &t.color_view,
        depth: &small.depth_view,
    };
    assert!(matches!(
        r.render(&ctx, &mixed, &inputs(None, None, &[])),
        Err(RenderError::Target(_))
    ));

    let no_binding = ctx.device.create_texture(&wgpu::TextureDescriptor {
        label: Some("test/depth-without-binding"),
        size: wgpu::Extent3d {
            width: SIZE,
            height: SIZE,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: tress_render::DEPTH_FORMAT,
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
        view_formats: &[],
    });
    let view = no_binding.create_view(&Default::default());
    let e = r
        .render(
            &ctx,
            &Targets {
                color: &t.color_view,
                depth: &view,
            },
            &inputs(None, None, &[]),
        )
        .expect_err("usage");
    assert!(e.to_string().contains("TEXTURE_BINDING"), "{e}");

    let bad = StrandSettings {
        k: 0,
        ..Default::default()
    };
    assert!(r.set_settings(&ctx, bad).is_err());
    assert!(OffscreenTargets::new(&ctx, [0, 4], COLOR_FORMAT).is_err());
}

#[test]
fn every_pass_is_timed_when_timestamps_exist() {
    let Some(ctx) = common::gpu() else { return };
    let mut r =
        Renderer::new(&ctx, TargetFormats::default(), StrandSettings::default()).expect("renderer");
    let hair = r
        .upload_hair(&ctx, &common::sphere_hair(0.5, 200, 8))
        .expect("hair");
    let head =
        HeadGeometry::new(&ctx, &TriMesh::uv_sphere(Vec3::ZERO, 0.45, 12, 16)).expect("head");
    let t = OffscreenTargets::new(&ctx, [SIZE, SIZE], COLOR_FORMAT).expect("targets");
    let lights = [DirectionalLight::default()];
    let stats = r
        .render(
            &ctx,
            &t.targets(),
            &inputs(Some(&hair), Some(&head), &lights),
        )
        .expect("frame");
    let gpu = stats.gpu.expect("stats are waited for");
    match &gpu.timings {
        Timings::NotSupported => {
            assert!(!ctx.caps.timestamps);
            assert!(gpu.timings.to_string().contains("not supported"));
            eprintln!("the adapter has no timestamp queries: the pass order is not checked");
        }
        Timings::Passes(p) => {
            let names: Vec<&str> = p.iter().map(|t| t.name).collect();
            // A strand frame times every pass but the volume's and the LOD blend's (those run
            // for the volume and hybrid techniques) and ShortCut's (the PPLL held the frame),
            // in PASS_NAMES order.
            let strand_passes: Vec<&str> = PASS_NAMES
                .iter()
                .copied()
                .filter(|n| {
                    !n.starts_with("volume/")
                        && !n.starts_with("lod/")
                        && !n.starts_with("strands/shortcut")
                })
                .collect();
            assert_eq!(names, strand_passes);
            assert!(p.iter().all(|t| t.ms.is_finite() && t.ms >= 0.0));
        }
    }
    assert!(gpu.ppll.used > 0 && gpu.ppll.dropped == 0);
}

#[test]
fn deferred_statistics_arrive_without_blocking_render() {
    let Some(ctx) = common::gpu() else { return };
    let mut r =
        Renderer::new(&ctx, TargetFormats::default(), StrandSettings::default()).expect("renderer");
    r.set_stats_readback(StatsReadback::Deferred);
    let hair = r
        .upload_hair(&ctx, &common::layer_strands(&[(0.0, Vec3::ONE, 0.5)]))
        .expect("hair");
    let t = OffscreenTargets::new(&ctx, [SIZE, SIZE], COLOR_FORMAT).expect("targets");
    let mut reported = None;
    for _ in 0..8 {
        let stats = r
            .render(&ctx, &t.targets(), &inputs(Some(&hair), None, &[]))
            .expect("frame");
        if let Some(gpu) = stats.gpu {
            assert!(
                gpu.frame < stats.frame,
                "a deferred report is of an earlier frame"
            );
            reported = Some(gpu);
            break;
        }
        ctx.wait_idle().expect("idle");
    }
    let gpu = reported.expect("a report arrives within a few frames");
    assert!(gpu.ppll.used > 0);
}

#[test]
fn renders_into_an_srgb_target() {
    let Some(ctx) = common::gpu() else { return };
    let format = wgpu::TextureFormat::Rgba8UnormSrgb;
    let settings = StrandSettings {
        alpha: 1.0,
        coverage: false,
        width_px: 24.0,
        ..Default::default()
    };
    let mut r = Renderer::new(&ctx, TargetFormats { color: format }, settings).expect("renderer");
    let hair = r
        .upload_hair(
            &ctx,
            &common::layer_strands(&[(0.0, Vec3::new(0.5, 0.25, 1.0), 1.0)]),
        )
        .expect("hair");
    let t = OffscreenTargets::new(&ctx, [SIZE, SIZE], format).expect("targets");
    r.render(&ctx, &t.targets(), &inputs(Some(&hair), None, &[]))
        .expect("frame");
    let p = read_texture(&ctx, &t.color)
        .expect("readback")
        .get(SIZE / 2, SIZE / 2)
        .expect("pixel");
    for (got, want) in p.iter().zip([0.5, 0.25, 1.0, 1.0]) {
        assert!((got - want).abs() < 0.01, "{p:?}");
    }
}

#[test]
fn readback_writes_png_and_exr() {
    let Some(ctx) = common::gpu() else { return };
    let mut r =
        Renderer::new(&ctx, TargetFormats::default(), StrandSettings::default()).expect("renderer");
    let t = OffscreenTargets::new(&ctx, [SIZE, SIZE / 2], COLOR_FORMAT).expect("targets");
    let mut frame = inputs(None, None, &[]);
    frame.shared.camera.viewport = [SIZE, SIZE / 2];
    frame.shared.clear = Some(wgpu::Color {
        r: 0.25,
        g: 0.5,
        b: 2.0,
        a: 1.0,
    });
    r.render(&ctx, &t.targets(), &frame).expect("frame");
    let img = read_texture(&ctx, &t.color).expect("readback");
    assert_eq!((img.width, img.height), (SIZE, SIZE / 2));
    assert_eq!(img.get(SIZE - 1, SIZE / 2 - 1), Some([0.25, 0.5, 2.0, 1.0]));

    let dir = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR"));
    let exr = dir.join("readback.exr");
    img.save_exr(&exr).expect("exr");
    let back = image::open(&exr).expect("reads").to_rgba32f();
    assert_eq!(back.dimensions(), (SIZE, SIZE / 2));
    assert_eq!(
        back.get_pixel(3, 3).0,
        [0.25, 0.5, 2.0, 1.0],
        "EXR keeps linear HDR values"
    );

    let png = dir.join("readback.png");
    img.save_png(&png).expect("png");
    let back = image::open(&png).expect("reads").to_rgba8();
    // sRGB encoding of 0.25 and 0.5; 2.0 clamps to 1.
    assert_eq!(back.get_pixel(3, 3).0, [137, 188, 255, 255]);
}
