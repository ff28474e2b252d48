//! Clamped uniform cubic B-splines on `[0, 1]`: the curves `T(t)`, `A(t)`, `B(t)` and `q(t)` of
//! the generalized cylinder (Xu et al. 2006, §3.2, equations 1–2).
//!
//! A spline of `n ≥ 4` control points has degree 3 and the knot vector
//! `0, 0, 0, 0, 1/m, 2/m, …, (m-1)/m, 1, 1, 1, 1` with `m = n - 3` segments: it starts at the first
//! control point, ends at the last, and four control points give the cubic Bézier curve. Basis
//! functions are computed with the Cox–de Boor recursion in `f64`.
//!
//! [`BSpline::fit`] solves the least-squares problem `min Σ |C(t_j) - y_j|² + λ |D² c|²` by
//! Cholesky on the normal equations; the tiny second-difference penalty `λ` (10⁻⁶ of the mean
//! diagonal, plus a thousandth of that on first differences) only keeps control points over empty
//! spans determined, and is invariant to translation, so it never pulls the curve toward the
//! origin.

use std::fmt::Debug;
use std::ops::{Add, Mul, Sub};

use glam::{Vec2, Vec3};

use crate::error::{SatfError, param};

/// The degree of every spline here.
pub const DEGREE: usize = 3;
/// The most control points a spline may have.
pub const MAX_CONTROL_POINTS: usize = 1024;
/// Relative weight of the second-difference penalty in [`BSpline::fit`].
const FIT_PENALTY: f64 = 1e-6;

/// A value a spline can interpolate: `f32`, [`Vec2`] or [`Vec3`].
pub trait ControlPoint:
    Copy
    + Default
    + Debug
    + PartialEq
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<f32, Output = Self>
    + Send
    + Sync
    + 'static
{
    /// Number of components.
    const DIM: usize;
    /// Component `i` (`i < DIM`).
    fn component(&self, i: usize) -> f32;
    /// The value with the given components (`DIM` entries).
    fn from_components(c: &[f64]) -> Self;
    /// Whether every component is finite.
    fn finite(&self) -> bool;
}

impl ControlPoint for f32 {
    const DIM: usize = 1;
    fn component(&self, _: usize) -> f32 {
        *self
    }
    fn from_components(c: &[f64]) -> Self {
        c[0] as f32
    }
    fn finite(&self) -> bool {
        self.is_finite()
    }
}

impl ControlPoint for Vec2 {
    const DIM: usize = 2;
    fn component(&self, i: usize) -> f32 {
        self[i]
    }
    fn from_components(c: &[f64]) -> Self {
        Vec2::new(c[0] as f32, c[1] as f32)
    }
    fn finite(&self) -> bool {
        self.is_finite()
    }
}

impl ControlPoint for Vec3 {
    const DIM: usize = 3;
    fn component(&self, i: usize) -> f32 {
        self[i]
    }
    fn from_components(c: &[f64]) -> Self {
        Vec3::new(c[0] as f32, c[1] as f32, c[2] as f32)
    }
    fn finite(&self) -> bool {
        self.is_finite()
    }
}

/// A clamped uniform cubic B-spline on `[0, 1]` (see the module docs).
#[derive(Clone, Debug, PartialEq)]
pub struct BSpline<P> {
    control: Vec<P>,
}

impl<P: ControlPoint> BSpline<P> {
    /// A spline from its control points (4 to [`MAX_CONTROL_POINTS`], all finite).
    pub fn new(control: Vec<P>) -> Result<Self, SatfError> {
        if !(DEGREE + 1..=MAX_CONTROL_POINTS).contains(&control.len()) {
            return Err(param(format!(
                "a cubic B-spline needs 4 to {MAX_CONTROL_POINTS} control points, got {}",
                control.len()
            )));
        }
        if let Some(i) = control.iter().position(|p| !p.finite()) {
            return Err(param(format!("control point {i} is not finite")));
        }
        Ok(BSpline { control })
    }

    /// The constant spline `C(t) = value` (four equal control points).
    pub fn constant(value: P) -> Self {
        BSpline {
            control: vec![value; DEGREE + 1],
        }
    }

    /// The straight line from `a` to `b` (four control points evenly spaced, so `C(t) = a + t (b - a)`).
    pub fn linear(a: P, b: P) -> Self {
        let control = (0..=DEGREE)
            .map(|i| a + (b - a) * (i as f32 / DEGREE as f32))
            .collect();
        BSpline { control }
    }

    /// The control points.
    pub fn control_points(&self) -> &[P] {
        &self.control
    }

    /// `C(t)`; `t` is clamped to `[0, 1]`.
    pub fn eval(&self, t: f32) -> P {
        let (first, w) = basis(self.control.len(), t);
        combine(&self.control[first..first + 4], &w)
    }

    /// `C'(t)` (derivative with respect to `t`); `t` is clamped to `[0, 1]`.
    pub fn derivative(&self, t: f32) -> P {
        let (first, w) = basis_derivative(self.control.len(), t);
        combine(&self.control[first..first + 4], &w)
    }

    /// The least-squares spline of `n_control` control points through `values` at `params` (see
    /// the module docs). Needs as many values as parameters, parameters finite in `[0, 1]`, at
    /// least one value, and `n_control` in `4..=MAX_CONTROL_POINTS`.
    pub fn fit(params: &[f32], values: &[P], n_control: usize) -> Result<Self, SatfError> {
        Self::fit_weighted(params, values, None, n_control)
    }

    /// [`BSpline::fit`] with a non-negative weight per value (`None`: all 1), minimizing
    /// `Σ w_j |C(t_j) - y_j|² + λ |D² c|²`; the weights must not all be zero.
    pub fn fit_weighted(
        params: &[f32],
        values: &[P],
        weights: Option<&[f32]>,
        n_control: usize,
    ) -> Result<Self, SatfError> {
        if let Some(w) = weights
            && (w.len() != values.len()
                || w.iter().any(|w| !(w.is_finite() && *w >= 0.0))
                || !w.iter().any(|w| *w > 0.0))
        {
            return Err(param(
                "spline fit weights must be one finite non-negative weight per value, not all zero",
            ));
        }
        if params.len() != values.len() || values.is_empty() {
            return Err(param(format!(
                "spline fit needs as many parameters as values (at least one), got {} and {}",
                params.len(),
                values.len()
            )));
        }
        if !(DEGREE + 1..=MAX_CONTROL_POINTS).contains(&n_control) {
            return Err(param(format!(
                "a cubic B-spline needs 4 to {MAX_CONTROL_POINTS} control points, got {n_control}"
            )));
        }
        if params.iter().any(|t| !(0.0..=1.0).contains(t)) || values.iter().any(|v| !v.finite()) {
            return Err(param(
                "spline fit inputs must be finite, parameters in [0, 1]",
            ));
        }
        let n = n_control;
        let mut ata = vec![0.0f64; n * n];
        let mut atb = vec![0.0f64; n * P::DIM];
        for (j, (&t, v)) in params.iter().zip(values).enumerate() {
            let weight = weights.map_or(1.0, |w| f64::from(w[j]));
            let (first, w) = basis(n, t);
            for a in 0..4 {
                for b in 0..4 {
                    ata[(first + a) * n + first + b] += weight * f64::from(w[a]) * f64::from(w[b]);
                }
                for d in 0..P::DIM {
                    atb[(first + a) * P::DIM + d] +=
                        weight * f64::from(w[a]) * f64::from(v.component(d));
                }
            }
        }
        let mean_diag = (0..n).map(|i| ata[i * n + i]).sum::<f64>() / n as f64;
        let lambda = FIT_PENALTY * mean_diag.max(1e-12);
        // Second-difference rows (1, -2, 1) and, far weaker, first-difference rows (1, -1) over
        // consecutive control points: with too few values the curve is then the flattest one.
        for i in 0..n - 2 {
            let row = [(i, 1.0), (i + 1, -2.0), (i + 2, 1.0)];
            for &(a, wa) in &row {
                for &(b, wb) in &row {
                    ata[a * n + b] += lambda * wa * wb;
                }
            }
        }
        for i in 0..n - 1 {
            let row = [(i, 1.0), (i + 1, -1.0)];
            for &(a, wa) in &row {
                for &(b, wb) in &row {
                    ata[a * n + b] += 1e-3 * lambda * wa * wb;
                }
            }
        }
        let l = cholesky(&ata, n)
            .ok_or_else(|| param("spline fit: the normal equations are singular"))?;
        let mut control = Vec::with_capacity(n);
        let mut x = vec![vec![0.0f64; n]; P::DIM];
        for (d, xd) in x.iter_mut().enumerate() {
            let rhs: Vec<f64> = (0..n).map(|i| atb[i * P::DIM + d]).collect();
            *xd = cholesky_solve(&l, n, &rhs);
        }
        for i in 0..n {
            let c: Vec<f64> = x.iter().map(|xd| xd[i]).collect();
            control.push(P::from_components(&c));
        }
        BSpline::new(control)
    }
}

fn combine<P: ControlPoint>(points: &[P], w: &[f32; 4]) -> P {
    points[0] * w[0] + points[1] * w[1] + points[2] * w[2] + points[3] * w[3]
}

/// Knot `i` of the clamped uniform cubic knot vector of `n` control points.
fn knot(n: usize, i: usize) -> f64 {
    let m = (n - DEGREE) as f64;
    ((i as f64 - DEGREE as f64) / m).clamp(0.0, 1.0)
}

/// The knot span of `t`: the index `k` with `knot(k) <= t < knot(k + 1)` (the last span for `t = 1`).
fn span(n: usize, t: f64) -> usize {
    let m = n - DEGREE;
    let seg = ((t * m as f64).floor() as usize).min(m - 1);
    seg + DEGREE
}

/// Values of the `p + 1` non-zero basis functions of degree `p` at `t` in span `k`:
/// `N_{k-p, p} … N_{k, p}` (Cox–de Boor).
fn basis_funs(n: usize, k: usize, t: f64, p: usize) -> [f64; 4] {
    let mut out = [0.0f64; 4];
    let mut left = [0.0f64; 4];
    let mut right = [0.0f64; 4];
    out[0] = 1.0;
    for j in 1..=p {
        left[j] = t - knot(n, k + 1 - j);
        right[j] = knot(n, k + j) - t;
        let mut saved = 0.0;
        for r in 0..j {
            let denom = right[r + 1] + left[j - r];
            let temp = if denom == 0.0 { 0.0 } else { out[r] / denom };
            out[r] = saved + right[r + 1] * temp;
            saved = left[j - r] * temp;
        }
        out[j] = saved;
    }
    out
}

/// The first control point index and the four weights of `C(t)` for `n` control points
/// (`t` clamped to `[0, 1]`). The weights are non-negative and sum to 1.
pub fn basis(n: usize, t: f32) -> (usize, [f32; 4]) {
    let t = f64::from(t.clamp(0.0, 1.0));
    let k = span(n, t);
    let w = basis_funs(n, k, t, DEGREE);
    (k - DEGREE, w.map(|x| x as f32))
}

/// The first control point index and the four weights of `C'(t)` for `n` control points.
pub fn basis_derivative(n: usize, t: f32) -> (usize, [f32; 4]) {
    let t = f64::from(t.clamp(0.0, 1.0));
    let k = span(n, t);
    // N_{k-2..k, 2}; N_{k-3, 2} and N_{k+1, 2} vanish on this span.
    let n2 = basis_funs(n, k, t, DEGREE - 1);
    let lower = |i: isize| -> f64 {
        let j = i - (k as isize - 2);
        if (0..3).contains(&j) {
            n2[j as usize]
        } else {
            0.0
        }
    };
    let p = DEGREE as f64;
    let mut w = [0.0f32; 4];
    for (a, wa) in w.iter_mut().enumerate() {
        let i = k - DEGREE + a;
        let d0 = knot(n, i + DEGREE) - knot(n, i);
        let d1 = knot(n, i + DEGREE + 1) - knot(n, i + 1);
        let t0 = if d0 > 0.0 {
            p / d0 * lower(i as isize)
        } else {
            0.0
        };
        let t1 = if d1 > 0.0 {
            p / d1 * lower(i as isize + 1)
        } else {
            0.0
        };
        *wa = (t0 - t1) as f32;
    }
    (k - DEGREE, w)
}

/// Lower-triangular Cholesky factor of the symmetric `n × n` matrix `a` (row-major), or `None`
/// when it is not positive definite.
fn cholesky(a: &[f64], n: usize) -> Option<Vec<f64>> {
    let mut l = vec![0.0f64; n * n];
    for i in 0..n {
        for j in 0..=i {
            let s: f64 = (0..j).map(|k| l[i * n + k] * l[j * n + k]).sum();
            if i == j {
                let d = a[i * n + i] - s;
                if d <= 0.0 || !d.is_finite() {
                    return None;
                }
                l[i * n + i] = d.sqrt();
            } else {
                l[i * n + j] = (a[i * n + j] - s) / l[j * n + j];
            }
        }
    }
    Some(l)
}

/// Solve `L Lᵀ x = b`.
fn cholesky_solve(l: &[f64], n: usize, b: &[f64]) -> Vec<f64> {
    let mut y = vec![0.0f64; n];
    for i in 0..n {
        let s: f64 = (0..i).map(|k| l[i * n + k] * y[k]).sum();
        y[i] = (b[i] - s) / l[i * n + i];
    }
    let mut x = vec![0.0f64; n];
    for i in (0..n).rev() {
        let s: f64 = (i + 1..n).map(|k| l[k * n + i] * x[k]).sum();
        x[i] = (y[i] - s) / l[i * n + i];
    }
    x
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: f32, b: f32, eps: f32) -> bool {
        (a - b).abs() <= eps
    }

    #[test]
    fn four_control_points_are_the_bezier_curve() {
        // Bernstein weights by hand: t = 1/2 gives (1, 3, 3, 1)/8, t = 1/4 gives (27, 27, 9, 1)/64.
        let (first, w) = basis(4, 0.5);
        assert_eq!(first, 0);
        for (a, b) in w.iter().zip([0.125, 0.375, 0.375, 0.125]) {
            assert!(close(*a, b, 1e-7), "{w:?}");
        }
        let (_, w) = basis(4, 0.25);
        for (a, b) in w
            .iter()
            .zip([27.0 / 64.0, 27.0 / 64.0, 9.0 / 64.0, 1.0 / 64.0])
        {
            assert!(close(*a, b, 1e-7), "{w:?}");
        }
        let s = BSpline::new(vec![0.0f32, 3.0, 6.0, 9.0]).unwrap();
        assert!(
            close(s.eval(0.3), 2.7, 1e-6),
            "evenly spaced control points give a line"
        );
        assert!(close(s.derivative(0.7), 9.0, 1e-5));
    }

    #[test]
    fn uniform_interior_knot_weights() {
        // 10 control points: 7 segments; the knot 3/7 is far enough from both ends that its three
        // basis functions are the uniform ones, 1/6, 2/3, 1/6 (hand value of the uniform cubic).
        let (first, w) = basis(10, 3.0 / 7.0);
        assert_eq!(first, 3);
        for (a, b) in w.iter().zip([1.0 / 6.0, 2.0 / 3.0, 1.0 / 6.0, 0.0]) {
            assert!(close(*a, b, 1e-6), "{w:?}");
        }
        // Uniform cubic derivative at a knot: (-1/2, 0, 1/2) per segment, times m = 7.
        let (first, w) = basis_derivative(10, 3.0 / 7.0);
        assert_eq!(first, 3);
        for (a, b) in w.iter().zip([-3.5, 0.0, 3.5, 0.0]) {
            assert!(close(*a, b, 1e-5), "{w:?}");
        }
    }

    #[test]
    fn partition_of_unity_and_end_interpolation() {
        for n in [4usize, 5, 7, 12, 40] {
            for i in 0..=200 {
                let t = i as f32 / 200.0;
                let (first, w) = basis(n, t);
                assert!(first + 4 <= n);
                assert!(w.iter().all(|x| *x >= -1e-7));
                assert!(close(w.iter().sum::<f32>(), 1.0, 1e-6));
                let (_, d) = basis_derivative(n, t);
                assert!(
                    close(d.iter().sum::<f32>(), 0.0, 1e-4),
                    "derivative weights sum to 0"
                );
            }
            let control: Vec<Vec3> = (0..n)
                .map(|i| Vec3::new(i as f32, (i * i) as f32, 1.0))
                .collect();
            let s = BSpline::new(control.clone()).unwrap();
            assert_eq!(s.eval(0.0), control[0]);
            assert!((s.eval(1.0) - control[n - 1]).length() < 1e-4);
        }
    }

    #[test]
    fn derivative_matches_finite_differences() {
        let s = BSpline::new(vec![
            Vec3::ZERO,
            Vec3::new(1.0, 2.0, 0.0),
            Vec3::new(3.0, -1.0, 2.0),
            Vec3::new(4.0, 0.0, 5.0),
            Vec3::new(2.0, 2.0, 1.0),
            Vec3::new(0.0, 5.0, 0.0),
        ])
        .unwrap();
        let h = 1e-3;
        for i in 1..100 {
            let t = i as f32 / 100.0;
            let fd = (s.eval(t + h) - s.eval(t - h)) / (2.0 * h);
            assert!((fd - s.derivative(t)).length() < 2e-2, "t = {t}");
        }
    }

    #[test]
    fn fit_reproduces_a_cubic_exactly() {
        // Cubic polynomials lie in the spline space, so least squares recovers them.
        let f = |t: f32| Vec3::new(1.0 + 2.0 * t, t * t * t - t, 3.0 * t * t);
        let params: Vec<f32> = (0..30).map(|i| i as f32 / 29.0).collect();
        let values: Vec<Vec3> = params.iter().map(|&t| f(t)).collect();
        for n in [4usize, 6, 9] {
            let s = BSpline::fit(&params, &values, n).unwrap();
            for i in 0..=50 {
                let t = i as f32 / 50.0;
                assert!((s.eval(t) - f(t)).length() < 1e-3, "n = {n}, t = {t}");
            }
        }
        // A constant fitted from a single value.
        let c = BSpline::fit(&[0.5], &[2.5f32], 4).unwrap();
        assert!(close(c.eval(0.1), 2.5, 1e-4) && close(c.eval(0.9), 2.5, 1e-4));
    }

    #[test]
    fn weights_scale_each_value() {
        // Two clouds at the same parameters: the fit is their weighted mean, and weight 2 on a
        // value is the same as the value twice.
        let params: Vec<f32> = (0..20).map(|i| i as f32 / 19.0).collect();
        let lo = vec![0.0f32; 20];
        let hi = vec![3.0f32; 20];
        let all_params = [params.clone(), params.clone()].concat();
        let values = [lo.clone(), hi.clone()].concat();
        let weights = [vec![2.0; 20], vec![1.0; 20]].concat();
        let w = BSpline::fit_weighted(&all_params, &values, Some(&weights), 5).unwrap();
        assert!(close(w.eval(0.3), 1.0, 1e-3), "{}", w.eval(0.3));
        let twice = [params.clone(), params.clone(), params].concat();
        let values = [lo.clone(), lo, hi].concat();
        let d = BSpline::fit(&twice, &values, 5).unwrap();
        assert!(close(d.eval(0.7), w.eval(0.7), 1e-4));
        assert!(BSpline::fit_weighted(&[0.5], &[1.0f32], Some(&[0.0]), 4).is_err());
        assert!(BSpline::fit_weighted(&[0.5], &[1.0f32], Some(&[-1.0]), 4).is_err());
    }

    #[test]
    fn rejects_bad_input() {
        assert!(BSpline::new(vec![0.0f32; 3]).is_err());
        assert!(BSpline::new(vec![0.0, 1.0, f32::NAN, 2.0]).is_err());
        assert!(BSpline::fit(&[0.0, 2.0], &[1.0f32, 2.0], 4).is_err());
        assert!(BSpline::fit(&[0.0], &[1.0f32, 2.0], 4).is_err());
        assert!(BSpline::fit(&[], &[] as &[f32], 4).is_err());
        let l = BSpline::linear(1.0f32, 4.0);
        assert!(close(l.eval(0.5), 2.5, 1e-6));
    }
}
