//! Tests of the generated styles.

use glam::{Vec2, Vec3};

use super::*;

/// A style's default parameters with fewer strands, for quick tests.
fn small(style: Style, strands: u32) -> StyleParams {
    StyleParams {
        strands,
        ..style.default_params()
    }
}

fn min_level(style: Style, h: &HairAsset) -> f32 {
    let head = head_for(style);
    h.positions()
        .iter()
        .map(|&p| head.level(p))
        .fold(f32::INFINITY, f32::min)
}

#[test]
fn names_parse_back() {
    for style in Style::ALL {
        assert_eq!(style.to_string().parse::<Style>().unwrap(), style);
        assert_eq!(style.to_string(), style.to_string().to_lowercase());
    }
    assert_eq!("ponytail".parse::<Style>().unwrap(), Style::Ponytail);
    let err = "mohawk".parse::<Style>().unwrap_err().to_string();
    assert!(err.contains("mohawk") && err.contains("curly"), "{err}");
}

#[test]
fn counts_thickness_and_uv() {
    for style in Style::ALL {
        let p = StyleParams {
            strands: 300,
            vertices: 9,
            thickness: 0.01,
            ..style.default_params()
        };
        let h = generate(style, &p).unwrap();
        assert_eq!(h.strand_count(), 300, "{style}");
        assert_eq!(h.vertices_per_strand_range(), (9, 9));
        let t = h.thickness().unwrap();
        for s in 0..300 {
            let t = &t[h.strand_range(s)];
            assert_eq!(t[0], 0.01);
            assert!((t[8] - 0.001).abs() < 1e-7);
            assert!(t.windows(2).all(|w| w[1] < w[0]), "tapers toward the tip");
        }
        let uv = h.strand_uv().unwrap();
        assert!(
            uv.iter()
                .all(|uv| (0.0..=1.0).contains(&uv.x) && (0.0..=1.0).contains(&uv.y))
        );
        // The UV names the root's place on the head (scalp) or body coordinate.
        let head = head_for(style);
        for (s, uv) in uv.iter().enumerate() {
            let at = if style == Style::Fur {
                head.body_point(*uv)
            } else {
                head.scalp_point(*uv)
            };
            assert!(
                at.position.distance(h.strand(s)[0]) < 1e-3,
                "{style} strand {s}"
            );
        }
    }
}

#[test]
fn default_ponytail_has_the_papers_size() {
    let p = Style::Ponytail.default_params();
    assert_eq!((p.strands, p.vertices), (136_320, 13));
    let h = generate(Style::Ponytail, &p).unwrap();
    // Jansson et al. 2019, Table 1: 136,320 strands, 1,772,160 vertices, 1,635,840 segments.
    assert_eq!(h.strand_count(), 136_320);
    assert_eq!(h.vertex_count(), 1_772_160);
    assert_eq!(h.segment_count(), 1_635_840);
}

#[test]
fn same_seed_same_asset_other_seed_other_asset() {
    for style in Style::ALL {
        let p = small(style, 500);
        let a = generate(style, &p).unwrap();
        assert_eq!(a, generate(style, &p).unwrap(), "{style}");
        let b = generate(style, &StyleParams { seed: 1, ..p }).unwrap();
        assert_ne!(a.positions(), b.positions(), "{style}");
    }
    // Strand i does not depend on how many strands there are (its own random stream).
    let p = small(Style::Straight, 100);
    let few = generate(Style::Straight, &StyleParams { strands: 10, ..p }).unwrap();
    let many = generate(Style::Straight, &p).unwrap();
    assert_eq!(few.strand(7), many.strand(7));
}

#[test]
fn strands_stay_outside_the_head() {
    for style in Style::ALL {
        let h = generate(style, &small(style, 2000)).unwrap();
        let level = min_level(style, &h);
        assert!(level > 1.0 - 1e-4, "{style}: a vertex at level {level}");
        // Roots on the surface.
        let head = head_for(style);
        for s in h.strands() {
            assert!((head.level(s[0]) - 1.0).abs() < 1e-4);
        }
    }
}

#[test]
fn segments_stay_outside_the_head_too() {
    // The paper's ponytail has 13 vertices over about 50 units: segments of several units,
    // whose chords over the scalp would dip into the head (and be hidden by it) if only the
    // vertices were kept out. Sample each segment and check it stays outside.
    for style in Style::ALL {
        let h = generate(style, &small(style, 1000)).unwrap();
        let head = head_for(style);
        let mut inside = 0;
        for s in h.strands() {
            for w in s.windows(2) {
                inside += (1..8)
                    .map(|k| w[0].lerp(w[1], k as f32 / 8.0))
                    .filter(|&p| head.level(p) < 1.0 - 1e-4)
                    .count();
            }
        }
        assert_eq!(inside, 0, "{style}: points of segments inside the head");
    }
}

#[test]
fn hanging_hair_falls_and_leaves_the_face_free() {
    for style in [Style::Straight, Style::Wavy, Style::Curly] {
        let h = generate(style, &small(style, 2000)).unwrap();
        let head = head_for(style);
        let mut below = 0;
        for s in h.strands() {
            let (root, tip) = (s[0], s[s.len() - 1]);
            assert!(tip.y < root.y, "{style}: a strand grows up");
            below += usize::from(tip.y < head.center.y - head.radii.y);
            // Nothing hangs in front of the face: in front of the head's front half (z > 0.5
            // radii), only the roots themselves and hair high on the forehead.
            for p in s {
                let q = (*p - head.center) / head.radii;
                assert!(
                    !(q.z > 0.8 && q.y < 0.2 && q.x.abs() < 0.5),
                    "{style}: {p} covers the face"
                );
            }
        }
        // 30 cm hair reaches below the head for most strands, 22 cm curls for a good part.
        let expected = if style == Style::Curly { 0.3 } else { 0.6 };
        assert!(
            below as f32 > expected * h.strand_count() as f32,
            "{style}: only {below} strands hang below the head"
        );
    }
}

#[test]
fn curly_strands_wind_around_a_helix() {
    // 161 vertices over 40 cm: 0.25 cm per segment, and 0.5 turns per cm: 8 vertices per turn.
    let p = StyleParams {
        strands: 200,
        vertices: 161,
        length: 40.0,
        curl_radius: 1.0,
        curl_frequency: 0.5,
        clumping: 0.0,
        noise: 0.0,
        ..Style::Curly.default_params()
    };
    let h = generate(Style::Curly, &p).unwrap();
    let head = head_for(Style::Curly);
    let mut checked = 0;
    for s in h.strands() {
        // The last 8 turns, if they hang freely below the head: the helix axis is then vertical.
        let tail = &s[s.len() - 64..];
        if tail
            .iter()
            .any(|p| p.y > head.center.y - head.radii.y - 2.0)
        {
            continue;
        }
        checked += 1;
        let axis = tail.iter().map(|p| Vec2::new(p.x, p.z)).sum::<Vec2>() / 64.0;
        let mut prev_angle: Option<f32> = None;
        for p in tail {
            let d = Vec2::new(p.x, p.z) - axis;
            assert!(
                (d.length() - 1.0).abs() < 0.15,
                "distance from the axis {}",
                d.length()
            );
            let angle = d.y.atan2(d.x);
            if let Some(a) = prev_angle {
                // A turn every 8 vertices: 45° per vertex, always the same way round.
                let step = (angle - a + std::f32::consts::PI).rem_euclid(std::f32::consts::TAU)
                    - std::f32::consts::PI;
                assert!(
                    (step.abs() - std::f32::consts::FRAC_PI_4).abs() < 0.12,
                    "step {step}"
                );
            }
            prev_angle = Some(angle);
        }
        // The axis descends one turn per 2 cm.
        let drop = tail[0].y - tail[63].y;
        assert!((drop - 63.0 * 0.25).abs() < 0.5, "drop {drop}");
    }
    assert!(checked > 50, "only {checked} strands hang freely");
}

#[test]
fn wavy_strands_wave_in_a_plane() {
    let p = StyleParams {
        strands: 200,
        vertices: 161,
        length: 40.0,
        curl_radius: 1.0,
        curl_frequency: 0.25,
        clumping: 0.0,
        noise: 0.0,
        ..Style::Wavy.default_params()
    };
    let h = generate(Style::Wavy, &p).unwrap();
    let head = head_for(Style::Wavy);
    let mut checked = 0;
    for s in h.strands() {
        // Two whole waves (16 vertices each) hanging below the head.
        let tail = &s[s.len() - 33..];
        if tail
            .iter()
            .any(|p| p.y > head.center.y - head.radii.y - 2.0)
        {
            continue;
        }
        checked += 1;
        let centre = tail[..32].iter().map(|p| Vec2::new(p.x, p.z)).sum::<Vec2>() / 32.0;
        let offsets: Vec<Vec2> = tail.iter().map(|p| Vec2::new(p.x, p.z) - centre).collect();
        // Planar: all horizontal offsets along one line through the centre.
        let widest = offsets
            .iter()
            .copied()
            .max_by(|a, b| a.length().total_cmp(&b.length()))
            .unwrap();
        assert!(
            (widest.length() - 1.0).abs() < 0.1,
            "amplitude {}",
            widest.length()
        );
        let dir = widest.normalize();
        for o in &offsets {
            assert!(
                o.perp_dot(dir).abs() < 0.1,
                "off the wave's plane by {}",
                o.perp_dot(dir)
            );
        }
        // A wave every 4 cm: the offset along the plane changes sign 4 times in two waves.
        let along: Vec<f32> = offsets.iter().map(|o| o.dot(dir)).collect();
        let crossings = along
            .windows(2)
            .filter(|w| (w[0] < 0.0) != (w[1] < 0.0))
            .count();
        assert!((3..=5).contains(&crossings), "{crossings} sign changes");
    }
    assert!(checked > 50, "only {checked} strands hang freely");
}

#[test]
fn clumping_brings_tips_together() {
    let distinct_tips = |clumping: f32| {
        let p = StyleParams {
            clumping,
            noise: 0.0,
            ..small(Style::Straight, 4000)
        };
        let h = generate(Style::Straight, &p).unwrap();
        let mut tips: Vec<[i64; 3]> = h
            .strands()
            .map(|s| {
                s[s.len() - 1]
                    .to_array()
                    .map(|x| (x * 100.0).round() as i64)
            })
            .collect();
        tips.sort_unstable();
        tips.dedup();
        tips.len()
    };
    assert!(distinct_tips(0.0) > 3900);
    // Full clumping: every strand's tip is its clump centre's tip (400 clumps on the scalp).
    assert!(distinct_tips(1.0) <= 400, "{}", distinct_tips(1.0));
}

#[test]
fn noise_grows_toward_the_tip() {
    let p = StyleParams {
        noise: 0.0,
        ..small(Style::Fur, 500)
    };
    let calm = generate(Style::Fur, &p).unwrap();
    let noisy = generate(Style::Fur, &StyleParams { noise: 0.2, ..p }).unwrap();
    let body = head_for(Style::Fur);
    let mut tip_moves = 0.0;
    for s in 0..500 {
        let (a, b) = (calm.strand(s), noisy.strand(s));
        assert_eq!(a[0], b[0], "roots do not move");
        for i in 1..6 {
            // Away from the body (where collision may push), the move is bounded by noise * t.
            if body.level(a[i]) > 1.01 && body.level(b[i]) > 1.01 {
                assert!(a[i].distance(b[i]) <= 0.2 * i as f32 / 5.0 + 1e-4);
            }
        }
        tip_moves += a[5].distance(b[5]);
    }
    // Uniform in a ball of radius 0.2 scaled by a uniform length: mean 0.1.
    let mean = tip_moves / 500.0;
    assert!((0.07..0.13).contains(&mean), "mean tip displacement {mean}");
}

#[test]
fn ponytail_gathers_behind_the_head() {
    let p = StyleParams {
        noise: 0.0,
        ..small(Style::Ponytail, 3000)
    };
    let h = generate(Style::Ponytail, &p).unwrap();
    let head = head_for(Style::Ponytail);
    let spread = |points: &[Vec3]| {
        let c = points.iter().sum::<Vec3>() / points.len() as f32;
        (c, points.iter().map(|p| p.distance(c)).fold(0.0, f32::max))
    };
    let roots: Vec<Vec3> = h.strands().map(|s| s[0]).collect();
    let tips: Vec<Vec3> = h.strands().map(|s| s[s.len() - 1]).collect();
    let (_, root_spread) = spread(&roots);
    let (tip_centre, tip_spread) = spread(&tips);
    assert!(root_spread > 8.0, "roots cover the scalp: {root_spread}");
    // The tail (radius at most 3 cm, clumped) ends behind the head, 35 cm of tail below the
    // tie, which sits a little above the head's middle.
    assert!(tip_spread < 4.0, "tips spread over {tip_spread}");
    assert!(tip_centre.z < head.center.z - head.radii.z, "{tip_centre}");
    assert!(tip_centre.y < head.center.y - 25.0, "{tip_centre}");
}

#[test]
fn fur_points_out_of_the_body() {
    let p = StyleParams {
        noise: 0.0,
        clumping: 0.0,
        ..small(Style::Fur, 2000)
    };
    let h = generate(Style::Fur, &p).unwrap();
    let body = head_for(Style::Fur);
    for s in h.strands() {
        let n = body
            .surface_point(((s[0] - body.center) / body.radii).normalize())
            .1;
        let out = s[s.len() - 1] - s[0];
        // Short (1.5), leaning but rooted outward: the tip is above the surface.
        assert!(out.length() <= 1.5 + 1e-4);
        assert!(out.dot(n) > 0.5, "{}", out.dot(n));
        assert!((s[1] - s[0]).normalize().dot(n) > 0.8);
    }
    assert!(h.bounds().size().z > 40.0, "covers the whole body");
}

#[test]
fn rejects_bad_parameters() {
    let ok = Style::Straight.default_params();
    let bad = [
        StyleParams { strands: 0, ..ok },
        StyleParams { vertices: 1, ..ok },
        StyleParams {
            strands: u32::MAX,
            vertices: 16,
            ..ok
        },
        StyleParams { length: -1.0, ..ok },
        StyleParams {
            length: f32::INFINITY,
            ..ok
        },
        StyleParams { length: 1e30, ..ok },
        StyleParams {
            curl_radius: f32::NAN,
            ..ok
        },
        StyleParams {
            curl_frequency: -0.1,
            ..ok
        },
        StyleParams { noise: -1.0, ..ok },
        StyleParams {
            thickness: f32::NAN,
            ..ok
        },
        StyleParams {
            clumping: 1.5,
            ..ok
        },
        StyleParams {
            clumping: f32::NAN,
            ..ok
        },
    ];
    for p in bad {
        for style in Style::ALL {
            assert!(
                matches!(generate(style, &p), Err(HairError::Parameter(_))),
                "{style} {p:?}"
            );
        }
    }
    // Degenerate but valid: zero length puts every vertex at the root.
    let h = generate(
        Style::Curly,
        &StyleParams {
            strands: 3,
            length: 0.0,
            noise: 0.0,
            clumping: 0.0,
            ..ok
        },
    )
    .unwrap();
    for s in h.strands() {
        assert!(s.iter().all(|p| p.distance(s[0]) < 0.1), "{s:?}");
    }
}
