//! The path tracer against what it must reproduce exactly: a white furnace, the BSDF times the
//! light for one bounce at a known offset, hard shadows of opaque fibres, the GPU head pass's
//! Lambert units.

use std::f32::consts::PI;

use glam::Vec3;
use tress_hair::rng::Rng;

use super::super::tests::{quad, scene, strands, tracer};
use super::super::{HEAD_COLOR, Tracer};
use crate::chiang::ChiangBsdf;
use crate::geometry::Ray;
use crate::{SceneGeometry, TraceSettings};

/// The test scene of the tracer's tests with physically based strands, `sets` applied.
fn pb_scene(size: u32, extra: &str, sets: &[&str]) -> tress_scene::Scene {
    let mut sc = scene(
        size,
        &format!("{extra}\n[strands]\nshading = \"marschner\"\n"),
    );
    sc.apply_overrides(sets).expect("overrides");
    sc
}

fn settings(spp: u32, bounces: u32, ambient: f32) -> TraceSettings {
    TraceSettings {
        spp,
        bounces,
        ambient: Some(ambient),
        ..TraceSettings::default()
    }
}

/// A clump of crossing strands around the origin.
fn clump() -> Vec<(Vec3, Vec3)> {
    (0..7)
        .map(|k| {
            let a = k as f32 * 0.45;
            let z = -0.3 * k as f32;
            let d = Vec3::new(a.cos(), a.sin(), 0.2);
            (
                Vec3::new(0.0, 0.0, z) - 2.5 * d,
                Vec3::new(0.0, 0.0, z) + 2.5 * d,
            )
        })
        .collect()
}

#[test]
fn white_fibres_in_a_white_furnace_return_the_sky() {
    // σa = 0 fibres under a uniform sky of radiance 1 (and a background of 1): nothing is
    // absorbed, so every pixel is 1; brown fibres absorb, so they are darker.
    let white = pb_scene(
        6,
        "",
        &[
            "background=[1.0,1.0,1.0]",
            "hair.0.material.sigma_a=[0.0,0.0,0.0]",
        ],
    );
    let s = settings(64, 1024, 1.0);
    let tr = tracer(&white, Some(strands(&clump(), 0.6)), None, &s);
    let img = tr.render(&|_| {}).image;
    for p in &img.pixels {
        assert!((*p - Vec3::ONE).abs().max_element() < 0.02, "{p}");
    }
    let brown = pb_scene(6, "", &["background=[1.0,1.0,1.0]"]);
    let tr = tracer(&brown, Some(strands(&clump(), 0.6)), None, &s);
    let dark = tr.render(&|_| {}).image;
    let centre = dark.get(3, 3);
    assert!(
        centre.max_element() < 0.9 && centre.x > centre.z,
        "{centre}"
    );
}

#[test]
fn one_bounce_is_the_bsdf_at_the_hit_offset_times_the_light() {
    // A strand along x through the origin, radius r; a camera ray down -z at height y0 hits it
    // at h = y0 / r, where the local frame is x, y = +z (towards the eye), z = x × y = -y.
    let r = 0.5f32;
    let sc = pb_scene(
        4,
        "[[light]]\ndirection = [0.3, 0.5, 0.8]\ncolor = [1.0, 0.8, 0.6]\nintensity = 1.0",
        &[],
    );
    let pair = [(Vec3::new(-3.0, 0.0, 0.0), Vec3::new(3.0, 0.0, 0.0))];
    let tr = tracer(
        &sc,
        Some(strands(&pair, 2.0 * r)),
        None,
        &settings(1, 0, 0.0),
    );
    let fiber = sc.hair[0].material.fiber().unwrap();
    let l = Vec3::new(0.3, 0.5, 0.8).normalize();
    let l_local = Vec3::new(l.x, l.z, -l.y);
    for y0 in [-0.45f32, -0.2, 0.0, 0.1, 0.35] {
        let ray = Ray::new(Vec3::new(0.4, y0, 10.0), -Vec3::Z, 0.0, f32::INFINITY);
        let mut rays = 0;
        let got = tr.path_radiance(&ray, &mut Rng::new(1), &mut rays);
        let bsdf = ChiangBsdf::new(&fiber, y0 / r);
        let want = bsdf.eval(Vec3::Y, l_local) * PI * Vec3::new(1.0, 0.8, 0.6);
        assert!(
            (got - want).abs().max_element() < 1e-4 * want.max_element().max(1e-3),
            "y0 {y0}: {got} vs {want}"
        );
        assert_eq!(rays, 2, "camera ray and one shadow ray");
    }
}

#[test]
fn opaque_fibres_cast_hard_shadows() {
    // A second strand between the first and the light blocks all direct light.
    let sc = pb_scene(4, "[[light]]\ndirection = [0.0, 0.0, 1.0]", &[]);
    let pairs = [
        (Vec3::new(-3.0, 0.0, 0.0), Vec3::new(3.0, 0.0, 0.0)),
        (Vec3::new(-3.0, 0.0, 3.0), Vec3::new(3.0, 0.0, 3.0)),
    ];
    let tr = tracer(&sc, Some(strands(&pairs, 0.4)), None, &settings(1, 0, 0.0));
    // From below, so the camera ray meets the lower strand first.
    let ray = Ray::new(Vec3::new(0.0, 0.05, -5.0), Vec3::Z, 0.0, f32::INFINITY);
    let mut rays = 0;
    assert_eq!(
        tr.path_radiance(&ray, &mut Rng::new(2), &mut rays),
        Vec3::ZERO
    );
    // The upper strand, seen from above, is lit.
    let ray = Ray::new(Vec3::new(0.0, 0.05, 8.0), -Vec3::Z, 0.0, f32::INFINITY);
    assert!(
        tr.path_radiance(&ray, &mut Rng::new(2), &mut rays)
            .max_element()
            > 0.0
    );
    // `trace.shadows = false`: the lower strand gets the light the upper one blocked, as much as
    // a lone strand does.
    let unshadowed = TraceSettings {
        shadows: false,
        ..settings(1, 0, 0.0)
    };
    let tr = tracer(&sc, Some(strands(&pairs, 0.4)), None, &unshadowed);
    let lone = tracer(
        &sc,
        Some(strands(&pairs[..1], 0.4)),
        None,
        &settings(1, 0, 0.0),
    );
    let below = Ray::new(Vec3::new(0.0, 0.05, -5.0), Vec3::Z, 0.0, f32::INFINITY);
    let lit = tr.path_radiance(&below, &mut Rng::new(2), &mut rays);
    assert!(lit.max_element() > 0.0, "{lit}");
    assert_eq!(lit, lone.path_radiance(&below, &mut Rng::new(2), &mut rays));
}

#[test]
fn an_overlapping_strand_shadows_the_fibre() {
    // Strand B overlaps strand A (axes 0.3 apart, radius 0.4), between A and the light: the
    // light reaching A's lit point crosses B, however the two intersect. A ray from A's axis
    // would start inside B and miss it (light came through before the fix); from A's surface
    // it enters B.
    let sc = pb_scene(4, "[[light]]\ndirection = [0.0, 0.0, 1.0]", &[]);
    let pairs = [
        (Vec3::new(-3.0, 0.0, 0.0), Vec3::new(3.0, 0.0, 0.0)),
        (Vec3::new(-3.0, 0.0, 0.3), Vec3::new(3.0, 0.0, 0.3)),
    ];
    let tr = tracer(&sc, Some(strands(&pairs, 0.8)), None, &settings(1, 0, 0.0));
    // From below, so the camera ray meets A (outside B) first.
    let mut rays = 0;
    for y in [0.0, 0.1, 0.2] {
        let ray = Ray::new(Vec3::new(0.0, y, -5.0), Vec3::Z, 0.0, f32::INFINITY);
        assert_eq!(
            tr.path_radiance(&ray, &mut Rng::new(2), &mut rays),
            Vec3::ZERO,
            "y = {y}"
        );
    }
    // Without B, the same points are lit through A (TT).
    let tr = tracer(
        &sc,
        Some(strands(&pairs[..1], 0.8)),
        None,
        &settings(1, 0, 0.0),
    );
    let ray = Ray::new(Vec3::new(0.0, 0.1, -5.0), Vec3::Z, 0.0, f32::INFINITY);
    assert!(
        tr.path_radiance(&ray, &mut Rng::new(2), &mut rays)
            .max_element()
            > 0.0
    );
}

#[test]
fn the_head_is_lambert_in_the_gpu_head_passs_units() {
    // A quad facing a light along its normal returns HEAD_COLOR · color · intensity, what the
    // Kajiya-Kay tracer and the GPU head pass draw.
    let sc = pb_scene(
        4,
        "[[light]]\ndirection = [0.0, 0.0, 1.0]\ncolor = [1.0, 1.0, 1.0]\nintensity = 2.0",
        &[],
    );
    let tr: Tracer = Tracer::new(
        &sc,
        &SceneGeometry {
            hair: None,
            head: Some(quad(0.0, 5.0)),
        },
        &settings(1, 0, 0.0),
    )
    .unwrap();
    let ray = Ray::new(Vec3::new(0.2, 0.1, 10.0), -Vec3::Z, 0.0, f32::INFINITY);
    let got = tr.path_radiance(&ray, &mut Rng::new(3), &mut 0);
    assert!((got - HEAD_COLOR * 2.0).abs().max_element() < 1e-5, "{got}");
}

#[test]
fn bounces_add_the_light_that_crosses_blond_hair() {
    let sc = pb_scene(
        8,
        "[[light]]\ndirection = [0.2, 0.9, 0.4]",
        &[
            "hair.0.material.eumelanin=0.2",
            "hair.0.material.pheomelanin=0.05",
        ],
    );
    let hair = || Some(strands(&clump(), 0.6));
    let sum = |img: &crate::Image| img.pixels.iter().map(|p| p.x).sum::<f32>();
    let direct = tracer(&sc, hair(), None, &settings(16, 0, 0.0)).render(&|_| {});
    let many = tracer(&sc, hair(), None, &settings(16, 16, 0.0)).render(&|_| {});
    assert!(sum(&many.image) > 1.2 * sum(&direct.image));
    assert!(many.stats.rays > direct.stats.rays);
    // Deterministic for a seed.
    let again = tracer(&sc, hair(), None, &settings(16, 16, 0.0)).render(&|_| {});
    assert_eq!(again.image, many.image);
}
