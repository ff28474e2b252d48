//! [`SimStep`], owner of `sim_step.wgsl`: one substep's dispatches.

use super::UNIFORM_STRIDE;
use super::buffers::SimBuffers;
use crate::bind::{bind_group_layout, entry, storage};
use crate::gpu::GpuTimer;
use crate::gpu::pipeline::{compute_pipeline, pipeline_layout};
use crate::gpu::types::SimParams;
use crate::volume::dispatch_2d;
use crate::{GpuContext, RenderError, shaders};

/// The substep pipelines and their bind groups (three of the state's, one for each turn of the
/// position buffers).
#[derive(Debug)]
pub(crate) struct SimStep {
    shock: wgpu::ComputePipeline,
    integrate: wgpu::ComputePipeline,
    grid_clear: wgpu::ComputePipeline,
    grid_splat: wgpu::ComputePipeline,
    grid_apply: wgpu::ComputePipeline,
    constraints: wgpu::ComputePipeline,
    friction: wgpu::ComputePipeline,
    state: [wgpu::BindGroup; 3],
    next: [wgpu::BindGroup; 3],
    grid: wgpu::BindGroup,
    colliders: wgpu::BindGroup,
}

fn buffer(binding: u32, b: &wgpu::Buffer) -> wgpu::BindGroupEntry<'_> {
    wgpu::BindGroupEntry {
        binding,
        resource: b.as_entire_binding(),
    }
}

impl SimStep {
    pub(crate) fn new(ctx: &GpuContext, b: &SimBuffers) -> Result<Self, RenderError> {
        let module = shaders::create_module(ctx, "sim/sim_step.wgsl", "sim/step/shader")?;
        ctx.scoped("creating the simulation pipelines", || {
            let c = wgpu::ShaderStages::COMPUTE;
            let uniform = entry(
                0,
                c,
                wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Uniform,
                    has_dynamic_offset: true,
                    min_binding_size: wgpu::BufferSize::new(std::mem::size_of::<SimParams>() as u64),
                },
            );
            let state_layout = bind_group_layout(
                ctx,
                "sim/step/state-layout",
                &[uniform, storage(1, c, false), storage(2, c, false), storage(3, c, true)],
            );
            let next_layout = bind_group_layout(ctx, "sim/step/next-layout", &[storage(0, c, false)]);
            let grid_layout = bind_group_layout(
                ctx,
                "sim/step/grid-layout",
                &[storage(1, c, false)],
            );
            let collider_layout = bind_group_layout(
                ctx,
                "sim/step/collider-layout",
                &[storage(3, c, true), storage(4, c, true), storage(5, c, true)],
            );
            let alone = pipeline_layout(ctx, "sim/step/state-pipeline-layout", &[Some(&state_layout)]);
            let with = |group: &wgpu::BindGroupLayout, label: &str| {
                pipeline_layout(ctx, label, &[Some(&state_layout), Some(group)])
            };
            let integrate_layout = with(&next_layout, "sim/step/integrate-pipeline-layout");
            let grid_pipeline_layout = with(&grid_layout, "sim/step/grid-pipeline-layout");
            let collider_pipeline_layout = with(&collider_layout, "sim/step/collider-pipeline-layout");
            let p = |e: &str, layout: &wgpu::PipelineLayout| {
                compute_pipeline(ctx, &format!("sim/step/{e}-pipeline"), &module, e, layout)
            };
            let uniform_binding = wgpu::BindGroupEntry {
                binding: 0,
                resource: wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                    buffer: &b.uniforms,
                    offset: 0,
                    size: wgpu::BufferSize::new(std::mem::size_of::<SimParams>() as u64),
                }),
            };
            let state = std::array::from_fn(|phase| {
                ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
                    label: Some("sim/step/state"),
                    layout: &state_layout,
                    entries: &[
                        uniform_binding.clone(),
                        buffer(1, &b.positions[phase % 3]),
                        buffer(2, &b.positions[(phase + 1) % 3]),
                        buffer(3, &b.rest),
                    ],
                })
            });
            let next = std::array::from_fn(|phase| {
                ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
                    label: Some("sim/step/next"),
                    layout: &next_layout,
                    entries: &[buffer(0, &b.positions[(phase + 2) % 3])],
                })
            });
            let grid = ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("sim/step/grid"),
                layout: &grid_layout,
                entries: &[buffer(1, &b.grid)],
            });
            let colliders = ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("sim/step/colliders"),
                layout: &collider_layout,
                entries: &[buffer(3, &b.offsets), buffer(4, &b.sdf), buffer(5, &b.shapes)],
            });
            SimStep {
                shock: p("shock", &alone),
                integrate: p("integrate", &integrate_layout),
                grid_clear: p("grid_clear", &grid_pipeline_layout),
                grid_splat: p("grid_splat", &grid_pipeline_layout),
                grid_apply: p("grid_apply", &grid_pipeline_layout),
                constraints: p("constraints", &collider_pipeline_layout),
                friction: p("friction", &collider_pipeline_layout),
                state,
                next,
                grid,
                colliders,
            }
        })
    }

    /// Record one substep whose uniforms are `params` in ring slot `slot`, the position buffers
    /// at turn `phase` (the caller advances it by one afterwards).
    /// With a `timer`, the substep's three compute passes (`sim/integrate`, `sim/grid`,
    /// `sim/constraints`) write their timestamps into object slot `slot`.
    pub(crate) fn encode(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        b: &SimBuffers,
        (phase, slot): (usize, usize),
        params: &SimParams,
        timer: Option<&GpuTimer>,
    ) {
        let offset = (slot as u64 * UNIFORM_STRIDE) as u32;
        let writes = |name: &'static str| {
            timer.and_then(|t| t.object_compute_writes(name, slot, true, true))
        };
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("sim/integrate"),
            timestamp_writes: writes("sim/integrate"),
        });
        let (vx, vy) = dispatch_2d(b.guide_vertices, 64);
        let after = (phase + 1) % 3;
        if params.shape[2] > 0.0 {
            pass.set_pipeline(&self.shock);
            pass.set_bind_group(0, &self.state[phase], &[offset]);
            pass.dispatch_workgroups(vx, vy, 1);
        }
        pass.set_pipeline(&self.integrate);
        pass.set_bind_group(0, &self.state[phase], &[offset]);
        pass.set_bind_group(1, &self.next[phase], &[]);
        pass.dispatch_workgroups(vx, vy, 1);
        drop(pass);
        // From here the new positions are the current ones.
        if params.counts2[2] != 0 {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("sim/grid"),
                timestamp_writes: writes("sim/grid"),
            });
            pass.set_bind_group(0, &self.state[after], &[offset]);
            pass.set_bind_group(1, &self.grid, &[]);
            let (nx, ny) = dispatch_2d(b.grid_nodes, 64);
            pass.set_pipeline(&self.grid_clear);
            pass.dispatch_workgroups(nx, ny, 1);
            pass.set_pipeline(&self.grid_splat);
            pass.dispatch_workgroups(vx, vy, 1);
            pass.set_pipeline(&self.grid_apply);
            pass.dispatch_workgroups(vx, vy, 1);
        }
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("sim/constraints"),
            timestamp_writes: writes("sim/constraints"),
        });
        pass.set_bind_group(0, &self.state[after], &[offset]);
        pass.set_bind_group(1, &self.colliders, &[]);
        let (sx, sy) = dispatch_2d(b.guides, 64);
        pass.set_pipeline(&self.constraints);
        pass.dispatch_workgroups(sx, sy, 1);
        pass.set_pipeline(&self.friction);
        pass.dispatch_workgroups(vx, vy, 1);
    }
}
