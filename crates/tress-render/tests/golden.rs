//! Golden images of the strand technique (design rule 7): small canonical scenes rendered
//! headlessly and compared with the committed PNGs under `tests/golden/` by mean FLIP error.
//! Re-bless with `TRESS_BLESS=1 cargo test -p tress-render --test golden`. On a mismatch the
//! rendered image and the FLIP error map are written to `CARGO_TARGET_TMPDIR/golden/`.

mod common;

use glam::Vec3;
use tress_render::{DirectionalLight, Renderer, Shading, StrandSettings, TargetFormats};

const SIZE: u32 = 128;
/// Mean FLIP error allowed: lavapipe reproduces its own images almost exactly; the margin allows
/// other drivers' rounding and the order of insertion in the PPLL tail.
const MAX_MEAN_FLIP: f32 = 0.03;

fn settings() -> StrandSettings {
    common::sphere_strand_settings()
}

fn render(settings: StrandSettings, lights: &[DirectionalLight]) -> image::RgbImage {
    let ctx = common::gpu().expect("checked by the caller");
    let mut r = Renderer::new(&ctx, TargetFormats::default(), settings).expect("renderer");
    let (stats, img) = common::render_sphere_golden(&ctx, &mut r, SIZE, lights);
    assert_eq!(stats.gpu.expect("stats").ppll.dropped, 0);
    img
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
