use glam::{Vec2, Vec3};
use tress_hair::HairAsset;
use tress_hair::rng::Rng;

use super::*;

/// Strands uniformly filling a straight elliptic tube along -y: half-axes 2 and 1, major
/// axis turned 30° from +x toward +z.
fn tube(count: usize) -> Vec<Vec<Vec3>> {
    let mut rng = Rng::new(3);
    let q = 30f32.to_radians();
    (0..count)
        .map(|_| {
            let d = rng.in_disk();
            let xy = Vec2::from_angle(q).rotate(Vec2::new(2.0 * d.x, d.y));
            (0..16)
                .map(|k| Vec3::new(5.0 + xy.x, -(k as f32), xy.y))
                .collect()
        })
        .collect()
}

fn asset_of(strands: Vec<Vec<Vec3>>) -> Result<HairAsset, tress_hair::HairError> {
    let counts: Vec<u32> = strands.iter().map(|s| s.len() as u32).collect();
    HairAsset::from_counts(strands.into_iter().flatten().collect(), &counts)
}

fn refs(strands: &[Vec<Vec3>]) -> Vec<&[Vec3]> {
    strands.iter().map(|s| s.as_slice()).collect()
}

fn seg_dist(p: Vec3, a: Vec3, b: Vec3) -> f32 {
    let ab = b - a;
    let f = ((p - a).dot(ab) / ab.length_squared().max(1e-12)).clamp(0.0, 1.0);
    (a + ab * f).distance(p)
}

/// Distance from `p` to the polyline `strand`.
fn polyline_dist(p: Vec3, strand: &[Vec3]) -> f32 {
    strand
        .windows(2)
        .map(|w| seg_dist(p, w[0], w[1]))
        .fold(f32::INFINITY, f32::min)
}

#[test]
fn resample_by_arc_length() {
    let s = [Vec3::ZERO, Vec3::X, Vec3::new(1.0, 3.0, 0.0)];
    let r = resample(&s, 5).unwrap();
    assert_eq!(r[0], Vec3::ZERO);
    assert!((r[1] - Vec3::X).length() < 1e-6);
    assert!((r[2] - Vec3::new(1.0, 1.0, 0.0)).length() < 1e-6);
    assert!((r[4] - s[2]).length() < 1e-6);
    assert!(resample(&[Vec3::ONE, Vec3::ONE], 4).is_none());
}

#[test]
fn grouping_splits_at_medians() {
    // 8 strands whose roots sit at x = 0..8: groups of at most 2 are consecutive pairs.
    let strands: Vec<Vec<Vec3>> = (0..8)
        .map(|i| {
            vec![
                Vec3::new(i as f32, 0.0, 0.0),
                Vec3::new(i as f32, -1.0, 0.0),
            ]
        })
        .collect();
    let s = FitSettings {
        strands_per_cluster: 2,
        grouping_samples: 1,
        ..Default::default()
    };
    let mut groups = group_strands(&strands, &s);
    for g in &mut groups {
        g.sort();
    }
    groups.sort();
    assert_eq!(groups, vec![vec![0, 1], vec![2, 3], vec![4, 5], vec![6, 7]]);
}

#[test]
fn fits_an_elliptic_tube() {
    let strands = tube(400);
    let s = FitSettings {
        axis_quantile: 1.0,
        ..Default::default()
    };
    let m = fit_cluster(&refs(&strands), &s).unwrap();
    let g = &m.geometry;
    assert!((g.length() - 15.0).abs() < 0.2, "length {}", g.length());
    let (a, b, q) = g.profile(0.5);
    assert!(
        (a - 2.0).abs() < 0.15 && (b - 1.0).abs() < 0.1,
        "A {a} B {b}"
    );
    // The major axis direction (cos q n + sin q b) is ±(cos 30°, 0, sin 30°).
    let f = g.frame(0.5);
    let axis = q.cos() * f.normal + q.sin() * f.binormal;
    let want = Vec3::new(30f32.to_radians().cos(), 0.0, 30f32.to_radians().sin());
    assert!(axis.dot(want).abs() > 0.995, "axis {axis}");
    // Every strand point maps back to itself through (t, v, u).
    let c = &m.clusters[0];
    for (strand, local) in strands.iter().zip(c.strands()) {
        for (p, l) in strand.iter().zip(local.points()) {
            assert!(l.v <= 1.0);
            assert!(
                (c.point(g, l.t, l.v, l.u) - *p).length() < 0.02,
                "{p} vs {l:?}"
            );
        }
    }
}

#[test]
fn fits_a_generated_volume_and_reconstructs_its_strands() {
    use crate::generate::{ClusterStyle, generate_clusters};
    let style = ClusterStyle {
        macro_clusters: 3,
        clusters_per_macro: 2,
        strands_per_cluster: 60,
        ..Default::default()
    };
    let asset = generate_clusters(&tress_hair::generate::Head::default(), &style)
        .unwrap()
        .to_asset()
        .unwrap();
    let s = FitSettings {
        strands_per_cluster: 60,
        axis_quantile: 1.0,
        ..Default::default()
    };
    let vol = fit_clusters(&asset, &s).unwrap();
    let stats = vol.stats(&crate::shell::ShellSampling::default());
    assert_eq!(stats.strands, 360);
    assert_eq!(stats.skipped.total(), 0);
    // The cuts fall in the gaps between bundles: the generator's 6 clusters of 60 come back.
    assert_eq!(stats.clusters, 6);
    assert!(vol.clusters().all(|(_, c)| c.strands().len() == 60));
    // Reconstruction: every resampled point is P(t, v, u) of its local coordinates.
    let mut worst = 0.0f32;
    for (g, c) in vol.clusters() {
        for l in c.strands() {
            let p = l.points()[8];
            let q = c.point(g, p.t, p.v, p.u);
            let d = (0..asset.strand_count())
                .map(|i| polyline_dist(q, asset.strand(i)))
                .fold(f32::INFINITY, f32::min);
            worst = worst.max(d);
        }
    }
    assert!(worst < 0.05, "worst reconstruction error {worst}");
    assert!(
        fit_clusters(
            &asset,
            &FitSettings {
                control_points: 2,
                ..s
            }
        )
        .is_err()
    );
}

/// A hand-built cluster: its strands and the radius of the tube they were built in (0 for a
/// single strand).
struct Shape {
    name: &'static str,
    strands: Vec<Vec<Vec3>>,
    radius: f32,
}

/// A point on the curved axis used by the hand-built shapes, at arc-length-like parameter `s`
/// (world units): down -y, bending toward +x.
fn curved_axis(s: f32) -> (Vec3, Vec3, Vec3) {
    let bend = 0.02;
    let p = Vec3::new(bend * s * s, -s, 0.0);
    let tangent = Vec3::new(2.0 * bend * s, -1.0, 0.0).normalize();
    let normal = Vec3::new(1.0, 2.0 * bend * s, 0.0).normalize();
    (p, tangent, normal)
}

/// Strands in a round tube of `radius` about the curved axis, lengths from `lengths`, with
/// `samples` points each.
fn curved_tube(
    count: usize,
    radius: f32,
    samples: usize,
    mut lengths: impl FnMut(&mut Rng) -> f32,
) -> Vec<Vec<Vec3>> {
    let mut rng = Rng::new(17);
    (0..count)
        .map(|_| {
            let d = rng.in_disk() * radius;
            let len = lengths(&mut rng);
            (0..samples)
                .map(|k| {
                    let s = len * k as f32 / (samples - 1) as f32;
                    let (p, _, n) = curved_axis(s);
                    p + d.x * n + d.y * Vec3::Z
                })
                .collect()
        })
        .collect()
}

fn shapes() -> Vec<Shape> {
    let mut out = Vec::new();
    // Very different lengths in one cluster: 3 to 30 units.
    out.push(Shape {
        name: "varied lengths",
        strands: curved_tube(120, 1.0, 16, |r| r.range(3.0, 30.0)),
        radius: 1.0,
    });
    // Very short strands (fur): 4 vertices, 0.3 units long, in a tube of radius 0.05.
    out.push(Shape {
        name: "very short",
        strands: curved_tube(80, 0.05, 4, |r| r.range(0.2, 0.3)),
        radius: 0.05,
    });
    // Short and long mixed: a tenth of the strands are 1/50 of the others' length.
    out.push(Shape {
        name: "short among long",
        strands: curved_tube(100, 1.0, 16, |r| if r.f32() < 0.1 { 0.5 } else { 25.0 }),
        radius: 1.0,
    });
    // Folding back: down 10 units, a U-turn of radius 3, up 6 units.
    let mut rng = Rng::new(5);
    let fold: Vec<Vec<Vec3>> = (0..60)
        .map(|_| {
            let d = rng.in_disk() * 0.6;
            let mut s = Vec::new();
            for k in 0..=10 {
                s.push(Vec3::new(d.x, -(k as f32), d.y));
            }
            for k in 1..12 {
                let a = std::f32::consts::PI * k as f32 / 12.0;
                let r = 3.0 - d.x;
                s.push(Vec3::new(3.0 - r * a.cos(), -10.0 - r * a.sin(), d.y));
            }
            for k in 0..=6 {
                s.push(Vec3::new(6.0 - d.x, -10.0 + k as f32, d.y));
            }
            resample(&s, 24).expect("long strand")
        })
        .collect();
    out.push(Shape {
        name: "folding back",
        strands: fold,
        radius: 0.6,
    });
    // Perfectly straight, parallel strands on a grid.
    let straight: Vec<Vec<Vec3>> = (0..7)
        .flat_map(|i| (0..7).map(move |j| (i, j)))
        .map(|(i, j)| {
            let x = 0.2 * (i as f32 - 3.0);
            let z = 0.2 * (j as f32 - 3.0);
            (0..16).map(|k| Vec3::new(x, -2.0 * k as f32, z)).collect()
        })
        .collect();
    out.push(Shape {
        name: "straight",
        strands: straight,
        radius: 0.6 * std::f32::consts::SQRT_2,
    });
    // One strand alone, curved, and one alone, straight.
    out.push(Shape {
        name: "one curved strand",
        strands: curved_tube(1, 0.0, 16, |_| 20.0),
        radius: 0.0,
    });
    out.push(Shape {
        name: "one straight strand",
        strands: vec![(0..8).map(|k| Vec3::new(1.0, 2.0, -(k as f32))).collect()],
        radius: 0.0,
    });
    out
}

/// The distances from shell points `P(t, 1, u)` on a 49 × 24 grid to the nearest source
/// strand, sorted.
fn shell_distances(m: &MacroCluster, strands: &[Vec<Vec3>]) -> Vec<f32> {
    let (g, c) = (&m.geometry, &m.clusters[0]);
    let mut out = Vec::new();
    for i in 0..=48 {
        for k in 0..24 {
            let p = c.point(
                g,
                i as f32 / 48.0,
                1.0,
                k as f32 / 24.0 * std::f32::consts::TAU,
            );
            out.push(
                strands
                    .iter()
                    .map(|s| polyline_dist(p, s))
                    .fold(f32::INFINITY, f32::min),
            );
        }
    }
    out.sort_by(f32::total_cmp);
    out
}

#[test]
fn every_shape_reconstructs_and_its_shell_stays_on_the_strands() {
    for shape in shapes() {
        let name = shape.name;
        let strands = &shape.strands;
        let length = strands
            .iter()
            .map(|s| group::polyline_length(s))
            .fold(0.0f32, f32::max);
        for quantile in [1.0, FitSettings::default().axis_quantile] {
            let s = FitSettings {
                axis_quantile: quantile,
                ..Default::default()
            };
            let m = fit_cluster(&refs(strands), &s).unwrap_or_else(|e| panic!("{name}: {e}"));
            let min_radius = resolved_min_radius(&s, {
                let b = asset_of(strands.clone()).unwrap().bounds();
                b.max - b.min
            });
            let (g, c) = (&m.geometry, &m.clusters[0]);
            assert_eq!(
                c.strands().len(),
                strands.len(),
                "{name}: every strand kept"
            );
            // Every sample, tips included, comes back on its own strand: to within 5% of the
            // tube's radius (plus a thousandth of the length) when every point lies inside the
            // ellipse, and within 40% of it when the outermost 5% are pulled onto the shell.
            let tol = if quantile == 1.0 { 0.05 } else { 0.4 } * shape.radius.max(min_radius)
                + 1e-3 * length;
            for (si, (strand, local)) in strands.iter().zip(c.strands()).enumerate() {
                for (k, l) in local.points().iter().enumerate() {
                    let q = c.point(g, l.t, l.v, l.u);
                    let d = if quantile == 1.0 {
                        q.distance(strand[k])
                    } else {
                        polyline_dist(q, strand)
                    };
                    assert!(
                        d <= tol,
                        "{name} (quantile {quantile}): strand {si} sample {k} comes back \
                         {d} from its strand (tolerance {tol})"
                    );
                }
            }
            // No shell point lies far from every strand. The shell lies on the tube the strands
            // fill: nine shell points in ten lie within half the tube's radius of a strand, and
            // none farther than 1.5 radii (where a cluster thins out to its few longest strands
            // the shell closes over them, up to a radius from the farthest of them); around a
            // single strand, within twice the minimum half-axis.
            let far = (1.5 * shape.radius).max(2.0 * min_radius) + 1e-3 * length;
            let near = (0.5 * shape.radius).max(2.0 * min_radius) + 1e-3 * length;
            let d = shell_distances(&m, strands);
            let (worst, p90) = (d[d.len() - 1], d[d.len() * 9 / 10]);
            assert!(
                worst <= far && p90 <= near,
                "{name} (quantile {quantile}): shell points lie up to {worst} from every strand, \
                 90% within {p90} (limits {far} and {near})"
            );
        }
    }
}

#[test]
fn every_shape_through_fit_clusters_at_the_default_settings() {
    // The same shapes as whole assets: resampled to 16 points, grouped, fitted. Every strand is
    // in a cluster and comes back near its own strand; no shell point is far from every strand.
    for shape in shapes() {
        let name = shape.name;
        let asset = asset_of(shape.strands.clone()).unwrap();
        let vol = fit_clusters(&asset, &FitSettings::default()).unwrap();
        let stats = vol.stats(&crate::shell::ShellSampling::default());
        assert_eq!(stats.strands, asset.strand_count(), "{name}");
        assert_eq!(stats.skipped.total(), 0, "{name}");
        let b = asset.bounds();
        let min_radius = MIN_RADIUS_FRACTION * (b.max - b.min).length();
        let length = asset.length_stats().max;
        let tol = 0.4 * shape.radius.max(min_radius) + 2e-3 * length;
        let far = (1.5 * shape.radius).max(2.0 * min_radius) + 2e-3 * length;
        let mut worst_shell = 0.0f32;
        for (g, c) in vol.clusters() {
            for l in c.strands() {
                // The local strand's own source: the asset strand nearest its root sample.
                let root = c.point(g, l.points()[0].t, l.points()[0].v, l.points()[0].u);
                let own = (0..asset.strand_count())
                    .min_by(|&i, &j| {
                        polyline_dist(root, asset.strand(i))
                            .total_cmp(&polyline_dist(root, asset.strand(j)))
                    })
                    .unwrap();
                for p in l.points() {
                    let d = polyline_dist(c.point(g, p.t, p.v, p.u), asset.strand(own));
                    assert!(
                        d <= tol,
                        "{name}: a sample comes back {d} from its strand ({tol})"
                    );
                }
            }
            for i in 0..=32 {
                for k in 0..16 {
                    let p = c.point(
                        g,
                        i as f32 / 32.0,
                        1.0,
                        k as f32 / 16.0 * std::f32::consts::TAU,
                    );
                    let d = (0..asset.strand_count())
                        .map(|s| polyline_dist(p, asset.strand(s)))
                        .fold(f32::INFINITY, f32::min);
                    worst_shell = worst_shell.max(d);
                }
            }
        }
        assert!(
            worst_shell <= far,
            "{name}: a shell point lies {worst_shell} from every strand ({far})"
        );
    }
}

#[test]
fn every_strand_is_fitted_or_counted() {
    // Ten good strands, two points, one strand of zero length and one of two coincident
    // vertices far from the origin.
    let mut strands: Vec<Vec<Vec3>> = curved_tube(10, 0.5, 8, |_| 10.0);
    strands.push(vec![Vec3::new(1.0, 1.0, 1.0); 3]);
    strands.push(vec![
        Vec3::splat(1.0e4),
        Vec3::splat(1.0e4) + Vec3::X * 1e-4,
    ]);
    let asset = asset_of(strands).unwrap();
    let vol = fit_clusters(&asset, &FitSettings::default()).unwrap();
    let stats = vol.stats(&crate::shell::ShellSampling::default());
    assert_eq!(stats.strands, 10);
    assert_eq!(
        stats.skipped,
        SkippedStrands {
            too_short: 2,
            degenerate: 0
        }
    );
    assert_eq!(stats.strands + stats.skipped.total(), asset.strand_count());
    // Nothing to fit at all is an error, not an empty volume.
    let points = asset_of(vec![vec![Vec3::ONE; 2]]).unwrap();
    assert!(fit_clusters(&points, &FitSettings::default()).is_err());
}

#[test]
fn a_group_without_a_trajectory_is_fitted_strand_by_strand() {
    // Two strands leaving one root in opposite directions: their mean has no length.
    let up: Vec<Vec3> = (0..8).map(|k| Vec3::new(0.0, k as f32, 0.0)).collect();
    let down: Vec<Vec3> = up.iter().map(|p| -*p).collect();
    let s = FitSettings {
        strands_per_cluster: 2,
        grouping_samples: 1,
        ..Default::default()
    };
    assert!(matches!(
        fit_cluster(&[&up, &down], &s),
        Err(SatfError::Degenerate(_))
    ));
    let asset = asset_of(vec![up, down]).unwrap();
    let vol = fit_clusters(&asset, &s).unwrap();
    let stats = vol.stats(&crate::shell::ShellSampling::default());
    assert_eq!(
        (stats.clusters, stats.strands, stats.skipped.total()),
        (2, 2, 0)
    );
}

#[test]
fn minimum_radius_follows_the_scale_of_the_hair() {
    // The same tube in centimetres and in metres: the single-strand tube is a thousandth of
    // the hair's diagonal at both scales, not a fixed 0.05 world units.
    for scale in [1.0f32, 0.01] {
        let strand: Vec<Vec3> = (0..16)
            .map(|k| Vec3::new(0.0, -(k as f32) * 2.0 * scale, 0.0))
            .collect();
        let m = fit_cluster(&[&strand], &FitSettings::default()).unwrap();
        let (a, b, _) = m.geometry.profile(0.5);
        let want = MIN_RADIUS_FRACTION * 30.0 * scale;
        assert!(
            (a - want).abs() < 1e-3 * want && (b - want).abs() < 1e-3 * want,
            "scale {scale}: A {a} B {b}, want {want}"
        );
    }
}

#[test]
fn splitting_stays_within_the_cluster_budget() {
    // A ponytail's scalp part is a sheet curved across the head: its groups' shells stray and
    // are split (step 7), but never into more than max_clusters clusters.
    use tress_hair::generate::{Style, StyleParams, generate};
    let params = StyleParams {
        strands: 2000,
        vertices: 13,
        ..Style::Ponytail.default_params()
    };
    let asset = generate(Style::Ponytail, &params).unwrap();
    let count = |max_clusters: u32, stray_split: f32| {
        let s = FitSettings {
            max_clusters,
            stray_split,
            ..Default::default()
        };
        let vol = fit_clusters(&asset, &s).unwrap();
        let stats = vol.stats(&crate::shell::ShellSampling::default());
        assert_eq!(stats.strands + stats.skipped.total(), 2000);
        stats.clusters
    };
    let groups = count(u32::MAX, 0.0);
    let free = count(u32::MAX, 0.75);
    assert!(free > groups + 8, "{free} clusters from {groups} groups");
    let budget = groups as u32 + 4;
    let capped = count(budget, 0.75);
    assert!(
        capped > groups && capped <= budget as usize,
        "{capped} of {budget}"
    );
    // A budget below the groups' count splits nothing and drops nothing.
    assert_eq!(count(1, 0.75), groups);
    assert!(
        fit_clusters(
            &asset,
            &FitSettings {
                max_clusters: 0,
                ..Default::default()
            }
        )
        .is_err()
    );
}

#[test]
fn a_small_group_from_two_patches_is_split() {
    // Twelve strands from two patches of scalp 5 units apart (the side of the head and the
    // back) gathered into one tie, as at a ponytail's tie: one cluster's shell would span the
    // gap between the patches, where no strand is. Groups this small are split too.
    let mut rng = Rng::new(5);
    let tie = Vec3::new(1.5, 3.0, -10.0);
    let strands: Vec<Vec<Vec3>> = (0..12)
        .map(|i| {
            let patch = if i % 2 == 0 {
                Vec3::new(8.0, 0.0, 0.0)
            } else {
                Vec3::new(6.5, 0.0, -5.0)
            };
            let root = patch + Vec3::new(0.0, rng.range(-0.5, 0.5), rng.range(-0.5, 0.5));
            let end = tie + Vec3::new(rng.range(-0.2, 0.2), -12.0, rng.range(-0.2, 0.2));
            let mut s: Vec<Vec3> = (0..8).map(|k| root.lerp(tie, k as f32 / 8.0)).collect();
            s.extend((0..=8).map(|k| tie.lerp(end, k as f32 / 8.0)));
            s
        })
        .collect();
    let asset = asset_of(strands.clone()).unwrap();
    let vol = fit_clusters(&asset, &FitSettings::default()).unwrap();
    assert!(
        vol.macro_clusters.len() >= 2,
        "one cluster for both patches"
    );
    let worst = vol
        .macro_clusters
        .iter()
        .flat_map(|m| shell_distances(m, &strands))
        .fold(0.0f32, f32::max);
    assert!(worst < 1.5, "a shell point lies {worst} from every strand");
}
