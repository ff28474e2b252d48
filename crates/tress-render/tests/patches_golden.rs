//! Golden images of the patch technique (design rule 7): the generated layered patch head and
//! strands converted to cards, rendered headlessly and compared with the committed PNGs under
//! `tests/golden/` by mean FLIP error; and the two schemes against each other (they resolve the
//! same visibility, so their images agree). Re-bless with
//! `TRESS_BLESS=1 cargo test -p tress-render --test patches_golden`. On a mismatch the rendered
//! image and the FLIP error map are written to `CARGO_TARGET_TMPDIR/golden/`.

mod common;

use glam::Vec3;
use tress_hair::generate::Head;
use tress_hair::patches::{
    AoParams, CardParams, PatchMesh, PatchParams, TextureParams, bake_ao, generate_patches,
};
use tress_render::patches::{PatchFrameInputs, PatchRenderer, PatchSettings, RenderScheme};
use tress_render::{
    COLOR_FORMAT, Camera, DirectionalLight, HeadGeometry, OffscreenTargets, SharedInputs,
    TargetFormats, TriMesh,
};

const SIZE: u32 = 128;
/// Mean FLIP error allowed against a golden (lavapipe reproduces its own images almost exactly;
/// the margin allows other drivers' rounding).
const MAX_MEAN_FLIP: f32 = 0.03;

fn head_mesh(head: &Head) -> TriMesh {
    head.mesh(24)
}

/// The generated layered patches on the default head (fewer than the defaults, for speed), AO
/// baked against patches and head.
fn generated() -> (PatchMesh, TriMesh, Vec3) {
    let head = Head::default();
    let params = PatchParams {
        head,
        layers: 3,
        patches_per_layer: 40,
        segments: 8,
        ..Default::default()
    };
    let mut mesh = generate_patches(&params).expect("patches");
    let head_mesh = head_mesh(&head);
    let ao = AoParams {
        rays: 16,
        ..Default::default()
    };
    bake_ao(&mut mesh, Some(&head_mesh), &ao).expect("AO");
    (mesh, head_mesh, head.center)
}

/// Cards from the test strands on a unit sphere.
fn cards() -> (PatchMesh, TriMesh, Vec3) {
    let hair = common::sphere_hair(1.0, 600, 12);
    let params = CardParams {
        cards: 60,
        segments: 8,
        min_width: 0.05,
        ..Default::default()
    };
    let mesh = PatchMesh::from_strands(&hair, &params).expect("cards");
    (
        mesh,
        TriMesh::uv_sphere(Vec3::ZERO, 0.97, 24, 32),
        Vec3::ZERO,
    )
}

fn render(
    scheme: RenderScheme,
    (mesh, head, center): &(PatchMesh, TriMesh, Vec3),
    eye: Vec3,
    target: Vec3,
) -> image::RgbImage {
    let ctx = common::gpu().expect("checked by the caller");
    let settings = PatchSettings {
        scheme,
        textures: TextureParams {
            width: 64,
            height: 128,
            strands: 16,
            ..Default::default()
        },
        ..Default::default()
    };
    let mut r = PatchRenderer::new(&ctx, TargetFormats::default(), settings).expect("renderer");
    let geometry = r.upload_patches(&ctx, mesh, *center).expect("upload");
    let head = HeadGeometry::new(&ctx, head).expect("head");
    let t = OffscreenTargets::new(&ctx, [SIZE, SIZE], COLOR_FORMAT).expect("targets");
    let lights = [
        DirectionalLight {
            direction: Vec3::new(-0.5, -0.6, 0.6),
            color: Vec3::new(1.0, 0.96, 0.9),
            intensity: 1.0,
        },
        DirectionalLight {
            direction: Vec3::new(0.7, -0.1, -0.3),
            color: Vec3::new(0.7, 0.8, 1.0),
            intensity: 0.35,
        },
    ];
    let camera = Camera::look_at(
        eye,
        target,
        Vec3::Y,
        40f32.to_radians(),
        0.05,
        200.0,
        [SIZE, SIZE],
    );
    let inputs = PatchFrameInputs {
        shared: SharedInputs {
            camera,
            lights: &lights,
            ambient: Vec3::splat(0.08),
            head: Some(&head),
            clear: Some(common::BACKGROUND),
        },
        head_color: Vec3::new(0.55, 0.4, 0.33),
        patches: Some(&geometry),
    };
    r.render(&ctx, &t.targets(), &inputs).expect("frame");
    common::srgb_image(&ctx, &t.color)
}

/// Mean FLIP error between two renders.
fn mean_flip(a: &image::RgbImage, b: &image::RgbImage) -> f32 {
    let f = nv_flip::flip(
        nv_flip::FlipImageRgb8::with_data(a.width(), a.height(), a),
        nv_flip::FlipImageRgb8::with_data(b.width(), b.height(), b),
        nv_flip::DEFAULT_PIXELS_PER_DEGREE,
    );
    nv_flip::FlipPool::from_image(&f).mean()
}

/// Fraction of pixels that differ from the background by more than a few levels.
fn coverage(img: &image::RgbImage) -> f32 {
    let bg = img.get_pixel(0, 0).0;
    let hit = img
        .pixels()
        .filter(|p| (0..3).any(|c| (i32::from(p.0[c]) - i32::from(bg[c])).abs() > 4))
        .count();
    hit as f32 / (img.width() * img.height()) as f32
}

const HEAD_EYE: Vec3 = Vec3::new(-40.0, 10.0, -45.0);
const HEAD_TARGET: Vec3 = Vec3::new(0.0, -5.0, 0.0);

#[test]
fn generated_patch_head_four_pass() {
    if common::gpu().is_none() {
        return;
    }
    let img = render(RenderScheme::FourPass, &generated(), HEAD_EYE, HEAD_TARGET);
    common::check_golden("patches_generated_4pass", &img, MAX_MEAN_FLIP);
    assert!(coverage(&img) > 0.2, "the head and hair fill the view");
}

#[test]
fn both_schemes_resolve_the_same_image() {
    if common::gpu().is_none() {
        return;
    }
    let scene = generated();
    let four = render(RenderScheme::FourPass, &scene, HEAD_EYE, HEAD_TARGET);
    let three = render(RenderScheme::ThreePass, &scene, HEAD_EYE, HEAD_TARGET);
    let mean = mean_flip(&four, &three);
    assert!(mean < 0.01, "4-pass and 3-pass differ: mean FLIP {mean}");
}

#[test]
fn strands_as_cards_three_pass() {
    if common::gpu().is_none() {
        return;
    }
    let img = render(
        RenderScheme::ThreePass,
        &cards(),
        Vec3::new(2.6, 1.2, 4.4),
        Vec3::new(0.0, -0.45, 0.0),
    );
    common::check_golden("patches_cards_3pass", &img, MAX_MEAN_FLIP);
    assert!(coverage(&img) > 0.1, "the cards fill part of the view");
}
