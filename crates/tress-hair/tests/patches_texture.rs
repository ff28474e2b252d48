//! Tests of the procedural patch textures.

use glam::Vec3;
use tress_hair::patches::texture::{
    alpha_texture, base_texture, spec_noise_texture, spec_shift_texture,
};
use tress_hair::patches::{AoParams, HairTextures, Texture, TextureParams};

fn small() -> TextureParams {
    TextureParams {
        width: 96,
        height: 128,
        strands: 24,
        ..TextureParams::default()
    }
}

/// Mean absolute difference between neighbouring texels along x (across) and along y (along the
/// hair) of channel 0.
fn gradients(t: &Texture) -> (f32, f32) {
    let (mut dx, mut dy) = (0.0, 0.0);
    for y in 0..t.height - 1 {
        for x in 0..t.width - 1 {
            dx += (t.get(x + 1, y, 0) - t.get(x, y, 0)).abs();
            dy += (t.get(x, y + 1, 0) - t.get(x, y, 0)).abs();
        }
    }
    let n = ((t.width - 1) * (t.height - 1)) as f32;
    (dx / n, dy / n)
}

#[test]
fn textures_have_their_sizes_ranges_and_are_deterministic() {
    let p = small();
    let all = HairTextures::generate(&p).unwrap();
    for (t, channels) in [
        (&all.base, 3),
        (&all.alpha, 1),
        (&all.spec_shift, 1),
        (&all.spec_noise, 1),
    ] {
        assert_eq!((t.width, t.height, t.channels), (96, 128, channels));
        assert_eq!(t.data.len(), (96 * 128 * channels) as usize);
        assert!(t.data.iter().all(|v| (0.0..=1.0).contains(v)));
        assert_eq!(t.to_u8().len(), t.data.len());
    }
    assert_eq!(all, HairTextures::generate(&p).unwrap());
    let other = HairTextures::generate(&TextureParams { seed: 5, ..p }).unwrap();
    assert_ne!(all.base, other.base);
    assert_ne!(all.alpha, other.alpha);
    assert_ne!(all.spec_shift, other.spec_shift);
    assert_ne!(all.spec_noise, other.spec_noise);
    assert_eq!(all.base, base_texture(&p).unwrap());
}

#[test]
fn base_is_noise_stretched_along_the_hair_in_the_base_color() {
    let p = small();
    let base = base_texture(&p).unwrap();
    let (dx, dy) = gradients(&base);
    assert!(
        dx > 3.0 * dy,
        "streaks run along v: across {dx}, along {dy}"
    );
    for texel in base.data.chunks_exact(3) {
        let c = Vec3::from_slice(texel);
        // A shade of the base color between 1 - contrast and 1.
        let shade = c.x / p.base_color.x;
        assert!((c - p.base_color * shade).length() < 1e-5);
        assert!(
            (1.0 - p.contrast - 1e-5..=1.0 + 1e-5).contains(&shade),
            "{shade}"
        );
    }
}

#[test]
fn alpha_is_opaque_in_the_middle_and_fades_at_the_tips_and_edges() {
    let p = small();
    let alpha = alpha_texture(&p).unwrap();
    let at = |u: f32, v: f32| {
        let x = ((u * p.width as f32) as u32).min(p.width - 1);
        let y = ((v * p.height as f32) as u32).min(p.height - 1);
        alpha.get(x, y, 0)
    };
    // The middle: strands whose centre is at least `edge` from the border, rows above the
    // shortest strand's fade.
    let cell = 1.0 / p.strands as f32;
    let mut opaque = 0;
    for y in 0..p.height {
        let v = (y as f32 + 0.5) / p.height as f32;
        for x in 0..p.width {
            let u = (x as f32 + 0.5) / p.width as f32;
            let centre = ((u / cell).floor() + 0.5) * cell;
            let middle = centre.min(1.0 - centre) >= p.edge && u.min(1.0 - u) >= p.edge;
            if middle && v <= p.tip_start - p.tip_fade {
                assert_eq!(alpha.get(x, y, 0), 1.0, "({u}, {v})");
                opaque += 1;
            }
        }
    }
    assert!(opaque as f32 > 0.3 * (p.width * p.height) as f32);
    // Past the longest strand nothing is left; the border columns are empty.
    for u in [0.1, 0.3, 0.5, 0.7, 0.9] {
        assert_eq!(at(u, 0.999), 0.0, "tip at u = {u}");
    }
    for y in 0..p.height {
        assert!(alpha.get(0, y, 0) < 0.1 && alpha.get(p.width - 1, y, 0) < 0.1);
    }
    // The default texture's mean coverage, which the AO bake's default patch opacity (0.55)
    // stands for.
    let full = alpha_texture(&TextureParams::default()).unwrap();
    let mean = full.data.iter().sum::<f32>() / full.data.len() as f32;
    assert!((mean - 0.55).abs() < 0.05, "mean alpha {mean}");
    assert_eq!(AoParams::default().patch_opacity, 0.55);
    // Strands end at different lengths: the tip rows are partly transparent.
    let row = (0.85 * p.height as f32) as u32;
    let values: Vec<f32> = (0..p.width).map(|x| alpha.get(x, row, 0)).collect();
    assert!(
        values.contains(&0.0) && values.iter().any(|&a| a > 0.5),
        "{values:?}"
    );
}

#[test]
fn specular_shift_is_centred_and_sparkles_are_sparse() {
    let p = small();
    let shift = spec_shift_texture(&p).unwrap();
    let n = shift.data.len() as f32;
    let mean = shift.data.iter().sum::<f32>() / n;
    assert!((mean - 0.5).abs() < 0.05, "mean shift {mean}");
    assert!(
        shift
            .data
            .iter()
            .all(|v| (v - 0.5).abs() <= p.shift_amplitude + 1e-6)
    );
    assert!(
        shift
            .data
            .iter()
            .any(|v| (v - 0.5).abs() > 0.5 * p.shift_amplitude)
    );

    let sparkle = spec_noise_texture(&p).unwrap();
    let dark = sparkle.data.iter().filter(|&&v| v == 0.0).count() as f32;
    let bright = sparkle.data.iter().filter(|&&v| v > 0.25).count() as f32;
    let total = sparkle.data.len() as f32;
    assert!(dark > 0.3 * total, "mostly dark: {}", dark / total);
    assert!(
        bright > 0.01 * total && bright < 0.4 * total,
        "sparse glints: {}",
        bright / total
    );
    // No shift amplitude: no shift at all.
    let flat = spec_shift_texture(&TextureParams {
        shift_amplitude: 0.0,
        ..p
    })
    .unwrap();
    assert!(flat.data.iter().all(|&v| v == 0.5));
}

#[test]
fn textures_tile_across_u() {
    // The noise is periodic in u: the last column continues into the first like any two
    // neighbouring columns do.
    let base = spec_shift_texture(&TextureParams {
        width: 256,
        ..small()
    })
    .unwrap();
    let (dx, _) = gradients(&base);
    let wrap: f32 = (0..base.height)
        .map(|y| (base.get(0, y, 0) - base.get(base.width - 1, y, 0)).abs())
        .sum::<f32>()
        / base.height as f32;
    assert!(wrap < 4.0 * dx + 1e-3, "seam {wrap} vs neighbours {dx}");
}

#[test]
fn bad_parameters_are_errors() {
    for bad in [
        TextureParams {
            width: 0,
            ..small()
        },
        TextureParams {
            height: 100_000,
            ..small()
        },
        TextureParams {
            strands: 0,
            ..small()
        },
        TextureParams {
            strands: 1000,
            ..small()
        },
        TextureParams {
            edge: 0.7,
            ..small()
        },
        TextureParams {
            tip_start: f32::NAN,
            ..small()
        },
        TextureParams {
            sparkle_threshold: 1.0,
            ..small()
        },
        TextureParams {
            base_color: Vec3::new(-1.0, 0.0, 0.0),
            ..small()
        },
    ] {
        assert!(HairTextures::generate(&bad).is_err(), "{bad:?}");
    }
}
