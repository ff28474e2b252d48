//! Shared helpers of the GPU tests: the context (fails loudly without an adapter), small scenes,
//! and the compute harness of the GPU-vs-CPU tests ([`compute`]).

#![allow(dead_code, unreachable_pub)]

pub mod compute;
pub mod layers;

use std::sync::OnceLock;

use glam::{Mat4, Vec3};
use tress_hair::HairAsset;
use tress_render::{
    COLOR_FORMAT, Camera, DirectionalLight, FrameInputs, FrameStats, GpuContext, HeadGeometry,
    Material, OffscreenTargets, Renderer, SharedInputs, StrandSettings, TriMesh, read_texture,
};

/// The GPU context shared by a test binary, or `None` when `TRESS_SKIP_GPU_TESTS=1` and there is
/// no adapter. Without an adapter (and without that variable) the test fails with a message that
/// says how to get one.
pub fn gpu() -> Option<GpuContext> {
    static CTX: OnceLock<Result<GpuContext, String>> = OnceLock::new();
    let ctx = CTX.get_or_init(|| GpuContext::headless().map_err(|e| e.to_string()));
    match ctx {
        Ok(ctx) => Some(ctx.clone()),
        Err(e) if std::env::var("TRESS_SKIP_GPU_TESTS").is_ok_and(|v| v == "1") => {
            eprintln!("TRESS_SKIP_GPU_TESTS=1: skipping a GPU test ({e})");
            None
        }
        Err(e) => panic!(
            "this test needs a GPU adapter: {e}\nOn a machine without a GPU install Mesa's CPU \
             Vulkan driver lavapipe (`apt-get install mesa-vulkan-drivers`) and run with \
             VK_DRIVER_FILES=/usr/share/vulkan/icd.d/lvp_icd.x86_64.json WGPU_BACKEND=vulkan; \
             set TRESS_SKIP_GPU_TESTS=1 only to skip GPU tests on purpose."
        ),
    }
}

/// An orthographic camera at z = 10 looking down -z at the square [-1, 1]², depth 0.1..20.
pub fn ortho_camera(size: u32) -> Camera {
    Camera {
        view_from_world: Mat4::look_at_rh(Vec3::new(0.0, 0.0, 10.0), Vec3::ZERO, Vec3::Y),
        clip_from_view: Mat4::orthographic_rh(-1.0, 1.0, -1.0, 1.0, 0.1, 20.0),
        viewport: [size, size],
    }
}

/// Normalized depth of world z under [`ortho_camera`].
pub fn ortho_depth(z: f32) -> f32 {
    (10.0 - z - 0.1) / 19.9
}

/// Horizontal two-vertex strands across the whole view at `y = 0`, one per `(z, color, alpha)`,
/// in the given order.
pub fn layer_strands(layers: &[(f32, Vec3, f32)]) -> HairAsset {
    let mut positions = Vec::new();
    for &(z, _, _) in layers {
        positions.push(Vec3::new(-3.0, 0.0, z));
        positions.push(Vec3::new(3.0, 0.0, z));
    }
    let counts = vec![2; layers.len()];
    let colors = layers.iter().flat_map(|&(_, c, _)| [c, c]).collect();
    let transparency = layers
        .iter()
        .flat_map(|&(_, _, a)| [1.0 - a, 1.0 - a])
        .collect();
    HairAsset::from_counts(positions, &counts)
        .and_then(|h| h.with_color(colors))
        .and_then(|h| h.with_transparency(transparency))
        .expect("valid asset")
}

/// Strands rooted on the upper part of a sphere of `radius` at the origin, falling under a little
/// gravity: a small stand-in hairstyle.
pub fn sphere_hair(radius: f32, strands: u32, vertices: u32) -> HairAsset {
    let mut positions = Vec::new();
    let golden = std::f32::consts::PI * (3.0 - 5f32.sqrt());
    for i in 0..strands {
        let y = 1.0 - (i as f32 + 0.5) / strands as f32 * 0.9;
        let r = (1.0 - y * y).sqrt();
        let phi = golden * i as f32;
        let n = Vec3::new(r * phi.cos(), y, r * phi.sin());
        let mut p = n * radius * 1.02;
        let mut dir = n;
        for _ in 0..vertices {
            positions.push(p);
            dir = (dir + Vec3::new(0.0, -0.3, 0.0)).normalize();
            p += dir * (radius * 0.1);
        }
    }
    let counts = vec![vertices; strands as usize];
    HairAsset::from_counts(positions, &counts).expect("valid asset")
}

/// Strand settings at the sphere scenes' scale: the head has radius 1 (about 10 cm), so `r` = 4
/// strands per centimetre is 40 per unit, and the bias is 0.5 mm.
pub fn sphere_strand_settings() -> StrandSettings {
    StrandSettings {
        shadow_r: 40.0,
        shadow_bias: 0.005,
        ..Default::default()
    }
}

/// The head of the sphere scenes: a sphere of radius 0.97 under [`sphere_hair`]`(1.0, …)`.
pub fn sphere_head(ctx: &GpuContext) -> HeadGeometry {
    HeadGeometry::new(ctx, &TriMesh::uv_sphere(Vec3::ZERO, 0.97, 24, 32)).expect("head")
}

/// What the golden scenes clear the color target to.
pub const BACKGROUND: wgpu::Color = wgpu::Color {
    r: 0.15,
    g: 0.16,
    b: 0.18,
    a: 1.0,
};

/// A frame's color target as an 8-bit sRGB image (what the goldens hold).
pub fn srgb_image(ctx: &GpuContext, color: &wgpu::Texture) -> image::RgbImage {
    let img = read_texture(ctx, color).expect("readback").to_srgb8();
    image::DynamicImage::ImageRgba8(img).to_rgb8()
}

/// The scene of the strand and volume goldens drawn by `renderer` under `lights`: 1200 strands
/// of [`sphere_hair`] on [`sphere_head`], `size`² from the front right. Returns the frame's
/// statistics and its image.
pub fn render_sphere_golden(
    ctx: &GpuContext,
    renderer: &mut Renderer,
    size: u32,
    lights: &[DirectionalLight],
) -> (FrameStats, image::RgbImage) {
    let hair = renderer
        .upload_hair(ctx, &sphere_hair(1.0, 1200, 12))
        .expect("hair");
    let head = sphere_head(ctx);
    let t = OffscreenTargets::new(ctx, [size, size], COLOR_FORMAT).expect("targets");
    let camera = Camera::look_at(
        Vec3::new(2.6, 1.2, 4.4),
        Vec3::new(0.0, -0.45, 0.0),
        Vec3::Y,
        45f32.to_radians(),
        0.1,
        20.0,
        [size, size],
    );
    let inputs = FrameInputs {
        shared: SharedInputs {
            camera,
            lights,
            ambient: Vec3::splat(0.06),
            head: Some(&head),
            clear: Some(BACKGROUND),
        },
        material: Material::default(),
        hair: Some(&hair),
        objects: &[],
    };
    let stats = renderer.render(ctx, &t.targets(), &inputs).expect("frame");
    (stats, srgb_image(ctx, &t.color))
}

/// Compare `image` with the golden PNG `tests/golden/{name}.png` by mean FLIP (design rule 7),
/// or write it when `TRESS_BLESS=1`. On a mismatch the render and the FLIP error map go to
/// `CARGO_TARGET_TMPDIR/golden/` and the test fails naming them. Returns the mean FLIP.
pub fn check_golden(name: &str, image: &image::RgbImage, max_mean_flip: f32) -> f32 {
    let path = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/golden")
        .join(format!("{name}.png"));
    if std::env::var("TRESS_BLESS").is_ok_and(|v| v == "1") {
        image.save(&path).expect("write golden");
        eprintln!("blessed {}", path.display());
        return 0.0;
    }
    let golden = image::open(&path)
        .unwrap_or_else(|e| panic!("{}: {e}; render it with TRESS_BLESS=1", path.display()))
        .to_rgb8();
    assert_eq!(golden.dimensions(), image.dimensions(), "{name}: size");
    let flip = nv_flip::flip(
        nv_flip::FlipImageRgb8::with_data(golden.width(), golden.height(), &golden),
        nv_flip::FlipImageRgb8::with_data(image.width(), image.height(), image),
        nv_flip::DEFAULT_PIXELS_PER_DEGREE,
    );
    let mean = nv_flip::FlipPool::from_image(&flip).mean();
    if mean > max_mean_flip {
        let dir = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("golden");
        std::fs::create_dir_all(&dir).expect("tmp dir");
        image
            .save(dir.join(format!("{name}.png")))
            .expect("write render");
        let map = flip.apply_color_lut(&nv_flip::magma_lut());
        image::RgbImage::from_raw(map.width(), map.height(), map.to_vec())
            .expect("flip map")
            .save(dir.join(format!("{name}.flip.png")))
            .expect("write flip map");
        panic!(
            "{name}: mean FLIP {mean:.4} > {max_mean_flip}; see {}",
            dir.display()
        );
    }
    eprintln!("{name}: mean FLIP {mean:.5}");
    mean
}

/// A small HRIR database for SATF tests: 8×8 view and light angles of 8-pixel HRIRs, `samples`
/// samples each (deterministic: the bake is seeded).
pub fn small_satf_database(samples: u32) -> tress_satf::Database {
    let s = tress_satf::database::BakeSettings {
        samples,
        hrir: tress_satf::hrir::HrirSettings {
            pixels: 8,
            view_angles: 8,
            light_angles: 8,
            ..Default::default()
        },
        ..Default::default()
    };
    tress_satf::database::bake(&s, |_, _| {}).expect("bake")
}

/// Coarse SATF settings for small test clusters: equation 3's sampling 6 × 4 × 5 with one core
/// ring, 3 map rows per HSV, 128² shadow maps; the rest default.
pub fn small_satf_settings() -> tress_render::satf::SatfSettings {
    tress_render::satf::SatfSettings {
        sampling: tress_satf::ShellSampling {
            st: 6,
            sv: 4,
            su: 5,
            core_rings: 1,
        },
        map_rows: 3,
        shadow_map_size: 128,
        ..Default::default()
    }
}
