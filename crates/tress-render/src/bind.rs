//! Bind group layouts shared by several passes.
//!
//! | group | layout | contents |
//! | --- | --- | --- |
//! | 0 | `view` | camera uniform, strand params uniform |
//! | 1 | `lighting` | lights, material, one shadow map per light (head and strand shading) |
//! | 2 | `strands` | strand vertices and segments (vertex pulling) |
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
        let lighting = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("frame/lighting/layout"),
            entries: &entries,
        });
        let strands = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("strands/geometry/layout"),
            entries: &[
                storage(0, wgpu::ShaderStages::VERTEX, true),
                storage(1, wgpu::ShaderStages::VERTEX, true),
            ],
        });
        Layouts {
            view,
            lighting,
            strands,
        }
    }
}
