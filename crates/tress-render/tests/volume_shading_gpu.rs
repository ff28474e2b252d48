//! Design rule 6 for the volume: the functions of `shaders/common/volume.wgsl` (volume shadows,
//! local ambient occlusion, ADSM's expected visibility, density gradient and normal, fake
//! transparency and the composite's transmittance and shading points, the strands' optical depth, LOD factor and dither,
//! tangent quantization, hashing, the integrated highlights' lookup and quantization) evaluated on
//! the GPU over a grid of inputs and a small density
//! volume sampled by the hardware's trilinear filter, against the CPU twins in
//! `tress_shading::volume` / `tress_shading::voxelize`.

mod common;

use bytemuck::{Pod, Zeroable};
use common::compute::{Rng, run_cases, test_module};
use glam::{UVec2, Vec3};
use tress_render::shaders;
use tress_shading::{self as cpu, DensityVolume};
use wgpu::util::DeviceExt;

const RES: u32 = 16;
const CASES: usize = 256;
const OUTPUTS: usize = 9;

#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
struct Case {
    x: [f32; 4],
    l: [f32; 4],
    ao: [f32; 4],
    s: [f32; 4],
    p: [f32; 4],
}

/// A blobby density volume with values in quarter steps (exact in the 8-bit texels).
fn densities() -> Vec<f32> {
    let mut d = Vec::with_capacity((RES * RES * RES) as usize);
    let c = Vec3::splat(RES as f32 * 0.5);
    for z in 0..RES {
        for y in 0..RES {
            for x in 0..RES {
                let p = Vec3::new(x as f32, y as f32, z as f32) + 0.5;
                let r = p.distance(c + Vec3::new(1.5, -1.0, 0.5));
                let wave = ((x * 7 + y * 3 + z * 5) % 5) as f32;
                let v = if r < 6.0 { (6.0 - r) * 2.0 + wave } else { 0.0 };
                d.push((v * 4.0).round() / 4.0);
            }
        }
    }
    d
}

fn cases() -> Vec<Case> {
    let mut rng = Rng(0x5eed_1234_abcd_ef01);
    (0..CASES)
        .map(|i| {
            let x = Vec3::new(
                rng.range(2.0, 14.0),
                rng.range(2.0, 14.0),
                rng.range(2.0, 14.0),
            );
            let l = rng.unit();
            Case {
                x: x.extend([0.5, 1.0, 0.75][i % 3]).to_array(),
                l: l.extend(rng.range(0.0, 2.0)).to_array(),
                ao: [
                    rng.range(0.5, 4.0),
                    (1 + i % 24) as f32,
                    rng.range(0.0, 2.0),
                    rng.next(),
                ],
                s: [
                    rng.range(0.0, 6.0),
                    [0.0, 1.0, 4.0][i % 3],
                    rng.range(0.0, 30.0),
                    10.0,
                ],
                p: [
                    if i % 7 == 0 { 10.0 } else { 20.0 },
                    (i % 13) as f32,
                    (i % 9) as f32,
                    (i * 37 % 50_000) as f32,
                ],
            }
        })
        .collect()
}

/// rgb: tangents turning from texel to texel (faded to 0.8), a: the density in quarter strands
/// (the shader reads the texels with a density unit of 0.25).
fn texels(density: &[f32]) -> Vec<[u8; 4]> {
    density
        .iter()
        .enumerate()
        .map(|(i, &d)| {
            let q = d * 4.0;
            assert!(q == q.round() && q <= 255.0, "{d} is not a texel");
            let t = Vec3::new((i % 3) as f32 - 1.0, 1.0, ((i / 16) % 2) as f32 - 0.5);
            cpu::voxelize::encode_texel(t.normalize() * 0.8, q as u32)
        })
        .collect()
}

fn run(ctx: &tress_render::GpuContext, cases: &[Case], density: &[f32]) -> Vec<[f32; 4]> {
    let module = test_module(
        ctx,
        "tests/volume_gpu.wgsl",
        include_str!("volume_gpu.wgsl"),
        "test/volume/shader",
    );
    let view = volume_view(ctx, "test/volume/texture", &texels(density));
    let sampler = ctx.device.create_sampler(&wgpu::SamplerDescriptor {
        label: Some("test/volume/sampler"),
        mag_filter: wgpu::FilterMode::Linear,
        min_filter: wgpu::FilterMode::Linear,
        ..Default::default()
    });
    let highlight_view = volume_view(ctx, "test/volume/highlights", &highlight_texels());
    run_cases(
        ctx,
        "test/volume",
        &module,
        cases,
        OUTPUTS,
        &[
            (2, wgpu::BindingResource::TextureView(&view)),
            (3, wgpu::BindingResource::Sampler(&sampler)),
            (4, wgpu::BindingResource::TextureView(&highlight_view)),
        ],
    )
}

/// A `RES³` texture of the volume's format holding `texels`, x fastest, and its view.
fn volume_view(
    ctx: &tress_render::GpuContext,
    label: &str,
    texels: &[[u8; 4]],
) -> wgpu::TextureView {
    let texture = ctx.device.create_texture_with_data(
        &ctx.queue,
        &wgpu::TextureDescriptor {
            label: Some(label),
            size: wgpu::Extent3d {
                width: RES,
                height: RES,
                depth_or_array_layers: RES,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D3,
            format: tress_render::volume::VOLUME_FORMAT,
            usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
            view_formats: &[],
        },
        wgpu::util::TextureDataOrder::LayerMajor,
        bytemuck::cast_slice(texels),
    );
    texture.create_view(&Default::default())
}

/// Each texel's four highlight bytes: every light different, some zero (empty and lit texels
/// side by side, so the density weighting matters).
fn highlight_texels() -> Vec<[u8; 4]> {
    (0..(RES * RES * RES) as usize)
        .map(|i| {
            let b = |k: usize| ((i * (37 + 16 * k) + 11 * k) % 301).min(255) as u8;
            [b(0), b(1), b(2), b(3)]
        })
        .collect()
}

/// `|gpu - cpu| <= abs + rel · |cpu|`, with a message naming the quantity and the case.
fn close(what: &str, i: usize, gpu: f32, cpu: f32, abs: f32, rel: f32) {
    assert!(
        (gpu - cpu).abs() <= abs + rel * cpu.abs(),
        "{what}, case {i}: GPU {gpu} vs CPU {cpu}"
    );
}

#[test]
fn volume_functions_match_the_cpu_twins() {
    let Some(ctx) = common::gpu() else {
        return;
    };
    let density = densities();
    let vol = DensityVolume::new(RES, &density).expect("volume");
    let cases = cases();
    let out = run(&ctx, &cases, &density);
    let bytes = texels(&density);
    let tangents = cpu::TexelVolume::new(RES, &bytes, 0.25).expect("texels");
    let mut coherences = Vec::new();
    let mut highlight_values = Vec::new();
    // The volume is filtered in the shader in f32 from exact texels (not by the hardware's
    // filter, whose weights have 8 fractional bits on lavapipe), so the marches agree to
    // rounding; the exact functions are compared exactly.
    for (i, c) in cases.iter().enumerate() {
        let r = &out[i * OUTPUTS..(i + 1) * OUTPUTS];
        let x = Vec3::from_slice(&c.x);
        let l = Vec3::from_slice(&c.l);
        let n = c.p[3] as u32;
        for (k, cap) in [(0, cpu::NO_CAP), (6, 1.0)] {
            let shadow = cpu::volume_shadow_strands(&vol, x, l, c.x[3], c.l[3], cap);
            close("volume_shadow_strands", i, r[k][0], shadow, 1e-3, 1e-4);
            let ao = cpu::volume_ao(&vol, x, c.ao[0], c.ao[1] as u32, c.ao[2], c.ao[3], cap);
            close("volume_ao", i, r[k][1], ao, 1e-4, 1e-4);
        }
        close("volume_density", i, r[0][2], vol.sample(x), 1e-4, 1e-5);
        close(
            "fake_transparency_alpha",
            i,
            r[0][3],
            cpu::fake_transparency_alpha(c.s[0], c.s[1]),
            1e-6,
            1e-5,
        );
        close(
            "composite_transmittance",
            i,
            r[6][2],
            cpu::composite_transmittance(c.s[0], c.s[1]),
            1e-6,
            1e-5,
        );
        assert_eq!(
            r[6][3] != 0.0,
            cpu::composite_point_reached(c.ao[3], n % 8, 1 + n % 7),
            "composite_point_reached, case {i}"
        );
        let adsm = cpu::volume_adsm_visibility(
            &vol,
            x,
            l,
            c.x[3],
            c.l[3],
            0.25 * c.ao[0],
            -c.ao[2],
            2.0 * c.ao[3],
        );
        close("volume_adsm_visibility", i, r[7][0], adsm, 1e-4, 1e-4);
        // A texel's round trip: the tangent through the cube-root store.
        let (t, _) =
            cpu::voxelize::decode_texel(cpu::voxelize::encode_texel(l * c.ao[3], 1 + n % 300), 0.5);
        for k in 0..3 {
            close(
                "decode_texel(encode_texel)",
                i,
                r[7][k + 1],
                t[k],
                1e-5,
                1e-4,
            );
        }
        let tangent = if n.is_multiple_of(8) {
            Vec3::ZERO
        } else {
            l * c.ao[3]
        };
        let optical = cpu::strand_optical_depth(
            c.s[0],
            tangent,
            (x - Vec3::splat(8.0)).normalize(),
            c.x[3],
            c.ao[0],
        );
        close("strand_optical_depth", i, r[8][0], optical, 1e-5, 1e-4);
        let coherence = cpu::volume_tangent_coherence(&tangents, x);
        close(
            "volume_tangent_coherence",
            i,
            r[8][1],
            coherence,
            1e-4,
            1e-4,
        );
        coherences.push(coherence);
        // The highlight texture's density-weighted trilinear mean, with the densities of the
        // volume texture's counts (quarter strands).
        let quarter: Vec<f32> = bytes.iter().map(|b| f32::from(b[3]) * 0.25).collect();
        let lit = highlight_texels();
        let hv = cpu::highlights::HighlightVolume::new(RES, &lit, &quarter).expect("highlights");
        let h = cpu::highlights::volume_highlight(&hv, x, (n % 4) as usize);
        close("volume_highlight", i, r[8][2], h, 1e-5, 1e-5);
        highlight_values.push(h);
        let q = cpu::highlights::quantize_highlight(c.ao[3]);
        let t = cpu::highlights::highlight_texel(n % 65025, 255 + n % 65025);
        assert_eq!(
            r[8][3],
            (q * 1000 + u32::from(t)) as f32,
            "quantize_highlight, highlight_texel, case {i}"
        );
        let g = cpu::density_gradient(&vol, x);
        for k in 0..3 {
            close("density_gradient", i, r[1][k], g[k], 1e-4, 1e-4);
        }
        close(
            "lod_factor",
            i,
            r[1][3],
            cpu::lod_factor(c.s[2], c.s[3], c.p[0]),
            1e-5,
            0.0,
        );
        if g.length() > 1.0 {
            let nrm = cpu::density_normal(g, Vec3::Z);
            let dot = Vec3::new(r[2][0], r[2][1], r[2][2]).dot(nrm);
            assert!(dot > 0.99, "density_normal, case {i}: {dot}");
        }
        let px = UVec2::new(c.p[1] as u32, c.p[2] as u32);
        assert_eq!(r[2][3], cpu::dither_threshold(px), "case {i}");
        let off = cpu::ao_offset(n % 64, 64);
        for k in 0..3 {
            close("ao_offset", i, r[3][k], off[k], 1e-4, 0.0);
        }
        assert_eq!(
            r[3][3],
            cpu::voxelize::isqrt(n * 977) as f32,
            "isqrt, case {i}"
        );
        let q = cpu::quantize_tangent(l);
        assert_eq!(
            [r[4][0], r[4][1], r[4][2]],
            q.as_vec3().to_array(),
            "case {i}"
        );
        assert_eq!(r[4][3], (cpu::voxel_hash(n) & 0xffff) as f32, "case {i}");
        let (t0, t1) = cpu::ray_box(x, l, Vec3::splat(2.0), Vec3::splat(RES as f32 - 3.0));
        close("ray_box", i, r[5][0], t0, 1e-4, 1e-5);
        close("ray_box", i, r[5][1], t1, 1e-4, 1e-5);
        let m = cpu::dequantize_tangent(Vec3::new(200.0, 30.0, 510.0), 2.0);
        close("dequantize_tangent", i, r[5][2], m.x, 1e-6, 0.0);
        close("dequantize_tangent", i, r[5][3], m.y, 1e-6, 0.0);
    }
    // The tangents turn: the coherence is well below 1 somewhere in the hair.
    assert!(
        coherences.iter().any(|&c| c < 0.9),
        "{:?}",
        coherences.iter().copied().fold(1.0f32, f32::min)
    );
    // The highlights vary over the cases (the lookup reads different texels and lights).
    let (lo, hi) = highlight_values
        .iter()
        .fold((f32::MAX, f32::MIN), |(a, b), &h| (a.min(h), b.max(h)));
    assert!(hi - lo > 0.3, "highlights {lo}..{hi}");
    // The grid is not trivial: the shadow rays met strands, the AO varied.
    let shadows: f32 = cases
        .iter()
        .enumerate()
        .map(|(i, _)| out[i * OUTPUTS][0])
        .sum();
    assert!(shadows > 100.0, "{shadows}");
}

#[test]
fn volume_harness_validates() {
    let text = shaders::compose_source("tests/volume_gpu.wgsl", include_str!("volume_gpu.wgsl"))
        .expect("composes");
    let module = naga::front::wgsl::parse_str(&text).expect("parses");
    naga::valid::Validator::new(naga::valid::ValidationFlags::all(), Default::default())
        .validate(&module)
        .expect("validates");
}
