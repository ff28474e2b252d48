//! [`VolumeResolve`], owner of `volume_resolve.wgsl`.

use crate::bind::{bind_group_layout, storage, uniform, write_texture_3d};
use crate::gpu::pipeline::{compute_pipeline, pipeline_layout};
use crate::{GpuContext, RenderError, shaders};

/// Format of the volume texture, 4 bytes a voxel: rgb the mean tangent, a the count, as
/// `tress_shading::voxelize::encode_texel` writes them.
pub const VOLUME_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;

/// The resolve pass: counters to the trilinearly sampled 3D texture, and the occupancy blocks.
#[derive(Debug)]
pub struct VolumeResolve {
    pipeline: wgpu::ComputePipeline,
    pub(crate) layout: wgpu::BindGroupLayout,
}

impl VolumeResolve {
    pub(crate) fn new(ctx: &GpuContext) -> Result<Self, RenderError> {
        let module = shaders::create_module(
            ctx,
            "volume/volume_resolve.wgsl",
            "volume/volume_resolve/shader",
        )?;
        ctx.scoped("creating the volume resolve pipeline", || {
            let c = wgpu::ShaderStages::COMPUTE;
            let layout = bind_group_layout(
                ctx,
                "volume/volume_resolve/layout",
                &[
                    uniform(0, c),
                    storage(1, c, true),
                    storage(2, c, true),
                    storage(3, c, true),
                    storage(4, c, true),
                    write_texture_3d(5, c, VOLUME_FORMAT),
                    storage(6, c, false),
                    storage(7, c, true),
                    storage(8, c, false),
                    storage(9, c, true),
                    write_texture_3d(10, c, VOLUME_FORMAT),
                ],
            );
            let pipeline_layout = pipeline_layout(
                ctx,
                "volume/volume_resolve/pipeline-layout",
                &[Some(&layout)],
            );
            let pipeline = compute_pipeline(
                ctx,
                "volume/volume_resolve/pipeline",
                &module,
                "resolve",
                &pipeline_layout,
            );
            VolumeResolve { pipeline, layout }
        })
    }

    /// Record one invocation per voxel of the region the bounds pass wrote into `args` (a
    /// `ResolveArgs` buffer: its first 12 bytes are the indirect dispatch).
    pub(crate) fn encode(
        &self,
        pass: &mut wgpu::ComputePass<'_>,
        group: &wgpu::BindGroup,
        args: &wgpu::Buffer,
    ) {
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, group, &[]);
        pass.dispatch_workgroups_indirect(args, 0);
    }
}
