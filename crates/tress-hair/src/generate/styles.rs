//! The strand shapes of each style, before clumping, noise and collision (see the module docs of
//! [`crate::generate`] for the whole pipeline).

use std::f32::consts::TAU;

use glam::{Vec2, Vec3};

use super::head::{Head, ScalpPoint};
use super::{Style, StyleParams, head_for};
use crate::rng::Rng;

/// Strands are kept at ellipsoid level `1 + MARGIN` or above (root vertices excepted).
pub(super) const MARGIN: f32 = 0.005;

/// Hanging hair is integrated in sub-steps of at most this arc length (cm), so that its shape
/// barely depends on the vertex count.
const HANG_STEP: f32 = 0.5;
/// At most this many sub-steps per segment (bounds the work for absurdly long strands).
const HANG_MAX_SUBSTEPS: usize = 16;
/// How hard the comb presses hair onto the upper head, relative to gravity.
const COMB_PRESS: f32 = 1.0;
/// Arc length over which the pull (gravity or combing) turns a strand's direction by about a
/// radian: smaller is limper hair.
const HANG_BEND: f32 = 2.0;
/// Strength of the combing pull on the upper head relative to gravity.
const COMB_PULL: f32 = 1.5;
/// Curls and waves grow to full amplitude over this arc length from the root (cm), or a quarter
/// of the strand if shorter, so that roots stay on the scalp.
const CURL_RAMP: f32 = 2.0;

/// Ponytail: the tie sits at this direction of the unit sphere (back of the head, a little
/// above the middle).
const TIE_DIRECTION: Vec3 = Vec3::new(0.0, 0.35, -1.0);
/// Ponytail: height of the tie's centre above the scalp (the thickness of the gathered hair).
const TIE_HEIGHT: f32 = 1.2;
/// Ponytail: radius of the bundle at the tie.
const TIE_RADIUS: f32 = 1.0;
/// Ponytail: radius the tail spreads to below the tie.
const TAIL_RADIUS: f32 = 3.0;
/// Ponytail: arc length over which the tail spreads from the tie radius to the tail radius.
const TAIL_SPREAD: f32 = 4.0;
/// Ponytail: arc length over which the tail turns from leaving the head to hanging down.
const TAIL_BEND: f32 = 5.0;
/// Ponytail: strands rise up to this far above the scalp on their way to the tie (layering).
const PONYTAIL_LIFT: f32 = 0.8;

/// Fur: the direction the coat is combed toward (back and down, like an animal's).
const FUR_COMB: Vec3 = Vec3::new(0.0, -0.5, -1.0);
/// Fur: how far a strand leans from the surface normal toward the comb direction at its tip.
const FUR_BEND: f32 = 1.2;

/// Everything random about one strand (or one clump centre), drawn in a fixed order.
#[derive(Clone, Copy, Debug)]
pub(super) struct Root {
    /// Where it grows from.
    pub(super) scalp: ScalpPoint,
    /// Phase of the curl or wave (radians).
    phase: f32,
    /// Uniform in [0, 1): ponytail layer height, fur comb wobble.
    lift: f32,
    /// Uniform in [0.7, 1.3): how strongly fur leans.
    bend: f32,
    /// Ponytail: where the strand sits in the tie, in the unit disk.
    disk: Vec2,
}

/// The ponytail's tie and tail frame.
#[derive(Clone, Copy, Debug)]
struct Tie {
    /// Unit-sphere direction of the tie.
    dir: Vec3,
    /// Scalp point below the tie and its normal.
    surface: Vec3,
    normal: Vec3,
    /// Centre of the bundle.
    point: Vec3,
    /// Direction the tail leaves the tie.
    tail_dir: Vec3,
    /// The bundle's "up" axis, perpendicular to `tail_dir` and +X.
    band_v: Vec3,
}

/// Grows the base shape of strands of one style.
#[derive(Clone, Debug)]
pub(super) struct Grower {
    style: Style,
    pub(super) head: Head,
    length: f32,
    curl_radius: f32,
    curl_frequency: f32,
    tie: Tie,
}

impl Grower {
    pub(super) fn new(style: Style, params: &StyleParams) -> Self {
        let head = head_for(style);
        let dir = TIE_DIRECTION.normalize();
        let (surface, normal) = head.surface_point(dir);
        let tail_dir = (normal + Vec3::NEG_Y * 0.5).normalize();
        let tie = Tie {
            dir,
            surface,
            normal,
            point: surface + normal * TIE_HEIGHT,
            tail_dir,
            band_v: Vec3::X.cross(tail_dir).normalize(),
        };
        Grower {
            style,
            head,
            length: params.length,
            curl_radius: params.curl_radius,
            curl_frequency: params.curl_frequency,
            tie,
        }
    }

    /// Clump grid over the strand coordinate: (cells around, cells from top to bottom).
    fn clump_grid(&self) -> (u32, u32) {
        match self.style {
            Style::Fur => (96, 48),
            _ => (40, 10),
        }
    }

    /// Number of clumps.
    pub(super) fn clump_count(&self) -> usize {
        let (nu, nv) = self.clump_grid();
        (nu * nv) as usize
    }

    /// The clump a strand with coordinate `uv` belongs to.
    pub(super) fn clump_of(&self, uv: Vec2) -> usize {
        let (nu, nv) = self.clump_grid();
        let iu = ((uv.x * nu as f32) as u32).min(nu - 1);
        let iv = ((uv.y * nv as f32) as u32).min(nv - 1);
        (iv * nu + iu) as usize
    }

    /// A random strand root.
    pub(super) fn sample_root(&self, rng: &mut Rng) -> Root {
        let scalp = match self.style {
            Style::Fur => self.head.sample_surface(rng),
            _ => self.head.sample_scalp(rng),
        };
        self.extras(scalp, rng)
    }

    /// The root of the centre strand of clump `cell` (the centre of its grid cell).
    pub(super) fn clump_root(&self, cell: usize, rng: &mut Rng) -> Root {
        let (nu, nv) = self.clump_grid();
        let (iu, iv) = (cell as u32 % nu, cell as u32 / nu);
        let uv = Vec2::new((iu as f32 + 0.5) / nu as f32, (iv as f32 + 0.5) / nv as f32);
        let scalp = match self.style {
            Style::Fur => self.head.body_point(uv),
            _ => self.head.scalp_point(uv),
        };
        self.extras(scalp, rng)
    }

    fn extras(&self, scalp: ScalpPoint, rng: &mut Rng) -> Root {
        let phase = rng.f32() * TAU;
        let lift = rng.f32();
        let bend = rng.range(0.7, 1.3);
        let jitter = rng.in_disk();
        // Gathered hair keeps its layout: hair from the crown runs in the middle of the tail,
        // hair from the hairline outside; the front on top, the sides at the sides.
        let angle = scalp.uv.x * TAU;
        let mut disk =
            Vec2::new(angle.sin(), angle.cos()) * scalp.uv.y.sqrt() * 0.85 + jitter * 0.15;
        disk = disk.clamp_length_max(1.0);
        Root {
            scalp,
            phase,
            lift,
            bend,
            disk,
        }
    }

    /// Write the strand's base shape into `out` (at least 2 vertices).
    pub(super) fn grow(&self, root: &Root, out: &mut [Vec3]) {
        match self.style {
            Style::Straight => self.hang(root, out),
            Style::Wavy => {
                self.hang(root, out);
                let t0 = (out[1] - out[0]).normalize_or(root.scalp.normal);
                let side = t0
                    .cross(root.scalp.normal)
                    .normalize_or(t0.any_orthonormal_vector());
                self.curl(out, 0, root.phase, side, false);
            }
            Style::Curly => {
                self.hang(root, out);
                let t0 = (out[1] - out[0]).normalize_or(root.scalp.normal);
                self.curl(out, 0, root.phase, t0.any_orthonormal_vector(), true);
            }
            Style::Ponytail => {
                let tail_start = self.ponytail(root, out);
                self.curl(out, tail_start, root.phase, Vec3::X, true);
            }
            Style::Fur => self.fur(root, out),
        }
    }

    /// Keep every vertex but the root outside the head (or body), far enough that the straight
    /// segments between them stay outside too: a chord of length `L` over a surface of radius of
    /// curvature `R` dips `L² / (8 R)` below its ends, and the first one starts at the root, so
    /// the vertices keep `L² / (3 R)` above the surface (`L² / (4 R)` with a margin for the
    /// ellipsoid not being a sphere; `R` its tightest radius of
    /// curvature, `L` the strand's longest segment). Without it a strand of few vertices runs
    /// through the head over the scalp, and the head hides it.
    pub(super) fn collide(&self, out: &mut [Vec3]) {
        let longest = out
            .windows(2)
            .map(|w| w[0].distance(w[1]))
            .fold(0.0, f32::max);
        let r = self.head.radii;
        let tightest = r.min_element() * r.min_element() / r.max_element();
        let clearance = longest * longest / (3.0 * tightest);
        let margin = MARGIN + clearance / r.min_element();
        for p in &mut out[1..] {
            *p = self.head.push_out(*p, margin);
        }
    }

    /// Horizontal direction hair at `p` is combed toward: away from the face, to the sides and
    /// the back, so that the face stays free.
    fn comb(&self, p: Vec3) -> Vec3 {
        let q = (p - self.head.center) / self.head.radii;
        Vec3::new(1.5 * q.x, 0.0, q.z - 0.9).normalize_or(Vec3::NEG_Z)
    }

    /// Hanging hair: rises from the scalp, is combed over the upper head away from the face and
    /// falls under gravity, sliding over the head where it meets it.
    fn hang(&self, root: &Root, out: &mut [Vec3]) {
        let segments = out.len() - 1;
        let ds = self.length / segments as f32;
        let substeps = ((ds / HANG_STEP).ceil() as usize).clamp(1, HANG_MAX_SUBSTEPS);
        let h = ds / substeps as f32;
        let (c, r) = (self.head.center, self.head.radii);
        let mut p = root.scalp.position;
        let comb0 = self.comb(p) - Vec3::Y * 0.3;
        let mut dir = (root.scalp.normal * 0.5 + comb0).normalize_or(root.scalp.normal);
        out[0] = p;
        for o in &mut out[1..] {
            for _ in 0..substeps {
                // On the upper head the comb wins over gravity; lower down, gravity does.
                let y = ((p.y - c.y) / r.y).clamp(0.0, 0.6) / 0.6;
                let w = y * y * (3.0 - 2.0 * y);
                let force = if w > 0.0 {
                    // The comb runs along the head's surface and presses the hair onto it.
                    let n = ((p - c) / (r * r)).normalize_or(Vec3::Y);
                    let comb = self.comb(p) - Vec3::Y * 0.3;
                    let along = (comb - n * comb.dot(n)).normalize_or(Vec3::NEG_Y);
                    Vec3::NEG_Y * (1.0 - w) + (along * COMB_PULL - n * COMB_PRESS) * w
                } else {
                    Vec3::NEG_Y
                };
                dir = (dir + force * (h / HANG_BEND)).normalize_or(Vec3::NEG_Y);
                let free = p + dir * h;
                let q = self.head.push_out(free, MARGIN);
                if q != free {
                    dir = (q - p).normalize_or(dir);
                }
                p = q;
            }
            *o = p;
        }
    }

    /// Add a curl to `out[start..]` around its current shape: a helix (or, with `helix` false,
    /// a planar sinusoid along `side`) of the curl radius, `curl_frequency` turns per unit of
    /// arc length, growing in over the first [`CURL_RAMP`]. The frame follows the strand by
    /// parallel transport, so the curl winds around a bent strand too.
    fn curl(&self, out: &mut [Vec3], start: usize, phase: f32, side: Vec3, helix: bool) {
        let n = out.len();
        if self.curl_radius == 0.0 || n < start + 2 {
            return;
        }
        let ramp = (self.length * 0.25).min(CURL_RAMP);
        let mut u = side;
        let mut t = Vec3::NEG_Y;
        let mut prev = out[start];
        let mut s = 0.0;
        for i in start..n {
            let base = out[i];
            s += base.distance(prev);
            let next = if i + 1 < n { out[i + 1] } else { base };
            t = (next - prev).normalize_or(t);
            u = (u - t * u.dot(t)).normalize_or(t.any_orthonormal_vector());
            let v = t.cross(u);
            let x = if ramp > 0.0 { (s / ramp).min(1.0) } else { 1.0 };
            let amplitude = self.curl_radius * x * x * (3.0 - 2.0 * x);
            let (sin, cos) = (TAU * self.curl_frequency * s + phase).sin_cos();
            let offset = if helix { u * cos + v * sin } else { u * sin };
            prev = base;
            out[i] = base + offset * amplitude;
        }
    }

    /// Ponytail: from the root over the scalp to the tie at the back of the head, then a tail of
    /// the strand length falling from the tie. Returns the index of the first tail vertex.
    fn ponytail(&self, root: &Root, out: &mut [Vec3]) -> usize {
        let tie = &self.tie;
        let from =
            ((root.scalp.position - self.head.center) / self.head.radii).normalize_or(tie.dir);
        let band = tie.point + (Vec3::X * root.disk.x + tie.band_v * root.disk.y) * TIE_RADIUS;
        let lift = PONYTAIL_LIFT * root.lift;
        // The path rises `lift` above the scalp and bends into its place in the bundle.
        let fix = band - (tie.surface + tie.normal * lift);
        // The great circle from the root's direction to the tie's: `from` turned toward `perp`.
        let axis = from.cross(tie.dir);
        let angle = axis.length().atan2(from.dot(tie.dir));
        let perp = axis.normalize_or(from.any_orthonormal_vector()).cross(from);
        let path = |t: f32| {
            let (sin, cos) = (angle * t).sin_cos();
            let (s, n) = self.head.surface_point(from * cos + perp * sin);
            s + n * (lift * t) + fix * (t * t * t)
        };
        let mut scalp_length = 0.0;
        let mut prev = root.scalp.position;
        for k in 1..=8 {
            let p = path(k as f32 / 8.0);
            scalp_length += p.distance(prev);
            prev = p;
        }
        let total = scalp_length + self.length;
        let last = (out.len() - 1) as f32;
        let mut tail_start = out.len();
        for (i, o) in out.iter_mut().enumerate() {
            let s = total * i as f32 / last;
            *o = if s < scalp_length {
                path(s / scalp_length)
            } else {
                tail_start = tail_start.min(i);
                self.tail(s - scalp_length, root.disk)
            };
        }
        tail_start
    }

    /// The ponytail's tail at arc length `s` below the tie, for a strand at `disk` in the bundle:
    /// the tail's centre leaves the head along the tie's direction and turns down over
    /// [`TAIL_BEND`], the bundle spreads from [`TIE_RADIUS`] to [`TAIL_RADIUS`] and narrows
    /// again toward the tips.
    fn tail(&self, s: f32, disk: Vec2) -> Vec3 {
        let tie = &self.tie;
        let e = (-s / TAIL_BEND).exp();
        let along = TAIL_BEND * (1.0 - e);
        let centre = tie.point + tie.tail_dir * along + Vec3::NEG_Y * (s - along);
        let d = tie.tail_dir * e + Vec3::NEG_Y * (1.0 - e);
        let v = Vec3::X.cross(d).normalize_or(tie.band_v);
        let spread = TIE_RADIUS + (TAIL_RADIUS - TIE_RADIUS) * (1.0 - (-s / TAIL_SPREAD).exp());
        let f = if self.length > 0.0 {
            (s / self.length).min(1.0)
        } else {
            1.0
        };
        let taper = 1.0 - 0.5 * f * f;
        centre + (Vec3::X * disk.x + v * disk.y) * (spread * taper)
    }

    /// Fur: straight out along the surface normal, leaning toward the comb direction more and
    /// more toward the tip.
    fn fur(&self, root: &Root, out: &mut [Vec3]) {
        let n = root.scalp.normal;
        let comb = (FUR_COMB - n * n.dot(FUR_COMB)).normalize_or(n.any_orthonormal_vector());
        // A little wobble of the comb direction around the normal, per strand.
        let (sin, cos) = ((root.lift - 0.5) * 0.8).sin_cos();
        let comb = comb * cos + n.cross(comb) * sin;
        let bend = FUR_BEND * root.bend;
        let segments = (out.len() - 1) as f32;
        let ds = self.length / segments;
        let mut p = root.scalp.position;
        out[0] = p;
        for (i, o) in out.iter_mut().enumerate().skip(1) {
            let t = (i as f32 - 0.5) / segments;
            p += (n + comb * (bend * t)).normalize() * ds;
            *o = p;
        }
    }
}
