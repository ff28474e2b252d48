//! `tress reference` under `strands.shading = "marschner"` (Chiang et al. 2016's fibres in the
//! path tracer) against Mitsuba 3, an outside renderer: the committed images
//! `docs/mitsuba/{blond,dark}-mitsuba.png` were rendered by Mitsuba 3.9.1 (`scalar_rgb`, its
//! `hair` BSDF on B-spline curves through the same strands) from the scene files beside them by
//! `docs/mitsuba/compare.py` (the command is in `docs/mitsuba/README.md`). CPU only.
//!
//! The test traces each scene at few samples (the CI machine's budget). Two measures:
//!
//! - mean FLIP over the frame and over the hair, as `compare.py` reports them; at this sample
//!   count they are dominated by the tracer's noise, so their bounds only catch gross errors;
//! - the mean linear colour of 10×10-pixel tiles, which averages the noise away: the mean
//!   absolute difference of the tiles relative to the Mitsuba image's mean. This one tells
//!   fibres apart that differ by a little: the test checks that the other scene's fibre and the
//!   blond fibre with `beta_m` 0.3 → 0.4 both fail its bound.
//!
//! The converged figures are in `docs/mitsuba/README.md`.

mod common;

use std::path::{Path, PathBuf};

use common::{tmp, tress};

/// Samples per pixel of the traced images (both scenes: about 20 s each in the test profile).
const SPP: &str = "32";

/// The mean FLIP over the hair's pixels each scene must stay under at `SPP`.
const HAIR_FLIP_MAX: f64 = 0.15;

/// The frame's mean FLIP bound at `SPP`.
const FRAME_FLIP_MAX: f64 = 0.085;

/// The tiles' relative colour error bound (see the module docs).
const TILE_ERROR_MAX: f64 = 0.015;

/// Tile size in pixels.
const TILE: u32 = 10;

/// The sky's radiance and bounces `compare.py` renders both sides with.
const SETS: [&str; 4] = ["--set", "trace.ambient=0.08", "--set", "trace.bounces=32"];

fn mitsuba_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../docs/mitsuba")
}

fn rgb8(path: &Path) -> image::RgbImage {
    image::open(path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .to_rgb8()
}

/// The scene's `background` as the 8-bit sRGB PNGs store it.
fn background8(scene: &Path) -> [u8; 3] {
    let text = std::fs::read_to_string(scene).unwrap();
    let line = text
        .lines()
        .find(|l| l.starts_with("background"))
        .expect("background");
    let inner = &line[line.find('[').unwrap() + 1..line.find(']').unwrap()];
    let v: Vec<f32> = inner
        .split(',')
        .map(|x| x.trim().parse().unwrap())
        .collect();
    [0, 1, 2].map(|i| {
        let c = v[i].clamp(0.0, 1.0);
        let s = if c <= 0.003_130_8 {
            c * 12.92
        } else {
            1.055 * c.powf(1.0 / 2.4) - 0.055
        };
        (s * 255.0 + 0.5) as u8
    })
}

/// Trace `name`'s scene at `SPP` into a PNG (`tag` names the file), with extra `--set`s.
fn trace(name: &str, tag: &str, extra: &[&str]) -> PathBuf {
    let scene = mitsuba_dir().join(format!("{name}.toml"));
    let png = tmp(&format!("{tag}-tress.png"));
    let mut args = vec![
        "reference",
        scene.to_str().unwrap(),
        "-o",
        png.to_str().unwrap(),
        "--spp",
        SPP,
    ];
    args.extend(SETS);
    for set in extra {
        args.extend(["--set", set]);
    }
    let out = tress(&args);
    assert!(
        out.status.success(),
        "tress reference {name}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    png
}

/// Mean FLIP of `test` against `reference` over the frame and over the pixels where either
/// differs from the background (as `compare.py` scores them), through `tress compare-images`.
fn flip(reference: &Path, test: &Path, background: [u8; 3]) -> (f64, f64) {
    let (a, b) = (rgb8(reference), rgb8(test));
    assert_eq!(a.dimensions(), b.dimensions());
    let differs =
        |p: &image::Rgb<u8>| (0..3).any(|c| (i32::from(p[c]) - i32::from(background[c])).abs() > 1);
    let mask = image::GrayImage::from_fn(a.width(), a.height(), |x, y| {
        let hair = differs(a.get_pixel(x, y)) || differs(b.get_pixel(x, y));
        image::Luma([if hair { 255 } else { 0 }])
    });
    let mask_path = tmp(&format!(
        "{}-mask.png",
        test.file_stem().unwrap().to_string_lossy()
    ));
    mask.save(&mask_path).unwrap();
    let out = tress(&[
        "compare-images",
        reference.to_str().unwrap(),
        test.to_str().unwrap(),
        "--json",
        "--mask",
        mask_path.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{out:?}");
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    (
        json["flip"].as_f64().unwrap(),
        json["flip_masked"].as_f64().unwrap(),
    )
}

/// The mean linear colour of each `TILE`² tile (8-bit sRGB decoded).
fn tiles(img: &image::RgbImage) -> Vec<[f64; 3]> {
    let decode = |v: u8| {
        let c = f64::from(v) / 255.0;
        if c <= 0.04045 {
            c / 12.92
        } else {
            ((c + 0.055) / 1.055).powf(2.4)
        }
    };
    let (w, h) = (img.width() / TILE, img.height() / TILE);
    let mut out = Vec::new();
    for ty in 0..h {
        for tx in 0..w {
            let mut sum = [0.0; 3];
            for y in ty * TILE..(ty + 1) * TILE {
                for x in tx * TILE..(tx + 1) * TILE {
                    let p = img.get_pixel(x, y);
                    for c in 0..3 {
                        sum[c] += decode(p[c]);
                    }
                }
            }
            out.push(sum.map(|s| s / f64::from(TILE * TILE)));
        }
    }
    out
}

/// The tiles' mean absolute colour difference over the reference tiles' mean colour.
fn tile_error(reference: &Path, test: &Path) -> f64 {
    let (a, b) = (tiles(&rgb8(reference)), tiles(&rgb8(test)));
    let n = (a.len() * 3) as f64;
    let diff: f64 = a
        .iter()
        .zip(&b)
        .map(|(p, q)| (0..3).map(|c| (p[c] - q[c]).abs()).sum::<f64>())
        .sum();
    let mean: f64 = a.iter().map(|p| p.iter().sum::<f64>()).sum();
    (diff / n) / (mean / n)
}

#[test]
fn marschner_reference_agrees_with_mitsuba() {
    let dir = mitsuba_dir();
    let scenes = ["blond", "dark"];
    let traced: Vec<PathBuf> = scenes.iter().map(|n| trace(n, n, &[])).collect();
    let background = background8(&dir.join("blond.toml"));
    assert_eq!(background, background8(&dir.join("dark.toml")));
    for (i, name) in scenes.iter().enumerate() {
        let mitsuba = dir.join(format!("{name}-mitsuba.png"));
        let (frame, hair) = flip(&mitsuba, &traced[i], background);
        let tile = tile_error(&mitsuba, &traced[i]);
        eprintln!(
            "{name}: FLIP against Mitsuba {frame:.4} (hair {hair:.4}), tile error {tile:.4} at \
             {SPP} spp"
        );
        assert!(
            hair <= HAIR_FLIP_MAX && frame <= FRAME_FLIP_MAX && tile <= TILE_ERROR_MAX,
            "{name}: FLIP against Mitsuba {frame:.4} (hair {hair:.4}), tile error {tile:.4}; \
             bounds {FRAME_FLIP_MAX} ({HAIR_FLIP_MAX}), {TILE_ERROR_MAX}"
        );
        // The other fibre against this Mitsuba image: the comparison tells the fibres apart.
        let wrong = tile_error(&mitsuba, &traced[1 - i]);
        eprintln!("{name}: the other scene's fibre: tile error {wrong:.4}");
        assert!(
            wrong > 3.0 * TILE_ERROR_MAX,
            "{name}: the wrong fibre's tile error {wrong:.4} is near the bound {TILE_ERROR_MAX}"
        );
    }
    // A small change of one fibre parameter fails the tile bound too.
    let rougher = trace("blond", "blond-rough", &["hair.0.material.beta_m=0.4"]);
    let tile = tile_error(&dir.join("blond-mitsuba.png"), &rougher);
    eprintln!("blond with beta_m 0.4: tile error {tile:.4}");
    assert!(
        tile > TILE_ERROR_MAX,
        "beta_m 0.3 -> 0.4 passes the tile bound ({tile:.4} <= {TILE_ERROR_MAX})"
    );
}
