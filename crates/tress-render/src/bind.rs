//! Bind group layouts shared by several passes.
//!
//! | group | layout | contents |
//! | --- | --- | --- |
//! | 0 | `view` | camera uniform, strand params uniform |
//! | 1 | `lighting` | lights, material, one shadow map per light, the hair volume (texture, sampler, grid, params: volume shadows and AO) |
//! | 2 | `strands` | strand vertices and segments (vertex pulling; the voxelizer's compute passes) |
//! | 3 | pass-specific | e.g. the PPLL buffers of the build pass |

use crate::MAX_LIGHTS;

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

pub(crate) fn uniform(binding: u32, visibility: wgpu::ShaderStages) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Uniform,
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    }
}

pub(crate) fn storage(
    binding: u32,
    visibility: wgpu::ShaderStages,
    read_only: bool,
) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Storage { read_only },
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    }
}

pub(crate) fn depth_texture(
    binding: u32,
    visibility: wgpu::ShaderStages,
) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility,
        ty: wgpu::BindingType::Texture {
            sample_type: wgpu::TextureSampleType::Depth,
            view_dimension: wgpu::TextureViewDimension::D2,
            multisampled: false,
        },
        count: None,
    }
}

pub(crate) fn texture_3d(
    binding: u32,
    visibility: wgpu::ShaderStages,
) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility,
        ty: wgpu::BindingType::Texture {
            sample_type: wgpu::TextureSampleType::Float { filterable: true },
            view_dimension: wgpu::TextureViewDimension::D3,
            multisampled: false,
        },
        count: None,
    }
}

pub(crate) fn filtering_sampler(
    binding: u32,
    visibility: wgpu::ShaderStages,
) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility,
        ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
        count: None,
    }
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
        // The hair volume (`common/lighting.wgsl`): texture, sampler, grid, volume params.
        let v = 2 + MAX_LIGHTS as u32;
        entries.extend([
            texture_3d(v, wgpu::ShaderStages::FRAGMENT),
            filtering_sampler(v + 1, wgpu::ShaderStages::FRAGMENT),
            uniform(v + 2, VF),
            uniform(v + 3, VF),
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
