//! SATF draws hair only where the strands are: clusters fitted to a ponytail whose strands have
//! very different lengths (what the fit got wrong on real assets: giant fans from the bottom of
//! the hair, spikes above the head) put every hair pixel inside the strand renderer's silhouette
//! of the same view dilated by 4 pixels. Both silhouettes are the pixels that change when the
//! hair is hidden, without a head (so no technique's shadows count).

mod common;

use tress_hair::generate::{Style, StyleParams, generate};
use tress_hair::rng::Rng;
use tress_hair::{HairAsset, formats};
use tress_render::read_texture;
use tress_render::session::{Session, SessionOptions, scene_from_inputs};
use tress_render::{COLOR_FORMAT, GpuContext, LinearImage, OffscreenTargets, TargetFormats};

const SIZE: [u32; 2] = [192, 108];
const DILATION: i64 = 4;

/// The generated ponytail, 3,000 strands, each cut to a random 25–100% of its vertices.
fn varied_ponytail() -> HairAsset {
    let params = StyleParams {
        strands: 3000,
        vertices: 13,
        ..Style::Ponytail.default_params()
    };
    let full = generate(Style::Ponytail, &params).unwrap();
    let mut rng = Rng::new(8);
    let mut positions = Vec::new();
    let mut counts = Vec::new();
    for s in 0..full.strand_count() {
        let strand = full.strand(s);
        let keep = ((strand.len() as f32 * rng.range(0.25, 1.0)).ceil() as usize).max(2);
        positions.extend_from_slice(&strand[..keep]);
        counts.push(keep as u32);
    }
    HairAsset::from_counts(positions, &counts).unwrap()
}

fn session_on(ctx: &GpuContext, path: &std::path::Path) -> Session {
    let (scene, auto_frame) = scene_from_inputs(&[path.to_path_buf()]).unwrap();
    let options = SessionOptions {
        auto_frame,
        satf_database: Some(Box::new(|_| Ok(common::small_satf_database(48)))),
        ..SessionOptions::default()
    };
    Session::new(ctx, TargetFormats::default(), scene, options).unwrap()
}

fn frame(ctx: &GpuContext, s: &mut Session, t: &OffscreenTargets) -> LinearImage {
    let camera = s.camera(SIZE);
    s.render(ctx, &t.targets(), &camera, None).unwrap();
    read_texture(ctx, &t.color).unwrap()
}

/// The pixels technique `name` changes when the hair is shown.
fn silhouette(ctx: &GpuContext, s: &mut Session, t: &OffscreenTargets, name: &str) -> Vec<bool> {
    s.set_technique(ctx, name).unwrap();
    s.set_hair_visible(true);
    let with = frame(ctx, s, t);
    s.set_hair_visible(false);
    let without = frame(ctx, s, t);
    s.set_hair_visible(true);
    with.pixels
        .iter()
        .zip(&without.pixels)
        .map(|(a, b)| (0..3).any(|c| (a[c] - b[c]).abs() > 1.0 / 255.0))
        .collect()
}

fn dilate(mask: &[bool]) -> Vec<bool> {
    let (w, h) = (i64::from(SIZE[0]), i64::from(SIZE[1]));
    let mut out = vec![false; mask.len()];
    for (i, _) in mask.iter().enumerate().filter(|(_, m)| **m) {
        let (x, y) = (i as i64 % w, i as i64 / w);
        for dy in -DILATION..=DILATION {
            for dx in -DILATION..=DILATION {
                let (nx, ny) = (x + dx, y + dy);
                if dx * dx + dy * dy <= DILATION * DILATION
                    && (0..w).contains(&nx)
                    && (0..h).contains(&ny)
                {
                    out[(ny * w + nx) as usize] = true;
                }
            }
        }
    }
    out
}

#[test]
fn satf_hair_lies_inside_the_strands_silhouette() {
    let Some(ctx) = common::gpu() else { return };
    let dir = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("satf-silhouette");
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("varied-ponytail.hair");
    formats::write_path(&path, &varied_ponytail()).unwrap();
    let mut s = session_on(&ctx, &path);
    assert!(
        s.prepared().head.is_none(),
        "hair files are drawn without a head"
    );
    let targets = OffscreenTargets::new(&ctx, SIZE, COLOR_FORMAT).unwrap();
    let strands = silhouette(&ctx, &mut s, &targets, "strands");
    let satf = silhouette(&ctx, &mut s, &targets, "satf");
    let allowed = dilate(&strands);
    let drawn = satf.iter().filter(|m| **m).count();
    let stray = satf
        .iter()
        .zip(&allowed)
        .filter(|(m, a)| **m && !**a)
        .count();
    let covered = strands.iter().filter(|m| **m).count();
    eprintln!(
        "strands cover {covered} pixels, SATF {drawn}, of which {stray} lie outside the strands' \
         silhouette dilated by {DILATION} px"
    );
    // Red: SATF outside the dilated silhouette; grey: the dilated silhouette; white: SATF.
    let picture = image::RgbImage::from_fn(SIZE[0], SIZE[1], |x, y| {
        let i = (y * SIZE[0] + x) as usize;
        image::Rgb(match (satf[i], allowed[i]) {
            (true, false) => [255, 0, 0],
            (true, true) => [255, 255, 255],
            (false, true) => [90, 90, 90],
            (false, false) => [0, 0, 0],
        })
    });
    picture.save(dir.join("silhouettes.png")).unwrap();
    assert!(
        drawn > covered / 2,
        "SATF draws the hair: {drawn} of {covered} pixels"
    );
    let inter = satf
        .iter()
        .zip(&strands)
        .filter(|(a, b)| **a && **b)
        .count();
    let union = satf
        .iter()
        .zip(&strands)
        .filter(|(a, b)| **a || **b)
        .count();
    let iou = inter as f64 / union.max(1) as f64;
    eprintln!("SATF's hair mask against the strands': IoU {iou:.3}");
    // Measured on lavapipe: none of 1,308 pixels outside and IoU 0.938. Before groups of 8 to
    // 15 strands could be split (step 7 of the fit), 4 of 1,421 lay outside at the tie: a group
    // of 15 strands from two patches of scalp (the side of the head and the back) converging
    // there, whose shell spanned the gap between them. The fit before issue 13 drew fans and spikes far
    // outside: 70% on a real ponytail.
    assert!(iou >= 0.9, "IoU {iou} with the strands' hair mask");
    assert!(
        stray == 0,
        "{stray} of SATF's {drawn} hair pixels ({:.2}%) lie outside the strands' silhouette \
         dilated by {DILATION} px (red in {})",
        100.0 * stray as f64 / drawn as f64,
        dir.join("silhouettes.png").display()
    );
}
