//! Design rule 6 for physically based hair: every function of `shaders/common/marschner.wgsl`,
//! evaluated on the GPU over a grid of inputs, matches its CPU twin in `tress-shading`
//! (`marschner.rs`, `dual_scattering.rs`). The harness module also validates with naga without
//! a GPU.

mod common;

use bytemuck::{Pod, Zeroable};
use common::compute::{Rng, run_cases, test_module};
use glam::{Vec3, Vec4};
use tress_render::shaders;
use tress_shading::dual_scattering::{DualScattering, dual_scattering_lighting};
use tress_shading::fiber::{HairFiber, sigma_a_from_melanin};
use tress_shading::marschner::{
    Marschner, fresnel_schlick, hair_angles, hair_gaussian, marschner, marschner_lighting,
    marschner_r, marschner_trt, marschner_tt,
};
use wgpu::util::DeviceExt;

const OUTPUTS: usize = 10;
const CASES: usize = 512;

#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
struct Case {
    t: [f32; 4],
    l: [f32; 4],
    v: [f32; 4],
    m0: [f32; 4],
    m1: [f32; 4],
    c: [f32; 4],
    g: [f32; 4],
}

fn cases() -> Vec<Case> {
    let mut rng = Rng(0x5eed_1234_abcd_0001);
    (0..CASES)
        .map(|i| {
            let t = rng.unit();
            let mut l = rng.unit();
            let mut v = rng.unit();
            // Edge rows: light along the tangent, backlit, light at the eye.
            match i % 16 {
                0 => l = t,
                1 => v = -l,
                2 => v = l,
                _ => {}
            }
            if i % 16 == 3 {
                l = (l - l.dot(t) * t).normalize();
            }
            // On the specular cone: facing the light (R, TRT) and through the fibre (TT).
            let along = l.dot(t) * t;
            match i % 16 {
                4 => v = l - 2.0 * along,
                5 => v = -(l - along) - along,
                _ => {}
            }
            let fiber = HairFiber {
                sigma_a: Vec3::new(
                    rng.range(0.0, 3.0),
                    rng.range(0.0, 3.0),
                    rng.range(0.0, 3.0),
                ),
                beta_m: rng.range(0.1, 0.9),
                beta_n: 0.3,
                alpha: rng.range(-5.0, 5.0).to_radians(),
                eta: rng.range(1.3, 1.8),
            };
            let m = Marschner::from_fiber(&fiber);
            let strands = if i % 8 == 0 {
                0.0
            } else {
                rng.range(0.0, 40.0)
            };
            let direct = if i % 8 == 1 { 1.0 } else { rng.next() };
            Case {
                t: t.extend(strands).to_array(),
                l: l.extend(direct).to_array(),
                v: v.extend(rng.range(-1.1, 1.1)).to_array(),
                m0: m.sigma_a.extend(m.eta).to_array(),
                m1: m.beta.extend(m.alpha).to_array(),
                c: rng.color().extend(rng.range(-1.0, 1.0)).to_array(),
                g: [
                    rng.range(0.05, 1.0),
                    rng.range(1.2, 2.0),
                    rng.range(-0.2, 1.2),
                    0.0,
                ],
            }
        })
        .collect()
}

/// The material whose dual-scattering table the harness binds.
fn table() -> (Marschner, DualScattering) {
    let m = Marschner::from_fiber(&HairFiber {
        sigma_a: sigma_a_from_melanin(0.5, 0.3),
        ..HairFiber::default()
    });
    (m, DualScattering::from_marschner(&m))
}

/// `DualScattering` as the uniform buffer's bytes (its WGSL layout: vec4 rows).
fn table_bytes(ds: &DualScattering) -> Vec<f32> {
    let mut out = Vec::new();
    for t in [&ds.a_f, &ds.a_b, &ds.delta_b, &ds.sigma_b2] {
        out.extend(t.iter().flat_map(|r| r.to_array()));
    }
    for r in [ds.params, ds.tt_avg, ds.trt_avg] {
        out.extend(r.to_array());
    }
    out
}

fn run_cpu(c: &Case, ds: &DualScattering) -> [Vec4; OUTPUTS] {
    let v3 = |a: [f32; 4]| Vec3::new(a[0], a[1], a[2]);
    let (t, l, v) = (v3(c.t), v3(c.l), v3(c.v));
    let m = Marschner {
        sigma_a: v3(c.m0),
        eta: c.m0[3],
        beta: v3(c.m1),
        alpha: c.m1[3],
    };
    let color = v3(c.c);
    let a = hair_angles(t, l, v);
    let at = ds.at(c.v[3]);
    [
        Vec4::new(a.sin_theta_i, a.sin_theta_o, a.cos_theta_d, a.cos_phi),
        Vec4::new(
            a.cos_half_phi,
            a.cos_half_lv,
            hair_gaussian(c.g[0], c.c[3]),
            fresnel_schlick(c.g[1], c.g[2]),
        ),
        {
            let tt = marschner_tt(&m, &a);
            Vec4::new(marschner_r(&m, &a), tt.x, tt.y, tt.z)
        },
        marschner_trt(&m, &a).extend(0.0),
        marschner(&m, t, l, v).extend(0.0),
        marschner_lighting(&m, t, l, color, v).extend(0.0),
        dual_scattering_lighting(&m, ds, t, l, color, v, c.t[3], c.l[3]).extend(0.0),
        at.a_f.extend(at.beta_f2),
        at.a_b.extend(at.delta_b.x),
        at.sigma_b2.extend(at.delta_b.y),
    ]
}

const NAMES: [&str; OUTPUTS] = [
    "hair_angles (sin θi, sin θo, cos θd, cos φ)",
    "hair_angles (cos φ/2, cos ½∠lv) / hair_gaussian / fresnel_schlick",
    "marschner_r / marschner_tt",
    "marschner_trt",
    "marschner",
    "marschner_lighting",
    "dual_scattering_lighting",
    "dual_scattering_at (a_f, βf²)",
    "dual_scattering_at (A_b, Δb.x)",
    "dual_scattering_at (σb², Δb.y)",
];

#[test]
fn marschner_test_harness_validates() {
    let src = include_str!("marschner_gpu.wgsl");
    let text = shaders::compose_source("tests/marschner_gpu.wgsl", src).expect("composes");
    let module = naga::front::wgsl::parse_str(&text)
        .unwrap_or_else(|e| panic!("does not parse:\n{}", e.emit_to_string(&text)));
    naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::default(),
    )
    .validate(&module)
    .unwrap_or_else(|e| panic!("does not validate:\n{}", e.emit_to_string(&text)));
}

#[test]
fn marschner_wgsl_matches_cpu_twins() {
    let Some(ctx) = common::gpu() else { return };
    let cases = cases();
    let (_, ds) = table();
    let module = test_module(
        &ctx,
        "tests/marschner_gpu.wgsl",
        include_str!("marschner_gpu.wgsl"),
        "test/marschner/shader",
    );
    let table_buf = ctx
        .device
        .create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("test/marschner/dual-scattering"),
            contents: bytemuck::cast_slice(&table_bytes(&ds)),
            usage: wgpu::BufferUsages::UNIFORM,
        });
    let gpu: Vec<[f32; 4]> = run_cases(
        &ctx,
        "test/marschner",
        &module,
        &cases,
        OUTPUTS,
        &[(2, table_buf.as_entire_binding())],
    );
    assert_eq!(gpu.len(), cases.len() * OUTPUTS);
    let cpu: Vec<[Vec4; OUTPUTS]> = cases.iter().map(|c| run_cpu(c, &ds)).collect();
    let mut worst = [0f32; OUTPUTS];
    for (i, (case, want)) in cases.iter().zip(&cpu).enumerate() {
        for (f, w) in want.iter().enumerate() {
            let g = Vec4::from(gpu[i * OUTPUTS + f]);
            // Relative to the value, with a floor far below what a pixel shows.
            let err = ((g - *w).abs() / w.abs().max(Vec4::splat(1e-3))).max_element();
            worst[f] = worst[f].max(err);
            assert!(
                err < 2e-3,
                "{} differs for case {i}: gpu {g}, cpu {w} ({case:?})",
                NAMES[f]
            );
        }
    }
    eprintln!("worst relative errors: {worst:?}");
    // The grid exercises lit and shadowed, forward and backward, narrow and wide lobes.
    let lit = cpu.iter().filter(|w| w[4].max_element() > 0.1).count();
    let scattered = cases
        .iter()
        .zip(&cpu)
        .filter(|(c, w)| w[6].max_element() > 1.05 * w[5].max_element() && c.l[3] < 0.5)
        .count();
    assert!(lit > CASES / 10, "too few cases with a visible lobe: {lit}");
    assert!(
        scattered > CASES / 20,
        "too few cases lit through the hair: {scattered}"
    );
}
