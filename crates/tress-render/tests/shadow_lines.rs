//! The ADSM shadow maps drawn with one-texel lines (the default `shadow_width_px = 1`) give the
//! frame the one-texel ribbons gave, at a third of the vertices.

mod common;

use tress_render::{DirectionalLight, Renderer, StrandSettings, TargetFormats};

fn frame(ctx: &tress_render::GpuContext, settings: StrandSettings) -> image::RgbImage {
    let mut r = Renderer::new(ctx, TargetFormats::default(), settings).expect("renderer");
    let lights = [DirectionalLight::default()];
    common::render_sphere_golden(ctx, &mut r, 160, &lights).1
}

fn mean_flip(a: &image::RgbImage, b: &image::RgbImage) -> f32 {
    let flip = nv_flip::flip(
        nv_flip::FlipImageRgb8::with_data(a.width(), a.height(), a),
        nv_flip::FlipImageRgb8::with_data(b.width(), b.height(), b),
        nv_flip::DEFAULT_PIXELS_PER_DEGREE,
    );
    nv_flip::FlipPool::from_image(&flip).mean()
}

#[test]
fn line_shadow_maps_match_one_texel_ribbons() {
    let Some(ctx) = common::gpu() else { return };
    let base = common::sphere_strand_settings();
    let lines = frame(&ctx, base.clone());
    // Just above one texel: drawn as ribbons.
    let ribbons = frame(
        &ctx,
        StrandSettings {
            shadow_width_px: 1.0001,
            ..base.clone()
        },
    );
    let unshadowed = frame(
        &ctx,
        StrandSettings {
            shadows: false,
            ..base
        },
    );
    let same = mean_flip(&lines, &ribbons);
    let shadow = mean_flip(&lines, &unshadowed);
    eprintln!("lines vs ribbons {same:.4}, shadows vs none {shadow:.4}");
    assert!(same < 0.01, "{same}");
    assert!(shadow > 5.0 * same, "the comparison can tell shadows apart");
}
