//! The benchmark's outputs: a CSV per sweep, charts, and the Markdown summary.

use std::fmt::Write as _;
use std::path::Path;

use anyhow::{Context, Result};

use super::chart::{BarChart, LineChart, Series, bar_chart, line_chart, tick};
use super::measure::Measurement;
use super::sweeps::Sweep;

/// One technique at one point of a sweep.
#[derive(Clone, Debug)]
pub(crate) struct Row {
    pub(crate) technique: &'static str,
    pub(crate) x: f64,
    /// The measurement, or why the point could not be measured.
    pub(crate) result: Result<Measurement, String>,
}

const MIB: f64 = (1u64 << 20) as f64;

/// The CSV header (memory columns in bytes).
pub(crate) const CSV_HEADER: &str = "sweep,technique,x,frame_ms,timing,wall_ms,coverage_pct,\
mem_geometry,mem_oit,mem_volumes,mem_shadow_maps,mem_textures,mem_database,mem_total,frames,\
passes,oit,oit_fragments,oit_lost,flip,error";

fn csv_field(s: &str) -> String {
    if s.contains([',', '"', '\n']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

/// The CSV text of a sweep's rows.
pub(crate) fn csv(sweep: &Sweep, rows: &[Row]) -> String {
    let mut out = String::from(CSV_HEADER);
    out.push('\n');
    for r in rows {
        match &r.result {
            Ok(m) => {
                let mem = m.memory.rows().map(|(_, b)| b.to_string()).join(",");
                let passes = m
                    .passes
                    .iter()
                    .map(|(n, ms)| format!("{n}={ms:.4}"))
                    .collect::<Vec<_>>()
                    .join(";");
                let oit = m.oit.map_or(",,".to_string(), |o| {
                    format!("{},{},{}", o.kind.name(), o.fragments, o.lost)
                });
                let flip = m.flip.map_or(String::new(), |f| format!("{f:.5}"));
                let _ = writeln!(
                    out,
                    "{},{},{},{:.4},{},{:.4},{:.3},{mem},{},{},{},{oit},{flip},",
                    sweep.name,
                    r.technique,
                    r.x,
                    m.frame_ms,
                    m.timing.name(),
                    m.wall_ms,
                    m.coverage_pct,
                    m.memory.total(),
                    m.frames,
                    csv_field(&passes)
                );
            }
            Err(e) => {
                let _ = writeln!(
                    out,
                    "{},{},{},,,,,,,,,,,,,,,,,,{}",
                    sweep.name,
                    r.technique,
                    r.x,
                    csv_field(e)
                );
            }
        }
    }
    out
}

fn ok(rows: &[Row]) -> impl Iterator<Item = (&Row, &Measurement)> {
    rows.iter()
        .filter_map(|r| r.result.as_ref().ok().map(|m| (r, m)))
}

/// The y label of times: GPU or CPU, as measured.
fn time_label(rows: &[Row]) -> &'static str {
    if ok(rows).any(|(_, m)| m.timing == super::measure::TimingSource::CpuWall) {
        "frame time, ms (CPU wall time where the device has no timestamps)"
    } else {
        "frame time, ms (GPU timestamps)"
    }
}

/// Write a sweep's charts into `dir`; returns their file stems.
pub(crate) fn charts(dir: &Path, sweep: &Sweep, rows: &[Row]) -> Result<Vec<String>> {
    let mut written = Vec::new();
    let mut series: Vec<Series> = Vec::new();
    for t in sweep.series.iter().map(|s| s.name) {
        let points: Vec<(f64, f64)> = ok(rows)
            .filter(|(r, _)| r.technique == t)
            .map(|(r, m)| (r.x, m.frame_ms))
            .collect();
        if !points.is_empty() {
            series.push(Series {
                name: t.to_string(),
                points,
            });
        }
    }
    // One technique: its passes as lines beside the total (Figure 9's breakdown).
    if let [only] = sweep.series.as_slice() {
        let only = only.name;
        let mut passes: Vec<String> = Vec::new();
        for (_, m) in ok(rows) {
            for (n, _) in &m.passes {
                if !passes.contains(n) {
                    passes.push(n.clone());
                }
            }
        }
        for p in &passes {
            series.push(Series {
                name: p.clone(),
                points: ok(rows)
                    .filter_map(|(r, m)| m.passes.iter().find(|x| &x.0 == p).map(|x| (r.x, x.1)))
                    .collect(),
            });
        }
        if let Some(total) = series.first_mut() {
            total.name = format!("{only} (frame)");
        }
    }
    if series.is_empty() {
        return Ok(written);
    }
    line_chart(
        &dir.join(sweep.name),
        &LineChart {
            title: sweep.title,
            x_label: sweep.x_label,
            y_label: time_label(rows),
            log_x: sweep.log_x,
            series,
        },
    )?;
    written.push(sweep.name.to_string());

    if sweep.name == "distance" {
        // Figure 8's other axis: the time against the hair's share of the screen.
        let cov: Vec<Series> = sweep
            .series
            .iter()
            .map(|s| Series {
                name: s.name.to_string(),
                points: ok(rows)
                    .filter(|(r, _)| r.technique == s.name)
                    .map(|(_, m)| (m.coverage_pct.max(1e-3), m.frame_ms))
                    .collect(),
            })
            .filter(|s| !s.points.is_empty())
            .collect();
        line_chart(
            &dir.join("coverage"),
            &LineChart {
                title: "Frame time by screen coverage of the hair (Figure 8)",
                x_label: "hair coverage, % of pixels",
                y_label: time_label(rows),
                log_x: true,
                series: cov,
            },
        )?;
        written.push("coverage".into());
        // Figure 7: passes of each technique, nearest and farthest.
        let (near, far) = (
            rows.iter().map(|r| r.x).fold(f64::INFINITY, f64::min),
            rows.iter().map(|r| r.x).fold(f64::NEG_INFINITY, f64::max),
        );
        let mut bars = Vec::new();
        for t in sweep.series.iter().map(|s| s.name) {
            for (tag, x) in [("near", near), ("far", far)] {
                if let Some((_, m)) = ok(rows).find(|(r, _)| r.technique == t && r.x == x) {
                    let segs = if m.passes.is_empty() {
                        vec![("frame (CPU wall)".to_string(), m.frame_ms)]
                    } else {
                        m.passes.clone()
                    };
                    bars.push((format!("{t} {tag}"), segs));
                }
            }
        }
        bar_chart(
            &dir.join("passes"),
            &BarChart {
                title: "Frame time by pass, near and far (Figure 7)",
                y_label: "ms",
                bars,
            },
        )?;
        written.push("passes".into());
        // Figure 6: memory by kind, at the nearest distance.
        let bars = sweep
            .series
            .iter()
            .map(|s| s.name)
            .filter_map(|t| {
                ok(rows)
                    .find(|(r, _)| r.technique == t && r.x == near)
                    .map(|(_, m)| {
                        let segs = m
                            .memory
                            .rows()
                            .iter()
                            .filter(|r| r.1 > 0)
                            .map(|(n, b)| ((*n).to_string(), *b as f64 / MIB))
                            .collect();
                        (t.to_string(), segs)
                    })
            })
            .collect();
        bar_chart(
            &dir.join("memory"),
            &BarChart {
                title: "GPU memory by kind (Figure 6)",
                y_label: "MiB",
                bars,
            },
        )?;
        written.push("memory".into());
    }
    Ok(written)
}

/// What the summary says about the machine and the run.
pub(crate) struct Header<'a> {
    pub(crate) adapter: &'a str,
    pub(crate) backend: &'a str,
    pub(crate) driver: &'a str,
    pub(crate) device_type: &'a str,
    pub(crate) scene: &'a str,
    pub(crate) size: [u32; 2],
    pub(crate) warmup: u32,
    pub(crate) frames: u32,
    pub(crate) quick: bool,
}

/// The Markdown summary.
pub(crate) fn markdown(h: &Header<'_>, sweeps: &[(Sweep, Vec<Row>, Vec<String>)]) -> String {
    let mut md = String::from("# tress bench\n\n");
    let _ = writeln!(
        md,
        "- adapter: **{}** ({}, {}; driver {})",
        h.adapter, h.device_type, h.backend, h.driver
    );
    let _ = writeln!(md, "- scene: {}", h.scene);
    let _ = writeln!(
        md,
        "- {}x{}, {} warm-up frames, then the mean of {} frames per point{}",
        h.size[0],
        h.size[1],
        h.warmup,
        h.frames,
        if h.quick { " (`--quick`)" } else { "" }
    );
    md.push_str(
        "- times are sums of per-pass GPU timestamps (`gpu_timestamps`), or the CPU wall time of \
         whole frames where the device has none (`cpu_wall`); coverage is the share of pixels the \
         hair changes; memory is what the technique allocated on the GPU\n",
    );
    for (sweep, rows, charts) in sweeps {
        let _ = writeln!(md, "\n## {}: {}\n", sweep.name, sweep.title);
        for c in charts {
            let _ = writeln!(md, "![{c}]({c}.png)");
        }
        let _ = writeln!(
            md,
            "\n`{}.csv`\n\n| technique | {} | frame ms | timing | wall ms | coverage % | memory MiB |",
            sweep.name, sweep.x_label
        );
        md.push_str("| --- | ---: | ---: | --- | ---: | ---: | ---: |\n");
        for r in rows {
            match &r.result {
                Ok(m) => {
                    let _ = writeln!(
                        md,
                        "| {} | {} | {:.2} | {} | {:.1} | {:.2} | {:.1} |",
                        r.technique,
                        tick(r.x),
                        m.frame_ms,
                        m.timing.name(),
                        m.wall_ms,
                        m.coverage_pct,
                        m.memory.total() as f64 / MIB
                    );
                }
                Err(e) => {
                    let _ = writeln!(
                        md,
                        "| {} | {} | failed: {} | | | | |",
                        r.technique,
                        tick(r.x),
                        e
                    );
                }
            }
        }
        if sweep.name == "characters" {
            characters_summary(&mut md, sweep, rows);
        }
    }
    md
}

/// The `characters` sweep's answer: characters each mode fits in the time the strands need
/// for two, and each mode's memory at the most characters.
fn characters_summary(md: &mut String, sweep: &Sweep, rows: &[Row]) {
    let series: Vec<&'static str> = sweep.series.iter().map(|s| s.name).collect();
    let Some(counts) = super::crowd::budget_counts(rows, &series) else {
        return;
    };
    md.push_str(
        "
| mode | characters in the time the strands need for 2 | memory MiB at the most \
         characters (geometry, oit, volumes, shadow maps) |\n| --- | ---: | --- |\n",
    );
    for (t, n) in counts {
        let most = ok(rows)
            .filter(|(r, _)| r.technique == t)
            .max_by(|a, b| a.0.x.total_cmp(&b.0.x));
        let memory = most.map_or(String::new(), |(r, m)| {
            let mem = m.memory;
            format!(
                "{:.1} at {} ({:.1}, {:.1}, {:.1}, {:.1})",
                mem.total() as f64 / MIB,
                tick(r.x),
                mem.geometry as f64 / MIB,
                mem.oit as f64 / MIB,
                mem.volumes as f64 / MIB,
                mem.shadow_maps as f64 / MIB
            )
        });
        let _ = writeln!(md, "| {t} | {} | {memory} |", tick(n));
    }
}

/// Write `text` to `dir/name`.
pub(crate) fn write(dir: &Path, name: &str, text: &str) -> Result<()> {
    let path = dir.join(name);
    std::fs::write(&path, text).with_context(|| path.display().to_string())
}
