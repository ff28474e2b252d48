//! Tests of the per-vertex ambient occlusion bake.

use std::f32::consts::TAU;

use glam::{Vec2, Vec3};
use tress_hair::generate::{Head, TriMesh};
use tress_hair::patches::{AoParams, AoSides, PatchMesh, PatchParams, bake_ao, generate_patches};

/// A small square patch of side `size` centred at `centre`, facing `normal` (+Z rotated).
fn square(centre: Vec3, size: f32) -> (Vec<Vec3>, Vec<u32>) {
    let h = size / 2.0;
    let p = [(-h, -h), (h, -h), (h, h), (-h, h)]
        .map(|(x, y)| centre + Vec3::new(x, y, 0.0))
        .to_vec();
    (p, vec![0, 1, 2, 0, 2, 3])
}

fn patch_mesh(parts: &[(Vec<Vec3>, Vec<u32>)]) -> PatchMesh {
    let (mut positions, mut indices) = (Vec::new(), Vec::new());
    for (p, i) in parts {
        let base = positions.len() as u32;
        positions.extend_from_slice(p);
        indices.extend(i.iter().map(|k| k + base));
    }
    let n = positions.len();
    PatchMesh::new(
        positions,
        vec![Vec3::Z; n],
        vec![Vec3::Y; n],
        vec![Vec2::ZERO; n],
        indices,
    )
    .unwrap()
}

/// A closed axis-aligned box of half-size `h` around `c` as a triangle mesh.
fn closed_box(c: Vec3, h: f32) -> TriMesh {
    let corners: Vec<Vec3> = (0..8)
        .map(|i| {
            c + Vec3::new(
                if i & 1 == 0 { -h } else { h },
                if i & 2 == 0 { -h } else { h },
                if i & 4 == 0 { -h } else { h },
            )
        })
        .collect();
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
        positions: corners,
        indices,
    }
}

#[test]
fn enclosed_vertices_are_darker_than_open_ones() {
    // One patch inside a closed box, one far away in the open.
    let inside = square(Vec3::ZERO, 0.2);
    let open = square(Vec3::new(50.0, 0.0, 0.0), 0.2);
    let mut mesh = patch_mesh(&[inside, open]);
    let params = AoParams {
        rays: 128,
        max_distance: 10.0,
        ..AoParams::default()
    };
    bake_ao(&mut mesh, Some(&closed_box(Vec3::ZERO, 1.0)), &params).unwrap();
    // Every ray from inside a closed box within reach meets a wall; nothing is near the other
    // patch but itself, which rays leave from.
    assert!(mesh.ao()[..4].iter().all(|&a| a == 0.0), "{:?}", mesh.ao());
    assert!(mesh.ao()[4..].iter().all(|&a| a == 1.0), "{:?}", mesh.ao());

    // A box farther than max_distance does not count.
    let mut far = patch_mesh(&[square(Vec3::ZERO, 0.2)]);
    bake_ao(
        &mut far,
        Some(&closed_box(Vec3::ZERO, 20.0)),
        &AoParams {
            max_distance: 10.0,
            ..params
        },
    )
    .unwrap();
    assert!(far.ao().iter().all(|&a| a == 1.0));
}

#[test]
fn a_disk_overhead_occludes_its_form_factor() {
    // A vertex under a disk of radius R at height h: the cosine-weighted fraction of the
    // hemisphere the disk covers is its form factor R² / (R² + h²), so AO = h² / (R² + h²).
    let (r, h) = (1.0f32, 1.0f32);
    let segments = 256;
    let centre = Vec3::new(0.0, 0.0, h);
    let mut disk = vec![centre];
    let mut indices = Vec::new();
    for i in 0..segments {
        let a = TAU * i as f32 / segments as f32;
        disk.push(centre + Vec3::new(r * a.cos(), r * a.sin(), 0.0));
        indices.extend([0, 1 + i, 1 + (i + 1) % segments]);
    }
    let occluder = TriMesh {
        normals: vec![Vec3::Z; disk.len()],
        positions: disk,
        indices,
    };
    let mut mesh = patch_mesh(&[square(Vec3::ZERO, 1e-3)]);
    let params = AoParams {
        rays: 20_000,
        max_distance: 100.0,
        sides: AoSides::Front,
        seed: 3,
        ..AoParams::default()
    };
    bake_ao(&mut mesh, Some(&occluder), &params).unwrap();
    let expected = h * h / (r * r + h * h);
    for &a in mesh.ao() {
        // Binomial standard deviation sqrt(0.25 / 20000) = 0.0035; allow about 4σ.
        assert!((a - expected).abs() < 0.015, "AO {a}, expected {expected}");
    }

    // Facing away from the disk (front side only), nothing blocks; the two-sided modes see
    // the open side as well.
    let n = mesh.vertex_count();
    let (p, i) = square(Vec3::ZERO, 1e-3);
    let mut down = PatchMesh::new(
        p,
        vec![Vec3::NEG_Z; n],
        vec![Vec3::Y; n],
        vec![Vec2::ZERO; n],
        i,
    )
    .unwrap();
    bake_ao(&mut down, Some(&occluder), &params).unwrap();
    assert!(down.ao().iter().all(|&a| a == 1.0));
    let mut mean = mesh.clone();
    bake_ao(
        &mut mean,
        Some(&occluder),
        &AoParams {
            sides: AoSides::Mean,
            ..params
        },
    )
    .unwrap();
    for &a in mean.ao() {
        assert!((a - (1.0 + expected) / 2.0).abs() < 0.015, "{a}");
    }
    let mut max = mesh.clone();
    bake_ao(
        &mut max,
        Some(&occluder),
        &AoParams {
            sides: AoSides::Max,
            ..params
        },
    )
    .unwrap();
    assert!(max.ao().iter().all(|&a| a == 1.0));
}

#[test]
fn generated_head_ao_is_in_range_darker_inside_and_deterministic() {
    let p = PatchParams {
        patches_per_layer: 40,
        segments: 6,
        layers: 3,
        ..PatchParams::default()
    };
    let mesh = generate_patches(&p).unwrap();
    let head = p.head.mesh(24);
    let params = AoParams {
        rays: 32,
        ..AoParams::default()
    };
    let mut a = mesh.clone();
    bake_ao(&mut a, Some(&head), &params).unwrap();
    assert!(a.ao().iter().all(|x| (0.0..=1.0).contains(x)));
    let mut b = mesh.clone();
    bake_ao(&mut b, Some(&head), &params).unwrap();
    assert_eq!(a.ao(), b.ao(), "same seed, same AO");
    let mut c = mesh.clone();
    bake_ao(&mut c, Some(&head), &AoParams { seed: 1, ..params }).unwrap();
    assert_ne!(a.ao(), c.ao());

    // Inner layer (closest to the scalp) against outer layer: mean AO of their root rows.
    let rows = p.segments as usize + 1;
    let radius = Head::default().radii.min_element();
    let (mut inner, mut outer) = (Vec::new(), Vec::new());
    for (k, strip) in a.positions().chunks_exact(2 * rows).enumerate() {
        let level = p.head.level((strip[0] + strip[1]) * 0.5) - 1.0;
        let layer = (level * radius / p.layer_spacing - 1.0).round() as u32;
        let ao = &a.ao()[k * 2 * rows..k * 2 * rows + 4];
        let mean = ao.iter().sum::<f32>() / 4.0;
        if layer == 0 {
            inner.push(mean);
        } else if layer == p.layers - 1 {
            outer.push(mean);
        }
    }
    let mean = |v: &[f32]| v.iter().sum::<f32>() / v.len() as f32;
    assert!(
        mean(&inner) + 0.1 < mean(&outer),
        "inner {} outer {}",
        mean(&inner),
        mean(&outer)
    );
}

#[test]
fn bad_parameters_and_heads_are_errors() {
    let mut mesh = patch_mesh(&[square(Vec3::ZERO, 1.0)]);
    let before = mesh.clone();
    for bad in [
        AoParams {
            rays: 0,
            ..AoParams::default()
        },
        AoParams {
            max_distance: 0.0,
            ..AoParams::default()
        },
        AoParams {
            max_distance: f32::INFINITY,
            ..AoParams::default()
        },
        AoParams {
            patch_opacity: 1.5,
            ..AoParams::default()
        },
    ] {
        assert!(bake_ao(&mut mesh, None, &bad).is_err());
    }
    let mut head = closed_box(Vec3::ZERO, 1.0);
    head.indices.push(99);
    head.indices.extend([0, 1]);
    assert!(bake_ao(&mut mesh, Some(&head), &AoParams::default()).is_err());
    head.indices.truncate(head.indices.len() - 3);
    head.indices[0] = 8;
    assert!(bake_ao(&mut mesh, Some(&head), &AoParams::default()).is_err());
    head.indices[0] = 0;
    head.positions[0].x = f32::NAN;
    assert!(bake_ao(&mut mesh, Some(&head), &AoParams::default()).is_err());
    assert_eq!(mesh, before, "a failed bake leaves the mesh alone");
}
