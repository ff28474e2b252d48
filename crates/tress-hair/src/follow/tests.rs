use glam::{Mat3, Vec3};

use super::*;
use crate::kdtree::KdTree;

/// Three guides on a line, 5 apart, running down -y.
fn line_guides() -> HairAsset {
    let mut p = Vec::new();
    for g in 0..3 {
        for i in 0..16 {
            p.push(Vec3::new(g as f32 * 5.0, -(i as f32), 0.0));
        }
    }
    HairAsset::from_counts(p, &[16, 16, 16]).unwrap()
}

fn asset(strands: Vec<Vec<Vec3>>) -> HairAsset {
    let counts: Vec<u32> = strands.iter().map(|s| s.len() as u32).collect();
    HairAsset::from_counts(strands.concat(), &counts).unwrap()
}

/// Guides with a known root spacing `h` on a spherical cap of radius `head` (a plane if
/// infinite; both times `scale`): a jittered hexagonal lattice of `rings` rings about the top, wrapped onto the
/// sphere along great circles (which keeps distances from the top), each guide leaving the
/// scalp along its normal and bending down under gravity, `length` long with `vertices`
/// vertices. `shape` moves every vertex `i` by `i` times an affine function of the root.
fn scalp_guides(
    h: f32,
    head: f32,
    rings: i32,
    vertices: usize,
    length: f32,
    scale: f32,
    shape: Option<(Vec3, Mat3)>,
) -> HairAsset {
    let mut rng = Rng::new(21);
    let mut strands = Vec::new();
    for a in -rings..=rings {
        for b in -rings..=rings {
            if (a + b).abs() > rings {
                continue;
            }
            // Hexagonal lattice point, jittered by a tenth of the spacing.
            let flat = Vec2::new(a as f32 + 0.5 * b as f32, b as f32 * 0.75f32.sqrt()) * h
                + Vec2::new(rng.range(-0.1, 0.1), rng.range(-0.1, 0.1)) * h;
            let (normal, root) = if head.is_finite() {
                let angle = flat.length() / head;
                let dir = flat.normalize_or_zero();
                let normal = Vec3::new(angle.sin() * dir.x, angle.cos(), angle.sin() * dir.y);
                (normal, normal * head)
            } else {
                (Vec3::Y, Vec3::new(flat.x, 0.0, flat.y))
            };
            let strand: Vec<Vec3> = (0..vertices)
                .map(|i| {
                    let s = length * i as f32 / (vertices - 1) as f32;
                    let droop = Vec3::new(0.0, -0.5 * s * s / length.max(f32::MIN_POSITIVE), 0.0);
                    let extra = shape.map_or(Vec3::ZERO, |(c, m)| (c + m * root) * i as f32);
                    (root + normal * s + droop + extra) * scale
                })
                .collect();
            strands.push(strand);
        }
    }
    asset(strands)
}

fn roots(h: &HairAsset) -> Vec<Vec3> {
    (0..h.strand_count()).map(|i| h.strand(i)[0]).collect()
}

/// The median distance from a root to the nearest other root.
fn median_spacing(points: &[Vec3]) -> f32 {
    let tree = KdTree::new(points);
    let mut d: Vec<f32> = points
        .par_iter()
        .enumerate()
        .map(|(i, &p)| tree.nearest(p, 1, |j| j as usize == i)[0].1.sqrt())
        .collect();
    let mid = d.len() / 2;
    *d.select_nth_unstable_by(mid, f32::total_cmp).1
}

/// The largest ratio, over the three axes, of the followed asset's extent to the guides'.
fn bounds_ratio(followed: &HairAsset, guides: &HairAsset) -> f32 {
    let (a, b) = (followed.bounds(), guides.bounds());
    ((a.max - a.min) / (b.max - b.min)).max_element()
}

#[test]
fn offset_followers_fan_out_around_their_guide() {
    let params = FollowParams {
        count: 4,
        mode: FollowMode::Offset,
        root_radius: FollowRadius::World(0.5),
        tip_separation: 2.0,
        seed: 9,
    };
    let h = line_guides().with_follow_hairs(&params).unwrap();
    assert_eq!(h.strand_count(), 3 * 5);
    for g in 0..3 {
        let guide = h.strand(g * 5);
        assert_eq!(guide, line_guides().strand(g));
        for f in 1..5 {
            let s = h.strand(g * 5 + f);
            let root = s[0] - guide[0];
            let tip = s[15] - guide[15];
            assert!(root.length() <= 0.5 + 1e-5);
            // The roots are collinear, so the offsets lie across the guide (it runs along -Y).
            assert!(root.y.abs() < 1e-5);
            assert!((tip.length() - 3.0 * root.length()).abs() < 1e-4);
        }
    }
}

#[test]
fn deterministic_for_a_seed() {
    let guides = scalp_guides(1.0, 10.0, 4, 8, 6.0, 1.0, None);
    for mode in [FollowMode::Interpolate, FollowMode::Offset] {
        let p = FollowParams {
            count: 3,
            mode,
            seed: 1,
            ..Default::default()
        };
        let a = guides.with_follow_hairs(&p).unwrap();
        assert_eq!(a, guides.with_follow_hairs(&p).unwrap());
        let q = FollowParams { seed: 2, ..p };
        assert_ne!(a, guides.with_follow_hairs(&q).unwrap());
    }
}

#[test]
fn rejects_bad_parameters() {
    let p = FollowParams {
        count: 1,
        root_radius: FollowRadius::World(f32::NAN),
        ..Default::default()
    };
    assert!(line_guides().with_follow_hairs(&p).is_err());
    let p = FollowParams {
        count: u32::MAX,
        ..Default::default()
    };
    assert!(line_guides().with_follow_hairs(&p).is_err());
    // One guide has no spacing to derive a radius from; an explicit radius works.
    let one = asset(vec![vec![Vec3::ZERO, Vec3::NEG_Y]]);
    let p = FollowParams {
        count: 2,
        ..Default::default()
    };
    assert!(one.with_follow_hairs(&p).is_err());
    let p = FollowParams {
        root_radius: FollowRadius::World(0.1),
        ..p
    };
    assert_eq!(one.with_follow_hairs(&p).unwrap().strand_count(), 3);
}

#[test]
fn radius_parses_world_units_and_multiples_of_the_spacing() {
    assert_eq!(
        "0.25".parse::<FollowRadius>().unwrap(),
        FollowRadius::World(0.25)
    );
    assert_eq!(
        "0.6x".parse::<FollowRadius>().unwrap(),
        FollowRadius::Spacing(0.6)
    );
    assert_eq!(
        " 2 X".parse::<FollowRadius>().unwrap(),
        FollowRadius::Spacing(2.0)
    );
    for bad in ["", "x", "-1", "1xx", "nanx", "inf"] {
        assert!(bad.parse::<FollowRadius>().is_err(), "{bad}");
    }
    assert_eq!(FollowRadius::Spacing(0.6).to_string(), "0.6x");
    assert_eq!("offset".parse::<FollowMode>().unwrap(), FollowMode::Offset);
    assert!("clump".parse::<FollowMode>().is_err());
}

#[test]
fn the_default_radius_follows_the_guides_spacing() {
    for scale in [1.0, 0.01] {
        let guides = scalp_guides(1.0, 10.0, 5, 8, 6.0, scale, None);
        let (_, report) = guides
            .follow_hairs(&FollowParams {
                count: 2,
                ..Default::default()
            })
            .unwrap();
        // The median nearest-neighbour distance, by brute force.
        let r = roots(&guides);
        let mut nearest: Vec<f32> = r
            .iter()
            .enumerate()
            .map(|(i, p)| {
                r.iter()
                    .enumerate()
                    .filter(|&(j, _)| j != i)
                    .map(|(_, q)| p.distance(*q))
                    .fold(f32::INFINITY, f32::min)
            })
            .collect();
        nearest.sort_by(f32::total_cmp);
        let want = nearest[nearest.len() / 2];
        let spacing = report.root_spacing.unwrap();
        assert!((spacing - want).abs() <= 1e-6 * want, "{spacing} vs {want}");
        // The lattice's spacing, less what the jitter takes from the nearest neighbour.
        assert!(
            (0.8..=1.0).contains(&(spacing / scale)),
            "spacing {spacing} at scale {scale}"
        );
        assert!((report.root_radius - DEFAULT_RADIUS_FACTOR * spacing).abs() < 1e-6);
        assert_eq!(report.offset_guides, 0);
    }
}

/// The test: guides of a known spacing at two unit scales; the followed asset's bounding
/// box stays within 1.2× the guides' on every axis, and the roots' median nearest-neighbour
/// distance is at least `ratio` × the guides' median / sqrt(N + 1).
#[test]
fn followers_fill_the_scalp_at_any_scale() {
    for scale in [1.0f32, 0.01] {
        let guides = scalp_guides(1.0, 12.0, 9, 16, 10.0, scale, None);
        let guide_spacing = median_spacing(&roots(&guides));
        for (mode, ratio) in [(FollowMode::Offset, 0.5), (FollowMode::Interpolate, 0.7)] {
            for count in [3u32, 8, 27] {
                let followed = guides
                    .with_follow_hairs(&FollowParams {
                        count,
                        mode,
                        seed: 3,
                        ..Default::default()
                    })
                    .unwrap();
                assert_eq!(
                    followed.strand_count(),
                    guides.strand_count() * (count as usize + 1)
                );
                let b = bounds_ratio(&followed, &guides);
                assert!(
                    b <= 1.2,
                    "{mode:?} ×{count} at scale {scale}: bounds grow {b}×"
                );
                let even = median_spacing(&roots(&followed))
                    / (guide_spacing / (count as f32 + 1.0).sqrt());
                eprintln!(
                    "scale {scale}, {mode:?} × {count}: spacing ratio {even:.3}, bounds {b:.3}×"
                );
                assert!(
                    even >= ratio,
                    "{mode:?} ×{count} at scale {scale}: spacing ratio {even} < {ratio}"
                );
            }
        }
    }
}

#[test]
fn interpolated_followers_blend_their_guides() {
    // Guides whose shapes vary affinely with their roots: any barycentric blend of three of
    // them is the guide an exact root there would have, so with no tip stray every follower
    // must be `root + i (c + M root)` at its own root.
    let c = Vec3::new(0.0, -1.0, 0.2);
    let m = Mat3::from_cols(
        Vec3::new(0.05, 0.0, 0.01),
        Vec3::new(0.0, 0.02, 0.0),
        Vec3::new(-0.03, 0.0, 0.04),
    );
    let guides = scalp_guides(1.0, f32::INFINITY, 5, 8, 0.0, 1.0, Some((c, m)));
    let followed = guides
        .with_follow_hairs(&FollowParams {
            count: 6,
            tip_separation: 0.0,
            ..Default::default()
        })
        .unwrap();
    for s in 0..followed.strand_count() {
        let strand = followed.strand(s);
        let root = strand[0];
        for (i, p) in strand.iter().enumerate() {
            let want = root + (c + m * root) * i as f32;
            assert!(
                p.distance(want) < 1e-3,
                "strand {s} vertex {i}: {p} vs {want}"
            );
        }
    }
    // Followers lie between guides: no root is outside the guides' bounds.
    let (g, f) = (guides.bounds(), followed.bounds());
    assert!(f.min.cmpge(g.min - 1e-4).all() && f.max.cmple(g.max + 1e-4).all());
}

#[test]
fn a_single_row_of_guides_falls_back_to_offsets() {
    let (h, report) = line_guides()
        .follow_hairs(&FollowParams {
            count: 2,
            ..Default::default()
        })
        .unwrap();
    assert_eq!(report.offset_guides, 3);
    assert_eq!(h.strand_count(), 9);
    assert!((report.root_radius - 0.7 * 5.0).abs() < 1e-5);
}

#[test]
fn attributes_are_copied_from_the_guide() {
    let guides = scalp_guides(1.0, 10.0, 2, 4, 3.0, 1.0, None);
    let n = guides.vertex_count();
    let thickness: Vec<f32> = (0..n).map(|i| i as f32).collect();
    let guides = guides.with_thickness(thickness).unwrap();
    let h = guides
        .with_follow_hairs(&FollowParams {
            count: 2,
            ..Default::default()
        })
        .unwrap();
    let t = h.thickness().unwrap();
    for g in 0..guides.strand_count() {
        for f in 0..3 {
            let r = h.strand_range(g * 3 + f);
            assert_eq!(&t[r], &guides.thickness().unwrap()[guides.strand_range(g)]);
        }
    }
}
