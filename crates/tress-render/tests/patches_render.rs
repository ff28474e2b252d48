//! GPU tests of the patch frame's behaviour: compositing of opaque and transparent parts, the
//! back-faces-first order, the front-face Z writes, the head drawn first, per-pass timestamps,
//! and the equivalence of the two schemes. Expected pixels are computed by hand from the
//! slides' scheme on scenes of full-screen quads under an orthographic camera.

mod common;

use glam::{Vec2, Vec3};
use tress_hair::patches::{HairTextures, PatchMesh, Texture};
use tress_render::gpu::{linear_to_srgb, srgb_to_linear};
use tress_render::patches::{PatchFrameInputs, PatchRenderer, PatchSettings, RenderScheme};
use tress_render::{
    COLOR_FORMAT, HeadGeometry, LinearImage, OffscreenTargets, SharedInputs, TargetFormats,
    TriMesh, read_texture,
};

const SIZE: u32 = 32;
const BASE: Vec3 = Vec3::new(0.8, 0.6, 0.4);
const BG: [f64; 3] = [0.1, 0.2, 0.3];
/// Alpha of the right half of the alpha texture (the left half is opaque).
const ALPHA_T: f32 = 0.25;
const TOL: f32 = 4e-3;

/// Full-screen quads, one per `(z, front, ao)` in index-buffer order: at depth `z`, facing the
/// camera (`front`) or away from it, with AO `ao`. `u` runs along x, `v` along y, the tangent
/// is +y.
fn mesh(quads: &[(f32, bool, f32)]) -> PatchMesh {
    let shifted: Vec<_> = quads.iter().map(|&(z, f, a)| (z, f, a, 0.0)).collect();
    mesh_shifted(&shifted)
}

/// [`mesh`] with each quad's `u` shifted by its fourth value.
fn mesh_shifted(quads: &[(f32, bool, f32, f32)]) -> PatchMesh {
    let (mut p, mut n, mut uv, mut ao, mut idx) = (vec![], vec![], vec![], vec![], vec![]);
    for &(z, front, a, du) in quads {
        let base = p.len() as u32;
        p.extend(
            [(-1.5, -1.5), (1.5, -1.5), (1.5, 1.5), (-1.5, 1.5)].map(|(x, y)| Vec3::new(x, y, z)),
        );
        uv.extend(
            [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)].map(|(u, v)| Vec2::new(u + du, v)),
        );
        let (normal, tri): (Vec3, [u32; 6]) = if front {
            (Vec3::Z, [0, 1, 2, 0, 2, 3])
        } else {
            (Vec3::NEG_Z, [0, 2, 1, 0, 3, 2])
        };
        n.extend([normal; 4]);
        ao.extend([a; 4]);
        idx.extend(tri.iter().map(|i| i + base));
    }
    let t = vec![Vec3::Y; p.len()];
    PatchMesh::new(p, n, t, uv, idx)
        .and_then(|m| m.with_ao(ao))
        .expect("valid mesh")
}

fn constant(w: u32, channels: u32, f: impl Fn(u32) -> Vec<f32>) -> Texture {
    let data = (0..w).flat_map(&f).collect();
    Texture {
        width: w,
        height: 1,
        channels,
        data,
    }
}

/// Base `BASE`; alpha 1 on the left half of `u`, `ALPHA_T` on the next quarter and 0 on the
/// last; shift 0.5, noise 1.
fn textures() -> HairTextures {
    let alpha = |x| match x {
        0..8 => 1.0,
        8..12 => ALPHA_T,
        _ => 0.0,
    };
    HairTextures {
        base: constant(16, 3, |_| BASE.to_array().to_vec()),
        alpha: constant(16, 1, |x| vec![alpha(x)]),
        spec_shift: constant(16, 1, |_| vec![0.5]),
        spec_noise: constant(16, 1, |_| vec![1.0]),
    }
}

/// The base color after the 8-bit sRGB texture round trip.
fn base_q() -> Vec3 {
    let q = |c: f32| srgb_to_linear((linear_to_srgb(c) * 255.0).round() / 255.0);
    Vec3::new(q(BASE.x), q(BASE.y), q(BASE.z))
}

struct Frame {
    image: LinearImage,
    stats: tress_render::PatchFrameStats,
}

/// Render `mesh` (sorted around `sort_center`) with ambient 1 and no lights, so a fragment's
/// straight color is `base · ao`.
fn render(
    scheme: RenderScheme,
    mesh: &PatchMesh,
    sort_center: Vec3,
    head: Option<&TriMesh>,
) -> Frame {
    let settings = PatchSettings {
        scheme,
        mipmaps: false,
        ..Default::default()
    };
    render_with(settings, mesh, sort_center, head)
}

fn render_with(
    settings: PatchSettings,
    mesh: &PatchMesh,
    sort_center: Vec3,
    head: Option<&TriMesh>,
) -> Frame {
    let ctx = common::gpu().expect("checked by the caller");
    let mut r = PatchRenderer::with_textures(&ctx, TargetFormats::default(), settings, textures())
        .expect("renderer");
    let geometry = r.upload_patches(&ctx, mesh, sort_center).expect("upload");
    let head = head.map(|h| HeadGeometry::new(&ctx, h).expect("head"));
    let t = OffscreenTargets::new(&ctx, [SIZE, SIZE], COLOR_FORMAT).expect("targets");
    let inputs = PatchFrameInputs {
        shared: SharedInputs {
            camera: common::ortho_camera(SIZE),
            lights: &[],
            ambient: Vec3::ONE,
            head: head.as_ref(),
            clear: Some(wgpu::Color {
                r: BG[0],
                g: BG[1],
                b: BG[2],
                a: 1.0,
            }),
        },
        head_color: Vec3::new(0.0, 1.0, 0.0),
        patches: Some(&geometry),
    };
    let stats = r.render(&ctx, &t.targets(), &inputs).expect("frame");
    let image = read_texture(&ctx, &t.color).expect("readback");
    Frame { image, stats }
}

/// `src` (straight, alpha `a`) over a premultiplied opaque `dst`.
fn over(src: Vec3, a: f32, dst: Vec3) -> Vec3 {
    src * a + dst * (1.0 - a)
}

fn bg() -> Vec3 {
    Vec3::new(BG[0] as f32, BG[1] as f32, BG[2] as f32)
}

#[track_caller]
fn assert_pixel(img: &LinearImage, x: u32, y: u32, expect: Vec3, what: &str) {
    let p = img.get(x, y).expect("inside");
    let got = Vec3::new(p[0], p[1], p[2]);
    assert!(
        (got - expect).abs().max_element() < TOL && (p[3] - 1.0).abs() < TOL,
        "{what}: pixel ({x}, {y}) is {p:?}, expected {expect}"
    );
}

/// Columns in the opaque, transparent and empty parts of the alpha texture (`u` = 0.34, 0.68
/// and 0.80: texels 5.5, 10.8 and 12.8, each one away from a change).
const OPAQUE_X: u32 = 8;
const TRANSPARENT_X: u32 = 24;
const EMPTY_X: u32 = 30;

#[test]
fn opaque_parts_hide_and_transparent_parts_blend_in_both_schemes() {
    if common::gpu().is_none() {
        return;
    }
    // Inner quad (z = 0, AO 0.25) under an outer quad (z = 0.5, AO 1), sorted inside out from
    // a centre behind them.
    let m = mesh(&[(0.0, true, 0.25), (0.5, true, 1.0)]);
    let b = base_q();
    for scheme in [RenderScheme::FourPass, RenderScheme::ThreePass] {
        let f = render(scheme, &m, Vec3::new(0.0, 0.0, -5.0), None);
        let y = SIZE / 2;
        // Opaque: only the nearest opaque fragment's color, once.
        assert_pixel(&f.image, OPAQUE_X, y, b, scheme.name());
        // Transparent: inner over the background, then outer over that.
        let inner = over(b * 0.25, ALPHA_T, bg());
        assert_pixel(
            &f.image,
            TRANSPARENT_X,
            y,
            over(b, ALPHA_T, inner),
            scheme.name(),
        );
        assert_eq!(f.stats.triangles, 4);
        assert_eq!(f.stats.scheme, scheme);
    }
}

#[test]
fn back_faces_are_blended_before_front_faces() {
    if common::gpu().is_none() {
        return;
    }
    // A back-facing quad in front (z = 0.5, AO 1) and a front-facing one behind it (z = 0,
    // AO 0.25); the front-facing one comes first in the sorted order. Pass "back" draws the
    // back face first without Z writes, then pass "front" blends the farther front face over it.
    let m = mesh(&[(0.0, true, 0.25), (0.5, false, 1.0)]);
    let b = base_q();
    for scheme in [RenderScheme::FourPass, RenderScheme::ThreePass] {
        let f = render(scheme, &m, Vec3::new(0.0, 0.0, -5.0), None);
        let back_first = over(b, ALPHA_T, bg());
        let expect = over(b * 0.25, ALPHA_T, back_first);
        assert_pixel(&f.image, TRANSPARENT_X, SIZE / 2, expect, scheme.name());
        // Opaque parts resolve by depth whatever the facing: the nearer back face wins.
        assert_pixel(&f.image, OPAQUE_X, SIZE / 2, b, scheme.name());
    }
}

#[test]
fn transparent_front_faces_write_depth() {
    if common::gpu().is_none() {
        return;
    }
    // Sorted around a centre in front of the quads, the nearer quad (z = 0.5, AO 1) is drawn
    // first; its transparent part writes depth in the last pass, so the farther quad drawn
    // after it (z = 0, AO 0.25) is rejected there.
    let m = mesh(&[(0.0, true, 0.25), (0.5, true, 1.0)]);
    let b = base_q();
    for scheme in [RenderScheme::FourPass, RenderScheme::ThreePass] {
        let f = render(scheme, &m, Vec3::new(0.0, 0.0, 5.0), None);
        assert_pixel(
            &f.image,
            TRANSPARENT_X,
            SIZE / 2,
            over(b, ALPHA_T, bg()),
            scheme.name(),
        );
    }
}

#[test]
fn min_alpha_keeps_empty_parts_from_hiding_later_patches() {
    if common::gpu().is_none() {
        return;
    }
    // As above, the nearer quad (AO 1) is drawn first; at EMPTY_X it is empty (alpha 0), while
    // the farther quad (AO 0.25), its u shifted, is transparent there.
    let m = mesh_shifted(&[(0.0, true, 0.25, -0.2), (0.5, true, 1.0, 0.0)]);
    let b = base_q();
    for scheme in [RenderScheme::FourPass, RenderScheme::ThreePass] {
        let paper = PatchSettings {
            scheme,
            mipmaps: false,
            ..Default::default()
        };
        // The slides' schemes: the empty fragment writes depth and hides the farther quad.
        let f = render_with(paper.clone(), &m, Vec3::new(0.0, 0.0, 5.0), None);
        assert_pixel(&f.image, EMPTY_X, SIZE / 2, bg(), scheme.name());
        // With min_alpha it is dropped, and the farther quad shows.
        let option = PatchSettings {
            min_alpha: 0.1,
            ..paper
        };
        let f = render_with(option, &m, Vec3::new(0.0, 0.0, 5.0), None);
        let expect = over(b * 0.25, ALPHA_T, bg());
        assert_pixel(&f.image, EMPTY_X, SIZE / 2, expect, scheme.name());
        // Transparent parts above min_alpha are unchanged: near over the background only.
        assert_pixel(
            &f.image,
            TRANSPARENT_X,
            SIZE / 2,
            over(b, ALPHA_T, bg()),
            scheme.name(),
        );
    }
}

#[test]
fn the_head_is_drawn_first_and_hides_the_hair_behind_it() {
    if common::gpu().is_none() {
        return;
    }
    let head = TriMesh::uv_sphere(Vec3::new(0.0, 0.0, 1.0), 0.5, 16, 24);
    let m = mesh(&[(0.0, true, 1.0)]);
    for scheme in [RenderScheme::FourPass, RenderScheme::ThreePass] {
        let f = render(scheme, &m, Vec3::new(0.0, 0.0, -5.0), Some(&head));
        // Centre: the head (ambient 1, green); left: the opaque hair.
        assert_pixel(&f.image, SIZE / 2, SIZE / 2, Vec3::Y, scheme.name());
        assert_pixel(&f.image, 2, SIZE / 2, base_q(), scheme.name());
    }
}

#[test]
fn every_pass_of_the_scheme_is_timed() {
    let Some(ctx) = common::gpu() else {
        return;
    };
    if !ctx.caps.timestamps {
        eprintln!("the adapter has no timestamp queries; nothing to check");
        return;
    }
    let m = mesh(&[(0.0, true, 1.0)]);
    for scheme in [RenderScheme::FourPass, RenderScheme::ThreePass] {
        let f = render(scheme, &m, Vec3::ZERO, None);
        let Some(tress_render::Timings::Passes(p)) = &f.stats.timings else {
            panic!("{}: no timings: {:?}", scheme.name(), f.stats.timings);
        };
        let names: Vec<&str> = p.iter().map(|t| t.name).collect();
        let mut expect = vec!["head"];
        expect.extend(scheme.passes().iter().map(|p| p.name));
        assert_eq!(names, expect, "{}", scheme.name());
        assert!(p.iter().all(|t| t.ms >= 0.0 && t.ms.is_finite()));
        assert_eq!(f.stats.gpu_frame, Some(f.stats.frame));
    }
}

#[test]
fn bad_inputs_are_errors_not_panics() {
    let Some(ctx) = common::gpu() else {
        return;
    };
    let mut r = PatchRenderer::with_textures(
        &ctx,
        TargetFormats::default(),
        PatchSettings::default(),
        textures(),
    )
    .expect("renderer");
    let t = OffscreenTargets::new(&ctx, [SIZE, SIZE], COLOR_FORMAT).expect("targets");
    let inputs = PatchFrameInputs {
        shared: SharedInputs {
            camera: common::ortho_camera(SIZE + 1),
            lights: &[],
            ambient: Vec3::ZERO,
            head: None,
            clear: None,
        },
        head_color: Vec3::ONE,
        patches: None,
    };
    assert!(r.render(&ctx, &t.targets(), &inputs).is_err());
    let lights = [tress_render::DirectionalLight::default(); 5];
    let inputs = PatchFrameInputs {
        shared: SharedInputs {
            camera: common::ortho_camera(SIZE),
            lights: &lights,
            ..inputs.shared
        },
        ..inputs
    };
    assert!(r.render(&ctx, &t.targets(), &inputs).is_err());
    let inputs = PatchFrameInputs {
        shared: SharedInputs {
            lights: &[],
            ambient: Vec3::NAN,
            ..inputs.shared
        },
        ..inputs
    };
    assert!(r.render(&ctx, &t.targets(), &inputs).is_err());
    // A texture with the wrong channel count is refused.
    let mut bad = textures();
    bad.alpha.channels = 3;
    assert!(r.set_textures(&ctx, bad).is_err());
    let bad_settings = PatchSettings {
        alpha_ref: 2.0,
        ..Default::default()
    };
    assert!(r.set_settings(&ctx, bad_settings).is_err());
    // Switching the scheme rebuilds the pipelines and renders (an empty frame here).
    let s = PatchSettings {
        scheme: RenderScheme::ThreePass,
        ..r.settings().clone()
    };
    r.set_settings(&ctx, s).expect("3-pass");
    let inputs = PatchFrameInputs {
        shared: SharedInputs {
            ambient: Vec3::ZERO,
            ..inputs.shared
        },
        ..inputs
    };
    let stats = r.render(&ctx, &t.targets(), &inputs).expect("empty frame");
    assert_eq!(
        (stats.triangles, stats.scheme),
        (0, RenderScheme::ThreePass)
    );
}

/// With deferred readback (the viewer's), a patch frame never waits for its own results: it
/// reports the newest earlier frame whose results arrived (read before it is submitted), as
/// every technique does through the shared frame services.
#[test]
fn deferred_patch_frames_report_an_earlier_frame() {
    let Some(ctx) = common::gpu() else {
        return;
    };
    let mut r = PatchRenderer::with_textures(
        &ctx,
        TargetFormats::default(),
        PatchSettings::default(),
        textures(),
    )
    .expect("renderer");
    let geometry = r
        .upload_patches(&ctx, &mesh(&[(0.0, true, 1.0)]), Vec3::ZERO)
        .expect("upload");
    let t = OffscreenTargets::new(&ctx, [SIZE, SIZE], COLOR_FORMAT).expect("targets");
    let inputs = PatchFrameInputs {
        shared: SharedInputs {
            camera: common::ortho_camera(SIZE),
            lights: &[],
            ambient: Vec3::ONE,
            head: None,
            clear: Some(wgpu::Color::BLACK),
        },
        head_color: Vec3::ONE,
        patches: Some(&geometry),
    };
    // Waiting (the default): the frame reports itself.
    let waited = r.render(&ctx, &t.targets(), &inputs).expect("frame");
    assert_eq!(waited.gpu_frame, Some(waited.frame));
    r.set_stats_readback(tress_render::StatsReadback::Deferred);
    let first = r.render(&ctx, &t.targets(), &inputs).expect("frame");
    assert!(
        first.gpu_frame.is_none_or(|g| g < first.frame),
        "a deferred frame waited for itself: {first:?}"
    );
    // Once the GPU is idle, a later frame reports an earlier one. (Tests share the device, and
    // another test's poll may run this frame's map callback a moment later, so a few tries.)
    let mut next = first.clone();
    for _ in 0..8 {
        ctx.wait_idle().expect("idle");
        next = r.render(&ctx, &t.targets(), &inputs).expect("frame");
        if next.gpu_frame.is_some() {
            break;
        }
    }
    let g = next.gpu_frame.expect("the earlier frames' results arrived");
    assert!(g >= first.frame && g < next.frame, "{next:?}");
    assert_eq!(next.timings.is_some(), next.gpu_frame.is_some());
}
