//! The playback's behaviour: play and pause, real time to frames with wrap and clamp, stepping,
//! seeking, the frame rate; and which entries of a scene are animated and their hair at a frame.

use std::path::PathBuf;

use glam::Vec3;
use tress_hair::formats::{load_path, write_cache_path, write_path};

use super::*;

fn playing(frames: u32, fps: Option<f64>) -> Playback {
    let mut p = Playback::new(frames, fps, 0);
    p.apply(PlayAction::Play(true));
    assert!(p.playing());
    p
}

#[test]
fn a_new_playback_is_paused_at_its_frame_and_looping_at_the_file_rate_or_24() {
    let p = Playback::new(12, Some(30.0), 5);
    assert_eq!(
        (p.frames(), p.frame(), p.playing(), p.looping()),
        (12, 5, false, true)
    );
    assert_eq!((p.fps(), p.file_fps()), (30.0, Some(30.0)));
    let p = Playback::new(12, None, 99);
    assert_eq!(
        (p.frame(), p.fps()),
        (11, DEFAULT_FPS),
        "past the last: the last"
    );
    // A rate that is no rate is not the file's; one out of range is clamped.
    assert_eq!(Playback::new(3, Some(f64::NAN), 0).file_fps(), None);
    assert_eq!(Playback::new(3, Some(0.0), 0).fps(), DEFAULT_FPS);
    assert_eq!(Playback::new(3, Some(1000.0), 0).fps(), 120.0);
    // One frame (a still file) has nothing to play.
    let mut still = Playback::default();
    assert!(!still.is_animated());
    still.apply(PlayAction::Play(true));
    assert!(!still.playing());
    assert_eq!(still.advance(10.0), 0);
}

#[test]
fn playing_advances_a_frame_every_one_over_fps_seconds() {
    let mut p = playing(100, None);
    assert_eq!(p.advance(0.5 / 24.0), 0, "half a frame: still the first");
    assert_eq!(p.advance(0.5 / 24.0), 1, "the other half: one on");
    assert_eq!(p.advance(0.5), 13, "half a second at 24 fps: 12 more");
    // Time left over carries: 0.75 frames, then 0.75 more is one frame with 0.5 left.
    assert_eq!(p.advance(0.75 / 24.0), 13);
    assert_eq!(p.advance(0.75 / 24.0), 14);
    assert_eq!(p.advance(0.5 / 24.0), 15);
    // Paused, time does not move the frame; nor do clocks that run backwards or not at all.
    p.apply(PlayAction::Play(false));
    assert_eq!(p.advance(1.0), 15);
    p.apply(PlayAction::Play(true));
    assert_eq!(p.advance(-1.0), 15);
    assert_eq!(p.advance(f64::NAN), 15);
    assert_eq!(p.advance(f64::INFINITY), 15);
}

#[test]
fn the_rate_sets_the_speed() {
    let mut p = playing(100, Some(30.0));
    assert_eq!(p.advance(1.0), 30);
    p.apply(PlayAction::Fps(10.0));
    assert_eq!(p.advance(1.0), 40);
    p.apply(PlayAction::Fps(0.0));
    assert_eq!(p.fps(), 1.0, "clamped to the range");
    p.apply(PlayAction::Fps(f64::NAN));
    assert_eq!(p.fps(), 1.0, "not a number: unchanged");
    assert_eq!(p.advance(2.5), 42);
}

#[test]
fn looping_wraps_round_and_not_looping_stops_at_the_last_frame() {
    let mut p = playing(10, None);
    assert_eq!(p.advance(12.0 / 24.0), 2, "12 frames on from 0 of 10: 2");
    assert!(p.playing());
    assert_eq!(p.advance(1000.0 * 10.0 / 24.0), 2, "whole loops come back");

    p.apply(PlayAction::Loop(false));
    assert_eq!(p.advance(5.0 / 24.0), 7);
    assert_eq!(p.advance(5.0 / 24.0), 9, "clamped at the last");
    assert!(!p.playing(), "and stopped there");
    assert_eq!(p.advance(1.0), 9);
    // Play from the last frame without looping starts again at the first.
    p.apply(PlayAction::Play(true));
    assert_eq!((p.frame(), p.playing()), (0, true));
    // Exactly reaching the last frame stops too.
    assert_eq!(p.advance(9.0 / 24.0), 9);
    assert!(!p.playing());
}

#[test]
fn toggle_step_and_seek() {
    let mut p = Playback::new(5, None, 0);
    p.apply(PlayAction::Toggle);
    assert!(p.playing());
    p.apply(PlayAction::Toggle);
    assert!(!p.playing());

    // Stepping pauses, and wraps round when looping.
    p.apply(PlayAction::Play(true));
    p.apply(PlayAction::Step(1));
    assert_eq!((p.frame(), p.playing()), (1, false));
    p.apply(PlayAction::Step(-2));
    assert_eq!(p.frame(), 4, "one back from 0 is the last");
    p.apply(PlayAction::Step(1));
    assert_eq!(p.frame(), 0, "one on from the last is the first");
    // Not looping, the ends hold.
    p.apply(PlayAction::Loop(false));
    p.apply(PlayAction::Step(-1));
    assert_eq!(p.frame(), 0);
    p.apply(PlayAction::Step(7));
    assert_eq!(p.frame(), 4);

    // Seeking keeps playing and starts the frame's time afresh; past the last is the last.
    p.apply(PlayAction::Loop(true));
    p.apply(PlayAction::Play(true));
    assert_eq!(p.advance(0.9 / 24.0), 4);
    p.apply(PlayAction::Seek(2));
    assert_eq!((p.frame(), p.playing()), (2, true));
    assert_eq!(
        p.advance(0.9 / 24.0),
        2,
        "the 0.9 frames before the seek are gone"
    );
    p.apply(PlayAction::Seek(99));
    assert_eq!(p.frame(), 4);
}

/// A folder of its own for a test's files.
fn folder(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("tress-viewer-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Three strands of four vertices and `n` frames of them swinging in x.
fn cache(n: usize) -> (HairAsset, Vec<Vec<Vec3>>) {
    let positions: Vec<Vec3> = (0..12)
        .map(|i| Vec3::new((i / 4) as f32, -((i % 4) as f32), 0.5))
        .collect();
    let asset = HairAsset::from_counts(positions, &[4, 4, 4]).unwrap();
    let frames = (0..n)
        .map(|k| {
            asset
                .positions()
                .iter()
                .map(|p| *p + Vec3::new(0.1 * k as f32 * -p.y, 0.0, 0.01 * k as f32))
                .collect()
        })
        .collect();
    (asset, frames)
}

/// A scene of `entries` (TOML `[[hair]]` tables) in `dir`.
fn scene(dir: &std::path::Path, entries: &str) -> Scene {
    Scene::from_str(entries, dir).unwrap()
}

#[test]
fn probe_finds_the_animated_entries_their_frames_rate_and_start() {
    let dir = folder("probe");
    let (asset, frames) = cache(4);
    write_cache_path(&dir.join("c.abc"), &asset, &frames, 30.0).unwrap();
    write_cache_path(&dir.join("c.usda"), &asset, &frames[..3], 12.0).unwrap();
    write_path(&dir.join("still.hair"), &asset).unwrap();
    write_path(&dir.join("still.usda"), &asset).unwrap();

    let s = scene(
        &dir,
        "[[hair]]\nfiles = [\"still.hair\"]\n\
         [[hair]]\nfiles = [\"c.usda\"]\nframe = 2\n\
         [[hair]]\ngenerator = { style = \"straight\", strands = 8, vertices = 4 }\n\
         [[hair]]\nfiles = [\"still.usda\", \"c.abc\"]\n",
    );
    let a = probe(&s).unwrap();
    assert_eq!(a.entries, [1, 3]);
    assert_eq!(a.frames, 4, "the most of any file");
    assert!((a.fps.unwrap() - 30.0).abs() < 1e-9, "that file's rate");
    assert_eq!(a.start, 2, "the first animated entry's frame");
    let p = a.playback();
    assert_eq!((p.frames(), p.frame(), p.playing()), (4, 2, false));

    let still = probe(&scene(
        &dir,
        "[[hair]]\nfiles = [\"still.usda\", \"still.hair\"]\n",
    ))
    .unwrap();
    assert_eq!(still, Animation::default());
    assert!(!still.playback().is_animated());
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn the_hair_at_a_frame_reads_the_animated_entries_and_keeps_the_others() {
    let dir = folder("hair-at");
    let (asset, frames) = cache(3);
    let path = dir.join("c.abc");
    write_cache_path(&path, &asset, &frames, 24.0).unwrap();
    // A generated entry between, and the cache moved by its entry's transform.
    let s = scene(
        &dir,
        "[[hair]]\nfiles = [\"c.abc\"]\n\
         [[hair]]\ngenerator = { style = \"straight\", strands = 8, vertices = 4 }\n\
         [[hair]]\nfiles = [\"c.abc\"]\ntransform = { translate = [5.0, 0.0, 0.0] }\n",
    );
    let prepared = PreparedScene::load(&s).unwrap();
    let a = probe(&s).unwrap();
    assert_eq!(a.entries, [0, 2]);
    let at2 = hair_at(&s, &prepared, &a, 2).unwrap();
    let want = load_path(
        &path,
        &ReadOptions {
            frame: 2,
            ..ReadOptions::default()
        },
    )
    .unwrap()
    .asset;
    let generated = prepared.objects[1].asset.positions();
    let n = want.positions().len();
    assert_eq!(at2.positions().len(), 2 * n + generated.len());
    assert_eq!(
        &at2.positions()[..n],
        want.positions(),
        "entry 0 at frame 2"
    );
    assert_eq!(
        &at2.positions()[n..n + generated.len()],
        generated,
        "entry 1 as loaded"
    );
    let moved: Vec<Vec3> = want
        .positions()
        .iter()
        .map(|p| *p + Vec3::X * 5.0)
        .collect();
    assert_eq!(
        &at2.positions()[n + generated.len()..],
        &moved[..],
        "entry 2 at 2, moved"
    );
    // Frame 0 is what the scene loaded.
    let at0 = hair_at(&s, &prepared, &a, 0).unwrap();
    let loaded = prepared.hair().unwrap();
    assert_eq!(at0.positions(), loaded.positions());
    std::fs::remove_dir_all(&dir).ok();
}
