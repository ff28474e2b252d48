//! Small builders shared by the SATF passes: bind group layouts from a list of slots, bind groups
//! from a list of resources, compute pipelines, and the atlas textures.

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
        .map(|&(binding, slot)| wgpu::BindGroupLayoutEntry {
            binding,
            visibility,
            ty: match slot {
                Slot::Uniform => wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Uniform,
                    has_dynamic_offset: false,
                    min_binding_size: None,
                },
                Slot::Storage { read_only } => wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Storage { read_only },
                    has_dynamic_offset: false,
                    min_binding_size: None,
                },
                Slot::Texture => wgpu::BindingType::Texture {
                    sample_type: wgpu::TextureSampleType::Float { filterable: false },
                    view_dimension: wgpu::TextureViewDimension::D2,
                    multisampled: false,
                },
                Slot::DepthArray => wgpu::BindingType::Texture {
                    sample_type: wgpu::TextureSampleType::Depth,
                    view_dimension: wgpu::TextureViewDimension::D2Array,
                    multisampled: false,
                },
                Slot::UintArray => wgpu::BindingType::Texture {
                    sample_type: wgpu::TextureSampleType::Uint,
                    view_dimension: wgpu::TextureViewDimension::D2Array,
                    multisampled: false,
                },
                Slot::StorageTexture(format) => wgpu::BindingType::StorageTexture {
                    access: wgpu::StorageTextureAccess::WriteOnly,
                    format,
                    view_dimension: wgpu::TextureViewDimension::D2,
                },
            },
            count: None,
        })
        .collect();
    ctx.device
        .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some(label),
            entries: &entries,
        })
}

/// A bind group of `entries` (`(binding, resource)`).
pub(crate) fn group(
    ctx: &GpuContext,
    label: &str,
    layout: &wgpu::BindGroupLayout,
    entries: &[(u32, wgpu::BindingResource<'_>)],
) -> wgpu::BindGroup {
    let entries: Vec<wgpu::BindGroupEntry<'_>> = entries
        .iter()
        .map(|(binding, resource)| wgpu::BindGroupEntry {
            binding: *binding,
            resource: resource.clone(),
        })
        .collect();
    ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some(label),
        layout,
        entries: &entries,
    })
}

/// A pipeline layout of one bind group layout.
pub(crate) fn pipeline_layout(
    ctx: &GpuContext,
    label: &str,
    group: &wgpu::BindGroupLayout,
) -> wgpu::PipelineLayout {
    ctx.device
        .create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some(label),
            bind_group_layouts: &[Some(group)],
            immediate_size: 0,
        })
}

/// Compute pipelines for `entries` of the crate module `path`, all with `layout`.
pub(crate) fn compute_pipelines(
    ctx: &GpuContext,
    path: &str,
    label: &str,
    layout: &wgpu::PipelineLayout,
    entries: &[&str],
) -> Result<Vec<wgpu::ComputePipeline>, RenderError> {
    let module = shaders::create_module(ctx, path, &format!("{label}/shader"))?;
    ctx.scoped(&format!("creating the {label} pipelines"), || {
        entries
            .iter()
            .map(|entry| {
                ctx.device
                    .create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                        label: Some(&format!("{label}/{entry}")),
                        layout: Some(layout),
                        module: &module,
                        entry_point: Some(entry),
                        compilation_options: Default::default(),
                        cache: None,
                    })
            })
            .collect()
    })
}

/// Workgroups of `size` covering `n` invocations.
pub(crate) fn groups(n: u32, size: u32) -> u32 {
    n.div_ceil(size)
}
