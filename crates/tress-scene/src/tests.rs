//! Tests of parsing, errors, overrides, technique tables, validation and writing.

use std::path::PathBuf;

use glam::Vec3;
use serde::Deserialize;
use tress_hair::generate::{Head, HeadShape, Style, head_for};

use crate::*;

fn parse(text: &str) -> Result<Scene, SceneError> {
    Scene::from_str(text, "base")
}

/// The default scene, with the base folder `parse` gives.
fn default_in_base() -> Scene {
    let mut s = Scene::default();
    s.base_dir = PathBuf::from("base");
    s
}

/// The message of an error, asserting it is one line.
fn message(e: SceneError) -> String {
    let m = e.to_string();
    assert!(!m.contains('\n'), "multi-line error: {m}");
    m
}

#[test]
fn empty_file_is_the_default_scene() {
    let s = parse("").unwrap();
    assert_eq!(s, default_in_base());
    assert_eq!(s.lights.len(), 2);
    assert!(s.hair.is_empty());
    assert_eq!(s.technique, "strands");
    Scene::default().validate().unwrap();
}

#[test]
fn documented_defaults_are_the_defaults() {
    let s = parse(include_str!("../doc/defaults.toml")).unwrap();
    assert_eq!(s, default_in_base());
}

#[test]
fn documented_hair_entry_is_the_default_entry() {
    let s = parse(include_str!("../doc/hair.toml")).unwrap();
    let expected = HairSpec {
        generator: Some(GeneratorSpec::new(Style::Ponytail)),
        ..HairSpec::default()
    };
    assert_eq!(s.hair, vec![expected]);
}

#[test]
fn default_camera_frames_the_default_head() {
    // Every corner of the default head's bounding box projects inside the image.
    let s = Scene::default();
    let head = Head::default();
    let m = s.camera.clip_from_world(s.output.aspect());
    for i in 0..8 {
        let sign = Vec3::new(
            if i & 1 == 0 { -1.0 } else { 1.0 },
            if i & 2 == 0 { -1.0 } else { 1.0 },
            if i & 4 == 0 { -1.0 } else { 1.0 },
        );
        let clip = m * (head.center + head.radii * sign).extend(1.0);
        let ndc = clip.truncate() / clip.w;
        assert!(
            ndc.x.abs() < 1.0 && ndc.y.abs() < 1.0 && (0.0..1.0).contains(&ndc.z),
            "{ndc}"
        );
    }
}

#[test]
fn integers_are_accepted_for_floats() {
    let s = parse("background = [1, 0, 0]\n[camera]\nfov_y_deg = 40\n").unwrap();
    assert_eq!(s.background, Vec3::X);
    assert_eq!(s.camera.fov_y_deg, 40.0);
}

#[test]
fn unknown_keys_name_key_and_line() {
    let cases = [
        ("[camera]\nfov = 35\n", "fov", 2),
        (
            "technique = \"strands\"\n\nbackgroud = [0, 0, 0]\n",
            "backgroud",
            3,
        ),
        (
            "[[light]]\nintensity = 1\n[[light]]\ncolour = [1, 1, 1]\n",
            "colour",
            4,
        ),
        (
            "[[hair]]\ngenerator = { style = \"curly\", strandz = 5 }\n",
            "strandz",
            2,
        ),
        (
            "[[hair]]\ngenerator = { style = \"curly\" }\n[hair.material]\n\nshine = 3\n",
            "shine",
            5,
        ),
        ("[output]\nwidth = 10\nheight = 10\ndepth = 3\n", "depth", 4),
        ("[strandz]\nk = 8\n", "strandz", 1),
    ];
    for (text, key, line) in cases {
        let m = message(parse(text).unwrap_err());
        assert!(m.contains(&format!("`{key}`")), "{text:?}: {m}");
        assert!(m.contains(&format!("line {line},")), "{text:?}: {m}");
    }
}

#[test]
fn type_and_syntax_errors_name_the_line() {
    let m = message(parse("[camera]\nnear = 1\nfar = \"far\"\n").unwrap_err());
    assert!(m.starts_with("line 3,"), "{m}");
    let m = message(parse("[camera\n").unwrap_err());
    assert!(m.starts_with("line 1,"), "{m}");
    let m = message(parse("[[hair]]\ngenerator = { strands = 5 }\n").unwrap_err());
    assert!(m.contains("line 2,") && m.contains("style"), "{m}");
}

#[test]
fn file_errors_name_the_file() {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("no-such-dir");
    let m = message(Scene::from_path(dir.join("missing.toml")).unwrap_err());
    assert!(m.contains("missing.toml"), "{m}");
}

#[test]
fn values_are_validated() {
    let cases = [
        ("technique = \"raytrace\"\n", "technique"),
        ("background = [-1, 0, 0]\n", "background"),
        ("ambient = -0.1\n", "ambient"),
        ("ambient = nan\n", "ambient"),
        ("[camera]\nnear = 0\n", "camera.near"),
        ("[camera]\nnear = 10\nfar = 5\n", "camera.far"),
        ("[camera]\nfov_y_deg = 180\n", "camera.fov_y_deg"),
        (
            "[camera]\neye = [0, 0, 5]\ntarget = [0, 0, 5]\n",
            "camera.target",
        ),
        (
            "[camera]\neye = [0, 5, 0]\ntarget = [0, 0, 0]\n",
            "camera.up",
        ),
        ("[[light]]\ndirection = [0, 0, 0]\n", "light.0.direction"),
        (
            "[[light]]\n[[light]]\nintensity = -1\n",
            "light.1.intensity",
        ),
        ("[[hair]]\n", "hair.0"),
        (
            "[[hair]]\nfiles = [\"a.tfx\"]\ngenerator = { style = \"fur\" }\n",
            "hair.0",
        ),
        (
            "[[hair]]\ngenerator = { style = \"mohawk\" }\n",
            "hair.0.generator.style",
        ),
        (
            "[[hair]]\ngenerator = { style = \"fur\", vertices = 1 }\n",
            "hair.0.generator",
        ),
        (
            "[[hair]]\ngenerator = { style = \"fur\" }\nstrand_ratio = 0\n",
            "hair.0.strand_ratio",
        ),
        (
            "[[hair]]\ngenerator = { style = \"fur\" }\ntransform = { scale = 0 }\n",
            "hair.0.transform.scale",
        ),
        (
            "[[hair]]\ngenerator = { style = \"fur\" }\n[hair.material]\nprimary_exponent = 0\n",
            "hair.0.material.primary_exponent",
        ),
        ("[head]\nobj = \"h.obj\"\ngenerated = true\n", "head"),
        ("[head]\nradii = [1, 0, 1]\n", "head.radii"),
        ("[output]\nwidth = 0\n", "output.width"),
    ];
    for (text, key) in cases {
        match parse(text) {
            Err(SceneError::Invalid { key: k, reason }) => assert_eq!(k, key, "{text:?}: {reason}"),
            other => panic!("{text:?}: expected an error for {key}, got {other:?}"),
        }
    }
}

#[test]
fn overrides_set_values_by_dotted_key() {
    let mut s = parse("[[hair]]\ngenerator = { style = \"wavy\" }\n").unwrap();
    s.apply_overrides([
        "camera.fov_y_deg=35.5",
        "strands.k=8",
        "light.0.intensity=2",
        "hair.0.material.base_color=[0.3,0.2,0.1]",
        "hair.0.generator.strands = 5000",
        "technique=volume",
        "head.generated=false",
    ])
    .unwrap();
    assert_eq!(s.camera.fov_y_deg, 35.5);
    assert_eq!(s.strands.get("k"), Some(&toml::Value::Integer(8)));
    assert_eq!(s.lights[0].intensity, 2.0);
    assert_eq!(
        s.lights[1],
        Light::default_rig()[1],
        "other lights untouched"
    );
    assert_eq!(s.hair[0].material.base_color, Vec3::new(0.3, 0.2, 0.1));
    assert_eq!(s.hair[0].generator.as_ref().unwrap().strands, Some(5000));
    assert_eq!(s.technique, "volume");
    assert_eq!(s.head_source(), HeadSource::None);
    assert_eq!(
        s.base_dir,
        PathBuf::from("base"),
        "overrides keep the base folder"
    );
}

#[test]
fn override_appends_array_entries() {
    let mut s = Scene::default();
    s.apply_override("light.2.intensity=0.5").unwrap();
    assert_eq!(s.lights.len(), 3);
    assert_eq!(
        s.lights[2],
        Light {
            intensity: 0.5,
            ..Light::default()
        }
    );
    s.apply_override("hair.0.generator={ style = \"fur\", strands = 10 }")
        .unwrap();
    assert_eq!(s.hair[0].generator.as_ref().unwrap().style, "fur");
}

#[test]
fn bad_overrides_are_errors_that_name_them_and_change_nothing() {
    let original = parse("[[hair]]\ngenerator = { style = \"wavy\" }\n").unwrap();
    let cases = [
        ("camera.fov=35", "`fov`"),
        ("light.0.intensty=2", "`intensty`"),
        ("hair.0.material.shine=1", "`shine`"),
        ("camera.near=-1", "camera.near"),
        ("camera.near=close", "string"),
        ("hair.0.generator.style=mohawk", "mohawk"),
        ("light.9.intensity=1", "out of range"),
        ("camera.fov_y_deg.x=1", "not a table"),
        ("nonsense", "key=value"),
        ("strandz.k=1", "`strandz`"),
    ];
    for (set, needle) in cases {
        let mut s = original.clone();
        let m = message(s.apply_override(set).unwrap_err());
        assert!(m.starts_with(&format!("--set `{set}`: ")), "{m}");
        assert!(m.contains(needle), "{set}: {m}");
        assert_eq!(s, original, "{set} changed the scene");
    }
}

#[derive(Debug, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields, default)]
struct StrandSettings {
    k: u32,
    shadow_alpha: f32,
}

#[test]
fn technique_settings_deserialize_with_defaults() {
    let s = parse("[strands]\nk = 16\n").unwrap();
    let settings: StrandSettings = s.technique_settings("strands").unwrap();
    assert_eq!(
        settings,
        StrandSettings {
            k: 16,
            shadow_alpha: 0.0
        }
    );
    let volume: StrandSettings = s.technique_settings("volume").unwrap();
    assert_eq!(volume, StrandSettings::default());
    assert!(s.technique_settings::<StrandSettings>("raytrace").is_err());
}

#[test]
fn technique_settings_errors_name_key_and_line() {
    let text = "technique = \"strands\"\n\n[strands]\nk = 16\nshadow_alfa = 0.5\n";
    let s = parse(text).unwrap();
    let m = message(
        s.technique_settings::<StrandSettings>("strands")
            .unwrap_err(),
    );
    assert!(m.contains("`shadow_alfa`") && m.contains("line 5,"), "{m}");
    // A wrong type too.
    let s = parse("[strands]\n\nk = -3\n").unwrap();
    let m = message(
        s.technique_settings::<StrandSettings>("strands")
            .unwrap_err(),
    );
    assert!(m.contains("line 3,"), "{m}");
}

#[test]
fn technique_settings_errors_from_overrides_name_the_key() {
    let mut s = parse("[strands]\nk = 16\n").unwrap();
    s.apply_override("strands.kk=3").unwrap();
    let m = message(
        s.technique_settings::<StrandSettings>("strands")
            .unwrap_err(),
    );
    assert!(m.contains("`kk`") && !m.contains("line"), "{m}");
}

#[test]
fn toml_round_trip() {
    let mut s = parse(
        "technique = \"volume\"\nlight = []\n[[hair]]\nfiles = [\"x/a.tfx\", \"b.hair\"]\n\
         follow = { count = 3 }\ntransform = { rotate_deg = [0, 90, 0] }\n\
         [[hair]]\ngenerator = { style = \"curly\", seed = 7, length = 12.5 }\n\
         [hair.material]\nthickness = 0.01\n[head]\nradii = [1, 2, 3]\n[volume]\nsteps = 64\n\
         [volume.shadow]\nalpha = 0.5\n",
    )
    .unwrap();
    s.apply_override("satf.layers=[1, 2]").unwrap();
    let text = s.to_toml_string().unwrap();
    let back = parse(&text).unwrap_or_else(|e| panic!("{e}\n{text}"));
    assert_eq!(back, s, "{text}");
    assert!(back.lights.is_empty());
    let back = parse(&Scene::default().to_toml_string().unwrap()).unwrap();
    assert_eq!(back, default_in_base());
}

#[test]
fn generator_fields_default_to_the_style() {
    let s =
        parse("[[hair]]\ngenerator = { style = \"curly\", strands = 12, noise = 0.5 }\n").unwrap();
    let (style, p) = s.hair[0]
        .generator
        .as_ref()
        .unwrap()
        .style_params()
        .unwrap();
    assert_eq!(style, Style::Curly);
    let d = Style::Curly.default_params();
    assert_eq!((p.strands, p.noise), (12, 0.5));
    assert_eq!(
        (p.vertices, p.length, p.curl_radius, p.curl_frequency),
        (d.vertices, d.length, d.curl_radius, d.curl_frequency)
    );
    assert_eq!(
        (p.clumping, p.seed, p.thickness),
        (d.clumping, d.seed, d.thickness)
    );
}

#[test]
fn transform_rotates_about_x_then_y_then_z() {
    let t = Transform {
        translate: Vec3::new(1.0, 2.0, 3.0),
        rotate_deg: Vec3::new(90.0, 0.0, 90.0),
        scale: 2.0,
    };
    // +y: Rx(90°) takes it to +z, Rz(90°) leaves +z; scaled by 2, then translated.
    let p = t.affine().transform_point3(Vec3::Y);
    assert!((p - Vec3::new(1.0, 2.0, 5.0)).length() < 1e-5, "{p}");
    // +x: Rx leaves it, Rz(90°) takes it to +y.
    let p = t.affine().transform_point3(Vec3::X);
    assert!((p - Vec3::new(1.0, 4.0, 3.0)).length() < 1e-5, "{p}");
    assert!(Transform::default().is_identity());
}

#[test]
fn head_source_follows_the_head_table() {
    assert_eq!(
        Scene::default().head_source(),
        HeadSource::Generated(GeneratedHead {
            head: Head::default(),
            shape: HeadShape::Face,
            placement: glam::Affine3A::IDENTITY
        })
    );
    let fur = parse("[[hair]]\ngenerator = { style = \"fur\" }\n").unwrap();
    assert_eq!(
        fur.head_source(),
        HeadSource::Generated(GeneratedHead {
            head: head_for(Style::Fur),
            shape: HeadShape::Ellipsoid,
            placement: glam::Affine3A::IDENTITY
        })
    );
    let sized = parse("[head]\nradii = [1, 2, 3]\n").unwrap();
    let HeadSource::Generated(GeneratedHead { head: h, .. }) = sized.head_source() else {
        panic!()
    };
    assert_eq!(
        (h.center, h.radii),
        (Head::default().center, Vec3::new(1.0, 2.0, 3.0))
    );
    // `shape` overrides the style's; an unknown one is an error naming the key.
    let bare =
        parse("[[hair]]\ngenerator = { style = \"straight\" }\n[head]\nshape = \"ellipsoid\"\n")
            .unwrap();
    assert!(matches!(
        bare.head_source(),
        HeadSource::Generated(GeneratedHead {
            shape: HeadShape::Ellipsoid,
            ..
        })
    ));
    let err = parse("[head]\nshape = \"sphere\"\n")
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("head.shape") && err.contains("sphere"),
        "{err}"
    );
    let obj = parse("[head]\nobj = \"meshes/head.obj\"\n").unwrap();
    assert_eq!(
        obj.head_source(),
        HeadSource::Obj(PathBuf::from("base/meshes/head.obj"))
    );
    let none = parse("[head]\ngenerated = false\n").unwrap();
    assert_eq!(none.head_source(), HeadSource::None);
}

#[test]
fn material_converts_to_shading_parameters() {
    let m = Material::default();
    let h = m.hair_lighting();
    assert_eq!(h.diffuse_color, Vec3::ONE);
    assert_eq!(
        (h.primary_exponent, h.secondary_shift),
        (m.primary_exponent, m.secondary_shift)
    );
    let kk = m.kajiya_kay();
    assert_eq!(
        (kk.diffuse, kk.specular, kk.exponent),
        (m.base_color, m.primary_color, m.primary_exponent)
    );
}

#[test]
fn follow_radius_in_world_units_or_times_the_spacing() {
    use tress_hair::{FollowMode, FollowParams, FollowRadius};
    let follow = |text: &str| -> Result<FollowParams, SceneError> {
        let s = parse(&format!(
            "[[hair]]\ngenerator = {{ style = \"straight\" }}\nfollow = {{ {text} }}\n"
        ))?;
        Ok(s.hair[0].follow.as_ref().unwrap().into())
    };
    let p = follow("count = 2, mode = \"offset\", root_radius = \"0.6x\"").unwrap();
    assert_eq!(
        (p.count, p.mode, p.root_radius),
        (2, FollowMode::Offset, FollowRadius::Spacing(0.6))
    );
    let p = follow("count = 1, root_radius = 0.25").unwrap();
    assert_eq!(
        (p.mode, p.root_radius),
        (FollowMode::Interpolate, FollowRadius::World(0.25))
    );
    assert_eq!(
        follow("count = 1").unwrap(),
        FollowParams {
            count: 1,
            ..Default::default()
        }
    );
    for bad in [
        "mode = \"clump\"",
        "root_radius = \"big\"",
        "root_radius = -1.0",
    ] {
        let e = message(follow(bad).unwrap_err());
        assert!(
            e.contains("follow") || e.contains("radius") || e.contains("mode"),
            "{bad}: {e}"
        );
    }
    // Written back as it was given.
    let mut s =
        parse("[[hair]]\nfiles = [\"a.hair\"]\nfollow = { root_radius = \"0.5x\" }\n").unwrap();
    s.base_dir = PathBuf::from("base");
    let text = s.to_toml_string().unwrap();
    assert!(text.contains("root_radius = \"0.5x\""), "{text}");
    assert_eq!(parse(&text).unwrap(), s);
}

/// Where `p` lies relative to the ellipsoid `head`: 1 on its surface (the norm of the point in
/// the unit sphere the ellipsoid is stretched from).
fn ellipsoid_radius(head: &Head, p: Vec3) -> f32 {
    ((p - head.center) / head.radii).length()
}

#[test]
fn a_hair_transform_moves_the_generated_head_with_its_hair() {
    let style =
        "[[hair]]\ngenerator = { style = \"fur\", strands = 300, vertices = 4, seed = 2 }\n";
    let moved = format!(
        "{style}transform = {{ translate = [0.3, -1.0, 2.0], rotate_deg = [10.0, 90.0, 20.0], scale = 2.0 }}\n"
    );
    for (text, identity) in [(style.to_string(), true), (moved, false)] {
        let scene = parse(&text).unwrap();
        let HeadSource::Generated(g) = scene.head_source() else {
            panic!("generated head expected")
        };
        assert_eq!(g.placement == glam::Affine3A::IDENTITY, identity);
        // The fur's roots grow on its ellipsoid; moved with the hair, they stay on the placed
        // head: mapped back by the placement, each lies on the unplaced ellipsoid.
        let hair = &scene.load_hair().unwrap()[0];
        let back = g.placement.inverse();
        for s in 0..hair.strand_count() {
            let root = back.transform_point3(hair.strand(s)[0]);
            let r = ellipsoid_radius(&g.head, root);
            assert!((r - 1.0).abs() < 0.02, "strand {s}: root at {r} head radii");
        }
        // And the mesh drawn is the placed one: its vertices map back onto the ellipsoid.
        let mesh = g.mesh(16);
        let unplaced = g.shape.mesh(&g.head, 16);
        for (p, q) in mesh.positions.iter().zip(&unplaced.positions) {
            assert!(back.transform_point3(*p).distance(*q) < 1e-4);
        }
        assert!(
            g.center()
                .distance(g.placement.transform_point3(g.head.center))
                < 1e-6
        );
        if !identity {
            assert!(g.center().distance(g.head.center) > 1.0, "the head moved");
        }
    }
}

#[test]
fn each_hair_entry_may_name_its_own_technique() {
    let text = "technique = \"volume\"\n\
                [[hair]]\ngenerator = { style = \"straight\" }\ntechnique = \"strands\"\n\
                [[hair]]\ngenerator = { style = \"fur\" }\n\
                [[hair]]\ngenerator = { style = \"curly\" }\ntechnique = \"auto\"\n";
    let s = parse(text).unwrap();
    let kinds: Vec<_> = (0..3).map(|i| s.hair_technique(i).unwrap()).collect();
    assert_eq!(
        kinds,
        [
            TechniqueKind::Strands,
            TechniqueKind::Volume,
            TechniqueKind::Auto
        ]
    );
    // Patches and SATF draw the whole scene, merged: the entries' own techniques do not apply.
    let mut patches = s.clone();
    patches.apply_override("technique=patches").unwrap();
    assert_eq!(patches.hair_technique(0).unwrap(), TechniqueKind::Patches);
    // Forcing a technique drops the entries' own, and round-trips through TOML.
    let mut forced = s.clone();
    forced.force_technique("hybrid").unwrap();
    assert!(forced.hair.iter().all(|h| h.technique.is_none()));
    assert!((0..3).all(|i| forced.hair_technique(i) == Ok(TechniqueKind::Hybrid)));
    assert!(forced.force_technique("raytrace").is_err());
    assert_eq!(forced.technique, "hybrid", "unchanged by a failed force");
    let back = parse(&s.to_toml_string().unwrap()).unwrap();
    assert_eq!(back.hair[0].technique.as_deref(), Some("strands"));
    // A scene-wide technique or an unknown name is an error naming the entry's key.
    for (bad, why) in [
        ("patches", "whole scene"),
        ("raytrace", "unknown technique"),
    ] {
        let e = parse(&format!(
            "[[hair]]\ngenerator = {{ style = \"fur\" }}\ntechnique = \"{bad}\"\n"
        ))
        .unwrap_err()
        .to_string();
        assert!(e.contains("hair.0.technique") && e.contains(why), "{e}");
    }
}

#[test]
fn every_generated_character_gets_its_own_head() {
    let text = "[[hair]]\ngenerator = { style = \"ponytail\" }\n\
                [[hair]]\ngenerator = { style = \"ponytail\" }\n\
                transform = { translate = [40, 0, -30] }\n\
                [[hair]]\ngenerator = { style = \"fur\" }\n\
                transform = { translate = [-40, 0, -60] }\n\
                [[hair]]\ngenerator = { style = \"straight\" }\n";
    let s = parse(text).unwrap();
    let heads = s.generated_heads();
    // The fourth entry grows on the first one's head (same style head, same place).
    assert_eq!(heads.len(), 3, "{heads:?}");
    let HeadSource::Generated(first) = s.head_source() else {
        panic!("a generated head")
    };
    assert_eq!(heads[0], first);
    assert_eq!(
        heads[1].center(),
        first.center() + Vec3::new(40.0, 0.0, -30.0)
    );
    assert_eq!(heads[2].shape, HeadShape::Ellipsoid, "the fur's body");
    assert_eq!(heads[2].head, head_for(Style::Fur));
    // An OBJ head or no head: none generated.
    let obj = parse(&format!("{text}[head]\nobj = \"head.obj\"\n")).unwrap();
    assert!(obj.generated_heads().is_empty());
}

/// The `[simulation]` and `[simulation.wind]` block of `doc/defaults.toml`, uncommented, is
/// exactly `SimSettings::default()`: the documented defaults cannot drift from the code's.
#[test]
fn documented_simulation_defaults_are_the_codes() {
    let doc = include_str!("../doc/defaults.toml");
    let start = doc.find("# [simulation]").expect("a [simulation] block");
    let text: String = doc[start..]
        .lines()
        .map_while(|l| l.strip_prefix("# "))
        .map(|l| format!("{l}\n"))
        .collect();
    let table: toml::Table = text.parse().expect("the block parses");
    let settings: tress_sim::SimSettings =
        toml::Value::Table(table["simulation"].as_table().unwrap().clone())
            .try_into()
            .expect("the block is valid settings");
    assert_eq!(settings, tress_sim::SimSettings::default());
    // Every key of the settings is documented (a table of defaults serializes every key).
    let all = toml::Value::try_from(tress_sim::SimSettings::default()).unwrap();
    let documented = table["simulation"].as_table().unwrap();
    for key in all.as_table().unwrap().keys() {
        assert!(
            documented.contains_key(key),
            "simulation.{key} is not in doc/defaults.toml"
        );
    }
}
