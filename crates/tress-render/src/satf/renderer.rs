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
//! readback           HSV counters + timestamps -> SatfFrameStats
//! ```

use std::cell::Cell;
use std::time::Instant;

use glam::Vec3;
use tress_satf::SkippedStrands;
use tress_satf::online::ShadowApprox;

use super::cluster_shadow::ShadowTargets;
use super::index_calc::Uniforms;
use super::{
    ClusterShadow, IndexCalc, Lighting, MapBuild, PASS_NAMES, Reflectance, SMaps, SatfDatabase,
    SatfGeometry, SatfHead, SatfSettings, StageTiming, TextureMap,
};
use crate::gpu::types::{CameraUniform, LightsUniform, SatfCounters, SatfParams};
use crate::gpu::{
    PassTiming, TargetFormats, Targets, Timings, clear_loads, read_buffer, uniform_buffer,
};
use crate::head::HeadGeometry;
use crate::inputs::union_sphere;
use crate::{Camera, DirectionalLight, GpuContext, RenderError};

/// Everything a SATF frame draws. Plain data: the application owns geometry and targets.
#[derive(Clone, Copy, Debug)]
pub struct SatfFrameInputs<'a> {
    /// The camera; its viewport must equal the targets' size.
    pub camera: Camera,
    /// Directional lights (at most [`MAX_LIGHTS`]).
    pub lights: &'a [DirectionalLight],
    /// Ambient light, linear RGB.
    pub ambient: Vec3,
    /// Head mesh color, linear RGB.
    pub head_color: Vec3,
    /// The clusters, if any.
    pub clusters: Option<&'a SatfGeometry>,
    /// The HRIR database the clusters were prepared for.
    pub database: &'a SatfDatabase,
    /// The opaque head, drawn first, if any.
    pub head: Option<&'a HeadGeometry>,
    /// Clear color and depth first (linear RGBA), or `None` to draw over what the targets hold.
    pub clear: Option<wgpu::Color>,
}

/// What [`SatfRenderer::render`] returns (the frame is waited for).
#[derive(Clone, Debug, PartialEq)]
pub struct SatfFrameStats {
    /// Index of this frame (from 0).
    pub frame: u64,
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

/// Offset of the timestamps in the readback buffer.
const TIMESTAMP_OFFSET: u64 = 256;

/// Timestamp queries of the SATF passes: two per name of [`PASS_NAMES`].
#[derive(Debug)]
struct SatfTimer {
    queries: Option<(wgpu::QuerySet, wgpu::Buffer)>,
    written: Vec<Cell<bool>>,
    /// Set while stages are timed by wall clock: no timestamp writes.
    suspended: Cell<bool>,
    period_ns: f64,
}

impl SatfTimer {
    fn new(ctx: &GpuContext) -> Self {
        let count = PASS_NAMES.len() as u32 * 2;
        let queries = ctx.caps.timestamps.then(|| {
            (
                ctx.device.create_query_set(&wgpu::QuerySetDescriptor {
                    label: Some("satf/timestamps"),
                    ty: wgpu::QueryType::Timestamp,
                    count,
                }),
                ctx.device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some("satf/timestamps-resolve"),
                    size: u64::from(count) * 8,
                    usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
                    mapped_at_creation: false,
                }),
            )
        });
        SatfTimer {
            queries,
            written: vec![Cell::new(false); PASS_NAMES.len()],
            suspended: Cell::new(false),
            period_ns: f64::from(ctx.queue.get_timestamp_period()),
        }
    }

    /// `(query set, begin index, end index)` of pass `name`; marks it written when `end`.
    fn slots(
        &self,
        name: &str,
        begin: bool,
        end: bool,
    ) -> Option<(&wgpu::QuerySet, Option<u32>, Option<u32>)> {
        let i = PASS_NAMES.iter().position(|n| *n == name)?;
        let (set, _) = self.queries.as_ref()?;
        if self.suspended.get() || (!begin && !end) {
            // A middle pass of a stage split over several passes writes nothing.
            return None;
        }
        if end {
            self.written[i].set(true);
        }
        Some((
            set,
            begin.then_some(2 * i as u32),
            end.then_some(2 * i as u32 + 1),
        ))
    }

    fn render(
        &self,
        name: &str,
        begin: bool,
        end: bool,
    ) -> Option<wgpu::RenderPassTimestampWrites<'_>> {
        self.slots(name, begin, end)
            .map(|(query_set, b, e)| wgpu::RenderPassTimestampWrites {
                query_set,
                beginning_of_pass_write_index: b,
                end_of_pass_write_index: e,
            })
    }

    fn compute(
        &self,
        name: &str,
        begin: bool,
        end: bool,
    ) -> Option<wgpu::ComputePassTimestampWrites<'_>> {
        self.slots(name, begin, end)
            .map(|(query_set, b, e)| wgpu::ComputePassTimestampWrites {
                query_set,
                beginning_of_pass_write_index: b,
                end_of_pass_write_index: e,
            })
    }

    fn resolve(&self, encoder: &mut wgpu::CommandEncoder, dst: &wgpu::Buffer) {
        if let Some((set, resolve)) = &self.queries {
            let count = PASS_NAMES.len() as u32 * 2;
            encoder.resolve_query_set(set, 0..count, resolve, 0);
            encoder.copy_buffer_to_buffer(
                resolve,
                0,
                dst,
                TIMESTAMP_OFFSET,
                Some(u64::from(count) * 8),
            );
        }
    }

    fn parse(&self, bytes: &[u8]) -> Timings {
        if self.queries.is_none() {
            return Timings::NotSupported;
        }
        let ts = |i: usize| {
            bytes
                .get(i * 8..i * 8 + 8)
                .and_then(|b| b.try_into().ok())
                .map_or(0, u64::from_le_bytes)
        };
        Timings::Passes(
            PASS_NAMES
                .iter()
                .enumerate()
                .filter(|(i, _)| self.written[*i].get())
                .map(|(i, name)| PassTiming {
                    name,
                    ms: ts(2 * i + 1).saturating_sub(ts(2 * i)) as f64 * self.period_ns * 1e-6,
                })
                .collect(),
        )
    }
}

/// The frame's command encoder; with [`StageTiming::WallClock`] each stage is submitted alone
/// and waited for, and its wall-clock time recorded.
struct Stages<'a> {
    ctx: &'a GpuContext,
    encoder: wgpu::CommandEncoder,
    wall: Option<(Instant, Vec<PassTiming>)>,
}

impl<'a> Stages<'a> {
    fn new(ctx: &'a GpuContext, timing: StageTiming) -> Result<Self, RenderError> {
        let wall = match timing {
            StageTiming::Timestamps => None,
            StageTiming::WallClock => {
                // Earlier work must not count toward the first stage.
                ctx.wait_idle()?;
                Some((Instant::now(), Vec::new()))
            }
        };
        Ok(Stages {
            ctx,
            encoder: Self::encoder(ctx),
            wall,
        })
    }

    fn encoder(ctx: &GpuContext) -> wgpu::CommandEncoder {
        ctx.device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("satf/encoder"),
            })
    }

    /// End stage `name`: with wall-clock timing, submit what was recorded, wait, and record it.
    fn cut(&mut self, name: &'static str) -> Result<(), RenderError> {
        let Some((start, times)) = &mut self.wall else {
            return Ok(());
        };
        let done = std::mem::replace(&mut self.encoder, Self::encoder(self.ctx));
        self.ctx.queue.submit([done.finish()]);
        self.ctx.wait_idle()?;
        let now = Instant::now();
        times.push(PassTiming {
            name,
            ms: (now - *start).as_secs_f64() * 1e3,
        });
        *start = now;
        Ok(())
    }
}

/// The SATF online renderer: renders clusters and a head into caller-provided targets.
#[derive(Debug)]
pub struct SatfRenderer {
    formats: TargetFormats,
    settings: SatfSettings,
    camera: wgpu::Buffer,
    lights: wgpu::Buffer,
    params: wgpu::Buffer,
    index_calc: IndexCalc,
    map_build: MapBuild,
    cluster_shadow: ClusterShadow,
    shadow_targets: ShadowTargets,
    s_maps: SMaps,
    lighting: Lighting,
    head: SatfHead,
    texture_map: TextureMap,
    timer: SatfTimer,
    readback: wgpu::Buffer,
    frame: u64,
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
        let (camera, lights, params) = ctx.scoped("creating SATF uniforms", || {
            (
                uniform_buffer(ctx, "satf/uniforms/camera", &CameraUniform::default()),
                uniform_buffer(ctx, "satf/uniforms/lights", &LightsUniform::default()),
                uniform_buffer(ctx, "satf/uniforms/params", &SatfParams::default()),
            )
        })?;
        let readback = ctx.scoped("creating the SATF readback buffer", || {
            ctx.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("satf/stats/readback"),
                size: TIMESTAMP_OFFSET + PASS_NAMES.len() as u64 * 16,
                usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            })
        })?;
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
            timer: SatfTimer::new(ctx),
            settings,
            camera,
            lights,
            params,
            readback,
            frame: 0,
        })
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
        let size = targets.validate_view(self.formats, &inputs.camera, inputs.lights.len())?;
        if !(inputs.ambient.is_finite() && inputs.head_color.is_finite()) {
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
        let bounds = match (geometry.map(|g| g.bounds), inputs.head.map(|h| h.bounds)) {
            (Some(a), Some(b)) => Some(union_sphere(a, b)),
            (a, b) => a.or(b),
        };
        let mut lights = LightsUniform {
            ambient: inputs.ambient.to_array(),
            count: inputs.lights.len() as u32,
            ..Default::default()
        };
        let mut light_cameras = Vec::new();
        for (i, light) in inputs.lights.iter().enumerate() {
            let (center, radius) = bounds.unwrap_or((Vec3::ZERO, 1.0));
            let (cam, range) = light.shadow_camera(center, radius, self.shadow_targets.size)?;
            lights.lights[i] = light.uniform(cam.clip_from_world(), range)?;
            light_cameras.push(cam.uniform());
        }
        let params = self.params(geometry, db, lights.count, inputs.head_color);
        let order = geometry.map_or_else(Vec::new, |g| {
            back_to_front(&inputs.camera, &g.cluster_bounds)
        });
        let q = &ctx.queue;
        q.write_buffer(
            &self.camera,
            0,
            bytemuck::bytes_of(&inputs.camera.uniform()),
        );
        q.write_buffer(&self.lights, 0, bytemuck::bytes_of(&lights));
        q.write_buffer(&self.params, 0, bytemuck::bytes_of(&params));

        let frame = self.frame;
        self.frame += 1;
        let shadows = params.cluster_shadows != 0 && geometry.is_some();
        let u = Uniforms {
            camera: &self.camera,
            lights: &self.lights,
            params: &self.params,
        };
        let timer = &self.timer;
        timer.written.iter().for_each(|w| w.set(false));
        let timing = self.settings.stage_timing;
        timer.suspended.set(timing == StageTiming::WallClock);
        let wall_times =
            ctx.scoped("rendering a SATF frame", || -> Result<_, RenderError> {
                let mut stages = Stages::new(ctx, timing)?;
                if let Some(g) = geometry {
                    let encoder = &mut stages.encoder;
                    // ---- index calculation (§6.2.1) and map construction (§6.2.2)
                    let ts = timer.compute("satf/index_calculation", true, true);
                    self.index_calc.encode(ctx, encoder, u, g, db, ts);
                    stages.cut("satf/index_calculation")?;
                    let ts = timer.compute("satf/map_construction", true, true);
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
                            inputs.head,
                            |i, _| {
                                begun = true;
                                timer.render("satf/shadowing", i == 0, false)
                            },
                        );
                    }
                    let ts = timer.compute("satf/shadowing", !begun, true);
                    self.s_maps
                        .encode(ctx, &mut stages.encoder, u, g, &self.shadow_targets, ts);
                    stages.cut("satf/shadowing")?;
                    // ---- lighting (§6.3)
                    let ts = timer.compute("satf/lighting", true, true);
                    self.lighting.encode(ctx, &mut stages.encoder, u, g, ts);
                    stages.cut("satf/lighting")?;
                }
                // ---- opaque head, depth written
                {
                    let mut pass = targets.begin_pass(
                        &mut stages.encoder,
                        "satf/head/pass",
                        clear_loads(inputs.clear),
                        timer.render("satf/head", true, true),
                    );
                    if let Some(head) = inputs.head {
                        self.head.draw(
                            ctx,
                            &mut pass,
                            [&self.camera, &self.lights, &self.params],
                            &self.shadow_targets,
                            head,
                        );
                    }
                }
                stages.cut("satf/head")?;
                // ---- texture mapping, shading and blending (§6.5)
                if let Some(g) = geometry {
                    self.texture_map.encode(
                        ctx,
                        &mut stages.encoder,
                        &self.camera,
                        &self.params,
                        g,
                        &order,
                        targets,
                        timer.render("satf/texture_mapping", true, true),
                    );
                    stages.cut("satf/texture_mapping")?;
                    stages.encoder.copy_buffer_to_buffer(
                        &g.counters,
                        0,
                        &self.readback,
                        0,
                        Some(size_of::<SatfCounters>() as u64),
                    );
                }
                timer.resolve(&mut stages.encoder, &self.readback);
                ctx.queue.submit([stages.encoder.finish()]);
                Ok(stages.wall.map(|(_, times)| times))
            })??;

        // ---- readback (waits for the frame)
        let bytes = read_buffer(ctx, &self.readback, 0..self.readback.size())?;
        let counters: SatfCounters = geometry.map_or_else(SatfCounters::default, |_| {
            bytemuck::pod_read_unaligned(&bytes[..size_of::<SatfCounters>()])
        });
        let timings = match wall_times {
            Some(times) => Timings::Passes(times),
            None => self.timer.parse(&bytes[TIMESTAMP_OFFSET as usize..]),
        };
        let l = geometry.map(|g| g.layout);
        Ok(SatfFrameStats {
            frame,
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
        let (c, r) = union_sphere((Vec3::ZERO, 1.0), (Vec3::new(4.0, 0.0, 0.0), 1.0));
        assert!((c.x - 2.0).abs() < 1e-6 && (r - 3.0).abs() < 1e-6);
    }
}
