//! SATF clusters fitted to a groom merged from several parts whose strands meet at a ponytail's
//! tie, as a user loads a TressFX ponytail of four files: short crown strands that end at the
//! tie, tail strands rooted at the tie, full strands from the scalp through the tie to the tail,
//! and short bangs at the front (4,933 guides of 16 vertices, like the TressFX 3 asset).
//!
//! The measure is the CPU stand-in of `tress bench --quality`'s stray %: in orthographic views,
//! the share of the fitted clusters' silhouette (their outer shells `v = 1`) that lies outside
//! the strands' silhouette dilated by 4 pixels.

use glam::Vec3;
use tress_hair::HairAsset;
use tress_hair::generate::{Head, Style, StyleParams, generate};
use tress_hair::rng::Rng;
use tress_satf::fit::{FitSettings, fit_clusters, resample};
use tress_satf::{GeneralizedCylinder, HairVolume};

/// Raster pixel (world units). `scenes/tressfx-ponytail.toml` frames this hair 54 units tall
/// (35° at 86 units); `tress bench --quality` renders it 216 pixels tall: 0.25 units a pixel.
const PIXEL: f32 = 0.25;
/// The dilation of the strands' silhouette, 4 pixels: 1 world unit.
const DILATION_PX: i32 = 4;

/// The generated ponytail's tie (`tress_hair::generate`: 1.2 units above the scalp in
/// direction (0, 0.35, -1) of the default head).
fn tie() -> Vec3 {
    let head = Head::default();
    let (surface, normal) = head.surface_point(Vec3::new(0.0, 0.35, -1.0).normalize());
    surface + normal * 1.2
}

/// A generated ponytail of `strands` strands, 64 vertices each.
fn ponytail(strands: u32, seed: u64) -> HairAsset {
    let params = StyleParams {
        strands,
        vertices: 64,
        seed,
        ..Style::Ponytail.default_params()
    };
    generate(Style::Ponytail, &params).expect("ponytail")
}

/// The index of the vertex of `strand` nearest the tie.
fn at_tie(strand: &[Vec3]) -> usize {
    let tie = tie();
    (0..strand.len())
        .min_by(|&a, &b| strand[a].distance(tie).total_cmp(&strand[b].distance(tie)))
        .unwrap_or(0)
}

/// The four parts, each resampled to 16 vertices, merged in one asset. The crown's strands run
/// from the scalp to the tie, or, with `crown_from_tie`, from the tie over the scalp (rooted
/// where the tail's strands are: a fan of strands of 6 to 15 units from one point).
fn merged_groom(crown_from_tie: bool) -> HairAsset {
    let n = 16;
    let part = |strands: Vec<Vec<Vec3>>| {
        let strands: Vec<Vec<Vec3>> = strands.iter().filter_map(|s| resample(s, n)).collect();
        let counts = vec![n as u32; strands.len()];
        HairAsset::from_counts(strands.concat(), &counts).expect("part")
    };
    // Crown: from the scalp to the tie, where the strands end.
    let crown = ponytail(1400, 11);
    let crown = part(
        crown
            .strands()
            .map(|s| {
                let mut v = s[..=at_tie(s).max(2)].to_vec();
                if crown_from_tie {
                    v.reverse();
                }
                v
            })
            .collect(),
    );
    // Tail: rooted at the tie, 30% to all of the tail's length.
    let mut rng = Rng::new(7);
    let tail = ponytail(1200, 12);
    let tail = part(
        tail.strands()
            .map(|s| {
                let from = at_tie(s);
                let len = s.len() - from;
                let keep = ((len as f32 * rng.range(0.3, 1.0)) as usize).max(3);
                s[from..from + keep.min(len)].to_vec()
            })
            .collect(),
    );
    // Full strands: scalp, tie and tail.
    let full = ponytail(1900, 13);
    let full = part(full.strands().map(|s| s.to_vec()).collect());
    // Bangs: short straight strands from the front of the scalp.
    let params = StyleParams {
        strands: 8000,
        vertices: 16,
        length: 7.0,
        seed: 14,
        ..Style::Straight.default_params()
    };
    let straight = generate(Style::Straight, &params).expect("straight");
    let bangs = part(
        straight
            .strands()
            .filter(|s| s[0].z > 5.0)
            .take(433)
            .map(|s| s.to_vec())
            .collect(),
    );
    HairAsset::merge(&[crown, tail, full, bangs]).expect("merge")
}

/// An orthographic raster: pixels of `PIXEL` across the plane spanned by `right` and `up`.
struct View {
    right: Vec3,
    up: Vec3,
    origin: (i32, i32),
    size: (i32, i32),
}

impl View {
    fn new(forward: Vec3, lo: Vec3, hi: Vec3) -> View {
        let forward = forward.normalize();
        let right = forward.cross(Vec3::Y).normalize();
        let up = right.cross(forward);
        let margin = 64.0;
        let (mut x0, mut x1, mut y0, mut y1) = (f32::MAX, f32::MIN, f32::MAX, f32::MIN);
        for i in 0..8 {
            let c = Vec3::new(
                if i & 1 == 0 { lo.x } else { hi.x },
                if i & 2 == 0 { lo.y } else { hi.y },
                if i & 4 == 0 { lo.z } else { hi.z },
            );
            let (x, y) = (c.dot(right) / PIXEL, c.dot(up) / PIXEL);
            (x0, x1, y0, y1) = (x0.min(x), x1.max(x), y0.min(y), y1.max(y));
        }
        let origin = ((x0 - margin) as i32, (y0 - margin) as i32);
        let size = (
            (x1 - x0 + 2.0 * margin) as i32 + 1,
            (y1 - y0 + 2.0 * margin) as i32 + 1,
        );
        View {
            right,
            up,
            origin,
            size,
        }
    }

    fn mask(&self) -> Vec<bool> {
        vec![false; (self.size.0 * self.size.1) as usize]
    }

    fn set(&self, mask: &mut [bool], p: Vec3) {
        let x = (p.dot(self.right) / PIXEL).floor() as i32 - self.origin.0;
        let y = (p.dot(self.up) / PIXEL).floor() as i32 - self.origin.1;
        if (0..self.size.0).contains(&x) && (0..self.size.1).contains(&y) {
            mask[(y * self.size.0 + x) as usize] = true;
        }
    }

    fn dilate(&self, mask: &[bool], r: i32) -> Vec<bool> {
        let (w, h) = self.size;
        let mut out = self.mask();
        for (i, _) in mask.iter().enumerate().filter(|(_, m)| **m) {
            let (x, y) = (i as i32 % w, i as i32 / w);
            for dy in -r..=r {
                for dx in -r..=r {
                    let (nx, ny) = (x + dx, y + dy);
                    if dx * dx + dy * dy <= r * r && (0..w).contains(&nx) && (0..h).contains(&ny) {
                        out[(ny * w + nx) as usize] = true;
                    }
                }
            }
        }
        out
    }
}

/// Points of `a`–`b` at most half a pixel apart.
fn segment_points(a: Vec3, b: Vec3) -> impl Iterator<Item = Vec3> {
    let n = ((a.distance(b) / (0.5 * PIXEL)).ceil() as usize).max(1);
    (0..=n).map(move |k| a.lerp(b, k as f32 / n as f32))
}

/// Points of a cluster's outer shell `v = 1`, at most half a pixel apart.
fn shell_points(g: &GeneralizedCylinder, c: &tress_satf::Cluster) -> Vec<Vec3> {
    let nt = ((g.length() / (0.5 * PIXEL)).ceil() as usize).max(2);
    let mut out = Vec::new();
    for i in 0..=nt {
        let t = i as f32 / nt as f32;
        let (a, b, _) = g.profile(t);
        let nu = ((std::f32::consts::TAU * a.max(b) / (0.5 * PIXEL)).ceil() as usize).max(8);
        out.extend(
            (0..nu).map(|k| c.point(g, t, 1.0, k as f32 / nu as f32 * std::f32::consts::TAU)),
        );
    }
    out
}

/// The stray share (percent) in the worst of three views, and the worst cluster's stray pixels
/// in that view.
fn stray_pct(asset: &HairAsset, volume: &HairVolume) -> (f64, usize) {
    let b = asset.bounds();
    let shells: Vec<Vec<Vec3>> = volume.clusters().map(|(g, c)| shell_points(g, c)).collect();
    let mut worst = (0.0f64, 0usize);
    // The bench camera of scenes/tressfx-ponytail.toml (from behind on the right), the side
    // and the back.
    for forward in [
        Vec3::new(-59.4, -19.8, 59.4),
        Vec3::new(-1.0, 0.0, 0.0),
        Vec3::new(0.0, 0.0, 1.0),
    ] {
        let view = View::new(forward, b.min, b.max);
        let mut strands = view.mask();
        for s in asset.strands() {
            for w in s.windows(2) {
                segment_points(w[0], w[1]).for_each(|p| view.set(&mut strands, p));
            }
        }
        let allowed = view.dilate(&strands, DILATION_PX);
        let mut hair = view.mask();
        let mut per_cluster = Vec::new();
        for shell in &shells {
            let mut own = view.mask();
            shell.iter().for_each(|&p| view.set(&mut own, p));
            per_cluster.push(
                own.iter()
                    .zip(&allowed)
                    .filter(|(o, a)| **o && !**a)
                    .count(),
            );
            for (h, o) in hair.iter_mut().zip(&own) {
                *h |= *o;
            }
        }
        let count = hair.iter().filter(|h| **h).count();
        let outside = hair
            .iter()
            .zip(&allowed)
            .filter(|(h, a)| **h && !**a)
            .count();
        let pct = 100.0 * outside as f64 / count.max(1) as f64;
        let worst_cluster = per_cluster.iter().copied().max().unwrap_or(0);
        eprintln!(
            "view {forward}: {outside} of {count} cluster pixels outside ({pct:.2}%), worst \
             cluster {worst_cluster}"
        );
        if pct >= worst.0 {
            worst = (pct, worst_cluster);
        }
    }
    worst
}

/// The largest ratio of a cluster's axis length to its longest strand (reconstructed from its
/// local coordinates). The trajectory is extended to the points past its ends (a fan's tips
/// beyond its short mean), so it may be longer than its strands, but not by much.
fn longest_axis(volume: &HairVolume) -> f32 {
    volume
        .clusters()
        .map(|(g, c)| {
            let longest = c
                .strands()
                .iter()
                .map(|l| {
                    let p: Vec<Vec3> = l
                        .points()
                        .iter()
                        .map(|q| c.point(g, q.t, q.v, q.u))
                        .collect();
                    p.windows(2).map(|w| w[0].distance(w[1])).sum::<f32>()
                })
                .fold(0.0f32, f32::max);
            g.length() / longest.max(f32::MIN_POSITIVE)
        })
        .fold(0.0f32, f32::max)
}

#[test]
fn clusters_of_parts_merged_at_a_tie_stay_on_the_strands() {
    // Before the fix (each extension of a trajectory past its ends one point, so the refitted
    // spline shot off: a 51-unit axis for strands of 6 to 9 units, 4.46 times its longest
    // strand; groups under 8 strands never split; the cluster budget spent in the first rounds
    // on groups straying a little) the stray share was 0.62% with the crown ending at the tie
    // and 37.25% with the crown rooted at it. Now 0.17% and 0.17%, axes at most 1.31 times
    // their longest strand (1.85 unsplit).
    for crown_from_tie in [false, true] {
        let asset = merged_groom(crown_from_tie);
        assert_eq!(asset.strand_count(), 4933);
        let volume = fit_clusters(&asset, &FitSettings::default()).unwrap();
        let (pct, worst) = stray_pct(&asset, &volume);
        let axis = longest_axis(&volume);
        // Groups of 128 strands fitted as they are (no splitting, step 7): the axes themselves
        // stay near their strands' length (the one-point extension gave 8.69 and 4.05 times).
        let unsplit = FitSettings {
            strands_per_cluster: 128,
            stray_split: 0.0,
            ..Default::default()
        };
        let unsplit_axis = longest_axis(&fit_clusters(&asset, &unsplit).unwrap());
        eprintln!(
            "crown from the tie {crown_from_tie}: {} clusters, stray {pct:.2}% (worst cluster \
             {worst} pixels), longest axis {axis:.2} times its longest strand \
             ({unsplit_axis:.2} unsplit)",
            volume.macro_clusters.len()
        );
        assert!(
            axis.max(unsplit_axis) < 2.5,
            "crown from the tie {crown_from_tie}: an axis {:.2} times its longest strand",
            axis.max(unsplit_axis)
        );
        assert!(
            pct < 0.5,
            "crown from the tie {crown_from_tie}: {pct:.2}% of the clusters' silhouette is stray"
        );
    }
}
