//! Render a procedural hairstyle (strands on a sphere "head") and print per-pass GPU times and
//! PPLL memory: a quick way to time the strand technique at a given size.
//!
//! ```text
//! cargo run --release -p tress-render --example bench -- \
//!     --strands 136000 --vertices 16 --size 1280x720 --frames 5 --out bench.png \
//!     --set shading=scheuermann --set k=16
//! ```
//!
//! `--light x,y,z` sets the direction the light travels. `--set` takes `key=value` for the strand settings `width_px`, `alpha`, `k`, `shading`,
//! `coverage`, `shadows`, `shadow_map_size`, `shadow_r`, `shadow_alpha`, `pcf_radius`,
//! `shadow_bias`, `ppll_nodes_per_pixel`.

use std::f32::consts::PI;

use anyhow::{Context, bail};
use glam::Vec3;
use tress_hair::HairAsset;
use tress_render::{
    COLOR_FORMAT, Camera, DirectionalLight, FrameInputs, GpuContext, HeadGeometry, Material,
    OffscreenTargets, Renderer, SharedInputs, StrandSettings, TargetFormats, TriMesh, read_texture,
};

/// `strands` strands of `vertices` vertices rooted on the upper part of a sphere of radius 10
/// (centimetre-like units), falling under a little gravity.
fn hair(strands: u32, vertices: u32) -> anyhow::Result<HairAsset> {
    let radius = 10.0;
    let mut positions = Vec::with_capacity((strands * vertices) as usize);
    let golden = PI * (3.0 - 5f32.sqrt());
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
            p += dir * (radius * 1.6 / vertices as f32);
        }
    }
    Ok(HairAsset::from_counts(
        positions,
        &vec![vertices; strands as usize],
    )?)
}

fn set(s: &mut StrandSettings, kv: &str) -> anyhow::Result<()> {
    let (k, v) = kv.split_once('=').context("--set takes key=value")?;
    match k {
        "width_px" => s.width_px = v.parse()?,
        "alpha" => s.alpha = v.parse()?,
        "k" => s.k = v.parse()?,
        "shading" => s.shading = v.parse()?,
        "coverage" => s.coverage = v.parse()?,
        "shadows" => s.shadows = v.parse()?,
        "shadow_map_size" => s.shadow_map_size = v.parse()?,
        "shadow_r" => s.shadow_r = v.parse()?,
        "shadow_alpha" => s.shadow_alpha = v.parse()?,
        "pcf_radius" => s.pcf_radius = v.parse()?,
        "shadow_bias" => s.shadow_bias = v.parse()?,
        "ppll_nodes_per_pixel" => s.ppll_nodes_per_pixel = v.parse()?,
        _ => bail!("unknown setting {k}"),
    }
    Ok(())
}

fn main() -> anyhow::Result<()> {
    let (mut strands, mut vertices, mut size, mut frames) =
        (10_000u32, 16u32, [640u32, 360], 3usize);
    let mut out = None;
    let mut light = Vec3::new(-0.6, -0.7, -0.4);
    let mut settings = StrandSettings::default();
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        let mut value = || args.next().with_context(|| format!("{a} needs a value"));
        match a.as_str() {
            "--strands" => strands = value()?.parse()?,
            "--vertices" => vertices = value()?.parse()?,
            "--frames" => frames = value()?.parse()?,
            "--out" => out = Some(value()?),
            "--light" => {
                let v: Vec<f32> = value()?
                    .split(',')
                    .map(str::parse)
                    .collect::<Result<_, _>>()?;
                light = Vec3::from_slice(v.get(..3).context("--light x,y,z")?);
            }
            "--set" => set(&mut settings, &value()?)?,
            "--size" => {
                let v = value()?;
                let (w, h) = v.split_once('x').context("--size WxH")?;
                size = [w.parse()?, h.parse()?];
            }
            _ => bail!("unknown argument {a}"),
        }
    }
    let ctx = GpuContext::headless()?;
    println!(
        "adapter: {} ({:?})",
        ctx.adapter_info.name, ctx.adapter_info.backend
    );
    let asset = hair(strands, vertices)?;
    let mut renderer = Renderer::new(&ctx, TargetFormats::default(), settings)?;
    let geometry = renderer.upload_hair(&ctx, &asset)?;
    let head = HeadGeometry::new(&ctx, &TriMesh::uv_sphere(Vec3::ZERO, 9.8, 48, 64))?;
    let targets = OffscreenTargets::new(&ctx, size, COLOR_FORMAT)?;
    let camera = Camera::look_at(
        Vec3::new(26.0, 10.0, 44.0),
        Vec3::new(0.0, -4.0, 0.0),
        Vec3::Y,
        40f32.to_radians(),
        1.0,
        200.0,
        size,
    );
    let lights = [DirectionalLight {
        direction: light,
        intensity: 1.4,
        ..Default::default()
    }];
    let inputs = FrameInputs {
        shared: SharedInputs {
            camera,
            lights: &lights,
            ambient: Vec3::splat(0.06),
            head: Some(&head),
            clear: Some(wgpu::Color {
                r: 0.15,
                g: 0.16,
                b: 0.18,
                a: 1.0,
            }),
        },
        material: Material::default(),
        hair: Some(&geometry),
        objects: &[],
    };
    println!(
        "{} strands x {} vertices = {} segments at {}x{}",
        strands,
        vertices,
        geometry.segment_count(),
        size[0],
        size[1]
    );
    for _ in 0..frames {
        let t0 = std::time::Instant::now();
        let stats = renderer.render(&ctx, &targets.targets(), &inputs)?;
        let wall = t0.elapsed().as_secs_f64() * 1e3;
        let gpu = stats.gpu.context("stats")?;
        println!("frame {}: wall {wall:.1} ms; {}", stats.frame, gpu.timings);
        println!(
            "  PPLL: {} nodes used of {} ({:.1} MiB nodes + {:.1} MiB heads), {} dropped",
            gpu.ppll.used,
            gpu.ppll.capacity,
            gpu.ppll.node_bytes as f64 / (1 << 20) as f64,
            gpu.ppll.head_bytes as f64 / (1 << 20) as f64,
            gpu.ppll.dropped
        );
    }
    if let Some(out) = out {
        read_texture(&ctx, &targets.color)?.save_png(&out)?;
        println!("wrote {out}");
    }
    Ok(())
}
