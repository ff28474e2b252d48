//! [`Voxelizer`]: the volume's GPU resources and the voxelization of one frame (bounds, voxelize,
//! resolve); `readback.rs` reads everything back for tests and tools.

use wgpu::util::DeviceExt;

use crate::bind::Layouts;
use crate::gpu::read_buffer;
use crate::gpu::types::{ResolveArgs, VolumeGrid, VolumeParams, VoxelStats};
use crate::strands::StrandGeometry;
use crate::volume::volume_resolve::VOLUME_FORMAT;
use crate::volume::{
    AO_FORMAT, AoBake, OCCUPANCY_BLOCK, VolumeBounds, VolumeResolve, VolumeSettings, VolumeStats,
    Voxelize, ao_resolution,
};
use crate::{GpuContext, RenderError};
use tress_shading::highlights::{HIGHLIGHT_LIGHTS, HighlightView};

mod readback;
pub use readback::VolumeReadback;

/// The voxelization's scratch: the per-voxel counters (a count, two tangent-sum words and two
/// highlight-sum words, 20 bytes a voxel). One set serves every object's voxelization in turn, so
/// a frame of several volume characters holds it once.
#[derive(Debug)]
struct Scratch {
    counts: wgpu::Buffer,
    tangent_xy: wgpu::Buffer,
    tangent_z: wgpu::Buffer,
    highlights: wgpu::Buffer,
}

/// One object's volume: what stays after its voxelization (the two `rgba8unorm` textures, 8
/// bytes a voxel, the baked ambient occlusion while something reads it, 4 bytes a texel of
/// `volume.ao_texel³` voxels, and the occupancy blocks), its fitted grid, and the bind groups of its passes over its own settings uniform and the shared
/// [`Scratch`].
#[derive(Debug)]
struct Grid {
    keys: wgpu::Buffer,
    grid: wgpu::Buffer,
    grid_uniform: wgpu::Buffer,
    resolve_args: wgpu::Buffer,
    stats: wgpu::Buffer,
    occupancy: wgpu::Buffer,
    texture: wgpu::Texture,
    view: wgpu::TextureView,
    highlight_texture: wgpu::Texture,
    highlight_view: wgpu::TextureView,
    /// The baked ambient occlusion, while something reads it.
    ao: Option<BakedAo>,
    bounds_group: wgpu::BindGroup,
    voxelize_group: wgpu::BindGroup,
    resolve_group: wgpu::BindGroup,
    /// The settings uniform its passes read.
    params: wgpu::Buffer,
    /// Voxels per axis.
    res: u32,
    /// Unique among the voxelizer's grids: a bind group showing this grid is current while the
    /// object's serial is the one it was built with.
    serial: u64,
}

/// An object's baked ambient-occlusion texture (`volume.ao_texel`) and its bake's bind group.
#[derive(Debug)]
struct BakedAo {
    texture: wgpu::Texture,
    view: wgpu::TextureView,
    group: wgpu::BindGroup,
    /// Voxels a texel.
    texel: u32,
    /// Texels per axis.
    res: u32,
}

impl Grid {
    /// Voxels a texel of its baked AO (0: it has none).
    fn ao_texel(&self) -> u32 {
        self.ao.as_ref().map_or(0, |a| a.texel)
    }
}

/// The strand voxelizer (§3.3): owns the counters, the volume textures and the three compute
/// passes. One voxelization (recorded into the renderer's frame, or [`Voxelizer::voxelize`] on
/// its own) rebuilds a volume from the geometry as it is.
///
/// A frame of several heads of hair keeps one volume per object that needs one (its texture and
/// occupancy, about 8 bytes a voxel) and voxelizes them one after another through one shared
/// set of counters ([`Voxelizer::counter_bytes`], 20 bytes a voxel). Each object's grid has its
/// own resolution (the renderer sizes it by the object's size on screen,
/// [`VolumeSettings::object_resolution`]); the counters are sized for the largest grid and each
/// voxelization clears and uses only its own grid's share of them. The standalone API
/// (`voxelize`, `view`, `read_back`) works on object 0 at [`Voxelizer::resolution`].
#[derive(Debug)]
pub struct Voxelizer {
    bounds: VolumeBounds,
    voxelize: Voxelize,
    resolve: VolumeResolve,
    ao_bake: AoBake,
    /// The bake's density sampler (unused by its manual filter, bound for the shared signature).
    sampler: wgpu::Sampler,
    /// The resolution of the standalone API (and the renderer's `volume.resolution`).
    res: u32,
    scratch: Scratch,
    /// Voxels per axis the counters hold.
    scratch_res: u32,
    /// The next grid's serial.
    next_serial: u64,
    /// Object `i`'s volume, once it has needed one.
    grids: Vec<Option<Grid>>,
    /// The settings uniform of object 0 (the standalone API's).
    params0: wgpu::Buffer,
}

/// Bind group entries 0, 1, ... for whole buffers.
fn entries<'a>(bufs: &[&'a wgpu::Buffer]) -> Vec<wgpu::BindGroupEntry<'a>> {
    bufs.iter()
        .enumerate()
        .map(|(i, b)| wgpu::BindGroupEntry {
            binding: i as u32,
            resource: b.as_entire_binding(),
        })
        .collect()
}

/// Storage buffers the voxelize and resolve passes bind in the compute stage (the voxelize pass:
/// counters, tangent sums, highlight sums, stats, grid, strand vertices and segments; the
/// resolve: the same counters and sums, grid, occupancy, region and stats).
const STORAGE_BUFFERS_PER_STAGE: u32 = 8;

const GRID_BYTES: u64 = std::mem::size_of::<VolumeGrid>() as u64;

fn buffer(ctx: &GpuContext, label: &str, size: u64, usage: wgpu::BufferUsages) -> wgpu::Buffer {
    ctx.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size,
        usage,
        mapped_at_creation: false,
    })
}

/// A `res³` 3D texture of `format` the volume's passes write and its shading samples.
fn texture_3d(
    ctx: &GpuContext,
    label: &str,
    res: u32,
    format: wgpu::TextureFormat,
) -> (wgpu::Texture, wgpu::TextureView) {
    let texture = ctx.device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d {
            width: res,
            height: res,
            depth_or_array_layers: res,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D3,
        format,
        usage: wgpu::TextureUsages::STORAGE_BINDING
            | wgpu::TextureUsages::TEXTURE_BINDING
            | wgpu::TextureUsages::COPY_SRC,
        view_formats: &[],
    });
    let view = texture.create_view(&wgpu::TextureViewDescriptor::default());
    (texture, view)
}

impl Voxelizer {
    /// A voxelizer of `resolution³` with its own settings uniform (write it with
    /// [`Voxelizer::voxelize`]).
    pub fn new(ctx: &GpuContext, resolution: u32) -> Result<Self, RenderError> {
        let params = ctx
            .device
            .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("volume/voxelizer/params"),
                contents: bytemuck::bytes_of(&VolumeParams::default()),
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            });
        let mut voxelizer = Self::with_params(
            ctx,
            &Layouts::new(&ctx.device),
            (resolution, resolution),
            &params,
        )?;
        voxelizer.ensure_grid(ctx, 0, &params, resolution, 0)?;
        Ok(voxelizer)
    }

    /// A voxelizer with no volume yet, whose object 0 reads its settings from `params` (a
    /// [`VolumeParams`] uniform the caller writes each frame); objects get theirs with
    /// [`Voxelizer::ensure_grid`]. Its counters start at `scratch_resolution³` (at most
    /// `resolution`) and grow with the grids.
    pub(crate) fn with_params(
        ctx: &GpuContext,
        layouts: &Layouts,
        (resolution, scratch_resolution): (u32, u32),
        params: &wgpu::Buffer,
    ) -> Result<Self, RenderError> {
        Self::check(ctx, resolution)?;
        let scratch_res = scratch_resolution.clamp(1, resolution);
        Ok(Voxelizer {
            bounds: VolumeBounds::new(ctx, layouts)?,
            voxelize: Voxelize::new(ctx, layouts)?,
            resolve: VolumeResolve::new(ctx)?,
            ao_bake: AoBake::new(ctx)?,
            sampler: ctx.scoped("creating the AO bake's sampler", || {
                ctx.device.create_sampler(&wgpu::SamplerDescriptor {
                    label: Some("volume/ao_bake/sampler"),
                    mag_filter: wgpu::FilterMode::Linear,
                    min_filter: wgpu::FilterMode::Linear,
                    ..Default::default()
                })
            })?,
            res: resolution,
            scratch: Self::allocate_scratch(ctx, scratch_res)?,
            scratch_res,
            next_serial: 0,
            grids: Vec::new(),
            params0: params.clone(),
        })
    }

    /// Check that the device can hold a `res³` volume and run the voxelizer: the resolution's
    /// range, the 3D texture edge, each counter buffer against the storage-binding and buffer
    /// limits, and the storage buffers the voxelize pass binds in one stage.
    pub fn check(ctx: &GpuContext, res: u32) -> Result<(), RenderError> {
        let lo = tress_shading::voxelize::MIN_RESOLUTION;
        let hi = tress_shading::voxelize::MAX_RESOLUTION;
        if !(lo..=hi).contains(&res) {
            return Err(RenderError::Invalid(format!(
                "volume.resolution {res} is outside {lo}..={hi}"
            )));
        }
        let limits = ctx.device.limits();
        if limits.max_storage_buffers_per_shader_stage < STORAGE_BUFFERS_PER_STAGE {
            return Err(RenderError::MissingCapability {
                adapter: ctx.adapter_info.name.clone(),
                missing: format!(
                    "{STORAGE_BUFFERS_PER_STAGE} storage buffers per shader stage for the \
                     voxelizer (has {})",
                    limits.max_storage_buffers_per_shader_stage
                ),
            });
        }
        if res > limits.max_texture_dimension_3d {
            return Err(RenderError::Limit {
                what: format!("a {res}³ volume texture (edge)"),
                needed: u64::from(res),
                limit: u64::from(limits.max_texture_dimension_3d),
            });
        }
        // The largest counter buffer: the highlight sums, two words a voxel.
        let counter_bytes = u64::from(res).pow(3) * 8;
        let limit = ctx.caps.max_storage_binding.min(ctx.caps.max_buffer_size);
        if counter_bytes > limit {
            return Err(RenderError::Limit {
                what: format!("the highlight sums of a {res}³ volume"),
                needed: counter_bytes,
                limit,
            });
        }
        Ok(())
    }

    fn allocate_scratch(ctx: &GpuContext, res: u32) -> Result<Scratch, RenderError> {
        let counter_bytes = u64::from(res).pow(3) * 4;
        ctx.scoped("allocating the voxel counters", || {
            use wgpu::BufferUsages as U;
            let storage = U::STORAGE | U::COPY_DST | U::COPY_SRC;
            Scratch {
                counts: buffer(ctx, "volume/voxelize/counts", counter_bytes, storage),
                tangent_xy: buffer(ctx, "volume/voxelize/tangent-xy", counter_bytes, storage),
                tangent_z: buffer(ctx, "volume/voxelize/tangent-z", counter_bytes, storage),
                highlights: buffer(
                    ctx,
                    "volume/voxelize/highlights",
                    counter_bytes * 2,
                    storage,
                ),
            }
        })
    }

    fn allocate_grid(
        &mut self,
        ctx: &GpuContext,
        params: &wgpu::Buffer,
        res: u32,
        ao_texel: u32,
    ) -> Result<Grid, RenderError> {
        let serial = self.next_serial;
        self.next_serial += 1;
        let blocks = u64::from(res.div_ceil(OCCUPANCY_BLOCK)).pow(3) * 4;
        let Scratch {
            counts,
            tangent_xy,
            tangent_z,
            highlights,
        } = &self.scratch;
        ctx.scoped("allocating the volume", || {
            use wgpu::BufferUsages as U;
            let storage = U::STORAGE | U::COPY_DST | U::COPY_SRC;
            let keys = buffer(ctx, "volume/bounds/keys", 32, storage);
            let grid = buffer(ctx, "volume/bounds/grid", GRID_BYTES, storage);
            let grid_uniform = buffer(
                ctx,
                "volume/grid/uniform",
                GRID_BYTES,
                U::UNIFORM | U::COPY_DST,
            );
            let resolve_args = buffer(
                ctx,
                "volume/bounds/resolve-args",
                std::mem::size_of::<ResolveArgs>() as u64,
                storage | U::INDIRECT,
            );
            let stats = buffer(ctx, "volume/voxelize/stats", 16, storage);
            let occupancy = buffer(ctx, "volume/resolve/occupancy", blocks, storage);
            let volume_texture = |label: &str| texture_3d(ctx, label, res, VOLUME_FORMAT);
            let (texture, view) = volume_texture("volume/resolve/texture");
            let (highlight_texture, highlight_view) = volume_texture("volume/resolve/highlights");
            let group =
                |label: &str, layout: &wgpu::BindGroupLayout, e: &[wgpu::BindGroupEntry<'_>]| {
                    ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
                        label: Some(label),
                        layout,
                        entries: e,
                    })
                };
            let bounds_group = group(
                "volume/volume_bounds/bind-group",
                &self.bounds.layout,
                &entries(&[params, &keys, &grid, &resolve_args]),
            );
            let voxelize_group = group(
                "volume/voxelize/bind-group",
                &self.voxelize.layout,
                &entries(&[
                    params, &grid, counts, tangent_xy, tangent_z, &stats, highlights,
                ]),
            );
            let mut e = entries(&[params, &grid, counts, tangent_xy, tangent_z]);
            e.push(wgpu::BindGroupEntry {
                binding: 5,
                resource: wgpu::BindingResource::TextureView(&view),
            });
            e.push(wgpu::BindGroupEntry {
                binding: 6,
                resource: occupancy.as_entire_binding(),
            });
            e.push(wgpu::BindGroupEntry {
                binding: 7,
                resource: resolve_args.as_entire_binding(),
            });
            e.push(wgpu::BindGroupEntry {
                binding: 8,
                resource: stats.as_entire_binding(),
            });
            e.push(wgpu::BindGroupEntry {
                binding: 9,
                resource: highlights.as_entire_binding(),
            });
            e.push(wgpu::BindGroupEntry {
                binding: 10,
                resource: wgpu::BindingResource::TextureView(&highlight_view),
            });
            let resolve_group = group("volume/volume_resolve/bind-group", &self.resolve.layout, &e);
            let ao = (ao_texel > 0).then(|| {
                let ao_res = ao_resolution(res, ao_texel);
                let (texture, ao_view) =
                    texture_3d(ctx, "volume/ao_bake/texture", ao_res, AO_FORMAT);
                let group = crate::bind::bind_group(
                    ctx,
                    "volume/ao_bake/bind-group",
                    &self.ao_bake.layout,
                    &[
                        (0, params.as_entire_binding()),
                        (1, grid.as_entire_binding()),
                        (2, occupancy.as_entire_binding()),
                        (3, wgpu::BindingResource::TextureView(&view)),
                        (4, wgpu::BindingResource::Sampler(&self.sampler)),
                        (5, wgpu::BindingResource::TextureView(&ao_view)),
                    ],
                );
                BakedAo {
                    texture,
                    view: ao_view,
                    group,
                    texel: ao_texel,
                    res: ao_res,
                }
            });
            Grid {
                keys,
                grid,
                grid_uniform,
                resolve_args,
                stats,
                occupancy,
                texture,
                view,
                highlight_texture,
                highlight_view,
                ao,
                bounds_group,
                voxelize_group,
                resolve_group,
                params: params.clone(),
                res,
                serial,
            }
        })
    }

    /// Give object `object` a `res³` volume reading its settings from `params`, with a baked
    /// ambient-occlusion texture of `ao_texel` voxels a texel (0: none), unless it has one of
    /// that resolution and texel; true when one was allocated (the caller rebuilds the bind groups
    /// that show it: [`Voxelizer::grid_serial`] tells which). Counters too small for it grow,
    /// which rebuilds every grid.
    pub(crate) fn ensure_grid(
        &mut self,
        ctx: &GpuContext,
        object: usize,
        params: &wgpu::Buffer,
        res: u32,
        ao_texel: u32,
    ) -> Result<bool, RenderError> {
        if self
            .grid(object)
            .is_some_and(|g| g.res == res && g.ao_texel() == ao_texel)
        {
            return Ok(false);
        }
        Self::check(ctx, res)?;
        if res > self.scratch_res {
            self.resize_scratch(ctx, res)?;
        }
        let grid = self.allocate_grid(ctx, params, res, ao_texel)?;
        if self.grids.len() <= object {
            self.grids.resize_with(object + 1, || None);
        }
        self.grids[object] = Some(grid);
        Ok(true)
    }

    /// Size the counters for the largest grid there is (after grids were released or shrunk);
    /// true when they changed, which rebuilds every grid.
    pub(crate) fn fit_scratch(&mut self, ctx: &GpuContext) -> Result<bool, RenderError> {
        let Some(largest) = self.grids.iter().flatten().map(|g| g.res).max() else {
            return Ok(false);
        };
        if largest == self.scratch_res {
            return Ok(false);
        }
        self.resize_scratch(ctx, largest)?;
        Ok(true)
    }

    /// New counters of `res³`, and every grid rebuilt over them (their bind groups name the
    /// counters; what they hold is rebuilt by the next voxelization anyway).
    fn resize_scratch(&mut self, ctx: &GpuContext, res: u32) -> Result<(), RenderError> {
        self.scratch = Self::allocate_scratch(ctx, res)?;
        self.scratch_res = res;
        let kept: Vec<Option<(wgpu::Buffer, u32, u32)>> = self
            .grids
            .iter()
            .map(|g| g.as_ref().map(|g| (g.params.clone(), g.res, g.ao_texel())))
            .collect();
        for (object, k) in kept.into_iter().enumerate() {
            if let Some((params, res, ao_texel)) = k {
                let grid = self.allocate_grid(ctx, &params, res, ao_texel)?;
                self.grids[object] = Some(grid);
            }
        }
        Ok(())
    }

    /// Object `object`'s grid resolution (`None` without a volume).
    pub(crate) fn grid_resolution(&self, object: usize) -> Option<u32> {
        self.grid(object).map(|g| g.res)
    }

    /// The serial of object `object`'s grid: it changes whenever the grid is reallocated.
    pub(crate) fn grid_serial(&self, object: usize) -> Option<u64> {
        self.grid(object).map(|g| g.serial)
    }

    /// Free object `object`'s volume (it no longer needs one); true when it had one.
    pub(crate) fn release_grid(&mut self, object: usize) -> bool {
        self.grids.get_mut(object).and_then(Option::take).is_some()
    }

    fn grid(&self, object: usize) -> Option<&Grid> {
        self.grids.get(object).and_then(Option::as_ref)
    }

    /// Object 0's volume, for the standalone API.
    fn grid0(&self) -> Result<&Grid, RenderError> {
        self.grid(0)
            .ok_or_else(|| RenderError::Invalid("the voxelizer has not voxelized anything".into()))
    }

    /// Reallocate for another resolution (no-op when it is the same): the counters and every
    /// object's volume, all at `resolution`.
    pub fn set_resolution(&mut self, ctx: &GpuContext, resolution: u32) -> Result<(), RenderError> {
        if resolution != self.res {
            Self::check(ctx, resolution)?;
            self.res = resolution;
            for g in self.grids.iter_mut().flatten() {
                g.res = resolution;
            }
            self.resize_scratch(ctx, resolution)?;
        }
        Ok(())
    }

    /// Voxels per axis.
    pub fn resolution(&self) -> u32 {
        self.res
    }

    /// Bytes of the counters, and of every object's texture and occupancy.
    pub fn bytes(&self) -> u64 {
        self.counter_bytes()
            + (0..self.grids.len())
                .map(|i| self.object_grid_bytes(i))
                .sum::<u64>()
    }

    /// Bytes of the shared voxel counters (20 a voxel of the largest grid).
    pub fn counter_bytes(&self) -> u64 {
        Self::settings_at(self.scratch_res).counter_bytes()
    }

    /// Bytes a volume at [`Voxelizer::resolution`] keeps between frames: its two textures (8 a
    /// voxel) and occupancy blocks.
    pub fn grid_bytes(&self) -> u64 {
        Self::settings_at(self.res).resident_bytes()
    }

    /// Bytes object `object`'s volume keeps between frames (0 without one).
    pub fn object_grid_bytes(&self, object: usize) -> u64 {
        self.grid(object).map_or(0, |g| {
            Self::settings_at(g.res).resident_bytes()
                + g.ao.as_ref().map_or(0, |a| u64::from(a.res).pow(3) * 4)
        })
    }

    /// Objects that have a volume.
    pub fn grid_count(&self) -> usize {
        self.grids.iter().flatten().count()
    }

    fn settings_at(resolution: u32) -> VolumeSettings {
        VolumeSettings {
            resolution,
            ..Default::default()
        }
    }

    /// Object 0's volume texture's view (rgb mean tangent, a density), once it has one.
    pub fn view(&self) -> Option<&wgpu::TextureView> {
        self.object_view(0)
    }

    /// Object `object`'s volume texture (`None` when it has none).
    pub(crate) fn object_view(&self, object: usize) -> Option<&wgpu::TextureView> {
        self.grid(object).map(|g| &g.view)
    }

    /// Object `object`'s highlight texture (each light's mean highlight; `None` when it has no
    /// volume).
    pub(crate) fn highlights(&self, object: usize) -> Option<&wgpu::TextureView> {
        self.grid(object).map(|g| &g.highlight_view)
    }

    /// Object `object`'s baked ambient-occlusion texture (`None` when it has no volume).
    pub(crate) fn ao_view(&self, object: usize) -> Option<&wgpu::TextureView> {
        self.grid(object)?.ao.as_ref().map(|a| &a.view)
    }

    /// The uniform copy of the grid object `object`'s last voxelization fitted.
    pub(crate) fn grid_uniform(&self, object: usize) -> Option<&wgpu::Buffer> {
        self.grid(object).map(|g| &g.grid_uniform)
    }

    /// Object `object`'s occupancy blocks (read by the raymarcher's empty-space skipping).
    pub(crate) fn occupancy(&self, object: usize) -> Option<&wgpu::Buffer> {
        self.grid(object).map(|g| &g.occupancy)
    }

    /// Object `object`'s deposit/drop counters (copied into the frame's statistics).
    pub(crate) fn stats_buffer(&self, object: usize) -> Option<&wgpu::Buffer> {
        self.grid(object).map(|g| &g.stats)
    }

    /// Record a whole voxelization of `geometry` into object `object`'s volume (clear the
    /// counters, bounds, voxelize, resolve, the ambient-occlusion bake when it has the texture,
    /// grid copy); nothing when it has none. Its [`VolumeParams`] uniform must describe this geometry
    /// and resolution. Voxelizations recorded one after another share the counters.
    pub(crate) fn encode(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        object: usize,
        geometry: &StrandGeometry,
        timestamps: Option<wgpu::ComputePassTimestampWrites<'_>>,
    ) {
        let Some(g) = self.grid(object) else { return };
        let s = &self.scratch;
        // Only the grid's own share of the counters: a far character's small grid clears
        // kilobytes, not the largest grid's megabytes.
        let words = u64::from(g.res).pow(3) * 4;
        for (b, size) in [
            (&s.counts, Some(words)),
            (&s.tangent_xy, Some(words)),
            (&s.tangent_z, Some(words)),
            (&s.highlights, Some(words * 2)),
            (&g.stats, None),
            (&g.occupancy, None),
        ] {
            encoder.clear_buffer(b, 0, size);
        }
        {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("volume/voxelize/pass"),
                timestamp_writes: timestamps,
            });
            self.bounds.encode(&mut pass, &g.bounds_group, geometry);
            self.voxelize.encode(&mut pass, &g.voxelize_group, geometry);
            self.resolve
                .encode(&mut pass, &g.resolve_group, &g.resolve_args);
            if let Some(ao) = &g.ao {
                self.ao_bake.encode(&mut pass, &ao.group, ao.res);
            }
        }
        encoder.copy_buffer_to_buffer(&g.grid, 0, &g.grid_uniform, 0, Some(GRID_BYTES));
    }

    /// The [`VolumeParams`] of a voxelization of `geometry` with `settings` (the raymarching and
    /// shading fields at their defaults; the renderer fills those per frame).
    pub fn params(settings: &VolumeSettings, geometry: &StrandGeometry) -> VolumeParams {
        VolumeParams {
            steps: settings.steps,
            iso: settings.iso,
            skip_empty: u32::from(settings.skip_empty),
            shadow_alpha: settings.shadow_alpha,
            shadow_step: settings.shadow_step,
            shadow_offset: settings.shadow_offset,
            ao_radius: settings.ao_radius,
            ao_samples: settings.ao_samples,
            ao_intensity: settings.ao_intensity,
            voxelize: match settings.voxelize {
                tress_shading::VoxelizeMode::Vertices => 0,
                tress_shading::VoxelizeMode::Segments => 1,
            },
            reconstruction_radius: settings.reconstruction_radius,
            capacity: settings.max_strands_per_voxel,
            mean_segment_length: geometry.mean_segment_length(),
            segment_count: geometry.segment_count(),
            vertex_count: geometry.vertex_count(),
            occupancy_res: settings.resolution.div_ceil(OCCUPANCY_BLOCK),
            resolution: settings.resolution,
            march_shadows: u32::from(settings.shadows),
            march_ao: u32::from(settings.ao),
            ao_texel: settings.ao_texel,
            strand_width: settings.strand_width,
            occlusion: settings.occlusion.gpu(),
            shade_samples: settings.shade_samples,
            // The renderer adds the frame's view, lights and exponent (and turns it off for
            // shading models other than Kajiya-Kay); without lights nothing is integrated.
            highlights: u32::from(settings.highlights == crate::volume::Highlights::Strands),
            ..Default::default()
        }
    }

    /// Give `params` the view, lights and exponent the voxelizer integrates highlights for (when
    /// its settings ask for them: `params.highlights` stays as [`Voxelizer::params`] set it).
    pub fn set_highlight_view(params: &mut VolumeParams, view: &HighlightView) {
        params.highlight_exponent = view.exponent;
        params.view_eye = view.eye.to_array();
        params.view_orthographic = u32::from(view.orthographic);
        params.view_forward = view.forward.to_array();
        params.light_count = view.lights.len().min(HIGHLIGHT_LIGHTS) as u32;
        params.light_dirs = [[0.0; 4]; 4];
        for (dir, l) in params.light_dirs.iter_mut().zip(&view.lights) {
            *dir = l.extend(0.0).to_array();
        }
    }

    /// Voxelize `geometry` with `settings` now (writes the params uniform, submits, waits) and
    /// return the counters' statistics. For tools and tests; the renderer records
    /// the same work into its frame.
    pub fn voxelize(
        &mut self,
        ctx: &GpuContext,
        geometry: &StrandGeometry,
        settings: &VolumeSettings,
    ) -> Result<VolumeStats, RenderError> {
        self.voxelize_faded(ctx, geometry, settings, 0.0)
    }

    /// [`Voxelizer::voxelize`] with the strands' tip fade: each sample's tangent weighed by its
    /// segment's thickness over `fade_ref` (0: no fade), as the renderer does under
    /// `strands.thickness_fade = "tip"`.
    pub fn voxelize_faded(
        &mut self,
        ctx: &GpuContext,
        geometry: &StrandGeometry,
        settings: &VolumeSettings,
        fade_ref: f32,
    ) -> Result<VolumeStats, RenderError> {
        self.voxelize_lit(ctx, geometry, settings, fade_ref, None)
    }

    /// [`Voxelizer::voxelize_faded`] that also integrates the strands' highlights for `view`
    /// (its eye and lights; `None`, or `volume.highlights = "mean_tangent"`: none).
    pub fn voxelize_lit(
        &mut self,
        ctx: &GpuContext,
        geometry: &StrandGeometry,
        settings: &VolumeSettings,
        fade_ref: f32,
        view: Option<&HighlightView>,
    ) -> Result<VolumeStats, RenderError> {
        settings.validate()?;
        self.set_resolution(ctx, settings.resolution)?;
        let params0 = self.params0.clone();
        // The raymarcher's AO (`ao`) is the standalone volume's only reader of the bake.
        let ao_texel = if settings.ao { settings.ao_texel } else { 0 };
        self.ensure_grid(ctx, 0, &params0, settings.resolution, ao_texel)?;
        let mut params = Self::params(settings, geometry);
        params.fade_ref = fade_ref;
        match view {
            Some(v) => Self::set_highlight_view(&mut params, v),
            None => params.highlights = 0,
        }
        ctx.queue
            .write_buffer(&self.params0, 0, bytemuck::bytes_of(&params));
        ctx.scoped("voxelizing", || {
            let mut encoder = ctx
                .device
                .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                    label: Some("volume/voxelizer/encoder"),
                });
            self.encode(&mut encoder, 0, geometry, None);
            ctx.queue.submit([encoder.finish()]);
        })?;
        let s: VoxelStats =
            bytemuck::pod_read_unaligned(&self.read(ctx, &self.grid0()?.stats, 16)?);
        Ok(VolumeStats {
            deposits: s.deposits,
            dropped: s.dropped,
            saturated: s.saturated,
        })
    }

    fn read(
        &self,
        ctx: &GpuContext,
        src: &wgpu::Buffer,
        size: u64,
    ) -> Result<Vec<u8>, RenderError> {
        let staging = ctx.scoped("volume readback", || {
            let staging = buffer(
                ctx,
                "volume/readback/staging",
                size,
                wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            );
            let mut encoder = ctx
                .device
                .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                    label: Some("volume/readback/encoder"),
                });
            encoder.copy_buffer_to_buffer(src, 0, &staging, 0, Some(size));
            ctx.queue.submit([encoder.finish()]);
            staging
        })?;
        read_buffer(ctx, &staging, 0..size)
    }
}
