//! Design rule 3: every `#[repr(C)]` struct in `gpu/types.rs` matches its WGSL twin in size and
//! member offsets, checked by parsing the composed WGSL with naga (no GPU needed).

use std::mem::{offset_of, size_of};

use tress_render::gpu::types::*;
use tress_render::shaders;

/// `(size, [(member, offset)])` of the WGSL struct `name`.
fn wgsl_layout(module: &naga::Module, name: &str) -> (u32, Vec<(String, u32)>) {
    let (_, ty) = module
        .types
        .iter()
        .find(|(_, t)| t.name.as_deref() == Some(name))
        .unwrap_or_else(|| panic!("no WGSL struct {name}"));
    match &ty.inner {
        naga::TypeInner::Struct { members, span } => (
            *span,
            members
                .iter()
                .map(|m| (m.name.clone().unwrap_or_default(), m.offset))
                .collect(),
        ),
        other => panic!("{name} is not a struct: {other:?}"),
    }
}

macro_rules! check {
    ($module:expr, $wgsl:literal, $rust:ty, [$($field:ident),* $(,)?]) => {{
        let (size, members) = wgsl_layout($module, $wgsl);
        assert_eq!(size as usize, size_of::<$rust>(), "size of {}", $wgsl);
        let rust: Vec<(String, u32)> =
            vec![$((stringify!($field).to_string(), offset_of!($rust, $field) as u32)),*];
        assert_eq!(members, rust, "members of {}", $wgsl);
    }};
}

#[test]
fn gpu_types_match_wgsl() {
    let text = shaders::compose("strands/ppll_build.wgsl").expect("composes");
    let m = naga::front::wgsl::parse_str(&text).expect("parses");
    check!(
        &m,
        "Camera",
        CameraUniform,
        [
            clip_from_world,
            eye,
            pixels_per_unit,
            viewport,
            orthographic,
            _pad0,
            forward,
            _pad1
        ]
    );
    check!(
        &m,
        "DirectionalLight",
        LightUniform,
        [light_from_world, to_light, intensity, color, depth_range]
    );
    check!(&m, "Lights", LightsUniform, [ambient, count, lights]);
    check!(
        &m,
        "StrandVertex",
        StrandVertex,
        [position, thickness, color, alpha]
    );
    check!(
        &m,
        "StrandParams",
        StrandParams,
        [
            width_px,
            alpha,
            k,
            shading,
            coverage,
            thickness_fade,
            vertex_color,
            node_capacity,
            shadow_r,
            shadow_alpha,
            pcf_radius,
            shadow_bias,
            shadow_map_size,
            shadow_width_px,
            target_width,
            shadows,
            hair_center,
            light_count,
            thickness_ref,
            nodes_per_chunk,
            shortcut_k,
            target_height,
            lod_factor,
            lod_dither,
            _pad0,
            _pad1
        ]
    );
    // HairLighting's trailing padding is implicit in WGSL (struct alignment), explicit in Rust.
    let (size, members) = wgsl_layout(&m, "HairLighting");
    assert_eq!(size as usize, size_of::<HairLightingGpu>());
    let rust = [
        ("diffuse_color", offset_of!(HairLightingGpu, diffuse_color)),
        (
            "primary_exponent",
            offset_of!(HairLightingGpu, primary_exponent),
        ),
        ("primary_color", offset_of!(HairLightingGpu, primary_color)),
        ("primary_shift", offset_of!(HairLightingGpu, primary_shift)),
        (
            "secondary_color",
            offset_of!(HairLightingGpu, secondary_color),
        ),
        (
            "secondary_exponent",
            offset_of!(HairLightingGpu, secondary_exponent),
        ),
        (
            "secondary_shift",
            offset_of!(HairLightingGpu, secondary_shift),
        ),
    ];
    let rust: Vec<(String, u32)> = rust
        .iter()
        .map(|(n, o)| (n.to_string(), *o as u32))
        .collect();
    assert_eq!(members, rust);
    check!(
        &m,
        "Material",
        MaterialUniform,
        [lighting, base_color, _pad0, head_color, _pad1, fiber, dual]
    );
    check!(
        &m,
        "DualScattering",
        DualScatteringGpu,
        [a_f, a_b, delta_b, sigma_b2, params, tt_avg, trt_avg]
    );
    check!(&m, "PpllNode", PpllNode, [color, alpha, depth, next]);
    check!(
        &m,
        "PpllCounters",
        PpllCounters,
        [requested, dropped, tail, _pad1]
    );
    // ShortCut's counters are read back with the PPLL's layout.
    let text = shaders::compose("strands/shortcut_depth.wgsl").expect("composes");
    let m = naga::front::wgsl::parse_str(&text).expect("parses");
    check!(
        &m,
        "ShortcutCounters",
        PpllCounters,
        [requested, dropped, tail, _pad1]
    );
}

#[test]
fn patch_types_match_wgsl() {
    let text = shaders::compose("patches/patch_shade.wgsl").expect("composes");
    let m = naga::front::wgsl::parse_str(&text).expect("parses");
    check!(
        &m,
        "PatchVertex",
        PatchVertex,
        [position, ao, normal, u, tangent, v]
    );
    let (size, members) = wgsl_layout(&m, "PatchParams");
    assert_eq!(size as usize, size_of::<PatchParamsGpu>());
    let rust: Vec<(String, u32)> = [
        ("lighting", offset_of!(PatchParamsGpu, lighting)),
        ("alpha_ref", offset_of!(PatchParamsGpu, alpha_ref)),
        ("use_ao", offset_of!(PatchParamsGpu, use_ao)),
        ("min_alpha", offset_of!(PatchParamsGpu, min_alpha)),
        ("shading", offset_of!(PatchParamsGpu, shading)),
        ("fiber", offset_of!(PatchParamsGpu, fiber)),
        ("dual", offset_of!(PatchParamsGpu, dual)),
    ]
    .iter()
    .map(|(n, o)| (n.to_string(), *o as u32))
    .collect();
    assert_eq!(members, rust);
}

#[test]
fn volume_types_match_wgsl() {
    for module in [
        "volume/volume_bounds.wgsl",
        "volume/voxelize.wgsl",
        "volume/raymarch.wgsl",
    ] {
        let text = shaders::compose(module).expect("composes");
        let m = naga::front::wgsl::parse_str(&text).expect("parses");
        check!(
            &m,
            "VolumeGrid",
            VolumeGrid,
            [
                origin,
                scale,
                bounds_min,
                voxel_size,
                bounds_max,
                res,
                box_min,
                occupied,
                box_max,
                density_unit
            ]
        );
        check!(
            &m,
            "VolumeParams",
            VolumeParams,
            [
                world_from_clip,
                steps,
                iso,
                skip_empty,
                shading,
                raster_shadow_mode,
                shadow_alpha,
                shadow_step,
                shadow_offset,
                raster_ao,
                ao_radius,
                ao_samples,
                ao_intensity,
                voxelize,
                reconstruction_radius,
                capacity,
                mean_segment_length,
                segment_count,
                vertex_count,
                occupancy_res,
                resolution,
                march_shadows,
                march_ao,
                strand_width,
                occlusion,
                occlusion_r,
                fade_ref,
                occlusion_width,
                occlusion_bias,
                shade_samples,
                optical_width,
                highlights,
                highlight_exponent,
                ao_texel,
                view_eye,
                view_orthographic,
                view_forward,
                light_count,
                light_dirs
            ]
        );
    }
    for module in ["volume/voxelize.wgsl", "volume/volume_resolve.wgsl"] {
        let text = shaders::compose(module).expect("composes");
        let m = naga::front::wgsl::parse_str(&text).expect("parses");
        check!(
            &m,
            "VoxelStats",
            VoxelStats,
            [deposits, dropped, saturated, _pad0]
        );
    }
    let text = shaders::compose("volume/volume_bounds.wgsl").expect("composes");
    let m = naga::front::wgsl::parse_str(&text).expect("parses");
    check!(&m, "BoundsKeys", BoundsKeys, [lo, hi]);
    check!(
        &m,
        "ResolveArgs",
        ResolveArgs,
        [groups, _pad0, origin, _pad1, end, _pad2]
    );
    let text = shaders::compose("hybrid/lod_blend.wgsl").expect("composes");
    let m = naga::front::wgsl::parse_str(&text).expect("parses");
    check!(
        &m,
        "LodParams",
        LodParams,
        [factor, transition, _pad0, _pad1]
    );
}

#[test]
fn satf_types_match_wgsl() {
    let text = shaders::compose("satf/index_calc.wgsl").expect("composes");
    let m = naga::front::wgsl::parse_str(&text).expect("parses");
    check!(
        &m,
        "SatfParams",
        SatfParams,
        [
            f_dif,
            k_dif,
            f_spe1,
            k_spe1,
            f_spe2,
            k_spe2,
            primary_shift,
            secondary_shift,
            k_h,
            k_shadow,
            feature_weights,
            k_threshold,
            angle_weight,
            shadow_approx,
            straight,
            sample_count,
            view_angles,
            light_angles,
            pixels,
            map_rows,
            st,
            su,
            layers,
            cluster_count,
            sector_count,
            hsv_count,
            tile_width,
            tile_height,
            tiles_per_row,
            mesh_nt,
            mesh_nu,
            light_count,
            key_light,
            cluster_shadows,
            pcf_radius,
            shadow_map_size,
            shadow_bias,
            shadow_opacity,
            local_shadows,
            tile_count,
            head_color,
            _pad0
        ]
    );
    check!(
        &m,
        "SatfSector",
        SatfSector,
        [
            position, cluster, normal, _pad0, s_axis, _pad1, features, _pad2
        ]
    );
    check!(
        &m,
        "SectorParams",
        SectorParams,
        [features, sample, theta_v, theta_l, _pad0, _pad1]
    );
    check!(
        &m,
        "HsvRecord",
        HsvRecord,
        [
            sample1, view1, light1, sample2, view2, light2, uniform, _pad
        ]
    );
    check!(
        &m,
        "SatfCounters",
        SatfCounters,
        [uniform_hsvs, interpolated_hsvs, _pad0, _pad1]
    );
    check!(
        &m,
        "SatfVertex",
        SatfVertex,
        [position, u, tangent, t, normal, tile]
    );
}

#[test]
fn simulation_types_match_wgsl() {
    let text = shaders::compose("sim/sim_step.wgsl").expect("composes");
    let m = naga::front::wgsl::parse_str(&text).expect("parses");
    check!(&m, "Rigid", RigidGpu, [rotation, translation]);
    check!(
        &m,
        "SimParams",
        SimParams,
        [
            h0,
            h1,
            delta,
            gravity,
            wind_dir,
            wind,
            shape,
            grid_params,
            grid_origin,
            grid_dims,
            sdf_origin,
            sdf_dims,
            counts,
            counts2
        ]
    );
    check!(
        &m,
        "SimRest",
        SimRest,
        [position, rest_len, global_w, margin, flags, strand]
    );
    assert!(
        std::mem::size_of::<SimParams>() as u64 <= tress_render::sim::UNIFORM_STRIDE,
        "a substep's uniforms overrun their slot"
    );
    let text = shaders::compose("sim/sim_output.wgsl").expect("composes");
    let m = naga::front::wgsl::parse_str(&text).expect("parses");
    check!(
        &m,
        "SimOutputParams",
        SimOutputParams,
        [head_rotation, counts]
    );
    check!(
        &m,
        "SimFollower",
        SimFollower,
        [guides, weights, first, asset_first, _pad0, _pad1]
    );
    check!(
        &m,
        "SimFollowerVertex",
        SimFollowerVertex,
        [offset, follower]
    );
    // The output writes the renderers' vertex through its own copy of the struct.
    check!(
        &m,
        "SimOutVertex",
        StrandVertex,
        [position, thickness, color, alpha]
    );
}

#[test]
fn simulation_constants_mirror_the_cpu_twin() {
    let text = shaders::compose("sim/sim_step.wgsl").expect("composes");
    let m = naga::front::wgsl::parse_str(&text).expect("parses");
    let constant = |name: &str| -> f64 {
        let (_, c) = m
            .constants
            .iter()
            .find(|(_, c)| c.name.as_deref() == Some(name))
            .unwrap_or_else(|| panic!("no constant {name}"));
        match m.global_expressions[c.init] {
            naga::Expression::Literal(naga::Literal::F32(v)) => f64::from(v),
            naga::Expression::Literal(naga::Literal::U32(v)) => f64::from(v),
            ref other => panic!("{name}: {other:?}"),
        }
    };
    assert_eq!(
        constant("GRID_WEIGHT_ONE"),
        f64::from(tress_sim::grid::WEIGHT_ONE)
    );
    assert_eq!(
        constant("GRID_VELOCITY_ONE"),
        f64::from(tress_sim::grid::VELOCITY_ONE)
    );
    assert_eq!(
        constant("GRID_MAX_CELLS"),
        f64::from(tress_sim::grid::MAX_CELLS)
    );
    assert_eq!(
        constant("GRID_MAX_PUSH_CELLS"),
        f64::from(tress_sim::grid::MAX_PUSH_CELLS)
    );
    assert_eq!(
        constant("SIM_FINAL_ROUNDS"),
        f64::from(tress_sim::step::FINAL_ROUNDS)
    );
    assert_eq!(
        constant("SIM_PROJECTION_STEPS"),
        f64::from(tress_sim::step::PROJECTION_STEPS)
    );
    assert_eq!(
        constant("SIM_MAX_VERTICES"),
        tress_render::sim::MAX_SIM_VERTICES as f64
    );
}
