//! Measuring one point of a sweep: warm-up frames, then per-pass GPU times averaged over the
//! timed frames (CPU wall time where the device has no timestamps), the hair's screen coverage
//! and the memory breakdown.

use anyhow::{Context, Result};
use tress_render::session::{FrameDetail, Memory, Session};
use tress_render::strands::OitStats;
use tress_render::{Camera, GpuContext, LinearImage, OffscreenTargets, Timings, read_texture};
use tress_scene::Scene;

/// Where a point's times come from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum TimingSource {
    /// GPU timestamp queries around each pass.
    Gpu,
    /// The CPU wall time of whole frames (the device has no timestamps).
    CpuWall,
}

impl TimingSource {
    pub(crate) fn name(self) -> &'static str {
        match self {
            TimingSource::Gpu => "gpu_timestamps",
            TimingSource::CpuWall => "cpu_wall",
        }
    }
}

/// What one point measured.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Measurement {
    /// Mean frame time, ms: the sum of the passes' means, or the mean wall time.
    pub(crate) frame_ms: f64,
    /// Where `frame_ms` comes from.
    pub(crate) timing: TimingSource,
    /// Mean CPU wall time of a frame (submission to finished results), ms.
    pub(crate) wall_ms: f64,
    /// Mean GPU time per pass, in the order the passes ran (empty without timestamps).
    pub(crate) passes: Vec<(String, f64)>,
    /// Share of the frame's pixels the hair changes, percent.
    pub(crate) coverage_pct: f64,
    /// GPU memory of the technique.
    pub(crate) memory: Memory,
    /// Frames timed.
    pub(crate) frames: u32,
    /// The strand OIT of the last timed frame (strands and hybrid frames).
    pub(crate) oit: Option<OitStats>,
    /// Mean FLIP against the sweep's reference frame, where the sweep has one (`oit`).
    pub(crate) flip: Option<f64>,
}

/// Mean per-pass times over frames; passes missing from some frames average over those they
/// ran in. `None` when no frame had timestamps.
pub(crate) fn mean_passes(frames: &[Option<Timings>]) -> Option<Vec<(String, f64)>> {
    let mut sums: Vec<(String, f64, u32)> = Vec::new();
    for t in frames.iter().flatten() {
        if let Timings::Passes(passes) = t {
            for p in passes {
                match sums.iter_mut().find(|s| s.0 == p.name) {
                    Some(s) => {
                        s.1 += p.ms;
                        s.2 += 1;
                    }
                    None => sums.push((p.name.to_string(), p.ms, 1)),
                }
            }
        }
    }
    (!sums.is_empty()).then(|| {
        sums.into_iter()
            .map(|(n, sum, count)| (n, sum / f64::from(count)))
            .collect()
    })
}

/// Share of pixels whose color differs between two frames by more than 1/255 in a channel,
/// percent (the two must be the same size).
pub(crate) fn coverage_pct(with: &LinearImage, without: &LinearImage) -> f64 {
    let mask = hair_mask(with, without);
    if mask.is_empty() {
        return 0.0;
    }
    100.0 * mask.iter().filter(|m| **m).count() as f64 / mask.len() as f64
}

/// Per pixel, whether two frames (with and without the hair) differ by more than 1/255 in a
/// channel: the pixels the hair covers.
pub(crate) fn hair_mask(with: &LinearImage, without: &LinearImage) -> Vec<bool> {
    with.pixels
        .iter()
        .zip(&without.pixels)
        .map(|(a, b)| (0..3).any(|c| (a[c] - b[c]).abs() > 1.0 / 255.0))
        .collect()
}

/// `scene` with its camera moved `factor` times its distance away from its target along its
/// view line (the far plane follows).
pub(crate) fn scene_at(scene: &Scene, factor: f32) -> Scene {
    let mut scene = scene.clone();
    let (eye, target) = (scene.camera.eye, scene.camera.target);
    scene.camera.eye = target + (eye - target) * factor;
    scene.camera.far = scene.camera.far.max(scene.camera.far * factor);
    scene
}

/// The session's scene camera moved as [`scene_at`] moves it.
pub(crate) fn camera_at(session: &Session, size: [u32; 2], factor: f32) -> Camera {
    tress_render::PreparedScene::camera(&scene_at(session.scene(), factor), size)
}

/// Render `warmup` frames, then time `frames` frames, then measure the coverage on one frame
/// with and one without the hair. Returns the measurement, the last frame with hair (and the
/// pixels the hair covers in it) and, with
/// `exact`, that frame as exact sorted compositing draws it (`Session::sort_exactly`: a strand
/// frame drawn with the PPLL that lost nothing, else an error).
pub(crate) fn measure(
    ctx: &GpuContext,
    session: &mut Session,
    targets: &OffscreenTargets,
    camera: &Camera,
    warmup: u32,
    frames: u32,
    exact: bool,
) -> Result<(Measurement, super::agreement::Frame, Option<LinearImage>)> {
    session.set_hair_visible(true);
    for _ in 0..warmup {
        session.render(ctx, &targets.targets(), camera, None)?;
    }
    let mut timings = Vec::with_capacity(frames as usize);
    let mut wall = 0.0;
    let mut memory = Memory::default();
    let mut oit = None;
    for _ in 0..frames.max(1) {
        let f = session.render(ctx, &targets.targets(), camera, None)?;
        wall += f.wall_ms;
        memory = f.memory;
        oit = match &f.detail {
            FrameDetail::Strands(s) => s.gpu.as_ref().and_then(|g| g.oit),
            _ => None,
        };
        timings.push(f.timings);
    }
    let n = frames.max(1);
    let wall_ms = wall / f64::from(n);
    let image = read_texture(ctx, &targets.color).context("reading the frame back")?;
    let exact = if exact {
        match oit {
            Some(o) if o.kind == tress_render::strands::OitKind::Ppll && o.lost == 0 => {}
            _ => anyhow::bail!("the exact reference needs a PPLL frame that lost nothing"),
        }
        let mut sorted = image.clone();
        if !session.sort_exactly(ctx, &mut sorted)? {
            anyhow::bail!("the exact reference needs a strand frame drawn with the PPLL");
        }
        Some(sorted)
    } else {
        None
    };
    session.set_hair_visible(false);
    let bare = session
        .render(ctx, &targets.targets(), camera, None)
        .and_then(|_| read_texture(ctx, &targets.color));
    session.set_hair_visible(true);
    let bare = bare.context("rendering the frame without hair")?;
    let (frame_ms, timing, passes) = match mean_passes(&timings) {
        Some(p) => (p.iter().map(|x| x.1).sum(), TimingSource::Gpu, p),
        None => (wall_ms, TimingSource::CpuWall, Vec::new()),
    };
    Ok((
        Measurement {
            frame_ms,
            timing,
            wall_ms,
            passes,
            coverage_pct: coverage_pct(&image, &bare),
            memory,
            frames: n,
            oit,
            flip: None,
        },
        super::agreement::Frame {
            hair: hair_mask(&image, &bare),
            image,
        },
        exact,
    ))
}

/// Linear RGB of the image's pixel at `(x, y)` (tests).
#[cfg(test)]
fn pixel(img: &LinearImage, x: u32, y: u32) -> glam::Vec3 {
    let p = img.pixels[(y * img.width + x) as usize];
    glam::Vec3::new(p[0], p[1], p[2])
}

#[cfg(test)]
mod tests {
    use super::*;
    use tress_render::gpu::PassTiming;

    fn img(w: u32, h: u32, f: impl Fn(u32, u32) -> [f32; 4]) -> LinearImage {
        LinearImage {
            width: w,
            height: h,
            pixels: (0..h)
                .flat_map(|y| (0..w).map(move |x| (x, y)))
                .map(|(x, y)| f(x, y))
                .collect(),
        }
    }

    #[test]
    fn coverage_counts_pixels_that_differ_beyond_one_level() {
        let bg = img(10, 10, |_, _| [0.2, 0.2, 0.2, 1.0]);
        // A 5 x 2 block of hair, and noise below one 8-bit level elsewhere.
        let hair = img(10, 10, |x, y| {
            if x < 5 && y < 2 {
                [0.5, 0.3, 0.1, 1.0]
            } else {
                [0.2 + 0.5 / 255.0, 0.2, 0.2, 1.0]
            }
        });
        assert_eq!(pixel(&hair, 0, 0), glam::Vec3::new(0.5, 0.3, 0.1));
        assert!((coverage_pct(&hair, &bg) - 10.0).abs() < 1e-9);
        assert_eq!(coverage_pct(&bg, &bg), 0.0);
    }

    #[test]
    fn pass_means_average_each_pass_over_the_frames_it_ran_in() {
        let t = |v: &[(&'static str, f64)]| {
            Some(Timings::Passes(
                v.iter()
                    .map(|&(name, ms)| PassTiming { name, ms })
                    .collect(),
            ))
        };
        let frames = vec![
            t(&[("a", 1.0), ("b", 4.0)]),
            t(&[("a", 3.0)]),
            None,
            Some(Timings::NotSupported),
        ];
        let m = mean_passes(&frames).unwrap();
        assert_eq!(m, vec![("a".to_string(), 2.0), ("b".to_string(), 4.0)]);
        assert_eq!(mean_passes(&[None, Some(Timings::NotSupported)]), None);
    }
}
