//! [`ShortcutThreshold`], owner of `shortcut_threshold.wgsl`.

use crate::bind::{bind_group, bind_group_layout, storage};
use crate::gpu::pipeline::{compute_pipeline, pipeline_layout};
use crate::strands::shortcut::ShortcutBuffers;
use crate::{GpuContext, RenderError, shaders};

/// Invocations per workgroup (`@workgroup_size` of `cs_main`).
const WORKGROUP: u32 = 64;
/// Workgroups along x before the dispatch wraps into y (the shader's `65535u`).
const MAX_GROUPS_X: u32 = 65535;

/// ShortCut's threshold pass: each pixel's k-th nearest key, copied after the depth pass.
#[derive(Debug)]
pub struct ShortcutThreshold {
    pipeline: wgpu::ComputePipeline,
    layout: wgpu::BindGroupLayout,
}

impl ShortcutThreshold {
    pub(crate) fn new(ctx: &GpuContext) -> Result<Self, RenderError> {
        let module = shaders::create_module(
            ctx,
            "strands/shortcut_threshold.wgsl",
            "strands/shortcut_threshold/shader",
        )?;
        ctx.scoped("creating the ShortCut threshold pipeline", || {
            let compute = wgpu::ShaderStages::COMPUTE;
            let layout = bind_group_layout(
                ctx,
                "strands/shortcut_threshold/layout",
                &[
                    storage(0, compute, false),
                    storage(1, compute, false),
                    storage(2, compute, false),
                ],
            );
            let pipeline_layout = pipeline_layout(
                ctx,
                "strands/shortcut_threshold/pipeline-layout",
                &[Some(&layout)],
            );
            let pipeline = compute_pipeline(
                ctx,
                "strands/shortcut_threshold/pipeline",
                &module,
                "cs_main",
                &pipeline_layout,
            );
            ShortcutThreshold { pipeline, layout }
        })
    }

    /// Record the pass over every pixel of `buffers`' target.
    pub(crate) fn encode(
        &self,
        ctx: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        buffers: &ShortcutBuffers,
        timestamps: Option<wgpu::ComputePassTimestampWrites<'_>>,
    ) {
        let group = bind_group(
            ctx,
            "strands/shortcut_threshold/bind-group",
            &self.layout,
            &[
                (0, buffers.keys.as_entire_binding()),
                (1, buffers.far.as_entire_binding()),
                (2, buffers.falloff.as_entire_binding()),
            ],
        );
        // One invocation a pair of pixels.
        let groups = (buffers.size[0] * buffers.size[1]).div_ceil(2 * WORKGROUP);
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("strands/shortcut_threshold/pass"),
            timestamp_writes: timestamps,
        });
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &group, &[]);
        pass.dispatch_workgroups(groups.min(MAX_GROUPS_X), groups.div_ceil(MAX_GROUPS_X), 1);
    }
}
