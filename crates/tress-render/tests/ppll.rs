//! PPLL build + resolve against the CPU composite (`tress_shading::resolve_k_buffer`), and the
//! node pool's overflow accounting and growth (design rule 8).

mod common;

use common::layers::{BACKGROUND, assert_close, layers};

use glam::Vec3;
use tress_render::{
    COLOR_FORMAT, FrameInputs, FrameStats, LinearImage, Material, OffscreenTargets, Renderer,
    SharedInputs, StrandSettings, TargetFormats, read_texture,
};
use tress_shading::{StrandFragment, resolve_k_buffer};

const SIZE: u32 = 64;

/// Render the layers with flat colors (no lights, white ambient: the fragment color is the vertex
/// color), no coverage, full strand alpha; returns the image and the stats.
fn render_layers(
    ctx: &tress_render::GpuContext,
    layers: &[(f32, Vec3, f32)],
    settings: StrandSettings,
    frames: usize,
    clear: bool,
) -> (LinearImage, Vec<FrameStats>) {
    let mut renderer = Renderer::new(ctx, TargetFormats::default(), settings).expect("renderer");
    let hair = renderer
        .upload_hair(ctx, &common::layer_strands(layers))
        .expect("upload");
    let targets = OffscreenTargets::new(ctx, [SIZE, SIZE], COLOR_FORMAT).expect("targets");
    let inputs = FrameInputs {
        shared: SharedInputs {
            camera: common::ortho_camera(SIZE),
            lights: &[],
            ambient: Vec3::ONE,
            head: None,
            clear: clear.then_some(wgpu::Color {
                r: f64::from(BACKGROUND.x),
                g: f64::from(BACKGROUND.y),
                b: f64::from(BACKGROUND.z),
                a: 1.0,
            }),
        },
        material: Material::default(),
        hair: Some(&hair),
        objects: &[],
    };
    let stats = (0..frames)
        .map(|_| {
            if !clear {
                app_clear(ctx, &targets);
            }
            renderer
                .render(ctx, &targets.targets(), &inputs)
                .expect("frame")
        })
        .collect();
    (read_texture(ctx, &targets.color).expect("readback"), stats)
}

/// What an application drawing its own content first would do: clear color and depth itself.
fn app_clear(ctx: &tress_render::GpuContext, targets: &OffscreenTargets) {
    let mut enc = ctx.device.create_command_encoder(&Default::default());
    enc.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some("test/app/clear"),
        color_attachments: &[Some(wgpu::RenderPassColorAttachment {
            view: &targets.color_view,
            depth_slice: None,
            resolve_target: None,
            ops: wgpu::Operations {
                load: wgpu::LoadOp::Clear(wgpu::Color::BLACK),
                store: wgpu::StoreOp::Store,
            },
        })],
        depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
            view: &targets.depth_view,
            depth_ops: Some(wgpu::Operations {
                load: wgpu::LoadOp::Clear(1.0),
                store: wgpu::StoreOp::Store,
            }),
            stencil_ops: None,
        }),
        timestamp_writes: None,
        occlusion_query_set: None,
        multiview_mask: None,
    });
    ctx.queue.submit([enc.finish()]);
}

fn flat(width_px: f32, k: u32) -> StrandSettings {
    StrandSettings {
        oit: tress_render::strands::Oit::Ppll,
        width_px,
        k,
        alpha: 1.0,
        coverage: false,
        shadows: false,
        ..Default::default()
    }
}

fn expected(layers: &[(f32, Vec3, f32)], k: usize) -> Vec3 {
    let fragments: Vec<StrandFragment> = layers
        .iter()
        .map(|&(z, color, alpha)| StrandFragment {
            color,
            alpha,
            depth: common::ortho_depth(z),
        })
        .collect();
    resolve_k_buffer(&fragments, k, BACKGROUND)
}

#[test]
fn sorted_layers_match_cpu_composite() {
    let Some(ctx) = common::gpu() else { return };
    let l = layers(4);
    let (img, stats) = render_layers(&ctx, &l, flat(32.0, 16), 1, true);
    let want = expected(&l, 16);
    // Inside the ribbons (rows 16..48), away from their edges.
    for (x, y) in [(32, 32), (5, 25), (60, 40)] {
        assert_close(
            img.get(x, y).expect("in image"),
            want,
            4e-3,
            &format!("pixel {x},{y}"),
        );
    }
    // Outside: the background, untouched.
    assert_close(
        img.get(32, 4).expect("in image"),
        BACKGROUND,
        1e-3,
        "background",
    );
    let gpu = stats[0].gpu.as_ref().expect("stats are waited for");
    assert_eq!(gpu.ppll.dropped, 0);
    assert_eq!(
        gpu.ppll.used,
        4 * SIZE * 32,
        "one node per layer per covered pixel"
    );
}

#[test]
fn layers_beyond_k_use_the_order_independent_tail() {
    let Some(ctx) = common::gpu() else { return };
    let l = layers(6);
    let (img, _) = render_layers(&ctx, &l, flat(32.0, 2), 1, true);
    let want = expected(&l, 2);
    let exact = expected(&l, 16);
    assert!(
        (want - exact).abs().max_element() > 0.01,
        "the test must tell k = 2 from exact"
    );
    assert_close(img.get(20, 30).expect("in image"), want, 4e-3, "k = 2");
    let (img, _) = render_layers(&ctx, &l, flat(32.0, 16), 1, true);
    assert_close(img.get(20, 30).expect("in image"), exact, 4e-3, "k = 16");
}

#[test]
fn overflow_is_counted_and_pool_stays_within_its_cap() {
    let Some(ctx) = common::gpu() else { return };
    let capacity = 1000u32;
    let settings = StrandSettings {
        ppll_nodes_per_pixel: 0.01,
        ppll_max_bytes: u64::from(capacity) * tress_render::strands::NODE_BYTES,
        ..flat(32.0, 16)
    };
    let (_, stats) = render_layers(&ctx, &layers(4), settings, 2, true);
    let requested = 4 * SIZE * 32;
    // Frame 0 starts at 0.01 nodes per pixel, overflows, and is rendered again with the pool
    // grown to its cap, where it still overflows; frame 1 starts at the cap.
    for (s, attempts) in stats.iter().zip([2, 1]) {
        let gpu = s.gpu.as_ref().expect("stats are waited for");
        assert_eq!(s.attempts, attempts, "frame {}", s.frame);
        assert_eq!(gpu.ppll.capacity, capacity, "the cap holds");
        assert_eq!(gpu.ppll.used, capacity, "a full pool");
        assert!(gpu.ppll.dropped > 0);
        assert_eq!(gpu.ppll.dropped, requested - capacity);
        assert_eq!(gpu.ppll.requested, requested);
        assert_eq!(s.ppll_capacity, capacity);
        // The OIT report says the same: the PPLL lost exactly what did not fit.
        let oit = gpu.oit.expect("strands were drawn");
        assert_eq!((oit.fragments, oit.lost), (requested, requested - capacity));
    }
}

#[test]
fn pool_grows_after_a_frame_that_dropped_fragments() {
    let Some(ctx) = common::gpu() else { return };
    let settings = StrandSettings {
        ppll_nodes_per_pixel: 0.25,
        ..flat(32.0, 16)
    };
    let l = layers(4);
    // Drawn over the target's content: never repeated, the next frame grows.
    let (_, stats) = render_layers(&ctx, &l, settings.clone(), 2, false);
    let first = stats[0].gpu.as_ref().expect("stats");
    let second = stats[1].gpu.as_ref().expect("stats");
    assert_eq!(stats[0].attempts, 1);
    assert_eq!(first.ppll.capacity, SIZE * SIZE / 4);
    assert!(first.ppll.dropped > 0);
    assert!(second.ppll.capacity > first.ppll.capacity);
    assert_eq!(second.ppll.dropped, 0);
    // A clearing frame is rendered again at once and comes out complete.
    let (img, stats) = render_layers(&ctx, &l, settings, 1, true);
    let gpu = stats[0].gpu.as_ref().expect("stats");
    assert_eq!(stats[0].attempts, 2);
    assert_eq!(gpu.ppll.dropped, 0);
    assert_close(
        img.get(32, 32).expect("in image"),
        expected(&l, 16),
        4e-3,
        "after growth",
    );
}
