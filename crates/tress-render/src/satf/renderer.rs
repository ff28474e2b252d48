//! A whole SATF frame, top to bottom: [`SatfRenderer::render`] (Xu et al. 2006, §6.1, Figure 3;
//! the stages of Table 1).
//!
//! ```text
//! uniforms           camera, lights (+ shadow cameras), SatfParams; clusters sorted back to front
//! index_calculation  Params(b) per sector, nearest records, eq. 6 per HSV          (IndexCalc)
//! map_construction   re-maps and alpha-maps, eq. 7                                  (MapBuild)
//! shadowing          per light: cluster + head shadow map (ClusterShadow); eq. 12 s-maps and
//!                    light visibility per texel                                     (SMaps)
//! lighting           eq. 8-11 per texel                                             (Lighting)
//! head               clear (optional), opaque head with depth writes                (SatfHead)
//! texture_mapping    layer meshes, eq. 13, blending = eq. 14                        (TextureMap)
//! readback           HSV counters + timestamps into the ReadbackRing -> SatfFrameStats (this
//!                    frame's, or the newest arrived with StatsReadback::Deferred)
//! ```

use glam::Vec3;
use tress_satf::SkippedStrands;
use tress_satf::online::ShadowApprox;

use super::cluster_shadow::ShadowTargets;
use super::index_calc::Uniforms;
use super::{
    ClusterShadow, IndexCalc, Lighting, MapBuild, PASS_NAMES, Reflectance, SMaps, SatfDatabase,
    SatfGeometry, SatfHead, SatfSettings, TextureMap,
};
use crate::gpu::types::SatfParams;
use crate::gpu::{FrameEncoder, TargetFormats, Targets, Timings, uniform_buffer};
use crate::head::HeadPassInfo;
use crate::inputs::{frame_sphere, lights_uniform};
use crate::services::FrameServices;
use crate::stats::{SlotInfo, StatsReadback};
use crate::{Camera, GpuContext, RenderError, SharedInputs};

/// Everything a SATF frame draws. Plain data: the application owns geometry and targets.
#[derive(Clone, Copy, Debug)]
pub struct SatfFrameInputs<'a> {
    /// The camera, lights, ambient light, opaque head and clear colour.
    pub shared: SharedInputs<'a>,
    /// Head mesh color, linear RGB.
    pub head_color: Vec3,
    /// The clusters, if any.
    pub clusters: Option<&'a SatfGeometry>,
    /// The HRIR database the clusters were prepared for.
    pub database: &'a SatfDatabase,
}

/// What [`SatfRenderer::render`] returns (the frame is waited for).
#[derive(Clone, Debug, PartialEq)]
pub struct SatfFrameStats {
    /// Index of this frame (from 0).
    pub frame: u64,
    /// The frame the HSV counters and the GPU timings belong to: this one with
    /// [`StatsReadback::Wait`], the newest that has arrived with [`StatsReadback::Deferred`]
    /// (`None` before any has; the counters are then zero).
    pub gpu_frame: Option<u64>,
    /// Target size in pixels.
    pub size: [u32; 2],
    /// Clusters drawn.
    pub clusters: u32,
    /// Shell layers over all clusters.
    pub layers: u32,
    /// HSVs over all clusters.
    pub hsvs: u32,
    /// HSVs that passed equation 6 (one averaged record).
    pub uniform_hsvs: u32,
    /// HSVs interpolated by equation 7.
    pub interpolated_hsvs: u32,
    /// Strands in the clusters drawn.
    pub strands: usize,
    /// Strands of the source asset that the cluster fit left out, by reason (zero for generated
    /// clusters).
    pub skipped_strands: SkippedStrands,
    /// Per-pass GPU times ([`PASS_NAMES`]).
    pub timings: Timings,
}

impl SatfFrameStats {
    /// GPU milliseconds of the stages of the paper's Table 1, in its order: index calculation,
    /// map construction, texture mapping, lighting, shadowing (`None` without timestamps or
    /// when the stage did not run).
    pub fn table1_ms(&self) -> [(&'static str, Option<f64>); 5] {
        [
            ("index_calculation", "satf/index_calculation"),
            ("map_construction", "satf/map_construction"),
            ("texture_mapping", "satf/texture_mapping"),
            ("lighting", "satf/lighting"),
            ("shadowing", "satf/shadowing"),
        ]
        .map(|(key, pass)| (key, self.timings.get(pass)))
    }
}

/// The SATF online renderer: renders clusters and a head into caller-provided targets.
#[derive(Debug)]
pub struct SatfRenderer {
    formats: TargetFormats,
    settings: SatfSettings,
    services: FrameServices,
    params: wgpu::Buffer,
    index_calc: IndexCalc,
    map_build: MapBuild,
    cluster_shadow: ClusterShadow,
    shadow_targets: ShadowTargets,
    s_maps: SMaps,
    lighting: Lighting,
    head: SatfHead,
    texture_map: TextureMap,
}

/// Cluster indices sorted back to front from `camera` by their bounding spheres' centres.
pub(crate) fn back_to_front(camera: &Camera, bounds: &[(Vec3, f32)]) -> Vec<u32> {
    let eye = camera.eye();
    let forward = camera.forward();
    let ortho = camera.is_orthographic();
    let key = |c: Vec3| {
        if ortho {
            (c - eye).dot(forward)
        } else {
            c.distance_squared(eye)
        }
    };
    let mut order: Vec<u32> = (0..bounds.len() as u32).collect();
    order.sort_by(|&a, &b| key(bounds[b as usize].0).total_cmp(&key(bounds[a as usize].0)));
    order
}

impl SatfRenderer {
    /// Build the pipelines for targets of `formats`, with `settings` (validated).
    pub fn new(
        ctx: &GpuContext,
        formats: TargetFormats,
        settings: SatfSettings,
    ) -> Result<Self, RenderError> {
        settings.validate()?;
        let params = ctx.scoped("creating SATF uniforms", || {
            uniform_buffer(ctx, "satf/uniforms/params", &SatfParams::default())
        })?;
        let mut services = FrameServices::new(ctx, "satf", PASS_NAMES, 0)?;
        services.set_timer_mode(settings.stage_timing.timer_mode());
        Ok(SatfRenderer {
            formats,
            index_calc: IndexCalc::new(ctx)?,
            map_build: MapBuild::new(ctx)?,
            cluster_shadow: ClusterShadow::new(ctx, &params)?,
            shadow_targets: ShadowTargets::new(ctx, settings.shadow_map_size)?,
            s_maps: SMaps::new(ctx)?,
            lighting: Lighting::new(ctx)?,
            head: SatfHead::new(ctx, formats.color)?,
            texture_map: TextureMap::new(ctx, formats.color)?,
            settings,
            services,
            params,
        })
    }

    /// How `render` reports the GPU's counters and timings (default [`StatsReadback::Wait`]:
    /// wait for the frame; `Deferred` never blocks and reports the newest frame that arrived).
    /// `stage_timing = "wall_clock"` waits for every stage whatever this says.
    pub fn set_stats_readback(&mut self, mode: StatsReadback) {
        self.services.readback = mode;
    }

    /// The current settings.
    pub fn settings(&self) -> &SatfSettings {
        &self.settings
    }

    /// Change the settings (validated). The sampling, `map_rows`, `mesh_t` and `mesh_u` are the
    /// geometry's: they take effect for clusters uploaded with them ([`SatfGeometry::new`]).
    pub fn set_settings(
        &mut self,
        ctx: &GpuContext,
        settings: SatfSettings,
    ) -> Result<(), RenderError> {
        settings.validate()?;
        if settings.shadow_map_size != self.shadow_targets.size {
            self.shadow_targets = ShadowTargets::new(ctx, settings.shadow_map_size)?;
        }
        self.services
            .set_timer_mode(settings.stage_timing.timer_mode());
        self.settings = settings;
        Ok(())
    }

    fn params(
        &self,
        geometry: Option<&SatfGeometry>,
        db: &SatfDatabase,
        lights: u32,
        head_color: Vec3,
    ) -> SatfParams {
        let s = &self.settings;
        let p = &s.lighting;
        let mut out = SatfParams {
            f_dif: p.f_dif.to_array(),
            k_dif: p.k_dif,
            f_spe1: p.f_spe1.to_array(),
            k_spe1: p.k_spe1,
            f_spe2: p.f_spe2.to_array(),
            k_spe2: p.k_spe2,
            primary_shift: p.primary_shift,
            secondary_shift: p.secondary_shift,
            k_h: p.k_h,
            k_shadow: s.k_shadow,
            feature_weights: s.lookup.feature_weights,
            k_threshold: s.lookup.k_threshold,
            angle_weight: s.lookup.angle_weight,
            shadow_approx: u32::from(s.shadow_approx == ShadowApprox::Linear),
            straight: u32::from(s.reflectance == Reflectance::Straight),
            sample_count: db.samples,
            view_angles: db.view_angles,
            light_angles: db.light_angles,
            pixels: db.pixels,
            light_count: lights,
            key_light: s.key_light,
            cluster_shadows: u32::from(s.cluster_shadows && lights > 0),
            pcf_radius: s.pcf_radius as i32,
            shadow_map_size: self.shadow_targets.size as f32,
            shadow_bias: s.shadow_bias,
            shadow_opacity: s.shadow_opacity,
            local_shadows: u32::from(s.local_shadows),
            head_color: head_color.to_array(),
            ..Default::default()
        };
        if let Some(g) = geometry {
            let l = &g.layout;
            out.map_rows = l.map_rows;
            out.st = l.sampling.st;
            out.su = l.sampling.su;
            out.layers = l.layers;
            out.cluster_count = l.clusters;
            out.sector_count = l.sectors();
            out.hsv_count = l.hsvs();
            out.tile_width = l.tile_width;
            out.tile_height = l.tile_height;
            out.tiles_per_row = l.tiles_per_row;
            out.mesh_nt = l.mesh_nt;
            out.mesh_nu = l.mesh_nu;
            out.tile_count = l.tiles();
        }
        out
    }

    /// Bytes of the shadow maps between clusters (depth and cluster ids per light).
    pub fn shadow_bytes(&self) -> u64 {
        self.shadow_targets.bytes()
    }

    /// Render one frame into `targets`, submit it and wait for its statistics.
    pub fn render(
        &mut self,
        ctx: &GpuContext,
        targets: &Targets<'_>,
        inputs: &SatfFrameInputs<'_>,
    ) -> Result<SatfFrameStats, RenderError> {
        // ---- validate inputs (never panic on user data)
        let size = targets.validate_view(
            self.formats,
            &inputs.shared.camera,
            inputs.shared.lights.len(),
        )?;
        if !(inputs.shared.ambient.is_finite() && inputs.head_color.is_finite()) {
            return Err(RenderError::Invalid(
                "ambient light or head color is not finite".into(),
            ));
        }
        let db = inputs.database;
        let geometry = inputs.clusters.filter(|g| g.layout.clusters > 0);
        if let Some(g) = geometry
            && g.layout.pixels != db.pixels
        {
            return Err(RenderError::Invalid(format!(
                "satf: the clusters were prepared for a database of {} pixels per HRIR, this \
                 one has {}",
                g.layout.pixels, db.pixels
            )));
        }

        // ---- uniforms and the back-to-front order
        let bounds = frame_sphere(
            geometry.map(|g| g.bounds),
            inputs.shared.head.map(|h| h.bounds),
        );
        let (lights, light_cameras) = lights_uniform(
            inputs.shared.ambient,
            inputs.shared.lights,
            Some((bounds, self.shadow_targets.size)),
        )?;
        let params = self.params(geometry, db, lights.count, inputs.head_color);
        let order = geometry.map_or_else(Vec::new, |g| {
            back_to_front(&inputs.shared.camera, &g.cluster_bounds)
        });
        self.services
            .write_view(ctx, &inputs.shared.camera, &lights);
        ctx.queue
            .write_buffer(&self.params, 0, bytemuck::bytes_of(&params));

        let shadows = params.cluster_shadows != 0 && geometry.is_some();
        let earlier = self.services.earlier(ctx)?;
        let ticket = self.services.begin(ctx)?;
        let services = &mut self.services;
        let u = Uniforms {
            camera: &services.camera,
            lights: &services.lights,
            params: &self.params,
        };
        let timer = &services.timer;
        ctx.scoped("rendering a SATF frame", || -> Result<_, RenderError> {
            let mut stages = FrameEncoder::new(ctx, timer, "satf/encoder");
            if let Some(g) = geometry {
                // ---- index calculation (§6.2.1) and map construction (§6.2.2)
                let ts = timer.compute_writes("satf/index_calculation", true, true);
                self.index_calc
                    .encode(ctx, &mut stages.encoder, u, g, db, ts);
                stages.cut("satf/index_calculation")?;
                let ts = timer.compute_writes("satf/map_construction", true, true);
                self.map_build
                    .encode(ctx, &mut stages.encoder, u, g, db, ts);
                stages.cut("satf/map_construction")?;
                // ---- shadowing (§6.4): shadow maps between clusters, then s-maps
                let mut begun = false;
                if shadows {
                    self.cluster_shadow.encode(
                        ctx,
                        &mut stages.encoder,
                        &self.shadow_targets,
                        &light_cameras,
                        Some(g),
                        inputs.shared.head,
                        |i, _| {
                            begun = true;
                            timer.render_writes("satf/shadowing", i == 0, false)
                        },
                    );
                }
                let ts = timer.compute_writes("satf/shadowing", !begun, true);
                self.s_maps
                    .encode(ctx, &mut stages.encoder, u, g, &self.shadow_targets, ts);
                stages.cut("satf/shadowing")?;
                // ---- lighting (§6.3)
                let ts = timer.compute_writes("satf/lighting", true, true);
                self.lighting.encode(ctx, &mut stages.encoder, u, g, ts);
                stages.cut("satf/lighting")?;
            }
            // ---- opaque head, depth written
            let info = HeadPassInfo {
                label: "satf/head/pass",
                clear: inputs.shared.clear,
                writes: timer.render_writes("satf/head", true, true),
            };
            self.head.encode(
                ctx,
                &mut stages.encoder,
                targets,
                info,
                [u.camera, u.lights, u.params],
                &self.shadow_targets,
                inputs.shared.head,
            );
            stages.cut("satf/head")?;
            // ---- texture mapping, shading and blending (§6.5)
            if let Some(g) = geometry {
                self.texture_map.encode(
                    ctx,
                    &mut stages.encoder,
                    u.camera,
                    u.params,
                    g,
                    &order,
                    targets,
                    timer.render_writes("satf/texture_mapping", true, true),
                );
                stages.cut("satf/texture_mapping")?;
            }
            // ---- statistics readback: the counters and the timestamps
            let info = SlotInfo {
                satf: geometry.is_some(),
                ..SlotInfo::without_oit(ticket.frame)
            };
            let counters = geometry.map(|g| &g.counters);
            let encoder = stages.into_encoder();
            ticket.submit(
                ctx,
                (&mut services.ring, timer),
                encoder,
                counters,
                &[],
                info,
            );
            Ok(())
        })??;

        // ---- this frame's results (Wait), or the newest earlier one read above (Deferred)
        let report = self.services.results(ctx, ticket, earlier)?;
        let counters = report.as_ref().and_then(|r| r.satf).unwrap_or_default();
        let timings = self.services.timings(ctx, report.as_ref());
        let frame = ticket.frame;
        let l = geometry.map(|g| g.layout);
        Ok(SatfFrameStats {
            frame,
            gpu_frame: report.map(|r| r.frame),
            size,
            clusters: l.map_or(0, |l| l.clusters),
            layers: l.map_or(0, |l| l.tiles()),
            hsvs: l.map_or(0, |l| l.hsvs()),
            uniform_hsvs: counters.uniform_hsvs,
            interpolated_hsvs: counters.interpolated_hsvs,
            strands: geometry.map_or(0, |g| g.stats().strands),
            skipped_strands: geometry.map_or_else(SkippedStrands::default, |g| g.stats().skipped),
            timings,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn clusters_sort_back_to_front() {
        let cam = Camera::look_at(
            Vec3::new(0.0, 0.0, 10.0),
            Vec3::ZERO,
            Vec3::Y,
            0.8,
            0.1,
            100.0,
            [8, 8],
        );
        let bounds = [
            (Vec3::new(0.0, 0.0, 5.0), 1.0),
            (Vec3::new(0.0, 0.0, -5.0), 1.0),
            (Vec3::ZERO, 1.0),
        ];
        assert_eq!(back_to_front(&cam, &bounds), vec![1, 2, 0]);
    }
}
