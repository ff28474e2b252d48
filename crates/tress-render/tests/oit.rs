//! The strand rasterizer's OIT beyond the paper's single-binding PPLL: ShortCut against its CPU
//! composite (`tress_shading::resolve_shortcut`), a PPLL node pool spread over several storage
//! bindings, the per-frame choice (`strands.oit = "auto"`) that never loses a fragment offline,
//! and the exact `lost` counter.

mod common;

use common::layers::{BACKGROUND, LAYERS, assert_close, layers};

use glam::Vec3;
use tress_render::strands::{NODE_BYTES, NODE_CHUNKS, Oit, OitKind};
use tress_render::{
    COLOR_FORMAT, FrameInputs, FrameStats, GpuContext, LinearImage, Material, OffscreenTargets,
    Renderer, SharedInputs, StrandSettings, TargetFormats, read_texture,
};
use tress_shading::{ShortcutFragment, StrandFragment, resolve_k_buffer, resolve_shortcut};

const SIZE: u32 = 64;

/// Flat colors (no lights, white ambient), no coverage, full strand alpha, 32 px ribbons across
/// rows 16..48.
fn flat(oit: Oit) -> StrandSettings {
    StrandSettings {
        oit,
        width_px: 32.0,
        alpha: 1.0,
        coverage: false,
        shadows: false,
        ..Default::default()
    }
}

fn render(
    ctx: &GpuContext,
    settings: StrandSettings,
    frames: usize,
) -> (LinearImage, Vec<FrameStats>) {
    let (img, stats, _) = render_keep(ctx, settings, frames);
    (img, stats)
}

/// [`render`], keeping the renderer (and its PPLL lists).
fn render_keep(
    ctx: &GpuContext,
    settings: StrandSettings,
    frames: usize,
) -> (LinearImage, Vec<FrameStats>, Renderer) {
    let mut renderer = Renderer::new(ctx, TargetFormats::default(), settings).expect("renderer");
    let hair = renderer
        .upload_hair(ctx, &common::layer_strands(&layers(LAYERS.len())))
        .expect("upload");
    let targets = OffscreenTargets::new(ctx, [SIZE, SIZE], COLOR_FORMAT).expect("targets");
    let inputs = FrameInputs {
        shared: SharedInputs {
            camera: common::ortho_camera(SIZE),
            lights: &[],
            ambient: Vec3::ONE,
            head: None,
            clear: Some(wgpu::Color {
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
            renderer
                .render(ctx, &targets.targets(), &inputs)
                .expect("frame")
        })
        .collect();
    let img = read_texture(ctx, &targets.color).expect("readback");
    (img, stats, renderer)
}

fn fragments() -> Vec<StrandFragment> {
    layers(LAYERS.len())
        .iter()
        .map(|&(z, color, alpha)| StrandFragment {
            color,
            alpha,
            depth: common::ortho_depth(z),
        })
        .collect()
}

/// Fragments the layers make: 6 layers over 64 x 32 pixels.
const LAYER_FRAGMENTS: u32 = 6 * SIZE * 32;

#[test]
fn shortcut_matches_its_cpu_composite_for_every_k() {
    let Some(ctx) = common::gpu() else { return };
    for k in [1, 2, 4, 6, 8] {
        let settings = StrandSettings {
            shortcut_k: k,
            ..flat(Oit::Shortcut)
        };
        let (img, stats) = render(&ctx, settings, 1);
        // Layer `i` is strand `i` (the tail roulette's number).
        let on_strands: Vec<ShortcutFragment> = (0u32..)
            .zip(fragments())
            .map(|(strand, fragment)| ShortcutFragment { fragment, strand })
            .collect();
        let want = resolve_shortcut(&on_strands, k as usize, BACKGROUND);
        for (x, y) in [(32, 32), (5, 25), (60, 40)] {
            // RGB9E5 colors and a half-float transmittance.
            assert_close(
                img.get(x, y).expect("in"),
                want,
                4e-3,
                &format!("k {k} at {x},{y}"),
            );
        }
        assert_close(img.get(32, 4).expect("in"), BACKGROUND, 1e-3, "background");
        let oit = stats[0]
            .gpu
            .as_ref()
            .and_then(|g| g.oit)
            .expect("oit stats");
        assert_eq!(oit.kind, OitKind::Shortcut);
        assert_eq!((oit.fragments, oit.lost), (LAYER_FRAGMENTS, 0));
        assert_eq!(
            oit.bytes,
            tress_render::strands::shortcut_bytes([SIZE, SIZE], k)
        );
        assert_eq!(stats[0].attempts, 1);
    }
    // With every layer stored ShortCut is exact sorted compositing, the PPLL's result.
    let (img, _) = render(&ctx, flat(Oit::Shortcut), 1);
    let exact = resolve_k_buffer(&fragments(), 16, BACKGROUND);
    assert_close(
        img.get(20, 30).expect("in"),
        exact,
        4e-3,
        "k = 8 >= 6 layers",
    );
}

#[test]
fn shortcut_and_ppll_count_the_same_fragments() {
    let Some(ctx) = common::gpu() else { return };
    let (_, p) = render(&ctx, flat(Oit::Ppll), 1);
    let (_, s) = render(&ctx, flat(Oit::Shortcut), 1);
    let p = p[0].gpu.as_ref().and_then(|g| g.oit).expect("ppll");
    let s = s[0].gpu.as_ref().and_then(|g| g.oit).expect("shortcut");
    assert_eq!(p.kind, OitKind::Ppll);
    assert_eq!(p.fragments, LAYER_FRAGMENTS);
    assert_eq!(s.fragments, p.fragments);
    assert_eq!((p.lost, s.lost), (0, 0));
}

/// The context with storage bindings limited to `nodes` PPLL nodes, so small frames exercise a
/// pool spread over several bindings (the device itself allows more).
fn small_bindings(ctx: &GpuContext, nodes: u64) -> GpuContext {
    let mut c = ctx.clone();
    c.caps.max_storage_binding = nodes * NODE_BYTES;
    c
}

#[test]
fn a_pool_over_several_bindings_composites_like_one() {
    let Some(ctx) = common::gpu() else { return };
    // 12,288 fragments over bindings of 4,096 nodes: three chunks written and read.
    let ctx = small_bindings(&ctx, 4096);
    let (img, stats) = render(&ctx, flat(Oit::Ppll), 1);
    let gpu = stats[0].gpu.as_ref().expect("stats");
    assert_eq!(gpu.ppll.dropped, 0);
    assert!(gpu.ppll.capacity > 2 * 4096, "{}", gpu.ppll.capacity);
    let want = resolve_k_buffer(&fragments(), 16, BACKGROUND);
    for (x, y) in [(0, 16), (32, 32), (63, 47)] {
        assert_close(img.get(x, y).expect("in"), want, 4e-3, &format!("{x},{y}"));
    }
}

#[test]
fn the_lists_read_back_over_several_bindings_are_the_layers_drawn() {
    let Some(ctx) = common::gpu() else { return };
    let ctx = small_bindings(&ctx, 4096);
    let (img, _, renderer) = render_keep(&ctx, flat(Oit::Ppll), 1);
    let lists = renderer
        .ppll_fragments(&ctx)
        .expect("readback")
        .expect("a PPLL frame");
    assert_eq!(lists.fragments.len(), LAYER_FRAGMENTS as usize);
    let mut want = fragments();
    want.sort_by(|a, b| a.depth.total_cmp(&b.depth));
    for (x, y) in [(0, 16), (32, 32), (63, 47)] {
        let mut got = lists.pixel(x, y).to_vec();
        got.sort_by(|a, b| a.depth.total_cmp(&b.depth));
        assert_eq!(got.len(), want.len(), "{x},{y}");
        for (g, w) in got.iter().zip(&want) {
            // Colors through RGB9E5 (9 bits relative to the largest channel).
            assert!(
                (g.color - w.color).abs().max_element() < 4e-3,
                "{g:?} vs {w:?}"
            );
            assert!((g.alpha - w.alpha).abs() < 1e-6 && (g.depth - w.depth).abs() < 1e-5);
        }
    }
    assert!(lists.pixel(32, 4).is_empty(), "no hair above the layers");
    // All six layers fit the k = 16 resolve: sorting exactly changes nothing.
    let mut sorted = img.clone();
    lists.sort_exactly(&mut sorted, 16);
    let diff = sorted
        .pixels
        .iter()
        .zip(&img.pixels)
        .flat_map(|(a, b)| a.iter().zip(b).map(|(x, y)| (x - y).abs()))
        .fold(0f32, f32::max);
    assert!(diff < 1e-6, "{diff}");
}

#[test]
fn the_pool_never_exceeds_its_bindings_and_counts_what_it_loses() {
    let Some(ctx) = common::gpu() else { return };
    // Four bindings of 1,024 nodes hold 4,096 of the 12,288 fragments (the 16 KiB head buffer
    // of the 64² target still fits one binding).
    let per_chunk = 1024u32;
    let ctx = small_bindings(&ctx, u64::from(per_chunk));
    let (_, stats) = render(&ctx, flat(Oit::Ppll), 1);
    let cap = per_chunk * NODE_CHUNKS as u32;
    let gpu = stats[0].gpu.as_ref().expect("stats");
    assert_eq!(gpu.ppll.capacity, cap);
    let oit = gpu.oit.expect("oit");
    assert_eq!(
        (oit.fragments, oit.lost),
        (LAYER_FRAGMENTS, LAYER_FRAGMENTS - cap)
    );
}

#[test]
fn auto_switches_to_shortcut_when_the_pool_cannot_hold_the_frame() {
    let Some(ctx) = common::gpu() else { return };
    let settings = StrandSettings {
        ppll_nodes_per_pixel: 0.5,
        ppll_max_bytes: 1000 * NODE_BYTES,
        ..flat(Oit::Auto)
    };
    let (img, stats) = render(&ctx, settings.clone(), 2);
    // Frame 0: the PPLL loses fragments, its cap cannot hold them, so the frame is drawn again
    // with ShortCut; frame 1 starts with ShortCut.
    for (s, attempts) in stats.iter().zip([2, 1]) {
        let oit = s.gpu.as_ref().and_then(|g| g.oit).expect("oit");
        assert_eq!(s.attempts, attempts, "frame {}", s.frame);
        assert_eq!(oit.kind, OitKind::Shortcut);
        assert_eq!((oit.fragments, oit.lost), (LAYER_FRAGMENTS, 0));
    }
    let (shortcut, _) = render(&ctx, flat(Oit::Shortcut), 1);
    assert_eq!(img, shortcut, "auto's frame is ShortCut's frame");
    // A cap that holds the frame keeps the paper's PPLL (grown, drawn again once).
    let (img, stats) = render(
        &ctx,
        StrandSettings {
            ppll_max_bytes: 64 << 20,
            ..settings
        },
        1,
    );
    let oit = stats[0].gpu.as_ref().and_then(|g| g.oit).expect("oit");
    assert_eq!(
        (oit.kind, oit.lost, stats[0].attempts),
        (OitKind::Ppll, 0, 2)
    );
    let (ppll, _) = render(&ctx, flat(Oit::Ppll), 1);
    assert_eq!(img, ppll);
}

/// The PPLL's resolve counts the fragments it merges behind each pixel's `k` nearest, and `auto`
/// leaves the PPLL for ShortCut when most of a frame is that unsorted tail.
#[test]
fn auto_leaves_the_ppll_when_most_fragments_fall_into_its_tail() {
    let Some(ctx) = common::gpu() else { return };
    let layers = LAYERS.len() as u32;
    for k in [1, 2, 4, 6, 8] {
        let (_, stats) = render(
            &ctx,
            StrandSettings {
                k,
                ..flat(Oit::Ppll)
            },
            1,
        );
        let oit = stats[0].gpu.as_ref().and_then(|g| g.oit).expect("oit");
        assert_eq!(oit.kind, OitKind::Ppll);
        assert_eq!(oit.tail, layers.saturating_sub(k) * SIZE * 32, "k = {k}");
    }
    // k = 1: 5 of the 6 layers (83%) are the tail, so the frame is drawn again with ShortCut,
    // and the next frame (as many fragments) stays with it.
    let (img, stats) = render(
        &ctx,
        StrandSettings {
            k: 1,
            ..flat(Oit::Auto)
        },
        2,
    );
    for (s, attempts) in stats.iter().zip([2, 1]) {
        let oit = s.gpu.as_ref().and_then(|g| g.oit).expect("oit");
        assert_eq!(
            (oit.kind, oit.tail, s.attempts),
            (OitKind::Shortcut, 0, attempts),
            "frame {}",
            s.frame
        );
    }
    let (shortcut, _) = render(&ctx, flat(Oit::Shortcut), 1);
    assert_eq!(img, shortcut, "auto's frame is ShortCut's frame");
    // k = 2: 4 of 6 (67%) are the tail, under the 75% share: the paper's PPLL stays.
    let (_, stats) = render(
        &ctx,
        StrandSettings {
            k: 2,
            ..flat(Oit::Auto)
        },
        1,
    );
    let oit = stats[0].gpu.as_ref().and_then(|g| g.oit).expect("oit");
    assert_eq!((oit.kind, stats[0].attempts), (OitKind::Ppll, 1));
    // (The two frames sit either side of the share.)
    const {
        assert!(tress_render::strands::oit::AUTO_TAIL_SHARE > 4.0 / 6.0);
        assert!(tress_render::strands::oit::AUTO_TAIL_SHARE < 5.0 / 6.0);
    }
}

/// Mean FLIP between two frames (8-bit sRGB).
fn mean_flip(a: &image::RgbImage, b: &image::RgbImage) -> f32 {
    let flip = nv_flip::flip(
        nv_flip::FlipImageRgb8::with_data(a.width(), a.height(), a),
        nv_flip::FlipImageRgb8::with_data(b.width(), b.height(), b),
        nv_flip::DEFAULT_PIXELS_PER_DEGREE,
    );
    nv_flip::FlipPool::from_image(&flip).mean()
}

#[test]
fn a_frame_beyond_a_16_mib_pool_comes_out_complete_with_shortcut() {
    let Some(ctx) = common::gpu() else { return };
    // 24,000 strands on the sphere head, 4 px ribbons at 256²: about 5M fragments, five times
    // what a 16 MiB pool (1M nodes) holds.
    let hair_asset = common::sphere_hair(1.0, 24_000, 12);
    let lights = [tress_render::DirectionalLight::default()];
    // The frame, its OIT statistics and (with `exact`) the frame as exact sorted compositing
    // draws it: the PPLL's lists read back and sorted on the CPU.
    let frame = |settings: StrandSettings, exact: bool| {
        let k = settings.k as usize;
        let mut r = Renderer::new(&ctx, TargetFormats::default(), settings).expect("renderer");
        let hair = r.upload_hair(&ctx, &hair_asset).expect("hair");
        let head = common::sphere_head(&ctx);
        let t = OffscreenTargets::new(&ctx, [256, 256], COLOR_FORMAT).expect("targets");
        let camera = tress_render::Camera::look_at(
            Vec3::new(2.6, 1.2, 4.4),
            Vec3::new(0.0, -0.45, 0.0),
            Vec3::Y,
            45f32.to_radians(),
            0.1,
            20.0,
            [256, 256],
        );
        let inputs = FrameInputs {
            shared: SharedInputs {
                camera,
                lights: &lights,
                ambient: Vec3::splat(0.06),
                head: Some(&head),
                clear: Some(common::BACKGROUND),
            },
            material: Material::default(),
            hair: Some(&hair),
            objects: &[],
        };
        let stats = r.render(&ctx, &t.targets(), &inputs).expect("frame");
        let oit = stats.gpu.as_ref().and_then(|g| g.oit).expect("oit");
        let mut img = read_texture(&ctx, &t.color).expect("readback");
        if exact {
            let f = r.ppll_fragments(&ctx).expect("readback").expect("lists");
            assert_eq!(
                f.fragments.len(),
                oit.fragments as usize,
                "every fragment read back"
            );
            f.sort_exactly(&mut img, k);
        }
        let rgb = image::DynamicImage::ImageRgba8(img.to_srgb8()).to_rgb8();
        (rgb, oit)
    };
    let base = StrandSettings {
        width_px: 4.0,
        ..common::sphere_strand_settings()
    };
    let mib16 = 16u64 << 20;
    let ppll = StrandSettings {
        oit: Oit::Ppll,
        ..base.clone()
    };
    let (exact_img, exact) = frame(ppll.clone(), true);
    assert_eq!((exact.kind, exact.lost), (OitKind::Ppll, 0));
    assert!(
        exact.fragments as u64 * NODE_BYTES > 2 * mib16,
        "the frame must overflow a 16 MiB pool: {} fragments",
        exact.fragments
    );
    let (paper, _) = frame(ppll.clone(), false);
    let (auto, a) = frame(
        StrandSettings {
            ppll_max_bytes: mib16,
            ..base.clone()
        },
        false,
    );
    assert_eq!(
        (a.kind, a.lost, a.fragments),
        (OitKind::Shortcut, 0, exact.fragments)
    );
    let (lossy, l) = frame(
        StrandSettings {
            ppll_max_bytes: mib16,
            ..ppll
        },
        false,
    );
    assert!(l.lost > 0 && l.lost == l.fragments - (mib16 / NODE_BYTES) as u32);
    let shortcut_error = mean_flip(&auto, &exact_img);
    let paper_error = mean_flip(&paper, &exact_img);
    let lossy_error = mean_flip(&lossy, &exact_img);
    eprintln!(
        "mean FLIP vs exact sorting: shortcut k = {} {shortcut_error:.4}, complete PPLL k = 16 \
         {paper_error:.4}, 16 MiB PPLL {lossy_error:.4}",
        base.shortcut_k
    );
    // A frame denser than the paper's scenes (about 75 fragments a covered pixel; the ponytail
    // at 1280x720 has 19 a pixel). Measured here: ShortCut 0.0099 at k = 8 (seven layers and
    // the threshold; 0.0126 at k = 7), the complete PPLL at k = 16 0.0070, the lossy PPLL 0.26.
    assert!(shortcut_error < 0.011, "{shortcut_error}");
    assert!(
        lossy_error > 10.0 * shortcut_error,
        "the test tells a lossy frame apart"
    );
}
