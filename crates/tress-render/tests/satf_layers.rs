//! SATF's screen stages against equation 14: two copies of one cluster at known depths along the
//! view line (no shadows between clusters, the light across the line so neither can shadow the
//! other). Each copy is drawn alone over black and over white, which gives its colour and
//! coverage per pixel; the frame with both must equal `tress_satf::online::blend_layers` of the
//! two, the far copy innermost, whatever order the clusters are listed in.

mod common;

use glam::{Affine3A, Vec3};
use tress_hair::generate::Head;
use tress_render::satf::SatfSettings;
use tress_render::{
    COLOR_FORMAT, Camera, DirectionalLight, GpuContext, LinearImage, OffscreenTargets,
    SatfDatabase, SatfFrameInputs, SatfGeometry, SatfRenderer, SharedInputs, TargetFormats,
    read_texture,
};
use tress_satf::generate::{ClusterStyle, generate_clusters};
use tress_satf::online::blend_layers;
use tress_satf::{Cluster, HairVolume, MacroCluster};

const SIZE: u32 = 64;

/// One generated cluster, as the template of both copies.
fn template() -> MacroCluster {
    let style = ClusterStyle {
        macro_clusters: 1,
        clusters_per_macro: 1,
        strands_per_cluster: 80,
        samples: 10,
        ..Default::default()
    };
    let volume = generate_clusters(&Head::default(), &style).expect("clusters");
    volume
        .macro_clusters
        .into_iter()
        .next()
        .expect("one macro-cluster")
}

/// The template's clusters moved by `offsets`, in that order, in one volume.
fn copies(template: &MacroCluster, offsets: &[Vec3]) -> HairVolume {
    let c = &template.clusters[0];
    let clusters = offsets
        .iter()
        .map(|o| {
            Cluster::new(
                Affine3A::from_translation(*o) * c.transform(),
                c.strands().to_vec(),
            )
            .expect("cluster")
        })
        .collect();
    HairVolume {
        macro_clusters: vec![MacroCluster {
            geometry: template.geometry.clone(),
            clusters,
        }],
        ..Default::default()
    }
}

/// Centre, half-length and direction of the template's axis (sampled along its arc length), and
/// the largest distance of its surface from the axis.
fn axis_bounds(template: &MacroCluster) -> (Vec3, f32, Vec3, f32) {
    let (c, g) = (&template.clusters[0], &template.geometry);
    let ts: Vec<f32> = (0..=16).map(|i| i as f32 / 16.0).collect();
    let points: Vec<Vec3> = ts.iter().map(|&t| c.point(g, t, 0.0, 0.0)).collect();
    let center = points.iter().copied().sum::<Vec3>() / points.len() as f32;
    let half = points
        .iter()
        .map(|p| p.distance(center))
        .fold(0.0, f32::max);
    let axis = (points[16] - points[0]).normalize();
    let mut thick = 0.0f32;
    for (&t, p) in ts.iter().zip(&points) {
        for k in 0..8 {
            thick = thick.max(c.point(g, t, 1.0, k as f32 / 8.0).distance(*p));
        }
    }
    (center, half, axis, thick)
}

struct Stage {
    ctx: GpuContext,
    db: SatfDatabase,
    settings: SatfSettings,
    camera: Camera,
    lights: [DirectionalLight; 1],
}

impl Stage {
    /// `volume` drawn over a black and a white background.
    fn draw(&self, volume: &HairVolume) -> (LinearImage, LinearImage) {
        let geometry =
            SatfGeometry::new(&self.ctx, volume, &self.db, &self.settings).expect("geometry");
        let mut r = SatfRenderer::new(&self.ctx, TargetFormats::default(), self.settings)
            .expect("renderer");
        let t = OffscreenTargets::new(&self.ctx, [SIZE, SIZE], COLOR_FORMAT).expect("targets");
        let mut frame = |clear| {
            r.render(
                &self.ctx,
                &t.targets(),
                &SatfFrameInputs {
                    shared: SharedInputs {
                        camera: self.camera,
                        lights: &self.lights,
                        ambient: Vec3::splat(0.1),
                        head: None,
                        clear: Some(clear),
                    },
                    head_color: Vec3::ONE,
                    clusters: Some(&geometry),
                    database: &self.db,
                },
            )
            .expect("frame");
            read_texture(&self.ctx, &t.color).expect("read back")
        };
        (frame(wgpu::Color::BLACK), frame(wgpu::Color::WHITE))
    }
}

/// Colour (straight) and coverage of a layer drawn over black (`b`) and white (`w`).
fn layer(b: [f32; 4], w: [f32; 4]) -> (Vec3, f32) {
    let (b, w) = (Vec3::new(b[0], b[1], b[2]), Vec3::new(w[0], w[1], w[2]));
    let alpha = (1.0 - (w - b).element_sum() / 3.0).clamp(0.0, 1.0);
    let color = if alpha > 1e-3 { b / alpha } else { Vec3::ZERO };
    (color, alpha)
}

#[test]
fn two_clusters_at_known_depths_blend_as_equation_14() {
    let Some(ctx) = common::gpu() else {
        return;
    };
    let template = template();
    let (center, half, axis, thick) = axis_bounds(&template);
    // The camera looks across the cluster, down the line through both copies; they sit two
    // cluster thicknesses in front of and behind the template, so their depth ranges do not
    // overlap.
    let view = axis.cross(Vec3::new(0.3, 0.2, 1.0)).normalize();
    let (near, far) = (view * 2.0 * thick, -view * 2.0 * thick);
    let up = axis;
    let camera = Camera::look_at(
        center + view * 2.5 * half,
        center,
        up,
        0.9,
        0.05 * half,
        20.0 * half,
        [SIZE, SIZE],
    );
    let across = view.cross(up).normalize();
    let stage = Stage {
        db: SatfDatabase::new(&ctx, &common::small_satf_database(48)).expect("database"),
        ctx,
        settings: SatfSettings {
            cluster_shadows: false,
            ..common::small_satf_settings()
        },
        camera,
        lights: [DirectionalLight {
            direction: (-across - 0.2 * up).normalize(),
            color: Vec3::ONE,
            intensity: 1.5,
        }],
    };

    let (near_b, near_w) = stage.draw(&copies(&template, &[near]));
    let (far_b, far_w) = stage.draw(&copies(&template, &[far]));
    for order in [[near, far], [far, near]] {
        let (both_b, both_w) = stage.draw(&copies(&template, &order));
        let (mut overlap, mut worst, mut sum) = (0usize, 0.0f32, 0.0f32);
        let n = (SIZE * SIZE) as usize;
        for i in 0..n {
            let f = layer(far_b.pixels[i], far_w.pixels[i]);
            let m = layer(near_b.pixels[i], near_w.pixels[i]);
            if f.1 > 0.1 && m.1 > 0.1 && m.1 < 0.9 {
                overlap += 1;
            }
            for (bg, got) in [
                (Vec3::ZERO, both_b.pixels[i]),
                (Vec3::ONE, both_w.pixels[i]),
            ] {
                // Equation 14 with the far copy innermost.
                let expected = blend_layers(bg, &[f, m]);
                let e = (Vec3::new(got[0], got[1], got[2]) - expected)
                    .abs()
                    .max_element();
                worst = worst.max(e);
                sum += e;
            }
        }
        let mean = sum / (2 * n) as f32;
        let seen = |b: &LinearImage, w: &LinearImage, lo: f32, hi: f32| {
            (0..n)
                .filter(|&i| (lo..hi).contains(&layer(b.pixels[i], w.pixels[i]).1))
                .count()
        };
        eprintln!(
            "far: {} covered, {} partly; near: {} covered, {} partly",
            seen(&far_b, &far_w, 0.1, 2.0),
            seen(&far_b, &far_w, 0.1, 0.9),
            seen(&near_b, &near_w, 0.1, 2.0),
            seen(&near_b, &near_w, 0.1, 0.9)
        );
        eprintln!(
            "clusters listed {}: {overlap} pixels where both are partly seen; error mean {mean:.5}, max {worst:.4}",
            if order[0] == near {
                "near first"
            } else {
                "far first"
            }
        );
        assert!(
            overlap >= 20,
            "the copies must overlap on screen ({overlap} pixels)"
        );
        assert!(mean < 5e-4 && worst < 0.01, "mean {mean}, max {worst}");
    }
}
