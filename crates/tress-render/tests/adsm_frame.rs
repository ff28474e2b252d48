//! ADSM at frame level (Jansson 2019 §3.4): an occluding strand between light `i` (each of
//! lights 0–3, so each of the four shadow maps) and an opaque receiving strand; the receiver's
//! pixels equal `ambient · base + KK(t, l, v) · L · (1 - α)^(max(0, d - bias) · r)`, `d` the
//! world distance from the occluder to the receiver along the light (the CPU twins'
//! Kajiya-Kay and ADSM visibility are the model). With three lights or more the middle shadow
//! passes write no timestamps (wgpu rejected the frames before: `GpuTimer::render_writes`).

mod common;

use glam::Vec3;
use tress_hair::HairAsset;
use tress_render::Shading;
use tress_render::strands::ThicknessFade;
use tress_render::{
    COLOR_FORMAT, DirectionalLight, FrameInputs, Material, OffscreenTargets, Renderer,
    SharedInputs, StrandSettings, TargetFormats, read_texture,
};
use tress_shading::dual_scattering::{DualScattering, dual_scattering_lighting};
use tress_shading::fiber::HairFiber;
use tress_shading::marschner::Marschner;
use tress_shading::{KajiyaKay, adsm_visibility, kajiya_kay, strands_from_visibility};

const SIZE: u32 = 64;
/// World units a pixel under `common::ortho_camera` (2 units over `SIZE`).
const PIXEL: f32 = 2.0 / SIZE as f32;
const RECEIVER: Vec3 = Vec3::new(0.0, -0.4, 0.0);
const OCCLUDER: Vec3 = Vec3::new(0.0, 0.4, 1.0);
const BASE: Vec3 = Vec3::new(0.5, 0.35, 0.2);
const AMBIENT: f32 = 0.1;

/// Two horizontal strands (along x) through `RECEIVER` (opaque) and `OCCLUDER` (opacity `alpha`,
/// irrelevant for the shadow: ADSM uses `shadow_alpha`).
fn strands() -> HairAsset {
    let positions = [RECEIVER, OCCLUDER]
        .iter()
        .flat_map(|c| [*c - Vec3::X * 3.0, *c + Vec3::X * 3.0])
        .collect();
    HairAsset::from_counts(positions, &[2, 2])
        .and_then(|h| h.with_color(vec![BASE; 4]))
        .expect("asset")
}

fn settings() -> StrandSettings {
    StrandSettings {
        width_px: 12.0,
        alpha: 1.0,
        coverage: false,
        thickness_fade: ThicknessFade::Off,
        shadow_r: 1.5,
        shadow_alpha: 0.4,
        shadow_bias: 0.05,
        // One texel, and the occluder drawn 4 texels wide into the maps: the receiver's texel
        // lies inside it wherever its centre line falls between texel rows (a 1-texel line
        // can land in the row next to the one the receiver looks up).
        pcf_radius: 0,
        shadow_width_px: 4.0,
        ..Default::default()
    }
}

/// Draw the two strands with `lights` and `material` (ambient `AMBIENT`, cleared to black) and
/// read the frame back.
fn frame(
    ctx: &tress_render::GpuContext,
    renderer: &mut Renderer,
    hair: &tress_render::StrandGeometry,
    lights: &[DirectionalLight],
    material: Material,
) -> tress_render::LinearImage {
    let targets = OffscreenTargets::new(ctx, [SIZE, SIZE], COLOR_FORMAT).unwrap();
    let inputs = FrameInputs {
        shared: SharedInputs {
            camera: common::ortho_camera(SIZE),
            lights,
            ambient: Vec3::splat(AMBIENT),
            head: None,
            clear: Some(wgpu::Color::BLACK),
        },
        material,
        hair: Some(hair),
        objects: &[],
    };
    renderer.render(ctx, &targets.targets(), &inputs).unwrap();
    read_texture(ctx, &targets.color).unwrap()
}

#[test]
fn the_receiver_gets_the_analytic_adsm_shadow_from_every_light() {
    let Some(ctx) = common::gpu() else { return };
    let settings = settings();
    let mut renderer = Renderer::new(&ctx, TargetFormats::default(), settings.clone()).unwrap();
    let hair = renderer.upload_hair(&ctx, &strands()).unwrap();
    // From the receiver's centre line to the occluder's: the light's direction.
    let to_light = (OCCLUDER - RECEIVER).normalize();
    let d = (OCCLUDER - RECEIVER).length();
    let t = Vec3::X;
    let v = Vec3::Z;
    let kk = KajiyaKay {
        diffuse: BASE,
        specular: Material::default().primary_color,
        exponent: Material::default().primary_exponent,
    };
    let light = DirectionalLight {
        direction: -to_light,
        color: Vec3::new(1.0, 0.9, 0.8),
        intensity: 0.8,
    };
    let visibility = adsm_visibility(
        d - settings.shadow_bias,
        settings.shadow_r,
        settings.shadow_alpha,
    );
    assert!(
        (0.2..0.8).contains(&visibility),
        "a shadow the test can see: {visibility}"
    );
    let lit = kajiya_kay(&kk, t, to_light, v) * light.color * light.intensity;
    let want = BASE * AMBIENT + lit * visibility;
    let unshadowed = BASE * AMBIENT + lit;
    // The receiver's rows (its ribbon is 12 px wide around y = -0.4), away from the edges.
    let row = ((1.0 - RECEIVER.y) / PIXEL) as u32;
    for i in 0..4 {
        // Light i is the one that shines; those before it are black but keep their slots, so
        // light i's own shadow map is used.
        let mut lights = vec![
            DirectionalLight {
                intensity: 0.0,
                ..light
            };
            i
        ];
        lights.push(light);
        let material = Material {
            base_color: BASE,
            ..Material::default()
        };
        let img = frame(&ctx, &mut renderer, &hair, &lights, material);
        for x in [8, 32, 56] {
            for y in [row - 2, row, row + 2] {
                let got = Vec3::from_slice(&img.get(x, y).expect("in image")[..3]);
                assert!(
                    (got - want).abs().max_element() < 0.01,
                    "light {i} at {x},{y}: {got} vs {want} (unshadowed {unshadowed})"
                );
            }
        }
        // The occluder itself is lit: nothing lies between it and the light.
        let occluder_row = ((1.0 - OCCLUDER.y) / PIXEL) as u32;
        let got = Vec3::from_slice(&img.get(32, occluder_row).expect("in image")[..3]);
        let open = BASE * AMBIENT + lit;
        assert!(
            (got - open).abs().max_element() < 0.01,
            "light {i}: occluder {got} vs {open}"
        );
    }
}

/// `strands.shading = "marschner"` in a frame: the receiver's pixels equal the CPU twin's dual
/// scattering with the strands its ADSM visibility stands for, the occluder's with none in the
/// way (blond fibre: the transmitted and multiply scattered light shows).
#[test]
fn marschner_frames_match_the_cpu_dual_scattering() {
    let Some(ctx) = common::gpu() else { return };
    let settings = StrandSettings {
        shading: Shading::Marschner,
        ..settings()
    };
    let fiber = HairFiber {
        sigma_a: tress_shading::fiber::sigma_a_from_melanin(0.3, 0.1),
        ..HairFiber::default()
    };
    let mut renderer = Renderer::new(&ctx, TargetFormats::default(), settings.clone()).unwrap();
    let hair = renderer.upload_hair(&ctx, &strands()).unwrap();
    let to_light = (OCCLUDER - RECEIVER).normalize();
    let light = DirectionalLight {
        direction: -to_light,
        color: Vec3::new(1.0, 0.9, 0.8),
        intensity: 0.8,
    };
    let material = Material {
        base_color: BASE,
        fiber,
        ..Material::default()
    };
    let img = frame(&ctx, &mut renderer, &hair, &[light], material);
    let m = Marschner::from_fiber(&fiber);
    let ds = DualScattering::from_marschner(&m);
    let radiance = light.color * light.intensity;
    let d = (OCCLUDER - RECEIVER).length();
    let direct = adsm_visibility(
        d - settings.shadow_bias,
        settings.shadow_r,
        settings.shadow_alpha,
    );
    let n = strands_from_visibility(direct, settings.shadow_alpha);
    assert!(n > 0.5, "{n} strands in the way");
    let shade_with = |ds: &DualScattering, strands: f32, direct: f32| {
        BASE * AMBIENT
            + dual_scattering_lighting(
                &m,
                ds,
                Vec3::X,
                to_light,
                radiance,
                Vec3::Z,
                strands,
                direct,
            )
    };
    let shade = |strands: f32, direct: f32| shade_with(&ds, strands, direct);
    for (centre, want) in [(RECEIVER, shade(n, direct)), (OCCLUDER, shade(0.0, 1.0))] {
        let row = ((1.0 - centre.y) / PIXEL) as u32;
        for x in [8, 32, 56] {
            let got = Vec3::from_slice(&img.get(x, row).expect("in image")[..3]);
            // RGB9E5 in the PPLL: 9 bits of mantissa.
            assert!(
                (got - want).abs().max_element() < 0.01 * want.max_element().max(0.1),
                "{centre} at {x}: {got} vs {want}"
            );
        }
    }
    // The shadow matters: lit and shadowed receivers differ clearly.
    let (shadowed, lit) = (shade(n, direct), shade(0.0, 1.0));
    assert!(
        (shadowed - lit).abs().max_element() > 0.2 * lit.max_element(),
        "shadowed {shadowed} vs lit {lit}"
    );
    // `multiple_scattering = false`: single scattering only, dual scattering's d_f and d_b 0.
    renderer
        .set_settings(
            &ctx,
            StrandSettings {
                multiple_scattering: false,
                ..settings.clone()
            },
        )
        .unwrap();
    let single_img = frame(&ctx, &mut renderer, &hair, &[light], material);
    let mut single_ds = ds;
    single_ds.params.y = 0.0;
    single_ds.params.z = 0.0;
    let want = shade_with(&single_ds, n, direct);
    let row = ((1.0 - RECEIVER.y) / PIXEL) as u32;
    let got = Vec3::from_slice(&single_img.get(32, row).expect("in image")[..3]);
    assert!(
        (got - want).abs().max_element() < 0.01 * want.max_element().max(0.1),
        "single scattering: {got} vs {want}"
    );
    // The shadowed receiver loses the light scattered to it through the occluder.
    assert!(
        (shade(n, direct) - want).max_element() > 0.05 * want.max_element(),
        "multiple scattering adds {} to {want}",
        shade(n, direct) - want
    );
}
