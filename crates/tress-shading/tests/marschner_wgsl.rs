//! The WGSL twin of the Marschner lobes and the dual-scattering term
//! (`tress-render/src/shaders/common/marschner.wgsl`) parses and validates with naga, and
//! declares exactly the functions and structs of `marschner.rs` and `dual_scattering.rs`, with
//! the same argument and field names in the same order and the same struct sizes.

use naga::valid::{Capabilities, ValidationFlags, Validator};

const MARSCHNER_WGSL: &str = include_str!("../../tress-render/src/shaders/common/marschner.wgsl");

fn module() -> naga::Module {
    naga::front::wgsl::parse_str(MARSCHNER_WGSL).unwrap_or_else(|e| {
        panic!(
            "marschner.wgsl does not parse:\n{}",
            e.emit_to_string(MARSCHNER_WGSL)
        )
    })
}

/// Every twin with its argument names.
const FUNCTIONS: &[(&str, &[&str])] = &[
    ("hair_angles", &["t", "l", "v"]),
    ("hair_gaussian", &["beta", "x"]),
    ("fresnel_schlick", &["eta", "cos_theta"]),
    ("marschner_r", &["m", "a"]),
    ("marschner_tt", &["m", "a"]),
    ("marschner_trt", &["m", "a"]),
    ("marschner", &["m", "t", "l", "v"]),
    ("marschner_lighting", &["m", "t", "l", "light_color", "v"]),
    ("dual_scattering_at", &["ds", "sin_theta_i"]),
    (
        "dual_scattering_lighting",
        &["m", "ds", "t", "l", "light_color", "v", "strands", "direct"],
    ),
];

/// The private helpers (CPU: private functions of the same modules).
const HELPERS: &[&str] = &[
    "marschner_inv_eta_prime",
    "marschner_crossing",
    "ds_gaussian3",
    "ds_spread_single_scattering",
    "ds_lighting_at",
    "ds_table_x",
    "ds_rows",
    "ds_table_mix",
];

const STRUCTS: &[(&str, &[&str], u32)] = &[
    ("Marschner", &["sigma_a", "eta", "beta", "alpha"], 32),
    (
        "HairAngles",
        &[
            "sin_theta_i",
            "sin_theta_o",
            "cos_theta_d",
            "cos_phi",
            "cos_half_phi",
            "cos_half_lv",
        ],
        24,
    ),
    (
        "DualScattering",
        &[
            "a_f", "a_b", "delta_b", "sigma_b2", "params", "tt_avg", "trt_avg",
        ],
        1072,
    ),
    (
        "DualScatteringAt",
        &["a_f", "beta_f2", "a_b", "delta_b", "sigma_b2"],
        64,
    ),
];

#[test]
fn marschner_wgsl_parses_and_validates() {
    let module = module();
    if let Err(e) = Validator::new(ValidationFlags::all(), Capabilities::all()).validate(&module) {
        panic!(
            "marschner.wgsl does not validate:\n{}",
            e.emit_to_string(MARSCHNER_WGSL)
        );
    }
    assert!(
        module.global_variables.is_empty(),
        "marschner.wgsl must not declare bindings"
    );
    assert!(
        module.entry_points.is_empty(),
        "marschner.wgsl is a library of functions"
    );
}

#[test]
fn functions_match_the_cpu_twins() {
    let module = module();
    for (name, args) in FUNCTIONS {
        let Some((_, f)) = module
            .functions
            .iter()
            .find(|(_, f)| f.name.as_deref() == Some(name))
        else {
            panic!("marschner.wgsl lacks fn {name}");
        };
        let got: Vec<_> = f
            .arguments
            .iter()
            .map(|a| a.name.as_deref().unwrap_or(""))
            .collect();
        assert_eq!(got, *args, "arguments of fn {name}");
    }
    for (_, f) in module.functions.iter() {
        let name = f.name.as_deref().unwrap_or("");
        assert!(
            HELPERS.contains(&name) || FUNCTIONS.iter().any(|(n, _)| *n == name),
            "fn {name} in marschner.wgsl is not in the twin table"
        );
    }
}

#[test]
fn structs_match_the_cpu_twins() {
    let module = module();
    for (name, fields, size) in STRUCTS {
        let found = module.types.iter().find_map(|(_, ty)| match &ty.inner {
            naga::TypeInner::Struct { members, span } if ty.name.as_deref() == Some(name) => {
                Some((
                    members
                        .iter()
                        .map(|m| m.name.clone().unwrap_or_default())
                        .collect::<Vec<_>>(),
                    *span,
                ))
            }
            _ => None,
        });
        let Some((got, span)) = found else {
            panic!("marschner.wgsl lacks struct {name}")
        };
        assert_eq!(got, *fields, "fields of struct {name}");
        assert_eq!(span, *size, "size of struct {name}");
    }
}

/// The CPU structs have the fields named in `STRUCTS` (this does not build if a field is renamed
/// on one side only), and the table length agrees.
#[test]
fn cpu_structs_have_the_same_fields() {
    use glam::{Vec3, Vec4};
    use tress_shading::dual_scattering::{DS_TABLE, DualScattering, DualScatteringAt};
    use tress_shading::marschner::{HairAngles, Marschner};
    let _ = Marschner {
        sigma_a: Vec3::ZERO,
        eta: 1.55,
        beta: Vec3::ONE,
        alpha: 0.0,
    };
    let _ = HairAngles {
        sin_theta_i: 0.0,
        sin_theta_o: 0.0,
        cos_theta_d: 1.0,
        cos_phi: 1.0,
        cos_half_phi: 1.0,
        cos_half_lv: 1.0,
    };
    let _ = DualScattering {
        a_f: [Vec4::ZERO; DS_TABLE],
        a_b: [Vec4::ZERO; DS_TABLE],
        delta_b: [Vec4::ZERO; DS_TABLE],
        sigma_b2: [Vec4::ZERO; DS_TABLE],
        params: Vec4::ZERO,
        tt_avg: Vec4::ZERO,
        trt_avg: Vec4::ZERO,
    };
    let _ = DualScatteringAt {
        a_f: Vec3::ZERO,
        beta_f2: 0.0,
        a_b: Vec3::ZERO,
        delta_b: Vec3::ZERO,
        sigma_b2: Vec3::ZERO,
    };
    assert!(MARSCHNER_WGSL.contains(&format!("array<vec4f, {DS_TABLE}>")));
    assert_eq!(size_of::<DualScattering>(), 1072);
}
