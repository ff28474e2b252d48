//! Stencils: for each output vertex of a cubic or NURBS curve, the weights of the control
//! vertices it blends (the [tessellation rule](super) of the curve formats).

use super::{CubicBasis, Wrap};

const BEZIER: [[f32; 4]; 4] = [
    [-1.0, 3.0, -3.0, 1.0],
    [3.0, -6.0, 3.0, 0.0],
    [-3.0, 3.0, 0.0, 0.0],
    [1.0, 0.0, 0.0, 0.0],
];
const S6: f32 = 1.0 / 6.0;
const BSPLINE: [[f32; 4]; 4] = [
    [-S6, 3.0 * S6, -3.0 * S6, S6],
    [3.0 * S6, -6.0 * S6, 3.0 * S6, 0.0],
    [-3.0 * S6, 0.0, 3.0 * S6, 0.0],
    [S6, 4.0 * S6, S6, 0.0],
];
const CATMULL_ROM: [[f32; 4]; 4] = [
    [-0.5, 1.5, -1.5, 0.5],
    [1.0, -2.5, 2.0, -0.5],
    [-0.5, 0.0, 0.5, 0.0],
    [0.0, 1.0, 0.0, 0.0],
];

fn basis_weights(m: &[[f32; 4]; 4], t: f32) -> [f32; 4] {
    let p = [t * t * t, t * t, t, 1.0];
    std::array::from_fn(|c| (0..4).map(|r| p[r] * m[r][c]).sum())
}

/// One output vertex: weights on control vertices (a stencil) and where it lies on the spans.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct Sample {
    pub(super) span: u32,
    pub(super) t: f32,
    pub(super) start: u32,
    pub(super) len: u32,
}

/// The samples of one curve, their stencils in `taps`.
#[derive(Default)]
pub(super) struct Stencils {
    pub(super) samples: Vec<Sample>,
    pub(super) taps: Vec<(u32, f32)>,
    pub(super) spans: u32,
}

impl Stencils {
    pub(super) fn clear(&mut self) {
        self.samples.clear();
        self.taps.clear();
        self.spans = 0;
    }

    fn push(&mut self, span: u32, t: f32, taps: impl IntoIterator<Item = (u32, f32)>) {
        let start = self.taps.len() as u32;
        self.taps.extend(taps);
        let len = self.taps.len() as u32 - start;
        self.samples.push(Sample {
            span,
            t,
            start,
            len,
        });
    }

    /// A cubic curve of `n` control vertices.
    pub(super) fn cubic(
        &mut self,
        basis: CubicBasis,
        wrap: Wrap,
        n: usize,
        segments: u32,
    ) -> Result<(), String> {
        let (matrix, bezier) = match basis {
            CubicBasis::Bezier => (&BEZIER, true),
            CubicBasis::Bspline => (&BSPLINE, false),
            CubicBasis::CatmullRom => (&CATMULL_ROM, false),
        };
        let wrap = if bezier && wrap == Wrap::Pinned {
            Wrap::NonPeriodic
        } else {
            wrap
        };
        let spans = match (bezier, wrap) {
            (true, Wrap::Periodic) if n >= 3 && n.is_multiple_of(3) => n / 3,
            (true, Wrap::Periodic) => {
                return Err(format!(
                    "a periodic Bezier curve needs 3k vertices, not {n}"
                ));
            }
            (true, _) if n >= 4 && (n - 4).is_multiple_of(3) => (n - 1) / 3,
            (true, _) => {
                return Err(format!(
                    "a Bezier curve needs 3k + 1 vertices (at least 4), not {n}"
                ));
            }
            (false, Wrap::NonPeriodic) if n >= 4 => n - 3,
            (false, Wrap::NonPeriodic) => {
                return Err(format!("needs at least 4 vertices, not {n}"));
            }
            (false, Wrap::Pinned) if n >= 2 => n - 1,
            (false, Wrap::Pinned) => {
                return Err(format!("a pinned curve needs at least 2 vertices, not {n}"));
            }
            (false, Wrap::Periodic) if n >= 3 => n,
            (false, Wrap::Periodic) => {
                return Err(format!(
                    "a periodic curve needs at least 3 vertices, not {n}"
                ));
            }
        };
        self.spans = spans as u32;
        let last = n as i64 - 1;
        for s in 0..spans {
            let first = if s == 0 { 0 } else { 1 };
            for k in first..=segments {
                let t = k as f32 / segments as f32;
                let w = basis_weights(matrix, t);
                let mut taps = [(0u32, 0.0f32); 8];
                let mut m = 0;
                for (j, &wj) in w.iter().enumerate() {
                    let raw = if bezier {
                        3 * s as i64 + j as i64
                    } else {
                        s as i64 + j as i64
                    };
                    match wrap {
                        Wrap::Periodic => {
                            taps[m] = ((raw.rem_euclid(n as i64)) as u32, wj);
                            m += 1;
                        }
                        Wrap::NonPeriodic => {
                            taps[m] = (raw as u32, wj);
                            m += 1;
                        }
                        Wrap::Pinned => {
                            // indices into [2P0 - P1, P0 .. Pn-1, 2Pn-1 - Pn-2]
                            let i = raw - 1;
                            if i < 0 {
                                taps[m] = (0, 2.0 * wj);
                                taps[m + 1] = (1, -wj);
                                m += 2;
                            } else if i > last {
                                taps[m] = (last as u32, 2.0 * wj);
                                taps[m + 1] = ((last - 1) as u32, -wj);
                                m += 2;
                            } else {
                                taps[m] = (i as u32, wj);
                                m += 1;
                            }
                        }
                    }
                }
                self.push(s as u32, t, taps[..m].iter().copied());
            }
        }
        Ok(())
    }

    /// A NURBS curve: `n` control vertices, `order`, its `n + order` knots.
    pub(super) fn nurbs(
        &mut self,
        n: usize,
        order: usize,
        knots: &[f64],
        segments: u32,
    ) -> Result<(), String> {
        if !(2..=MAX_ORDER).contains(&order) {
            return Err(format!("order {order} is outside 2..={MAX_ORDER}"));
        }
        if n < order {
            return Err(format!("{n} vertices are fewer than the order {order}"));
        }
        if knots.iter().any(|k| !k.is_finite()) || knots.windows(2).any(|w| w[1] < w[0]) {
            return Err("the knots are not finite and non-decreasing".into());
        }
        let p = order - 1;
        let mut span_index = 0u32;
        for i in p..n {
            let (a, b) = (knots[i], knots[i + 1]);
            if b <= a {
                continue;
            }
            let first = if self.samples.is_empty() { 0 } else { 1 };
            for k in first..=segments {
                let t = k as f32 / segments as f32;
                let u = a + (b - a) * f64::from(t);
                let basis = cox_de_boor(knots, i, p, u);
                self.push(
                    span_index,
                    t,
                    (0..order).map(|j| ((i - p + j) as u32, basis[j] as f32)),
                );
            }
            span_index += 1;
        }
        if span_index == 0 {
            return Err("the knots leave no span of positive length".into());
        }
        self.spans = span_index;
        Ok(())
    }
}

/// Highest NURBS order read.
const MAX_ORDER: usize = 16;

/// The `p + 1` non-zero B-spline basis functions of degree `p` at `u` in knot span `i`
/// (The NURBS Book, algorithm A2.2).
fn cox_de_boor(knots: &[f64], i: usize, p: usize, u: f64) -> [f64; MAX_ORDER] {
    let mut n = [0.0; MAX_ORDER];
    let mut left = [0.0; MAX_ORDER];
    let mut right = [0.0; MAX_ORDER];
    n[0] = 1.0;
    for j in 1..=p {
        left[j] = u - knots[i + 1 - j];
        right[j] = knots[i + j] - u;
        let mut saved = 0.0;
        for r in 0..j {
            let denom = right[r + 1] + left[j - r];
            let temp = if denom == 0.0 { 0.0 } else { n[r] / denom };
            n[r] = saved + right[r + 1] * temp;
            saved = left[j - r] * temp;
        }
        n[j] = saved;
    }
    n
}
