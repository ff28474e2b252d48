//! The WGSL twin of this crate (`tress-render/src/shaders/common/shading.wgsl`) parses and
//! validates with naga, and declares exactly the functions and structs the CPU side documents,
//! with the same argument and field names in the same order.

use naga::valid::{Capabilities, ValidationFlags, Validator};

const SHADING_WGSL: &str = include_str!("../../tress-render/src/shaders/common/shading.wgsl");

fn module() -> naga::Module {
    match naga::front::wgsl::parse_str(SHADING_WGSL) {
        Ok(m) => m,
        Err(e) => panic!(
            "shading.wgsl does not parse:\n{}",
            e.emit_to_string(SHADING_WGSL)
        ),
    }
}

#[test]
fn shading_wgsl_parses_and_validates() {
    let module = module();
    if let Err(e) = Validator::new(ValidationFlags::all(), Capabilities::all()).validate(&module) {
        panic!(
            "shading.wgsl does not validate:\n{}",
            e.emit_to_string(SHADING_WGSL)
        );
    }
}

/// Every twin of the table in the crate docs, with its argument names.
const FUNCTIONS: &[(&str, &[&str])] = &[
    ("kajiya_kay_diffuse", &["t", "l"]),
    ("kajiya_kay_specular", &["t", "l", "v", "exponent"]),
    ("kajiya_kay", &["kk", "t", "l", "v"]),
    ("spread_kajiya_kay", &["kk", "mean_length"]),
    ("shift_tangent", &["t", "n", "shift"]),
    ("strand_specular", &["t", "v", "l", "exponent"]),
    ("scheuermann_diffuse", &["n", "l"]),
    ("hair_lighting", &["p", "s", "l", "light_color", "v"]),
    ("coverage_from_distance", &["d", "line_thickness"]),
    ("screen_from_clip", &["clip", "resolution"]),
    (
        "strand_coverage",
        &[
            "screen_fragment",
            "world_line",
            "clip_from_world",
            "resolution",
            "line_thickness",
        ],
    ),
    ("tip_fade", &["thickness", "line_thickness"]),
    ("strand_visibility", &["n", "alpha"]),
    ("adsm_visibility", &["d", "r", "alpha"]),
    ("adsm_depth", &["fragment_depth", "occluder_depth"]),
    (
        "adsm_pcf",
        &[
            "map",
            "texel",
            "kernel_radius",
            "fragment_depth",
            "r",
            "alpha",
        ],
    ),
    ("blend_under", &["acc", "src"]),
    ("blend_front_to_back", &["acc", "color", "alpha"]),
    ("tail_empty", &[]),
    ("tail_accumulate", &["tail", "color", "alpha"]),
    ("tail_resolve", &["tail"]),
    ("composite_over_background", &["acc", "background"]),
];

/// Structs shared with the CPU side, with their field names in order.
const STRUCTS: &[(&str, &[&str])] = &[
    ("KajiyaKay", &["diffuse", "specular", "exponent"]),
    (
        "HairLighting",
        &[
            "diffuse_color",
            "primary_exponent",
            "primary_color",
            "primary_shift",
            "secondary_color",
            "secondary_exponent",
            "secondary_shift",
        ],
    ),
    (
        "HairSample",
        &[
            "tangent",
            "shift_tex",
            "normal",
            "spec_mask",
            "base_color",
            "amb_occ",
        ],
    ),
    (
        "TailAccum",
        &["weighted_color", "alpha_sum", "transmittance"],
    ),
];

#[test]
fn functions_match_the_cpu_twins() {
    let module = module();
    for (name, args) in FUNCTIONS {
        let Some((_, f)) = module
            .functions
            .iter()
            .find(|(_, f)| f.name.as_deref() == Some(name))
        else {
            panic!("shading.wgsl lacks fn {name}");
        };
        let got: Vec<_> = f
            .arguments
            .iter()
            .map(|a| a.name.as_deref().unwrap_or(""))
            .collect();
        assert_eq!(got, *args, "arguments of fn {name}");
        assert!(f.result.is_some(), "fn {name} returns nothing");
    }
    // Only the documented twins and the private helper exist: nothing undocumented.
    for (_, f) in module.functions.iter() {
        let name = f.name.as_deref().unwrap_or("");
        assert!(
            name == "sin_from_cos" || FUNCTIONS.iter().any(|(n, _)| *n == name),
            "fn {name} in shading.wgsl is not in the twin table"
        );
    }
    assert!(
        module.global_variables.is_empty(),
        "shading.wgsl must not declare bindings"
    );
    assert!(
        module.entry_points.is_empty(),
        "shading.wgsl is a library of functions"
    );
}

#[test]
fn structs_match_the_cpu_twins() {
    let module = module();
    for (name, fields) in STRUCTS {
        let found = module.types.iter().find_map(|(_, ty)| match &ty.inner {
            naga::TypeInner::Struct { members, .. } if ty.name.as_deref() == Some(name) => Some(
                members
                    .iter()
                    .map(|m| m.name.clone().unwrap_or_default())
                    .collect::<Vec<_>>(),
            ),
            _ => None,
        });
        let Some(got) = found else {
            panic!("shading.wgsl lacks struct {name}")
        };
        assert_eq!(got, *fields, "fields of struct {name}");
    }
}

/// The CPU structs have the fields named in `STRUCTS` (checked by the compiler: this does not
/// build if a field is renamed on one side only), and the constant agrees.
#[test]
fn cpu_structs_have_the_same_fields() {
    use glam::Vec3;
    use tress_shading::{HairLighting, HairSample, KajiyaKay, TailAccum};
    let _ = KajiyaKay {
        diffuse: Vec3::ONE,
        specular: Vec3::ONE,
        exponent: 1.0,
    };
    let _ = HairLighting {
        diffuse_color: Vec3::ONE,
        primary_exponent: 1.0,
        primary_color: Vec3::ONE,
        primary_shift: 0.0,
        secondary_color: Vec3::ONE,
        secondary_exponent: 1.0,
        secondary_shift: 0.0,
    };
    let _ = HairSample {
        tangent: Vec3::X,
        shift_tex: 0.5,
        normal: Vec3::Y,
        spec_mask: 1.0,
        base_color: Vec3::ONE,
        amb_occ: 1.0,
    };
    let _ = TailAccum {
        weighted_color: Vec3::ZERO,
        alpha_sum: 0.0,
        transmittance: 1.0,
    };
    assert!(
        SHADING_WGSL.contains(&format!(
            "const MAX_PCF_RADIUS: i32 = {};",
            tress_shading::MAX_PCF_RADIUS
        )),
        "MAX_PCF_RADIUS differs between the twins"
    );
}
