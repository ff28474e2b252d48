//! The playback driving a real session, as the viewer does (`app/playback.rs`): a 3-frame cache
//! opened as the viewer opens files, stepped to frame 2, draws the hair at frame 2 (what
//! `tress render cache --frame 2` reads), by positions with the strand techniques and by a reload
//! with patches. Needs a GPU adapter (lavapipe will do); `TRESS_SKIP_GPU_TESTS=1` skips it where
//! there is none.

use std::sync::OnceLock;

use glam::Vec3;
use tress_hair::formats::{load_path, write_cache_path};
use tress_render::session::{SessionOptions, scene_from_inputs};
use tress_render::{GpuContext, TargetFormats};

use super::*;

/// The GPU context, or `None` when `TRESS_SKIP_GPU_TESTS=1` and there is no adapter (as
/// tress-render's GPU tests).
fn gpu() -> Option<GpuContext> {
    static CTX: OnceLock<Result<GpuContext, String>> = OnceLock::new();
    match CTX.get_or_init(|| GpuContext::headless().map_err(|e| e.to_string())) {
        Ok(ctx) => Some(ctx.clone()),
        Err(e) if std::env::var("TRESS_SKIP_GPU_TESTS").is_ok_and(|v| v == "1") => {
            eprintln!("TRESS_SKIP_GPU_TESTS=1: skipping a GPU test ({e})");
            None
        }
        Err(e) => panic!(
            "this test needs a GPU adapter: {e} (lavapipe will do: \
             VK_DRIVER_FILES=/usr/share/vulkan/icd.d/lvp_icd.x86_64.json WGPU_BACKEND=vulkan; \
             TRESS_SKIP_GPU_TESTS=1 skips GPU tests on purpose)"
        ),
    }
}

/// 16 strands of 6 vertices swinging further each frame.
fn write_cache(path: &std::path::Path, frames: usize) {
    let positions: Vec<Vec3> = (0..16 * 6)
        .map(|i| Vec3::new((i / 6) as f32 * 0.5, -((i % 6) as f32), 0.0))
        .collect();
    let asset = HairAsset::from_counts(positions, &[6; 16]).unwrap();
    let frames: Vec<Vec<Vec3>> = (0..frames)
        .map(|k| {
            let k = k as f32;
            asset
                .positions()
                .iter()
                .map(|p| *p + Vec3::new(0.3 * k * -p.y, 0.0, 0.2 * k))
                .collect()
        })
        .collect();
    write_cache_path(path, &asset, &frames, 24.0).unwrap();
}

#[test]
fn stepping_a_cache_to_frame_2_draws_the_hair_at_frame_2() {
    let Some(ctx) = gpu() else { return };
    let dir = std::env::temp_dir().join(format!("tress-viewer-play-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("cache.abc");
    write_cache(&path, 3);
    let at = |k: u32| {
        let options = ReadOptions {
            frame: k,
            ..ReadOptions::default()
        };
        load_path(&path, &options)
            .unwrap()
            .asset
            .positions()
            .to_vec()
    };

    // Opened as the viewer opens a hair file.
    let (scene, auto_frame) = scene_from_inputs(std::slice::from_ref(&path)).unwrap();
    let options = SessionOptions {
        auto_frame,
        ..SessionOptions::default()
    };
    let mut s = Session::new(&ctx, TargetFormats::default(), scene, options).unwrap();
    let animation = probe(s.scene()).unwrap();
    assert_eq!(
        (animation.entries.as_slice(), animation.frames),
        (&[0][..], 3)
    );
    let mut p = animation.playback();
    assert_eq!(s.read_hair_positions(&ctx).unwrap(), at(0));

    // Two steps on (the `.` key), shown as the viewer shows a frame: positions only.
    p.apply(PlayAction::Step(1));
    p.apply(PlayAction::Step(1));
    assert_eq!(p.frame(), 2);
    let shown = show_frame(&mut s, &ctx, &animation, p.frame()).unwrap();
    assert_eq!(shown, Shown::Positions);
    let drawn = s.read_hair_positions(&ctx).unwrap();
    assert_eq!(drawn, at(2));
    assert_ne!(drawn, at(0), "the frames differ");
    assert_eq!(
        s.scene().hair[0].frame,
        None,
        "the positions moved without reloading the scene"
    );

    // Playing wraps round: a frame's time on from 2 is 0 again.
    p.apply(PlayAction::Play(true));
    assert_eq!(p.advance(1.0 / 24.0), 0);
    show_frame(&mut s, &ctx, &animation, p.frame()).unwrap();
    assert_eq!(s.read_hair_positions(&ctx).unwrap(), at(0));

    // Patches build their cards from the loaded hair: the frame is the `hair.0.frame` setting.
    s.set_technique(&ctx, "patches").unwrap();
    assert_eq!(
        show_frame(&mut s, &ctx, &animation, 2).unwrap(),
        Shown::Reloaded
    );
    assert_eq!(s.scene().hair[0].frame, Some(2));
    assert_eq!(s.prepared().objects[0].asset.positions(), &at(2)[..]);
    std::fs::remove_dir_all(&dir).ok();
}
