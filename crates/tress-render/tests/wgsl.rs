//! Every WGSL module of the crate, composed, parses and validates with naga (no GPU needed).

use tress_render::shaders;

fn validate(name: &str, text: &str) -> naga::Module {
    let module = naga::front::wgsl::parse_str(text)
        .unwrap_or_else(|e| panic!("{name} does not parse:\n{}", e.emit_to_string(text)));
    naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::default(),
    )
    .validate(&module)
    .unwrap_or_else(|e| panic!("{name} does not validate:\n{}", e.emit_to_string(text)));
    module
}

#[test]
fn every_source_file_composes_and_validates() {
    assert!(shaders::SOURCES.len() >= 10);
    for (path, _) in shaders::SOURCES {
        let text = shaders::compose(path).expect("composes");
        validate(path, &text);
    }
}

#[test]
fn entry_modules_have_their_entry_points() {
    let expect: &[(&str, &[&str])] = &[
        ("head/head_pass.wgsl", &["vs_main", "fs_main"]),
        (
            "strands/shadow.wgsl",
            &["vs_strand", "vs_strand_line", "vs_head"],
        ),
        ("strands/ppll_build.wgsl", &["vs_main", "fs_main"]),
        ("strands/ppll_resolve.wgsl", &["vs_main", "fs_main"]),
        ("strands/shortcut_depth.wgsl", &["vs_main", "fs_main"]),
        ("strands/shortcut_shade.wgsl", &["vs_main", "fs_main"]),
        ("strands/shortcut_resolve.wgsl", &["vs_main", "fs_main"]),
        ("satf/index_calc.wgsl", &["cs_sectors", "cs_hsvs"]),
        ("satf/map_build.wgsl", &["cs_main"]),
        (
            "satf/cluster_shadow.wgsl",
            &["vs_layer", "vs_head", "fs_main"],
        ),
        ("satf/s_maps.wgsl", &["cs_main"]),
        ("satf/lighting.wgsl", &["cs_main"]),
        ("satf/texture_map.wgsl", &["vs_main", "fs_main"]),
        ("satf/head.wgsl", &["vs_main", "fs_main"]),
        ("volume/volume_bounds.wgsl", &["clear", "reduce", "fit"]),
        ("volume/voxelize.wgsl", &["voxelize"]),
        ("volume/volume_resolve.wgsl", &["resolve"]),
        ("volume/ao_bake.wgsl", &["bake"]),
        ("volume/raymarch.wgsl", &["vs_main", "fs_main"]),
        ("hybrid/lod_blend.wgsl", &["vs_main", "fs_main"]),
        ("patches/z_prime.wgsl", &["vs_main", "fs_main"]),
        (
            "patches/patch_shade.wgsl",
            &[
                "vs_main",
                "fs_main",
                "fs_opaque",
                "fs_transparent",
                "fs_non_empty",
                "fs_transparent_non_empty",
            ],
        ),
        ("patches/patch_head.wgsl", &["vs_main", "fs_main"]),
        (
            "sim/sim_step.wgsl",
            &[
                "shock",
                "integrate",
                "grid_clear",
                "grid_splat",
                "grid_apply",
                "constraints",
                "friction",
            ],
        ),
        (
            "sim/sim_output.wgsl",
            &[
                "write_frames",
                "write_guides",
                "write_followers",
                "fix_follower_lengths",
            ],
        ),
    ];
    assert_eq!(expect.len(), shaders::ENTRY_MODULES.len());
    for (path, entries) in expect {
        let module = validate(path, &shaders::compose(path).expect("composes"));
        let names: Vec<&str> = module
            .entry_points
            .iter()
            .map(|e| e.name.as_str())
            .collect();
        assert_eq!(&names, entries, "{path}");
    }
}

#[test]
fn every_wgsl_file_on_disk_is_listed() {
    fn walk(dir: &std::path::Path, root: &std::path::Path, out: &mut Vec<String>) {
        for entry in std::fs::read_dir(dir).expect("src is readable") {
            let path = entry.expect("entry").path();
            if path.is_dir() {
                walk(&path, root, out);
            } else if path.extension().is_some_and(|e| e == "wgsl") {
                let rel = path.strip_prefix(root).expect("under src");
                let rel = rel.to_string_lossy().replace('\\', "/");
                out.push(rel.strip_prefix("shaders/").unwrap_or(&rel).to_string());
            }
        }
    }
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut on_disk = Vec::new();
    walk(&root, &root, &mut on_disk);
    on_disk.sort();
    let mut listed: Vec<String> = shaders::SOURCES
        .iter()
        .map(|(p, _)| p.to_string())
        .collect();
    listed.sort();
    assert_eq!(on_disk, listed);
}

#[test]
fn shading_test_harness_validates() {
    let src = include_str!("shading_gpu.wgsl");
    let text = shaders::compose_source("tests/shading_gpu.wgsl", src).expect("composes");
    validate("tests/shading_gpu.wgsl", &text);
}

/// The value of a scalar `const` of a composed module, as f64.
fn scalar_const(module: &naga::Module, name: &str) -> f64 {
    let (_, c) = module
        .constants
        .iter()
        .find(|(_, c)| c.name.as_deref() == Some(name))
        .unwrap_or_else(|| panic!("no const {name}"));
    match module.global_expressions[c.init] {
        naga::Expression::Literal(naga::Literal::F32(v)) => f64::from(v),
        naga::Expression::Literal(naga::Literal::U32(v)) => f64::from(v),
        ref e => panic!("{name} is not a literal: {e:?}"),
    }
}

#[test]
fn shortcut_tail_constants_mirror_the_cpu_twin() {
    let text = shaders::compose("common/shortcut_keys.wgsl").expect("composes");
    let module = validate("common/shortcut_keys.wgsl", &text);
    assert_eq!(
        scalar_const(&module, "TAIL_SPACINGS"),
        f64::from(tress_shading::SHORTCUT_TAIL_SPACINGS)
    );
    assert_eq!(
        scalar_const(&module, "TAIL_PICK"),
        f64::from(tress_shading::SHORTCUT_TAIL_PICK)
    );
    assert_eq!(
        scalar_const(&module, "TAIL_SALT"),
        f64::from(tress_shading::SHORTCUT_TAIL_SALT)
    );
    assert_eq!(
        scalar_const(&module, "DEPTH_LEVELS"),
        f64::from(tress_shading::SHORTCUT_DEPTH_LEVELS)
    );
    assert_eq!(
        scalar_const(&module, "ALPHA_LEVELS"),
        f64::from(tress_shading::SHORTCUT_ALPHA_LEVELS)
    );
    // The key's shift leaves the alpha's bits: 2^ALPHA_BITS - 1 >= ALPHA_LEVELS + 1 words.
    assert_eq!(scalar_const(&module, "ALPHA_BITS"), 9.0);
    assert!(f64::from(tress_shading::SHORTCUT_ALPHA_LEVELS) + 1.0 <= 511.0);
}

#[test]
fn the_shadow_strand_cap_mirrors_the_cpu_twin() {
    let text = shaders::compose("common/lighting.wgsl").expect("composes");
    let module = validate("common/lighting.wgsl", &text);
    assert_eq!(
        scalar_const(&module, "MAX_SHADOW_STRANDS"),
        f64::from(tress_shading::MAX_SHADOW_STRANDS)
    );
}

#[test]
fn the_volume_constants_mirror_the_settings() {
    let text = shaders::compose("common/volume.wgsl").expect("composes");
    let module = validate("common/volume.wgsl", &text);
    assert_eq!(
        scalar_const(&module, "MAX_SHADE_SAMPLES"),
        f64::from(tress_render::volume::MAX_SHADE_SAMPLES)
    );
    assert_eq!(
        scalar_const(&module, "OCCUPANCY_BLOCK"),
        f64::from(tress_render::volume::OCCUPANCY_BLOCK)
    );
    use tress_shading::voxelize::{TEXEL_MAX_COUNT, TEXEL_TANGENT_SCALE, TEXEL_TANGENT_ZERO};
    assert_eq!(
        scalar_const(&module, "TEXEL_TANGENT_ZERO"),
        f64::from(TEXEL_TANGENT_ZERO)
    );
    assert_eq!(
        scalar_const(&module, "TEXEL_TANGENT_SCALE"),
        f64::from(TEXEL_TANGENT_SCALE)
    );
    assert_eq!(
        scalar_const(&module, "TEXEL_MAX_COUNT"),
        f64::from(TEXEL_MAX_COUNT)
    );
}
