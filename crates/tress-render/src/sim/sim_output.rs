//! [`SimOutput`], owner of `sim_output.wgsl`: the simulated hair into a renderer's vertices.

use std::collections::HashMap;
use std::sync::Mutex;

use super::buffers::SimBuffers;
use crate::bind::{bind_group_layout, storage, uniform};
use crate::gpu::GpuTimer;
use crate::gpu::pipeline::{compute_pipeline, pipeline_layout};
use crate::volume::dispatch_2d;
use crate::{GpuContext, RenderError, StrandGeometry, shaders};

fn entry(binding: u32, buffer: &wgpu::Buffer) -> wgpu::BindGroupEntry<'_> {
    wgpu::BindGroupEntry {
        binding,
        resource: buffer.as_entire_binding(),
    }
}

/// The output pipelines and their bind groups; the group over a geometry's vertex buffer is
/// made on first use and kept (keyed by the buffer and the turn of the position buffers).
#[derive(Debug)]
pub(crate) struct SimOutput {
    frames: wgpu::ComputePipeline,
    guides: wgpu::ComputePipeline,
    followers: wgpu::ComputePipeline,
    lengths: wgpu::ComputePipeline,
    out_layout: wgpu::BindGroupLayout,
    guide_group: wgpu::BindGroup,
    follower_group: wgpu::BindGroup,
    out_groups: Mutex<HashMap<(wgpu::Buffer, usize), wgpu::BindGroup>>,
}

impl SimOutput {
    pub(crate) fn new(ctx: &GpuContext, b: &SimBuffers) -> Result<Self, RenderError> {
        let module = shaders::create_module(ctx, "sim/sim_output.wgsl", "sim/output/shader")?;
        ctx.scoped("creating the simulation output pipelines", || {
            let c = wgpu::ShaderStages::COMPUTE;
            let out_layout = bind_group_layout(
                ctx,
                "sim/output/layout",
                &[
                    uniform(0, c),
                    storage(1, c, true),
                    storage(2, c, true),
                    storage(3, c, false),
                    storage(4, c, false),
                ],
            );
            let guide_layout = bind_group_layout(
                ctx,
                "sim/output/guide-layout",
                &[storage(0, c, true), storage(1, c, true)],
            );
            let follower_layout = bind_group_layout(
                ctx,
                "sim/output/follower-layout",
                &[
                    storage(2, c, true),
                    storage(3, c, true),
                    storage(4, c, true),
                ],
            );
            let guide_pipeline_layout = pipeline_layout(
                ctx,
                "sim/output/guide-pipeline-layout",
                &[Some(&out_layout), Some(&guide_layout)],
            );
            let follower_pipeline_layout = pipeline_layout(
                ctx,
                "sim/output/follower-pipeline-layout",
                &[Some(&out_layout), Some(&follower_layout)],
            );
            let p = |e: &str, layout: &wgpu::PipelineLayout| {
                compute_pipeline(ctx, &format!("sim/output/{e}-pipeline"), &module, e, layout)
            };
            SimOutput {
                frames: p("write_frames", &guide_pipeline_layout),
                guides: p("write_guides", &guide_pipeline_layout),
                followers: p("write_followers", &follower_pipeline_layout),
                lengths: p("fix_follower_lengths", &follower_pipeline_layout),
                guide_group: ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
                    label: Some("sim/output/guide-group"),
                    layout: &guide_layout,
                    entries: &[entry(0, &b.rest), entry(1, &b.guide_first)],
                }),
                follower_group: ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
                    label: Some("sim/output/follower-group"),
                    layout: &follower_layout,
                    entries: &[
                        entry(2, &b.followers),
                        entry(3, &b.follower_vertex_data),
                        entry(4, &b.follower_len),
                    ],
                }),
                out_layout,
                out_groups: Mutex::new(HashMap::new()),
            }
        })
    }

    /// Record the output dispatches: positions at turn `phase` into `geometry`'s vertices.
    pub(crate) fn encode(
        &self,
        ctx: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        b: &SimBuffers,
        phase: usize,
        geometry: &StrandGeometry,
        timer: Option<&GpuTimer>,
    ) {
        let target = geometry.vertex_buffer();
        let mut groups = self.out_groups.lock().unwrap_or_else(|e| e.into_inner());
        let group = groups
            .entry((target.clone(), phase % 3))
            .or_insert_with(|| {
                ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
                    label: Some("sim/output/group"),
                    layout: &self.out_layout,
                    entries: &[
                        entry(0, &b.output_uniform),
                        entry(1, &b.positions[(phase + 1) % 3]),
                        entry(2, &b.offsets),
                        entry(3, &b.frames),
                        entry(4, target),
                    ],
                })
            });
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("sim/output/pass"),
            timestamp_writes: timer.and_then(|t| t.compute_writes("sim/output", true, true)),
        });
        pass.set_bind_group(0, &*group, &[]);
        let (gx, gy) = dispatch_2d(b.guide_vertices, 64);
        pass.set_bind_group(1, &self.guide_group, &[]);
        pass.set_pipeline(&self.frames);
        pass.dispatch_workgroups(gx, gy, 1);
        pass.set_pipeline(&self.guides);
        pass.dispatch_workgroups(gx, gy, 1);
        if b.follower_vertices > 0 {
            let (fx, fy) = dispatch_2d(b.follower_vertices, 64);
            pass.set_bind_group(1, &self.follower_group, &[]);
            pass.set_pipeline(&self.followers);
            pass.dispatch_workgroups(fx, fy, 1);
            let (lx, ly) = dispatch_2d(b.followers_count, 64);
            pass.set_pipeline(&self.lengths);
            pass.dispatch_workgroups(lx, ly, 1);
        }
    }
}
