//! What each key of `[satf]` means, with its default from [`SatfSettings::default`] and the
//! bake's, fit's and generator's own defaults (the scene reference, [`crate::settings_doc`]).
//! Nested tables' keys are dotted (`bake.samples`).

use tress_satf::database::BakeSettings;
use tress_satf::fit::FitSettings;
use tress_satf::generate::ClusterStyle;
use tress_satf::online::ShadowApprox;

use super::{Reflectance, SatfSettings, StageTiming};
use crate::settings_doc::{Absent, SettingDoc, doc};

/// The settings' spellings of the three enumerations (as [`super::scene::satf_settings`] reads
/// them).
fn names(s: &SatfSettings) -> [&'static str; 3] {
    [
        match s.shadow_approx {
            ShadowApprox::Exponential => "exponential",
            ShadowApprox::Linear => "linear",
        },
        match s.reflectance {
            Reflectance::Straight => "straight",
            Reflectance::Premultiplied => "premultiplied",
        },
        match s.stage_timing {
            StageTiming::Timestamps => "timestamps",
            StageTiming::WallClock => "wall_clock",
        },
    ]
}

/// The `[satf]` keys.
pub(crate) fn satf() -> Vec<SettingDoc> {
    let d = SatfSettings::default();
    let (sm, lk, li) = (&d.sampling, &d.lookup, &d.lighting);
    let (b, f, g) = (
        BakeSettings::default(),
        FitSettings::default(),
        ClusterStyle::default(),
    );
    let [shadow_approx, reflectance, stage_timing] = names(&d);
    vec![
        doc(
            "database",
            Absent,
            "the HRIR database file, relative to the scene's folder (baked there when missing); \
             absent: a cache file named by the bake settings",
        ),
        doc(
            "bake.samples",
            b.samples,
            "database bake: random generalized sectors",
        ),
        doc(
            "bake.angles",
            b.hrir.view_angles,
            "both `view_angles` and `light_angles`",
        ),
        doc(
            "bake.view_angles",
            b.hrir.view_angles,
            "view azimuth bins over the full circle",
        ),
        doc(
            "bake.light_angles",
            b.hrir.light_angles,
            "light azimuth bins over the full circle",
        ),
        doc(
            "bake.pixels",
            b.hrir.pixels,
            "samples of each HRIR along `s`",
        ),
        doc("bake.seed", b.seed, "random seed"),
        doc(
            "bake.max_strands",
            b.max_strands,
            "most strands in a random sector",
        ),
        doc(
            "clusters",
            "auto",
            "`\"fit\"`: clusters fitted to the scene's strands; `\"generate\"`: a clustered style \
             on the generated head; `\"auto\"`: fit when the scene has hair",
        ),
        doc(
            "fit.strands_per_cluster",
            f.strands_per_cluster,
            "fit: largest group of strands per cluster",
        ),
        doc(
            "fit.grouping_samples",
            f.grouping_samples,
            "points per strand used for grouping (1: roots only)",
        ),
        doc(
            "fit.fit_samples",
            f.fit_samples,
            "points per strand after resampling",
        ),
        doc(
            "fit.control_points",
            f.control_points,
            "control points of the trajectory",
        ),
        doc(
            "fit.profile_control_points",
            f.profile_control_points,
            "control points of `A`, `B` and `q`",
        ),
        doc(
            "fit.profile_bins",
            f.profile_bins,
            "bins along `t` for the ellipse fit",
        ),
        doc(
            "fit.axis_quantile",
            f.axis_quantile,
            "share of the points inside the fitted ellipse",
        ),
        doc(
            "fit.min_radius",
            f.min_radius,
            "smallest half-axis (world units); absent: a fixed share of the diagonal of the \
             hair's box",
        ),
        doc(
            "fit.stray_split",
            f.stray_split,
            "split a group while some point of its shell lies farther from every strand than this \
             share of the cross-section's larger half-axis (0: never); a group under 8 strands is \
             split, down to single strands, only where its shell lies over 20 minimum half-axes \
             from every strand",
        ),
        doc(
            "fit.max_clusters",
            f.max_clusters,
            "most clusters the stray split makes",
        ),
        doc(
            "generate.macro_clusters",
            g.macro_clusters,
            "generated style: distinct cluster geometries",
        ),
        doc(
            "generate.clusters_per_macro",
            g.clusters_per_macro,
            "placements of each geometry",
        ),
        doc(
            "generate.strands_per_cluster",
            g.strands_per_cluster,
            "strands per cluster",
        ),
        doc("generate.length", g.length, "trajectory length"),
        doc(
            "generate.root_radius",
            g.root_radius,
            "half-axis `A` at the root",
        ),
        doc(
            "generate.tip_radius",
            g.tip_radius,
            "half-axis `A` at the tip",
        ),
        doc("generate.aspect", g.aspect, "`B / A`, in (0, 1]"),
        doc(
            "generate.twist",
            g.twist,
            "turns of the twist `q` from root to tip",
        ),
        doc(
            "generate.strand_jitter",
            g.strand_jitter,
            "largest drift of a strand in `v` from root to tip",
        ),
        doc("generate.samples", g.samples, "samples per strand"),
        doc("generate.seed", g.seed, "random seed"),
        doc("st", sm.st, "equation 3: `s_t`, steps along the trajectory"),
        doc("sv", sm.sv, "equation 3: `s_v`, radial steps (rings)"),
        doc("su", sm.su, "equation 3: `s_u`, sectors per ring"),
        doc(
            "core_rings",
            sm.core_rings,
            "innermost rings that form the transparent core",
        ),
        doc("map_rows", d.map_rows, "map rows per HSV"),
        doc("mesh_t", d.mesh_t, "layer mesh quads per HSV along `t`"),
        doc("mesh_u", d.mesh_u, "layer mesh quads per sector around `u`"),
        doc(
            "feature_weights",
            lk.feature_weights,
            "weights of `(ρ_st, ρ_s, ρ_t)` in the feature distance",
        ),
        doc(
            "angle_weight",
            lk.angle_weight,
            "per radian in equation 6 (16 / 2π)",
        ),
        doc("k_threshold", lk.k_threshold, "equation 6"),
        doc("k_dif", li.k_dif, "equations 8–11: the diffuse coefficient"),
        doc(
            "f_dif",
            li.f_dif,
            "the hair's diffuse color (the first `[[hair]]` material's `base_color` when there is \
             one)",
        ),
        doc("k_spe1", li.k_spe1, "the primary specular coefficient"),
        doc(
            "f_spe1",
            li.f_spe1,
            "the primary highlight's color (the light's, §6.3)",
        ),
        doc(
            "primary_shift",
            li.primary_shift,
            "`s` of equation 10 (toward the tip)",
        ),
        doc("k_spe2", li.k_spe2, "the secondary specular coefficient"),
        doc(
            "f_spe2",
            li.f_spe2,
            "the secondary highlight's color (the hair's, §6.3: the first `[[hair]]` material's \
             `base_color` when there is one)",
        ),
        doc(
            "secondary_shift",
            li.secondary_shift,
            "`s` of equation 11 (toward the root)",
        ),
        doc("k_h", li.k_h, "the specular exponent of both lobes"),
        doc("k_shadow", d.k_shadow, "equation 12"),
        doc(
            "shadow_approx",
            shadow_approx,
            "equation 12's `\"exponential\"` or `\"linear\"` form",
        ),
        doc(
            "local_shadows",
            d.local_shadows,
            "equation 12's s-maps (off: `τ = 1`)",
        ),
        doc(
            "reflectance",
            reflectance,
            "what the re-maps hold: `\"straight\"` or `\"premultiplied\"`",
        ),
        doc(
            "key_light",
            d.key_light,
            "the light whose azimuth indexes the database",
        ),
        doc(
            "cluster_shadows",
            d.cluster_shadows,
            "shadow maps between clusters",
        ),
        doc(
            "shadow_map_size",
            d.shadow_map_size,
            "shadow map edge in texels",
        ),
        doc(
            "shadow_opacity",
            d.shadow_opacity,
            "light a shadowing cluster blocks",
        ),
        doc(
            "shadow_bias",
            d.shadow_bias,
            "depth bias of the shadow test (world units)",
        ),
        doc("pcf_radius", d.pcf_radius, "PCF kernel radius in texels"),
        doc(
            "stage_timing",
            stage_timing,
            "`\"timestamps\"`, or `\"wall_clock\"` (each stage submitted alone and waited for)",
        ),
    ]
}

#[cfg(test)]
mod tests {
    use super::super::scene::{BakeTable, FitTable, GenerateTable, SatfTable, satf_settings};
    use super::*;
    use crate::settings_doc::introspect::{assert_same_keys, fields, flatten};
    use tress_scene::Scene;

    #[test]
    fn documented_keys_are_the_tables_keys() {
        let accepted = flatten(
            fields::<SatfTable>(),
            &[
                ("bake", fields::<BakeTable>()),
                ("fit", fields::<FitTable>()),
                ("generate", fields::<GenerateTable>()),
            ],
        );
        assert_same_keys("satf", &satf(), &accepted);
    }

    #[test]
    fn documented_defaults_read_back_as_the_defaults() {
        let parts = |scene: &Scene| {
            [None, Some(&crate::Material::default())].map(|hair| {
                let s = satf_settings(scene, hair).unwrap();
                (s.settings, s.bake, s.clusters, s.database)
            })
        };
        let defaults = parts(&Scene::from_str("", ".").unwrap());
        for d in satf() {
            let Some(v) = &d.default else { continue };
            let scene = Scene::from_str(&format!("[satf]\n{} = {v}\n", d.key), ".").unwrap();
            let got = parts(&scene);
            if matches!(d.key, "f_dif" | "f_spe2") {
                // The hair's colour gives way to the key.
                assert_eq!(got[0], defaults[0], "satf.{}", d.key);
            } else {
                assert_eq!(got, defaults, "satf.{}", d.key);
            }
        }
    }
}
