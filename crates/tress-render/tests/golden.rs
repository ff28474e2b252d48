//! Golden images of the strand technique (design rule 7): small canonical scenes rendered
//! headlessly and compared with the committed PNGs under `tests/golden/` by mean FLIP error.
//! Re-bless with `TRESS_BLESS=1 cargo test -p tress-render --test golden`. On a mismatch the
//! rendered image and the FLIP error map are written to `CARGO_TARGET_TMPDIR/golden/`.

mod common;

use glam::Vec3;
use tress_render::{
    COLOR_FORMAT, Camera, DirectionalLight, FrameInputs, HeadGeometry, HeadMesh, Material,
    OffscreenTargets, Renderer, Shading, StrandSettings, TargetFormats, read_texture,
};

const SIZE: u32 = 128;
/// Mean FLIP error allowed: lavapipe reproduces its own images almost exactly; the margin allows
/// other drivers' rounding and the order of insertion in the PPLL tail.
const MAX_MEAN_FLIP: f32 = 0.03;

/// Settings at this scene's scale: the head has radius 1 (about 10 cm), so `r` = 4 strands per
/// centimetre is 40 per unit, and the bias is 0.5 mm.
fn settings() -> StrandSettings {
    StrandSettings {
        shadow_r: 40.0,
        shadow_bias: 0.005,
        ..Default::default()
    }
}

fn render(settings: StrandSettings, lights: &[DirectionalLight]) -> image::RgbImage {
    let ctx = common::gpu().expect("checked by the caller");
    let mut r = Renderer::new(&ctx, TargetFormats::default(), settings).expect("renderer");
    let hair = r
        .upload_hair(&ctx, &common::sphere_hair(1.0, 1200, 12))
        .expect("hair");
    let head =
        HeadGeometry::new(&ctx, &HeadMesh::uv_sphere(Vec3::ZERO, 0.97, 24, 32)).expect("head");
    let t = OffscreenTargets::new(&ctx, [SIZE, SIZE], COLOR_FORMAT).expect("targets");
    let camera = Camera::look_at(
        Vec3::new(2.6, 1.2, 4.4),
        Vec3::new(0.0, -0.45, 0.0),
        Vec3::Y,
        45f32.to_radians(),
        0.1,
        20.0,
        [SIZE, SIZE],
    );
    let inputs = FrameInputs {
        camera,
        lights,
        ambient: Vec3::splat(0.06),
        material: Material::default(),
        hair: Some(&hair),
        head: Some(&head),
        clear: Some(wgpu::Color {
            r: 0.15,
            g: 0.16,
            b: 0.18,
            a: 1.0,
        }),
    };
    let stats = r.render(&ctx, &t.targets(), &inputs).expect("frame");
    assert_eq!(stats.gpu.expect("stats").ppll.dropped, 0);
    let img = read_texture(&ctx, &t.color).expect("readback").to_srgb8();
    image::DynamicImage::ImageRgba8(img).to_rgb8()
}

fn key_light() -> DirectionalLight {
    DirectionalLight {
        direction: Vec3::new(0.6, -0.6, -0.5),
        color: Vec3::ONE,
        intensity: 2.5,
    }
}

#[test]
fn kajiya_kay_with_adsm_shadows() {
    if common::gpu().is_none() {
        return;
    }
    let img = render(settings(), &[key_light()]);
    common::check_golden("strands_kajiya_kay", &img, MAX_MEAN_FLIP);
}

#[test]
fn scheuermann_two_lights() {
    if common::gpu().is_none() {
        return;
    }
    let settings = StrandSettings {
        shading: Shading::Scheuermann,
        pcf_radius: 2,
        ..settings()
    };
    let rim = DirectionalLight {
        direction: Vec3::new(-0.8, -0.2, -0.6),
        color: Vec3::new(0.6, 0.7, 1.0),
        intensity: 1.5,
    };
    let img = render(settings, &[key_light(), rim]);
    common::check_golden("strands_scheuermann", &img, MAX_MEAN_FLIP);
}

#[test]
fn aliased_without_coverage_small_k_no_shadows() {
    if common::gpu().is_none() {
        return;
    }
    let settings = StrandSettings {
        coverage: false,
        k: 4,
        shadows: false,
        width_px: 1.0,
        ..settings()
    };
    let img = render(settings, &[key_light()]);
    common::check_golden("strands_aliased_k4", &img, MAX_MEAN_FLIP);
}
