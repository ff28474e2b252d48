//! The pass states of both schemes, checked on the pipeline descriptor parts the pass owners
//! hand to wgpu, against the slides' lists (Scheuermann 2004, "Sorted Hair Rendering Scheme"
//! and "Optimized Rendering Scheme"). No GPU needed.

use tress_render::COLOR_FORMAT;
use tress_render::patches::{AlphaTest, BLEND, PassShader, PatchPipelineParts, RenderScheme};
use wgpu::{ColorWrites, CompareFunction, Face};

fn parts(scheme: RenderScheme) -> Vec<(&'static str, PatchPipelineParts)> {
    scheme
        .passes()
        .iter()
        .map(|p| (p.name, p.pipeline_parts(COLOR_FORMAT)))
        .collect()
}

/// `(cull, depth compare, depth write, color writes, fragment entry)` of a pass.
fn state(p: &PatchPipelineParts) -> (Option<Face>, CompareFunction, bool, bool, &'static str) {
    (
        p.primitive.cull_mode,
        p.depth_stencil.depth_compare.expect("depth compare set"),
        p.depth_stencil
            .depth_write_enabled
            .expect("depth write set"),
        p.color_target.write_mask == ColorWrites::ALL,
        p.fragment_entry,
    )
}

#[test]
fn four_pass_scheme_matches_the_optimized_slide() {
    let p = parts(RenderScheme::FourPass);
    let names: Vec<&str> = p.iter().map(|(n, _)| *n).collect();
    assert_eq!(
        names,
        [
            "patches/z_prime",
            "patches/opaque",
            "patches/back",
            "patches/front"
        ]
    );
    // Pass 1: prime Z: alpha test (opaque only), no culling, Z writes, Less, no color writes,
    // the alpha-only shader.
    assert_eq!(
        state(&p[0].1),
        (None, CompareFunction::Less, true, false, "fs_main")
    );
    assert_eq!(p[0].1.module, "patches/z_prime.wgsl");
    assert_eq!(p[0].1.color_target.write_mask, ColorWrites::empty());
    // Pass 2: opaque parts: no culling, no Z writes, Equal, full shader without alpha test.
    assert_eq!(
        state(&p[1].1),
        (None, CompareFunction::Equal, false, true, "fs_main")
    );
    // Pass 3: transparent back faces: cull front, no Z writes, Less.
    assert_eq!(
        state(&p[2].1),
        (
            Some(Face::Front),
            CompareFunction::Less,
            false,
            true,
            "fs_main"
        )
    );
    // Pass 4: transparent front faces: cull back, Z writes, Less.
    assert_eq!(
        state(&p[3].1),
        (
            Some(Face::Back),
            CompareFunction::Less,
            true,
            true,
            "fs_main"
        )
    );
    for (_, parts) in &p[1..] {
        assert_eq!(parts.module, "patches/patch_shade.wgsl");
        assert_eq!(parts.color_target.blend, Some(BLEND));
    }
}

#[test]
fn three_pass_scheme_matches_the_sorted_slide() {
    let p = parts(RenderScheme::ThreePass);
    let names: Vec<&str> = p.iter().map(|(n, _)| *n).collect();
    assert_eq!(names, ["patches/opaque", "patches/back", "patches/front"]);
    // Pass 1: alpha test passes opaque pixels, no culling, Z writes, Less.
    assert_eq!(
        state(&p[0].1),
        (None, CompareFunction::Less, true, true, "fs_opaque")
    );
    // Pass 2: alpha test passes non-opaque pixels, cull front, no Z writes, Less.
    assert_eq!(
        state(&p[1].1),
        (
            Some(Face::Front),
            CompareFunction::Less,
            false,
            true,
            "fs_transparent"
        )
    );
    // Pass 3: alpha test passes non-opaque pixels, cull back, Z writes, Less.
    assert_eq!(
        state(&p[2].1),
        (
            Some(Face::Back),
            CompareFunction::Less,
            true,
            true,
            "fs_transparent"
        )
    );
}

#[test]
fn only_the_z_prime_and_the_three_pass_scheme_alpha_test() {
    // The point of the optimized scheme: after the Z prime, no pass discards (early Z stays on).
    for p in RenderScheme::FourPass.passes() {
        let expect = if p.shader == PassShader::AlphaOnly {
            AlphaTest::PassOpaque
        } else {
            AlphaTest::Off
        };
        assert_eq!(p.alpha_test, expect, "{}", p.name);
    }
    for p in RenderScheme::ThreePass.passes() {
        assert_ne!(p.alpha_test, AlphaTest::Off, "{}", p.name);
        assert_eq!(p.shader, PassShader::Full);
    }
}

#[test]
fn front_faces_are_counter_clockwise_and_depth_is_the_renderers() {
    for scheme in [RenderScheme::FourPass, RenderScheme::ThreePass] {
        for (name, p) in parts(scheme) {
            assert_eq!(p.primitive.front_face, wgpu::FrontFace::Ccw, "{name}");
            assert_eq!(
                p.primitive.topology,
                wgpu::PrimitiveTopology::TriangleList,
                "{name}"
            );
            assert_eq!(p.depth_stencil.format, tress_render::DEPTH_FORMAT, "{name}");
            assert_eq!(p.color_target.format, COLOR_FORMAT, "{name}");
            assert!(p.label.starts_with(name), "{name}");
        }
    }
}
