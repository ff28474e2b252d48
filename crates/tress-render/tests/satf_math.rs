//! Design rule 6 for the SATF technique: every function of `satf/online.wgsl`, evaluated on the
//! GPU over a grid of inputs, matches its CPU twin in `tress_satf` (`online`, `database`,
//! `hrir`), and the GPU's blending with the layer pass's blend state is equation 14
//! (`tress_satf::online::blend_layers`).

mod common;

use std::f32::consts::PI;

use bytemuck::{Pod, Zeroable};
use common::compute::{Rng, run_cases, test_module};
use glam::{Vec3, Vec4};
use tress_render::GpuContext;
use tress_satf::cylinder::SurfacePoint;
use tress_satf::database::{self as db, LookupSettings, Params};
use tress_satf::hrir;
use tress_satf::online::{self, SatfLighting, ShadowApprox};
use wgpu::util::DeviceExt;

const CASES: usize = 384;
const INPUTS: usize = 12;
const OUTPUTS: usize = 10;

const HARNESS: &str = r#"
#include "satf/online.wgsl"

struct Case { v: array<vec4f, 12> }
struct Out { v: array<vec4f, 10> }

@group(0) @binding(0) var<storage, read> cases: array<Case>;
@group(0) @binding(1) var<storage, read_write> outs: array<Out>;

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) id: vec3u) {
    let i = id.x;
    if i >= arrayLength(&cases) {
        return;
    }
    let c = cases[i].v;
    let t = c[0].xyz;
    let s = c[0].w;
    let n = c[1].xyz;
    let k_spe = c[1].w;
    let l = c[2].xyz;
    let k_h = c[2].w;
    let v = c[3].xyz;
    let k_dif = c[3].w;
    let f = c[4].xyz;
    let gamma = c[4].w;
    let pa = HsvParams(c[5].xyz, c[5].w, c[7].x);
    let pb = HsvParams(c[6].xyz, c[6].w, c[7].y);
    let angle_weight = c[7].z;
    let k_threshold = c[7].w;
    let weights = c[8].xyz;
    let count = u32(c[8].w);
    let c1 = c[9].x;
    let c2 = c[9].y;
    let re = c[9].z;
    let alpha = c[9].w;
    let alpha_sum = c[10].x;
    let k_shadow = c[10].y;
    let tau = c[10].z;
    let theta = c[10].w;
    let acc = c[11].xyz;
    let blend_alpha = c[11].w;

    var o: Out;
    o.v[0] = vec4f(
        satf_azimuth(l, n, v),
        f32(satf_angle_bin(theta, count)),
        satf_angle_difference(pa.theta_v, pb.theta_v),
        satf_params_distance(pa, pb, weights, angle_weight),
    );
    let ave = satf_average_params(pa, pb);
    o.v[1] = vec4f(select(0.0, 1.0, satf_is_uniform(pa, pb, weights, angle_weight, k_threshold)), ave.features);
    o.v[2] = vec4f(ave.theta_v, ave.theta_l, satf_interpolate(c1, c2, gamma), satf_straight_reflectance(re, alpha));
    o.v[3] = vec4f(satf_diffuse(t, l, k_dif, f), 0.0);
    o.v[4] = vec4f(satf_primary_specular(t, n, s, l, v, k_spe, k_h, f), 0.0);
    o.v[5] = vec4f(satf_secondary_specular(t, n, s, l, v, k_spe, k_h, f), 0.0);
    var m: SatfLighting;
    m.k_dif = k_dif;
    m.f_dif = f;
    m.k_spe1 = k_spe;
    m.f_spe1 = vec3f(1.0, 0.9, 0.8);
    m.primary_shift = s;
    m.k_spe2 = 0.5 * k_spe;
    m.f_spe2 = f.zyx;
    m.secondary_shift = 0.5 * s;
    m.k_h = k_h;
    o.v[6] = vec4f(satf_lighting(m, t, n, l, v), 0.0);
    o.v[7] = vec4f(satf_transmittance(alpha_sum, k_shadow, 0u), satf_transmittance(alpha_sum, k_shadow, 1u), 0.0, 0.0);
    o.v[8] = vec4f(satf_shading(f, re, tau), 0.0);
    o.v[9] = vec4f(satf_blend_over(acc, f, blend_alpha), 0.0);
    outs[i] = o;
}
"#;

#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
struct Case {
    v: [[f32; 4]; INPUTS],
}

fn cases() -> Vec<Case> {
    let mut rng = Rng(0x5a7f_2006_0b5e_55ed);
    (0..CASES)
        .map(|i| {
            let t = rng.unit();
            let n = (rng.unit() - t * rng.unit().dot(t)).normalize_or(t.any_orthonormal_vector());
            let n = (n - n.dot(t) * t).normalize();
            let l = rng.unit();
            let v = rng.unit();
            let features = |r: &mut Rng| Vec3::new(r.range(0.0, 2.0), r.next(), r.next());
            let fa = features(&mut rng);
            // Every fourth case: nearly equal boundary sectors, so both sides of equation 6 occur.
            let fb = if i % 4 == 0 {
                fa + Vec3::splat(0.02 * rng.next())
            } else {
                features(&mut rng)
            };
            let angle = |r: &mut Rng| r.range(-PI, PI);
            let (tva, tla) = (angle(&mut rng), angle(&mut rng));
            let (tvb, tlb) = if i % 4 == 0 {
                (tva + 0.01 * rng.next(), tla - 0.01 * rng.next())
            } else {
                (angle(&mut rng), angle(&mut rng))
            };
            let count = [1.0, 4.0, 8.0, 16.0, 7.0][i % 5];
            let alpha = if i % 8 == 0 { 0.0 } else { rng.next() };
            Case {
                v: [
                    t.extend(rng.range(0.0, 0.3)).to_array(),
                    n.extend(rng.range(0.0, 1.0)).to_array(),
                    l.extend(rng.range(4.0, 100.0)).to_array(),
                    v.extend(rng.range(0.0, 1.0)).to_array(),
                    rng.color().extend(rng.next()).to_array(),
                    fa.extend(tva).to_array(),
                    fb.extend(tvb).to_array(),
                    [tla, tlb, rng.range(0.0, 4.0), rng.range(0.05, 0.6)],
                    Vec4::new(rng.next(), rng.next(), rng.next(), count).to_array(),
                    [rng.next(), rng.next(), rng.next() * alpha, alpha],
                    [
                        rng.range(0.0, 3.0),
                        rng.range(0.0, 1.5),
                        rng.next(),
                        rng.range(-7.0, 7.0),
                    ],
                    rng.color().extend(rng.next()).to_array(),
                ],
            }
        })
        .collect()
}

fn run_gpu(ctx: &GpuContext, cases: &[Case]) -> Vec<[[f32; 4]; OUTPUTS]> {
    let module = test_module(ctx, "tests/satf_math", HARNESS, "test/satf-math/shader");
    run_cases(ctx, "test/satf-math", &module, cases, 1, &[])
}

fn close3(gpu: [f32; 4], cpu: Vec3, rel: f32, what: &str, i: usize) {
    let g = Vec3::new(gpu[0], gpu[1], gpu[2]);
    let tol = rel * cpu.abs().max_element().max(1.0);
    assert!(
        (g - cpu).abs().max_element() <= tol,
        "case {i}: {what}: GPU {g} vs CPU {cpu}"
    );
}

fn close(gpu: f32, cpu: f32, tol: f32, what: &str, i: usize) {
    assert!(
        (gpu - cpu).abs() <= tol * cpu.abs().max(1.0),
        "case {i}: {what}: GPU {gpu} vs CPU {cpu}"
    );
}

#[test]
fn online_functions_match_their_cpu_twins() {
    let Some(ctx) = common::gpu() else {
        return;
    };
    let cases = cases();
    let gpu = run_gpu(&ctx, &cases);
    let (mut uniform, mut bins) = (0, 0);
    for (i, (c, o)) in cases.iter().zip(&gpu).enumerate() {
        let v3 = |k: usize| Vec3::new(c.v[k][0], c.v[k][1], c.v[k][2]);
        let (t, n, l, v, f) = (v3(0), v3(1), v3(2), v3(3), v3(4));
        let (s, k_spe, k_h, k_dif, gamma) = (c.v[0][3], c.v[1][3], c.v[2][3], c.v[3][3], c.v[4][3]);
        let pa = Params {
            features: v3(5).to_array(),
            theta_v: c.v[5][3],
            theta_l: c.v[7][0],
        };
        let pb = Params {
            features: v3(6).to_array(),
            theta_v: c.v[6][3],
            theta_l: c.v[7][1],
        };
        let lookup = LookupSettings {
            feature_weights: v3(8).to_array(),
            angle_weight: c.v[7][2],
            k_threshold: c.v[7][3],
        };
        let count = c.v[8][3] as u32;
        let [c1, c2, re, alpha] = c.v[9];
        let [alpha_sum, k_shadow, tau, theta] = c.v[10];
        let (acc, blend_alpha) = (v3(11), c.v[11][3]);

        let surface = SurfacePoint {
            position: Vec3::ZERO,
            tangent: t,
            normal: n,
            s_axis: v,
        };
        close(o[0][0], online::azimuth(l, &surface), 1e-5, "azimuth", i);
        // Angle bins: exact, except within rounding of a boundary between two bins.
        let x = (theta + PI) / (2.0 * PI) * count as f32;
        if (x - x.floor() - 0.5).abs() > 1e-3 {
            assert_eq!(
                o[0][1] as u32,
                hrir::angle_bin(theta, count),
                "case {i}: angle_bin"
            );
            bins += 1;
        }
        close(
            o[0][2],
            db::angle_difference(pa.theta_v, pb.theta_v),
            1e-5,
            "angle_difference",
            i,
        );
        let dist = db::params_distance(&pa, &pb, &lookup);
        close(o[0][3], dist, 1e-5, "params_distance (eq. 6)", i);
        if (dist - lookup.k_threshold).abs() > 1e-4 {
            let cpu = db::is_uniform(&pa, &pb, &lookup);
            assert_eq!(o[1][0] == 1.0, cpu, "case {i}: is_uniform (eq. 6)");
            uniform += usize::from(cpu);
        }
        let ave = db::average_params(&pa, &pb);
        close3(
            [o[1][1], o[1][2], o[1][3], 0.0],
            Vec3::from(ave.features),
            1e-6,
            "Params_ave features",
            i,
        );
        close(
            db::angle_difference(o[2][0], ave.theta_v),
            0.0,
            1e-5,
            "Params_ave theta_v",
            i,
        );
        close(
            db::angle_difference(o[2][1], ave.theta_l),
            0.0,
            1e-5,
            "Params_ave theta_l",
            i,
        );
        close(
            o[2][2],
            db::interpolate_value(c1, c2, gamma),
            1e-6,
            "interpolate (eq. 7)",
            i,
        );
        close(
            o[2][3],
            hrir::straight_reflectance(re, alpha),
            1e-5,
            "straight_reflectance",
            i,
        );
        close3(
            o[3],
            online::diffuse(t, l, k_dif, f),
            1e-5,
            "diffuse (eq. 9)",
            i,
        );
        close3(
            o[4],
            online::primary_specular(t, n, s, l, v, k_spe, k_h, f),
            2e-4,
            "primary specular (eq. 10)",
            i,
        );
        close3(
            o[5],
            online::secondary_specular(t, n, s, l, v, k_spe, k_h, f),
            2e-4,
            "secondary specular (eq. 11)",
            i,
        );
        let m = SatfLighting {
            k_dif,
            f_dif: f,
            k_spe1: k_spe,
            f_spe1: Vec3::new(1.0, 0.9, 0.8),
            primary_shift: s,
            k_spe2: 0.5 * k_spe,
            f_spe2: Vec3::new(f.z, f.y, f.x),
            secondary_shift: 0.5 * s,
            k_h,
        };
        close3(
            o[6],
            online::lighting(&m, t, n, l, v),
            2e-4,
            "lighting (eq. 8)",
            i,
        );
        close(
            o[7][0],
            online::transmittance(&[alpha_sum], k_shadow, ShadowApprox::Exponential),
            1e-5,
            "transmittance (eq. 12, exponential)",
            i,
        );
        close(
            o[7][1],
            online::transmittance(&[alpha_sum], k_shadow, ShadowApprox::Linear),
            1e-5,
            "transmittance (eq. 12, linear)",
            i,
        );
        close3(
            o[8],
            online::shading(f, re, tau),
            1e-6,
            "shading (eq. 13)",
            i,
        );
        close3(
            o[9],
            online::blend_over(acc, f, blend_alpha),
            1e-6,
            "blend_over (eq. 14)",
            i,
        );
    }
    // The grid exercises both outcomes of equation 6 and almost every angle bin case.
    assert!(
        uniform > 20 && uniform < CASES - 20,
        "{uniform} uniform cases"
    );
    assert!(bins > CASES * 9 / 10, "{bins} angle-bin cases checked");
}

/// Equation 14 through the GPU's blending with the layer pass's blend state (premultiplied
/// `(Y α, α)`, One / OneMinusSrcAlpha): layers drawn innermost first over a background give
/// `Y_bk Π(1 − α_k) + Σ Y_k α_k Π_{j>k}(1 − α_j)`.
#[test]
fn gpu_blending_is_equation_14() {
    let Some(ctx) = common::gpu() else {
        return;
    };
    const SRC: &str = r#"
@group(0) @binding(0) var<storage, read> layers: array<vec4f>;
struct V { @builtin(position) p: vec4f, @location(0) @interpolate(flat) i: u32 }
@vertex fn vs(@builtin(vertex_index) vi: u32, @builtin(instance_index) ii: u32) -> V {
    let xy = vec2f(f32((vi << 1u) & 2u), f32(vi & 2u)) * 2.0 - 1.0;
    return V(vec4f(xy, 0.0, 1.0), ii);
}
@fragment fn fs(in: V) -> @location(0) vec4f {
    let c = layers[in.i];
    return vec4f(c.xyz * c.w, c.w);
}
"#;
    let mut rng = Rng(77);
    let pixels = 4u32;
    // Per pixel (column), a background and a stack of up to 6 layers.
    let stacks: Vec<(Vec3, Vec<(Vec3, f32)>)> = (0..pixels)
        .map(|p| {
            let bk = rng.color();
            let layers = (0..(p + 3)).map(|_| (rng.color(), rng.next())).collect();
            (bk, layers)
        })
        .collect();
    let module = ctx
        .device
        .create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("test/satf-blend/shader"),
            source: wgpu::ShaderSource::Wgsl(SRC.into()),
        });
    let blend = wgpu::BlendComponent {
        src_factor: wgpu::BlendFactor::One,
        dst_factor: wgpu::BlendFactor::OneMinusSrcAlpha,
        operation: wgpu::BlendOperation::Add,
    };
    let pipeline = ctx
        .device
        .create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("test/satf-blend/pipeline"),
            layout: None,
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some("vs"),
                compilation_options: Default::default(),
                buffers: &[],
            },
            primitive: Default::default(),
            depth_stencil: None,
            multisample: Default::default(),
            fragment: Some(wgpu::FragmentState {
                module: &module,
                entry_point: Some("fs"),
                compilation_options: Default::default(),
                targets: &[Some(wgpu::ColorTargetState {
                    format: tress_render::COLOR_FORMAT,
                    blend: Some(wgpu::BlendState {
                        color: blend,
                        alpha: blend,
                    }),
                    write_mask: wgpu::ColorWrites::ALL,
                })],
            }),
            multiview_mask: None,
            cache: None,
        });
    let targets = tress_render::OffscreenTargets::new(&ctx, [1, 1], tress_render::COLOR_FORMAT)
        .expect("targets");
    for (bk, layers) in &stacks {
        let data: Vec<[f32; 4]> = layers
            .iter()
            .map(|(c, a)| c.extend(*a).to_array())
            .collect();
        let buf = ctx
            .device
            .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("test/satf-blend/layers"),
                contents: bytemuck::cast_slice(&data),
                usage: wgpu::BufferUsages::STORAGE,
            });
        let group = ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: None,
            layout: &pipeline.get_bind_group_layout(0),
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: buf.as_entire_binding(),
            }],
        });
        let view = targets.color.create_view(&Default::default());
        let mut enc = ctx.device.create_command_encoder(&Default::default());
        {
            let mut pass = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: None,
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: &view,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(wgpu::Color {
                            r: bk.x.into(),
                            g: bk.y.into(),
                            b: bk.z.into(),
                            a: 1.0,
                        }),
                        store: wgpu::StoreOp::Store,
                    },
                })],
                depth_stencil_attachment: None,
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_pipeline(&pipeline);
            pass.set_bind_group(0, &group, &[]);
            // One draw per layer, innermost first, as the texture mapping pass draws them.
            for k in 0..layers.len() as u32 {
                pass.draw(0..3, k..k + 1);
            }
        }
        ctx.queue.submit([enc.finish()]);
        let img = tress_render::read_texture(&ctx, &targets.color).expect("readback");
        let px = img.get(0, 0).expect("pixel");
        let cpu = online::blend_layers(*bk, layers);
        // The target is 16-bit float: about 3 decimal digits per blend step.
        let gpu = Vec3::new(px[0], px[1], px[2]);
        assert!(
            (gpu - cpu).abs().max_element() < 4e-3,
            "GPU {gpu} vs equation 14 {cpu} for {} layers",
            layers.len()
        );
    }
}
