use super::*;
use crate::sampling::lattice_point;
use tress_hair::HairAsset;
use tress_hair::generate::TriMesh;

/// A scene looking down -z from `(0, 0, 10)` at the origin (30° field of view), black
/// background, no head, no lights unless `extra` adds them, a hair entry for the material.
pub(super) fn scene(size: u32, extra: &str) -> Scene {
    let lights = if extra.contains("[[light]]") {
        ""
    } else {
        "light = []\n"
    };
    let text = format!(
        "background = [0.0, 0.0, 0.0]\n{lights}\
         [camera]\neye = [0.0, 0.0, 10.0]\ntarget = [0.0, 0.0, 0.0]\nup = [0.0, 1.0, 0.0]\n\
         fov_y_deg = 30.0\nnear = 0.1\nfar = 100.0\n\
         [output]\nwidth = {size}\nheight = {size}\n\
         [head]\ngenerated = false\n\
         {extra}\n\
         [[hair]]\nfiles = [\"unused.hair\"]\n\
         [hair.material]\nbase_color = [1.0, 1.0, 1.0]\n"
    );
    Scene::from_str(&text, ".").expect("test scene")
}

/// Straight two-vertex strands from `a` to `b` with a constant thickness.
pub(super) fn strands(pairs: &[(Vec3, Vec3)], thickness: f32) -> HairAsset {
    let positions: Vec<Vec3> = pairs.iter().flat_map(|&(a, b)| [a, b]).collect();
    let n = positions.len();
    HairAsset::from_counts(positions, &vec![2; pairs.len()])
        .unwrap()
        .with_thickness(vec![thickness; n])
        .unwrap()
}

pub(super) fn quad(z: f32, half: f32) -> TriMesh {
    TriMesh {
        positions: vec![
            Vec3::new(-half, -half, z),
            Vec3::new(half, -half, z),
            Vec3::new(half, half, z),
            Vec3::new(-half, half, z),
        ],
        normals: vec![Vec3::Z; 4],
        indices: vec![0, 1, 2, 0, 2, 3],
    }
}

/// The 12 triangles of the cube `[-h, h]³`.
fn cube(h: f32) -> TriMesh {
    let mut positions = Vec::new();
    for i in 0..8 {
        positions.push(Vec3::new(
            if i & 1 == 0 { -h } else { h },
            if i & 2 == 0 { -h } else { h },
            if i & 4 == 0 { -h } else { h },
        ));
    }
    let faces = [
        [0, 1, 3, 2],
        [4, 6, 7, 5],
        [0, 4, 5, 1],
        [2, 3, 7, 6],
        [0, 2, 6, 4],
        [1, 5, 7, 3],
    ];
    let indices = faces
        .iter()
        .flat_map(|f| [f[0], f[1], f[2], f[0], f[2], f[3]])
        .collect();
    TriMesh {
        normals: vec![Vec3::Y; 8],
        positions,
        indices,
    }
}

pub(super) fn tracer(
    scene: &Scene,
    hair: Option<HairAsset>,
    head: Option<TriMesh>,
    s: &TraceSettings,
) -> Tracer {
    Tracer::new(scene, &SceneGeometry { hair, head }, s).expect("tracer")
}

/// `n²` stratified points for AO.
fn ao_points(n: u32) -> impl Iterator<Item = (f32, f32)> {
    let g = lattice_generator(n * n);
    (0..n * n).map(move |i| lattice_point(i, n * n, g, 0.5, 0.5))
}

#[test]
fn transmittance_through_n_strands_is_one_minus_alpha_to_the_n() {
    for n in [0usize, 1, 2, 5, 12] {
        let pairs: Vec<(Vec3, Vec3)> = (0..n)
            .map(|k| {
                let z = 1.0 + k as f32;
                (Vec3::new(-1.0, 0.0, z), Vec3::new(1.0, 0.0, z))
            })
            .collect();
        let sc = scene(8, "[strands]\nalpha = 0.3\n");
        let hair = (n > 0).then(|| strands(&pairs, 0.1));
        let tr = tracer(&sc, hair, None, &TraceSettings::default());
        let none = Origin::Triangle(u32::MAX);
        let up = Ray::new(Vec3::new(0.2, 0.0, 0.0), Vec3::Z, 0.0, f32::INFINITY);
        let got = tr.transmittance(&up, none, None);
        let expected = 0.7f32.powi(n as i32);
        assert!((got - expected).abs() < 1e-6, "n {n}: {got} vs {expected}");
        // A ray beside the strands (radius 0.05) crosses none; a shorter one only the first two.
        let beside = Ray::new(Vec3::new(0.0, 0.06, 0.0), Vec3::Z, 0.0, f32::INFINITY);
        assert_eq!(tr.transmittance(&beside, none, None), 1.0);
        let short = Ray::new(Vec3::new(0.2, 0.0, 0.0), Vec3::Z, 0.0, 2.5);
        let first_two = 0.7f32.powi(n.min(2) as i32);
        assert!((tr.transmittance(&short, none, None) - first_two).abs() < 1e-6);
        if n > 0 {
            // Starting on strand 0 skips it.
            let own = Origin::Strand {
                strand: 0,
                vertex: 0,
            };
            let got = tr.transmittance(&up, own, None);
            assert!((got - 0.7f32.powi(n as i32 - 1)).abs() < 1e-6);
        }
    }
}

#[test]
fn transparency_scales_alpha_and_the_head_blocks() {
    let pairs = [(Vec3::new(-1.0, 0.0, 1.0), Vec3::new(1.0, 0.0, 1.0))];
    let hair = strands(&pairs, 0.1)
        .with_transparency(vec![0.5, 0.5])
        .unwrap();
    let sc = scene(8, "[strands]\nalpha = 0.8\n");
    let tr = tracer(
        &sc,
        Some(hair),
        Some(quad(2.0, 5.0)),
        &TraceSettings::default(),
    );
    let none = Origin::Triangle(u32::MAX);
    let up = Ray::new(Vec3::ZERO, Vec3::Z, 0.0, f32::INFINITY);
    assert_eq!(
        tr.transmittance(&up, none, None),
        0.0,
        "the quad at z = 2 is opaque"
    );
    let up = Ray::new(Vec3::ZERO, Vec3::Z, 0.0, 1.5);
    assert!(
        (tr.transmittance(&up, none, None) - 0.6).abs() < 1e-6,
        "alpha 0.8 · 0.5"
    );
}

#[test]
fn ao_is_one_on_an_open_plane_and_zero_in_a_closed_box() {
    let sc = scene(8, "");
    let inf = TraceSettings {
        ao_radius: f32::INFINITY,
        ..TraceSettings::default()
    };
    let tr = tracer(&sc, None, Some(quad(0.0, 1000.0)), &inf);
    let mut rays = 0;
    let ao = tr.ambient_occlusion(
        Vec3::new(0.0, 0.0, 1e-4),
        Vec3::Z,
        Origin::Triangle(0),
        &mut ao_points(32),
        None,
        &mut rays,
    );
    assert_eq!(ao, 1.0);
    assert_eq!(rays, 1024);
    let tr = tracer(&sc, None, Some(cube(1.0)), &inf);
    for n in [Vec3::Z, Vec3::X, Vec3::new(1.0, -2.0, 0.5).normalize()] {
        let ao = tr.ambient_occlusion(
            Vec3::new(0.1, -0.2, 0.3),
            n,
            Origin::Triangle(u32::MAX),
            &mut ao_points(16),
            None,
            &mut rays,
        );
        assert_eq!(ao, 0.0);
    }
}

#[test]
fn ao_under_a_ceiling_is_h_over_r_squared() {
    // A point on the floor, an opaque ceiling at height h, AO radius R > h: a direction at
    // angle θ from the normal reaches the ceiling within R when cos θ > h / R. For cosine-
    // weighted directions cos²θ is uniform, so the unoccluded fraction is (h / R)².
    let sc = scene(8, "");
    for (h, r) in [(1.0f32, 2.0f32), (1.0, 4.0), (3.0, 4.0)] {
        let s = TraceSettings {
            ao_radius: r,
            ..TraceSettings::default()
        };
        let tr = tracer(&sc, None, Some(quad(h, 1000.0)), &s);
        let mut rays = 0;
        let ao = tr.ambient_occlusion(
            Vec3::ZERO,
            Vec3::Z,
            Origin::Triangle(u32::MAX),
            &mut ao_points(64),
            None,
            &mut rays,
        );
        let expected = (h / r).powi(2);
        assert!(
            (ao - expected).abs() < 2e-3,
            "h {h} R {r}: {ao} vs {expected}"
        );
    }
}

/// Settings that make a strand's color its coverage: white base, ambient 1, no AO, no lights.
fn coverage_settings(spp: u32) -> TraceSettings {
    TraceSettings {
        spp,
        ambient: Some(1.0),
        ao_samples: 0,
        ..TraceSettings::default()
    }
}

#[test]
fn stochastic_transparency_converges_to_front_to_back_compositing() {
    // k thick strands stacked towards the camera, each covering the central pixel: it shows
    // 1 - (1 - α)^k of the (white) hair over the black background.
    for (k, alpha) in [(1usize, 0.6f32), (3, 0.3), (6, 0.5)] {
        let pairs: Vec<(Vec3, Vec3)> = (0..k)
            .map(|i| {
                let z = -(i as f32) * 0.5;
                (Vec3::new(-3.0, 0.0, z), Vec3::new(3.0, 0.0, z))
            })
            .collect();
        let sc = scene(5, &format!("[strands]\nalpha = {alpha}\n"));
        let tr = tracer(
            &sc,
            Some(strands(&pairs, 2.0)),
            None,
            &coverage_settings(4096),
        );
        let out = tr.render(&|_| {});
        let got = out.image.get(2, 2).x;
        let expected = 1.0 - (1.0 - alpha).powi(k as i32);
        assert!((got - expected).abs() < 0.03, "k {k}: {got} vs {expected}");
        assert_eq!(out.stats.samples, 25 * 4096);
        assert_eq!(
            out.stats.rays,
            25 * 4096,
            "one camera ray per sample, nothing else"
        );
    }
}

#[test]
fn screen_width_puts_down_width_px_of_ink_per_column() {
    // A strand along x at depth 10: summed down a column, its coverage is its width in pixels.
    let pairs = [(Vec3::new(-50.0, 0.013, 0.0), Vec3::new(50.0, 0.013, 0.0))];
    let sc = scene(48, "[strands]\nalpha = 1.0\nwidth_px = 3.0\n");
    let hair = strands(&pairs, 0.0).without_attributes();
    for (width_px, expected) in [(None, 1.5f32), (Some(2.0), 2.0)] {
        let s = TraceSettings {
            width_px,
            ..coverage_settings(256)
        };
        let tr = tracer(&sc, Some(hair.clone()), None, &s);
        assert_eq!(
            tr.strand_width(),
            StrandWidth::Screen,
            "no thickness: screen width"
        );
        let img = tr.render(&|_| {}).image;
        for x in [5, 24, 40] {
            let ink: f32 = (0..48).map(|y| img.get(x, y).x).sum();
            assert!(
                (ink - expected).abs() < 0.03 * expected,
                "x {x}: {ink} vs {expected}"
            );
        }
    }
}

#[test]
fn thickness_width_is_the_physical_diameter() {
    // Thickness 0.05 at depth 10 with a 30° field of view on 48 pixels:
    // 48 / (2 tan 15°) / 10 pixels per unit.
    let pairs = [(Vec3::new(-50.0, 0.0, 0.0), Vec3::new(50.0, 0.0, 0.0))];
    let sc = scene(48, "[strands]\nalpha = 1.0\n");
    let tr = tracer(
        &sc,
        Some(strands(&pairs, 0.05)),
        None,
        &coverage_settings(1024),
    );
    assert_eq!(tr.strand_width(), StrandWidth::Thickness);
    let img = tr.render(&|_| {}).image;
    let expected = 0.05 * 48.0 / (2.0 * 15f32.to_radians().tan()) / 10.0;
    let ink: f32 = (0..48).map(|y| img.get(20, y).x).sum();
    assert!(
        (ink - expected).abs() < 0.03 * expected,
        "{ink} vs {expected}"
    );
}

#[test]
fn shading_matches_the_tress_shading_twins() {
    // One fat strand along x under one light, no occluders, no ambient: the central pixel is
    // the twin's value for t = x, v = +z.
    let pairs = [(Vec3::new(-5.0, 0.0, 0.0), Vec3::new(5.0, 0.0, 0.0))];
    let lights =
        "[[light]]\ndirection = [0.0, 0.6, 0.8]\ncolor = [1.0, 0.5, 0.25]\nintensity = 2.0\n";
    let s = TraceSettings {
        spp: 16,
        ambient: Some(0.0),
        ..TraceSettings::default()
    };
    let l = Vec3::new(0.0, 0.6, 0.8);
    let radiance = Vec3::new(2.0, 1.0, 0.5);
    let v = Vec3::Z;
    for shading in ["kajiya-kay", "scheuermann"] {
        // 45 pixels over 30°: the central pixel's rays stay within 0.33° of +z, where the
        // exponent-80 highlight changes by under 0.1%.
        let sc = scene(
            45,
            &format!("[strands]\nalpha = 1.0\nshading = \"{shading}\"\n{lights}"),
        );
        let material = sc.hair[0].material.clone();
        let tr = tracer(&sc, Some(strands(&pairs, 2.0)), None, &s);
        let got = tr.render(&|_| {}).image.get(22, 22);
        let expected = if shading == "kajiya-kay" {
            kajiya_kay(&material.kajiya_kay(), Vec3::X, l, v) * radiance
        } else {
            let sample = HairSample {
                tangent: Vec3::X,
                shift_tex: strand_random(0, 0),
                normal: Vec3::Z,
                spec_mask: strand_random(0, 1),
                base_color: material.base_color,
                amb_occ: 1.0,
            };
            hair_lighting(&material.hair_lighting(), &sample, l, radiance, v)
        };
        assert!(
            (got - expected).abs().max_element() < 2e-3 * (1.0 + expected.max_element()),
            "{shading}: {got} vs {expected}"
        );
    }
}

#[test]
fn strands_shadow_the_head_by_one_minus_alpha() {
    // The camera looks down -z at a floor quad (z = -1). A strand along x at z = 2 (radius
    // 0.6) lies under a light in direction (0, 0.5, 1): floor points with |y + 1.5| < 0.6 ·
    // sqrt(1.25) = 0.671 see the light through it. At depth 11 the floor has
    // 16 / (2 tan 15°) / 11 = 2.71 pixels per unit, so that band covers rows 10.3 to 13.9; the
    // strand itself (depth 8, 3.73 px per unit) hides rows 5.8 to 10.2.
    let pairs = [(Vec3::new(-20.0, 0.0, 2.0), Vec3::new(20.0, 0.0, 2.0))];
    let sc = scene(
        16,
        "[strands]\nalpha = 0.4\n[[light]]\ndirection = [0.0, 0.5, 1.0]\n",
    );
    let s = TraceSettings {
        spp: 16,
        aov: Aov::Shadow,
        ..TraceSettings::default()
    };
    let tr = tracer(&sc, Some(strands(&pairs, 1.2)), Some(quad(-1.0, 50.0)), &s);
    let img = tr.render(&|_| {}).image;
    for row in [11, 12] {
        let shadow = img.get(3, row).x;
        assert!(
            (shadow - 0.6).abs() < 1e-5,
            "row {row} in the shadow: {shadow}"
        );
    }
    assert_eq!(img.get(3, 2).x, 1.0, "lit floor");
    assert_eq!(img.get(3, 15).x, 1.0, "lit floor");
}

#[test]
fn renders_are_deterministic_for_a_seed_on_any_thread_count() {
    let pairs: Vec<(Vec3, Vec3)> = (0..20)
        .map(|i| {
            let a = i as f32 * 0.3;
            (
                Vec3::new(-2.0, a.sin(), a.cos() - 1.0),
                Vec3::new(2.0, a.cos(), a.sin()),
            )
        })
        .collect();
    let sc = scene(12, "[[light]]\ndirection = [0.3, 1.0, 0.5]\n");
    let s = TraceSettings {
        spp: 8,
        ..TraceSettings::default()
    };
    let tr = tracer(&sc, Some(strands(&pairs, 0.08)), Some(quad(-2.0, 5.0)), &s);
    let one = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap();
    let a = one.install(|| tr.render(&|_| {}).image);
    let b = tr.render(&|_| {}).image;
    assert_eq!(a, b);
    let other = TraceSettings { seed: 1, ..s };
    let tr = tracer(
        &sc,
        Some(strands(&pairs, 0.08)),
        Some(quad(-2.0, 5.0)),
        &other,
    );
    assert_ne!(tr.render(&|_| {}).image, a);
}

#[test]
fn strand_settings_from_the_scene_are_checked() {
    let bad = scene(4, "[strands]\nalpha = 1.5\n");
    let e = Tracer::new(
        &bad,
        &SceneGeometry {
            hair: None,
            head: None,
        },
        &TraceSettings::default(),
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("strands.alpha"), "{e}");
    let bad = scene(4, "[strands]\nshading = \"phong\"\n");
    assert!(
        Tracer::new(
            &bad,
            &SceneGeometry {
                hair: None,
                head: None
            },
            &TraceSettings::default()
        )
        .is_err()
    );
}

#[test]
fn a_ray_through_a_joint_or_across_pieces_crosses_the_strand_once() {
    // A straight strand of three segments along x (joints at x = -1 and 1), long enough to be
    // referenced in pieces: rays through the joints, and anywhere along it, see one crossing.
    let positions = vec![
        Vec3::new(-3.0, 0.0, 1.0),
        Vec3::new(-1.0, 0.0, 1.0),
        Vec3::new(1.0, 0.0, 1.0),
        Vec3::new(3.0, 0.0, 1.0),
    ];
    let hair = HairAsset::from_counts(positions, &[4])
        .unwrap()
        .with_thickness(vec![0.4; 4])
        .unwrap();
    let sc = scene(8, "[strands]\nalpha = 0.5\n");
    let tr = tracer(&sc, Some(hair), None, &TraceSettings::default());
    assert!(tr.reference_count() > 3, "segments are split into pieces");
    let none = Origin::Triangle(u32::MAX);
    for k in 0..=60 {
        let x = -2.9 + 5.8 * k as f32 / 60.0;
        for dir in [
            Vec3::Z,
            Vec3::new(0.6, 0.0, 0.8),
            Vec3::new(-0.3, 0.1, 0.9).normalize(),
        ] {
            let origin = Vec3::new(x, 0.0, 1.0) - dir * 3.0;
            let t = tr.transmittance(&Ray::new(origin, dir, 0.0, f32::INFINITY), none, None);
            assert!((t - 0.5).abs() < 1e-6, "x {x}, dir {dir}: {t}");
        }
    }
}

#[test]
fn russian_roulette_keeps_the_expected_transmittance() {
    // Twelve strands of alpha 0.3: the exact product is 0.7^12 = 0.0138; roulette (which
    // starts below 0.25) returns 0 or at least 0.25 times what is left, averaging to it.
    let pairs: Vec<(Vec3, Vec3)> = (0..12)
        .map(|k| {
            let z = 1.0 + k as f32;
            (Vec3::new(-1.0, 0.0, z), Vec3::new(1.0, 0.0, z))
        })
        .collect();
    let sc = scene(8, "[strands]\nalpha = 0.3\n");
    let tr = tracer(
        &sc,
        Some(strands(&pairs, 0.1)),
        None,
        &TraceSettings::default(),
    );
    let ray = Ray::new(Vec3::ZERO, Vec3::Z, 0.0, f32::INFINITY);
    let none = Origin::Triangle(u32::MAX);
    let n = 40_000;
    let mut sum = 0.0f64;
    let mut zeros = 0;
    for key in 0..n {
        let t = tr.transmittance(&ray, none, Some(crate::sampling::hash2(99, key)));
        sum += f64::from(t);
        zeros += usize::from(t == 0.0);
    }
    let mean = sum / n as f64;
    let exact = 0.7f64.powi(12);
    assert!((mean - exact).abs() < 0.0015, "{mean} vs {exact}");
    assert!(zeros > n as usize / 2, "most rays stop early");
}

/// The test scene's camera as matrices (glam's `look_at_rh` and `perspective_rh`, as the GPU).
fn scene_matrices(size: u32) -> ViewCamera {
    ViewCamera {
        view_from_world: glam::Mat4::look_at_rh(Vec3::new(0.0, 0.0, 10.0), Vec3::ZERO, Vec3::Y),
        clip_from_view: glam::Mat4::perspective_rh(30f32.to_radians(), 1.0, 0.1, 100.0),
        width: size,
        height: size,
    }
}

#[test]
fn matrix_camera_rays_match_the_look_at_camera_and_follow_an_off_centre_projection() {
    let scene = scene(32, "");
    let look_at = PinholeCamera::new(&scene);
    let m = scene_matrices(32);
    let matrices = PinholeCamera::from_matrices(&m).unwrap();
    // The same rays: same direction, origins on the same line (the near plane's point).
    for (x, y) in [(0.5, 0.5), (16.0, 16.0), (3.25, 29.5), (31.5, 7.0)] {
        let (a, b) = (look_at.ray(x, y), matrices.ray(x, y));
        assert!(a.dir.dot(b.dir) > 1.0 - 1e-6, "({x}, {y})");
        let off = b.origin - a.origin;
        assert!((off - off.dot(a.dir) * a.dir).length() < 1e-4, "({x}, {y})");
    }
    assert!((look_at.world_per_pixel(10.0) - matrices.world_per_pixel(10.0)).abs() < 1e-6);
    // Moving the principal point 4 pixels right (NDC x + 8/32) moves every ray with it.
    let shift = glam::Mat4::from_translation(Vec3::new(8.0 / 32.0, 0.0, 0.0));
    let shifted = PinholeCamera::from_matrices(&ViewCamera {
        clip_from_view: shift * m.clip_from_view,
        ..m
    })
    .unwrap();
    for (x, y) in [(0.5, 0.5), (16.0, 16.0), (20.0, 3.0)] {
        let (a, b) = (matrices.ray(x, y), shifted.ray(x + 4.0, y));
        assert!(a.dir.dot(b.dir) > 1.0 - 1e-6, "({x}, {y})");
    }
    // Orthographic: parallel rays, a constant pixel size.
    let ortho = PinholeCamera::from_matrices(&ViewCamera {
        clip_from_view: glam::Mat4::orthographic_rh(-2.0, 2.0, -2.0, 2.0, 0.1, 100.0),
        ..m
    })
    .unwrap();
    assert!(ortho.ray(0.5, 0.5).dir.dot(ortho.ray(31.5, 20.0).dir) > 1.0 - 1e-6);
    assert!((ortho.world_per_pixel(3.0) - 4.0 / 32.0).abs() < 1e-6);
    let singular = ViewCamera {
        clip_from_view: glam::Mat4::ZERO,
        ..m
    };
    assert!(PinholeCamera::from_matrices(&singular).is_err());
}

#[test]
fn a_matrix_camera_renders_what_the_scene_camera_renders() {
    let scene = scene(24, "");
    let hair = strands(
        &[(Vec3::new(-2.0, -1.0, 0.0), Vec3::new(2.0, 1.5, 0.0))],
        0.2,
    );
    let s = TraceSettings {
        spp: 4,
        ..Default::default()
    };
    let geometry = SceneGeometry {
        hair: Some(hair),
        head: None,
    };
    let a = Tracer::new(&scene, &geometry, &s).unwrap().render(&|_| {});
    let b = Tracer::with_camera(&scene, &geometry, &s, &scene_matrices(24))
        .unwrap()
        .render(&|_| {});
    let differ = a
        .image
        .pixels
        .iter()
        .zip(&b.image.pixels)
        .filter(|(p, q)| (**p - **q).abs().max_element() > 1e-3)
        .count();
    assert!(a.image.pixels.iter().any(|p| p.max_element() > 0.0));
    assert!(differ <= 2, "{differ} pixels differ");
}

/// The converged reference stops at the first sample count whose seed pair is within the
/// threshold: every earlier round was above it, and the floor it reports is the pair's own.
#[test]
fn converged_reference_stops_at_its_threshold() {
    use crate::converge::{ConvergeSettings, render_converged};
    let pairs: Vec<(Vec3, Vec3)> = (0..40)
        .map(|i| {
            let a = i as f32 * 0.37;
            (
                Vec3::new(-2.0, a.sin(), a.cos() - 1.0),
                Vec3::new(2.0, a.cos() * 1.5, a.sin()),
            )
        })
        .collect();
    let sc = scene(24, "[[light]]\ndirection = [0.3, 1.0, 0.5]\n");
    let s = TraceSettings {
        spp: 1,
        ..TraceSettings::default()
    };
    let make = || tracer(&sc, Some(strands(&pairs, 0.05)), Some(quad(-2.0, 5.0)), &s);
    // The noisy first round's floor sets a threshold the doubling must work to reach.
    let mut probe = make();
    let first = render_converged(
        &mut probe,
        None,
        &ConvergeSettings {
            threshold: 1.0,
            scale: 1,
            max_spp: 1,
        },
        &|_, _| {},
    )
    .unwrap();
    assert_eq!(first.spp, 1);
    let threshold = first.floor * 0.5;
    let mut tr = make();
    let c = render_converged(
        &mut tr,
        None,
        &ConvergeSettings {
            threshold,
            scale: 1,
            max_spp: 256,
        },
        &|_, _| {},
    )
    .unwrap();
    assert!(c.converged, "{:?}", c.history);
    assert!(c.spp > 1 && c.floor <= threshold, "{:?}", c.history);
    let (last, earlier) = c.history.split_last().unwrap();
    assert_eq!(*last, (c.spp, c.floor));
    for (i, &(spp, floor)) in earlier.iter().enumerate() {
        assert_eq!(spp, 1 << i, "the count doubles");
        assert!(floor > threshold, "stopped late: {:?}", c.history);
    }
    // The reported floor is the pair's own distance, measured independently.
    let again = crate::matched::compare(&c.image, &c.second, None, 1).unwrap();
    assert!((again.flip - c.floor).abs() < 1e-12);
    // An unreachable threshold stops at the cap and says so.
    let capped = render_converged(
        &mut make(),
        None,
        &ConvergeSettings {
            threshold: 0.0,
            scale: 1,
            max_spp: 4,
        },
        &|_, _| {},
    )
    .unwrap();
    assert!(!capped.converged);
    assert_eq!(capped.spp, 4);
    // The first round's image equals a plain render at the first seed (nothing else mixed in).
    let plain = make().render(&|_| {}).image;
    assert_eq!(first.image, plain);
}
