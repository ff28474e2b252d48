//! [`SatfGeometry`]: a hair volume's clusters uploaded for the online phase: boundary sectors
//! (anchor frames and density features), layer meshes, the per-frame HSV buffers and the map
//! atlas.

use std::f32::consts::TAU;
use std::time::Instant;

use glam::Vec3;
use tress_satf::hierarchy::VolumeStats;
use tress_satf::{HairVolume, ShellSampling, shell};
use wgpu::util::DeviceExt;

use super::{SatfDatabase, SatfSettings};
use crate::gpu::types::{HsvRecord, SatfCounters, SatfSector, SatfVertex, SectorParams};
use crate::gpu::{LinearImage, read_buffer, read_texture};
use crate::{GpuContext, RenderError};

/// Largest compute dispatch along one dimension (WebGPU's default limit).
const MAX_DISPATCH: u32 = 65_535;

/// How the geometry's buffers and atlas are laid out (shared with the passes).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct SatfLayout {
    pub(crate) sampling: ShellSampling,
    pub(crate) clusters: u32,
    pub(crate) layers: u32,
    pub(crate) pixels: u32,
    pub(crate) map_rows: u32,
    pub(crate) mesh_nt: u32,
    pub(crate) mesh_nu: u32,
    pub(crate) tile_width: u32,
    pub(crate) tile_height: u32,
    pub(crate) tiles_per_row: u32,
    pub(crate) atlas: [u32; 2],
}

impl SatfLayout {
    pub(crate) fn tiles(&self) -> u32 {
        self.clusters * self.layers
    }
    pub(crate) fn sectors(&self) -> u32 {
        self.clusters * self.sampling.sector_count() as u32
    }
    pub(crate) fn hsvs(&self) -> u32 {
        self.clusters * self.sampling.hsv_count() as u32
    }
    pub(crate) fn vertices_per_tile(&self) -> u32 {
        (self.mesh_nt + 1) * (self.mesh_nu + 1)
    }
    pub(crate) fn indices_per_tile(&self) -> u32 {
        self.mesh_nt * self.mesh_nu * 6
    }
}

/// The four map textures of the atlas (all rgba16float), one tile per (cluster, layer).
#[derive(Debug)]
pub(crate) struct Atlas {
    textures: [wgpu::Texture; 4],
    /// `(re, α, 0, 0)` (map construction).
    pub(crate) maps: wgpu::TextureView,
    /// `(τ, 0, 0, 0)` (equation 12).
    pub(crate) s_map: wgpu::TextureView,
    /// Light visibility through other clusters (lights 0..3).
    pub(crate) vis: wgpu::TextureView,
    /// `(Y_lighting, 1)`.
    pub(crate) l_map: wgpu::TextureView,
}

/// Clusters uploaded for the SATF renderer.
#[derive(Debug)]
pub struct SatfGeometry {
    pub(crate) layout: SatfLayout,
    pub(crate) sectors: wgpu::Buffer,
    pub(crate) vertices: wgpu::Buffer,
    pub(crate) indices: wgpu::Buffer,
    pub(crate) sector_params: wgpu::Buffer,
    pub(crate) hsvs: wgpu::Buffer,
    pub(crate) counters: wgpu::Buffer,
    pub(crate) atlas: Atlas,
    /// Bounding sphere per cluster (for the back-to-front sort).
    pub(crate) cluster_bounds: Vec<(Vec3, f32)>,
    /// Bounding sphere of everything.
    pub bounds: (Vec3, f32),
    stats: VolumeStats,
    features_ms: f64,
}

/// One cluster's CPU data.
struct ClusterData {
    sectors: Vec<SatfSector>,
    vertices: Vec<SatfVertex>,
    bounds: (Vec3, f32),
}

fn sphere_of(points: impl Iterator<Item = Vec3> + Clone) -> (Vec3, f32) {
    let (lo, hi) = points.clone().fold(
        (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
        |(lo, hi), p| (lo.min(p), hi.max(p)),
    );
    if !lo.is_finite() {
        return (Vec3::ZERO, 0.0);
    }
    let c = (lo + hi) * 0.5;
    let r = points.map(|p| p.distance(c)).fold(0.0f32, f32::max);
    (c, r)
}

/// The index list of one tile: `(a, a+du, a+dt)` and `(a+du, a+du+dt, a+dt)`, counter-clockwise
/// seen from outside (`s_axis × tangent` is the outward normal).
fn tile_indices(nt: u32, nu: u32) -> Vec<u32> {
    let row = nu + 1;
    let mut out = Vec::with_capacity((nt * nu * 6) as usize);
    for y in 0..nt {
        for x in 0..nu {
            let a = y * row + x;
            let (b, d) = (a + 1, a + row);
            let c = d + 1;
            out.extend_from_slice(&[a, b, d, b, c, d]);
        }
    }
    out
}

impl SatfGeometry {
    /// Prepare and upload `volume` for `database` with `settings` (validated): the sector
    /// features (CPU, rayon), anchors and layer meshes, the atlas. Errors when the atlas or a
    /// buffer exceeds the device's limits.
    pub fn new(
        ctx: &GpuContext,
        volume: &HairVolume,
        database: &SatfDatabase,
        settings: &SatfSettings,
    ) -> Result<Self, RenderError> {
        settings.validate()?;
        let sampling = settings.sampling;
        let layers = sampling.layers();
        let clusters: Vec<_> = volume.clusters().collect();
        let cluster_count = clusters.len() as u32;
        let pixels = database.pixels();
        let (mesh_nt, mesh_nu) = (sampling.st * settings.mesh_t, sampling.su * settings.mesh_u);
        let tile_width = sampling.su * pixels;
        let tile_height = sampling.st * settings.map_rows;
        let max_2d = ctx.caps.max_texture_2d;
        if tile_width > max_2d || tile_height > max_2d {
            return Err(RenderError::Invalid(format!(
                "satf: a map tile of {tile_width}x{tile_height} texels exceeds the device's {max_2d}"
            )));
        }
        let tiles = cluster_count.max(1) * layers;
        let tiles_per_row = (max_2d / tile_width).clamp(1, tiles);
        let rows = tiles.div_ceil(tiles_per_row);
        let atlas = [tiles_per_row * tile_width, rows * tile_height];
        if atlas[1] > max_2d || tiles > MAX_DISPATCH {
            return Err(RenderError::Invalid(format!(
                "satf: {cluster_count} clusters of {layers} layers need a {}x{} map atlas; the \
                 device allows {max_2d} (use fewer clusters or a smaller s_t, s_u or map_rows)",
                atlas[0], atlas[1]
            )));
        }
        let layout = SatfLayout {
            sampling,
            clusters: cluster_count,
            layers,
            pixels,
            map_rows: settings.map_rows,
            mesh_nt,
            mesh_nu,
            tile_width,
            tile_height,
            tiles_per_row,
            atlas,
        };
        if layout.sectors().div_ceil(64) > MAX_DISPATCH {
            return Err(RenderError::Invalid(format!(
                "satf: {} boundary sectors are more than one dispatch can cover",
                layout.sectors()
            )));
        }

        // ---- CPU: features (the view-independent part of the index calculation, parallel inside
        // cluster_features), anchors, meshes
        let start = Instant::now();
        let features: Vec<Vec<[f32; 3]>> = clusters
            .iter()
            .map(|(_, c)| shell::cluster_features(c, &sampling, database.density()))
            .collect();
        let features_ms = start.elapsed().as_secs_f64() * 1e3;
        let data: Vec<ClusterData> = clusters
            .iter()
            .zip(&features)
            .enumerate()
            .map(|(ci, ((g, c), f))| {
                let mut sectors = Vec::with_capacity(sampling.sector_count());
                for i in 0..=sampling.st {
                    for layer in 0..layers {
                        for m in 0..sampling.su {
                            let s = c.sector_surface(g, &sampling, i, layer, m);
                            let feat = f[sampling.sector_index(i, layer, m)];
                            sectors.push(SatfSector {
                                position: s.position.to_array(),
                                cluster: ci as u32,
                                normal: s.normal.to_array(),
                                s_axis: s.s_axis.to_array(),
                                features: feat,
                                ..Default::default()
                            });
                        }
                    }
                }
                let mut vertices =
                    Vec::with_capacity((layers * layout.vertices_per_tile()) as usize);
                for layer in 0..layers {
                    let v = sampling.v(sampling.ring_of_layer(layer) + 1);
                    for y in 0..=mesh_nt {
                        let t = y as f32 / mesh_nt as f32;
                        for x in 0..=mesh_nu {
                            let uf = x as f32 / mesh_nu as f32;
                            let s = c.surface(g, t, v, TAU * uf);
                            vertices.push(SatfVertex {
                                position: s.position.to_array(),
                                u: uf,
                                tangent: s.tangent.to_array(),
                                t,
                                normal: s.normal.to_array(),
                                tile: ci as u32 * layers + layer,
                            });
                        }
                    }
                }
                let outer = (layers - 1) as usize * layout.vertices_per_tile() as usize;
                let bounds = sphere_of(vertices[outer..].iter().map(|v| Vec3::from(v.position)));
                ClusterData {
                    sectors,
                    vertices,
                    bounds,
                }
            })
            .collect();
        let mut sectors = Vec::with_capacity(layout.sectors() as usize);
        let mut vertices =
            Vec::with_capacity((layout.tiles() * layout.vertices_per_tile()) as usize);
        let mut cluster_bounds = Vec::with_capacity(data.len());
        for d in data {
            sectors.extend(d.sectors);
            vertices.extend(d.vertices);
            cluster_bounds.push(d.bounds);
        }
        if vertices.is_empty() {
            // Buffers cannot be empty; one degenerate vertex and sector are never drawn.
            vertices.push(SatfVertex::default());
        }
        if sectors.is_empty() {
            sectors.push(SatfSector::default());
        }
        let bounds = sphere_of(vertices.iter().map(|v| Vec3::from(v.position)));
        let limit = ctx.caps.max_storage_binding.min(ctx.caps.max_buffer_size);
        let vertex_bytes = (vertices.len() * size_of::<SatfVertex>()) as u64;
        if vertex_bytes > limit {
            return Err(RenderError::Limit {
                what: "satf: layer mesh vertices".into(),
                needed: vertex_bytes,
                limit,
            });
        }
        let hsv_count = layout.hsvs().max(1) as usize;
        let sector_count = sectors.len();

        let (sectors, vertices, indices, sector_params, hsvs, counters, atlas) =
            ctx.scoped("uploading SATF clusters", || {
                let init = |label: &str, contents: &[u8], usage| {
                    ctx.device
                        .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                            label: Some(label),
                            contents,
                            usage,
                        })
                };
                let empty = |label: &str, size: u64, usage| {
                    ctx.device.create_buffer(&wgpu::BufferDescriptor {
                        label: Some(label),
                        size,
                        usage,
                        mapped_at_creation: false,
                    })
                };
                let storage = wgpu::BufferUsages::STORAGE;
                let readable = storage | wgpu::BufferUsages::COPY_SRC;
                (
                    init(
                        "satf/geometry/sectors",
                        bytemuck::cast_slice(&sectors),
                        storage,
                    ),
                    init(
                        "satf/geometry/vertices",
                        bytemuck::cast_slice(&vertices),
                        storage | wgpu::BufferUsages::VERTEX,
                    ),
                    init(
                        "satf/geometry/indices",
                        bytemuck::cast_slice(&tile_indices(mesh_nt, mesh_nu)),
                        wgpu::BufferUsages::INDEX,
                    ),
                    empty(
                        "satf/geometry/sector-params",
                        (sector_count * size_of::<SectorParams>()) as u64,
                        readable,
                    ),
                    empty(
                        "satf/geometry/hsvs",
                        (hsv_count * size_of::<HsvRecord>()) as u64,
                        readable,
                    ),
                    empty(
                        "satf/geometry/counters",
                        size_of::<SatfCounters>() as u64,
                        storage | wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST,
                    ),
                    Atlas::new(ctx, atlas),
                )
            })?;
        Ok(SatfGeometry {
            layout,
            sectors,
            vertices,
            indices,
            sector_params,
            hsvs,
            counters,
            atlas,
            cluster_bounds,
            bounds,
            stats: volume.stats(&sampling),
            features_ms,
        })
    }

    /// Counts of the hierarchy (Table 1's `C#`, `L#`, `S#`, `H#`).
    pub fn stats(&self) -> VolumeStats {
        self.stats
    }

    /// CPU milliseconds of the sector features at upload (the view-independent part of the
    /// index calculation).
    pub fn features_ms(&self) -> f64 {
        self.features_ms
    }

    /// The map atlas size in texels.
    pub fn atlas_size(&self) -> [u32; 2] {
        self.layout.atlas
    }

    /// Bytes of GPU buffers (sectors, vertices, indices, parameters, HSVs, counters).
    pub fn buffer_bytes(&self) -> u64 {
        [
            &self.sectors,
            &self.vertices,
            &self.indices,
            &self.sector_params,
            &self.hsvs,
            &self.counters,
        ]
        .iter()
        .map(|b| b.size())
        .sum()
    }

    /// Bytes of the map atlas textures (re/α maps, s-maps, visibility, l-maps).
    pub fn atlas_bytes(&self) -> u64 {
        self.atlas
            .textures
            .iter()
            .map(crate::gpu::texture_bytes)
            .sum()
    }
}

impl Atlas {
    fn new(ctx: &GpuContext, size: [u32; 2]) -> Atlas {
        let make = |name: &str| {
            ctx.device.create_texture(&wgpu::TextureDescriptor {
                label: Some(&format!("satf/atlas/{name}")),
                size: wgpu::Extent3d {
                    width: size[0],
                    height: size[1],
                    depth_or_array_layers: 1,
                },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format: wgpu::TextureFormat::Rgba16Float,
                usage: wgpu::TextureUsages::STORAGE_BINDING
                    | wgpu::TextureUsages::TEXTURE_BINDING
                    | wgpu::TextureUsages::COPY_SRC,
                view_formats: &[],
            })
        };
        let textures = [
            make("maps"),
            make("s-map"),
            make("visibility"),
            make("l-map"),
        ];
        let view = |i: usize| textures[i].create_view(&Default::default());
        Atlas {
            maps: view(0),
            s_map: view(1),
            vis: view(2),
            l_map: view(3),
            textures,
        }
    }
}

/// The online phase's intermediate results of the last frame, read back (inspection and tests).
/// Atlas texel `(x, y)` of a tile is [`SatfGeometry::atlas_texel`].
#[derive(Clone, Debug, PartialEq)]
pub struct SatfReadback {
    /// `Params(b)` and the nearest sample of every boundary sector (cluster-major, then
    /// `tress_satf::ShellSampling::sector_index`).
    pub sector_params: Vec<SectorParams>,
    /// The records of every HSV (cluster-major, then `(i · layers + layer) · s_u + m`).
    pub hsvs: Vec<HsvRecord>,
    /// `(re, α, 0, 0)` per texel.
    pub maps: LinearImage,
    /// `(τ, 0, 0, 0)` per texel (equation 12).
    pub s_map: LinearImage,
    /// Visibility of lights 0..3 through other clusters per texel.
    pub visibility: LinearImage,
    /// `(Y_lighting, 1)` per texel (equations 8–11).
    pub l_map: LinearImage,
}

impl SatfGeometry {
    /// Size of one (cluster, layer) tile of the maps: `s_u · pixels` by `s_t · map_rows`.
    pub fn tile_size(&self) -> [u32; 2] {
        [self.layout.tile_width, self.layout.tile_height]
    }

    /// The atlas texel of texel `(x, y)` of the tile of `layer` (0 innermost) of `cluster`.
    pub fn atlas_texel(&self, cluster: u32, layer: u32, x: u32, y: u32) -> [u32; 2] {
        let l = &self.layout;
        let tile = cluster * l.layers + layer;
        [
            (tile % l.tiles_per_row) * l.tile_width + x,
            (tile / l.tiles_per_row) * l.tile_height + y,
        ]
    }

    /// Read back what the last frame computed (waits for the GPU).
    pub fn read_back(&self, ctx: &GpuContext) -> Result<SatfReadback, RenderError> {
        let buffers = [&self.sector_params, &self.hsvs];
        let staging: Vec<wgpu::Buffer> = ctx.scoped("reading back SATF buffers", || {
            let mut encoder = ctx
                .device
                .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                    label: Some("satf/readback/encoder"),
                });
            let staging = buffers
                .iter()
                .map(|b| {
                    let s = ctx.device.create_buffer(&wgpu::BufferDescriptor {
                        label: Some("satf/readback/staging"),
                        size: b.size(),
                        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                        mapped_at_creation: false,
                    });
                    encoder.copy_buffer_to_buffer(b, 0, &s, 0, None);
                    s
                })
                .collect();
            ctx.queue.submit([encoder.finish()]);
            staging
        })?;
        let sector_params: Vec<SectorParams> =
            bytemuck::pod_collect_to_vec(&read_buffer(ctx, &staging[0], 0..staging[0].size())?);
        let hsvs: Vec<HsvRecord> =
            bytemuck::pod_collect_to_vec(&read_buffer(ctx, &staging[1], 0..staging[1].size())?);
        let t = &self.atlas.textures;
        Ok(SatfReadback {
            sector_params,
            hsvs,
            maps: read_texture(ctx, &t[0])?,
            s_map: read_texture(ctx, &t[1])?,
            visibility: read_texture(ctx, &t[2])?,
            l_map: read_texture(ctx, &t[3])?,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tile_triangles_face_outward() {
        // A cylinder of radius 1 along +y: u around, t along; vertex (x, y) at angle 2πx/nu,
        // height y. Every triangle's normal must point away from the axis.
        let (nt, nu) = (3, 8);
        let pos = |i: u32| {
            let (x, y) = (i % (nu + 1), i / (nu + 1));
            let a = TAU * x as f32 / nu as f32;
            // u runs counter-clockwise seen from the tip (+y): (cos, -sin) keeps s × t outward.
            Vec3::new(a.cos(), y as f32, -a.sin())
        };
        let idx = tile_indices(nt, nu);
        assert_eq!(idx.len(), (nt * nu * 6) as usize);
        for tri in idx.chunks(3) {
            let (a, b, c) = (pos(tri[0]), pos(tri[1]), pos(tri[2]));
            let n = (b - a).cross(c - a);
            let centre = (a + b + c) / 3.0;
            let out = Vec3::new(centre.x, 0.0, centre.z);
            assert!(n.dot(out) > 0.0, "triangle {tri:?} faces inward");
        }
    }

    #[test]
    fn bounding_sphere_contains_points() {
        let pts = [
            Vec3::ZERO,
            Vec3::new(2.0, 0.0, 0.0),
            Vec3::new(1.0, 1.0, 0.0),
        ];
        let (c, r) = sphere_of(pts.iter().copied());
        assert!(pts.iter().all(|p| p.distance(c) <= r + 1e-6));
        assert_eq!(sphere_of(std::iter::empty()), (Vec3::ZERO, 0.0));
    }
}
