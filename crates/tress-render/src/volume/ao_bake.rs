//! [`AoBake`], owner of `ao_bake.wgsl`: local ambient occlusion baked once a voxelization into a
//! texture of `volume.ao_texel`³ voxels a texel.

use crate::bind::{bind_group_layout, filtering_sampler, storage, uniform, write_texture_3d};
use crate::gpu::pipeline::{compute_pipeline, pipeline_layout};
use crate::{GpuContext, RenderError, shaders};

/// Format of the baked AO texture: r the visibility (4 bytes a texel). `rgba8unorm` is a storage
/// format everywhere and filterable; 8 bits of visibility are finer than the trilinear filter's
/// own error.
pub const AO_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;

/// Texels per axis of the AO texture of a `res³` grid at `texel` voxels a texel (at least 1).
pub fn ao_resolution(res: u32, texel: u32) -> u32 {
    res.div_ceil(texel.max(1))
}

/// The bake pass: one invocation per AO texel.
#[derive(Debug)]
pub struct AoBake {
    pipeline: wgpu::ComputePipeline,
    pub(crate) layout: wgpu::BindGroupLayout,
}

impl AoBake {
    pub(crate) fn new(ctx: &GpuContext) -> Result<Self, RenderError> {
        let module = shaders::create_module(ctx, "volume/ao_bake.wgsl", "volume/ao_bake/shader")?;
        ctx.scoped("creating the ambient-occlusion bake pipeline", || {
            let c = wgpu::ShaderStages::COMPUTE;
            let layout = bind_group_layout(
                ctx,
                "volume/ao_bake/layout",
                &[
                    uniform(0, c),
                    storage(1, c, true),
                    storage(2, c, true),
                    crate::bind::texture_3d(3, c),
                    filtering_sampler(4, c),
                    write_texture_3d(5, c, AO_FORMAT),
                ],
            );
            let pipeline_layout =
                pipeline_layout(ctx, "volume/ao_bake/pipeline-layout", &[Some(&layout)]);
            let pipeline = compute_pipeline(
                ctx,
                "volume/ao_bake/pipeline",
                &module,
                "bake",
                &pipeline_layout,
            );
            AoBake { pipeline, layout }
        })
    }

    /// Record the bake of an AO texture of `ao_res³` texels.
    pub(crate) fn encode(
        &self,
        pass: &mut wgpu::ComputePass<'_>,
        group: &wgpu::BindGroup,
        ao_res: u32,
    ) {
        let n = ao_res.div_ceil(4);
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, group, &[]);
        pass.dispatch_workgroups(n, n, n);
    }
}
