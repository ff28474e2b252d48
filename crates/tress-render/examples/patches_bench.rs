//! Time the patch technique: the AO bake of the generated layered patch head, then the slides'
//! 4-pass scheme against the 3-pass scheme on the same frame (interleaved, median GPU time per
//! pass over `--frames` frames after a warm-up frame each), and the ratio.
//!
//! ```text
//! cargo run --release -p tress-render --example patches_bench -- \
//!     --size 1280x720 --frames 9 --rays 64 --out patches.png
//! ```
//!
//! `--layers N` and `--patches N` change the generator (defaults: `PatchParams::default()`,
//! 4 layers of 64 patches), `--distance D` moves the camera (default 55, the head filling about
//! half the frame height), `--min-alpha A` turns on the option that drops nearly empty fragments
//! in the last pass, `--no-ao` skips the bake.

use std::time::Instant;

use anyhow::{Context, bail};
use glam::Vec3;
use tress_hair::generate::Head;
use tress_hair::patches::{AoParams, PatchParams, bake_ao, generate_patches};
use tress_render::patches::{PatchFrameInputs, PatchRenderer, PatchSettings, RenderScheme};
use tress_render::{
    COLOR_FORMAT, Camera, DirectionalLight, GpuContext, HeadGeometry, OffscreenTargets,
    SharedInputs, TargetFormats, Timings, read_texture,
};

struct Options {
    size: [u32; 2],
    frames: usize,
    rays: u32,
    ao: bool,
    layers: u32,
    patches: u32,
    distance: f32,
    min_alpha: f32,
    out: Option<String>,
}

fn options() -> anyhow::Result<Options> {
    let mut o = Options {
        size: [1280, 720],
        frames: 9,
        rays: AoParams::default().rays,
        ao: true,
        layers: PatchParams::default().layers,
        patches: PatchParams::default().patches_per_layer,
        distance: 55.0,
        min_alpha: 0.0,
        out: None,
    };
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        let mut value = || args.next().with_context(|| format!("{a} needs a value"));
        match a.as_str() {
            "--size" => {
                let v = value()?;
                let (w, h) = v.split_once('x').context("--size takes WxH")?;
                o.size = [w.parse()?, h.parse()?];
            }
            "--frames" => o.frames = value()?.parse()?,
            "--rays" => o.rays = value()?.parse()?,
            "--no-ao" => o.ao = false,
            "--layers" => o.layers = value()?.parse()?,
            "--patches" => o.patches = value()?.parse()?,
            "--distance" => o.distance = value()?.parse()?,
            "--min-alpha" => o.min_alpha = value()?.parse()?,
            "--out" => o.out = Some(value()?),
            other => bail!("unknown argument {other}"),
        }
    }
    if o.frames == 0 {
        bail!("--frames must be at least 1");
    }
    Ok(o)
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn main() -> anyhow::Result<()> {
    let o = options()?;
    let head = Head::default();
    let params = PatchParams {
        head,
        layers: o.layers,
        patches_per_layer: o.patches,
        ..Default::default()
    };
    let mut mesh = generate_patches(&params)?;
    let head_mesh = head.mesh(64);
    println!(
        "generated patch head: {} patches, {} vertices, {} triangles; head {} triangles",
        mesh.component_count(),
        mesh.vertex_count(),
        mesh.triangle_count(),
        head_mesh.indices.len() / 3
    );
    if o.ao {
        let ao = AoParams {
            rays: o.rays,
            ..Default::default()
        };
        let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
        let start = Instant::now();
        bake_ao(&mut mesh, Some(&head_mesh), &ao)?;
        println!(
            "AO bake: {} rays per hemisphere, {:.3} s on {threads} threads",
            o.rays,
            start.elapsed().as_secs_f64()
        );
    }

    let ctx = GpuContext::headless()?;
    println!(
        "adapter: {} ({:?})",
        ctx.adapter_info.name, ctx.adapter_info.backend
    );
    if !ctx.caps.timestamps {
        bail!("the adapter has no timestamp queries");
    }
    let targets = OffscreenTargets::new(&ctx, o.size, COLOR_FORMAT)?;
    let head_gpu = HeadGeometry::new(&ctx, &head_mesh)?;
    let target = head.center + Vec3::new(0.0, -5.0, 0.0);
    let eye = target + Vec3::new(-0.6, 0.15, -0.75).normalize() * o.distance;
    let camera = Camera::look_at(eye, target, Vec3::Y, 40f32.to_radians(), 1.0, 500.0, o.size);
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
    let schemes = [RenderScheme::FourPass, RenderScheme::ThreePass];
    let mut renderers = Vec::new();
    for scheme in schemes {
        let settings = PatchSettings {
            scheme,
            min_alpha: o.min_alpha,
            ..Default::default()
        };
        let r = PatchRenderer::new(&ctx, TargetFormats::default(), settings)?;
        let g = r.upload_patches(&ctx, &mesh, head.center)?;
        renderers.push((r, g));
    }
    let mut samples: Vec<Vec<Timings>> = vec![Vec::new(), Vec::new()];
    for frame in 0..=o.frames {
        for (i, (r, g)) in renderers.iter_mut().enumerate() {
            let inputs = PatchFrameInputs {
                shared: SharedInputs {
                    camera,
                    lights: &lights,
                    ambient: Vec3::splat(0.08),
                    head: Some(&head_gpu),
                    clear: Some(wgpu::Color {
                        r: 0.18,
                        g: 0.18,
                        b: 0.2,
                        a: 1.0,
                    }),
                },
                head_color: Vec3::new(0.55, 0.4, 0.33),
                patches: Some(g),
            };
            let stats = r.render(&ctx, &targets.targets(), &inputs)?;
            if frame > 0 {
                samples[i].push(stats.timings.context("no GPU times")?);
            }
        }
    }
    let mut totals = [0.0; 2];
    for (i, scheme) in schemes.iter().enumerate() {
        let mut names: Vec<&str> = vec!["head"];
        names.extend(scheme.passes().iter().map(|p| p.name));
        let mut line = format!("{:>6}:", scheme.name());
        let mut hair = 0.0;
        for name in &names {
            let ms = median(samples[i].iter().filter_map(|t| t.get(name)).collect());
            if *name != "head" {
                hair += ms;
            }
            line.push_str(&format!(" {name} {ms:.3} ms,"));
        }
        let frame = median(samples[i].iter().filter_map(Timings::total_ms).collect());
        totals[i] = hair;
        println!(
            "{line} patch passes {hair:.3} ms, frame {frame:.3} ms (medians of {})",
            o.frames
        );
    }
    println!(
        "4-pass / 3-pass patch time: {:.3} ({}x{}, {})",
        totals[0] / totals[1],
        o.size[0],
        o.size[1],
        ctx.adapter_info.name
    );
    if let Some(path) = &o.out {
        // The last frame rendered was 3-pass; render the 4-pass one again for the picture.
        let (r, g) = &mut renderers[0];
        let inputs = PatchFrameInputs {
            shared: SharedInputs {
                camera,
                lights: &lights,
                ambient: Vec3::splat(0.08),
                head: Some(&head_gpu),
                clear: Some(wgpu::Color {
                    r: 0.18,
                    g: 0.18,
                    b: 0.2,
                    a: 1.0,
                }),
            },
            head_color: Vec3::new(0.55, 0.4, 0.33),
            patches: Some(g),
        };
        r.render(&ctx, &targets.targets(), &inputs)?;
        read_texture(&ctx, &targets.color)?.save_png(path)?;
        println!("wrote {path}");
    }
    Ok(())
}
