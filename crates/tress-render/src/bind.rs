//! Bind group layouts shared by several passes, and the builders of layout entries, layouts and
//! bind groups that every pass uses.
//!
//! | group | layout | contents |
//! | --- | --- | --- |
//! | 0 | `view` | camera uniform, strand params uniform |
//! | 1 | `lighting` | lights, material, one shadow map per light, the hair volume (texture, sampler, grid, params, baked AO texture: volume shadows and AO) |
//! | 2 | `strands` | strand vertices and segments (vertex pulling; the voxelizer's compute passes) |
//! | 3 | pass-specific | e.g. the PPLL buffers of the build pass |

use crate::{GpuContext, MAX_LIGHTS};

/// The shared layouts, created once per renderer.
#[derive(Debug)]
pub(crate) struct Layouts {
    pub(crate) view: wgpu::BindGroupLayout,
    pub(crate) lighting: wgpu::BindGroupLayout,
    pub(crate) strands: wgpu::BindGroupLayout,
}

const VF: wgpu::ShaderStages = wgpu::ShaderStages::VERTEX_FRAGMENT;
const VERTEX_COMPUTE: wgpu::ShaderStages =
    wgpu::ShaderStages::VERTEX.union(wgpu::ShaderStages::COMPUTE);

/// A layout entry: `ty` at `binding`, visible to `visibility`, not an array.
pub(crate) fn entry(
    binding: u32,
    visibility: wgpu::ShaderStages,
    ty: wgpu::BindingType,
) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility,
        ty,
        count: None,
    }
}

/// A buffer binding of `ty`, without dynamic offset or minimum size.
pub(crate) fn buffer_type(ty: wgpu::BufferBindingType) -> wgpu::BindingType {
    wgpu::BindingType::Buffer {
        ty,
        has_dynamic_offset: false,
        min_binding_size: None,
    }
}

/// A single-sampled texture binding.
pub(crate) fn texture_type(
    sample_type: wgpu::TextureSampleType,
    view_dimension: wgpu::TextureViewDimension,
) -> wgpu::BindingType {
    wgpu::BindingType::Texture {
        sample_type,
        view_dimension,
        multisampled: false,
    }
}

pub(crate) fn uniform(binding: u32, visibility: wgpu::ShaderStages) -> wgpu::BindGroupLayoutEntry {
    entry(
        binding,
        visibility,
        buffer_type(wgpu::BufferBindingType::Uniform),
    )
}

pub(crate) fn storage(
    binding: u32,
    visibility: wgpu::ShaderStages,
    read_only: bool,
) -> wgpu::BindGroupLayoutEntry {
    entry(
        binding,
        visibility,
        buffer_type(wgpu::BufferBindingType::Storage { read_only }),
    )
}

const UNFILTERABLE: wgpu::TextureSampleType = wgpu::TextureSampleType::Float { filterable: false };
const FILTERABLE: wgpu::TextureSampleType = wgpu::TextureSampleType::Float { filterable: true };
const D2: wgpu::TextureViewDimension = wgpu::TextureViewDimension::D2;

/// A 2D float texture read with `textureLoad` (not filterable, so `r32float` is allowed too).
pub(crate) fn texture_2d(
    binding: u32,
    visibility: wgpu::ShaderStages,
) -> wgpu::BindGroupLayoutEntry {
    entry(binding, visibility, texture_type(UNFILTERABLE, D2))
}

/// A 2D float texture sampled with filtering.
pub(crate) fn filterable_texture_2d(
    binding: u32,
    visibility: wgpu::ShaderStages,
) -> wgpu::BindGroupLayoutEntry {
    entry(binding, visibility, texture_type(FILTERABLE, D2))
}

pub(crate) fn depth_texture(
    binding: u32,
    visibility: wgpu::ShaderStages,
) -> wgpu::BindGroupLayoutEntry {
    entry(
        binding,
        visibility,
        texture_type(wgpu::TextureSampleType::Depth, D2),
    )
}

pub(crate) fn texture_3d(
    binding: u32,
    visibility: wgpu::ShaderStages,
) -> wgpu::BindGroupLayoutEntry {
    entry(
        binding,
        visibility,
        texture_type(FILTERABLE, wgpu::TextureViewDimension::D3),
    )
}

/// A write-only 3D storage texture of `format`.
pub(crate) fn write_texture_3d(
    binding: u32,
    visibility: wgpu::ShaderStages,
    format: wgpu::TextureFormat,
) -> wgpu::BindGroupLayoutEntry {
    entry(
        binding,
        visibility,
        wgpu::BindingType::StorageTexture {
            access: wgpu::StorageTextureAccess::WriteOnly,
            format,
            view_dimension: wgpu::TextureViewDimension::D3,
        },
    )
}

pub(crate) fn filtering_sampler(
    binding: u32,
    visibility: wgpu::ShaderStages,
) -> wgpu::BindGroupLayoutEntry {
    let filtering = wgpu::SamplerBindingType::Filtering;
    entry(binding, visibility, wgpu::BindingType::Sampler(filtering))
}

/// A bind group layout of `entries`.
pub(crate) fn bind_group_layout(
    ctx: &GpuContext,
    label: &str,
    entries: &[wgpu::BindGroupLayoutEntry],
) -> wgpu::BindGroupLayout {
    ctx.device
        .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some(label),
            entries,
        })
}

/// A bind group of `entries` (`(binding, resource)`).
pub(crate) fn bind_group(
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

impl Layouts {
    pub(crate) fn new(device: &wgpu::Device) -> Self {
        let view = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("frame/view/layout"),
            entries: &[uniform(0, VF), uniform(1, VF)],
        });
        let mut entries = vec![
            uniform(0, wgpu::ShaderStages::FRAGMENT),
            uniform(1, wgpu::ShaderStages::FRAGMENT),
        ];
        entries.extend(
            (0..MAX_LIGHTS as u32).map(|i| depth_texture(2 + i, wgpu::ShaderStages::FRAGMENT)),
        );
        // The hair volume (`common/lighting.wgsl`): texture, sampler, grid, volume params, baked
        // ambient occlusion.
        let v = 2 + MAX_LIGHTS as u32;
        entries.extend([
            texture_3d(v, wgpu::ShaderStages::FRAGMENT),
            filtering_sampler(v + 1, wgpu::ShaderStages::FRAGMENT),
            uniform(v + 2, VF),
            uniform(v + 3, VF),
            texture_3d(v + 4, wgpu::ShaderStages::FRAGMENT),
        ]);
        let lighting = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("frame/lighting/layout"),
            entries: &entries,
        });
        let strands = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("strands/geometry/layout"),
            entries: &[
                storage(0, VERTEX_COMPUTE, true),
                storage(1, VERTEX_COMPUTE, true),
            ],
        });
        Layouts {
            view,
            lighting,
            strands,
        }
    }
}
