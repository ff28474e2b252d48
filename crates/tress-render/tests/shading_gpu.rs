//! Design rule 6: every function of `shaders/common/shading.wgsl`, evaluated on the GPU over a grid
//! of inputs, matches its CPU twin in `tress-shading`.

mod common;

use bytemuck::{Pod, Zeroable};
use common::compute::{Rng, run_cases, test_module};
use glam::{IVec2, Mat4, Vec2, Vec3, Vec4};
use tress_render::GpuContext;
use tress_shading as cpu;
use wgpu::util::DeviceExt;

const OUTPUTS: usize = 12;
const CASES: usize = 512;
const MAP: u32 = 8;

#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
struct Case {
    t: [f32; 4],
    l: [f32; 4],
    v: [f32; 4],
    n: [f32; 4],
    s: [f32; 4],
    c: [f32; 4],
    p: [f32; 4],
    f: [f32; 4],
    acc: [f32; 4],
    k: [f32; 4],
}

#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
struct Harness {
    clip_from_world: [[f32; 4]; 4],
    resolution: [f32; 4],
    h0: [f32; 4],
    h1: [f32; 4],
    h2: [f32; 4],
    h3: [f32; 4],
}

fn lighting() -> cpu::HairLighting {
    cpu::HairLighting {
        diffuse_color: Vec3::new(0.9, 0.8, 0.7),
        primary_exponent: 60.0,
        primary_color: Vec3::new(0.4, 0.35, 0.3),
        primary_shift: -0.15,
        secondary_color: Vec3::new(0.6, 0.4, 0.2),
        secondary_exponent: 12.0,
        secondary_shift: 0.12,
    }
}

fn clip_from_world() -> Mat4 {
    Mat4::perspective_rh(0.9, 1.5, 0.1, 50.0)
        * Mat4::look_at_rh(Vec3::new(1.0, 2.0, 8.0), Vec3::ZERO, Vec3::Y)
}

const RESOLUTION: Vec2 = Vec2::new(96.0, 64.0);

fn cases() -> Vec<Case> {
    let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
    let m = clip_from_world();
    (0..CASES)
        .map(|i| {
            let t = rng.unit();
            let l = rng.unit();
            let mut v = rng.unit();
            if (l + v).length() < 0.1 {
                v = -v;
            }
            let n = t
                .any_orthonormal_vector()
                .rotate_towards(t.cross(t.any_orthonormal_vector()), rng.next());
            let n = (n - n.dot(t) * t).normalize();
            let p = Vec3::new(
                rng.range(-2.0, 2.0),
                rng.range(-2.0, 2.0),
                rng.range(-2.0, 2.0),
            )
            .extend(1.0);
            let screen = cpu::screen_from_clip(m * p, RESOLUTION);
            let frag = screen + Vec2::new(rng.range(-3.0, 3.0), rng.range(-3.0, 3.0));
            let acc_a = rng.next();
            let acc = (rng.color() * acc_a).extend(acc_a);
            // Edge cases on some rows: zero alpha, full alpha, zero distance.
            let alpha = match i % 16 {
                0 => 0.0,
                1 => 1.0,
                _ => rng.next(),
            };
            let d = if i % 16 == 2 {
                0.0
            } else {
                rng.range(0.0, 3.0)
            };
            let kernel = if i % 32 == 3 { 12.0 } else { (i % 4) as f32 };
            Case {
                t: t.extend(rng.range(1.0, 100.0)).to_array(),
                l: l.extend(rng.range(-0.5, 0.5)).to_array(),
                v: v.extend(alpha).to_array(),
                n: n.extend(d).to_array(),
                s: [
                    rng.range(0.0, 8.0),
                    rng.range(0.5, 4.0),
                    rng.range(0.0, 3.0),
                    rng.next(),
                ],
                c: rng.color().extend(rng.next()).to_array(),
                p: p.to_array(),
                f: [
                    frag.x,
                    frag.y,
                    rng.range(-2.0, 10.0).floor(),
                    rng.range(-2.0, 10.0).floor(),
                ],
                acc: acc.to_array(),
                k: [kernel, rng.next(), rng.next(), rng.next()],
            }
        })
        .collect()
}

fn map_depths() -> Vec<f32> {
    let mut rng = Rng(12345);
    (0..MAP * MAP).map(|_| rng.next()).collect()
}

/// Render `depths` into an 8x8 depth texture (depth formats cannot be copied into).
fn depth_map(ctx: &GpuContext, module: &wgpu::ShaderModule, depths: &[f32]) -> wgpu::Texture {
    let texture = ctx.device.create_texture(&wgpu::TextureDescriptor {
        label: Some("test/shading/depth-map"),
        size: wgpu::Extent3d {
            width: MAP,
            height: MAP,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: tress_render::DEPTH_FORMAT,
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
        view_formats: &[],
    });
    let buffer = ctx
        .device
        .create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("test/shading/map-depths"),
            contents: bytemuck::cast_slice(depths),
            usage: wgpu::BufferUsages::STORAGE,
        });
    let pipeline = ctx
        .device
        .create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("test/shading/fill-pipeline"),
            layout: None,
            vertex: wgpu::VertexState {
                module,
                entry_point: Some("vs_fill"),
                compilation_options: Default::default(),
                buffers: &[],
            },
            primitive: Default::default(),
            depth_stencil: Some(wgpu::DepthStencilState {
                format: tress_render::DEPTH_FORMAT,
                depth_write_enabled: Some(true),
                depth_compare: Some(wgpu::CompareFunction::Always),
                stencil: Default::default(),
                bias: Default::default(),
            }),
            multisample: Default::default(),
            fragment: Some(wgpu::FragmentState {
                module,
                entry_point: Some("fs_fill"),
                compilation_options: Default::default(),
                targets: &[],
            }),
            multiview_mask: None,
            cache: None,
        });
    let group = ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("test/shading/fill-group"),
        layout: &pipeline.get_bind_group_layout(1),
        entries: &[wgpu::BindGroupEntry {
            binding: 0,
            resource: buffer.as_entire_binding(),
        }],
    });
    let view = texture.create_view(&Default::default());
    let mut enc = ctx.device.create_command_encoder(&Default::default());
    {
        let mut pass = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("test/shading/fill-pass"),
            color_attachments: &[],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &view,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Clear(1.0),
                    store: wgpu::StoreOp::Store,
                }),
                stencil_ops: None,
            }),
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(1, &group, &[]);
        pass.draw(0..3, 0..1);
    }
    ctx.queue.submit([enc.finish()]);
    texture
}

fn run_gpu(ctx: &GpuContext, cases: &[Case], depths: &[f32]) -> Vec<Vec4> {
    let module = test_module(
        ctx,
        "tests/shading_gpu.wgsl",
        include_str!("shading_gpu.wgsl"),
        "test/shading/shader",
    );
    let map = depth_map(ctx, &module, depths);
    let h = lighting();
    let harness = Harness {
        clip_from_world: clip_from_world().to_cols_array_2d(),
        resolution: [RESOLUTION.x, RESOLUTION.y, 0.0, 0.0],
        h0: h.diffuse_color.extend(h.primary_exponent).to_array(),
        h1: h.primary_color.extend(h.primary_shift).to_array(),
        h2: h.secondary_color.extend(h.secondary_exponent).to_array(),
        h3: [h.secondary_shift, 0.0, 0.0, 0.0],
    };
    let harness_buf = ctx
        .device
        .create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("test/shading/harness"),
            contents: bytemuck::bytes_of(&harness),
            usage: wgpu::BufferUsages::UNIFORM,
        });
    let map_view = map.create_view(&Default::default());
    let results: Vec<[f32; 4]> = run_cases(
        ctx,
        "test/shading",
        &module,
        cases,
        OUTPUTS,
        &[
            (2, harness_buf.as_entire_binding()),
            (3, wgpu::BindingResource::TextureView(&map_view)),
        ],
    );
    results.into_iter().map(Vec4::from).collect()
}

/// What the CPU twins give for one case, in the harness's output order.
fn run_cpu(c: &Case, map: &cpu::DepthMap<'_>) -> [Vec4; OUTPUTS] {
    let v3 = |a: [f32; 4]| Vec3::new(a[0], a[1], a[2]);
    let (t, l, v, n) = (v3(c.t), v3(c.l), v3(c.v), v3(c.n));
    let (exponent, alpha, d, r, line) = (c.t[3], c.v[3], c.n[3], c.s[0], c.s[1]);
    let color = v3(c.c);
    let acc = Vec4::from(c.acc);
    let kk = cpu::KajiyaKay {
        diffuse: color,
        specular: Vec3::new(0.3, 0.35, 0.4),
        exponent,
    };
    let sample = cpu::HairSample {
        tangent: t,
        shift_tex: c.s[3],
        normal: n,
        spec_mask: c.c[3],
        base_color: color,
        amb_occ: 0.8,
    };
    let m = clip_from_world();
    let p = Vec4::from(c.p);
    let screen = cpu::screen_from_clip(m * p, RESOLUTION);
    let mut tail = cpu::tail_accumulate(cpu::TailAccum::EMPTY, color, alpha);
    tail = cpu::tail_accumulate(tail, Vec3::new(c.k[1], c.k[2], c.k[3]), c.s[3]);
    tail = cpu::tail_accumulate(tail, v * 0.5 + 0.5, d);
    let resolved = cpu::tail_resolve(tail);
    let texel = IVec2::new(c.f[2] as i32, c.f[3] as i32);
    [
        Vec4::new(
            cpu::kajiya_kay_diffuse(t, l),
            cpu::kajiya_kay_specular(t, l, v, exponent),
            cpu::scheuermann_diffuse(n, l),
            cpu::strand_specular(t, v, l, exponent),
        ),
        cpu::kajiya_kay(&kk, t, l, v).extend((1.0 - t.dot(l).powi(2)).max(0.0).sqrt()),
        cpu::shift_tangent(t, n, c.l[3]).extend(0.0),
        cpu::hair_lighting(&lighting(), &sample, l, Vec3::new(1.0, 0.9, 0.8), v).extend(0.0),
        Vec4::new(
            cpu::coverage_from_distance(d, line),
            cpu::tip_fade(c.s[2], line),
            cpu::strand_visibility(d * r, alpha),
            cpu::adsm_visibility(d, r, alpha),
        ),
        Vec4::new(
            screen.x,
            screen.y,
            cpu::strand_coverage(Vec2::new(c.f[0], c.f[1]), p, m, RESOLUTION, line),
            cpu::adsm_depth(c.k[1], d),
        ),
        cpu::blend_under(acc, (color * alpha).extend(alpha)),
        cpu::blend_front_to_back(acc, color, alpha),
        tail.weighted_color.extend(tail.alpha_sum),
        resolved.truncate().extend(tail.transmittance),
        cpu::composite_over_background(acc, color).extend(resolved.w),
        {
            let kk = cpu::KajiyaKay {
                diffuse: Vec3::new(c.c[0], c.c[1], c.c[2]),
                specular: Vec3::new(0.7, 0.5, 0.3),
                exponent: c.t[3],
            };
            let spread = cpu::spread_kajiya_kay(&kk, c.s[3] * 1.2 - 0.1);
            Vec4::new(
                cpu::adsm_pcf(map, texel, c.k[0] as i32, c.k[1], r, alpha),
                spread.exponent,
                spread.specular.y,
                spread.diffuse.x,
            )
        },
    ]
}

const NAMES: [&str; OUTPUTS] = [
    "kajiya_kay_diffuse / kajiya_kay_specular / scheuermann_diffuse / strand_specular",
    "kajiya_kay / sin_from_cos",
    "shift_tangent",
    "hair_lighting",
    "coverage_from_distance / tip_fade / strand_visibility / adsm_visibility",
    "screen_from_clip / strand_coverage / adsm_depth",
    "blend_under",
    "blend_front_to_back",
    "tail_accumulate",
    "tail_resolve / transmittance",
    "composite_over_background / tail alpha",
    "adsm_pcf / spread_kajiya_kay",
];

#[test]
fn shading_wgsl_matches_cpu_twins() {
    let Some(ctx) = common::gpu() else { return };
    let cases = cases();
    let depths = map_depths();
    let map = cpu::DepthMap::new(MAP, MAP, &depths).expect("map");
    let gpu = run_gpu(&ctx, &cases, &depths);
    assert_eq!(gpu.len(), cases.len() * OUTPUTS);
    let mut worst = [0f32; OUTPUTS];
    for (i, case) in cases.iter().enumerate() {
        let want = run_cpu(case, &map);
        for (f, w) in want.iter().enumerate() {
            let g = gpu[i * OUTPUTS + f];
            // Screen coordinates are in pixels: compare them relative to the resolution.
            let scale = if f == 5 {
                Vec4::new(100.0, 100.0, 1.0, 1.0)
            } else {
                Vec4::ONE
            };
            let err = ((g - *w).abs() / (w.abs().max(scale))).max_element();
            worst[f] = worst[f].max(err);
            assert!(
                err < 2e-3,
                "{} differs for case {i}: gpu {g}, cpu {w} ({case:?})",
                NAMES[f]
            );
        }
    }
    eprintln!("worst relative errors: {worst:?}");
    // The grid must exercise the interesting ranges, not only the clamped ends.
    let partial = |f: usize, c: usize| {
        let inside = |x: f32| x > 0.0 && x < 1.0;
        cases
            .iter()
            .filter(|case| inside(run_cpu(case, &map)[f][c]))
            .count()
    };
    assert!(partial(5, 2) > CASES / 20, "too few partial coverages");
    assert!(
        partial(4, 3) > CASES / 4,
        "too few partial ADSM visibilities"
    );
    assert!(partial(11, 0) > CASES / 4, "too few partial PCF results");
}
