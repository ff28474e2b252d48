//! The [`Renderer`]'s construction and settings: pipelines, uniforms, the lighting bind group
//! (lights, material, shadow maps, the hair volume), techniques. A frame itself is in `renderer.rs`.

use super::{PASS_NAMES, Renderer};
use crate::bind::Layouts;
use crate::gpu::{TargetFormats, uniform_buffer};
use crate::head::HeadPass;
use crate::hybrid::{HybridSettings, LodBlend, TechniqueKind, check_technique};
use crate::services::FrameServices;
use crate::stats::StatsReadback;
use crate::strands::oit::StrandOit;
use crate::strands::{ShadowMap, StrandGeometry, StrandSettings};
use crate::volume::{Raymarch, VolumeBinding, VolumeSettings, Voxelizer, volume_resources};
use crate::{GpuContext, MAX_LIGHTS, RenderError};

impl Renderer {
    /// Build the pipelines for targets of `formats`, with `settings` (validated).
    pub fn new(
        ctx: &GpuContext,
        formats: TargetFormats,
        settings: StrandSettings,
    ) -> Result<Self, RenderError> {
        settings.validate()?;
        let layouts = ctx.scoped("creating bind group layouts", || Layouts::new(&ctx.device))?;
        let services = FrameServices::new(ctx, "frame", PASS_NAMES, super::MAX_OBJECTS)?;
        let params0 = ctx.scoped("creating uniforms", || {
            uniform_buffer(
                ctx,
                "frame/uniforms/params",
                &crate::gpu::types::StrandParams::default(),
            )
        })?;
        // The light cameras read the settings every head of hair shares from object 0's.
        let shadow = ShadowMap::new(ctx, &layouts, &params0, settings.shadow_map_size)?;
        let (_, volume_sampler, fallback_volume) = volume_resources(ctx)?;
        let mut renderer = Renderer {
            formats,
            technique: TechniqueKind::Strands,
            volume_settings: VolumeSettings::default(),
            hybrid: HybridSettings::default(),
            raymarch: Raymarch::new(ctx, &layouts, formats.color)?,
            lod_blend: LodBlend::new(ctx, formats.color)?,
            volume_sampler,
            fallback_volume,
            voxelizer: None,
            layers: None,
            head_pass: HeadPass::new(ctx, &layouts, formats.color)?,
            oit: StrandOit::new(ctx, &layouts, formats.color)?,
            settings,
            layouts,
            slots: Vec::new(),
            shadow,
            services,
            warned: Vec::new(),
            costs: crate::hybrid::budget::CostModel::default(),
        };
        let slot0 = renderer.new_slot(ctx, 0, Some(params0))?;
        renderer.slots.push(slot0);
        Ok(renderer)
    }

    pub(super) fn lighting_group(
        ctx: &GpuContext,
        layouts: &Layouts,
        lights: &wgpu::Buffer,
        material: &wgpu::Buffer,
        shadow: &ShadowMap,
        volume: VolumeBinding<'_>,
    ) -> Result<wgpu::BindGroup, RenderError> {
        let mut entries = vec![
            wgpu::BindGroupEntry {
                binding: 0,
                resource: lights.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 1,
                resource: material.as_entire_binding(),
            },
        ];
        entries.extend(shadow.layer_views().iter().enumerate().map(|(i, v)| {
            wgpu::BindGroupEntry {
                binding: 2 + i as u32,
                resource: wgpu::BindingResource::TextureView(v),
            }
        }));
        let v = 2 + MAX_LIGHTS as u32;
        entries.extend([
            wgpu::BindGroupEntry {
                binding: v,
                resource: wgpu::BindingResource::TextureView(volume.view),
            },
            wgpu::BindGroupEntry {
                binding: v + 1,
                resource: wgpu::BindingResource::Sampler(volume.sampler),
            },
            wgpu::BindGroupEntry {
                binding: v + 2,
                resource: volume.grid.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: v + 3,
                resource: volume.params.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: v + 4,
                resource: wgpu::BindingResource::TextureView(volume.ao_view),
            },
        ]);
        ctx.scoped("creating the lighting bind group", || {
            ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("frame/lighting/bind-group"),
                layout: &layouts.lighting,
                entries: &entries,
            })
        })
    }

    /// Upload a hair asset for this renderer (same as [`StrandGeometry::new`]).
    pub fn upload_hair(
        &self,
        ctx: &GpuContext,
        asset: &tress_hair::HairAsset,
    ) -> Result<StrandGeometry, RenderError> {
        StrandGeometry::with_layout(ctx, &self.layouts.strands, asset)
    }

    /// The current settings.
    pub fn settings(&self) -> &StrandSettings {
        &self.settings
    }

    /// Change settings (validated). A new shadow map size reallocates the maps; new OIT settings
    /// (pool, `oit`, `shortcut_k`) reallocate the OIT's buffers at the next frame.
    pub fn set_settings(
        &mut self,
        ctx: &GpuContext,
        settings: StrandSettings,
    ) -> Result<(), RenderError> {
        settings.validate()?;
        if settings.shadow_map_size != self.shadow.size() {
            self.shadow = ShadowMap::new(
                ctx,
                &self.layouts,
                &self.slots[0].params,
                settings.shadow_map_size,
            )?;
            self.refresh_lighting_groups(ctx, true)?;
        }
        if settings.ppll_nodes_per_pixel != self.settings.ppll_nodes_per_pixel
            || settings.ppll_max_bytes != self.settings.ppll_max_bytes
            || settings.oit != self.settings.oit
            || settings.shortcut_k != self.settings.shortcut_k
        {
            self.oit.reset();
        }
        self.settings = settings;
        Ok(())
    }

    /// The technique that draws `FrameInputs::hair` (default [`TechniqueKind::Strands`]).
    pub fn technique(&self) -> TechniqueKind {
        self.technique
    }

    /// Choose the technique that draws `FrameInputs::hair`: strands, volume, hybrid or auto
    /// (patches and SATF are errors, and leave it unchanged).
    pub fn set_technique(&mut self, technique: TechniqueKind) -> Result<(), RenderError> {
        self.technique = check_technique(technique)?;
        Ok(())
    }

    /// The volume settings.
    pub fn volume_settings(&self) -> &VolumeSettings {
        &self.volume_settings
    }

    /// Change the volume settings (validated, and the resolution checked against the device's
    /// limits). A new resolution reallocates the volumes now when they exist, else at the next
    /// frame that needs them.
    pub fn set_volume_settings(
        &mut self,
        ctx: &GpuContext,
        settings: VolumeSettings,
    ) -> Result<(), RenderError> {
        settings.validate()?;
        Voxelizer::check(ctx, settings.resolution)?;
        if let Some(v) = &mut self.voxelizer
            && v.resolution() != settings.resolution
        {
            v.set_resolution(ctx, settings.resolution)?;
            self.volume_settings = settings;
            return self.refresh_lighting_groups(ctx, true);
        }
        self.volume_settings = settings;
        Ok(())
    }

    /// The hybrid's settings.
    pub fn hybrid_settings(&self) -> &HybridSettings {
        &self.hybrid
    }

    /// Change the hybrid's settings (validated).
    pub fn set_hybrid_settings(&mut self, settings: HybridSettings) -> Result<(), RenderError> {
        settings.validate()?;
        self.hybrid = settings;
        Ok(())
    }

    /// The voxelizer, once a frame has needed the volume (for tools: its texture, a readback).
    pub fn voxelizer(&self) -> Option<&Voxelizer> {
        self.voxelizer.as_ref()
    }

    /// Bytes of the shadow maps (one depth layer per possible light).
    pub fn shadow_bytes(&self) -> u64 {
        self.shadow.bytes()
    }

    /// How `render` reports GPU results (default [`StatsReadback::Wait`]).
    pub fn set_stats_readback(&mut self, mode: StatsReadback) {
        self.services.readback = mode;
    }
}
