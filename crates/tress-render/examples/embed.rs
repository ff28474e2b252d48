//! Embedding tress in an application that owns its wgpu device and render targets.
//!
//! The application creates the instance, adapter, device, and the color and depth textures
//! itself, wraps the device in a `GpuContext` (which only checks capabilities), gives its own
//! hair and head to a `Session` (`Session::with_hair`, the one frame driver every front end
//! uses) and renders into views of its own textures. Then it simulates the hair while turning
//! the head with its own animation (`Session::simulate_to_with`: the application says where the
//! head is; the simulation runs at its fixed rate on the GPU and the frame draws the result) and
//! renders again. Writes `embed.png` and `embed-moved.png` (or the path given and its `-moved`
//! sibling).
//!
//! ```text
//! cargo run -p tress-render --example embed -- out.png
//! ```

use std::f32::consts::{PI, TAU};

use anyhow::Context;
use glam::Vec3;
use tress_hair::HairAsset;
use tress_render::scene_setup::PreparedHair;
use tress_render::session::{FrameDetail, Session, SessionOptions};
use tress_render::{
    Camera, DirectionalLight, GpuContext, Material, TargetFormats, Targets, TechniqueKind, TriMesh,
};

/// Strands rooted on the upper half of a sphere, falling under "gravity".
fn hair(radius: f32, strands: u32, vertices: u32) -> anyhow::Result<HairAsset> {
    let mut positions = Vec::new();
    let golden = PI * (3.0 - 5f32.sqrt());
    for i in 0..strands {
        let y = 1.0 - (i as f32 + 0.5) / strands as f32 * 0.9;
        let r = (1.0 - y * y).sqrt();
        let phi = golden * i as f32;
        let n = Vec3::new(r * phi.cos(), y, r * phi.sin());
        let mut p = n * radius;
        let mut dir = n;
        for _ in 0..vertices {
            positions.push(p);
            dir = (dir + Vec3::new(0.0, -0.35, 0.0)).normalize();
            p += dir * (radius * 0.12);
        }
    }
    let counts = vec![vertices; strands as usize];
    Ok(HairAsset::from_counts(positions, &counts)?)
}

fn main() -> anyhow::Result<()> {
    let out = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "embed.png".into());
    let size = [320u32, 240];

    // ---- the application's own device
    let instance =
        wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle_from_env());
    let adapter = pollster::block_on(instance.request_adapter(&Default::default()))
        .context("no GPU adapter (install mesa-vulkan-drivers for lavapipe)")?;
    let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
        label: Some("app/device"),
        required_limits: adapter.limits(),
        ..Default::default()
    }))?;
    let ctx = GpuContext::from_device(&adapter, device.clone(), queue)?;

    // ---- the application's own targets (depth needs TEXTURE_BINDING: the strands read it)
    let extent = wgpu::Extent3d {
        width: size[0],
        height: size[1],
        depth_or_array_layers: 1,
    };
    let texture = |label, format, usage| {
        device.create_texture(&wgpu::TextureDescriptor {
            label: Some(label),
            size: extent,
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format,
            usage,
            view_formats: &[],
        })
    };
    let color_format = wgpu::TextureFormat::Rgba8UnormSrgb;
    let color = texture(
        "app/color",
        color_format,
        wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
    );
    let depth = texture(
        "app/depth",
        tress_render::DEPTH_FORMAT,
        wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
    );
    let color_view = color.create_view(&Default::default());
    let depth_view = depth.create_view(&Default::default());

    // ---- tress: the application's hair and head, the scene's settings (defaults here)
    let mut scene = tress_scene::Scene::default();
    scene.background = Vec3::new(0.2, 0.22, 0.25);
    let hair = PreparedHair {
        asset: hair(10.0, 3000, 16)?,
        material: Material::default(),
        technique: TechniqueKind::Strands,
    };
    let head = TriMesh::uv_sphere(Vec3::ZERO, 9.5, 32, 48);
    let formats = TargetFormats {
        color: color_format,
    };
    let options = SessionOptions::default();
    let mut session = Session::with_hair(&ctx, formats, scene, vec![hair], Some(head), options)?;
    let camera = Camera::look_at(
        Vec3::new(30.0, 8.0, 45.0),
        Vec3::new(0.0, -3.0, 0.0),
        Vec3::Y,
        40f32.to_radians(),
        1.0,
        200.0,
        size,
    );
    let lights = [DirectionalLight {
        direction: Vec3::new(-0.5, -0.7, -0.3) * TAU,
        ..Default::default()
    }];
    let targets = Targets {
        color: &color_view,
        depth: &depth_view,
    };
    let frame = session.render(&ctx, &targets, &camera, Some(&lights))?;
    if let Some(timings) = &frame.timings {
        println!("{timings}");
    }
    if let FrameDetail::Strands(stats) = &frame.detail
        && let Some(gpu) = &stats.gpu
    {
        println!(
            "PPLL: {} of {} nodes used, {} dropped",
            gpu.ppll.used, gpu.ppll.capacity, gpu.ppll.dropped
        );
    }
    tress_render::read_texture(&ctx, &color)?.save_png(&out)?;
    println!("wrote {out}");

    // ---- the hair simulated, the head turned by the application's own animation
    let settings = tress_sim::SimSettings::default();
    session.start_simulation(&ctx, settings, tress_sim::MotionSpec::default())?;
    // The application's head: a turn about the vertical axis through the sphere's centre.
    let head = |_character: usize, t: f32| {
        tress_sim::Rigid::about(
            Vec3::ZERO,
            glam::Quat::from_rotation_y(0.8 * (2.0 * t).sin()),
            Vec3::ZERO,
        )
    };
    // Its frames: 30 of them at 30 Hz (the simulation steps at 60 Hz whatever the display does).
    for frame in 1..=30 {
        let t = f64::from(frame) / 30.0;
        session.simulate_to_with(&ctx, t, false, head)?;
        session.render(&ctx, &targets, &camera, Some(&lights))?;
    }
    let moved = out.replace(".png", "-moved.png");
    tress_render::read_texture(&ctx, &color)?.save_png(&moved)?;
    let sim = session.simulation().context("simulating")?;
    let (guides, strands) = sim.counts();
    println!(
        "wrote {moved} ({guides} guides of {strands} strands simulated for {:.1} s)",
        sim.time()
    );
    Ok(())
}
