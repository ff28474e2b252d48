//! Geometry maps (strand index, projected direction, depth, head silhouette) against the CPU:
//! the shader's direction against its twin `segment_direction`, the depth against the strands'
//! own view depths, the head behind and in front of the hair.

mod common;

use glam::Vec3;
use tress_hair::HairAsset;
use tress_render::maps::{EMPTY_ID, HEAD_ID, MapRenderer, segment_direction};
use tress_render::{Camera, TriMesh};

/// Straight strands fanning out from the middle in 24 directions, each at its own depth.
fn fan() -> HairAsset {
    let mut points = Vec::new();
    for i in 0..24 {
        let a = i as f32 / 24.0 * std::f32::consts::TAU;
        let dir = Vec3::new(a.cos(), a.sin(), 0.0);
        let z = -0.1 * (i % 5) as f32;
        for k in 0..6 {
            let r = 0.5 + 0.8 * k as f32 / 5.0;
            points.push(dir * r * 4.0 + Vec3::new(0.0, 0.0, z));
        }
    }
    HairAsset::from_counts(points, &[6; 24]).expect("valid")
}

fn camera(size: [u32; 2]) -> Camera {
    Camera::look_at(
        Vec3::new(1.0, 2.0, 14.0),
        Vec3::ZERO,
        Vec3::Y,
        50f32.to_radians(),
        1.0,
        100.0,
        size,
    )
}

#[test]
fn direction_and_depth_agree_with_the_cpu_twin() {
    let Some(ctx) = common::gpu() else { return };
    let hair = fan();
    let cam = camera([160, 120]);
    let maps = MapRenderer::new(&ctx, &hair, None)
        .and_then(|m| m.render(&ctx, &cam))
        .expect("maps");
    let m = cam.clip_from_world();
    let mut seen = [0usize; 24];
    for (p, &id) in maps.strand_id.iter().enumerate() {
        if id == EMPTY_ID {
            assert!(maps.depth[p].is_infinite());
            continue;
        }
        assert!((0..24).contains(&id), "strand index {id}");
        seen[id as usize] += 1;
        let s = hair.strand(id as usize);
        let want = segment_direction(m, [160.0, 120.0], s[0], s[5]);
        let got = maps.direction[p];
        assert!(
            (got[0] - want.x).abs() < 1e-3 && (got[1] - want.y).abs() < 1e-3,
            "strand {id}: {got:?} against {want}"
        );
        let depths = s
            .iter()
            .map(|q| -(cam.view_from_world.transform_point3(*q)).z);
        let (lo, hi) = depths.fold((f32::MAX, f32::MIN), |(lo, hi), d| (lo.min(d), hi.max(d)));
        assert!(
            maps.depth[p] > lo - 1e-3 && maps.depth[p] < hi + 1e-3,
            "depth {} outside {lo}..{hi}",
            maps.depth[p]
        );
    }
    // Every strand shows along its projection: a 1-pixel line covers about the larger of its
    // projected extents in x and y (less where a nearer strand crosses it; up to about twice
    // that where the driver rasterizes lines as 1-pixel-wide rectangles, as lavapipe does).
    let pixel = |q: Vec3| {
        let c = m * q.extend(1.0);
        glam::Vec2::new((c.x / c.w + 1.0) * 80.0, (1.0 - c.y / c.w) * 60.0)
    };
    for (i, &n) in seen.iter().enumerate() {
        let s = hair.strand(i);
        let d = (pixel(s[5]) - pixel(s[0])).abs();
        let extent = d.x.max(d.y);
        assert!(
            n as f32 > 0.6 * extent && (n as f32) < 2.0 * extent + 2.0,
            "strand {i} covers {n} pixels, its projection {extent}"
        );
    }
    assert!(maps.head.iter().all(|&h| !h));
}

#[test]
fn the_head_hides_hair_behind_it_and_shows_through_its_silhouette() {
    let Some(ctx) = common::gpu() else { return };
    let hair = fan();
    // A sphere in front of the fan's centre (towards the camera), radius 2.
    let head = TriMesh::uv_sphere(Vec3::new(0.0, 0.0, 3.0), 2.0, 24, 32);
    let cam = camera([160, 120]);
    let maps = MapRenderer::new(&ctx, &hair, Some(&head))
        .and_then(|m| m.render(&ctx, &cam))
        .expect("maps");
    let centre = (60 * 160 + 80) as usize;
    assert!(maps.head[centre]);
    assert_eq!(maps.strand_id[centre], HEAD_ID);
    let eye_to_head = (Vec3::new(0.0, 0.0, 3.0) - cam.eye()).length();
    assert!((maps.depth[centre] - (eye_to_head - 2.0)).abs() < 0.3);
    let head_px = maps.head.iter().filter(|&&h| h).count();
    // The sphere's projected disc: radius about f * 2 / distance pixels.
    let f = 60.0 / (25f32.to_radians()).tan();
    let r = f * 2.0 / eye_to_head;
    let disc = std::f32::consts::PI * r * r;
    assert!(
        (head_px as f32 - disc).abs() < 0.15 * disc,
        "{head_px} head pixels against a disc of {disc}"
    );
    // Hair outside the disc is still there.
    assert!(maps.strand_id.iter().any(|&i| i >= 0));
}

#[test]
fn the_twin_handles_points_behind_the_eye() {
    let cam = camera([64, 64]);
    let behind = Vec3::new(1.0, 2.0, 20.0);
    let d = segment_direction(cam.clip_from_world(), [64.0, 64.0], Vec3::ZERO, behind);
    assert_eq!(d, glam::Vec2::ZERO);
    let right = segment_direction(cam.clip_from_world(), [64.0, 64.0], Vec3::ZERO, Vec3::X);
    assert!(right.x > 0.99, "{right}");
}
