//! Follow hairs on reproductions of the production assets of issue 13, at their shapes and
//! scales: a mohawk modelled in metres (10 cm strands, roots 3.5 mm apart, `--follow 8`), a
//! TressFX-ponytail-sized head (4,933 guides 0.47 units apart × 16 vertices, `--follow 27`:
//! 138,124 strands) and a bear-sized fur (48,113 guides × 4 vertices, `--follow 19`: 962,260
//! strands). Each must keep its bounds (within 1.2× per axis), lose nothing, and spread its
//! roots evenly. The spacing is measured here with a uniform grid, independently of the
//! library's k-d tree.
//!
//! Run with `--nocapture` to print the measured figures.

use std::collections::HashMap;
use std::f32::consts::PI;

use glam::{IVec3, Vec3};
use tress_hair::{FollowMode, FollowParams, HairAsset};

fn asset(strands: Vec<Vec<Vec3>>) -> HairAsset {
    let counts: Vec<u32> = strands.iter().map(|s| s.len() as u32).collect();
    HairAsset::from_counts(strands.concat(), &counts).unwrap()
}

/// The median distance from each point to its nearest other point, by a uniform grid of
/// cells `cell` wide (which must exceed most nearest-neighbour distances).
fn median_nearest(points: &[Vec3], cell: f32) -> f32 {
    let key = |p: Vec3| (p / cell).floor().as_ivec3();
    let mut grid: HashMap<IVec3, Vec<u32>> = HashMap::new();
    for (i, p) in points.iter().enumerate() {
        grid.entry(key(*p)).or_default().push(i as u32);
    }
    let mut d: Vec<f32> = points
        .iter()
        .enumerate()
        .map(|(i, &p)| {
            let k = key(p);
            let mut best = f32::INFINITY;
            for dx in -1..=1 {
                for dy in -1..=1 {
                    for dz in -1..=1 {
                        if let Some(cell) = grid.get(&(k + IVec3::new(dx, dy, dz))) {
                            for &j in cell {
                                if j as usize != i {
                                    best = best.min(points[j as usize].distance_squared(p));
                                }
                            }
                        }
                    }
                }
            }
            best.sqrt()
        })
        .collect();
    d.sort_by(f32::total_cmp);
    d[d.len() / 2]
}

fn roots(h: &HairAsset) -> Vec<Vec3> {
    (0..h.strand_count()).map(|i| h.strand(i)[0]).collect()
}

/// Follow `guides` with `count` followers in both modes and check bounds, counts and spacing,
/// printing what it measured.
fn check(name: &str, guides: &HairAsset, count: u32) {
    let guide_roots = roots(guides);
    let b = guides.bounds();
    let cell = (b.max - b.min).max_element() / 50.0;
    let guide_spacing = median_nearest(&guide_roots, cell);
    for (mode, ratio) in [(FollowMode::Offset, 0.5), (FollowMode::Interpolate, 0.7)] {
        let (followed, report) = guides
            .follow_hairs(&FollowParams {
                count,
                mode,
                seed: 1,
                ..Default::default()
            })
            .unwrap();
        assert_eq!(
            followed.strand_count(),
            guides.strand_count() * (count as usize + 1),
            "{name}: strands"
        );
        assert_eq!(
            followed.vertex_count(),
            guides.vertex_count() * (count as usize + 1),
            "{name}: vertices"
        );
        let (f, g) = (followed.bounds(), guides.bounds());
        let grow = ((f.max - f.min) / (g.max - g.min)).max_element();
        let expected = guide_spacing / (count as f32 + 1.0).sqrt();
        let even = median_nearest(
            &roots(&followed),
            cell / (count as f32 + 1.0).sqrt().max(1.0),
        ) / expected;
        eprintln!(
            "{name}, {} × {count}: {} guides → {} strands; root spacing {:.4} (reported {:.4}), \
             radius {:.4}; bounds {:.3}× the guides'; spacing ratio {even:.3}; {} guides offset",
            mode.name(),
            guides.strand_count(),
            followed.strand_count(),
            guide_spacing,
            report.root_spacing.unwrap_or(0.0),
            report.root_radius,
            grow,
            report.offset_guides,
        );
        assert!(grow <= 1.2, "{name} ({mode:?}): bounds grow {grow}×");
        assert!(
            even >= ratio,
            "{name} ({mode:?}): spacing ratio {even} < {ratio}"
        );
    }
}

/// A head of hair modelled in metres, shaped like the mohawk asset (a crest 0.2 m
/// across): roots 3.5 mm apart on a hexagonal lattice over the top of a 10 cm head, from the
/// forehead to the nape (±70°) and ±45° to the sides, 10 cm spikes of 16 vertices standing out
/// of the scalp.
fn mohawk() -> HairAsset {
    let (head, h, length) = (0.1f32, 0.0035f32, 0.1f32);
    let row_step = h * 0.75f32.sqrt();
    let rows = (head * 70f32.to_radians() / row_step) as i32;
    let columns = (head * 45f32.to_radians() / h) as i32;
    let mut strands = Vec::new();
    for r in -rows..=rows {
        for c in -columns..=columns {
            let (arc, lateral) = (r as f32 * row_step, (c as f32 + 0.5 * (r & 1) as f32) * h);
            let (a, b) = (arc / head, lateral / head);
            let normal = Vec3::new(b.sin(), a.cos() * b.cos(), a.sin() * b.cos()).normalize();
            let root = normal * head;
            strands.push(
                (0..16)
                    .map(|i| root + normal * length * i as f32 / 15.0)
                    .collect(),
            );
        }
    }
    asset(strands)
}

/// Roots evenly spread over the unit sphere (a Fibonacci lattice), `n` of them, keeping those
/// `keep` accepts.
fn fibonacci(n: usize, keep: impl Fn(Vec3) -> bool) -> Vec<Vec3> {
    (0..n)
        .map(|i| {
            let z = 1.0 - 2.0 * (i as f32 + 0.5) / n as f32;
            let r = (1.0 - z * z).max(0.0).sqrt();
            let a = i as f32 * PI * (3.0 - 5f32.sqrt());
            Vec3::new(r * a.cos(), z, r * a.sin())
        })
        .filter(|d| keep(*d))
        .collect()
}

/// A ponytail the size of TressFX's: 4,933 guide roots over the top three quarters of a head
/// of radius 10 (0.47 units apart), 16 vertices each: along the scalp to a tie at the back of
/// the crown, then hanging 30 units below it.
fn ponytail() -> HairAsset {
    let dirs = fibonacci(6577, |d| d.y > -0.5);
    assert_eq!(dirs.len(), 4933);
    let tie = Vec3::new(0.0, 0.7, -0.714).normalize();
    let strands = dirs
        .iter()
        .map(|&d| {
            let spread = (d - tie) * 0.8;
            (0..16)
                .map(|i| {
                    if i < 6 {
                        let f = i as f32 / 5.0;
                        d.lerp(tie, f).normalize() * (10.0 + 0.3 * f)
                    } else {
                        let f = (i - 5) as f32 / 10.0;
                        tie * 10.3 + spread * f + Vec3::new(0.0, -30.0 * f, -2.0 * f)
                    }
                })
                .collect()
        })
        .collect();
    asset(strands)
}

/// Fur the size of TressFX's bear: 48,113 guides of 4 vertices over an ellipsoid body
/// (40 × 30 × 60 units), 1.5 units long along the body's normal.
fn bear() -> HairAsset {
    let radii = Vec3::new(20.0, 15.0, 30.0);
    let strands = fibonacci(48_113, |_| true)
        .iter()
        .map(|&d| {
            let root = d * radii;
            let normal = (d / radii).normalize();
            (0..4)
                .map(|i| {
                    root + normal * 1.5 * i as f32 / 3.0 + Vec3::new(0.0, -0.1 * i as f32, 0.0)
                })
                .collect()
        })
        .collect();
    asset(strands)
}

#[test]
fn mohawk_in_metres_keeps_its_bounds() {
    let guides = mohawk();
    check("mohawk (metres)", &guides, 8);
    // The reproduction reproduces the issue: the old fixed 0.3-unit radius throws followers
    // 30 cm around roots 3.5 mm apart.
    let old = guides
        .with_follow_hairs(&FollowParams {
            count: 8,
            mode: FollowMode::Offset,
            root_radius: tress_hair::FollowRadius::World(0.3),
            seed: 1,
            ..Default::default()
        })
        .unwrap();
    let (f, g) = (old.bounds(), guides.bounds());
    let grow = ((f.max - f.min) / (g.max - g.min)).max_element();
    eprintln!("mohawk (metres), the old fixed radius 0.3: bounds {grow:.3}× the guides'");
    assert!(grow > 2.0, "{grow}");
}

#[test]
fn ponytail_scale_follows_evenly() {
    check("ponytail (TressFX scale)", &ponytail(), 27);
}

#[test]
fn bear_scale_fur_follows_evenly() {
    check("bear fur (TressFX scale)", &bear(), 19);
}
