//! `Session` adds nothing to a frame: for the built-in demo scene (a thinned ponytail on the
//! generated head), the frame a `Session` draws equals, bit for bit, the frame the technique's
//! own renderer draws from the same scene's settings (`Renderer` for strands, volume and hybrid;
//! `PatchRenderer` for patches; `SatfRenderer` for satf, with a small baked database). A safety
//! net for reworking the frame driver.

mod common;

use glam::Vec3;
use tress_render::patches::scene::{load_patches, patch_settings};
use tress_render::satf::scene::{load_clusters, satf_settings};
use tress_render::session::{AMBIENT, Session, SessionOptions, scene_from_inputs};
use tress_render::{
    COLOR_FORMAT, FrameInputs, GpuContext, HeadGeometry, LinearImage, OffscreenTargets,
    PatchFrameInputs, PatchRenderer, PreparedScene, Renderer, SatfDatabase, SatfFrameInputs,
    SatfGeometry, SatfRenderer, SharedInputs, TargetFormats, TechniqueKind, read_texture,
};

const SIZE: [u32; 2] = [96, 54];

fn scene() -> tress_scene::Scene {
    let (mut scene, _) = scene_from_inputs(&[]).unwrap();
    scene.apply_override("hair.0.strand_ratio=0.01").unwrap();
    scene
}

fn session_frame(ctx: &GpuContext, technique: &str) -> LinearImage {
    let options = SessionOptions {
        satf_database: Some(Box::new(|_| Ok(common::small_satf_database(48)))),
        ..SessionOptions::default()
    };
    let mut s = Session::new(ctx, TargetFormats::default(), scene(), options).unwrap();
    s.set_technique(ctx, technique).unwrap();
    let targets = OffscreenTargets::new(ctx, SIZE, COLOR_FORMAT).unwrap();
    let camera = s.camera(SIZE);
    s.render(ctx, &targets.targets(), &camera, None).unwrap();
    read_texture(ctx, &targets.color).unwrap()
}

#[test]
fn session_frames_equal_the_renderers_frames() {
    let Some(ctx) = common::gpu() else { return };
    let scene = scene();
    let prepared = PreparedScene::load(&scene).unwrap();
    let camera = PreparedScene::camera(&scene, SIZE);
    let head = prepared
        .head
        .as_ref()
        .map(|m| HeadGeometry::new(&ctx, m).unwrap());
    let targets = OffscreenTargets::new(&ctx, SIZE, COLOR_FORMAT).unwrap();
    let bg = prepared.background;

    let mut renderer =
        Renderer::new(&ctx, TargetFormats::default(), prepared.strands.clone()).unwrap();
    renderer
        .set_volume_settings(&ctx, prepared.volume.clone())
        .unwrap();
    renderer
        .set_hybrid_settings(prepared.hybrid.clone())
        .unwrap();
    let hair = renderer
        .upload_hair(&ctx, &prepared.hair().unwrap())
        .unwrap();
    for (name, technique) in [
        ("strands", TechniqueKind::Strands),
        ("volume", TechniqueKind::Volume),
        ("hybrid", TechniqueKind::Hybrid),
    ] {
        renderer.set_technique(technique).expect("technique");
        let inputs = FrameInputs {
            shared: SharedInputs {
                camera,
                lights: &prepared.lights,
                ambient: Vec3::splat(AMBIENT),
                head: head.as_ref(),
                clear: prepared.clear_color(),
            },
            material: prepared.material,
            hair: Some(&hair),
            objects: &[],
        };
        renderer.render(&ctx, &targets.targets(), &inputs).unwrap();
        let direct = read_texture(&ctx, &targets.color).unwrap();
        let via_session = session_frame(&ctx, name);
        assert!(
            direct.pixels.iter().any(|p| (p[0] - bg.x).abs() > 0.02),
            "{name}: the frame must show hair"
        );
        assert_eq!(direct.pixels, via_session.pixels, "{name}");
    }

    let patches = load_patches(&scene, &prepared).unwrap();
    assert!(!patches.textures_from_files);
    let mut renderer = PatchRenderer::new(
        &ctx,
        TargetFormats::default(),
        patch_settings(&scene, prepared.first_hair()).unwrap(),
    )
    .unwrap();
    let geometry = renderer
        .upload_patches(&ctx, &patches.mesh, patches.sort_center)
        .unwrap();
    renderer
        .render(
            &ctx,
            &targets.targets(),
            &PatchFrameInputs {
                shared: SharedInputs {
                    camera,
                    lights: &prepared.lights,
                    ambient: Vec3::splat(AMBIENT),
                    head: head.as_ref(),
                    clear: prepared.clear_color(),
                },
                head_color: prepared.material.head_color,
                patches: Some(&geometry),
            },
        )
        .unwrap();
    let direct = read_texture(&ctx, &targets.color).unwrap();
    assert_eq!(
        direct.pixels,
        session_frame(&ctx, "patches").pixels,
        "patches"
    );

    let settings = satf_settings(&scene, prepared.first_hair()).unwrap();
    let volume = load_clusters(&scene, &settings, prepared.hair().as_deref()).unwrap();
    let db = SatfDatabase::new(&ctx, &common::small_satf_database(48)).unwrap();
    let geometry = SatfGeometry::new(&ctx, &volume, &db, &settings.settings).unwrap();
    let mut renderer =
        SatfRenderer::new(&ctx, TargetFormats::default(), settings.settings).unwrap();
    renderer
        .render(
            &ctx,
            &targets.targets(),
            &SatfFrameInputs {
                shared: SharedInputs {
                    camera,
                    lights: &prepared.lights,
                    ambient: Vec3::splat(AMBIENT),
                    head: head.as_ref(),
                    clear: prepared.clear_color(),
                },
                head_color: prepared.material.head_color,
                clusters: Some(&geometry),
                database: &db,
            },
        )
        .unwrap();
    let direct = read_texture(&ctx, &targets.color).unwrap();
    assert!(
        direct.pixels.iter().any(|p| (p[0] - bg.x).abs() > 0.02),
        "satf: the frame must show hair"
    );
    assert_eq!(direct.pixels, session_frame(&ctx, "satf").pixels, "satf");
}
