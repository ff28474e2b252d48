//! `Session`: one scene drawn with every technique, settings by dotted name, memory breakdown.

mod common;

use tress_render::session::{FrameDetail, Session, SessionOptions, TECHNIQUES, scene_from_inputs};
use tress_render::{
    COLOR_FORMAT, GpuContext, OffscreenTargets, StatsReadback, TargetFormats, read_texture,
};

const SIZE: [u32; 2] = [96, 54];

/// The demo scene with 0.5% of the ponytail's strands, and a small SATF database.
fn session(ctx: &GpuContext) -> Session {
    let (scene, auto_frame) = scene_from_inputs(&[]).unwrap();
    let options = SessionOptions {
        auto_frame,
        overrides: vec!["hair.0.strand_ratio=0.005".into()],
        satf_database: Some(Box::new(|_| Ok(common::small_satf_database(48)))),
        ..SessionOptions::default()
    };
    Session::new(ctx, TargetFormats::default(), scene, options).unwrap()
}

/// Pixels differing from the background by more than a few levels.
fn drawn(ctx: &GpuContext, targets: &OffscreenTargets, bg: glam::Vec3) -> usize {
    let img = read_texture(ctx, &targets.color).unwrap();
    img.pixels
        .iter()
        .filter(|p| (0..3).any(|c| (p[c] - bg[c]).abs() > 0.02))
        .count()
}

#[test]
fn every_technique_draws_the_scene_and_reports_its_memory() {
    let Some(ctx) = common::gpu() else { return };
    let mut s = session(&ctx);
    assert_eq!(s.technique(), "strands");
    let targets = OffscreenTargets::new(&ctx, SIZE, COLOR_FORMAT).unwrap();
    let camera = s.camera(SIZE);
    let bg = s.prepared().background;
    for t in TECHNIQUES {
        s.set_technique(&ctx, t).unwrap();
        let f = s.render(&ctx, &targets.targets(), &camera, None).unwrap();
        assert_eq!(f.technique, t);
        assert_eq!(f.size, SIZE);
        let n = drawn(&ctx, &targets, bg);
        assert!(n > 100, "{t}: only {n} pixels drawn");
        let m = f.memory;
        assert!(m.geometry > 0, "{t}: {m}");
        match t {
            "strands" => {
                assert!(m.oit > 0 && m.shadow_maps > 0 && m.volumes == 0, "{t}: {m}");
                assert!(matches!(f.detail, FrameDetail::Strands(_)));
            }
            // The raymarcher uses no PPLL and no shadow maps, though the renderer kept them.
            "volume" => assert!(m.volumes > 0 && m.oit == 0 && m.shadow_maps == 0, "{m}"),
            "patches" => {
                assert!(m.textures > 0 && m.oit == 0, "{m}");
                assert!(matches!(f.detail, FrameDetail::Patches(_)));
            }
            "satf" => {
                assert!(m.database > 0 && m.textures > 0 && m.shadow_maps > 0, "{m}");
                assert!(matches!(f.detail, FrameDetail::Satf(_)));
            }
            _ => {}
        }
        assert_eq!(m.total(), m.rows().iter().map(|r| r.1).sum::<u64>());
    }
}

#[test]
fn hiding_the_hair_leaves_the_head_and_settings_apply_live() {
    let Some(ctx) = common::gpu() else { return };
    let mut s = session(&ctx);
    let targets = OffscreenTargets::new(&ctx, SIZE, COLOR_FORMAT).unwrap();
    let camera = s.camera(SIZE);
    let bg = s.prepared().background;
    s.render(&ctx, &targets.targets(), &camera, None).unwrap();
    let with = drawn(&ctx, &targets, bg);
    s.set_hair_visible(false);
    s.render(&ctx, &targets.targets(), &camera, None).unwrap();
    let without = drawn(&ctx, &targets, bg);
    assert!(
        without > 0 && without < with,
        "head {without}, head and hair {with}"
    );
    s.set_hair_visible(true);

    // A live setting: the volume's memory follows its resolution.
    s.set_technique(&ctx, "volume").unwrap();
    s.set(&ctx, "volume.resolution=32").unwrap();
    let small = s.render(&ctx, &targets.targets(), &camera, None).unwrap();
    s.set(&ctx, "volume.resolution=64").unwrap();
    let big = s.render(&ctx, &targets.targets(), &camera, None).unwrap();
    let ratio = big.memory.volumes as f64 / small.memory.volumes as f64;
    assert!((7.0..9.0).contains(&ratio), "volume bytes ratio {ratio}");

    // Bad settings are errors that change nothing.
    let before = s.scene().clone();
    assert!(s.set(&ctx, "volume.steps=0").is_err());
    assert!(s.set(&ctx, "volume.nonsense=1").is_err());
    assert!(s.set_technique(&ctx, "raytraced").is_err());
    assert_eq!(s.technique(), "volume");
    assert_eq!(s.scene().camera.eye, before.camera.eye);
    s.render(&ctx, &targets.targets(), &camera, None).unwrap();

    // Reloading the hair with a different strand ratio changes the geometry.
    s.set_technique(&ctx, "strands").unwrap();
    let a = s.render(&ctx, &targets.targets(), &camera, None).unwrap();
    s.set(&ctx, "hair.0.strand_ratio=0.01").unwrap();
    let b = s.render(&ctx, &targets.targets(), &camera, None).unwrap();
    assert!(b.memory.geometry > a.memory.geometry);
}

/// A `[hair.material]` key reaches the patches live: under `patches.shading = "marschner"`
/// the frame after `hair.0.material.eumelanin=0.2` changes, and equals the frame of a session
/// opened with that material.
#[test]
fn material_keys_reach_the_patches_live() {
    let Some(ctx) = common::gpu() else { return };
    let targets = OffscreenTargets::new(&ctx, SIZE, COLOR_FORMAT).unwrap();
    let draw = |s: &mut Session| {
        let camera = s.camera(SIZE);
        s.render(&ctx, &targets.targets(), &camera, None).unwrap();
        read_texture(&ctx, &targets.color).unwrap().pixels
    };
    let mut s = session(&ctx);
    s.set_technique(&ctx, "patches").unwrap();
    s.set(&ctx, "patches.shading=\"marschner\"").unwrap();
    let brown = draw(&mut s);
    s.set(&ctx, "hair.0.material.eumelanin=0.2").unwrap();
    let blond = draw(&mut s);
    let changed = brown.iter().zip(&blond).filter(|(a, b)| a != b).count();
    assert!(changed > 100, "only {changed} pixels changed");

    let (scene, auto_frame) = scene_from_inputs(&[]).unwrap();
    let options = SessionOptions {
        auto_frame,
        overrides: vec![
            "hair.0.strand_ratio=0.005".into(),
            "patches.shading=\"marschner\"".into(),
            "hair.0.material.eumelanin=0.2".into(),
        ],
        ..SessionOptions::default()
    };
    let mut fresh = Session::new(&ctx, TargetFormats::default(), scene, options).unwrap();
    fresh.set_technique(&ctx, "patches").unwrap();
    assert!(
        draw(&mut fresh) == blond,
        "the live frame differs from a fresh session's"
    );
}

#[test]
fn satf_without_a_database_is_a_clear_error() {
    let Some(ctx) = common::gpu() else { return };
    let (scene, _) = scene_from_inputs(&[]).unwrap();
    let options = SessionOptions {
        overrides: vec!["hair.0.strand_ratio=0.005".into()],
        ..SessionOptions::default()
    };
    let mut s = Session::new(&ctx, TargetFormats::default(), scene, options).unwrap();
    let e = s.set_technique(&ctx, "satf").unwrap_err().to_string();
    assert!(e.contains("database"), "{e}");
    assert_eq!(s.technique(), "strands");
}

#[test]
fn deferred_satf_frames_do_not_wait_for_their_results() {
    // The viewer reads statistics back deferred: an SATF frame must return before the GPU has
    // finished it (its own counters cannot have arrived) and report the newest frame that has.
    let Some(ctx) = common::gpu() else { return };
    let mut s = session(&ctx);
    s.set_technique(&ctx, "satf").unwrap();
    let targets = OffscreenTargets::new(&ctx, [64, 48], COLOR_FORMAT).unwrap();
    let camera = s.camera([64, 48]);
    let frame = |s: &mut Session| match s
        .render(&ctx, &targets.targets(), &camera, None)
        .unwrap()
        .detail
    {
        FrameDetail::Satf(stats) => stats,
        other => panic!("not an SATF frame: {other:?}"),
    };
    // Waiting (the default): every frame reports itself.
    let waited = frame(&mut s);
    assert_eq!(waited.gpu_frame, Some(waited.frame));
    assert!(
        waited.uniform_hsvs + waited.interpolated_hsvs > 0,
        "{waited:?}"
    );
    s.set_stats_readback(StatsReadback::Deferred);
    let first = frame(&mut s);
    assert!(
        first.gpu_frame.is_none_or(|g| g < first.frame),
        "a deferred frame waited for itself: {first:?}"
    );
    // Once the GPU is idle, a later frame reports an earlier one. (Tests share the device, and
    // another test's poll may run this frame's map callback a moment later, so a few tries.)
    let mut next = first.clone();
    for _ in 0..8 {
        ctx.wait_idle().unwrap();
        next = frame(&mut s);
        if next.gpu_frame.is_some() {
            break;
        }
    }
    let g = next.gpu_frame.expect("results arrive");
    assert!(g >= first.frame && g < next.frame, "{next:?}");
    assert!(next.uniform_hsvs + next.interpolated_hsvs > 0, "{next:?}");
}

/// Two characters (the demo's ponytail twice, the second moved aside), drawn as strands.
fn two_characters(ctx: &GpuContext, shift: f32) -> Session {
    let (mut scene, _) = scene_from_inputs(&[]).unwrap();
    let mut second = scene.hair[0].clone();
    second.transform.translate += glam::Vec3::new(30.0, 0.0, -20.0 + shift);
    scene.hair.push(second);
    let options = SessionOptions {
        // No heads: a session moves hair, not heads.
        overrides: vec![
            "hair.0.strand_ratio=0.005".into(),
            "hair.1.strand_ratio=0.005".into(),
            "head.generated=false".into(),
        ],
        ..SessionOptions::default()
    };
    Session::new(ctx, TargetFormats::default(), scene, options).unwrap()
}

#[test]
fn moving_the_hair_of_two_characters_moves_each_one() {
    let Some(ctx) = common::gpu() else { return };
    let targets = OffscreenTargets::new(&ctx, SIZE, COLOR_FORMAT).unwrap();
    let mut s = two_characters(&ctx, 0.0);
    let camera = s.camera(SIZE);
    // The merged hair with the second character 8 units farther: as a session built so.
    let mut merged = s.prepared().hair().unwrap().into_owned();
    let first = s.prepared().objects[0].asset.vertex_count();
    for p in &mut merged.positions_mut()[first..] {
        p.z -= 8.0;
    }
    s.update_hair_positions(&ctx, &merged).unwrap();
    let frame = |s: &mut Session| {
        s.render(&ctx, &targets.targets(), &camera, None).unwrap();
        read_texture(&ctx, &targets.color).unwrap().pixels
    };
    let differing =
        |a: &[[f32; 4]], b: &[[f32; 4]]| a.iter().zip(b).filter(|(p, q)| p != q).count();
    let moved = frame(&mut s);
    let mut fresh = two_characters(&ctx, -8.0);
    // The positions moved by hand and by the scene's transform round apart in the last bit:
    // measured 1 pixel of 5,184 apart.
    let near = differing(&moved, &frame(&mut fresh));
    let mut still = two_characters(&ctx, 0.0);
    let far = differing(&moved, &frame(&mut still));
    eprintln!("{near} pixels differ from the scene moved so, {far} from the scene unmoved");
    assert!(
        near <= 5,
        "each character took its own strands ({near} pixels differ)"
    );
    assert!(far > 20 * near.max(1), "the move shows ({far} pixels)");
    // An asset with other strands is refused, and nothing moves.
    let one = s.prepared().objects[0].asset.clone();
    assert!(s.update_hair_positions(&ctx, &one).is_err());
}

/// An application's own hair and head, given in memory (`Session::with_hair`, what
/// `examples/embed.rs` does), draw exactly as the same hair and head loaded from a scene; a key
/// that would reload hair or head from the scene is refused by name.
#[test]
fn hair_given_in_memory_draws_like_the_same_hair_loaded_from_a_scene() {
    let Some(ctx) = common::gpu() else { return };
    let targets = OffscreenTargets::new(&ctx, SIZE, COLOR_FORMAT).unwrap();
    let given = |loaded: &Session, head: bool| {
        let prepared = loaded.prepared();
        let mut scene = loaded.scene().clone();
        scene.hair.clear();
        let options = SessionOptions {
            satf_database: Some(Box::new(|_| Ok(common::small_satf_database(48)))),
            ..SessionOptions::default()
        };
        let head = prepared.head.clone().filter(|_| head);
        let hair = prepared.objects.clone();
        Session::with_hair(&ctx, TargetFormats::default(), scene, hair, head, options).unwrap()
    };
    let image = |s: &mut Session, t: &str| {
        s.set_technique(&ctx, t).unwrap();
        let camera = s.camera(SIZE);
        s.render(&ctx, &targets.targets(), &camera, None).unwrap();
        read_texture(&ctx, &targets.color).unwrap().pixels
    };
    // With the head: the patches sort their cards around the given mesh's bounding sphere, the
    // loaded scene's around its generated head's centre, so they are compared without it.
    let mut loaded = session(&ctx);
    let mut with_head = given(&loaded, true);
    assert_eq!(
        with_head.prepared().hair_counts(),
        loaded.prepared().hair_counts()
    );
    assert_eq!(
        with_head.camera(SIZE),
        loaded.camera(SIZE),
        "the scene's camera"
    );
    let mut headless = session(&ctx);
    headless.set(&ctx, "head.generated=false").unwrap();
    let mut without_head = given(&headless, false);
    for t in TECHNIQUES {
        let mut pairs = vec![(&mut headless, &mut without_head)];
        if t != "patches" {
            pairs.push((&mut loaded, &mut with_head));
        }
        for (a, b) in pairs {
            let (a, b) = (image(a, t), image(b, t));
            let differ = a.iter().zip(&b).filter(|(p, q)| p != q).count();
            assert_eq!(differ, 0, "{t}: {differ} of {} pixels differ", a.len());
        }
    }
    let e = with_head
        .set(&ctx, "head.generated=true")
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("head.generated") && e.contains("with_hair"),
        "{e}"
    );
    with_head.set(&ctx, "strands.alpha=0.5").unwrap();
}

/// The scene's top-level `ambient` reaches every technique's shading live: the frame at
/// `ambient = 0.3` is lighter than at `0`, for each technique; a negative one is an error that
/// changes nothing.
#[test]
fn the_scene_ambient_lights_every_technique() {
    let Some(ctx) = common::gpu() else { return };
    let mut s = session(&ctx);
    let targets = OffscreenTargets::new(&ctx, SIZE, COLOR_FORMAT).unwrap();
    let camera = s.camera(SIZE);
    for t in ["strands", "volume", "patches"] {
        s.set_technique(&ctx, t).unwrap();
        let sum = |s: &mut Session, ambient: &str| -> f32 {
            s.set(&ctx, &format!("ambient={ambient}")).unwrap();
            s.render(&ctx, &targets.targets(), &camera, None).unwrap();
            let img = read_texture(&ctx, &targets.color).unwrap();
            img.pixels.iter().map(|p| p[0] + p[1] + p[2]).sum()
        };
        let (dark, light) = (sum(&mut s, "0"), sum(&mut s, "0.3"));
        assert!(light > dark * 1.05, "{t}: {light} vs {dark}");
    }
    assert!(s.set(&ctx, "ambient=-1").is_err());
    assert_eq!(s.scene().ambient, 0.3);
}
