//! Benchmark charts with plotters, each written as PNG and SVG: line charts (time against a
//! swept setting, one line per technique or pass) and stacked bars (time per pass, memory per
//! kind), like the hybrid paper's Figures 6 to 10.

use std::path::Path;
use std::sync::Once;

use anyhow::{Context, Result, anyhow};
use plotters::coord::Shift;
use plotters::prelude::*;

const SIZE: (u32, u32) = (960, 540);
const FONT: &str = "sans-serif";

/// Distinct, color-blind-friendly line colors (Okabe–Ito).
const COLORS: [RGBColor; 8] = [
    RGBColor(0, 114, 178),
    RGBColor(213, 94, 0),
    RGBColor(0, 158, 115),
    RGBColor(204, 121, 167),
    RGBColor(230, 159, 0),
    RGBColor(86, 180, 233),
    RGBColor(240, 228, 66),
    RGBColor(0, 0, 0),
];

/// One line of a line chart.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Series {
    pub(crate) name: String,
    pub(crate) points: Vec<(f64, f64)>,
}

/// A line chart.
#[derive(Clone, Debug)]
pub(crate) struct LineChart<'a> {
    pub(crate) title: &'a str,
    pub(crate) x_label: &'a str,
    pub(crate) y_label: &'a str,
    /// Log-scaled x axis (labels still show the values).
    pub(crate) log_x: bool,
    pub(crate) series: Vec<Series>,
}

/// A stacked bar chart: one bar per label, stacked by segment.
#[derive(Clone, Debug)]
pub(crate) struct BarChart<'a> {
    pub(crate) title: &'a str,
    pub(crate) y_label: &'a str,
    pub(crate) bars: Vec<(String, Vec<(String, f64)>)>,
}

fn register_font() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        // The egui crate's bundled Ubuntu Light: the same text everywhere, no system fonts.
        let _ = plotters::style::register_font(
            FONT,
            FontStyle::Normal,
            epaint_default_fonts::UBUNTU_LIGHT,
        );
    });
}

fn color(i: usize) -> RGBColor {
    COLORS[i % COLORS.len()]
}

/// Color `i` of `n`: the line palette while it lasts, else `n` hues around the wheel.
fn color_of(i: usize, n: usize) -> RGBColor {
    if n <= COLORS.len() {
        return color(i);
    }
    let (r, g, b) = HSLColor(i as f64 / n as f64, 0.6, 0.45 + 0.15 * (i % 2) as f64).rgb();
    RGBColor(r, g, b)
}

fn err(e: impl std::fmt::Display) -> anyhow::Error {
    anyhow!("drawing a chart: {e}")
}

/// Write `draw` to `base.png` and `base.svg`.
fn write_both(
    base: &Path,
    draw_png: impl FnOnce(DrawingArea<BitMapBackend<'_>, Shift>) -> Result<()>,
    draw_svg: impl FnOnce(DrawingArea<SVGBackend<'_>, Shift>) -> Result<()>,
) -> Result<()> {
    register_font();
    let png = base.with_extension("png");
    let svg = base.with_extension("svg");
    let mut buf = vec![0u8; (SIZE.0 * SIZE.1 * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut buf, SIZE).into_drawing_area();
        draw_png(root)?;
    }
    image::RgbImage::from_raw(SIZE.0, SIZE.1, buf)
        .context("chart buffer size")?
        .save(&png)
        .with_context(|| png.display().to_string())?;
    let root = SVGBackend::new(&svg, SIZE).into_drawing_area();
    draw_svg(root)?;
    Ok(())
}

fn bounds(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = values
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        });
    if !lo.is_finite() {
        return (0.0, 1.0);
    }
    if hi - lo < 1e-9 {
        return (lo - 0.5, hi + 0.5);
    }
    (lo, hi)
}

/// The body of a line chart on a built chart (linear or log x: the coordinate types differ).
macro_rules! lines_body {
    ($root:expr, $chart:expr, $c:expr) => {{
        let c = $c;
        let mut chart = $chart;
        chart
            .configure_mesh()
            .x_desc(c.x_label)
            .y_desc(c.y_label)
            .x_label_formatter(&|v: &f64| tick(*v))
            .label_style((FONT, 14))
            .axis_desc_style((FONT, 16))
            .draw()
            .map_err(err)?;
        for (i, s) in c.series.iter().enumerate() {
            let col = color(i);
            chart
                .draw_series(LineSeries::new(s.points.clone(), col.stroke_width(2)))
                .map_err(err)?
                .label(s.name.as_str())
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 20, y)], col.stroke_width(2))
                });
            chart
                .draw_series(s.points.iter().map(|p| Circle::new(*p, 4, col.filled())))
                .map_err(err)?;
        }
        chart
            .configure_series_labels()
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .label_font((FONT, 14))
            .position(SeriesLabelPosition::UpperLeft)
            .draw()
            .map_err(err)?;
        $root.present().map_err(err)?;
    }};
}

/// A tick label: whole numbers plainly, fractions with up to three significant digits.
pub(crate) fn tick(v: f64) -> String {
    if (v - v.round()).abs() < 1e-9 && v.abs() < 1e9 {
        format!("{}", v.round() as i64)
    } else {
        let s = format!("{v:.3}");
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    }
}

fn draw_lines<DB: DrawingBackend>(root: DrawingArea<DB, Shift>, c: &LineChart<'_>) -> Result<()> {
    root.fill(&WHITE).map_err(err)?;
    let (x0, x1) = bounds(c.series.iter().flat_map(|s| s.points.iter().map(|p| p.0)));
    let (_, y1) = bounds(c.series.iter().flat_map(|s| s.points.iter().map(|p| p.1)));
    let y = 0.0..(y1.max(1e-6) * 1.1);
    let mut builder = ChartBuilder::on(&root);
    builder
        .caption(c.title, (FONT, 24))
        .margin(16)
        .x_label_area_size(48)
        .y_label_area_size(72);
    if c.log_x && x0 > 0.0 {
        let chart = builder
            .build_cartesian_2d((x0 / 1.15..x1 * 1.15).log_scale(), y)
            .map_err(err)?;
        lines_body!(root, chart, c);
    } else {
        let pad = (x1 - x0) * 0.04;
        let chart = builder
            .build_cartesian_2d((x0 - pad)..(x1 + pad), y)
            .map_err(err)?;
        lines_body!(root, chart, c);
    }
    Ok(())
}

fn draw_bars<DB: DrawingBackend>(root: DrawingArea<DB, Shift>, c: &BarChart<'_>) -> Result<()> {
    root.fill(&WHITE).map_err(err)?;
    let n = c.bars.len().max(1);
    let top = c
        .bars
        .iter()
        .map(|b| b.1.iter().map(|s| s.1.max(0.0)).sum::<f64>())
        .fold(0.0, f64::max)
        .max(1e-6);
    // Segment names in first-seen order: one color each, one legend entry each.
    let mut names: Vec<&str> = Vec::new();
    for (_, segs) in &c.bars {
        for (name, _) in segs {
            if !names.contains(&name.as_str()) {
                names.push(name);
            }
        }
    }
    let labels: Vec<String> = c.bars.iter().map(|b| b.0.clone()).collect();
    // The legend gets its own column on the right, so it never covers a bar.
    let (plot, legend) = root.split_horizontally(SIZE.0 - 230);
    let mut chart = ChartBuilder::on(&plot)
        .caption(c.title, (FONT, 24))
        .margin(16)
        .x_label_area_size(48)
        .y_label_area_size(72)
        .build_cartesian_2d(0.0..n as f64, 0.0..top * 1.1)
        .map_err(err)?;
    let label_of = move |v: &f64| {
        let i = v.floor() as usize;
        if (v - i as f64 - 0.5).abs() < 1e-6 {
            labels.get(i).cloned().unwrap_or_default()
        } else {
            String::new()
        }
    };
    chart
        .configure_mesh()
        .disable_x_mesh()
        .x_labels(2 * n + 1)
        .x_label_formatter(&label_of)
        .y_desc(c.y_label)
        .label_style((FONT, 13))
        .axis_desc_style((FONT, 16))
        .draw()
        .map_err(err)?;
    for (k, name) in names.iter().enumerate() {
        let col = color_of(k, names.len());
        let rects: Vec<Rectangle<(f64, f64)>> = c
            .bars
            .iter()
            .enumerate()
            .filter_map(|(i, (_, segs))| {
                let pos = segs.iter().position(|s| s.0 == *name)?;
                let below: f64 = segs[..pos].iter().map(|s| s.1.max(0.0)).sum();
                let x = i as f64;
                Some(Rectangle::new(
                    [(x + 0.2, below), (x + 0.8, below + segs[pos].1.max(0.0))],
                    col.filled(),
                ))
            })
            .collect();
        chart.draw_series(rects).map_err(err)?;
        let y = 60 + 22 * k as i32;
        legend
            .draw(&Rectangle::new([(8, y - 6), (22, y + 6)], col.filled()))
            .map_err(err)?;
        legend
            .draw(&Text::new(name.to_string(), (30, y - 8), (FONT, 14)))
            .map_err(err)?;
    }
    root.present().map_err(err)?;
    Ok(())
}

/// Write a line chart to `base.png` and `base.svg`.
pub(crate) fn line_chart(base: &Path, c: &LineChart<'_>) -> Result<()> {
    write_both(base, |r| draw_lines(r, c), |r| draw_lines(r, c))
}

/// Write a stacked bar chart to `base.png` and `base.svg`.
pub(crate) fn bar_chart(base: &Path, c: &BarChart<'_>) -> Result<()> {
    write_both(base, |r| draw_bars(r, c), |r| draw_bars(r, c))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn charts_are_written_as_png_and_svg_with_their_text() {
        let dir = std::env::temp_dir().join(format!("tress-chart-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let base = dir.join("lines");
        line_chart(
            &base,
            &LineChart {
                title: "Frame time",
                x_label: "steps",
                y_label: "ms",
                log_x: true,
                series: vec![Series {
                    name: "volume".into(),
                    points: vec![(32.0, 1.0), (64.0, 2.0), (128.0, 4.0)],
                }],
            },
        )
        .unwrap();
        let svg = std::fs::read_to_string(base.with_extension("svg")).unwrap();
        assert!(svg.contains("Frame time") && svg.contains("volume"));
        let png = image::open(base.with_extension("png")).unwrap().to_rgb8();
        assert_eq!(png.dimensions(), SIZE);
        // Not blank: the line's blue is somewhere, and text (dark pixels) too.
        assert!(png.pixels().any(|p| p.0 == [0, 114, 178]));
        assert!(png.pixels().filter(|p| p.0[0] < 80 && p.0[1] < 80).count() > 500);

        let base = dir.join("bars");
        bar_chart(
            &base,
            &BarChart {
                title: "Memory",
                y_label: "MiB",
                bars: vec![
                    (
                        "strands".into(),
                        vec![("geometry".into(), 3.0), ("ppll".into(), 9.0)],
                    ),
                    (
                        "volume".into(),
                        vec![("geometry".into(), 3.0), ("volumes".into(), 2.0)],
                    ),
                ],
            },
        )
        .unwrap();
        let svg = std::fs::read_to_string(base.with_extension("svg")).unwrap();
        assert!(svg.contains("ppll") && svg.contains("strands"));
        let png = image::open(base.with_extension("png")).unwrap().to_rgb8();
        // Three segment colors drawn.
        for c in &COLORS[..3] {
            assert!(png.pixels().any(|p| p.0 == [c.0, c.1, c.2]), "{c:?}");
        }
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
