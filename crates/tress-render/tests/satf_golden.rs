//! Golden images of the SATF technique (design rule 7): generated clusters on a head and clusters
//! fitted to a strand asset, rendered headlessly with a small baked database and compared with
//! the committed PNGs under `tests/golden/` by mean FLIP error. Re-bless with
//! `TRESS_BLESS=1 cargo test -p tress-render --test satf_golden`. On a mismatch the rendered image
//! and the FLIP map are written to `CARGO_TARGET_TMPDIR/golden/`.

mod common;

use std::sync::OnceLock;

use glam::Vec3;
use tress_hair::generate::Head;
use tress_render::satf::{Reflectance, SatfSettings, StageTiming};
use tress_render::{
    COLOR_FORMAT, Camera, DirectionalLight, HeadGeometry, OffscreenTargets, SatfDatabase,
    SatfFrameInputs, SatfFrameStats, SatfGeometry, SatfRenderer, SharedInputs, TargetFormats,
};
use tress_satf::database::Database;
use tress_satf::generate::{ClusterStyle, generate_clusters};
use tress_satf::{HairVolume, ShellSampling};

const SIZE: u32 = 160;
/// Mean FLIP error allowed (lavapipe reproduces its own images almost exactly).
const MAX_MEAN_FLIP: f32 = 0.03;

/// A small database, baked once per test binary.
fn database() -> &'static Database {
    static DB: OnceLock<Database> = OnceLock::new();
    DB.get_or_init(|| common::small_satf_database(96))
}

fn settings() -> SatfSettings {
    SatfSettings {
        sampling: ShellSampling {
            st: 8,
            sv: 4,
            su: 6,
            core_rings: 1,
        },
        map_rows: 3,
        shadow_map_size: 256,
        ..Default::default()
    }
}

fn clusters() -> HairVolume {
    let style = ClusterStyle {
        macro_clusters: 4,
        clusters_per_macro: 3,
        strands_per_cluster: 80,
        samples: 12,
        ..Default::default()
    };
    generate_clusters(&Head::default(), &style).expect("clusters")
}

fn key_light() -> DirectionalLight {
    DirectionalLight {
        direction: Vec3::new(-0.5, -0.7, -0.5),
        color: Vec3::ONE,
        intensity: 2.0,
    }
}

fn render(settings: SatfSettings, volume: &HairVolume) -> (image::RgbImage, SatfFrameStats) {
    let ctx = common::gpu().expect("checked by the caller");
    let mut r = SatfRenderer::new(&ctx, TargetFormats::default(), settings).expect("renderer");
    let db = SatfDatabase::new(&ctx, database()).expect("database");
    let geometry = SatfGeometry::new(&ctx, volume, &db, &settings).expect("geometry");
    let head = Head::default();
    let head = HeadGeometry::new(&ctx, &head.mesh(32)).expect("head");
    let t = OffscreenTargets::new(&ctx, [SIZE, SIZE], COLOR_FORMAT).expect("targets");
    let camera = Camera::look_at(
        Vec3::new(38.0, 8.0, 52.0),
        Vec3::new(0.0, -6.0, 0.0),
        Vec3::Y,
        45f32.to_radians(),
        1.0,
        200.0,
        [SIZE, SIZE],
    );
    let lights = [key_light()];
    let inputs = SatfFrameInputs {
        shared: SharedInputs {
            camera,
            lights: &lights,
            ambient: Vec3::splat(0.08),
            head: Some(&head),
            clear: Some(common::BACKGROUND),
        },
        head_color: Vec3::new(0.6, 0.45, 0.35),
        clusters: Some(&geometry),
        database: &db,
    };
    let stats = r.render(&ctx, &t.targets(), &inputs).expect("frame");
    (common::srgb_image(&ctx, &t.color), stats)
}

#[test]
fn generated_clusters_on_a_head() {
    if common::gpu().is_none() {
        return;
    }
    let volume = clusters();
    let (img, stats) = render(settings(), &volume);
    assert_eq!(stats.clusters, 12);
    assert_eq!(stats.hsvs, 12 * 8 * 3 * 6);
    assert_eq!(stats.uniform_hsvs + stats.interpolated_hsvs, stats.hsvs);
    common::check_golden("satf_generated", &img, MAX_MEAN_FLIP);
}

/// Wall-clock stage timing submits every stage alone: the same image, every stage timed.
#[test]
fn wall_clock_stage_timing_renders_the_same_image() {
    if common::gpu().is_none() {
        return;
    }
    let settings = SatfSettings {
        stage_timing: StageTiming::WallClock,
        ..settings()
    };
    let (img, stats) = render(settings, &clusters());
    match &stats.timings {
        tress_render::Timings::Passes(p) => {
            let names: Vec<&str> = p.iter().map(|t| t.name).collect();
            assert_eq!(names, tress_render::satf::PASS_NAMES);
            assert!(p.iter().all(|t| t.ms >= 0.0));
        }
        other => panic!("wall-clock timings are always available: {other:?}"),
    }
    common::check_golden("satf_generated", &img, MAX_MEAN_FLIP);
}

/// Clusters fitted to a generated straight style (the path that lets SATF render any strand
/// asset), with the paper's literal readings: premultiplied reflectance and the linear form of
/// equation 12, and no shadows between clusters.
#[test]
fn fitted_clusters_literal_settings() {
    if common::gpu().is_none() {
        return;
    }
    let style = tress_hair::generate::Style::Straight;
    let params = tress_hair::generate::StyleParams {
        strands: 1500,
        vertices: 12,
        ..style.default_params()
    };
    let hair = tress_hair::generate::generate(style, &params).expect("hair");
    let fit = tress_satf::fit::FitSettings {
        strands_per_cluster: 160,
        ..Default::default()
    };
    let volume = tress_satf::fit::fit_clusters(&hair, &fit).expect("fit");
    let settings = SatfSettings {
        reflectance: Reflectance::Premultiplied,
        shadow_approx: tress_satf::online::ShadowApprox::Linear,
        cluster_shadows: false,
        ..settings()
    };
    let (img, stats) = render(settings, &volume);
    assert!(stats.clusters >= 10, "{} clusters", stats.clusters);
    common::check_golden("satf_fitted_literal", &img, MAX_MEAN_FLIP);
}
