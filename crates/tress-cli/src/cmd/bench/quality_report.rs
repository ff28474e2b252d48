//! The files of `tress bench --quality`: `quality.csv` (one line a score) and `quality.md`.

use super::quality::{Converge, Row};

/// A ratio triple as `r / g / b`, or empty.
fn ratio_cells(r: Option<[f64; 3]>, sep: &str) -> String {
    r.map_or_else(
        || [""; 3].join(sep),
        |q| format!("{:.4}{sep}{:.4}{sep}{:.4}", q[0], q[1], q[2]),
    )
}

pub(super) fn csv(rows: &[Row]) -> String {
    let mut out = String::from(
        "scene,distance,coverage_pct,technique,aov,flip,rmse,ssim,flip_hair,image,heatmap,\
         hair_iou,stray_pct,scale,flip_hair_matched,mean_r,mean_g,mean_b,ratio_r,ratio_g,\
         ratio_b,reference_spp,reference_floor,reference_converged,error\n",
    );
    for r in rows {
        let scene = r.scene.replace([',', '"', '\n'], "_");
        let outline = r.silhouette.map_or_else(
            || ",".to_owned(),
            |s| format!("{:.4},{:.3}", s.iou, s.outside_pct),
        );
        let reference = format!(
            "{},{:.5},{}",
            r.reference.spp, r.reference.floor, r.reference.converged
        );
        match &r.result {
            Ok(s) => {
                let m = &s.matched;
                out.push_str(&format!(
                    "{scene},{},{:.3},{},{},{:.5},{:.5},{:.4},{:.5},{},{},{outline},{},{},{},{},\
                     {reference},\n",
                    r.distance,
                    r.coverage_pct,
                    r.technique,
                    r.aov,
                    s.scores.flip,
                    s.scores.rmse,
                    s.scores.ssim,
                    s.flip_hair,
                    s.image,
                    s.heat,
                    m.scale,
                    m.flip_masked
                        .map_or_else(String::new, |f| format!("{f:.5}")),
                    ratio_cells(m.mean_test, ","),
                    ratio_cells(m.color_ratio, ","),
                ));
            }
            Err(e) => out.push_str(&format!(
                "{scene},{},{:.3},{},{},,,,,,,{outline},,,,,,,,,{reference},\"{}\"\n",
                r.distance,
                r.coverage_pct,
                r.technique,
                r.aov,
                e.replace('"', "'")
            )),
        }
    }
    out
}

pub(super) fn markdown(
    rows: &[Row],
    adapter: &str,
    size: [u32; 2],
    converge: Converge,
    shading: Option<&str>,
) -> String {
    let shading = match shading {
        Some("marschner") => "Shading: **Marschner** (`--shading marschner`: strands, volume, \
             hybrid and patches shade the `[hair.material]` fibre; SATF keeps its paper's \
             lighting), against the path-traced reference with Chiang et al. 2016's fibres."
            .to_string(),
        Some(model) => format!(
            "Shading: **{model}** (`--shading {model}`), the reference evaluating the same model."
        ),
        None => "Shading: the scenes' own (Kajiya-Kay unless a scene says otherwise), the \
                 reference evaluating the same model."
            .to_string(),
    };
    let s = converge.scale;
    let mut md = format!(
        "# tress image quality\n\n{shading}\n\nEvery technique against the CPU reference ray tracer \
         (`tress-trace`), {}x{}, GPU images from **{adapter}**. The reference is traced from {} \
         samples per pixel, doubling until its seed pair's FLIP over the hair at scale {s} is at \
         most {} (or {} spp): the spp each took and that floor are in the reference column. \
         FLIP is the mean FLIP error over the frame (0 identical, lower is better), FLIP on \
         hair its mean over the pixels the hair covers (which the background does not dilute); \
         at scale {s}, the same after both images are box-filtered {s}×{s} in linear light (the \
         reference's noise and the strands' pixel texture averaged away, what remains is the \
         model's); colour ratio is the mean linear colour over the hair divided by the \
         reference's, per channel (R / G / B). \
         The `reference` row is the reference's seed-pair twin: its noise, \
         a floor no technique can beat; the `none` row is the frame \
         without its hair (head and background), the baseline every technique must beat on \
         the hair; the AO row compares the \
         volume's ambient occlusion alone with the traced AO over the hair (see \
         `crates/tress-cli/src/cmd/bench/quality.rs`); hair IoU compares the technique's hair \
         silhouette with the reference's and stray % is the share of it outside the strand \
         renderer's silhouette dilated by 4 pixels (both without the head). Distances are \
         multiples of the scene camera's.\n\n| scene | distance | coverage % | technique | aov | \
         FLIP | FLIP on hair | FLIP on hair, scale {s} | colour ratio | RMSE | SSIM | hair IoU | \
         stray % | reference: spp, floor | image | FLIP map |\n\
         | --- | ---: | ---: | --- | --- | ---: | ---: | ---: | --- | ---: | ---: | ---: | ---: | \
         --- | --- | --- |\n",
        size[0], size[1], converge.spp, converge.threshold, converge.max_spp
    );
    for r in rows {
        let outline = r.silhouette.map_or_else(
            || " | ".to_owned(),
            |s| format!("{:.3} | {:.2}", s.iou, s.outside_pct),
        );
        let reference = format!(
            "{}, {:.4}{}",
            r.reference.spp,
            r.reference.floor,
            if r.reference.converged {
                ""
            } else {
                " (not converged)"
            }
        );
        match &r.result {
            Ok(s) => md.push_str(&format!(
                "| {} | {} | {:.2} | {} | {} | {:.4} | {:.4} | {} | {} | {:.4} | {:.3} | {outline} | \
                 {reference} | ![]({}) | ![]({}) |\n",
                r.scene,
                r.distance,
                r.coverage_pct,
                r.technique,
                r.aov,
                s.scores.flip,
                s.flip_hair,
                s.matched
                    .flip_masked
                    .map_or_else(String::new, |f| format!("{f:.4}")),
                ratio_cells(s.matched.color_ratio, " / "),
                s.scores.rmse,
                s.scores.ssim,
                s.image,
                s.heat
            )),
            Err(e) => md.push_str(&format!(
                "| {} | {} | {:.2} | {} | {} | failed: {e} | | | | | | {outline} | {reference} | | |\n",
                r.scene, r.distance, r.coverage_pct, r.technique, r.aov
            )),
        }
    }
    md.push_str(
        "\nReferences: `*-reference.png` (color), `*-reference-seed2.png` (its seed-pair twin) \
         and `*-reference-ao.png` (AO over the hair).\n",
    );
    md
}
