//! A session simulating an application's hair with the application's own head transform
//! (`Session::simulate_to_with`, as `examples/embed.rs` does): the roots the frames draw sit
//! exactly on the moving head, the strands keep their length, and a technique that cannot draw
//! simulated hair refuses.

mod common;

use glam::{Quat, Vec3};
use tress_hair::HairAsset;
use tress_render::scene_setup::PreparedHair;
use tress_render::session::{Session, SessionOptions};
use tress_render::{Material, TargetFormats, TechniqueKind, TriMesh};
use tress_sim::{MotionSpec, Rigid, SimSettings};

/// Strands rooted on the upper half of a sphere of radius 10, drooping outwards.
fn hair() -> HairAsset {
    let mut positions = Vec::new();
    let (strands, vertices) = (200u32, 10u32);
    for i in 0..strands {
        let y = 1.0 - (i as f32 + 0.5) / strands as f32 * 0.8;
        let r = (1.0 - y * y).sqrt();
        let phi = 2.39996 * i as f32;
        let n = Vec3::new(r * phi.cos(), y, r * phi.sin());
        let mut p = n * 10.0;
        let mut dir = n;
        for _ in 0..vertices {
            positions.push(p);
            dir = (dir + Vec3::new(0.0, -0.3, 0.0)).normalize();
            p += dir * 1.5;
        }
    }
    HairAsset::from_counts(positions, &vec![vertices; strands as usize]).unwrap()
}

fn session(ctx: &tress_render::GpuContext, asset: &HairAsset) -> Session {
    let hair = PreparedHair {
        asset: asset.clone(),
        material: Material::default(),
        technique: TechniqueKind::Strands,
    };
    let head = TriMesh::uv_sphere(Vec3::ZERO, 9.8, 24, 32);
    Session::with_hair(
        ctx,
        TargetFormats::default(),
        tress_scene::Scene::default(),
        vec![hair],
        Some(head),
        SessionOptions::default(),
    )
    .unwrap()
}

#[test]
fn the_applications_head_carries_the_roots_and_the_strands_keep_their_length() {
    let Some(ctx) = common::gpu() else { return };
    let asset = hair();
    let mut s = session(&ctx, &asset);
    let settings = SimSettings {
        guides: 0.25,
        ..SimSettings::default()
    };
    s.start_simulation(&ctx, settings, MotionSpec::default())
        .unwrap();
    let head = |_: usize, t: f32| {
        Rigid::about(
            Vec3::ZERO,
            Quat::from_rotation_y(1.2 * t),
            Vec3::new(4.0 * t, 0.0, 0.0),
        )
    };
    let frame = s.simulate_to_with(&ctx, 0.5, true, head).unwrap();
    assert_eq!(frame.steps, 30);
    let p = s.read_hair_positions(&ctx).unwrap();
    let now = head(0, 0.5);
    let mut worst = 0.0f32;
    for st in 0..asset.strand_count() {
        let r = asset.strand_range(st);
        let root = now.apply(asset.positions()[r.start]);
        assert!(
            p[r.start].distance(root) < 1e-3,
            "strand {st}'s root is off the head"
        );
        for i in r.start + 1..r.end {
            let l0 = asset.positions()[i].distance(asset.positions()[i - 1]);
            let e = (p[i].distance(p[i - 1]) - l0).abs() / l0;
            worst = worst.max(e);
        }
    }
    // Guides and followers alike (followers are rebuilt, then take back their rest lengths).
    assert!(worst <= 0.005, "a segment's length changed by {worst}");
    // The hair moved with the head, not only its roots.
    let tips_moved = (0..asset.strand_count())
        .map(|st| {
            let tip = asset.strand_range(st).end - 1;
            p[tip].distance(asset.positions()[tip])
        })
        .fold(0.0f32, f32::max);
    assert!(tips_moved > 2.0, "the tips moved {tips_moved}");
    // Stopping puts the hair back at rest.
    s.stop_simulation(&ctx).unwrap();
    assert_eq!(s.read_hair_positions(&ctx).unwrap(), asset.positions());
}

#[test]
fn patches_and_satf_refuse_simulation_and_say_what_draws_it() {
    let Some(ctx) = common::gpu() else { return };
    let mut s = session(&ctx, &hair());
    s.set_technique(&ctx, "patches").unwrap();
    let e = s
        .start_simulation(&ctx, SimSettings::default(), MotionSpec::default())
        .unwrap_err()
        .to_string();
    assert!(e.contains("strands, volume, hybrid and auto"), "{e}");
}

#[test]
fn a_cache_of_the_simulated_frames_reads_back_as_simulated() {
    let Some(ctx) = common::gpu() else { return };
    let asset = hair();
    let mut s = session(&ctx, &asset);
    let settings = SimSettings {
        guides: 0.25,
        ..SimSettings::default()
    };
    let motion = MotionSpec::preset(tress_sim::Preset::Turn);
    s.start_simulation(&ctx, settings, motion).unwrap();
    let frames: Vec<Vec<Vec3>> = (0..5)
        .map(|k| {
            s.simulate_to(&ctx, f64::from(k) / 24.0, false).unwrap();
            s.read_hair_positions(&ctx).unwrap()
        })
        .collect();
    assert_ne!(frames[0], frames[4], "the hair moved");
    let dir = std::env::temp_dir().join(format!("tress-sim-cache-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for ext in ["abc", "usdc", "usda"] {
        let path = dir.join(format!("cache.{ext}"));
        tress_hair::formats::write_cache_path(&path, &asset, &frames, 24.0).unwrap();
        for (k, want) in frames.iter().enumerate() {
            let options = tress_hair::formats::ReadOptions {
                frame: k as u32,
                ..Default::default()
            };
            let got = tress_hair::formats::load_path(&path, &options)
                .unwrap()
                .asset;
            assert_eq!(got.positions(), &want[..], "{ext} frame {k}");
        }
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// Two characters (the hair and a copy of it 40 units along x), no head.
fn two_characters(ctx: &tress_render::GpuContext, assets: &[HairAsset]) -> Session {
    let hair = assets
        .iter()
        .map(|a| PreparedHair {
            asset: a.clone(),
            material: Material::default(),
            technique: TechniqueKind::Strands,
        })
        .collect();
    Session::with_hair(
        ctx,
        TargetFormats::default(),
        tress_scene::Scene::default(),
        hair,
        None,
        SessionOptions::default(),
    )
    .unwrap()
}

fn mean_abs(a: &tress_render::LinearImage, b: &tress_render::LinearImage) -> f32 {
    let sum: f32 = a
        .pixels
        .iter()
        .zip(&b.pixels)
        .map(|(p, q)| (0..3).map(|c| (p[c] - q[c]).abs()).sum::<f32>() / 3.0)
        .sum();
    sum / a.pixels.len() as f32
}

#[test]
fn volume_hybrid_and_auto_draw_every_characters_simulated_hair() {
    let Some(ctx) = common::gpu() else { return };
    let first = hair();
    let mut second = first.clone();
    second
        .positions_mut()
        .iter_mut()
        .for_each(|p| *p += Vec3::new(40.0, 0.0, 0.0));
    let rest = [first, second];
    let mut s = two_characters(&ctx, &rest);
    let settings = SimSettings {
        guides: 0.25,
        ..SimSettings::default()
    };
    s.start_simulation(&ctx, settings, MotionSpec::preset(tress_sim::Preset::Turn))
        .unwrap();
    s.simulate_to(&ctx, 0.5, false).unwrap();
    assert_eq!(s.simulation().unwrap().characters().count(), 2);
    // Each character turned about its own pivot and its hair moved.
    let p = s.read_hair_positions(&ctx).unwrap();
    let n = rest[0].positions().len();
    let moved: Vec<HairAsset> = rest
        .iter()
        .enumerate()
        .map(|(k, a)| {
            let mut m = a.clone();
            m.positions_mut().copy_from_slice(&p[k * n..(k + 1) * n]);
            let tips = m
                .positions()
                .iter()
                .zip(a.positions())
                .map(|(x, y)| x.distance(*y))
                .fold(0.0f32, f32::max);
            assert!(tips > 2.0, "character {k} moved {tips}");
            m
        })
        .collect();
    // Every strand technique draws what was simulated: about the frame of a session given the
    // simulated positions as still hair (not to the bit: the simulated hair's volume is placed
    // by bounds that allow for its reach, the still hair's by its own box), and far from the
    // frame of the hair at rest.
    let size = [160, 90];
    let targets =
        tress_render::OffscreenTargets::new(&ctx, size, tress_render::COLOR_FORMAT).unwrap();
    let camera = tress_render::Camera::look_at(
        Vec3::new(20.0, 5.0, 90.0),
        Vec3::new(20.0, -5.0, 0.0),
        Vec3::Y,
        0.6,
        1.0,
        300.0,
        size,
    );
    let mut still = two_characters(&ctx, &moved);
    let mut at_rest = two_characters(&ctx, &rest);
    // The fixed grid: sized by the screen, the simulated hair's grid (its bounds allow for its
    // reach, so it looks larger) would get another resolution than the still hair's.
    for session in [&mut s, &mut still, &mut at_rest] {
        session.set(&ctx, "volume.screen_resolution=false").unwrap();
    }
    let frame = |session: &mut Session, technique: &str| {
        session.set_technique(&ctx, technique).unwrap();
        session
            .render(&ctx, &targets.targets(), &camera, None)
            .unwrap();
        tress_render::read_texture(&ctx, &targets.color).unwrap()
    };
    for technique in ["volume", "hybrid", "auto"] {
        let simulated = frame(&mut s, technique);
        let same = frame(&mut still, technique);
        let resting = frame(&mut at_rest, technique);
        let (d_same, d_rest) = (mean_abs(&simulated, &same), mean_abs(&simulated, &resting));
        assert!(
            d_same < 2e-3 && d_rest > 10.0 * d_same.max(1e-5),
            "{technique}: {d_same} from the simulated positions drawn still, {d_rest} from rest"
        );
    }
}
