//! From a [`Scene`] to the SATF technique's inputs: the `[satf]` table ([`satf_settings`]) and
//! the clusters ([`load_clusters`]).
//!
//! Settings start from [`SatfSettings::default`], take the first `[[hair]]` entry's base color as
//! the hair color (`f_dif`, and `f_speII`, which §6.3 says is the hair's color), then every key
//! of `[satf]`. Clusters come from one of two sources (`satf.clusters`):
//!
//! - `"fit"`: `tress_satf::fit::fit_clusters` on the scene's `[[hair]]` assets (merged), so SATF
//!   renders the same hair as the other techniques (`[satf.fit]`);
//! - `"generate"`: `tress_satf::generate::generate_clusters` on the scene's generated head
//!   (`[satf.generate]`);
//! - `"auto"` (default): `"fit"` when the scene has hair, else `"generate"`.
//!
//! The HRIR database is the file `satf.database` (relative to the scene's folder); the CLI bakes
//! it there when it is missing, or into its cache folder when no path is given. `[satf.bake]`
//! gives the settings of such a bake; when any of its keys is set, an existing file must have
//! been baked with exactly those settings (else the error names the first that differs).
//!
//! Every key with its default and meaning: [`crate::settings_reference`]`("satf")`
//! (`tress settings satf`, and the book's SATF chapter).

use std::path::PathBuf;

use glam::{Affine3A, Vec3};
use serde::Deserialize;
use tress_hair::HairAsset;
use tress_hair::generate::Head;
use tress_satf::HairVolume;
use tress_satf::database::BakeSettings;
use tress_satf::fit::{FitSettings, fit_clusters};
use tress_satf::generate::{ClusterStyle, generate_clusters};
use tress_satf::online::ShadowApprox;
use tress_scene::{HeadSource, Scene};

use super::{Reflectance, SatfSettings, StageTiming};
use crate::RenderError;

/// `[satf.bake]`.
#[derive(Deserialize, Default, Debug)]
#[serde(deny_unknown_fields, default)]
pub(super) struct BakeTable {
    samples: Option<u32>,
    angles: Option<u32>,
    view_angles: Option<u32>,
    light_angles: Option<u32>,
    pixels: Option<u32>,
    seed: Option<u64>,
    max_strands: Option<u32>,
}

/// `[satf.fit]`.
#[derive(Deserialize, Default, Debug)]
#[serde(deny_unknown_fields, default)]
pub(super) struct FitTable {
    strands_per_cluster: Option<u32>,
    grouping_samples: Option<u32>,
    fit_samples: Option<u32>,
    control_points: Option<u32>,
    profile_control_points: Option<u32>,
    profile_bins: Option<u32>,
    axis_quantile: Option<f32>,
    min_radius: Option<f32>,
    stray_split: Option<f32>,
    max_clusters: Option<u32>,
}

/// `[satf.generate]`.
#[derive(Deserialize, Default, Debug)]
#[serde(deny_unknown_fields, default)]
pub(super) struct GenerateTable {
    macro_clusters: Option<u32>,
    clusters_per_macro: Option<u32>,
    strands_per_cluster: Option<u32>,
    length: Option<f32>,
    root_radius: Option<f32>,
    tip_radius: Option<f32>,
    aspect: Option<f32>,
    twist: Option<f32>,
    strand_jitter: Option<f32>,
    samples: Option<u32>,
    seed: Option<u64>,
}

/// The `[satf]` table: every key optional, unknown keys are errors naming key and line.
#[derive(Deserialize, Default, Debug)]
#[serde(deny_unknown_fields, default)]
pub(super) struct SatfTable {
    database: Option<PathBuf>,
    bake: BakeTable,
    clusters: Option<String>,
    fit: FitTable,
    generate: GenerateTable,
    st: Option<u32>,
    sv: Option<u32>,
    su: Option<u32>,
    core_rings: Option<u32>,
    map_rows: Option<u32>,
    mesh_t: Option<u32>,
    mesh_u: Option<u32>,
    feature_weights: Option<[f32; 3]>,
    angle_weight: Option<f32>,
    k_threshold: Option<f32>,
    k_dif: Option<f32>,
    f_dif: Option<Vec3>,
    k_spe1: Option<f32>,
    f_spe1: Option<Vec3>,
    primary_shift: Option<f32>,
    k_spe2: Option<f32>,
    f_spe2: Option<Vec3>,
    secondary_shift: Option<f32>,
    k_h: Option<f32>,
    k_shadow: Option<f32>,
    shadow_approx: Option<String>,
    local_shadows: Option<bool>,
    reflectance: Option<String>,
    key_light: Option<u32>,
    cluster_shadows: Option<bool>,
    shadow_map_size: Option<u32>,
    shadow_opacity: Option<f32>,
    shadow_bias: Option<f32>,
    pcf_radius: Option<u32>,
    stage_timing: Option<String>,
}

/// Where the clusters come from (see the module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ClusterSource {
    /// Fit clusters to the scene's strands.
    Fit(FitSettings),
    /// Generate a clustered style on the scene's head.
    Generate(ClusterStyle),
}

/// The SATF technique's part of a scene.
#[derive(Clone, Debug, PartialEq)]
pub struct SatfScene {
    /// Renderer and geometry settings.
    pub settings: SatfSettings,
    /// The database file (resolved against the scene's folder), or `None` for the cache.
    pub database: Option<PathBuf>,
    /// Settings of a bake of the database ([`BakeSettings::default`] with `[satf.bake]`).
    pub bake: BakeSettings,
    /// Whether `[satf.bake]` set any key: then an existing database must match [`Self::bake`].
    pub bake_explicit: bool,
    /// Where the clusters come from (`auto` resolved against the scene's hair).
    pub clusters: ClusterSource,
}

/// An invalid-input error with its message (errors from other crates convert with `?`).
fn invalid(message: impl Into<String>) -> RenderError {
    RenderError::Invalid(message.into())
}

/// The `[satf]` table over the defaults, the colours from `first_hair`, the first character's
/// material (`None` without hair; [`crate::PreparedScene::first_hair`]); see the module docs.
/// Errors name the key.
pub fn satf_settings(
    scene: &Scene,
    first_hair: Option<&crate::Material>,
) -> Result<SatfScene, RenderError> {
    let t: SatfTable = scene.technique_settings("satf")?;
    let mut s = SatfSettings::default();
    if let Some(m) = first_hair {
        s.lighting.f_dif = m.base_color;
        s.lighting.f_spe2 = m.base_color;
    }
    macro_rules! set {
        ($src:expr => $dst:expr, $($f:ident),*) => { $( if let Some(v) = $src.$f { $dst.$f = v; } )* };
    }
    set!(t => s.sampling, st, sv, su, core_rings);
    set!(
        t => s,
        map_rows,
        mesh_t,
        mesh_u,
        k_shadow,
        local_shadows,
        key_light,
        cluster_shadows,
        shadow_map_size,
        shadow_opacity,
        shadow_bias,
        pcf_radius
    );
    set!(t => s.lookup, feature_weights, angle_weight, k_threshold);
    set!(
        t => s.lighting,
        k_dif,
        f_dif,
        k_spe1,
        f_spe1,
        primary_shift,
        k_spe2,
        f_spe2,
        secondary_shift,
        k_h
    );
    if let Some(a) = &t.shadow_approx {
        s.shadow_approx = match a.as_str() {
            "exponential" => ShadowApprox::Exponential,
            "linear" => ShadowApprox::Linear,
            other => {
                return Err(invalid(format!(
                    "satf.shadow_approx must be \"exponential\" or \"linear\", got \"{other}\""
                )));
            }
        };
    }
    if let Some(r) = &t.reflectance {
        s.reflectance = r.parse::<Reflectance>()?;
    }
    if let Some(r) = &t.stage_timing {
        s.stage_timing = r.parse::<StageTiming>()?;
    }
    s.validate()?;

    let b = &t.bake;
    let mut bake = BakeSettings::default();
    set!(b => bake, samples, seed, max_strands);
    if let Some(m) = b.angles {
        bake.hrir.view_angles = m;
        bake.hrir.light_angles = m;
    }
    set!(b => bake.hrir, view_angles, light_angles, pixels);
    bake.validate()
        .map_err(|e| RenderError::setting("satf.bake", e))?;
    let bake_explicit = b.samples.is_some()
        || b.angles.is_some()
        || b.view_angles.is_some()
        || b.light_angles.is_some()
        || b.pixels.is_some()
        || b.seed.is_some()
        || b.max_strands.is_some();

    let mut fit = FitSettings::default();
    let f = &t.fit;
    set!(
        f => fit,
        strands_per_cluster,
        grouping_samples,
        fit_samples,
        control_points,
        profile_control_points,
        profile_bins,
        axis_quantile,
        stray_split,
        max_clusters
    );
    if let Some(r) = f.min_radius {
        fit.min_radius = Some(r);
    }
    fit.validate()
        .map_err(|e| RenderError::setting("satf.fit", e))?;
    let mut style = ClusterStyle::default();
    let g = &t.generate;
    set!(
        g => style,
        macro_clusters,
        clusters_per_macro,
        strands_per_cluster,
        length,
        root_radius,
        tip_radius,
        aspect,
        twist,
        strand_jitter,
        samples,
        seed
    );
    style
        .validate()
        .map_err(|e| RenderError::setting("satf.generate", e))?;
    let clusters = match t.clusters.as_deref().unwrap_or("auto") {
        "fit" => ClusterSource::Fit(fit),
        "generate" => ClusterSource::Generate(style),
        "auto" if first_hair.is_none() => ClusterSource::Generate(style),
        "auto" => ClusterSource::Fit(fit),
        other => {
            return Err(invalid(format!(
                "satf.clusters must be \"auto\", \"fit\" or \"generate\", got \"{other}\""
            )));
        }
    };
    Ok(SatfScene {
        settings: s,
        database: t.database.map(|p| scene.resolve(&p)),
        bake,
        bake_explicit,
        clusters,
    })
}

/// The clusters of a scene: fitted to `hair` (the scene's merged assets) or generated on its
/// head, as `satf.clusters` says.
pub fn load_clusters(
    scene: &Scene,
    satf: &SatfScene,
    hair: Option<&HairAsset>,
) -> Result<HairVolume, RenderError> {
    match satf.clusters {
        ClusterSource::Fit(fit) => {
            let hair = hair.ok_or_else(|| {
                invalid("satf.clusters = \"fit\" needs [[hair]] in the scene (or use \"generate\")")
            })?;
            fit_clusters(hair, &fit).map_err(|e| RenderError::setting("satf: fitting clusters", e))
        }
        ClusterSource::Generate(style) => {
            // Clusters grow on the generated head where it is placed (the default head without
            // one).
            let (head, placement) = match scene.head_source() {
                HeadSource::Generated(g) => (g.head, g.placement),
                _ => (Head::default(), Affine3A::IDENTITY),
            };
            let mut volume = generate_clusters(&head, &style)
                .map_err(|e| RenderError::setting("satf: generating clusters", e))?;
            volume.transform(placement);
            Ok(volume)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The first hair entry's material, as the session prepares it.
    fn first(scene: &Scene) -> Option<crate::Material> {
        let m = &scene.hair.first()?.material;
        Some(crate::scene_setup::hair_material(m).unwrap())
    }

    #[test]
    fn generated_clusters_move_with_the_generated_head() {
        let text = "[[hair]]\ngenerator = { style = \"straight\", strands = 10 }\n\
                    [satf]\nclusters = \"generate\"\n\
                    generate = { macro_clusters = 3, clusters_per_macro = 2, strands_per_cluster = 4 }\n";
        let moved = format!(
            "{text}[hair.transform]\ntranslate = [1.0, 2.0, -3.0]\nrotate_deg = [0.0, 45.0, 0.0]\nscale = 1.5\n"
        );
        let load = |t: &str| {
            let scene = Scene::from_str(t, ".").unwrap();
            let settings = satf_settings(&scene, first(&scene).as_ref()).unwrap();
            let HeadSource::Generated(g) = scene.head_source() else {
                panic!("generated head expected")
            };
            (load_clusters(&scene, &settings, None).unwrap(), g.placement)
        };
        let (rest, identity) = load(text);
        let (placed, placement) = load(&moved);
        assert_eq!(identity, Affine3A::IDENTITY);
        assert_ne!(placement, Affine3A::IDENTITY);
        let pairs: Vec<_> = rest.clusters().zip(placed.clusters()).collect();
        assert_eq!(pairs.len(), 6);
        for ((_, a), (_, b)) in pairs {
            let expected = placement * a.transform();
            assert!(
                b.transform().abs_diff_eq(expected, 1e-5),
                "each cluster is placed by the head's transform"
            );
        }
    }

    #[test]
    fn table_overrides_defaults_and_names_bad_keys() {
        let scene = Scene::from_str(
            "[satf]\nst = 8\nk_shadow = 0.3\nshadow_approx = \"linear\"\n\
             bake = { samples = 64 }\nclusters = \"generate\"\n",
            "/scenes",
        )
        .unwrap();
        let s = satf_settings(&scene, first(&scene).as_ref()).unwrap();
        assert_eq!(s.settings.sampling.st, 8);
        assert_eq!(s.settings.k_shadow, 0.3);
        assert_eq!(s.settings.shadow_approx, ShadowApprox::Linear);
        assert_eq!(s.bake.samples, 64);
        assert!(s.bake_explicit);
        assert!(matches!(s.clusters, ClusterSource::Generate(_)));
        assert_eq!(s.database, None);

        let scene = Scene::from_str("[satf]\ndatabase = \"db.satfdb\"\n", "/scenes").unwrap();
        let s = satf_settings(&scene, first(&scene).as_ref()).unwrap();
        assert_eq!(s.database, Some(PathBuf::from("/scenes/db.satfdb")));
        assert!(!s.bake_explicit);
        // No hair: auto generates.
        assert!(matches!(s.clusters, ClusterSource::Generate(_)));

        let bad = Scene::from_str("\n[satf]\nkk = 1\n", ".").unwrap();
        let err = satf_settings(&bad, first(&bad).as_ref())
            .unwrap_err()
            .to_string();
        assert!(err.contains("kk") && err.contains("line 3"), "{err}");
        let bad = Scene::from_str("[satf]\nmap_rows = 0\n", ".").unwrap();
        assert!(
            satf_settings(&bad, first(&bad).as_ref())
                .unwrap_err()
                .to_string()
                .contains("map_rows")
        );
        let bad = Scene::from_str("[satf]\nclusters = \"x\"\n", ".").unwrap();
        assert!(
            satf_settings(&bad, first(&bad).as_ref())
                .unwrap_err()
                .to_string()
                .contains("satf.clusters")
        );
        let scene = Scene::from_str(
            "[satf]\nclusters = \"fit\"\nfit = { min_radius = 0.002, stray_split = 0.5 }\n",
            ".",
        )
        .unwrap();
        let ClusterSource::Fit(fit) = satf_settings(&scene, first(&scene).as_ref())
            .unwrap()
            .clusters
        else {
            panic!("satf.clusters = \"fit\" fits")
        };
        assert_eq!((fit.min_radius, fit.stray_split), (Some(0.002), 0.5));
        let bad = Scene::from_str("[satf]\nfit = { stray_split = -1 }\n", ".").unwrap();
        assert!(
            satf_settings(&bad, first(&bad).as_ref())
                .unwrap_err()
                .to_string()
                .contains("stray_split")
        );
        let bad = Scene::from_str("[satf]\nbake = { samples = 0 }\n", ".").unwrap();
        assert!(
            satf_settings(&bad, first(&bad).as_ref())
                .unwrap_err()
                .to_string()
                .contains("satf.bake")
        );
    }

    #[test]
    fn hair_color_is_the_diffuse_and_secondary_color() {
        let scene = Scene::from_str(
            "[[hair]]\ngenerator = { style = \"straight\", strands = 10 }\n\
             [hair.material]\nbase_color = [0.5, 0.25, 0.125]\n",
            ".",
        )
        .unwrap();
        let s = satf_settings(&scene, first(&scene).as_ref()).unwrap();
        assert_eq!(s.settings.lighting.f_dif, Vec3::new(0.5, 0.25, 0.125));
        assert_eq!(s.settings.lighting.f_spe2, Vec3::new(0.5, 0.25, 0.125));
        assert!(matches!(s.clusters, ClusterSource::Fit(_)));
    }
}
