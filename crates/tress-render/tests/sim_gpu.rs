//! The GPU simulation against its CPU twin (`tress_sim::Simulation`): the same steps give the
//! same guides and the same rebuilt followers in the renderers' vertex buffer; two GPU runs are
//! byte-identical.

mod common;

use glam::{Quat, Vec3};
use tress_hair::HairAsset;
use tress_hair::generate::{Style, TriMesh, generate, head_for};
use tress_render::gpu::read_whole_buffer;
use tress_render::sim::GpuSimulation;
use tress_render::{GpuContext, StrandGeometry};
use tress_sim::{
    Capsule, GuideChoice, MotionSpec, Preset, Rigid, SimSettings, Simulation, Sphere, Wind,
};

fn groom() -> (HairAsset, TriMesh) {
    let mut p = Style::Curly.default_params();
    p.strands = 90;
    p.vertices = 12;
    p.seed = 7;
    (
        generate(Style::Curly, &p).unwrap(),
        head_for(Style::Curly).mesh(3),
    )
}

/// Everything on: wind with turbulence, shock propagation, the grid, the head's field, a sphere
/// and a capsule.
fn settings() -> SimSettings {
    SimSettings {
        wind: Wind {
            direction: Vec3::new(1.0, 0.0, 0.3),
            strength: 150.0,
            turbulence: 0.5,
            drag: 3.0,
        },
        shock: 0.8,
        shock_threshold: 2.0,
        hair_friction: 0.2,
        hair_volume: 0.3,
        spheres: vec![Sphere {
            center: Vec3::new(0.0, -12.0, 4.0),
            radius: 4.0,
        }],
        capsules: vec![Capsule {
            a: Vec3::new(-8.0, -16.0, -6.0),
            b: Vec3::new(8.0, -16.0, -6.0),
            radius: 2.5,
        }],
        ..SimSettings::default()
    }
}

fn motion() -> impl Fn(f32) -> Rigid {
    let spec = MotionSpec {
        frequency: Some(1.5),
        ..MotionSpec::preset(Preset::Shake)
    };
    let pivot = head_for(Style::Curly).center;
    move |t| spec.at(t, pivot)
}

/// The renderers' vertex positions after the GPU wrote the simulated hair into them.
fn rendered(ctx: &GpuContext, geometry: &StrandGeometry) -> Vec<Vec3> {
    let bytes = read_whole_buffer(ctx, geometry.vertex_buffer(), "test/vertices").unwrap();
    bytemuck::cast_slice::<u8, [f32; 8]>(&bytes)
        .iter()
        .map(|v| Vec3::new(v[0], v[1], v[2]))
        .collect()
}

fn worst(a: &[Vec3], b: &[Vec3]) -> f32 {
    assert_eq!(a.len(), b.len());
    a.iter()
        .zip(b)
        .map(|(p, q)| p.distance(*q))
        .fold(0.0, f32::max)
}

#[test]
fn the_gpu_steps_as_the_cpu_twin_does() {
    let Some(ctx) = common::gpu() else { return };
    let (asset, mesh) = groom();
    let s = settings();
    let guides = GuideChoice::Share(1.0 / 3.0);
    let mut cpu = Simulation::new(&asset, Some(&mesh), &s, &guides, Rigid::IDENTITY).unwrap();
    let mut gpu = GpuSimulation::new(
        &ctx,
        Simulation::new(&asset, Some(&mesh), &s, &guides, Rigid::IDENTITY).unwrap(),
    )
    .unwrap();
    let geometry = StrandGeometry::new(&ctx, &asset).unwrap();
    let size = asset.bounds().size().length();
    let m = motion();
    // A few steps at a time: the two diverge only by rounding, which chaotic motion grows.
    for t in [1.0 / 60.0, 2.0 / 60.0, 5.0 / 60.0, 10.0 / 60.0] {
        cpu.advance_to(t, &m);
        gpu.advance_to(&ctx, t, &m).unwrap();
        assert_eq!(cpu.steps(), gpu.steps());
        let g = gpu.read_guides(&ctx).unwrap();
        let e = worst(cpu.guides().0, &g);
        assert!(e < 1e-4 * size, "t = {t}: guides differ by {e} of {size}");
        gpu.write_positions(&ctx, &geometry).unwrap();
        let e = worst(&cpu.positions(), &rendered(&ctx, &geometry));
        assert!(
            e < 2e-4 * size,
            "t = {t}: followers differ by {e} of {size}"
        );
    }
    // The hair moved: the comparison is not of two still images.
    let moved = worst(&cpu.positions(), asset.positions());
    assert!(moved > 0.05 * size, "the hair moved only {moved}");
}

#[test]
fn a_teleport_on_the_gpu_moves_the_hair_as_on_the_cpu() {
    let Some(ctx) = common::gpu() else { return };
    let (asset, mesh) = groom();
    let s = SimSettings::default();
    let guides = GuideChoice::Share(1.0);
    let mut cpu = Simulation::new(&asset, Some(&mesh), &s, &guides, Rigid::IDENTITY).unwrap();
    let mut gpu = GpuSimulation::new(
        &ctx,
        Simulation::new(&asset, Some(&mesh), &s, &guides, Rigid::IDENTITY).unwrap(),
    )
    .unwrap();
    let far = Rigid::about(
        Vec3::ZERO,
        Quat::from_rotation_y(2.0),
        Vec3::new(400.0, 0.0, 0.0),
    );
    for head in [Rigid::IDENTITY, Rigid::IDENTITY, far, far] {
        cpu.step(head);
        gpu.step(&ctx, head).unwrap();
    }
    let e = worst(cpu.guides().0, &gpu.read_guides(&ctx).unwrap());
    assert!(e < 1e-3, "{e}");
}

#[test]
fn two_gpu_runs_are_byte_identical_timed_or_not() {
    let Some(ctx) = common::gpu() else { return };
    let (asset, mesh) = groom();
    let s = settings();
    let run = |timed: bool| {
        let sim = Simulation::new(
            &asset,
            Some(&mesh),
            &s,
            &GuideChoice::Share(0.5),
            Rigid::IDENTITY,
        )
        .unwrap();
        let mut gpu = GpuSimulation::new(&ctx, sim).unwrap();
        gpu.set_timing(&ctx, timed);
        gpu.advance_to(&ctx, 0.25, motion()).unwrap();
        let geometry = StrandGeometry::new(&ctx, &asset).unwrap();
        gpu.write_positions(&ctx, &geometry).unwrap();
        let timings = gpu.take_timings();
        (
            read_whole_buffer(&ctx, geometry.vertex_buffer(), "test/vertices").unwrap(),
            timings,
        )
    };
    let (a, untimed) = run(false);
    assert_eq!(untimed, tress_render::Timings::NotSupported);
    // Timing the passes changes nothing in the result.
    let (b, timed) = run(true);
    assert_eq!(a, b);
    match timed {
        tress_render::Timings::Passes(p) => {
            assert!(ctx.caps.timestamps);
            let names: Vec<&str> = p.iter().map(|t| t.name).collect();
            assert_eq!(names, tress_render::sim::SIM_PASS_NAMES);
            // Every pass ran (the grid too: hair friction and volume are on) and took time.
            for t in &p {
                assert!(t.ms > 0.0 && t.ms < 1e4, "{}: {} ms", t.name, t.ms);
            }
        }
        tress_render::Timings::NotSupported => assert!(!ctx.caps.timestamps),
    }
}
