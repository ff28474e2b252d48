//! The volume raymarcher and the hybrid level of detail through `Renderer` (Jansson 2019 §3.3,
//! §3.4, §4): the isosurface stops at the head, empty-space skipping changes nothing, LOD 0 is the
//! strand renderer and LOD 1 the raymarcher exactly, the alpha and dithered transitions mix the
//! two, volume shadows and AO reach the rasterizer, and the frame reports its volume.

mod common;

use glam::Vec3;
use tress_render::{
    COLOR_FORMAT, Camera, DirectionalLight, FrameInputs, FrameStats, GpuContext, HeadGeometry,
    HybridSettings, LinearImage, Material, OffscreenTargets, Renderer, ShadowMode, SharedInputs,
    StrandGeometry, StrandSettings, TargetFormats, TechniqueKind, Timings, Transition, TriMesh,
    VolumeSettings, read_texture,
};

const SIZE: u32 = 96;

fn strands() -> StrandSettings {
    common::sphere_strand_settings()
}

fn volume() -> VolumeSettings {
    VolumeSettings {
        resolution: 48,
        steps: 128,
        ao_radius: 0.1,
        // The strands occlusion model, a thin isosurface and AO on: what these tests measure.
        // The scene's unit is about 10 cm and its 1200 strands are sparse: thick strands make
        // the shadows visible, and 6 strands to the surface (half opaque after 0.75 strands, as
        // the paper's linear `iso = 2` after one) suit them.
        occlusion: tress_render::volume::Occlusion::Strands,
        opacity: tress_render::volume::Opacity::Iso,
        iso: 6.0,
        ao: true,
        strand_width: 0.01,
        ..Default::default()
    }
}

struct Scene {
    ctx: GpuContext,
    renderer: Renderer,
    hair: StrandGeometry,
    head: HeadGeometry,
    targets: OffscreenTargets,
}

fn scene() -> Scene {
    let ctx = common::gpu().expect("checked by the caller");
    let mut renderer = Renderer::new(&ctx, TargetFormats::default(), strands()).expect("renderer");
    renderer
        .set_volume_settings(&ctx, volume())
        .expect("volume settings");
    let hair = renderer
        .upload_hair(&ctx, &common::sphere_hair(1.0, 1200, 12))
        .expect("hair");
    let head = common::sphere_head(&ctx);
    let targets = OffscreenTargets::new(&ctx, [SIZE, SIZE], COLOR_FORMAT).expect("targets");
    Scene {
        ctx,
        renderer,
        hair,
        head,
        targets,
    }
}

fn camera(distance: f32) -> Camera {
    let dir = Vec3::new(2.6, 1.2, 4.4).normalize();
    Camera::look_at(
        dir * distance,
        Vec3::new(0.0, -0.45, 0.0),
        Vec3::Y,
        45f32.to_radians(),
        0.1,
        100.0,
        [SIZE, SIZE],
    )
}

fn key_light() -> DirectionalLight {
    DirectionalLight {
        direction: Vec3::new(0.6, -0.6, -0.5),
        color: Vec3::ONE,
        intensity: 2.5,
    }
}

impl Scene {
    fn render(&mut self, camera: Camera, head: bool) -> (LinearImage, FrameStats) {
        let lights = [key_light()];
        let inputs = FrameInputs {
            shared: SharedInputs {
                camera,
                lights: &lights,
                ambient: Vec3::splat(0.06),
                head: head.then_some(&self.head),
                clear: Some(wgpu::Color {
                    r: 0.15,
                    g: 0.16,
                    b: 0.18,
                    a: 1.0,
                }),
            },
            material: Material::default(),
            hair: Some(&self.hair),
            objects: &[],
        };
        let stats = self
            .renderer
            .render(&self.ctx, &self.targets.targets(), &inputs)
            .expect("frame");
        let image = read_texture(&self.ctx, &self.targets.color).expect("readback");
        (image, stats)
    }
}

fn background() -> [f32; 4] {
    [0.15, 0.16, 0.18, 1.0]
}

fn differs(a: [f32; 4], b: [f32; 4]) -> bool {
    a.iter().zip(&b).any(|(x, y)| (x - y).abs() > 2e-3)
}

fn save(name: &str, image: &LinearImage) {
    let dir = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("volume");
    std::fs::create_dir_all(&dir).expect("tmp dir");
    image
        .save_png(dir.join(format!("{name}.png")))
        .expect("png");
}

#[test]
fn raymarcher_draws_the_hair_and_stops_at_the_head() {
    if common::gpu().is_none() {
        return;
    }
    let mut s = scene();
    s.renderer
        .set_technique(TechniqueKind::Volume)
        .expect("technique");
    let (hair, stats) = s.render(camera(5.0), false);
    save("volume", &hair);
    let hair_pixels = hair
        .pixels
        .iter()
        .filter(|p| differs(**p, background()))
        .count();
    assert!(hair_pixels > (SIZE * SIZE / 10) as usize, "{hair_pixels}");
    assert_eq!(stats.lod, 1.0);
    let v = stats.volume.expect("the frame voxelized");
    assert_eq!(v.resolution, 48);
    let gpu = stats.gpu.expect("stats");
    let counters = gpu.volume.expect("voxel counters");
    assert!(
        counters.deposits > 1000 && counters.dropped == 0,
        "{counters:?}"
    );
    assert_eq!(gpu.ppll.requested, 0, "no strand pass ran");
    if let Timings::Passes(p) = &gpu.timings {
        let names: Vec<&str> = p.iter().map(|t| t.name).collect();
        assert_eq!(names, ["volume/voxelize", "head", "volume/raymarch"]);
    } else {
        eprintln!("the adapter has no timestamp queries: the volume's pass order is not checked");
    }

    // An opaque ball between the eye and the hair: where it covers the view, the march stops at
    // its depth and the pixel is the ball alone (shadows off, so the ball is shaded alike).
    s.renderer
        .set_settings(
            &s.ctx,
            StrandSettings {
                shadows: false,
                ..strands()
            },
        )
        .expect("settings");
    s.renderer
        .set_volume_settings(
            &s.ctx,
            VolumeSettings {
                shadows: false,
                ..volume()
            },
        )
        .expect("settings");
    let cam = camera(5.0);
    let ball = cam.eye() * 0.55 + Vec3::new(0.0, -0.3, 0.0) * 0.45;
    s.head = HeadGeometry::new(&s.ctx, &TriMesh::uv_sphere(ball, 0.35, 16, 24)).expect("ball");
    let (both, _) = s.render(cam, true);
    save("volume_ball", &both);
    let lights = [key_light()];
    let ball_only = {
        let inputs = FrameInputs {
            shared: SharedInputs {
                camera: cam,
                lights: &lights,
                ambient: Vec3::splat(0.06),
                head: Some(&s.head),
                clear: Some(wgpu::Color {
                    r: 0.15,
                    g: 0.16,
                    b: 0.18,
                    a: 1.0,
                }),
            },
            material: Material::default(),
            hair: None,
            objects: &[],
        };
        s.renderer
            .render(&s.ctx, &s.targets.targets(), &inputs)
            .expect("frame");
        read_texture(&s.ctx, &s.targets.color).expect("readback")
    };
    let mut covered = 0;
    for (i, (b, o)) in both.pixels.iter().zip(&ball_only.pixels).enumerate() {
        if differs(*o, background()) {
            covered += 1;
            assert!(!differs(*b, *o), "pixel {i}: {b:?} vs the ball alone {o:?}");
        }
    }
    assert!(covered > 200, "{covered}");
    // ...and elsewhere the hair is still drawn.
    let hair_left = both
        .pixels
        .iter()
        .zip(&ball_only.pixels)
        .filter(|(b, o)| differs(**b, **o))
        .count();
    assert!(hair_left > 200, "{hair_left}");
}

#[test]
fn empty_space_skipping_gives_the_same_image() {
    if common::gpu().is_none() {
        return;
    }
    let mut s = scene();
    s.renderer
        .set_technique(TechniqueKind::Volume)
        .expect("technique");
    let (plain, _) = s.render(camera(6.0), true);
    s.renderer
        .set_volume_settings(
            &s.ctx,
            VolumeSettings {
                skip_empty: true,
                ..volume()
            },
        )
        .expect("settings");
    let (skipping, _) = s.render(camera(6.0), true);
    assert_eq!(plain.pixels, skipping.pixels);
    assert!(plain.pixels.iter().any(|p| differs(*p, background())));
}

#[test]
fn lod_0_is_the_strand_renderer_and_lod_1_the_raymarcher() {
    if common::gpu().is_none() {
        return;
    }
    let mut s = scene();
    let cam = camera(5.0);
    let (strands, _) = s.render(cam, true);
    s.renderer
        .set_technique(TechniqueKind::Volume)
        .expect("technique");
    let (volume, _) = s.render(cam, true);
    s.renderer
        .set_technique(TechniqueKind::Hybrid)
        .expect("technique");
    let fixed = |lod| HybridSettings {
        lod: Some(lod),
        ..Default::default()
    };
    s.renderer
        .set_hybrid_settings(fixed(0.0))
        .expect("settings");
    let (lod0, stats0) = s.render(cam, true);
    s.renderer
        .set_hybrid_settings(fixed(1.0))
        .expect("settings");
    let (lod1, stats1) = s.render(cam, true);
    assert_eq!(lod0.pixels, strands.pixels, "lod 0 = strands");
    assert_eq!(lod1.pixels, volume.pixels, "lod 1 = volume");
    assert!(stats0.volume.is_none() && stats1.volume.is_some());
    // The two renderers do differ (the equalities above are not trivial).
    let d = strands
        .pixels
        .iter()
        .zip(&volume.pixels)
        .filter(|(a, b)| differs(**a, **b))
        .count();
    assert!(d > 100, "{d}");

    // By distance: near shows strands, far the volume.
    s.renderer
        .set_hybrid_settings(HybridSettings {
            near: 6.0,
            far: 9.0,
            ..Default::default()
        })
        .expect("settings");
    let (near, near_stats) = s.render(camera(5.0), true);
    assert_eq!(near_stats.lod, 0.0);
    assert_eq!(near.pixels, strands.pixels);
    let (_, far_stats) = s.render(camera(10.0), true);
    assert_eq!(far_stats.lod, 1.0);
    let mid = camera(7.5);
    let d = mid.eye().distance(s.hair.bounds.0);
    let (_, mid_stats) = s.render(mid, true);
    assert!(
        mid_stats.lod > 0.05 && mid_stats.lod < 0.95,
        "{}",
        mid_stats.lod
    );
    let want = tress_shading::lod_factor(d, 6.0, 9.0);
    assert!(
        (mid_stats.lod - want).abs() < 1e-5,
        "{} vs {want}",
        mid_stats.lod
    );
}

#[test]
fn transitions_mix_the_two_renderers() {
    if common::gpu().is_none() {
        return;
    }
    let mut s = scene();
    // The head as the volume shadows it in every frame: where the volume is translucent over
    // the head, the mix is the mean of the two frames only if the head looks the same in both.
    let settings = StrandSettings {
        shadow_mode: ShadowMode::Volume,
        ..strands()
    };
    s.renderer.set_settings(&s.ctx, settings).expect("settings");
    // The head as the volume shadows it in every frame: where the volume is translucent over
    // the head, the mix is the mean of the two frames only if the head looks the same in both.
    let settings = StrandSettings {
        shadow_mode: ShadowMode::Volume,
        ..strands()
    };
    s.renderer.set_settings(&s.ctx, settings).expect("settings");
    let cam = camera(5.0);
    let (strands, _) = s.render(cam, true);
    s.renderer
        .set_technique(TechniqueKind::Volume)
        .expect("technique");
    let (volume, _) = s.render(cam, true);
    s.renderer
        .set_technique(TechniqueKind::Hybrid)
        .expect("technique");
    for transition in [Transition::Alpha, Transition::Dither] {
        s.renderer
            .set_hybrid_settings(HybridSettings {
                lod: Some(0.5),
                transition,
                ..Default::default()
            })
            .expect("settings");
        let (mixed, stats) = s.render(cam, true);
        save(&format!("hybrid_{}", transition.name()), &mixed);
        assert!(
            stats.gpu.expect("stats").timings.get("lod/blend").is_some() || !s.ctx.caps.timestamps
        );
        let (mut from_volume, mut differing) = (0, 0);
        for ((m, a), b) in mixed.pixels.iter().zip(&strands.pixels).zip(&volume.pixels) {
            // Half-float targets: a few 1e-3 of rounding through the extra layer.
            let near =
                |x: [f32; 4], y: [f32; 4]| x.iter().zip(&y).all(|(p, q)| (p - q).abs() <= 4e-3);
            match transition {
                Transition::Alpha => {
                    let want = [0, 1, 2, 3].map(|k| 0.5 * (a[k] + b[k]));
                    assert!(near(*m, want), "{m:?} vs {want:?} ({a:?}, {b:?})");
                }
                Transition::Dither => {
                    assert!(
                        near(*m, *a) || near(*m, *b),
                        "{m:?} is neither {a:?} nor {b:?}"
                    );
                    if differs(*a, *b) {
                        differing += 1;
                        if near(*m, *b) {
                            from_volume += 1;
                        }
                    }
                }
            }
        }
        if transition == Transition::Dither {
            // Factor 0.5: half of the Bayer thresholds are below it.
            let share = from_volume as f32 / differing as f32;
            assert!(
                (0.35..=0.65).contains(&share),
                "{from_volume} of {differing}"
            );
        }
    }
}

#[test]
fn volume_shadows_and_ao_reach_the_rasterizer() {
    if common::gpu().is_none() {
        return;
    }
    let mut s = scene();
    let cam = camera(5.0);
    let mean = |img: &LinearImage| -> f32 {
        img.pixels.iter().map(|p| p[0] + p[1] + p[2]).sum::<f32>() / img.pixels.len() as f32
    };
    let unshadowed = StrandSettings {
        shadows: false,
        ..strands()
    };
    s.renderer
        .set_settings(&s.ctx, unshadowed.clone())
        .expect("settings");
    let (lit, lit_stats) = s.render(cam, true);
    assert!(lit_stats.volume.is_none());
    let volume_shadows = StrandSettings {
        shadow_mode: ShadowMode::Volume,
        ..strands()
    };
    s.renderer
        .set_settings(&s.ctx, volume_shadows)
        .expect("settings");
    let (shadowed, stats) = s.render(cam, true);
    save("strands_volume_shadows", &shadowed);
    assert!(
        stats.volume.is_some(),
        "the rasterizer's volume shadows voxelize"
    );
    let gpu = stats.gpu.expect("stats");
    if let Timings::Passes(p) = &gpu.timings {
        let names: Vec<&str> = p.iter().map(|t| t.name).collect();
        // No shadow maps with volume shadows.
        assert_eq!(
            names,
            [
                "volume/voxelize",
                "head",
                "strands/ppll_build",
                "strands/ppll_resolve"
            ]
        );
    } else {
        eprintln!("the adapter has no timestamp queries: the pass order is not checked");
    }
    assert!(
        mean(&shadowed) < 0.9 * mean(&lit),
        "{} vs {}",
        mean(&shadowed),
        mean(&lit)
    );
    let with_ao = StrandSettings {
        ao: true,
        ..unshadowed
    };
    s.renderer.set_settings(&s.ctx, with_ao).expect("settings");
    let (occluded, _) = s.render(cam, true);
    save("strands_volume_ao", &occluded);
    assert!(
        mean(&occluded) < 0.97 * mean(&lit),
        "{} vs {}",
        mean(&occluded),
        mean(&lit)
    );
}

/// The hair's pixels: those the hair changes from the background by more than a few percent.
fn hair_mask(image: &LinearImage) -> Vec<bool> {
    let bg = background();
    image
        .pixels
        .iter()
        .map(|p| (0..3).any(|c| (p[c] - bg[c]).abs() > 0.02))
        .collect()
}

/// Mean FLIP between two frames over the pixels of `mask`.
fn masked_flip(a: &LinearImage, b: &LinearImage, mask: &[bool]) -> f32 {
    let rgb = |img: &LinearImage| -> Vec<u8> {
        img.to_srgb8()
            .pixels()
            .flat_map(|p| [p[0], p[1], p[2]])
            .collect()
    };
    let (ra, rb) = (rgb(a), rgb(b));
    let map = nv_flip::flip(
        nv_flip::FlipImageRgb8::with_data(a.width, a.height, &ra),
        nv_flip::FlipImageRgb8::with_data(b.width, b.height, &rb),
        nv_flip::DEFAULT_PIXELS_PER_DEGREE,
    )
    .to_vec();
    let (sum, n) = map
        .iter()
        .zip(mask)
        .filter(|(_, m)| **m)
        .fold((0.0, 0usize), |(s, n), (v, _)| (s + v, n + 1));
    sum / n.max(1) as f32
}

/// Strands and volume of one view: their frames, the union of their hair masks, its size, the
/// masks' IoU and the hair FLIP between the frames over the union.
struct Agreement {
    strands: LinearImage,
    volume: LinearImage,
    union: Vec<bool>,
    either: usize,
    iou: f32,
    flip: f32,
}

fn agreement(s: &mut Scene, distance: f32) -> Agreement {
    let cam = camera(distance);
    s.renderer
        .set_technique(TechniqueKind::Strands)
        .expect("technique");
    let (strands, _) = s.render(cam, false);
    s.renderer
        .set_technique(TechniqueKind::Volume)
        .expect("technique");
    let (volume, _) = s.render(cam, false);
    let (a, b) = (hair_mask(&strands), hair_mask(&volume));
    let both = a.iter().zip(&b).filter(|(x, y)| **x && **y).count();
    let union: Vec<bool> = a.iter().zip(&b).map(|(x, y)| *x || *y).collect();
    let either = union.iter().filter(|u| **u).count();
    let flip = masked_flip(&strands, &volume, &union);
    Agreement {
        strands,
        volume,
        union,
        either,
        iou: both as f32 / either.max(1) as f32,
        flip,
    }
}

#[test]
fn volume_and_strands_agree_on_where_the_hair_is() {
    if common::gpu().is_none() {
        return;
    }
    let mut s = scene();
    // Hair FLIP over the hair's pixels, measured: 0.272 at 5 and 0.172 at 8 (IoU 0.934 and
    // 0.951; with the mean tangent's highlights 0.302 and 0.209, and before the
    // opacity-weighted composite and ADSM's expected visibility 0.329 and 0.260). Bounded 10%
    // above, against a frame without hair as the baseline.
    let mut last = f32::INFINITY;
    for (distance, bound) in [(5.0, 0.30), (8.0, 0.19)] {
        let Agreement {
            strands,
            volume,
            union,
            either,
            iou,
            flip,
        } = agreement(&mut s, distance);
        let blank = LinearImage {
            pixels: vec![background(); strands.pixels.len()],
            ..strands.clone()
        };
        let baseline = masked_flip(&strands, &blank, &union);
        eprintln!(
            "distance {distance}: hair-mask IoU {iou:.3} over {either} px, hair FLIP {flip:.3} \
             (without hair {baseline:.3})"
        );
        save(&format!("agree_strands_{distance}"), &strands);
        save(&format!("agree_volume_{distance}"), &volume);
        assert!(either > 500, "{either} hair pixels");
        assert!(iou >= 0.9, "distance {distance}: IoU {iou}");
        assert!(
            flip <= bound,
            "distance {distance}: hair FLIP {flip} > {bound}"
        );
        assert!(flip < 0.6 * baseline, "{flip} vs no hair's {baseline}");
        assert!(
            flip < last,
            "the volume must get closer to the strands with distance"
        );
        last = flip;
    }
}

/// The physically based model in both renderers (`strands.shading = "marschner"`): the volume
/// shades the voxelized tangent with the same lobes and dual scattering, and still agrees with
/// the strands on where the hair is, as closely as under Kajiya-Kay.
#[test]
fn under_marschner_the_volume_still_matches_the_strands() {
    if common::gpu().is_none() {
        return;
    }
    let mut s = scene();
    let settings = StrandSettings {
        shading: tress_render::Shading::Marschner,
        ..strands()
    };
    s.renderer.set_settings(&s.ctx, settings).expect("settings");
    // Measured: hair FLIP 0.239 at 5 and 0.111 at 8 (IoU 0.936, 0.952), against 0.272 and
    // 0.172 under Kajiya-Kay; bounded as before (0.309 and 0.204 were measured when the
    // volume's composite was the paper's `iso`).
    let mut last = f32::INFINITY;
    for (distance, bound) in [(5.0, 0.34), (8.0, 0.225)] {
        let Agreement {
            strands,
            volume,
            iou,
            flip,
            ..
        } = agreement(&mut s, distance);
        eprintln!("marschner distance {distance}: IoU {iou:.3}, hair FLIP {flip:.3}");
        save(&format!("marschner_strands_{distance}"), &strands);
        save(&format!("marschner_volume_{distance}"), &volume);
        assert!(iou >= 0.9, "distance {distance}: IoU {iou}");
        assert!(
            flip <= bound,
            "distance {distance}: hair FLIP {flip} > {bound}"
        );
        assert!(flip < last);
        last = flip;
    }
}

/// The brightest tenth of `image`'s hair pixels by luminance (its highlights), over `mask`.
fn highlight_mask(image: &LinearImage, mask: &[bool]) -> Vec<bool> {
    let lum = |p: &[f32; 4]| 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2];
    let mut hair: Vec<f32> = image
        .pixels
        .iter()
        .zip(mask)
        .filter(|(_, m)| **m)
        .map(|(p, _)| lum(p))
        .collect();
    hair.sort_by(f32::total_cmp);
    let cut = hair[hair.len() * 9 / 10];
    image
        .pixels
        .iter()
        .zip(mask)
        .map(|(p, m)| *m && lum(p) > cut)
        .collect()
}

/// `volume.highlights = "strands"` (the voxelizer integrates the strands' own Kajiya-Kay lobes
/// per voxel) against the paper's lobe of the mean tangent: the volume's highlights sit where
/// the strands' are, and the frame is closer to the strands' (issue 13's ponytail: hair FLIP
/// 0.113 → 0.083 at the scene's distance).
#[test]
fn integrated_highlights_sit_where_the_strands_highlights_are() {
    if common::gpu().is_none() {
        return;
    }
    let mut s = scene();
    let mut measure = |highlights| {
        let settings = VolumeSettings {
            highlights,
            ..volume()
        };
        s.renderer
            .set_volume_settings(&s.ctx, settings)
            .expect("volume settings");
        let a = agreement(&mut s, 5.0);
        let (hs, hv) = (
            highlight_mask(&a.strands, &a.union),
            highlight_mask(&a.volume, &a.union),
        );
        let both = hs.iter().zip(&hv).filter(|(x, y)| **x && **y).count();
        let either = hs.iter().zip(&hv).filter(|(x, y)| **x || **y).count();
        save(&format!("highlights_{highlights}"), &a.volume);
        (a.flip, both as f32 / either.max(1) as f32)
    };
    let (flip_lobes, iou_lobes) = measure(tress_render::volume::Highlights::Strands);
    let (flip_mean, iou_mean) = measure(tress_render::volume::Highlights::MeanTangent);
    eprintln!(
        "hair FLIP {flip_lobes:.3} (mean tangent {flip_mean:.3}); highlight IoU \
         {iou_lobes:.3} (mean tangent {iou_mean:.3})"
    );
    // Measured: hair FLIP 0.272 against 0.295, highlight IoU 0.387 against 0.334.
    assert!(flip_lobes < 0.97 * flip_mean, "{flip_lobes} vs {flip_mean}");
    assert!(iou_lobes > iou_mean + 0.03, "{iou_lobes} vs {iou_mean}");
}

/// The baked ambient occlusion (`volume.ao_texel`, 1 and 2) darkens the strands and the
/// raymarcher as the paper's per-point samples (`ao_texel = 0`) do: over the hair, FLIP against
/// the per-point frame far under the AO's own effect, and the same mean darkening within 3% (a
/// texel a voxel) or 6% (every other voxel: interpolated between texel centres, a point on a
/// strand is a little lighter than its own samples make it, 1.9% and 3.5% here).
#[test]
fn baked_ao_gives_the_per_point_ao() {
    if common::gpu().is_none() {
        return;
    }
    let mut s = scene();
    let cam = camera(5.0);
    let mean = |img: &LinearImage, mask: &[bool]| -> f32 {
        let (sum, n) = img
            .pixels
            .iter()
            .zip(mask)
            .filter(|(_, m)| **m)
            .fold((0.0, 0usize), |(s, n), (p, _)| {
                (s + p[0] + p[1] + p[2], n + 1)
            });
        sum / n.max(1) as f32
    };
    for technique in [TechniqueKind::Strands, TechniqueKind::Volume] {
        s.renderer.set_technique(technique).expect("technique");
        let frame = |s: &mut Scene, ao: bool, ao_texel: u32| {
            let strands = StrandSettings { ao, ..strands() };
            s.renderer.set_settings(&s.ctx, strands).expect("strands");
            // A ball of about four voxels, as the ponytail's default one is at 256³.
            let volume = VolumeSettings {
                ao,
                ao_texel,
                ao_radius: 0.25,
                ..volume()
            };
            s.renderer
                .set_volume_settings(&s.ctx, volume)
                .expect("volume settings");
            s.render(cam, true).0
        };
        let lit = frame(&mut s, false, 1);
        let per_point = frame(&mut s, true, 0);
        let mask = hair_mask(&lit);
        let effect = masked_flip(&lit, &per_point, &mask);
        let darkening = mean(&per_point, &mask) / mean(&lit, &mask);
        assert!(darkening < 0.97, "{technique:?}: AO darkens by {darkening}");
        for texel in [1, 2] {
            let baked = frame(&mut s, true, texel);
            save(&format!("baked_ao_{technique:?}_{texel}"), &baked);
            let flip = masked_flip(&per_point, &baked, &mask);
            let d = mean(&baked, &mask) / mean(&lit, &mask);
            eprintln!(
                "{technique:?} texel {texel}: FLIP {flip:.4} against the per-point AO (the AO \
                 itself {effect:.4}), darkening {d:.4} against {darkening:.4}"
            );
            assert!(
                flip < 0.25 * effect,
                "{technique:?} texel {texel}: {flip} vs {effect}"
            );
            assert!(
                ((1.0 - d) / (1.0 - darkening) - 1.0).abs() < 0.03 * texel as f32,
                "{technique:?} texel {texel}: darkening {d} vs {darkening}"
            );
        }
    }
}
