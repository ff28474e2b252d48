//! The heads of hair of a frame: [`HairObject`] (what the caller draws), and each one's GPU
//! state in the [`Renderer`] ([`ObjectSlot`]: its strand settings, material and volume
//! uniforms, and the view and lighting bind groups over them and the frame's shared camera,
//! lights, shadow maps and volume sampler).
//!
//! Object `i` of a frame always uses slot `i`, so a frame of one head of hair uses exactly the
//! buffers it always did.

use crate::bind::Layouts;
use crate::gpu::types::{FiberCache, MaterialUniform, StrandParams, VolumeParams};
use crate::gpu::uniform_buffer;
use crate::hybrid::{FramePlan, TechniqueKind};
use crate::strands::StrandGeometry;
use crate::volume::VolumeSettings;
use crate::volume::{VolumeBinding, Voxelizer};
use crate::{GpuContext, Material, RenderError};

use super::Renderer;

/// Most heads of hair one frame draws (each has its uniforms, its timestamps and, when
/// voxelized, its volume).
pub const MAX_OBJECTS: usize = 64;

/// One head of hair in a frame: its strands, material and technique (a character of a crowd).
#[derive(Clone, Copy, Debug)]
pub struct HairObject<'a> {
    /// The strands, uploaded with [`Renderer::upload_hair`].
    pub hair: &'a StrandGeometry,
    /// Its material.
    pub material: Material,
    /// What draws it: strands, volume, hybrid or auto (by its size on screen); patches and
    /// SATF are errors.
    pub technique: TechniqueKind,
}

/// The renderer's state for one head of hair of a frame.
#[derive(Debug)]
pub(crate) struct ObjectSlot {
    pub(crate) params: wgpu::Buffer,
    pub(crate) material: wgpu::Buffer,
    pub(crate) volume_params: wgpu::Buffer,
    pub(crate) view_group: wgpu::BindGroup,
    pub(crate) lighting_group: wgpu::BindGroup,
    /// The serial of the object's own volume the lighting group shows (`None`: the empty one).
    pub(crate) shows_volume: Option<u64>,
    /// The material fibre's uniform (filled only while the strands shade with it).
    pub(crate) fiber: FiberCache,
}

/// What a frame draws for one head of hair: its strands (none: a frame of the head only), its
/// material and its plan.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Drawn<'a> {
    pub(crate) hair: Option<&'a StrandGeometry>,
    pub(crate) material: Material,
    pub(crate) plan: FramePlan,
}

impl Renderer {
    /// A new slot's buffers (its strand settings in `params` when given) and bind groups
    /// (showing object `index`'s volume if it has one).
    pub(super) fn new_slot(
        &self,
        ctx: &GpuContext,
        index: usize,
        params: Option<wgpu::Buffer>,
    ) -> Result<ObjectSlot, RenderError> {
        let (params, material, volume_params) = ctx.scoped("creating uniforms", || {
            (
                params.unwrap_or_else(|| {
                    uniform_buffer(ctx, "frame/uniforms/params", &StrandParams::default())
                }),
                uniform_buffer(ctx, "frame/uniforms/material", &MaterialUniform::default()),
                uniform_buffer(ctx, "volume/params", &VolumeParams::default()),
            )
        })?;
        let view_group = view_group(ctx, &self.layouts, &self.services.camera, &params)?;
        let volume = self.voxelizer.as_ref().and_then(|v| v.grid_serial(index));
        let lighting_group = self.slot_lighting_group(ctx, index, &material, &volume_params)?;
        Ok(ObjectSlot {
            params,
            material,
            volume_params,
            view_group,
            lighting_group,
            shows_volume: volume,
            fiber: FiberCache::default(),
        })
    }

    /// The lighting group of object `index` over its `material` and `volume_params`: the
    /// frame's lights and shadow maps, and its own volume (the empty one while it has none).
    pub(super) fn slot_lighting_group(
        &self,
        ctx: &GpuContext,
        index: usize,
        material: &wgpu::Buffer,
        volume_params: &wgpu::Buffer,
    ) -> Result<wgpu::BindGroup, RenderError> {
        let own = self
            .voxelizer
            .as_ref()
            .and_then(|v| Some((v.object_view(index)?, v.grid_uniform(index)?)));
        let (view, grid) = own.unwrap_or((&self.fallback_volume.0, &self.fallback_volume.1));
        // Without a baked AO texture (nothing reads AO, or `volume.ao_texel = 0`) the empty
        // volume's texture stands in for it: it is never read.
        let ao_view = self
            .voxelizer
            .as_ref()
            .and_then(|v| v.ao_view(index))
            .unwrap_or(&self.fallback_volume.0);
        Self::lighting_group(
            ctx,
            &self.layouts,
            &self.services.lights,
            material,
            &self.shadow,
            VolumeBinding {
                view,
                ao_view,
                sampler: &self.volume_sampler,
                grid,
                params: volume_params,
            },
        )
    }

    /// Slots for `count` objects (at least one).
    pub(super) fn ensure_slots(
        &mut self,
        ctx: &GpuContext,
        count: usize,
    ) -> Result<(), RenderError> {
        while self.slots.len() < count.max(1) {
            let slot = self.new_slot(ctx, self.slots.len(), None)?;
            self.slots.push(slot);
        }
        Ok(())
    }

    /// Rebuild the lighting group of every slot whose volume changed (was allocated, resized or
    /// freed), or of all (`force`: the shadow maps or the volume's resolution changed).
    pub(super) fn refresh_lighting_groups(
        &mut self,
        ctx: &GpuContext,
        force: bool,
    ) -> Result<(), RenderError> {
        for i in 0..self.slots.len() {
            let has = self.voxelizer.as_ref().and_then(|v| v.grid_serial(i));
            if force || has != self.slots[i].shows_volume {
                let slot = &self.slots[i];
                let group =
                    self.slot_lighting_group(ctx, i, &slot.material, &slot.volume_params)?;
                self.slots[i].lighting_group = group;
                self.slots[i].shows_volume = has;
            }
        }
        Ok(())
    }

    /// The grid resolution of object `i` drawn as `d` this frame: by its size on screen
    /// ([`VolumeSettings::object_resolution`]), its current one kept while what it needs is
    /// at least two thirds of it (one step of hysteresis: a character moving to and fro across
    /// a step does not change resolution every frame).
    ///
    /// A character whose volume gives ambient occlusion (`volume.ao`, or the strands'
    /// `strands.ao`) keeps `volume.resolution`: the AO ball has a radius in world units, which a
    /// grid sized by the screen can make smaller than a voxel (the demo's AO alone at 3× its
    /// distance at 128×72 scored FLIP 0.34 against the traced AO over the hair with it, 0.16
    /// at the full grid).
    fn object_resolution(&self, i: usize, d: &Drawn<'_>) -> u32 {
        if self.volume_settings.ao || d.plan.raster_ao {
            return self.volume_settings.resolution;
        }
        let wanted = self
            .volume_settings
            .object_resolution(d.plan.extent.size_px);
        match self.voxelizer.as_ref().and_then(|v| v.grid_resolution(i)) {
            Some(current)
                if current >= wanted
                    && current <= self.volume_settings.resolution
                    && wanted * 3 >= current * 2 =>
            {
                current
            }
            _ => wanted,
        }
    }

    /// The baked AO of object `d`'s volume at `resolution`: voxels a texel (0: none, when
    /// nothing reads its AO or `volume.ao_texel` is 0) and its bytes.
    fn ao_settings(&self, resolution: u32, d: &Drawn<'_>) -> (u32, u64) {
        let reads_ao = self.volume_settings.ao || d.plan.raster_ao;
        let s = VolumeSettings {
            resolution,
            ..self.volume_settings.clone()
        };
        let texel = if reads_ao { s.ao_texel } else { 0 };
        (texel, s.ao_bytes(reads_ao))
    }

    /// Give every head of hair that voxelizes a volume within `volume.budget_mib`, in order, at
    /// its resolution on screen; one that does not fit is drawn as strands instead (warned once
    /// until it fits again). Volumes of heads of hair that no longer voxelize are freed.
    pub(super) fn grant_volumes(
        &mut self,
        ctx: &GpuContext,
        drawn: &mut [Drawn<'_>],
    ) -> Result<(), RenderError> {
        let resolutions: Vec<u32> = drawn
            .iter()
            .enumerate()
            .map(|(i, d)| self.object_resolution(i, d))
            .collect();
        let settings = &self.volume_settings;
        let budget = u64::from(settings.budget_mib) << 20;
        let at = |resolution: u32| VolumeSettings {
            resolution,
            ..VolumeSettings::default()
        };
        // The counters are as large as the largest grid voxelized.
        let largest = drawn
            .iter()
            .zip(&resolutions)
            .filter(|(d, _)| d.plan.voxelize)
            .map(|(_, &r)| r)
            .max()
            .unwrap_or(settings.resolution);
        let counters = at(largest).counter_bytes();
        let mut used = counters;
        for (i, d) in drawn.iter_mut().enumerate() {
            if !d.plan.voxelize {
                continue;
            }
            let per_object =
                at(resolutions[i]).resident_bytes() + self.ao_settings(resolutions[i], d).1;
            if used + per_object > budget {
                if !self.warned.get(i).copied().unwrap_or(false) {
                    tracing::warn!(
                        "hair object {i}: its volume ({:.1} MiB) does not fit volume.budget_mib \
                         = {} beside the voxel counters ({:.1} MiB) and the other volumes; drawn \
                         as strands",
                        per_object as f64 / f64::from(1 << 20),
                        settings.budget_mib,
                        counters as f64 / f64::from(1 << 20),
                    );
                    if self.warned.len() <= i {
                        self.warned.resize(i + 1, false);
                    }
                    self.warned[i] = true;
                }
                d.plan = d.plan.strands_only(
                    "volume.budget_mib",
                    &self.hybrid,
                    &self.settings,
                    &self.volume_settings,
                );
                continue;
            }
            used += per_object;
            if let Some(w) = self.warned.get_mut(i) {
                *w = false;
            }
        }
        let wants: Vec<bool> = drawn.iter().map(|d| d.plan.voxelize).collect();
        let ao_texels: Vec<u32> = drawn
            .iter()
            .zip(&resolutions)
            .map(|(d, &r)| self.ao_settings(r, d).0)
            .collect();
        if wants.iter().any(|&w| w) && self.voxelizer.is_none() {
            self.voxelizer = Some(Voxelizer::with_params(
                ctx,
                &self.layouts,
                (self.volume_settings.resolution, largest),
                &self.slots[0].volume_params,
            )?);
        }
        if let Some(v) = &mut self.voxelizer {
            for (i, slot) in self.slots.iter().enumerate() {
                if wants.get(i).copied().unwrap_or(false) {
                    let ao_texel = ao_texels[i];
                    v.ensure_grid(ctx, i, &slot.volume_params, resolutions[i], ao_texel)?;
                } else {
                    v.release_grid(i);
                }
            }
            v.fit_scratch(ctx)?;
        }
        self.refresh_lighting_groups(ctx, false)
    }
}

/// The view group over the frame's camera and an object's strand settings.
pub(super) fn view_group(
    ctx: &GpuContext,
    layouts: &Layouts,
    camera: &wgpu::Buffer,
    params: &wgpu::Buffer,
) -> Result<wgpu::BindGroup, RenderError> {
    ctx.scoped("creating the view bind group", || {
        ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("frame/view/bind-group"),
            layout: &layouts.view,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: camera.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: params.as_entire_binding(),
                },
            ],
        })
    })
}

/// The frame's heads of hair: `hair` (with the frame's `material` and the renderer's
/// `technique`) first, then `objects`; one entry without hair when there is none (the head
/// alone).
pub(super) fn frame_objects<'a>(
    hair: Option<&'a StrandGeometry>,
    material: Material,
    technique: TechniqueKind,
    objects: &[HairObject<'a>],
) -> Vec<(Option<&'a StrandGeometry>, Material, TechniqueKind)> {
    let mut all: Vec<_> = hair
        .map(|h| (Some(h), material, technique))
        .into_iter()
        .chain(
            objects
                .iter()
                .map(|o| (Some(o.hair), o.material, o.technique)),
        )
        .collect();
    if all.is_empty() {
        all.push((None, material, technique));
    }
    all
}

/// At most [`MAX_OBJECTS`] heads of hair a frame, or the error.
pub(crate) fn check_objects(count: usize) -> Result<(), RenderError> {
    if count > MAX_OBJECTS {
        return Err(RenderError::Invalid(format!(
            "{count} heads of hair in one frame, at most {MAX_OBJECTS} supported"
        )));
    }
    Ok(())
}
