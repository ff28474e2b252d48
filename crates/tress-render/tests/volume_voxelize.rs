//! The GPU voxelizer against its CPU reference (`tress_shading::voxelize`, Jansson 2019 §3.3):
//! the AABB and grid, the exact per-voxel strand counts in both modes, the mean tangents within
//! the quantization error, the integrated highlights within one level, the resolve into the 3D
//! textures and the occupancy blocks, and the capacity check with its drop counter (design rule
//! 8).

mod common;

use glam::{UVec3, Vec3};
use tress_hair::HairAsset;
use tress_render::volume::{VolumeReadback, VolumeSettings, Voxelizer};
use tress_render::{RenderError, StrandGeometry, VoxelizeMode};
use tress_shading::highlights::HighlightView;
use tress_shading::voxelize::{self, SUBVOXEL_BITS, VoxelCounts, VoxelGrid};

const RES: u32 = 40;

fn settings(mode: VoxelizeMode) -> VolumeSettings {
    VolumeSettings {
        resolution: RES,
        voxelize: mode,
        ..Default::default()
    }
}

/// Strands with long segments (several voxels) so the two modes differ, plus a one-vertex strand
/// (no segment) and a zero-length segment.
fn asset() -> HairAsset {
    let base = common::sphere_hair(1.0, 300, 9);
    let mut positions = base.positions().to_vec();
    let mut counts: Vec<u32> = base.vertex_counts().collect();
    positions.push(Vec3::new(0.0, 1.5, 0.0));
    counts.push(1);
    positions.extend([Vec3::new(0.2, 1.2, 0.1); 2]);
    counts.push(2);
    HairAsset::from_counts(positions, &counts).expect("valid asset")
}

fn cpu_grid(g: &tress_render::gpu::types::VolumeGrid) -> VoxelGrid {
    VoxelGrid {
        origin: Vec3::from_array(g.origin),
        scale: g.scale,
        voxel_size: g.voxel_size,
        bounds_min: Vec3::from_array(g.bounds_min),
        bounds_max: Vec3::from_array(g.bounds_max),
        res: g.res,
    }
}

fn run(
    asset: &HairAsset,
    s: &VolumeSettings,
) -> (VolumeReadback, VoxelCounts, tress_render::VolumeStats) {
    run_faded(asset, s, None)
}

/// `run` with the tip fade of `fade_ref` (the asset's thickness) on both sides.
fn run_faded(
    asset: &HairAsset,
    s: &VolumeSettings,
    fade_ref: Option<f32>,
) -> (VolumeReadback, VoxelCounts, tress_render::VolumeStats) {
    let ctx = common::gpu().expect("checked by the caller");
    let geometry = StrandGeometry::new(&ctx, asset).expect("upload");
    let mut voxelizer = Voxelizer::new(&ctx, s.resolution).expect("voxelizer");
    let stats = voxelizer
        .voxelize_faded(&ctx, &geometry, s, fade_ref.unwrap_or(0.0))
        .expect("voxelize");
    let gpu = voxelizer.read_back(&ctx).expect("readback");
    // The GPU's box is the exact box of the vertices; its grid is the CPU fit of that box up to
    // the rounding of one division.
    let b = asset.bounds();
    assert_eq!(gpu.grid.bounds_min, b.min.to_array());
    assert_eq!(gpu.grid.bounds_max, b.max.to_array());
    assert_eq!((gpu.grid.res, gpu.grid.occupied), (s.resolution, 1));
    let fit = VoxelGrid::fit(b.min, b.max, s.resolution);
    let g = cpu_grid(&gpu.grid);
    assert!(
        (g.scale - fit.scale).abs() <= fit.scale * 1e-6,
        "{} {}",
        g.scale,
        fit.scale
    );
    assert!(
        (g.origin - fit.origin).abs().max_element() <= 1e-5 * fit.voxel_size * s.resolution as f32
    );
    // The CPU reference on the GPU's grid.
    let segments = voxelize::strand_segments(asset.strand_offsets());
    let cpu = voxelize::voxelize(
        asset.positions(),
        &segments,
        &g,
        s.voxelize,
        s.max_strands_per_voxel,
        fade_ref.map(|r| (asset.thickness().expect("thickness"), r)),
    );
    (gpu, cpu, stats)
}

fn check_exact(mode: VoxelizeMode) {
    let asset = asset();
    let s = settings(mode);
    let (gpu, cpu, stats) = run(&asset, &s);
    assert_eq!(gpu.counts, cpu.counts, "{mode:?}: per-voxel counts");
    assert_eq!(u64::from(stats.deposits), cpu.deposits);
    assert_eq!((stats.dropped, cpu.dropped), (0, 0));
    assert!(cpu.deposits > 1000, "{}", cpu.deposits);
    // Tangent sums: equal up to the quantization of the rare tangent whose GPU normalize rounds
    // differently (at most one level per sample).
    let mut worst = 0.0f32;
    for (i, (g, c)) in gpu.tangent_sums.iter().zip(&cpu.tangent_sums).enumerate() {
        let n = cpu.counts[i].max(1) as f32;
        for k in 0..3 {
            let d = (g[k] as f32 - c[k] as f32).abs() / n;
            worst = worst.max(d);
        }
    }
    assert!(
        worst <= 1.0,
        "{mode:?}: tangent sums differ by {worst} levels per sample"
    );
    // The resolved texels: the bytes the CPU twin encodes (the count exactly, the tangent within
    // the level a rarely differing sum can move it), read back as the density and the mean
    // tangent of the CPU resolve.
    let weight = match mode {
        VoxelizeMode::Segments => 1.0,
        VoxelizeMode::Vertices => {
            let len: f32 = asset
                .strands()
                .flat_map(|s| s.windows(2).map(|w| w[0].distance(w[1])))
                .sum();
            len / asset.segment_count() as f32 * gpu.grid.scale
        }
    };
    let radius = match mode {
        VoxelizeMode::Segments => 0,
        VoxelizeMode::Vertices => s.reconstruction_radius,
    };
    let mut non_empty = 0;
    for z in 0..RES {
        for y in 0..RES {
            for x in 0..RES {
                let v = UVec3::new(x, y, z);
                let i = cpu.grid.index(v);
                let want = voxelize::resolve(&cpu, v, radius, weight, s.max_strands_per_voxel);
                let bytes = gpu.texel_bytes[i];
                let texel = want.texel();
                assert_eq!(bytes[3], texel[3], "count at {v}");
                // An empty voxel's rgb is not read (the resolve writes zeros).
                for k in (0..3).filter(|_| texel[3] > 0) {
                    assert!(
                        bytes[k].abs_diff(texel[k]) <= 1,
                        "{v}: texel {bytes:?}, CPU {texel:?}"
                    );
                }
                let got = gpu.texels[i];
                if mode == VoxelizeMode::Segments {
                    assert_eq!(got[3], cpu.counts[i] as f32, "density at {v}");
                } else {
                    assert!(want.count <= 255, "{v}: the test scene saturates a texel");
                    assert!(
                        (got[3] - want.density).abs() <= want.density * 1e-4 + 1e-6,
                        "{got:?} {want:?}"
                    );
                }
                let t = Vec3::new(got[0], got[1], got[2]);
                // The texel's cube-root store: half a level of u is 3|u|² / 2 levels of t.
                assert!(
                    (t - want.tangent).abs().max_element() <= 2.5 / 127.0,
                    "{v}: {t} {}",
                    want.tangent
                );
                if got[3] > 0.0 {
                    non_empty += 1;
                    // Every non-empty voxel's occupancy block is marked.
                    let b = v / 8;
                    let ob = RES.div_ceil(8);
                    assert_eq!(gpu.occupancy[(b.x + ob * (b.y + ob * b.z)) as usize], 1);
                }
            }
        }
    }
    assert!(non_empty > 100, "{non_empty}");
}

#[test]
fn segments_mode_matches_the_cpu_reference_exactly() {
    if common::gpu().is_none() {
        return;
    }
    check_exact(VoxelizeMode::Segments);
}

#[test]
fn vertices_mode_matches_the_cpu_reference_exactly() {
    if common::gpu().is_none() {
        return;
    }
    check_exact(VoxelizeMode::Vertices);
}

#[test]
fn segments_fill_the_gaps_vertices_leave() {
    if common::gpu().is_none() {
        return;
    }
    // Long segments (about 14 voxels): every voxel a strand passes through is hit in the
    // segments mode; the vertices mode hits one in 14 before its filter.
    let mut positions = Vec::new();
    for i in 0..200 {
        let (x, z) = ((i % 20) as f32 * 0.1, (i / 20) as f32 * 0.1);
        positions.extend([
            Vec3::new(x, 0.0, z),
            Vec3::new(x, -1.0, z),
            Vec3::new(x, -2.0, z + 0.5),
        ]);
    }
    let asset = HairAsset::from_counts(positions, &[3; 200]).expect("asset");
    let (seg, _, _) = run(&asset, &settings(VoxelizeMode::Segments));
    let (ver, _, _) = run(&asset, &settings(VoxelizeMode::Vertices));
    let hit = |r: &VolumeReadback| r.counts.iter().filter(|c| **c > 0).count();
    assert!(hit(&seg) > 3 * hit(&ver), "{} vs {}", hit(&seg), hit(&ver));
}

#[test]
fn full_counters_drop_and_count_what_overflows() {
    if common::gpu().is_none() {
        return;
    }
    // 2000 short strands through almost the same point, capacity 7.
    let mut positions = Vec::new();
    for i in 0..2000 {
        let o = (i % 7) as f32 * 1e-3;
        positions.extend([
            Vec3::new(o, 0.0, 0.0),
            Vec3::new(o, 0.001, 0.0),
            Vec3::new(1.0, 1.0, 1.0),
        ]);
    }
    let asset = HairAsset::from_counts(positions, &[3; 2000]).expect("asset");
    let s = VolumeSettings {
        resolution: 16,
        max_strands_per_voxel: 7,
        voxelize: VoxelizeMode::Vertices,
        ..Default::default()
    };
    let (gpu, cpu, stats) = run(&asset, &s);
    assert_eq!(gpu.counts, cpu.counts);
    assert!(cpu.dropped > 1000, "{}", cpu.dropped);
    assert_eq!(u64::from(stats.dropped), cpu.dropped);
    assert_eq!(u64::from(stats.deposits), cpu.deposits);
    let expected: u64 = cpu
        .counts
        .iter()
        .map(|&c| u64::from(c.saturating_sub(7)))
        .sum();
    assert_eq!(cpu.dropped, expected);
    // The texture holds the clamped count and a mean tangent of unit range.
    let i = cpu
        .grid
        .index(cpu.grid.fixed_point(Vec3::ZERO) >> SUBVOXEL_BITS);
    let t = gpu.texels[i];
    assert!(t[..3].iter().all(|c| c.abs() <= 1.0) && t[3] > 0.0, "{t:?}");
}

#[test]
fn a_filter_box_over_a_texel_is_clamped_and_counted() {
    if common::gpu().is_none() {
        return;
    }
    // Vertices mode: 400 two-vertex strands between two points a voxel apart, so two
    // neighbouring voxels hold 255 counts each (the rest dropped) and every 3³ box holding both
    // sums 510, more than a texel's 255.
    let mut positions = Vec::new();
    for _ in 0..400 {
        positions.extend([Vec3::ZERO, Vec3::new(0.07, 0.0, 0.0)]);
    }
    positions.extend([Vec3::splat(-0.5), Vec3::splat(0.5)]);
    let mut counts = vec![2u32; 400];
    counts.push(2);
    let asset = HairAsset::from_counts(positions, &counts).expect("asset");
    let s = VolumeSettings {
        resolution: 20,
        voxelize: VoxelizeMode::Vertices,
        ..Default::default()
    };
    let (gpu, cpu, stats) = run(&asset, &s);
    assert_eq!(gpu.counts, cpu.counts);
    let r = s.reconstruction_radius;
    let mut want = 0;
    for (i, bytes) in gpu.texel_bytes.iter().enumerate() {
        let res = s.resolution;
        let v = UVec3::new(i as u32 % res, i as u32 / res % res, i as u32 / (res * res));
        let value = voxelize::resolve(&cpu, v, r, 1.0, s.max_strands_per_voxel);
        if value.count > 255 {
            want += 1;
            assert_eq!(bytes[3], 255, "{v}");
        }
    }
    assert!(want > 0, "the test must saturate a box");
    assert_eq!(stats.saturated, want);
}

#[test]
fn a_volume_over_the_binding_limit_is_a_typed_error() {
    let Some(ctx) = common::gpu() else {
        return;
    };
    let limit = ctx.caps.max_storage_binding.min(ctx.caps.max_buffer_size);
    // The largest counter buffer holds the highlight sums, 8 bytes a voxel.
    let res = (1..=1024u32).find(|r| u64::from(*r).pow(3) * 8 > limit);
    if let Some(res) = res {
        let err = Voxelizer::new(&ctx, res).expect_err("over the limit");
        assert!(matches!(err, RenderError::Limit { .. }), "{err}");
    }
    assert!(Voxelizer::new(&ctx, 4).is_err());
}

#[test]
fn empty_hair_gives_an_unoccupied_grid() {
    if common::gpu().is_none() {
        return;
    }
    let ctx = common::gpu().expect("gpu");
    let asset = HairAsset::from_counts(vec![Vec3::ZERO], &[1]).expect("asset");
    let geometry = StrandGeometry::new(&ctx, &asset).expect("upload");
    let mut v = Voxelizer::new(&ctx, 16).expect("voxelizer");
    let stats = v
        .voxelize(
            &ctx,
            &geometry,
            &VolumeSettings {
                resolution: 16,
                ..Default::default()
            },
        )
        .expect("voxelize");
    assert_eq!(stats.deposits, 0);
    let r = v.read_back(&ctx).expect("readback");
    assert!(r.counts.iter().all(|c| *c == 0));
    assert!(r.texels.iter().all(|t| t[3] == 0.0));
}

#[test]
fn moving_hair_leaves_no_stale_voxels() {
    if common::gpu().is_none() {
        return;
    }
    // The resolve only writes the hair's box and the last frame's: after the hair moved (and
    // the grid with it), the texture must be exactly a fresh voxelization's.
    let ctx = common::gpu().expect("gpu");
    let s = settings(VoxelizeMode::Vertices);
    let a = common::sphere_hair(1.0, 300, 9);
    let b = HairAsset::from_counts(
        a.positions()
            .iter()
            .map(|p| Vec3::new(p.x * 0.4, p.y * 1.5, p.z * 0.3) + Vec3::X)
            .collect(),
        &a.vertex_counts().collect::<Vec<_>>(),
    )
    .expect("asset");
    let (ga, gb) = (
        StrandGeometry::new(&ctx, &a).expect("upload"),
        StrandGeometry::new(&ctx, &b).expect("upload"),
    );
    let mut reused = Voxelizer::new(&ctx, RES).expect("voxelizer");
    reused.voxelize(&ctx, &ga, &s).expect("voxelize a");
    let before = reused.read_back(&ctx).expect("readback");
    reused.voxelize(&ctx, &gb, &s).expect("voxelize b");
    let after = reused.read_back(&ctx).expect("readback");
    let mut fresh = Voxelizer::new(&ctx, RES).expect("voxelizer");
    fresh.voxelize(&ctx, &gb, &s).expect("voxelize b");
    let want = fresh.read_back(&ctx).expect("readback");
    assert_eq!(after.texels, want.texels);
    assert_eq!(after.occupancy, want.occupancy);
    // The test is not trivial: the two frames' boxes differ, and a's texels reached outside b's.
    assert_ne!(before.grid.box_min, after.grid.box_min);
    let outside = |v: &VolumeReadback, i: usize| {
        let r = RES as usize;
        let p = [i % r, (i / r) % r, i / (r * r)];
        (0..3).any(|k| p[k] < v.grid.box_min[k] as usize || p[k] >= v.grid.box_max[k] as usize)
    };
    let stale = (0..before.texels.len())
        .filter(|&i| before.texels[i][3] > 0.0 && outside(&after, i))
        .count();
    assert!(stale > 10, "{stale}");
    assert!((0..after.texels.len()).all(|i| !outside(&after, i) || after.texels[i] == [0.0; 4]));
}

#[test]
fn the_renderer_refuses_a_resolution_the_device_cannot_hold() {
    let Some(ctx) = common::gpu() else {
        return;
    };
    let limit = ctx.caps.max_storage_binding.min(ctx.caps.max_buffer_size);
    let Some(res) = (8..=1024u32).find(|r| u64::from(*r).pow(3) * 4 > limit) else {
        return;
    };
    let mut r = tress_render::Renderer::new(
        &ctx,
        tress_render::TargetFormats::default(),
        tress_render::StrandSettings::default(),
    )
    .expect("renderer");
    let err = r
        .set_volume_settings(
            &ctx,
            VolumeSettings {
                resolution: res,
                ..Default::default()
            },
        )
        .expect_err("over the storage-binding limit");
    assert!(matches!(err, RenderError::Limit { .. }), "{err}");
    assert_eq!(
        r.volume_settings().resolution,
        256,
        "the settings are unchanged"
    );
}

/// [`asset`] with every strand tapering from thickness 1 at the root to 0.1 at the tip.
fn tapered() -> HairAsset {
    let base = asset();
    let mut thickness = Vec::with_capacity(base.positions().len());
    for strand in base.strands() {
        let n = strand.len().max(2) - 1;
        thickness.extend((0..strand.len()).map(|i| 1.0 - 0.9 * i as f32 / n as f32));
    }
    base.with_thickness(thickness).expect("thickness")
}

#[test]
fn the_tip_fade_weighs_the_tangents_as_the_cpu_reference_does() {
    if common::gpu().is_none() {
        return;
    }
    let tapered = tapered();
    let s = settings(VoxelizeMode::Segments);
    let (gpu, cpu, _) = run_faded(&tapered, &s, Some(1.0));
    let (_, plain, _) = run(&tapered, &s);
    assert_eq!(gpu.counts, cpu.counts, "the fade leaves the density alone");
    // The fades summed for the highlights' weights: within one level a sample.
    for (i, (g, c)) in gpu.fade_sums.iter().zip(&cpu.fade_sums).enumerate() {
        assert!(
            g.abs_diff(*c) <= cpu.counts[i],
            "voxel {i}: fade sums {g} vs {c}"
        );
    }
    assert!(
        cpu.fade_sums
            .iter()
            .zip(&plain.fade_sums)
            .any(|(f, p)| f < p)
    );
    assert_eq!(cpu.counts, plain.counts);
    let (mut faded_len, mut plain_len, mut n) = (0.0, 0.0, 0);
    for (i, (g, c)) in gpu.tangent_sums.iter().zip(&cpu.tangent_sums).enumerate() {
        let count = cpu.counts[i];
        if count == 0 {
            continue;
        }
        for k in 0..3 {
            let d = (g[k] as f32 - c[k] as f32).abs() / count as f32;
            assert!(
                d <= 1.0,
                "voxel {i}: tangent sums differ by {d} levels per sample"
            );
        }
        let mean = |sum: UVec3| voxelize::dequantize_tangent(sum.as_vec3(), count as f32).length();
        faded_len += mean(UVec3::from_array(*g));
        plain_len += mean(plain.tangent_sums[i]);
        n += 1;
    }
    // The mean fade of a linear taper from 1 to 0.1 is 0.55; voxels near the roots of many
    // strands weigh more, so the mean tangent's length falls to between 0.4 and 0.8 of the
    // unfaded one.
    let ratio = faded_len / plain_len;
    assert!(
        n > 100 && (0.4..0.8).contains(&ratio),
        "{n} voxels, ratio {ratio}"
    );
}

#[test]
fn the_highlights_integrate_the_strands_lobes_as_the_cpu_reference_does() {
    let Some(ctx) = common::gpu() else {
        return;
    };
    // Three lights (the fourth channel stays empty), the eye close enough that the view
    // direction turns across the hair, a narrow lobe so highlights are sparse.
    let view = HighlightView {
        eye: Vec3::new(0.4, 0.8, 4.0),
        forward: Vec3::new(-0.1, -0.2, -1.0).normalize(),
        orthographic: false,
        lights: vec![
            Vec3::new(0.3, 0.9, 0.3).normalize(),
            Vec3::new(-0.8, 0.1, 0.6).normalize(),
            Vec3::Z,
        ],
        exponent: 40.0,
    };
    // Tapered strands under the tip fade: each sample's highlight weighed by its fade.
    let asset = tapered();
    let s = settings(VoxelizeMode::Segments);
    let geometry = StrandGeometry::new(&ctx, &asset).expect("upload");
    let mut voxelizer = Voxelizer::new(&ctx, s.resolution).expect("voxelizer");
    voxelizer
        .voxelize_lit(&ctx, &geometry, &s, 1.0, Some(&view))
        .expect("voxelize");
    let gpu = voxelizer.read_back(&ctx).expect("readback");
    let g = cpu_grid(&gpu.grid);
    let segments = voxelize::strand_segments(asset.strand_offsets());
    let cpu = voxelize::voxelize_lit(
        asset.positions(),
        &segments,
        &g,
        s.voxelize,
        s.max_strands_per_voxel,
        Some((asset.thickness().expect("thickness"), 1.0)),
        Some(&view),
    );
    assert_eq!(gpu.counts, cpu.counts);
    // The sums: equal up to the rare sample whose GPU `pow` rounds to the other level (at most
    // one level per sample); the texels within one level of the CPU resolve's.
    let (mut lit, mut worst) = ([0u32; 4], 0.0f32);
    for (i, (gs, cs)) in gpu
        .highlight_sums
        .iter()
        .zip(&cpu.highlight_sums)
        .enumerate()
    {
        let n = cpu.counts[i].max(1) as f32;
        for k in 0..4 {
            worst = worst.max((gs[k] as f32 - cs[k] as f32).abs() / n);
            lit[k] += u32::from(cs[k] > 0);
        }
        let v = UVec3::new(
            i as u32 % RES,
            (i as u32 / RES) % RES,
            i as u32 / (RES * RES),
        );
        let want = voxelize::resolve(&cpu, v, 0, 1.0, s.max_strands_per_voxel).highlights;
        for k in 0..4 {
            assert!(
                gpu.highlight_texels[i][k].abs_diff(want[k]) <= 1,
                "{v}: highlight texel {:?}, CPU {want:?}",
                gpu.highlight_texels[i]
            );
        }
    }
    assert!(
        worst <= 1.0,
        "highlight sums differ by {worst} levels per sample"
    );
    // Each of the three lights lights some voxels; the absent fourth none.
    assert!(lit[..3].iter().all(|&n| n > 20), "{lit:?}");
    assert_eq!(lit[3], 0);
    // Without a view (or with `volume.highlights = "mean_tangent"`) nothing is integrated.
    let mut plain = s.clone();
    plain.highlights = tress_render::volume::Highlights::MeanTangent;
    voxelizer
        .voxelize_lit(&ctx, &geometry, &plain, 1.0, Some(&view))
        .expect("voxelize");
    let off = voxelizer.read_back(&ctx).expect("readback");
    assert!(off.highlight_sums.iter().all(|h| *h == [0; 4]));
    assert!(off.highlight_texels.iter().all(|h| *h == [0; 4]));
    assert_eq!(off.counts, gpu.counts);
}

/// The baked ambient occlusion (`volume.ao_texel`) against the CPU's `volume_ao` at each texel's
/// centre on the read-back density, and its footprint against the trilinear filter: every texel a
/// point on a strand can read is baked, and the texels no point reaches are skipped (1). At a
/// texel a voxel (the default) and every other voxel.
#[test]
fn the_baked_ao_holds_the_local_ao_wherever_a_strand_can_read_it() {
    if common::gpu().is_none() {
        return;
    }
    for texel in [1, 2] {
        check_baked_ao(texel);
    }
}

fn check_baked_ao(texel: u32) {
    use glam::IVec3;
    use tress_render::volume::{OCCUPANCY_BLOCK, ao_resolution};
    use tress_shading::volume::{
        DensityVolume, NO_CAP, ao_texel_centre, ao_texel_reached, volume_ao,
    };
    let s = VolumeSettings {
        ao: true,
        ao_texel: texel,
        ao_radius: 0.3,
        occlusion: tress_render::volume::Occlusion::Strands,
        strand_width: 0.05,
        ..settings(VoxelizeMode::Segments)
    };
    let (gpu, _, _) = run(&asset(), &s);
    let res = gpu.grid.res;
    let ao_res = ao_resolution(res, texel);
    assert_eq!(gpu.ao_texels.len(), (ao_res as usize).pow(3));
    let density: Vec<f32> = gpu.texels.iter().map(|t| t[3]).collect();
    let vol = DensityVolume::new(res, &density).expect("density");
    let occ_res = res.div_ceil(OCCUPANCY_BLOCK);
    let occupied = |b: UVec3| gpu.occupancy[(b.x + occ_res * (b.y + occ_res * b.z)) as usize] != 0;
    let reached = |t: UVec3| ao_texel_reached(t, texel, occ_res, OCCUPANCY_BLOCK, occupied);
    let scale = gpu.grid.scale;
    let index = |t: UVec3| (t.x + ao_res * (t.y + ao_res * t.z)) as usize;
    let (mut baked, mut occluded, mut worst) = (0, 0, 0i32);
    for z in 0..ao_res {
        for y in 0..ao_res {
            for x in 0..ao_res {
                let t = UVec3::new(x, y, z);
                let expected = if reached(t) {
                    baked += 1;
                    volume_ao(
                        &vol,
                        ao_texel_centre(t, texel),
                        s.ao_radius * scale,
                        s.ao_samples,
                        s.ao_intensity * s.strand_width * scale,
                        s.shadow_alpha,
                        NO_CAP,
                    )
                } else {
                    1.0
                };
                let want = (expected * 255.0).round() as i32;
                let got = i32::from(gpu.ao_texels[index(t)]);
                occluded += usize::from(got < 250);
                worst = worst.max((got - want).abs());
            }
        }
    }
    assert!(
        worst <= 1,
        "texel {texel}: a baked texel is {worst} levels from the CPU's AO"
    );
    let total = (ao_res as usize).pow(3);
    assert!(
        baked > 0 && baked < total,
        "texel {texel}: {baked} of {total} texels baked"
    );
    assert!(
        occluded > 100,
        "texel {texel}: only {occluded} texels are occluded"
    );
    // The footprint from the filter's side: a point on a strand lies within a voxel of a counted
    // voxel; a point at voxel position `x` reads texels `floor(x / texel - 1/2)` and the next,
    // so the points of voxels `lo ..= hi` read those from `lo`'s first to `hi + 0.999`'s second.
    // Each of them was baked.
    let r = res as i32;
    let last = IVec3::splat(ao_res as i32 - 1);
    let first = |v: IVec3, frac: f32| {
        let t = (v.as_vec3() + glam::Vec3::splat(frac)) / texel as f32 - glam::Vec3::splat(0.5);
        t.floor().as_ivec3().clamp(IVec3::ZERO, last)
    };
    for (i, &c) in gpu.counts.iter().enumerate() {
        if c == 0 {
            continue;
        }
        let v = IVec3::new(i as i32 % r, (i as i32 / r) % r, i as i32 / (r * r));
        let t0 = first((v - 1).max(IVec3::ZERO), 0.0);
        let t1 = (first((v + 1).min(IVec3::splat(r - 1)), 0.999) + 1).min(last);
        for z in t0.z..=t1.z {
            for y in t0.y..=t1.y {
                for x in t0.x..=t1.x {
                    let t = IVec3::new(x, y, z).as_uvec3();
                    assert!(
                        reached(t),
                        "texel {texel}: AO texel {t} is read near counted voxel {v} but not baked"
                    );
                }
            }
        }
    }
}
