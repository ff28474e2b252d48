//! The volume twins' WGSL side (`tress-render/src/shaders/common/volume.wgsl`) parses and
//! validates with naga, and every function with a CPU twin in `tress_shading::volume` /
//! `tress_shading::voxelize` has the same argument names in the same order (the WGSL functions
//! that take the volume texture and its sampler take them in place of the CPU `&DensityVolume`
//! and the texels' `vt` (resolution and density unit), first). GPU-vs-CPU values are compared in `tress-render/tests/volume_shading_gpu.rs`.

use naga::valid::{Capabilities, ValidationFlags, Validator};

const SHADING_WGSL: &str = include_str!("../../tress-render/src/shaders/common/shading.wgsl");
const VOLUME_WGSL: &str = include_str!("../../tress-render/src/shaders/common/volume.wgsl");

/// volume.wgsl with its one include (shading.wgsl) spliced in, as the renderer composes it.
fn module() -> naga::Module {
    let text = VOLUME_WGSL.replace("#include \"common/shading.wgsl\"", SHADING_WGSL);
    let module = naga::front::wgsl::parse_str(&text)
        .unwrap_or_else(|e| panic!("volume.wgsl does not parse:\n{}", e.emit_to_string(&text)));
    if let Err(e) = Validator::new(ValidationFlags::all(), Capabilities::all()).validate(&module) {
        panic!(
            "volume.wgsl does not validate:\n{}",
            e.emit_to_string(&text)
        );
    }
    module
}

/// `(WGSL name, WGSL arguments)`; a leading `tex, samp, vt` stands for the CPU `vol`.
const FUNCTIONS: &[(&str, &[&str])] = &[
    ("voxel_hash", &["x"]),
    ("isqrt", &["x"]),
    ("quantize_tangent", &["t"]),
    ("dequantize_tangent", &["sum", "count"]),
    ("segment_tangent", &["p0", "p1"]),
    ("encode_texel", &["tangent", "count"]),
    ("decode_texel", &["raw", "density_unit"]),
    ("segment_sample_count", &["q0", "q1", "segment"]),
    ("segment_sample", &["a", "d", "k", "n"]),
    ("ray_box", &["o", "d", "lo", "hi"]),
    (
        "volume_shadow_strands",
        &["tex", "samp", "vt", "x", "l", "step", "offset", "cap"],
    ),
    ("ao_offset", &["i", "n"]),
    (
        "volume_ao",
        &[
            "tex",
            "samp",
            "vt",
            "x",
            "radius",
            "samples",
            "intensity",
            "alpha",
            "cap",
        ],
    ),
    ("density_gradient", &["tex", "samp", "vt", "x"]),
    ("density_normal", &["gradient", "fallback"]),
    ("fake_transparency_alpha", &["strands", "iso"]),
    ("volume_tangent_coherence", &["tex", "samp", "vt", "x"]),
    (
        "strand_optical_depth",
        &["strands", "tangent", "dir", "pixel_voxels", "optical_width"],
    ),
    ("lod_factor", &["distance", "near", "far"]),
    ("dither_threshold", &["px"]),
];

#[test]
fn volume_wgsl_declares_the_twins_with_the_cpu_argument_names() {
    let module = module();
    for (name, args) in FUNCTIONS {
        let Some((_, f)) = module
            .functions
            .iter()
            .find(|(_, f)| f.name.as_deref() == Some(name))
        else {
            panic!("volume.wgsl lacks fn {name}");
        };
        let got: Vec<_> = f
            .arguments
            .iter()
            .map(|a| a.name.as_deref().unwrap_or(""))
            .collect();
        assert_eq!(got, *args, "arguments of fn {name}");
    }
    assert!(
        module.global_variables.is_empty(),
        "volume.wgsl must not declare bindings"
    );
    assert!(module.entry_points.is_empty(), "volume.wgsl is a library");
}

#[test]
fn cpu_twins_exist_with_the_same_arity() {
    // Calling each twin with the WGSL argument count (a `vol` for `tex, samp, vt`) is the check:
    // this test does not compile if a CPU signature drifts.
    use glam::{IVec3, UVec2, UVec3, Vec3};
    use tress_shading::voxelize::{isqrt, segment_sample, segment_sample_count, segment_tangent};
    use tress_shading::*;
    let d = vec![1.0; 8];
    let vol = DensityVolume::new(2, &d).unwrap();
    let _ = (voxel_hash(1), isqrt(4), quantize_tangent(Vec3::X));
    let _ = dequantize_tangent(Vec3::ONE, 1.0);
    let _ = segment_tangent(Vec3::ZERO, Vec3::X);
    let _ = tress_shading::voxelize::decode_texel([0; 4], 1.0);
    let _ = tress_shading::voxelize::encode_texel(Vec3::X, 1);
    let _ = segment_sample_count(UVec3::ZERO, UVec3::ONE, 0);
    let _ = segment_sample(IVec3::ZERO, IVec3::ONE, 0, 1);
    let _ = ray_box(Vec3::ZERO, Vec3::X, Vec3::ZERO, Vec3::ONE);
    let _ = volume_shadow_strands(&vol, Vec3::ONE, Vec3::X, 1.0, 0.0, 1.0);
    let _ = ao_offset(0, 1);
    let _ = volume_ao(&vol, Vec3::ONE, 1.0, 4, 1.0, 0.5, 1.0);
    let _ = density_normal(density_gradient(&vol, Vec3::ONE), Vec3::Z);
    let _ = (fake_transparency_alpha(1.0, 2.0), lod_factor(1.0, 0.0, 2.0));
    let _ = strand_optical_depth(1.0, Vec3::X, Vec3::Z, 1.0, 0.5);
    let texels = [[0u8; 4]; 8];
    let _ = volume_tangent_coherence(&TexelVolume::new(2, &texels, 1.0).unwrap(), Vec3::ONE);
    let _ = dither_threshold(UVec2::ZERO);
}
