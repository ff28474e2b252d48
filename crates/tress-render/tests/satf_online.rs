//! The SATF online passes against their CPU definitions, on real clusters and a real (small)
//! database: the index calculation's `Params(b)` and nearest samples (§6.2.1), equation 6 and
//! the re-/α-maps of every HSV against `tress_satf::Database::hsv_maps` (§6.2.2, equation 7),
//! the s-maps against `tress_satf::online::s_maps` (equation 12), and input errors.

mod common;

use std::f32::consts::PI;

use glam::Vec3;
use tress_hair::generate::Head;
use tress_render::satf::SatfSettings;
use tress_render::{
    COLOR_FORMAT, Camera, DirectionalLight, OffscreenTargets, RenderError, SatfDatabase,
    SatfFrameInputs, SatfGeometry, SatfRenderer, SharedInputs, TargetFormats,
};
use tress_satf::database::{BakeSettings, Database, bake, is_uniform, params_distance};
use tress_satf::generate::{ClusterStyle, generate_clusters};
use tress_satf::hrir::{self, HrirSettings};
use tress_satf::online::{self, ShadowApprox};
use tress_satf::{HairVolume, shell};

fn small_db(pixels: u32) -> Database {
    let s = BakeSettings {
        samples: 48,
        hrir: HrirSettings {
            pixels,
            view_angles: 8,
            light_angles: 6,
            ..Default::default()
        },
        ..Default::default()
    };
    bake(&s, |_, _| {}).expect("bake")
}

fn volume() -> HairVolume {
    let style = ClusterStyle {
        macro_clusters: 2,
        clusters_per_macro: 2,
        strands_per_cluster: 70,
        samples: 10,
        ..Default::default()
    };
    generate_clusters(&Head::default(), &style).expect("clusters")
}

fn settings() -> SatfSettings {
    SatfSettings {
        k_shadow: 0.9,
        // Sparse test clusters: sectors differ by about 1 in equation 6's norm; this threshold
        // makes both outcomes occur.
        lookup: tress_render::satf::LookupSettings {
            k_threshold: 1.0,
            ..Default::default()
        },
        ..common::small_satf_settings()
    }
}

fn camera(size: u32) -> Camera {
    Camera::look_at(
        Vec3::new(30.0, 10.0, 45.0),
        Vec3::new(0.0, -5.0, 0.0),
        Vec3::Y,
        0.8,
        1.0,
        200.0,
        [size, size],
    )
}

fn light() -> DirectionalLight {
    DirectionalLight {
        direction: Vec3::new(-0.4, -0.8, -0.3),
        color: Vec3::ONE,
        intensity: 1.5,
    }
}

/// Whether `theta` lies within `margin` bins of the boundary between two of `count` bins.
fn near_bin_edge(theta: f32, count: u32, margin: f32) -> bool {
    let x = (theta + PI) / (2.0 * PI) * count as f32;
    (x - x.floor() - 0.5).abs() < margin
}

#[test]
fn index_calculation_maps_and_s_maps_match_the_cpu() {
    let Some(ctx) = common::gpu() else {
        return;
    };
    let cpu_db = small_db(6);
    let settings = settings();
    let sampling = settings.sampling;
    let vol = volume();
    let db = SatfDatabase::new(&ctx, &cpu_db).expect("database");
    let geometry = SatfGeometry::new(&ctx, &vol, &db, &settings).expect("geometry");
    let mut r = SatfRenderer::new(&ctx, TargetFormats::default(), settings).expect("renderer");
    let size = 32;
    let t = OffscreenTargets::new(&ctx, [size, size], COLOR_FORMAT).expect("targets");
    let lights = [light()];
    let cam = camera(size);
    let stats = r
        .render(
            &ctx,
            &t.targets(),
            &SatfFrameInputs {
                shared: SharedInputs {
                    camera: cam,
                    lights: &lights,
                    ambient: Vec3::splat(0.1),
                    head: None,
                    clear: Some(wgpu::Color::BLACK),
                },
                head_color: Vec3::ONE,
                clusters: Some(&geometry),
                database: &db,
            },
        )
        .expect("frame");
    let back = geometry.read_back(&ctx).expect("read back");
    let layers = sampling.layers();
    assert_eq!(stats.clusters, 4);
    assert_eq!(stats.hsvs as usize, 4 * sampling.hsv_count());
    assert_eq!(back.hsvs.len(), stats.hsvs as usize);
    assert_eq!(stats.uniform_hsvs + stats.interpolated_hsvs, stats.hsvs);
    let uniform_gpu = back.hsvs.iter().filter(|h| h.uniform == 1).count() as u32;
    assert_eq!(uniform_gpu, stats.uniform_hsvs);

    let lookup = settings.lookup;
    let h = cpu_db.settings().hrir;
    let to_light = light().to_light().expect("light");
    let eye = cam.eye();
    let [tile_w, tile_h] = geometry.tile_size();
    assert_eq!([tile_w, tile_h], [sampling.su * 6, sampling.st * 3]);
    let (mut compared, mut skipped, mut uniform_seen) = (0, 0, [false; 2]);
    for (ci, (g, c)) in vol.clusters().enumerate() {
        // ---- Params(b) of every boundary sector (§6.2.1)
        let features = shell::cluster_features(c, &sampling, &cpu_db.settings().density);
        let base = ci * sampling.sector_count();
        let mut params = Vec::new();
        for i in 0..=sampling.st {
            for layer in 0..layers {
                for m in 0..sampling.su {
                    let k = sampling.sector_index(i, layer, m);
                    let s = c.sector_surface(g, &sampling, i, layer, m);
                    let p = online::sector_params(
                        features[k],
                        &s,
                        (eye - s.position).normalize(),
                        to_light,
                    );
                    let gpu = back.sector_params[base + k];
                    assert_eq!(gpu.features, p.features, "sector {k}: features");
                    assert!(
                        (gpu.theta_v - p.theta_v).abs() < 1e-4
                            && (gpu.theta_l - p.theta_l).abs() < 1e-4,
                        "sector {k}: azimuths GPU ({}, {}) CPU ({}, {})",
                        gpu.theta_v,
                        gpu.theta_l,
                        p.theta_v,
                        p.theta_l
                    );
                    assert_eq!(
                        gpu.sample as usize,
                        cpu_db.nearest_sample(p.features, lookup.feature_weights),
                        "sector {k}: nearest sample"
                    );
                    params.push(p);
                }
            }
        }
        // ---- every HSV: equation 6, then its maps by sweep or equation 7 (§6.2.2)
        for i in 0..sampling.st {
            for layer in 0..layers {
                for m in 0..sampling.su {
                    let (top, bottom) = sampling.hsv_sectors(i, layer, m);
                    let (a, b) = (params[top], params[bottom]);
                    let hsv = ci * sampling.hsv_count()
                        + ((i * layers + layer) * sampling.su + m) as usize;
                    let ave = tress_satf::database::average_params(&a, &b);
                    let edgy = [a, b, ave].iter().any(|p| {
                        near_bin_edge(p.theta_v, h.view_angles, 1e-3)
                            || near_bin_edge(p.theta_l, h.light_angles, 1e-3)
                    });
                    if edgy || (params_distance(&a, &b, &lookup) - lookup.k_threshold).abs() < 1e-4
                    {
                        skipped += 1;
                        continue;
                    }
                    let uniform = is_uniform(&a, &b, &lookup);
                    assert_eq!(
                        back.hsvs[hsv].uniform == 1,
                        uniform,
                        "HSV {hsv}: equation 6"
                    );
                    uniform_seen[usize::from(uniform)] = true;
                    let cpu = cpu_db.hsv_maps(&a, &b, 3, &lookup);
                    for row in 0..3 {
                        for j in 0..h.pixels {
                            let [x, y] = geometry.atlas_texel(
                                ci as u32,
                                layer,
                                m * h.pixels + j,
                                i * 3 + row,
                            );
                            let px = back.maps.get(x, y).expect("texel");
                            let idx = (row * h.pixels + j) as usize;
                            let alpha = cpu.alpha[idx];
                            let re = hrir::straight_reflectance(cpu.re[idx], alpha);
                            assert!(
                                (px[1] - alpha).abs() < 2e-3 && (px[0] - re).abs() < 3e-3,
                                "HSV {hsv} row {row} pixel {j}: GPU (re {}, α {}) CPU (re {re}, α {alpha})",
                                px[0],
                                px[1]
                            );
                        }
                    }
                    compared += 1;
                }
            }
        }
        // ---- equation 12 at every texel: τ_k from the α-maps of the layers outside k
        for y in 0..tile_h {
            for x in 0..tile_w {
                let alphas: Vec<f32> = (0..layers)
                    .map(|k| {
                        let [ax, ay] = geometry.atlas_texel(ci as u32, k, x, y);
                        back.maps.get(ax, ay).expect("texel")[1]
                    })
                    .collect();
                let cpu = online::s_maps(&alphas, settings.k_shadow, ShadowApprox::Exponential);
                for k in 0..layers {
                    let [ax, ay] = geometry.atlas_texel(ci as u32, k, x, y);
                    let tau = back.s_map.get(ax, ay).expect("texel")[0];
                    assert!(
                        (tau - cpu[k as usize]).abs() < 2e-3,
                        "cluster {ci} layer {k} texel ({x}, {y}): τ GPU {tau} CPU {}",
                        cpu[k as usize]
                    );
                }
            }
        }
    }
    assert!(
        compared > 10 * skipped,
        "{compared} HSVs compared, {skipped} skipped at bin edges"
    );
    assert!(
        uniform_seen[0] && uniform_seen[1],
        "both outcomes of equation 6 occur: {} of {} uniform",
        stats.uniform_hsvs,
        stats.hsvs
    );
}

#[test]
fn inputs_are_checked() {
    let Some(ctx) = common::gpu() else {
        return;
    };
    let settings = settings();
    let db6 = SatfDatabase::new(&ctx, &small_db(6)).expect("database");
    let db4 = SatfDatabase::new(&ctx, &small_db(4)).expect("database");
    let geometry = SatfGeometry::new(&ctx, &volume(), &db6, &settings).expect("geometry");
    let mut r = SatfRenderer::new(&ctx, TargetFormats::default(), settings).expect("renderer");
    let t = OffscreenTargets::new(&ctx, [16, 16], COLOR_FORMAT).expect("targets");
    let lights = [light(); 5];
    let inputs = SatfFrameInputs {
        shared: SharedInputs {
            camera: camera(16),
            lights: &lights[..1],
            ambient: Vec3::ZERO,
            head: None,
            clear: None,
        },
        head_color: Vec3::ONE,
        clusters: Some(&geometry),
        database: &db4,
    };
    // Clusters prepared for another database layout.
    let err = r.render(&ctx, &t.targets(), &inputs).unwrap_err();
    assert!(
        matches!(err, RenderError::Invalid(_)) && err.to_string().contains("pixels"),
        "{err}"
    );
    // Too many lights, a camera of another size.
    let err = r
        .render(
            &ctx,
            &t.targets(),
            &SatfFrameInputs {
                shared: SharedInputs {
                    lights: &lights,
                    ..inputs.shared
                },
                database: &db6,
                ..inputs
            },
        )
        .unwrap_err();
    assert!(err.to_string().contains("lights"), "{err}");
    let err = r
        .render(
            &ctx,
            &t.targets(),
            &SatfFrameInputs {
                shared: SharedInputs {
                    camera: camera(8),
                    ..inputs.shared
                },
                database: &db6,
                ..inputs
            },
        )
        .unwrap_err();
    assert!(matches!(err, RenderError::Target(_)), "{err}");
    // Bad settings name the setting.
    let bad = SatfSettings {
        pcf_radius: 99,
        ..settings
    };
    let err = SatfRenderer::new(&ctx, TargetFormats::default(), bad).unwrap_err();
    assert!(err.to_string().contains("pcf_radius"), "{err}");
    // No clusters: the frame is the background, and nothing is counted.
    let stats = r
        .render(
            &ctx,
            &t.targets(),
            &SatfFrameInputs {
                shared: SharedInputs {
                    clear: Some(wgpu::Color::RED),
                    ..inputs.shared
                },
                database: &db6,
                clusters: None,
                ..inputs
            },
        )
        .expect("empty frame");
    assert_eq!((stats.clusters, stats.hsvs, stats.uniform_hsvs), (0, 0, 0));
    let img = tress_render::read_texture(&ctx, &t.color).expect("readback");
    assert_eq!(img.get(3, 3), Some([1.0, 0.0, 0.0, 1.0]));
}
