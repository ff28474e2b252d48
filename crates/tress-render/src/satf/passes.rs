//! Small builders shared by the SATF passes: bind group layouts from a list of slots, compute
//! pipelines, the per-texel passes over the atlas tiles ([`TilePass`]), and the atlas textures.

use super::geometry::SatfLayout;
use crate::bind::{bind_group, bind_group_layout, buffer_type, entry, texture_type};
use crate::gpu::pipeline::{compute_pipeline, pipeline_layout};
use crate::{GpuContext, RenderError, shaders};

/// What a binding holds.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Slot {
    /// A uniform buffer.
    Uniform,
    /// A storage buffer.
    Storage {
        /// Read-only in the shader.
        read_only: bool,
    },
    /// A 2D float texture read with `textureLoad` (not filterable: r32float is allowed).
    Texture,
    /// A 2D array depth texture read with `textureLoad`.
    DepthArray,
    /// A 2D array `u32` texture.
    UintArray,
    /// A write-only 2D storage texture.
    StorageTexture(wgpu::TextureFormat),
}

/// A bind group layout of `slots` (`(binding, slot)`) visible to `visibility`.
pub(crate) fn layout(
    ctx: &GpuContext,
    label: &str,
    visibility: wgpu::ShaderStages,
    slots: &[(u32, Slot)],
) -> wgpu::BindGroupLayout {
    let entries: Vec<wgpu::BindGroupLayoutEntry> = slots
        .iter()
        .map(|&(binding, slot)| {
            let ty = match slot {
                Slot::Uniform => buffer_type(wgpu::BufferBindingType::Uniform),
                Slot::Storage { read_only } => {
                    buffer_type(wgpu::BufferBindingType::Storage { read_only })
                }
                Slot::Texture => texture_type(
                    wgpu::TextureSampleType::Float { filterable: false },
                    wgpu::TextureViewDimension::D2,
                ),
                Slot::DepthArray => texture_type(
                    wgpu::TextureSampleType::Depth,
                    wgpu::TextureViewDimension::D2Array,
                ),
                Slot::UintArray => texture_type(
                    wgpu::TextureSampleType::Uint,
                    wgpu::TextureViewDimension::D2Array,
                ),
                Slot::StorageTexture(format) => wgpu::BindingType::StorageTexture {
                    access: wgpu::StorageTextureAccess::WriteOnly,
                    format,
                    view_dimension: wgpu::TextureViewDimension::D2,
                },
            };
            entry(binding, visibility, ty)
        })
        .collect();
    bind_group_layout(ctx, label, &entries)
}

/// Compute pipelines for `entries` of the crate module `path`, all with `layout`, labelled
/// `{label}/{entry}`.
pub(crate) fn compute_pipelines<const N: usize>(
    ctx: &GpuContext,
    path: &str,
    label: &str,
    layout: &wgpu::PipelineLayout,
    entries: [&str; N],
) -> Result<[wgpu::ComputePipeline; N], RenderError> {
    let module = shaders::create_module(ctx, path, &format!("{label}/shader"))?;
    ctx.scoped(&format!("creating the {label} pipelines"), || {
        entries
            .map(|entry| compute_pipeline(ctx, &format!("{label}/{entry}"), &module, entry, layout))
    })
}

/// A compute pass of `satf/{name}.wgsl`'s `cs_main` over every texel of every tile (8 × 8
/// texels a workgroup, one tile a z slice), with one bind group: what the per-texel passes
/// ([`super::MapBuild`], [`super::SMaps`], [`super::Lighting`]) share. Labels are
/// `satf/{name}/…`.
#[derive(Debug)]
pub(crate) struct TilePass {
    name: &'static str,
    layout: wgpu::BindGroupLayout,
    pipeline: wgpu::ComputePipeline,
}

impl TilePass {
    /// The pass `name` with a bind group of `slots`.
    pub(crate) fn new(
        ctx: &GpuContext,
        name: &'static str,
        slots: &[(u32, Slot)],
    ) -> Result<Self, RenderError> {
        let label = format!("satf/{name}");
        let layout = layout(
            ctx,
            &format!("{label}/layout"),
            wgpu::ShaderStages::COMPUTE,
            slots,
        );
        let pl = pipeline_layout(ctx, &format!("{label}/pipeline-layout"), &[Some(&layout)]);
        let [pipeline] =
            compute_pipelines(ctx, &format!("{label}.wgsl"), &label, &pl, ["cs_main"])?;
        Ok(TilePass {
            name,
            layout,
            pipeline,
        })
    }

    /// Record the pass with `entries` bound, over every tile of `tiles`.
    pub(crate) fn encode(
        &self,
        ctx: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        entries: &[(u32, wgpu::BindingResource<'_>)],
        tiles: &SatfLayout,
        timestamps: Option<wgpu::ComputePassTimestampWrites<'_>>,
    ) {
        let name = self.name;
        let bind = bind_group(
            ctx,
            &format!("satf/{name}/bind-group"),
            &self.layout,
            entries,
        );
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some(&format!("satf/{name}/pass")),
            timestamp_writes: timestamps,
        });
        pass.set_bind_group(0, &bind, &[]);
        pass.set_pipeline(&self.pipeline);
        pass.dispatch_workgroups(
            groups(tiles.tile_width, 8),
            groups(tiles.tile_height, 8),
            tiles.tiles(),
        );
    }
}

/// Workgroups of `size` covering `n` invocations.
pub(crate) fn groups(n: u32, size: u32) -> u32 {
    n.div_ceil(size)
}
