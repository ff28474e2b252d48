//! GPU vs CPU: the patch technique's rendered pixels against `tress_shading::hair_lighting` (the
//! CPU twin of the slides' `HairLighting`), and under `shading = "marschner"` against
//! `tress_shading::dual_scattering::dual_scattering_lighting`, evaluated at the same pixels: a single quad under a
//! perspective camera and one light, constant textures, AO varying from root to tip. The CPU side
//! reconstructs each pixel's surface point by casting the pixel's ray against the quad.

mod common;

use glam::{Vec2, Vec3, Vec4Swizzles};
use tress_hair::patches::{HairTextures, PatchMesh, Texture};
use tress_render::gpu::{linear_to_srgb, srgb_to_linear};
use tress_render::patches::{PatchFrameInputs, PatchRenderer, PatchSettings, RenderScheme};
use tress_render::{
    COLOR_FORMAT, Camera, DirectionalLight, OffscreenTargets, Shading, SharedInputs, TargetFormats,
    read_texture,
};
use tress_shading::dual_scattering::{DualScattering, dual_scattering_lighting};
use tress_shading::fiber::{HairFiber, sigma_a_from_melanin};
use tress_shading::marschner::Marschner;
use tress_shading::{HairLighting, HairSample, hair_lighting};

const SIZE: u32 = 64;
const BASE: Vec3 = Vec3::new(0.5, 0.4, 0.3);
const SHIFT: f32 = 0.7;
const NOISE: f32 = 0.6;
const AO_ROOT: f32 = 0.4;

fn constant(channels: u32, value: &[f32]) -> Texture {
    Texture {
        width: 4,
        height: 4,
        channels,
        data: value.repeat(16),
    }
}

fn unorm8(v: f32) -> f32 {
    (v * 255.0).round() / 255.0
}

/// The unit quad `[-1, 1]²` at z = 0 facing +z, tangent +y (v from y = -1 to 1), AO growing
/// linearly from `AO_ROOT` at the root to 1 at the tip.
fn quad() -> PatchMesh {
    let p = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)].map(|(x, y)| Vec3::new(x, y, 0.0));
    let uv = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)].map(|(u, v)| Vec2::new(u, v));
    let ao = uv.map(|t| AO_ROOT + (1.0 - AO_ROOT) * t.y);
    PatchMesh::new(
        p.to_vec(),
        vec![Vec3::Z; 4],
        vec![Vec3::Y; 4],
        uv.to_vec(),
        vec![0, 1, 2, 0, 2, 3],
    )
    .and_then(|m| m.with_ao(ao.to_vec()))
    .expect("valid quad")
}

/// The world point of pixel `(x, y)`'s centre on the plane z = 0.
fn pixel_point(camera: &Camera, x: u32, y: u32) -> Option<Vec3> {
    let inv = camera.clip_from_world().inverse();
    let ndc = Vec2::new(
        (x as f32 + 0.5) / SIZE as f32 * 2.0 - 1.0,
        1.0 - (y as f32 + 0.5) / SIZE as f32 * 2.0,
    );
    let unproject = |z: f32| {
        let w = inv * ndc.extend(z).extend(1.0);
        w.xyz() / w.w
    };
    let (a, b) = (unproject(0.0), unproject(1.0));
    let t = -a.z / (b.z - a.z);
    (t.is_finite() && t > 0.0).then(|| a + (b - a) * t)
}

/// The view and light every comparison uses, chosen to put a highlight on the quad.
fn view() -> (Camera, DirectionalLight) {
    let camera = Camera::look_at(
        Vec3::new(0.6, -0.4, 2.2),
        Vec3::new(0.0, 0.1, 0.0),
        Vec3::Y,
        50f32.to_radians(),
        0.1,
        10.0,
        [SIZE, SIZE],
    );
    let light = DirectionalLight {
        direction: -Vec3::new(0.2, 0.45, 1.0),
        color: Vec3::new(1.0, 0.9, 0.8),
        intensity: 1.5,
    };
    (camera, light)
}

/// Render the quad with `settings` and compare every inner pixel with `expect(sample, l,
/// light color, v)` (the CPU twin of one light's term; ambient is zero). Returns the largest
/// expected value, to check that a highlight was in view.
fn compare_with_cpu(
    settings: PatchSettings,
    expect: impl Fn(&HairSample, Vec3, Vec3, Vec3) -> Vec3,
) -> Option<f32> {
    let ctx = common::gpu()?;
    let textures = HairTextures {
        base: constant(3, &BASE.to_array()),
        alpha: constant(1, &[1.0]),
        spec_shift: constant(1, &[SHIFT]),
        spec_noise: constant(1, &[NOISE]),
    };
    let mut r = PatchRenderer::with_textures(&ctx, TargetFormats::default(), settings, textures)
        .expect("renderer");
    let geometry = r
        .upload_patches(&ctx, &quad(), Vec3::NEG_Z)
        .expect("upload");
    let (camera, light) = view();
    let t = OffscreenTargets::new(&ctx, [SIZE, SIZE], COLOR_FORMAT).expect("targets");
    let inputs = PatchFrameInputs {
        shared: SharedInputs {
            camera,
            lights: &[light],
            ambient: Vec3::ZERO,
            head: None,
            clear: Some(wgpu::Color::BLACK),
        },
        head_color: Vec3::ONE,
        patches: Some(&geometry),
    };
    r.render(&ctx, &t.targets(), &inputs).expect("frame");
    let image = read_texture(&ctx, &t.color).expect("readback");

    // The texels as the GPU reads them: 8-bit, the base through sRGB.
    let base = BASE.map(|c| srgb_to_linear(unorm8(linear_to_srgb(c))));
    let l = light.to_light().expect("light");
    let light_color = light.color * light.intensity;
    let (mut compared, mut worst, mut brightest) = (0, 0.0f32, 0.0f32);
    for y in 0..SIZE {
        for x in 0..SIZE {
            let Some(p) = pixel_point(&camera, x, y) else {
                continue;
            };
            // Skip pixels within a pixel or so of the quad's edges (coverage is ambiguous).
            if p.x.abs() > 0.95 || p.y.abs() > 0.95 {
                continue;
            }
            let v_coord = (p.y + 1.0) * 0.5;
            let sample = HairSample {
                tangent: Vec3::Y,
                shift_tex: unorm8(SHIFT),
                normal: Vec3::Z,
                spec_mask: unorm8(NOISE),
                base_color: base,
                amb_occ: AO_ROOT + (1.0 - AO_ROOT) * v_coord,
            };
            let v = (camera.eye() - p).normalize();
            let expect = expect(&sample, l, light_color, v);
            let got = image.get(x, y).expect("inside");
            let got = Vec3::new(got[0], got[1], got[2]);
            let err = ((got - expect).abs() / (expect.abs() + Vec3::splat(0.05))).max_element();
            assert!(
                err < 0.02,
                "pixel ({x}, {y}) at {p}: GPU {got}, CPU {expect} (relative error {err})"
            );
            worst = worst.max(err);
            brightest = brightest.max(expect.max_element());
            compared += 1;
        }
    }
    assert!(compared > 1000, "only {compared} pixels compared");
    eprintln!("{compared} pixels, worst relative error {worst:.5}");
    Some(brightest)
}

#[test]
fn rendered_pixels_match_the_cpu_hair_lighting() {
    let lighting = HairLighting {
        diffuse_color: Vec3::new(0.9, 0.95, 1.0),
        primary_exponent: 60.0,
        primary_color: Vec3::new(0.6, 0.6, 0.55),
        primary_shift: -0.15,
        secondary_color: Vec3::new(0.7, 0.5, 0.3),
        secondary_exponent: 12.0,
        secondary_shift: 0.2,
    };
    let settings = PatchSettings {
        scheme: RenderScheme::FourPass,
        lighting,
        mipmaps: false,
        ..Default::default()
    };
    let Some(brightest) =
        compare_with_cpu(settings, |s, l, c, v| hair_lighting(&lighting, s, l, c, v))
    else {
        return;
    };
    // The view was chosen to put the primary highlight on the quad: the comparison covers the
    // specular terms, not only the diffuse one.
    let (_, light) = view();
    let base = BASE.map(|c| srgb_to_linear(unorm8(linear_to_srgb(c))));
    let diffuse_only =
        (lighting.diffuse_color * base * light.color * light.intensity).max_element();
    assert!(
        brightest > diffuse_only * 1.2,
        "no highlight in view: {brightest} vs {diffuse_only}"
    );
}

/// `patches.shading = "marschner"`: each pixel is the CPU twin's unshadowed dual-scattering
/// term of the patch tangent (no strands towards the light, all of it direct); the base texture
/// and AO only reach the ambient term, which is zero here. The test first checks that the
/// slides' default lighting differs clearly from it at this view, so a shader that ignored the
/// mode would fail.
#[test]
fn marschner_patches_match_the_cpu_dual_scattering() {
    let fiber = HairFiber {
        sigma_a: sigma_a_from_melanin(0.3, 0.1),
        beta_m: 0.25,
        beta_n: 0.35,
        alpha: 3f32.to_radians(),
        eta: 1.55,
    };
    let settings = PatchSettings {
        shading: Shading::Marschner,
        fiber,
        mipmaps: false,
        ..Default::default()
    };
    let m = Marschner::from_fiber(&fiber);
    let ds = DualScattering::from_marschner(&m);
    let (_, light) = view();
    let scheuermann = |s: &HairSample, l, c, v| hair_lighting(&settings.lighting, s, l, c, v);
    let marschner =
        |_: &HairSample, l, c, v| dual_scattering_lighting(&m, &ds, Vec3::Y, l, c, v, 0.0, 1.0);
    // The two models differ clearly at this view, so the comparison can tell them apart.
    let (camera, _) = view();
    let l = light.to_light().expect("light");
    let v = (camera.eye() - Vec3::ZERO).normalize();
    let sample = HairSample {
        tangent: Vec3::Y,
        shift_tex: unorm8(SHIFT),
        normal: Vec3::Z,
        spec_mask: unorm8(NOISE),
        base_color: BASE,
        amb_occ: 0.7,
    };
    let c = light.color * light.intensity;
    let (a, b) = (marschner(&sample, l, c, v), scheuermann(&sample, l, c, v));
    assert!(
        ((a - b).abs() / (b + Vec3::splat(0.05))).max_element() > 0.1,
        "the models agree at the centre ({a} vs {b}): the test could not tell them apart"
    );
    let Some(brightest) = compare_with_cpu(settings.clone(), marschner) else {
        return;
    };
    assert!(brightest > 0.05, "the quad is nearly black: {brightest}");
}
