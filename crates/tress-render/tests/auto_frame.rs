//! Auto-framing of hair files at any unit and aspect: the same asset in metres, centimetres and
//! "hundreds" fills 60–100% of a landscape and a portrait frame along the axis that limits it, and the three
//! frames agree, shadows included (the world-unit defaults follow the asset's unit:
//! `scene_setup::unit_scale`).

mod common;

use glam::{Affine3A, Vec3};
use tress_hair::generate::{Style, StyleParams, generate};
use tress_render::session::{Session, SessionOptions, scene_from_inputs};
use tress_render::{COLOR_FORMAT, GpuContext, LinearImage, OffscreenTargets, TargetFormats};

/// A straight style of 600 strands scaled by `scale`, written as a Cem Yuksel `.hair` file.
fn hair_file(scale: f32) -> std::path::PathBuf {
    let style = Style::Straight;
    let params = StyleParams {
        strands: 600,
        vertices: 12,
        ..style.default_params()
    };
    let mut hair = generate(style, &params).expect("hair");
    hair.transform(Affine3A::from_scale(Vec3::splat(scale)))
        .expect("scaled");
    let dir = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("auto_frame");
    std::fs::create_dir_all(&dir).expect("tmp dir");
    let path = dir.join(format!("straight_{scale}.hair"));
    tress_hair::formats::write_path(&path, &hair).expect("write");
    path
}

fn render(ctx: &GpuContext, scale: f32, size: [u32; 2]) -> LinearImage {
    let (scene, auto_frame) = scene_from_inputs(&[hair_file(scale)]).expect("scene");
    assert!(auto_frame);
    let options = SessionOptions {
        auto_frame,
        overrides: vec![
            format!("output.width={}", size[0]),
            format!("output.height={}", size[1]),
        ],
        ..SessionOptions::default()
    };
    let mut s = Session::new(ctx, TargetFormats::default(), scene, options).expect("session");
    let targets = OffscreenTargets::new(ctx, size, COLOR_FORMAT).expect("targets");
    let camera = s.camera(size);
    s.render(ctx, &targets.targets(), &camera, None)
        .expect("frame");
    tress_render::read_texture(ctx, &targets.color).expect("readback")
}

/// How much of the frame the hair fills along the axis that limits it: the larger of its
/// extents over the width and over the height.
fn fill(img: &LinearImage, background: [f32; 4]) -> f32 {
    let (w, h) = (img.width as usize, img.height as usize);
    let (mut lo, mut hi) = ([usize::MAX; 2], [0usize; 2]);
    for y in 0..h {
        for x in 0..w {
            let p = img.pixels[y * w + x];
            if (0..3).any(|c| (p[c] - background[c]).abs() > 0.02) {
                for (a, v) in [x, y].into_iter().enumerate() {
                    lo[a] = lo[a].min(v);
                    hi[a] = hi[a].max(v);
                }
            }
        }
    }
    if lo[0] > hi[0] {
        return 0.0;
    }
    let extent = |a: usize, n: usize| (hi[a] - lo[a] + 1) as f32 / n as f32;
    extent(0, w).max(extent(1, h))
}

fn mean_abs(a: &LinearImage, b: &LinearImage) -> f32 {
    let sum: f32 = a
        .pixels
        .iter()
        .zip(&b.pixels)
        .map(|(p, q)| (0..3).map(|c| (p[c] - q[c]).abs()).sum::<f32>() / 3.0)
        .sum();
    sum / a.pixels.len() as f32
}

#[test]
fn an_asset_at_any_unit_and_aspect_fills_the_frame_and_looks_the_same() {
    let Some(ctx) = common::gpu() else { return };
    let (scene, _) = scene_from_inputs(&[hair_file(1.0)]).expect("scene");
    let bg = scene.background;
    let background = [bg.x, bg.y, bg.z, 1.0];
    for size in [[96, 54], [54, 96]] {
        let unit = render(&ctx, 1.0, size);
        let filled = fill(&unit, background);
        assert!(
            (0.6..=1.0).contains(&filled),
            "{size:?}: the hair fills {filled} of the frame"
        );
        // Shadows are on: the frame differs from the same frame without them.
        for scale in [0.01, 100.0] {
            let other = render(&ctx, scale, size);
            let fill_other = fill(&other, background);
            let d = mean_abs(&unit, &other);
            eprintln!(
                "{size:?} x{scale}: fill {fill_other:.2} (x1 {filled:.2}), mean |diff| {d:.5}"
            );
            assert!(
                (fill_other - filled).abs() < 0.05,
                "{size:?} x{scale}: fill {fill_other} vs {filled}"
            );
            // Measured 0 (the frames are the same); without the unit scaling 0.0049.
            assert!(d < 0.001, "{size:?} x{scale}: mean difference {d} from x1");
        }
    }
}
