//! `tress bench --quality`: every technique's image against the CPU reference ray tracer
//! (`tress-trace`), on the example scenes at several camera distances, as mean FLIP, RMSE and
//! SSIM; and the volume's ambient occlusion alone against the traced AO (the hybrid paper's
//! Figure 5 comparison, as a number).
//!
//! **AO alone.** The renderer has no AO output of its own, so the volume technique renders the
//! scene twice with every light off, once with `volume.ao` on and once off: what remains is the
//! ambient term `ambient · base · AO` and `ambient · base`, and their ratio is the AO the
//! raymarcher applied, per pixel. It is compared with the traced AO image (same `ao_radius`)
//! over the hair only: pixels the hair does not cover (the same hair mask for both) are set to 1
//! in both images, so the head, which has no volume AO on the GPU, does not count.
//!
//! **Silhouettes** ([`super::silhouette`]). Each technique's hair silhouette, from frames
//! without the head, is compared with the reference's (traced without the head at up to 16
//! spp): `hair_iou` is their intersection over union, `stray_pct` the percent of the
//! technique's silhouette outside the strand renderer's dilated by 4 pixels (hair drawn where
//! no strand is).
//!
//! **A converged reference at a matched scale** (issue 36). The reference is traced until its
//! seed pair agrees over the hair ([`tress_trace::converge`]: from `--spp`, doubling, until
//! their matched-scale FLIP is at most `--converge`, or `--max-spp`); the `reference` row is
//! that pair, the noise floor. Every score is also given at a matched scale
//! ([`tress_trace::matched`]: both images box-filtered in linear light by `--scale`, default
//! 3), with the mean linear colour over the hair and its per-channel ratio to the reference's.

use std::path::Path;

use anyhow::{Context, Result};
use glam::Vec3;
use tress_render::session::{Session, TECHNIQUES};
use tress_render::{COLOR_FORMAT, LinearImage, OffscreenTargets};
use tress_scene::Scene;
use tress_trace::converge::{ConvergeSettings, render_converged};
use tress_trace::{
    Aov, DisplayImage, Image, SceneGeometry, TraceSettings, Tracer, matched, metrics,
};

use super::Run;
use super::measure::{camera_at, coverage_pct, hair_mask, scene_at};
use super::quality_report::{csv, markdown};
use super::report::write;
use super::silhouette::{self, DILATION, Silhouette};
use crate::cmd::open::open_session;
use crate::progress;

/// The example scenes measured when no input is given (all generated hair, no download).
const SCENES: [(&str, &str); 3] = [
    ("demo", include_str!("../../../../../scenes/demo.toml")),
    (
        "straight",
        include_str!("../../../../../scenes/straight.toml"),
    ),
    ("curly", include_str!("../../../../../scenes/curly.toml")),
];

/// One score.
pub(super) struct Row {
    pub(super) scene: String,
    pub(super) distance: f32,
    pub(super) coverage_pct: f64,
    pub(super) technique: &'static str,
    /// `color` or `ao`.
    pub(super) aov: &'static str,
    pub(super) result: Result<Score, String>,
    /// The colour rows of the techniques: their silhouette against the reference's.
    pub(super) silhouette: Option<Silhouette>,
    /// The reference this row was scored against: its samples a pixel and its seed pair's
    /// matched-scale FLIP over the hair (its noise floor).
    pub(super) reference: Reference,
}

/// The traced reference of a scene and distance.
#[derive(Clone, Copy, Debug)]
pub(super) struct Reference {
    pub(super) spp: u32,
    pub(super) floor: f64,
    pub(super) converged: bool,
}

/// Which part of the report to run: the techniques (empty: all) and camera distances (empty:
/// the defaults).
pub(crate) struct Select<'a> {
    pub(crate) techniques: &'a [String],
    pub(crate) distances: &'a [f32],
    /// `--shading`, for the report's title (the overrides are already in the run's scene).
    pub(crate) shading: Option<&'a str>,
    /// The reference's convergence (`start_spp` is `--spp`).
    pub(crate) converge: Converge,
}

/// How far the reference is traced: from `spp`, doubling until the seed pair's matched-scale
/// FLIP over the hair is at most `threshold`, or `max_spp`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Converge {
    pub(crate) spp: u32,
    pub(crate) threshold: f64,
    pub(crate) max_spp: u32,
    pub(crate) scale: u32,
}

/// A technique's image scored against the reference.
pub(super) struct Score {
    pub(super) scores: metrics::Scores,
    /// Mean FLIP over the hair's pixels only.
    pub(super) flip_hair: f64,
    /// The same at the matched scale, with the mean colours over the hair.
    pub(super) matched: matched::MatchedScore,
    /// File names of the image and its FLIP map.
    pub(super) image: String,
    pub(super) heat: String,
}

/// A frame as the tracer's linear RGB image (alpha dropped: frames are drawn over an opaque
/// background).
pub(crate) fn linear_to_trace(img: &LinearImage) -> Image {
    Image {
        width: img.width,
        height: img.height,
        pixels: img
            .pixels
            .iter()
            .map(|p| Vec3::new(p[0], p[1], p[2]))
            .collect(),
    }
}

/// The AO the raymarcher applied: `lit / unlit` per pixel where the hair covers it, 1 elsewhere
/// (also where the unlit ambient is too dark to divide by).
fn ao_ratio(with_ao: &LinearImage, without_ao: &LinearImage, mask: &[bool]) -> Image {
    let pixels = with_ao
        .pixels
        .iter()
        .zip(&without_ao.pixels)
        .zip(mask)
        .map(|((a, b), &hair)| {
            let lum = |p: &[f32; 4]| 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2];
            let v = if hair && lum(b) > 1e-5 {
                (lum(a) / lum(b)).clamp(0.0, 1.0)
            } else {
                1.0
            };
            Vec3::splat(v)
        })
        .collect();
    Image {
        width: with_ao.width,
        height: with_ao.height,
        pixels,
    }
}

fn save(img: &Image, path: &Path) -> Result<String> {
    img.save(path)?;
    Ok(path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default())
}

fn score(
    reference: &Image,
    test: &Image,
    mask: &[bool],
    scale: u32,
    dir: &Path,
    stem: &str,
) -> Result<Score> {
    let cmp = metrics::compare(
        &DisplayImage::from_linear(reference),
        &DisplayImage::from_linear(test),
    )?;
    let matched = matched::compare(reference, test, Some(mask), scale)?;
    let image = save(test, &dir.join(format!("{stem}.png")))?;
    let heat = dir.join(format!("{stem}-flip.png"));
    cmp.save_heatmap(&heat)?;
    let heat = heat
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    Ok(Score {
        scores: cmp.scores,
        flip_hair: cmp.masked_flip(mask),
        matched,
        image,
        heat,
    })
}

/// The scenes of the report: the inputs' one, or the examples.
fn scenes(run: &Run) -> Result<Vec<(String, Scene, bool)>> {
    if run.scene_name.starts_with("the built-in demo") {
        SCENES
            .iter()
            .map(|(name, text)| {
                let mut s = Scene::from_str(text, ".")?;
                s.apply_overrides(&run.sets)?;
                Ok(((*name).to_string(), s, false))
            })
            .collect()
    } else {
        Ok(vec![(
            run.scene_name.clone(),
            run.scene.clone(),
            run.auto_frame,
        )])
    }
}

/// Render the report into `run.dir`.
pub(crate) fn run(run: &Run, quick: bool, select: &Select<'_>) -> Result<()> {
    let converge = select.converge;
    let (spp, scale) = (converge.spp, converge.scale);
    let distances: &[f32] = match select.distances {
        [] if quick => &[1.0, 3.0],
        [] => &[1.0, 2.0, 4.0],
        d => d,
    };
    let techniques: Vec<&'static str> = if select.techniques.is_empty() {
        TECHNIQUES.to_vec()
    } else {
        select
            .techniques
            .iter()
            .map(|t| tress_render::session::technique_name(t))
            .collect::<Result<_, _>>()?
    };
    if let Some(d) = distances.iter().find(|d| !(d.is_finite() && **d > 0.0)) {
        anyhow::bail!("--distance must be positive, got {d}");
    }
    let size = if run.size == [1280, 720] || run.size == [320, 180] {
        // The traced reference is the slow part: a smaller default frame.
        if quick { [192, 108] } else { [384, 216] }
    } else {
        run.size
    };
    let mut all = scenes(run)?;
    if quick {
        all.truncate(1);
    }
    let targets = OffscreenTargets::new(&run.ctx, size, COLOR_FORMAT)?;
    let mut rows = Vec::new();
    for (name, scene, auto_frame) in &all {
        let mut scene = scene.clone();
        scene.output.width = size[0];
        scene.output.height = size[1];
        let mut session = open_session(&run.ctx, &scene, *auto_frame, Vec::new(), None)?;
        let mut headless = open_session(
            &run.ctx,
            &silhouette::without_head(&scene),
            *auto_frame,
            Vec::new(),
            None,
        )?;
        for &d in distances {
            let tag = format!("{}-d{d}", slug(name));
            let camera = camera_at(&session, size, d);
            // The hair's pixels (the strand renderer's frame with and without its hair): where
            // the scores over the hair and the reference's convergence are measured.
            let pb = progress::spinner(format!("{name} x{d}: the hair's pixels"));
            let masked = (|| -> Result<_> {
                session.set_technique(&run.ctx, "strands")?;
                session.set_hair_visible(true);
                let img = frame(run, &mut session, &targets, &camera);
                session.set_hair_visible(false);
                let bare = frame(run, &mut session, &targets, &camera);
                session.set_hair_visible(true);
                let (img, bare) = (img?, bare?);
                Ok((hair_mask(&img, &bare), coverage_pct(&img, &bare), bare))
            })();
            pb.finish_and_clear();
            let (mask, coverage, bare) =
                masked.with_context(|| format!("{name}: the hair's pixels"))?;
            // The reference sees exactly the session's scene from the same camera.
            let traced = scene_at(session.scene(), d);
            let settings = TraceSettings {
                spp,
                ..TraceSettings::default()
            };
            let pb = progress::spinner(format!("{name} x{d}: tracing the reference ({spp} spp)"));
            let converged = (|| -> Result<_> {
                let geometry = SceneGeometry::load(&traced)?;
                let mut tracer = Tracer::new(&traced, &geometry, &settings)?;
                let c = render_converged(
                    &mut tracer,
                    Some(&mask),
                    &ConvergeSettings {
                        threshold: converge.threshold,
                        scale,
                        max_spp: converge.max_spp.max(spp),
                    },
                    &|n, floor| {
                        pb.set_message(format!(
                            "{name} x{d}: tracing the reference ({n} spp: seed pair {floor:.4})"
                        ));
                    },
                )?;
                Ok(c)
            })();
            pb.finish_and_clear();
            let converged = converged.with_context(|| format!("{name}: the reference"))?;
            let reference_info = Reference {
                spp: converged.spp,
                floor: converged.floor,
                converged: converged.converged,
            };
            if !converged.converged {
                eprintln!(
                    "warning: {name} x{d}: the reference stopped at {} spp with its seed pair \
                     {:.4} apart over the hair (--converge {}); raise --max-spp to go on",
                    converged.spp, converged.floor, converge.threshold
                );
            }
            let reference = converged.image;
            save(&reference, &run.dir.join(format!("{tag}-reference.png")))?;

            // The silhouettes: the reference's, and the strand renderer's dilated.
            let pb = progress::spinner(format!("{name} x{d}: the hair's silhouette"));
            let outlines = (|| -> Result<_> {
                let bare = silhouette::without_head(&traced);
                let traced_outline = tress_trace::render_reference(
                    &bare,
                    &TraceSettings {
                        spp: spp.min(16),
                        ..settings.clone()
                    },
                )?;
                let reference = silhouette::traced_mask(&traced_outline, bare.background);
                let strands = outline(run, &mut headless, &targets, &camera, "strands")?;
                Ok((reference, silhouette::dilate(&strands, size[0], DILATION)))
            })();
            pb.finish_and_clear();
            let outlines = outlines.with_context(|| format!("{name}: the silhouettes"))?;

            for t in TECHNIQUES {
                if !techniques.contains(&t) {
                    continue;
                }
                let pb = progress::spinner(format!("{name} x{d}: {t}"));
                let result = (|| -> Result<_> {
                    session.set_technique(&run.ctx, t)?;
                    session.set_hair_visible(true);
                    let img = frame(run, &mut session, &targets, &camera)?;
                    score(
                        &reference,
                        &linear_to_trace(&img),
                        &mask,
                        scale,
                        &run.dir,
                        &format!("{tag}-{t}"),
                    )
                })();
                pb.finish_and_clear();
                let outline = outline(run, &mut headless, &targets, &camera, t)
                    .ok()
                    .map(|m| silhouette::compare(&m, &outlines.0, &outlines.1));
                rows.push(Row {
                    scene: name.clone(),
                    distance: d,
                    coverage_pct: coverage,
                    technique: t,
                    aov: "color",
                    result: result.map_err(|e| format!("{e:#}")),
                    silhouette: outline,
                    reference: reference_info,
                });
            }

            // The baseline: the frame without its hair (head and background only), scored like a
            // technique over the hair's pixels. A technique that draws hair at all should beat it
            // clearly; a blank or wrong-coloured one does not.
            rows.push(Row {
                scene: name.clone(),
                distance: d,
                coverage_pct: coverage,
                technique: "none",
                aov: "color",
                result: score(
                    &reference,
                    &linear_to_trace(&bare),
                    &mask,
                    scale,
                    &run.dir,
                    &format!("{tag}-none"),
                )
                .map_err(|e| format!("{e:#}")),
                silhouette: None,
                reference: reference_info,
            });

            // The noise floor: the reference's seed-pair twin (as many samples, other seeds),
            // scored like a technique. No technique can be expected to score better than this.
            rows.push(Row {
                scene: name.clone(),
                distance: d,
                coverage_pct: coverage,
                technique: "reference",
                aov: "color",
                result: score(
                    &reference,
                    &converged.second,
                    &mask,
                    scale,
                    &run.dir,
                    &format!("{tag}-reference-seed2"),
                )
                .map_err(|e| format!("{e:#}")),
                silhouette: None,
                reference: reference_info,
            });

            // The volume's AO alone against the traced AO.
            let pb = progress::spinner(format!("{name} x{d}: ambient occlusion"));
            let result = (|| -> Result<_> {
                let ao_settings = TraceSettings {
                    spp,
                    aov: Aov::Ao,
                    ao_radius: session.prepared().volume.ao_radius,
                    ..TraceSettings::default()
                };
                let traced_ao = tress_trace::render_reference(&traced, &ao_settings)?;
                let masked = Image {
                    width: traced_ao.width,
                    height: traced_ao.height,
                    pixels: traced_ao
                        .pixels
                        .iter()
                        .zip(&mask)
                        .map(|(p, &hair)| if hair { *p } else { Vec3::ONE })
                        .collect(),
                };
                save(&masked, &run.dir.join(format!("{tag}-reference-ao.png")))?;
                let gpu = volume_ao(run, &mut session, &targets, &camera, &mask)?;
                score(
                    &masked,
                    &gpu,
                    &mask,
                    scale,
                    &run.dir,
                    &format!("{tag}-volume-ao"),
                )
            })();
            pb.finish_and_clear();
            rows.push(Row {
                scene: name.clone(),
                distance: d,
                coverage_pct: coverage,
                technique: "volume",
                aov: "ao",
                result: result.map_err(|e| format!("{e:#}")),
                silhouette: None,
                reference: reference_info,
            });
            for r in rows.iter().filter(|r| r.scene == *name && r.distance == d) {
                let outline = r.silhouette.map_or_else(String::new, |s| {
                    format!(", hair IoU {:.3}, stray {:.2}%", s.iou, s.outside_pct)
                });
                match &r.result {
                    Ok(s) => eprintln!(
                        "{} x{} {} {}: FLIP {:.4} (hair {:.4}, at scale {scale} {:.4}) RMSE {:.4} \
                         SSIM {:.3}{outline}{}",
                        r.scene,
                        r.distance,
                        r.technique,
                        r.aov,
                        s.scores.flip,
                        s.flip_hair,
                        s.matched.flip_masked.unwrap_or(f64::NAN),
                        s.scores.rmse,
                        s.scores.ssim,
                        s.matched.color_ratio.map_or_else(String::new, |q| format!(
                            ", colour ratio ({:.3}, {:.3}, {:.3})",
                            q[0], q[1], q[2]
                        ))
                    ),
                    Err(e) => eprintln!(
                        "{} x{} {} {}: failed: {e}",
                        r.scene, r.distance, r.technique, r.aov
                    ),
                }
            }
        }
    }
    write(&run.dir, "quality.csv", &csv(&rows))?;
    let adapter = &run.ctx.adapter_info.name;
    write(
        &run.dir,
        "quality.md",
        &markdown(&rows, adapter, size, converge, select.shading),
    )?;
    println!(
        "wrote the quality report of {} scenes x {} distances into {} ({} scores) on {adapter}",
        all.len(),
        distances.len(),
        run.dir.display(),
        rows.len()
    );
    Ok(())
}

fn slug(name: &str) -> String {
    name.chars()
        .map(|c| if c.is_ascii_alphanumeric() { c } else { '_' })
        .collect::<String>()
        .trim_matches('_')
        .chars()
        .take(40)
        .collect()
}

fn frame(
    run: &Run,
    session: &mut Session,
    targets: &OffscreenTargets,
    camera: &tress_render::Camera,
) -> Result<LinearImage> {
    session.render(&run.ctx, &targets.targets(), camera, None)?;
    Ok(tress_render::read_texture(&run.ctx, &targets.color)?)
}

/// The hair's silhouette in technique `t`'s frame of the head-less `session`: the pixels that
/// change when the hair is hidden.
fn outline(
    run: &Run,
    session: &mut Session,
    targets: &OffscreenTargets,
    camera: &tress_render::Camera,
    t: &str,
) -> Result<Vec<bool>> {
    session.set_technique(&run.ctx, t)?;
    session.set_hair_visible(true);
    let with = frame(run, session, targets, camera);
    session.set_hair_visible(false);
    let without = frame(run, session, targets, camera);
    session.set_hair_visible(true);
    Ok(hair_mask(&with?, &without?))
}

/// The raymarcher's AO (see the module docs): lights off, AO on over AO off.
fn volume_ao(
    run: &Run,
    session: &mut Session,
    targets: &OffscreenTargets,
    camera: &tress_render::Camera,
    mask: &[bool],
) -> Result<Image> {
    session.set_technique(&run.ctx, "volume")?;
    let dark: Vec<_> = session
        .lights()
        .iter()
        .map(|l| tress_render::DirectionalLight {
            intensity: 0.0,
            ..*l
        })
        .collect();
    let was_on = session.prepared().volume.ao;
    let mut render = |ao: bool| -> Result<LinearImage> {
        session.set(&run.ctx, &format!("volume.ao={ao}"))?;
        session.render(&run.ctx, &targets.targets(), camera, Some(&dark))?;
        Ok(tress_render::read_texture(&run.ctx, &targets.color)?)
    };
    let on = render(true);
    let off = render(false);
    session.set(&run.ctx, &format!("volume.ao={was_on}"))?;
    Ok(ao_ratio(&on?, &off?, mask))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn img(v: &[[f32; 4]]) -> LinearImage {
        LinearImage {
            width: v.len() as u32,
            height: 1,
            pixels: v.to_vec(),
        }
    }

    #[test]
    fn ao_ratio_is_lit_over_unlit_on_the_hair_and_one_elsewhere() {
        let on = img(&[[0.01, 0.01, 0.01, 1.0], [0.02, 0.02, 0.02, 1.0], [0.0; 4]]);
        let off = img(&[[0.02, 0.02, 0.02, 1.0], [0.02, 0.02, 0.02, 1.0], [0.0; 4]]);
        let ao = ao_ratio(&on, &off, &[true, false, true]);
        assert!((ao.pixels[0].x - 0.5).abs() < 1e-6);
        assert_eq!(ao.pixels[1], Vec3::ONE, "not hair");
        assert_eq!(ao.pixels[2], Vec3::ONE, "too dark to divide");
    }

    #[test]
    fn the_example_scenes_parse() {
        for (name, text) in SCENES {
            Scene::from_str(text, ".").unwrap_or_else(|e| panic!("{name}: {e}"));
        }
    }
}
