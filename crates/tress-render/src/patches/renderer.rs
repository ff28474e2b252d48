//! A whole patch frame, top to bottom: [`PatchRenderer::render`].
//!
//! ```text
//! uniforms     camera, lights, head material, patch constants
//! head         clear (optional), opaque head with depth writes          (HeadPass)
//! 4-pass       patches/z_prime  alpha-tested depth only, no culling      (ZPrime)
//!              patches/opaque   full shader, depth Equal, no Z writes    (PatchShade)
//!              patches/back     front faces culled, no Z writes, Less    (PatchShade)
//!              patches/front    back faces culled, Z writes, Less        (PatchShade)
//! 3-pass       patches/opaque (alpha test), patches/back, patches/front (alpha test inverted)
//! readback     timestamps -> PatchFrameStats
//! ```

use glam::Vec3;
use tress_hair::patches::HairTextures;

use super::passes::PassShader;
use super::{
    PASS_NAMES, PatchGeometry, PatchLayouts, PatchSettings, PatchShade, PatchTextures,
    RenderScheme, TextureSlot, ZPrime,
};
use crate::gpu::types::{FiberCache, PatchParamsGpu};
use crate::gpu::{TargetFormats, Targets, Timings, uniform_buffer};
use crate::services::FrameServices;
use crate::stats::{SlotInfo, StatsReadback};
use crate::{GpuContext, RenderError, SharedInputs};

/// Everything a patch frame draws. Plain data: the application owns geometry and targets.
#[derive(Clone, Debug)]
pub struct PatchFrameInputs<'a> {
    /// The camera, lights (each adds one `HairLighting` term), ambient light (adds
    /// `ambient · base · ao`; zero gives the slide's formula), opaque head (drawn first) and
    /// clear colour.
    pub shared: SharedInputs<'a>,
    /// Head mesh color, linear RGB.
    pub head_color: Vec3,
    /// The patches, if any.
    pub patches: Option<&'a PatchGeometry>,
}

/// What [`PatchRenderer::render`] returns.
#[derive(Clone, Debug, PartialEq)]
pub struct PatchFrameStats {
    /// Index of this frame (from 0).
    pub frame: u64,
    /// Target size in pixels.
    pub size: [u32; 2],
    /// Triangles drawn per pass.
    pub triangles: u32,
    /// The scheme the frame used.
    pub scheme: RenderScheme,
    /// Per-pass GPU times: this frame's with [`StatsReadback::Wait`], the newest available
    /// otherwise (`None` when none has arrived yet).
    pub timings: Option<Timings>,
    /// The frame `timings` belong to: this one with [`StatsReadback::Wait`], the newest that has
    /// arrived with [`StatsReadback::Deferred`] (as [`crate::SatfFrameStats::gpu_frame`] and
    /// [`crate::GpuReport::frame`]).
    pub gpu_frame: Option<u64>,
}

/// The patch renderer with its head pass: renders into caller-provided targets.
#[derive(Debug)]
pub struct PatchRenderer {
    formats: TargetFormats,
    settings: PatchSettings,
    layouts: PatchLayouts,
    head_color: wgpu::Buffer,
    patch_params: wgpu::Buffer,
    view_group: wgpu::BindGroup,
    lights_group: wgpu::BindGroup,
    textures_cpu: HairTextures,
    textures_given: bool,
    textures: PatchTextures,
    material_group: wgpu::BindGroup,
    head: crate::head::HeadPass,
    z_prime: ZPrime,
    shade: PatchShade,
    services: FrameServices,
    /// The fibre's uniform (filled only while the patches shade with Marschner).
    fiber: FiberCache,
}

fn generate_textures(settings: &PatchSettings) -> Result<HairTextures, RenderError> {
    HairTextures::generate(&settings.textures)
        .map_err(|e| RenderError::setting("patches.textures", e))
}

impl PatchRenderer {
    /// Build the pipelines for targets of `formats`, with `settings` (validated) and the
    /// procedural textures they describe.
    pub fn new(
        ctx: &GpuContext,
        formats: TargetFormats,
        settings: PatchSettings,
    ) -> Result<Self, RenderError> {
        settings.validate()?;
        let textures = generate_textures(&settings)?;
        Self::build(ctx, formats, settings, textures, false)
    }

    /// Like [`PatchRenderer::new`], with explicit textures (e.g. read from PNG files) instead of
    /// the procedural ones.
    pub fn with_textures(
        ctx: &GpuContext,
        formats: TargetFormats,
        settings: PatchSettings,
        textures: HairTextures,
    ) -> Result<Self, RenderError> {
        settings.validate()?;
        Self::build(ctx, formats, settings, textures, true)
    }

    fn build(
        ctx: &GpuContext,
        formats: TargetFormats,
        settings: PatchSettings,
        textures_cpu: HairTextures,
        textures_given: bool,
    ) -> Result<Self, RenderError> {
        let layouts = ctx.scoped("creating the patch bind group layouts", || {
            PatchLayouts::new(&ctx.device)
        })?;
        let textures = PatchTextures::new(ctx, &textures_cpu, settings.mipmaps)?;
        let services = FrameServices::new(ctx, "patches", PASS_NAMES, 0)?;
        let (camera, lights) = (&services.camera, &services.lights);
        let (head_color, patch_params) = ctx.scoped("creating uniforms", || {
            (
                uniform_buffer(ctx, "patches/uniforms/head-color", &[0.0f32; 4]),
                uniform_buffer(ctx, "patches/uniforms/params", &settings.params()),
            )
        })?;
        let (view_group, lights_group) = ctx.scoped("creating the patch bind groups", || {
            let view_group = ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("patches/view/bind-group"),
                layout: &layouts.view,
                entries: &[wgpu::BindGroupEntry {
                    binding: 0,
                    resource: camera.as_entire_binding(),
                }],
            });
            let lights_group = ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("patches/lights/bind-group"),
                layout: &layouts.lights,
                entries: &[
                    wgpu::BindGroupEntry {
                        binding: 0,
                        resource: lights.as_entire_binding(),
                    },
                    wgpu::BindGroupEntry {
                        binding: 1,
                        resource: head_color.as_entire_binding(),
                    },
                ],
            });
            (view_group, lights_group)
        })?;
        let material_group =
            Self::material_group(ctx, &layouts.material, &patch_params, &textures)?;
        Ok(PatchRenderer {
            head: super::patch_head(ctx, &layouts.view, &layouts.lights, formats.color)?,
            z_prime: ZPrime::new(ctx, &layouts, formats.color)?,
            shade: PatchShade::new(ctx, &layouts, formats.color, settings.passes())?,
            formats,
            settings,
            layouts,
            head_color,
            patch_params,
            view_group,
            lights_group,
            textures_cpu,
            textures_given,
            textures,
            material_group,
            services,
            fiber: FiberCache::default(),
        })
    }

    fn material_group(
        ctx: &GpuContext,
        layout: &wgpu::BindGroupLayout,
        params: &wgpu::Buffer,
        textures: &PatchTextures,
    ) -> Result<wgpu::BindGroup, RenderError> {
        let mut entries = vec![wgpu::BindGroupEntry {
            binding: 0,
            resource: params.as_entire_binding(),
        }];
        entries.extend(TextureSlot::ALL.iter().enumerate().map(|(i, &slot)| {
            wgpu::BindGroupEntry {
                binding: 1 + i as u32,
                resource: wgpu::BindingResource::TextureView(textures.view(slot)),
            }
        }));
        entries.push(wgpu::BindGroupEntry {
            binding: 5,
            resource: wgpu::BindingResource::Sampler(&textures.sampler),
        });
        ctx.scoped("creating the patch material bind group", || {
            ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("patches/material/bind-group"),
                layout,
                entries: &entries,
            })
        })
    }

    /// Upload a patch mesh sorted around `sort_center` (same as [`PatchGeometry::new`]).
    pub fn upload_patches(
        &self,
        ctx: &GpuContext,
        mesh: &tress_hair::patches::PatchMesh,
        sort_center: Vec3,
    ) -> Result<PatchGeometry, RenderError> {
        PatchGeometry::new(ctx, mesh, sort_center)
    }

    /// The current settings.
    pub fn settings(&self) -> &PatchSettings {
        &self.settings
    }

    /// The textures in use (procedural or given).
    pub fn textures(&self) -> &HairTextures {
        &self.textures_cpu
    }

    /// Change settings (validated). A new scheme or `min_alpha` switch rebuilds the shading
    /// pipelines; new texture
    /// parameters regenerate the procedural textures (textures given with
    /// [`PatchRenderer::set_textures`] are kept).
    pub fn set_settings(
        &mut self,
        ctx: &GpuContext,
        settings: PatchSettings,
    ) -> Result<(), RenderError> {
        settings.validate()?;
        let passes = settings.passes();
        if passes != self.shade.passes() {
            self.shade = PatchShade::new(ctx, &self.layouts, self.formats.color, passes)?;
        }
        let regenerate = !self.textures_given && settings.textures != self.settings.textures;
        if regenerate || settings.mipmaps != self.settings.mipmaps {
            let cpu = if regenerate {
                generate_textures(&settings)?
            } else {
                self.textures_cpu.clone()
            };
            self.upload_textures(ctx, cpu, settings.mipmaps)?;
        }
        self.settings = settings;
        Ok(())
    }

    /// Replace the textures (validated; e.g. read from PNG files).
    pub fn set_textures(
        &mut self,
        ctx: &GpuContext,
        textures: HairTextures,
    ) -> Result<(), RenderError> {
        self.upload_textures(ctx, textures, self.settings.mipmaps)?;
        self.textures_given = true;
        Ok(())
    }

    fn upload_textures(
        &mut self,
        ctx: &GpuContext,
        cpu: HairTextures,
        mipmaps: bool,
    ) -> Result<(), RenderError> {
        let gpu = PatchTextures::new(ctx, &cpu, mipmaps)?;
        self.material_group =
            Self::material_group(ctx, &self.layouts.material, &self.patch_params, &gpu)?;
        self.textures = gpu;
        self.textures_cpu = cpu;
        Ok(())
    }

    /// Bytes of the four textures on the GPU (with their mip chains).
    pub fn texture_bytes(&self) -> u64 {
        self.textures.bytes()
    }

    /// How `render` reports GPU times (default [`StatsReadback::Wait`]).
    pub fn set_stats_readback(&mut self, mode: StatsReadback) {
        self.services.readback = mode;
    }

    /// This frame's patch uniform: the settings' constants, and under Marschner shading the
    /// fibre's lobes and table.
    fn params(&mut self) -> PatchParamsGpu {
        if self.settings.shading != crate::Shading::Marschner {
            return self.settings.params();
        }
        let uniform = self.fiber.get(&self.settings.fiber);
        self.settings.params_with(&uniform)
    }

    /// Render one frame into `targets` and submit it on `ctx.queue`.
    pub fn render(
        &mut self,
        ctx: &GpuContext,
        targets: &Targets<'_>,
        inputs: &PatchFrameInputs<'_>,
    ) -> Result<PatchFrameStats, RenderError> {
        // ---- validate inputs (never panic on user data)
        let size = targets.validate_view(
            self.formats,
            &inputs.shared.camera,
            inputs.shared.lights.len(),
        )?;
        if !inputs.shared.ambient.is_finite() || !inputs.head_color.is_finite() {
            return Err(RenderError::Invalid(
                "ambient light and head color must be finite".into(),
            ));
        }

        // ---- uniforms
        // Patches cast no shadows: the lights carry no shadow transform.
        let (lights, _) =
            crate::inputs::lights_uniform(inputs.shared.ambient, inputs.shared.lights, None)?;
        let head_color = inputs.head_color.extend(1.0).to_array();
        self.services
            .write_view(ctx, &inputs.shared.camera, &lights);
        let q = &ctx.queue;
        q.write_buffer(&self.head_color, 0, bytemuck::bytes_of(&head_color));
        let params = self.params();
        q.write_buffer(&self.patch_params, 0, bytemuck::bytes_of(&params));

        // Deferred: the newest earlier frame's results, read before this one is submitted.
        let earlier = self.services.earlier(ctx)?;
        let ticket = self.services.begin(ctx)?;
        let scheme = self.settings.scheme;
        let patches = inputs.patches.filter(|p| p.triangle_count() > 0);
        let services = &mut self.services;
        let (view, lighting, material) =
            (&self.view_group, &self.lights_group, &self.material_group);
        let (head_pass, z_prime, shade) = (&self.head, &self.z_prime, &self.shade);
        ctx.scoped("rendering a patch frame", || {
            let timer = &services.timer;
            let mut encoder = ctx
                .device
                .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                    label: Some("patches/frame/encoder"),
                });
            // ---- the head first, depth written (slide "Performance Tuning")
            head_pass.encode(
                &mut encoder,
                targets,
                inputs.shared.clear,
                timer.render_writes("head", true, true),
                [view, lighting],
                inputs.shared.head,
            );
            // ---- the scheme's passes over the static inside-to-outside index buffer
            if let Some(geometry) = patches {
                for p in shade.passes() {
                    let label = format!("{}/pass", p.name);
                    let mut pass = targets.begin_pass(
                        &mut encoder,
                        &label,
                        (wgpu::LoadOp::Load, wgpu::LoadOp::Load),
                        timer.render_writes(p.name, true, true),
                    );
                    pass.set_bind_group(0, view, &[]);
                    pass.set_bind_group(2, material, &[]);
                    match p.shader {
                        PassShader::AlphaOnly => z_prime.draw(&mut pass, geometry),
                        PassShader::Full => {
                            pass.set_bind_group(1, lighting, &[]);
                            shade.draw(&mut pass, p, geometry);
                        }
                    }
                }
            }
            // ---- timestamps readback
            let info = SlotInfo::without_oit(ticket.frame);
            ticket.submit(ctx, (&mut services.ring, timer), encoder, None, &[], info);
        })?;

        let report = self.services.results(ctx, ticket, earlier)?;
        Ok(PatchFrameStats {
            frame: ticket.frame,
            size,
            triangles: patches.map_or(0, |p| p.triangle_count()),
            scheme,
            gpu_frame: report.as_ref().map(|r| r.frame),
            timings: report.map(|r| r.timings),
        })
    }
}
