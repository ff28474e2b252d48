//! The harness of the GPU-vs-CPU tests (design rule 6): a WGSL test module composed with the
//! crate's includes, a grid of cases from a seeded generator, and one compute dispatch whose
//! results come back for comparison with the CPU twins.

use bytemuck::Pod;
use glam::Vec3;
use tress_render::gpu::read_buffer;
use tress_render::{GpuContext, shaders};
use wgpu::util::DeviceExt;

/// A small deterministic generator (xorshift), so a grid of cases is the same on every run.
pub struct Rng(pub u64);

impl Rng {
    /// Uniform in [0, 1).
    pub fn next(&mut self) -> f32 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 40) as f32 / (1u64 << 24) as f32
    }

    /// Uniform in [lo, hi).
    pub fn range(&mut self, lo: f32, hi: f32) -> f32 {
        lo + (hi - lo) * self.next()
    }

    /// A unit vector (rejection sampling in the unit ball, away from its centre).
    pub fn unit(&mut self) -> Vec3 {
        loop {
            let p = Vec3::new(
                self.range(-1.0, 1.0),
                self.range(-1.0, 1.0),
                self.range(-1.0, 1.0),
            );
            if p.length() > 0.1 && p.length() <= 1.0 {
                return p.normalize();
            }
        }
    }

    /// An RGB color in [0, 1)³.
    pub fn color(&mut self) -> Vec3 {
        Vec3::new(self.next(), self.next(), self.next())
    }
}

/// The shader module of a test's WGSL `src` (its `#include` lines name the crate's files).
pub fn test_module(ctx: &GpuContext, name: &str, src: &str, label: &str) -> wgpu::ShaderModule {
    let text = shaders::compose_source(name, src).expect("composes");
    ctx.device
        .create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some(label),
            source: wgpu::ShaderSource::Wgsl(text.into()),
        })
}

/// Run `main` of `module` (64 invocations a workgroup, one per case) with `cases` at binding 0,
/// a results buffer of `results_per_case` values `R` per case at binding 1 and `extra` further
/// bindings of group 0 (the layout is the shader's own); return the results.
pub fn run_cases<C: Pod, R: Pod>(
    ctx: &GpuContext,
    label: &str,
    module: &wgpu::ShaderModule,
    cases: &[C],
    results_per_case: usize,
    extra: &[(u32, wgpu::BindingResource<'_>)],
) -> Vec<R> {
    let input = ctx
        .device
        .create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some(&format!("{label}/cases")),
            contents: bytemuck::cast_slice(cases),
            usage: wgpu::BufferUsages::STORAGE,
        });
    let bytes = (cases.len() * results_per_case * size_of::<R>()) as u64;
    let buffer = |name: &str, usage| {
        ctx.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(&format!("{label}/{name}")),
            size: bytes,
            usage,
            mapped_at_creation: false,
        })
    };
    let results = buffer(
        "results",
        wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
    );
    let readback = buffer(
        "readback",
        wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
    );
    let pipeline = ctx
        .device
        .create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some(&format!("{label}/pipeline")),
            layout: None,
            module,
            entry_point: Some("main"),
            compilation_options: Default::default(),
            cache: None,
        });
    let mut entries = vec![
        wgpu::BindGroupEntry {
            binding: 0,
            resource: input.as_entire_binding(),
        },
        wgpu::BindGroupEntry {
            binding: 1,
            resource: results.as_entire_binding(),
        },
    ];
    entries.extend(
        extra
            .iter()
            .map(|(binding, resource)| wgpu::BindGroupEntry {
                binding: *binding,
                resource: resource.clone(),
            }),
    );
    let group = ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some(&format!("{label}/bind-group")),
        layout: &pipeline.get_bind_group_layout(0),
        entries: &entries,
    });
    let mut encoder = ctx.device.create_command_encoder(&Default::default());
    {
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some(&format!("{label}/pass")),
            timestamp_writes: None,
        });
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &group, &[]);
        pass.dispatch_workgroups((cases.len() as u32).div_ceil(64), 1, 1);
    }
    encoder.copy_buffer_to_buffer(&results, 0, &readback, 0, Some(bytes));
    ctx.queue.submit([encoder.finish()]);
    let raw = read_buffer(ctx, &readback, 0..bytes).expect("readback");
    bytemuck::pod_collect_to_vec(&raw)
}
