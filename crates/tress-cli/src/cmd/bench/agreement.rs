//! The `distance` sweep's image agreement: every technique's frame scored by mean FLIP against
//! the strand rasterizer's frame at the same distance, over the hair's pixels (those either frame
//! covers). The hybrid paper's claim (Figure 1) is that the raymarched volume is indistinguishable
//! from the strands from medium distance on; this is the figure that checks it.

use tress_render::LinearImage;
use tress_trace::{DisplayImage, metrics};

use super::quality::linear_to_trace;
use super::report::Row;

/// One row's frame and hair mask (pixels the hair changes), kept for scoring.
pub(crate) struct Frame {
    pub(crate) image: LinearImage,
    pub(crate) hair: Vec<bool>,
}

/// Mean FLIP between `a` and `b` over the pixels `mask` marks (0 with none marked).
pub(crate) fn masked_flip(a: &LinearImage, b: &LinearImage, mask: &[bool]) -> anyhow::Result<f64> {
    let display = |i: &LinearImage| DisplayImage::from_linear(&linear_to_trace(i));
    Ok(metrics::compare(&display(a), &display(b))?.masked_flip(mask))
}

/// Set the `flip` of every row but the strands' to its FLIP against the strands row at the same
/// x, over the union of the two frames' hair masks. Rows without a frame keep `None`.
pub(crate) fn score_against_strands(rows: &mut [Row], frames: &[Option<Frame>]) {
    let strands: Vec<(f64, usize)> = rows
        .iter()
        .enumerate()
        .filter(|(i, r)| r.technique == "strands" && frames[*i].is_some())
        .map(|(i, r)| (r.x, i))
        .collect();
    for i in 0..rows.len() {
        let Some(&(_, s)) = strands.iter().find(|(x, _)| *x == rows[i].x) else {
            continue;
        };
        let (Some(reference), Some(frame)) = (&frames[s], &frames[i]) else {
            continue;
        };
        if i == s {
            continue;
        }
        let mask: Vec<bool> = reference
            .hair
            .iter()
            .zip(&frame.hair)
            .map(|(a, b)| *a || *b)
            .collect();
        if let Ok(m) = &mut rows[i].result {
            m.flip = masked_flip(&reference.image, &frame.image, &mask).ok();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cmd::bench::measure::{Measurement, TimingSource};

    fn measurement() -> Measurement {
        Measurement {
            frame_ms: 1.0,
            timing: TimingSource::CpuWall,
            wall_ms: 1.0,
            passes: Vec::new(),
            coverage_pct: 50.0,
            memory: Default::default(),
            frames: 1,
            oit: None,
            flip: None,
        }
    }

    fn flat(w: u32, h: u32, c: f32) -> LinearImage {
        LinearImage {
            width: w,
            height: h,
            pixels: vec![[c, c, c, 1.0]; (w * h) as usize],
        }
    }

    #[test]
    fn flip_counts_only_the_masked_pixels() {
        // 64 x 64: the left 16 columns change; FLIP's filters spread an edge a few pixels, so
        // the right 16 columns see no error and the changed columns the most.
        let (w, h) = (64u32, 64u32);
        let (a, mut b) = (flat(w, h, 0.2), flat(w, h, 0.2));
        let column = |i: usize| i as u32 % w;
        for (i, p) in b.pixels.iter_mut().enumerate() {
            if column(i) < 16 {
                *p = [0.8, 0.8, 0.8, 1.0];
            }
        }
        let mask = |f: &dyn Fn(u32) -> bool| -> Vec<bool> {
            (0..(w * h) as usize).map(|i| f(column(i))).collect()
        };
        assert_eq!(masked_flip(&a, &b, &mask(&|x| x >= 48)).unwrap(), 0.0);
        let all = masked_flip(&a, &b, &mask(&|_| true)).unwrap();
        let changed = masked_flip(&a, &b, &mask(&|x| x < 16)).unwrap();
        assert!(changed > 2.0 * all && all > 0.05, "{changed} {all}");
        assert_eq!(masked_flip(&a, &b, &mask(&|_| false)).unwrap(), 0.0);
    }

    #[test]
    fn rows_are_scored_against_the_strands_at_their_own_distance() {
        let row = |t: &'static str, x: f64| Row {
            technique: t,
            x,
            result: Ok(measurement()),
        };
        let mut rows = vec![
            row("strands", 1.0),
            row("volume", 1.0),
            row("strands", 2.0),
            row("volume", 2.0),
        ];
        let frame = |c: f32| {
            Some(Frame {
                image: flat(8, 8, c),
                hair: vec![true; 64],
            })
        };
        // At x = 1 the volume equals the strands; at x = 2 it differs.
        let frames = vec![frame(0.3), frame(0.3), frame(0.3), frame(0.9)];
        score_against_strands(&mut rows, &frames);
        let flip = |i: usize| rows[i].result.as_ref().unwrap().flip;
        assert_eq!(flip(0), None);
        assert_eq!(flip(1), Some(0.0));
        assert_eq!(flip(2), None);
        assert!(flip(3).unwrap() > 0.1);
    }
}
