//! The whole CPU side end to end, as the GPU online phase will run it: a generated clustered
//! style, written out as strands and fitted back; a small database; per HSV the sector
//! parameters, equation 6 and the maps; per texel equations 8–14.

use glam::Vec3;
use tress_hair::generate::Head;
use tress_satf::database::{BakeSettings, LookupSettings, bake};
use tress_satf::density::DensitySettings;
use tress_satf::fit::{FitSettings, fit_clusters};
use tress_satf::generate::{ClusterStyle, generate_clusters};
use tress_satf::hrir::{HrirSettings, straight_reflectance};
use tress_satf::online::{
    SatfLighting, ShadowApprox, blend_layers, lighting, s_maps, sector_params, shading,
};
use tress_satf::shell::{ShellSampling, cluster_features};

#[test]
fn generate_fit_bake_and_shade() {
    let style = ClusterStyle {
        macro_clusters: 2,
        clusters_per_macro: 2,
        strands_per_cluster: 80,
        ..Default::default()
    };
    let asset = generate_clusters(&Head::default(), &style)
        .unwrap()
        .to_asset()
        .unwrap();
    let volume = fit_clusters(
        &asset,
        &FitSettings {
            strands_per_cluster: 80,
            ..Default::default()
        },
    )
    .unwrap();
    let sampling = ShellSampling {
        st: 6,
        sv: 3,
        su: 6,
        core_rings: 1,
    };
    let stats = volume.stats(&sampling);
    assert_eq!((stats.clusters, stats.strands, stats.layers), (4, 320, 8));

    let settings = BakeSettings {
        samples: 64,
        density: DensitySettings {
            grid_s: 16,
            grid_depth: 8,
            sigma: 0.06,
            ..Default::default()
        },
        hrir: HrirSettings {
            pixels: 8,
            view_angles: 8,
            light_angles: 8,
            ..Default::default()
        },
        ..Default::default()
    };
    let db = bake(&settings, |_, _| {}).unwrap();
    let lookup = LookupSettings::default();
    let light = LightingSetup::default();

    let mut lit_texels = 0;
    for (geometry, cluster) in volume.clusters() {
        let features = cluster_features(cluster, &sampling, &db.settings().density);
        // 80 strands over 2 layers × 6 sectors: some sector holds strands at every section.
        assert!(features.iter().any(|f| f[0] > 0.0));
        for m in 0..sampling.su {
            for i in 0..sampling.st {
                // Per layer, innermost first: the maps of HSV (i, layer, m), texel (row 0, pixel 3).
                let mut alphas = Vec::new();
                let mut colors = Vec::new();
                for layer in 0..sampling.layers() {
                    let (top, bottom) = sampling.hsv_sectors(i, layer, m);
                    let s_top = cluster.sector_surface(geometry, &sampling, i, layer, m);
                    let s_bottom = cluster.sector_surface(geometry, &sampling, i + 1, layer, m);
                    let to_eye = (light.eye - s_top.position).normalize();
                    let to_light = (light.light - s_top.position).normalize();
                    let p_top = sector_params(features[top], &s_top, to_eye, to_light);
                    let p_bottom = sector_params(features[bottom], &s_bottom, to_eye, to_light);
                    let maps = db.hsv_maps(&p_top, &p_bottom, 4, &lookup);
                    assert_eq!(maps.re.len(), 4 * 8);
                    let (re, alpha) = (maps.re[3], maps.alpha[3]);
                    assert!((0.0..=1.0).contains(&alpha) && re <= alpha + 1e-3);
                    let y = lighting(
                        &light.material,
                        s_top.tangent,
                        s_top.normal,
                        to_light,
                        to_eye,
                    );
                    alphas.push(alpha);
                    colors.push((y, straight_reflectance(re, alpha)));
                }
                let taus = s_maps(&alphas, 0.7, ShadowApprox::Exponential);
                let layers: Vec<(Vec3, f32)> = colors
                    .iter()
                    .zip(&taus)
                    .zip(&alphas)
                    .map(|(((y, re), tau), a)| (shading(*y, *re, *tau), *a))
                    .collect();
                let out = blend_layers(Vec3::ZERO, &layers);
                assert!(out.is_finite() && out.min_element() >= 0.0);
                if out.max_element() > 0.0 {
                    lit_texels += 1;
                }
            }
        }
    }
    assert!(lit_texels > 0, "some texel is lit");
}

struct LightingSetup {
    eye: Vec3,
    light: Vec3,
    material: SatfLighting,
}

impl Default for LightingSetup {
    fn default() -> Self {
        LightingSetup {
            eye: Vec3::new(0.0, 0.0, 80.0),
            light: Vec3::new(40.0, 60.0, 60.0),
            material: SatfLighting::default(),
        }
    }
}
