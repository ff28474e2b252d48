//! Every GPU-visible struct, mirrored from WGSL: `#[repr(C)]` bytemuck `Pod` types with explicit
//! padding, uniforms included (encase 0.13 has no glam support). The test
//! `tests/layout.rs` parses the WGSL with naga and checks each struct's size and member offsets
//! against these (design rule 3). Field names are the WGSL names.

use bytemuck::{Pod, Zeroable};

mod sim;
pub use sim::*;

/// A column-major 4x4 matrix as WGSL `mat4x4<f32>`.
pub type Mat4Gpu = [[f32; 4]; 4];

/// `struct Camera` in `shaders/common/camera.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct CameraUniform {
    /// Clip from world.
    pub clip_from_world: Mat4Gpu,
    /// Eye position.
    pub eye: [f32; 3],
    /// Pixels covered by one world unit at clip w = 1.
    pub pixels_per_unit: f32,
    /// Viewport size in pixels.
    pub viewport: [f32; 2],
    /// 1 for orthographic.
    pub orthographic: u32,
    /// Padding.
    pub _pad0: u32,
    /// Unit view direction.
    pub forward: [f32; 3],
    /// Padding.
    pub _pad1: f32,
}

/// `struct DirectionalLight` in `shaders/common/lights.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct LightUniform {
    /// Orthographic shadow projection.
    pub light_from_world: Mat4Gpu,
    /// Unit vector towards the light.
    pub to_light: [f32; 3],
    /// Intensity multiplier.
    pub intensity: f32,
    /// Linear RGB color.
    pub color: [f32; 3],
    /// World length of the shadow depth range.
    pub depth_range: f32,
}

/// `struct Lights` in `shaders/common/lights.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct LightsUniform {
    /// Ambient light.
    pub ambient: [f32; 3],
    /// Number of valid entries in `lights`.
    pub count: u32,
    /// The lights.
    pub lights: [LightUniform; crate::MAX_LIGHTS],
}

/// `struct StrandVertex` in `shaders/common/strand.wgsl` (storage array element).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct StrandVertex {
    /// World position.
    pub position: [f32; 3],
    /// Diameter in world units (0: none).
    pub thickness: f32,
    /// Linear RGB.
    pub color: [f32; 3],
    /// 1 - transparency.
    pub alpha: f32,
}

/// `struct StrandParams` in `shaders/common/strand.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct StrandParams {
    /// Quad width in pixels.
    pub width_px: f32,
    /// Strand alpha multiplier.
    pub alpha: f32,
    /// Sorted fragments per pixel in the resolve.
    pub k: u32,
    /// 0 Kajiya-Kay, 1 Scheuermann.
    pub shading: u32,
    /// 1: multiply alpha by the §3.2 coverage.
    pub coverage: u32,
    /// Thickness fade: 0 off, 1 tip (relative to `thickness_ref`), 2 projected (`tip_fade`).
    pub thickness_fade: u32,
    /// 1: vertex colors replace the material's base color.
    pub vertex_color: u32,
    /// PPLL node capacity.
    pub node_capacity: u32,
    /// ADSM `r` in strands per normalized light depth (per light it is scaled by its range).
    pub shadow_r: f32,
    /// ADSM `alpha`.
    pub shadow_alpha: f32,
    /// PCF kernel radius in texels.
    pub pcf_radius: i32,
    /// Depth bias in world units.
    pub shadow_bias: f32,
    /// Shadow map edge in texels.
    pub shadow_map_size: f32,
    /// Strand width in the shadow map, in texels.
    pub shadow_width_px: f32,
    /// Width of the color target (PPLL head index = y * width + x).
    pub target_width: u32,
    /// 1: shadows on.
    pub shadows: u32,
    /// Centre of the hair's bounds (Scheuermann normals point away from it).
    pub hair_center: [f32; 3],
    /// Number of lights.
    pub light_count: u32,
    /// Thickness that fades nothing in the tip mode (the asset's thickest vertex).
    pub thickness_ref: f32,
    /// PPLL nodes per storage buffer of the pool (chunk `i / nodes_per_chunk` holds node `i`).
    pub nodes_per_chunk: u32,
    /// ShortCut's k: nearest fragments per pixel blended in order.
    pub shortcut_k: u32,
    /// Height of the color target.
    pub target_height: u32,
    /// The blend factor of a hybrid head of hair drawn dithered (`lod_dither`).
    pub lod_factor: f32,
    /// 1: a hybrid head of hair in a frame of several, its strands and volume sharing the
    /// pixels by the 4 × 4 dither (`tress_shading::dither_threshold`); 0 otherwise.
    pub lod_dither: u32,
    /// Padding to 16 bytes.
    pub _pad0: u32,
    /// Padding to 16 bytes.
    pub _pad1: u32,
}

/// `struct HairLighting` in `shaders/common/shading.wgsl` (twin of `tress_shading::HairLighting`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct HairLightingGpu {
    /// Diffuse multiplier.
    pub diffuse_color: [f32; 3],
    /// Primary highlight exponent.
    pub primary_exponent: f32,
    /// Primary highlight color.
    pub primary_color: [f32; 3],
    /// Primary tangent shift.
    pub primary_shift: f32,
    /// Secondary highlight color.
    pub secondary_color: [f32; 3],
    /// Secondary highlight exponent.
    pub secondary_exponent: f32,
    /// Secondary tangent shift.
    pub secondary_shift: f32,
    /// Padding to the struct's 16-byte alignment.
    pub _pad: [f32; 3],
}

/// `Marschner` and `DualScattering` of `shaders/common/marschner.wgsl` (the material's
/// `fiber` and `dual`): the physically based fibre of `strands.shading = "marschner"`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FiberUniform {
    /// `struct Marschner`: `(σa, η)` and `(β_R, β_TT, β_TRT, α)`.
    pub marschner: [[f32; 4]; 2],
    /// `struct DualScattering`.
    pub dual: DualScatteringGpu,
}

/// The [`FiberUniform`] of the last fibre asked for: the dual-scattering table is integrated on
/// the CPU once per fibre (some 20 ms), not every frame. Every renderer that shades with
/// Marschner keeps one.
#[derive(Clone, Copy, Debug, Default)]
pub struct FiberCache(Option<(tress_shading::fiber::HairFiber, FiberUniform)>);

impl FiberCache {
    /// `fiber`'s uniform, computed again only when the fibre changed.
    pub fn get(&mut self, fiber: &tress_shading::fiber::HairFiber) -> FiberUniform {
        match self.0 {
            Some((f, u)) if f == *fiber => u,
            _ => {
                let u = FiberUniform::new(fiber);
                self.0 = Some((*fiber, u));
                u
            }
        }
    }
}

/// `struct DualScattering` in `shaders/common/marschner.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct DualScatteringGpu {
    /// The four 16-row tables `a_f`, `a_b`, `Δb`, `σb²`.
    pub a_f: [[f32; 4]; 16],
    /// `A_b`.
    pub a_b: [[f32; 4]; 16],
    /// `Δb`.
    pub delta_b: [[f32; 4]; 16],
    /// `σb²`.
    pub sigma_b2: [[f32; 4]; 16],
    /// `(⟨N_R A_R⟩, d_f, d_b, 0)`.
    pub params: [f32; 4],
    /// `⟨N_TT A_TT⟩`.
    pub tt_avg: [f32; 4],
    /// `⟨N_TRT A_TRT⟩`.
    pub trt_avg: [f32; 4],
}

impl Default for DualScatteringGpu {
    fn default() -> Self {
        Zeroable::zeroed()
    }
}

impl FiberUniform {
    /// The lobes and dual-scattering table of `fiber` (the table takes some 20 ms to integrate:
    /// compute it once per material).
    pub fn new(fiber: &tress_shading::fiber::HairFiber) -> FiberUniform {
        let m = tress_shading::marschner::Marschner::from_fiber(fiber);
        let ds = tress_shading::dual_scattering::DualScattering::from_marschner(&m);
        let rows = |t: &[glam::Vec4; 16]| t.map(|v| v.to_array());
        FiberUniform {
            marschner: [
                m.sigma_a.extend(m.eta).to_array(),
                m.beta.extend(m.alpha).to_array(),
            ],
            dual: DualScatteringGpu {
                a_f: rows(&ds.a_f),
                a_b: rows(&ds.a_b),
                delta_b: rows(&ds.delta_b),
                sigma_b2: rows(&ds.sigma_b2),
                params: ds.params.to_array(),
                tt_avg: ds.tt_avg.to_array(),
                trt_avg: ds.trt_avg.to_array(),
            },
        }
    }
}

/// `struct Material` in `shaders/common/material.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct MaterialUniform {
    /// Scheuermann constants (Kajiya-Kay uses the primary color and exponent).
    pub lighting: HairLightingGpu,
    /// Hair base color.
    pub base_color: [f32; 3],
    /// Padding.
    pub _pad0: f32,
    /// Head mesh color.
    pub head_color: [f32; 3],
    /// Padding.
    pub _pad1: f32,
    /// The physically based fibre's lobes, `struct Marschner` (zero unless the strands shade
    /// with it).
    pub fiber: [[f32; 4]; 2],
    /// Its dual-scattering table.
    pub dual: DualScatteringGpu,
}

/// `struct PpllNode` in `shaders/common/ppll.wgsl`: one stored fragment.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct PpllNode {
    /// Straight linear RGB, RGB9E5-packed.
    pub color: u32,
    /// Opacity times coverage.
    pub alpha: f32,
    /// Fragment depth (0 near, 1 far).
    pub depth: f32,
    /// Index + 1 of the next node of the pixel's list; 0 ends it.
    pub next: u32,
}

/// `struct PpllCounters` in `strands/ppll_build.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Pod, Zeroable)]
pub struct PpllCounters {
    /// Nodes requested this frame (may exceed the capacity; those beyond were dropped).
    pub requested: u32,
    /// Fragments dropped because the pool was full.
    pub dropped: u32,
    /// Fragments the resolve merged unsorted behind their pixel's `k` nearest (the tail).
    pub tail: u32,
    /// Padding.
    pub _pad1: u32,
}

/// A vertex of the head mesh (vertex buffer, locations 0 and 1 of `head/head_pass.wgsl`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct HeadVertex {
    /// World position.
    pub position: [f32; 3],
    /// Unit normal.
    pub normal: [f32; 3],
}

/// `struct PatchVertex` in `patches/geometry.wgsl`: one vertex of a polygon-patch mesh (vertex
/// buffer, locations 0 to 5).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct PatchVertex {
    /// World position.
    pub position: [f32; 3],
    /// Baked ambient occlusion in `[0, 1]` (1: unoccluded).
    pub ao: f32,
    /// Unit normal.
    pub normal: [f32; 3],
    /// Texture coordinate across the patch.
    pub u: f32,
    /// Unit tangent, root to tip.
    pub tangent: [f32; 3],
    /// Texture coordinate from root (0) to tip (1).
    pub v: f32,
}

/// `struct PatchParams` in `patches/geometry.wgsl`: the patch technique's shader constants.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct PatchParamsGpu {
    /// The slide's `HairLighting` constants.
    pub lighting: HairLightingGpu,
    /// Alpha test reference: alpha at or above it is opaque.
    pub alpha_ref: f32,
    /// 1: multiply by the baked ambient occlusion; 0: ignore it.
    pub use_ao: u32,
    /// The `min_alpha` option: the depth-writing transparent pass drops alpha below it.
    pub min_alpha: f32,
    /// `patches.shading`: 0 Scheuermann's `HairLighting`, 1 Marschner.
    pub shading: u32,
    /// The physically based fibre's lobes, `struct Marschner` (zero unless the patches shade
    /// with it).
    pub fiber: [[f32; 4]; 2],
    /// Its dual-scattering table.
    pub dual: DualScatteringGpu,
}

/// Convert a glam matrix for upload.
pub fn mat4(m: glam::Mat4) -> Mat4Gpu {
    m.to_cols_array_2d()
}

/// `struct VolumeGrid` in `shaders/common/volume.wgsl`: the voxel grid fitted to the hair on the
/// GPU every frame (twin of `tress_shading::VoxelGrid`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct VolumeGrid {
    /// World position of the corner of voxel `(0, 0, 0)`.
    pub origin: [f32; 3],
    /// Voxels per world unit.
    pub scale: f32,
    /// The hair's bounding box, minimum corner.
    pub bounds_min: [f32; 3],
    /// World length of a voxel edge.
    pub voxel_size: f32,
    /// The hair's bounding box, maximum corner.
    pub bounds_max: [f32; 3],
    /// Voxels per axis.
    pub res: u32,
    /// First voxel the resolve writes from the counters.
    pub box_min: [u32; 3],
    /// 1 when the hair has vertices.
    pub occupied: u32,
    /// One past the last voxel the resolve writes from the counters.
    pub box_max: [u32; 3],
    /// Strands per level of the texels' 8-bit density: 1 in the segments mode, the
    /// reconstruction filter's weight over its box in the vertices mode.
    pub density_unit: f32,
}

/// `struct ResolveArgs` in `shaders/common/volume.wgsl`: the resolve's indirect dispatch.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Pod, Zeroable)]
pub struct ResolveArgs {
    /// Workgroups (4³ voxels each) per axis.
    pub groups: [u32; 3],
    /// Padding.
    pub _pad0: u32,
    /// First voxel resolved.
    pub origin: [u32; 3],
    /// Padding.
    pub _pad1: u32,
    /// One past the last voxel resolved.
    pub end: [u32; 3],
    /// Padding.
    pub _pad2: u32,
}

/// `struct VolumeParams` in `shaders/common/volume.wgsl`: per-frame settings of the volume passes.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct VolumeParams {
    /// World from clip of the frame's camera.
    pub world_from_clip: Mat4Gpu,
    /// Raymarching steps across the box diagonal.
    pub steps: u32,
    /// Strands to a solid isosurface.
    pub iso: f32,
    /// 1: skip empty occupancy blocks.
    pub skip_empty: u32,
    /// Shading model (0 Kajiya-Kay, 1 Scheuermann).
    pub shading: u32,
    /// Shadows of the rasterizer and the head: 0 ADSM, 1 volume.
    pub raster_shadow_mode: u32,
    /// Opacity of one occluding strand (volume shadows and AO).
    pub shadow_alpha: f32,
    /// Shadow march step in voxels.
    pub shadow_step: f32,
    /// Shadow march start in voxels.
    pub shadow_offset: f32,
    /// 1: the rasterizer multiplies its color by the volume AO.
    pub raster_ao: u32,
    /// AO ball radius in world units.
    pub ao_radius: f32,
    /// AO samples.
    pub ao_samples: u32,
    /// AO intensity.
    pub ao_intensity: f32,
    /// 0 vertices, 1 segments.
    pub voxelize: u32,
    /// Reconstruction filter radius (vertices mode).
    pub reconstruction_radius: u32,
    /// Per-voxel counter capacity.
    pub capacity: u32,
    /// Mean segment length in world units.
    pub mean_segment_length: f32,
    /// Segments of the hair.
    pub segment_count: u32,
    /// Vertices of the hair.
    pub vertex_count: u32,
    /// Occupancy blocks per axis.
    pub occupancy_res: u32,
    /// Voxels per axis.
    pub resolution: u32,
    /// 1: volume shadows in the raymarcher.
    pub march_shadows: u32,
    /// 1: AO in the raymarcher.
    pub march_ao: u32,
    /// Effective strand width in world units (occlusion per strand crossing a voxel).
    pub strand_width: f32,
    /// How shadows and AO count strands in the way: 0 strands × strand width, 1 ADSM's `r` ×
    /// the path's length inside the hair.
    pub occlusion: u32,
    /// ADSM's `r` (strands per world unit of depth) for `occlusion` 1.
    pub occlusion_r: f32,
    /// Thickness that fades nothing (the strands' tip fade; 0: no fade).
    pub fade_ref: f32,
    /// ADSM's model: width in world units of a shadow-map line.
    pub occlusion_width: f32,
    /// ADSM's model: the depth bias in world units.
    pub occlusion_bias: f32,
    /// Raymarch: points shaded per pixel.
    pub shade_samples: u32,
    /// Raymarch: optical width in pixels of a strand's line (`volume.opacity = "strands"`), 0
    /// for the paper's `iso` count.
    pub optical_width: f32,
    /// 1: the voxelizer integrates the strands' Kajiya-Kay highlights per voxel and the
    /// raymarcher shades with them (`volume.highlights = "strands"`).
    pub highlights: u32,
    /// Kajiya-Kay's specular exponent of the integrated highlights.
    pub highlight_exponent: f32,
    /// Voxels a texel of the ambient-occlusion texture baked after each voxelization
    /// (`volume.ao_texel`); 0: local AO is evaluated at every shaded point.
    pub ao_texel: u32,
    /// Padding.
    pub _pad_ao: [u32; 3],
    /// The frame's eye (perspective), for the highlights.
    pub view_eye: [f32; 3],
    /// 1: orthographic (the view direction is `view_forward` everywhere).
    pub view_orthographic: u32,
    /// The frame's unit view direction.
    pub view_forward: [f32; 3],
    /// Lights whose highlights are integrated (at most 4).
    pub light_count: u32,
    /// Unit directions towards the lights (xyz).
    pub light_dirs: [[f32; 4]; 4],
}

/// `struct VoxelStats` in `volume/voxelize.wgsl`: the voxel counters' occupancy.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Pod, Zeroable)]
pub struct VoxelStats {
    /// Samples deposited (accepted and dropped).
    pub deposits: u32,
    /// Samples dropped at a full counter.
    pub dropped: u32,
    /// Voxels whose filter box summed more than a texel's 255 counts (vertices mode).
    pub saturated: u32,
    /// Padding.
    pub _pad0: u32,
}

/// `struct BoundsKeys` in `volume/volume_bounds.wgsl`: the hair's box as order-preserving integer
/// keys of its float coordinates.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Pod, Zeroable)]
pub struct BoundsKeys {
    /// Keys of the minimum corner.
    pub lo: [u32; 3],
    /// Keys of the maximum corner.
    pub hi: [u32; 3],
}

/// `struct LodParams` in `lod_blend.wgsl`: the level-of-detail blend of one frame.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct LodParams {
    /// Blend factor: 0 strands, 1 volume.
    pub factor: f32,
    /// 0 alpha blend, 1 dither.
    pub transition: u32,
    /// Padding.
    pub _pad0: u32,
    /// Padding.
    pub _pad1: u32,
}

/// `struct SatfParams` in `satf/types.wgsl`: the SATF online phase's per-frame constants.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct SatfParams {
    /// `f_dif` (equation 9).
    pub f_dif: [f32; 3],
    /// `k_dif`.
    pub k_dif: f32,
    /// `f_speI` (equation 10).
    pub f_spe1: [f32; 3],
    /// `k_speI`.
    pub k_spe1: f32,
    /// `f_speII` (equation 11).
    pub f_spe2: [f32; 3],
    /// `k_speII`.
    pub k_spe2: f32,
    /// `s` of equation 10.
    pub primary_shift: f32,
    /// `s` of equation 11.
    pub secondary_shift: f32,
    /// `k_h`.
    pub k_h: f32,
    /// `k_shadow` (equation 12).
    pub k_shadow: f32,
    /// Feature weights of the lookup and equation 6.
    pub feature_weights: [f32; 3],
    /// `k_threshold` (equation 6).
    pub k_threshold: f32,
    /// Weight of an angle difference per radian (equation 6).
    pub angle_weight: f32,
    /// 0 exponential, 1 linear equation 12.
    pub shadow_approx: u32,
    /// 1: straight reflectance in the re-maps.
    pub straight: u32,
    /// Database samples.
    pub sample_count: u32,
    /// Database view bins.
    pub view_angles: u32,
    /// Database light bins.
    pub light_angles: u32,
    /// Pixels per HRIR.
    pub pixels: u32,
    /// Map rows per HSV.
    pub map_rows: u32,
    /// `s_t`.
    pub st: u32,
    /// `s_u`.
    pub su: u32,
    /// Shell layers per cluster.
    pub layers: u32,
    /// Clusters.
    pub cluster_count: u32,
    /// Boundary sectors over all clusters.
    pub sector_count: u32,
    /// HSVs over all clusters.
    pub hsv_count: u32,
    /// Tile width in texels (`s_u · pixels`).
    pub tile_width: u32,
    /// Tile height in texels (`s_t · map_rows`).
    pub tile_height: u32,
    /// Tiles per atlas row.
    pub tiles_per_row: u32,
    /// Layer mesh quads along `t` per tile.
    pub mesh_nt: u32,
    /// Layer mesh quads around `u` per tile.
    pub mesh_nu: u32,
    /// Lights this frame.
    pub light_count: u32,
    /// The light whose azimuth indexes the database.
    pub key_light: u32,
    /// 1: shadow maps between clusters.
    pub cluster_shadows: u32,
    /// PCF radius in texels.
    pub pcf_radius: i32,
    /// Shadow map edge in texels.
    pub shadow_map_size: f32,
    /// Shadow bias in world units.
    pub shadow_bias: f32,
    /// Light a shadowing cluster blocks.
    pub shadow_opacity: f32,
    /// 1: equation 12 s-maps.
    pub local_shadows: u32,
    /// Tiles (clusters · layers).
    pub tile_count: u32,
    /// Head color.
    pub head_color: [f32; 3],
    /// Padding.
    pub _pad0: u32,
}

/// `struct SatfSector` in `satf/types.wgsl`: a boundary generalized sector's anchor, frame and
/// features (storage array element).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct SatfSector {
    /// Anchor (middle of the outer arc).
    pub position: [f32; 3],
    /// Cluster index.
    pub cluster: u32,
    /// Unit outward normal at the anchor.
    pub normal: [f32; 3],
    /// Padding.
    pub _pad0: u32,
    /// Unit `s` axis (increasing `u`).
    pub s_axis: [f32; 3],
    /// Padding.
    pub _pad1: u32,
    /// `ρ_feature`.
    pub features: [f32; 3],
    /// Padding.
    pub _pad2: u32,
}

/// `struct SectorParams` in `satf/types.wgsl`: `Params(b)` of a sector this frame.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct SectorParams {
    /// `ρ_feature`.
    pub features: [f32; 3],
    /// Nearest database sample.
    pub sample: u32,
    /// View azimuth.
    pub theta_v: f32,
    /// Light azimuth.
    pub theta_l: f32,
    /// Padding.
    pub _pad0: u32,
    /// Padding.
    pub _pad1: u32,
}

/// `struct HsvRecord` in `satf/types.wgsl`: an HSV's two records this frame.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Pod, Zeroable)]
pub struct HsvRecord {
    /// Record 1 (`b⊤`) sample.
    pub sample1: u32,
    /// Record 1 view bin.
    pub view1: u32,
    /// Record 1 light bin.
    pub light1: u32,
    /// Record 2 (`b⊥`) sample.
    pub sample2: u32,
    /// Record 2 view bin.
    pub view2: u32,
    /// Record 2 light bin.
    pub light2: u32,
    /// 1 when equation 6 held (both records are the averaged one).
    pub uniform: u32,
    /// Padding.
    pub _pad: u32,
}

/// `struct SatfVertex` in `satf/types.wgsl`: a layer mesh vertex (vertex buffer, locations 0 to
/// 5, and storage array element).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct SatfVertex {
    /// World position on the layer's outer surface.
    pub position: [f32; 3],
    /// Texture coordinate around the cluster, `[0, 1]`.
    pub u: f32,
    /// Unit hair tangent.
    pub tangent: [f32; 3],
    /// Texture coordinate along the cluster, `[0, 1]`.
    pub t: f32,
    /// Unit outward normal.
    pub normal: [f32; 3],
    /// Tile: `cluster · layers + layer`.
    pub tile: u32,
}

/// `struct SatfCounters` in `satf/types.wgsl`: counters of the index calculation.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Pod, Zeroable)]
pub struct SatfCounters {
    /// HSVs that passed equation 6.
    pub uniform_hsvs: u32,
    /// HSVs interpolated by equation 7.
    pub interpolated_hsvs: u32,
    /// Padding.
    pub _pad0: u32,
    /// Padding.
    pub _pad1: u32,
}
