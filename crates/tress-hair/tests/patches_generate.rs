//! Tests of the patch sources that build geometry: the layered generator and strand-to-card
//! conversion, and of the inside-to-outside sort.

use glam::Vec3;
use tress_hair::HairAsset;
use tress_hair::generate::{Head, Style, StyleParams, generate};
use tress_hair::patches::{
    CardParams, PatchMesh, PatchParams, component_distances, generate_patches, sorted_indices,
};

fn small() -> PatchParams {
    PatchParams {
        patches_per_layer: 40,
        segments: 6,
        ..PatchParams::default()
    }
}

/// The vertices of each component, as index lists.
fn component_vertices(mesh: &PatchMesh) -> Vec<Vec<u32>> {
    let mut out = vec![Vec::new(); mesh.component_count()];
    for (t, &c) in mesh.indices().chunks_exact(3).zip(mesh.components()) {
        out[c as usize].extend_from_slice(t);
    }
    for v in &mut out {
        v.sort_unstable();
        v.dedup();
    }
    out
}

/// Checks every mesh must pass: unit normals perpendicular to unit tangents, UVs in [0, 1].
fn check_frames(mesh: &PatchMesh) {
    for ((n, t), uv) in mesh.normals().iter().zip(mesh.tangents()).zip(mesh.uvs()) {
        assert!((n.length() - 1.0).abs() < 1e-4);
        assert!((t.length() - 1.0).abs() < 1e-4);
        assert!(
            n.dot(*t).abs() < 1e-3,
            "normal {n} not perpendicular to tangent {t}"
        );
        assert!((0.0..=1.0).contains(&uv.x) && (0.0..=1.0).contains(&uv.y));
    }
}

#[test]
fn generated_layers_are_strips_outside_the_head() {
    let p = small();
    let mesh = generate_patches(&p).unwrap();
    let rows = p.segments as usize + 1;
    // Every patch is a strip of 2 vertices per row and 2 triangles per segment.
    assert_eq!(mesh.vertex_count(), mesh.component_count() * 2 * rows);
    assert_eq!(
        mesh.triangle_count(),
        mesh.component_count() * 2 * p.segments as usize
    );
    // About `patches_per_layer` per layer (the lattice is cut by the hairline).
    let per_layer = mesh.component_count() as f32 / p.layers as f32;
    assert!(
        (per_layer - 40.0).abs() <= 6.0,
        "{per_layer} patches per layer"
    );
    check_frames(&mesh);
    let head = p.head;
    for (&x, &n) in mesh.positions().iter().zip(mesh.normals()) {
        // Only the strips' corners may dip a little under the ellipsoid where the head curves
        // away below them; centre lines lie on or above their layer's shell.
        assert!(head.level(x) > 0.97, "vertex {x} inside the head");
        assert!(x.is_finite() && n.is_finite());
    }
    for strip in mesh.positions().chunks_exact(2 * rows) {
        let root = (strip[0] + strip[1]) * 0.5;
        let level = head.level(root);
        assert!(
            (1.0..1.0 + 1.5 / 8.0).contains(&level),
            "root at level {level}"
        );
    }
}

#[test]
fn normals_face_out_and_triangles_wind_with_them() {
    let mesh = generate_patches(&small()).unwrap();
    let c = PatchParams::default().head.center;
    let mut outward = 0;
    for t in 0..mesh.triangle_count() {
        let [a, b, cc] = mesh.triangle(t);
        let face = (b - a).cross(cc - a);
        let i = mesh.indices()[3 * t] as usize;
        assert!(
            face.dot(mesh.normals()[i]) > 0.0,
            "triangle {t} winds against its normal"
        );
        if mesh.normals()[i].dot(a - c) > 0.0 {
            outward += 1;
        }
    }
    assert!(
        outward as f32 > 0.95 * mesh.triangle_count() as f32,
        "{outward}"
    );
}

#[test]
fn inner_layers_are_shorter_and_closer() {
    let p = PatchParams {
        layers: 3,
        ..small()
    };
    let mesh = generate_patches(&p).unwrap();
    let rows = p.segments as usize + 1;
    let per_layer_len = |layer: usize| -> (f32, f32) {
        // Patches are numbered layer by layer; recover the layer from the root level.
        let mut lengths = Vec::new();
        let mut levels = Vec::new();
        for strip in mesh.positions().chunks_exact(2 * rows) {
            let centre: Vec<Vec3> = strip.chunks_exact(2).map(|q| (q[0] + q[1]) * 0.5).collect();
            let root_height = p.head.level(centre[0]) - 1.0;
            let k = (root_height * p.head.radii.min_element() / p.layer_spacing - 1.0).round();
            if k as usize == layer {
                lengths.push(centre.windows(2).map(|w| w[0].distance(w[1])).sum::<f32>());
                levels.push(p.head.level(centre[0]));
            }
        }
        assert!(!lengths.is_empty(), "layer {layer} is empty");
        let n = lengths.len() as f32;
        (
            lengths.iter().sum::<f32>() / n,
            levels.iter().sum::<f32>() / n,
        )
    };
    let (l0, h0) = per_layer_len(0);
    let (l1, h1) = per_layer_len(1);
    let (l2, h2) = per_layer_len(2);
    assert!(l0 < l1 && l1 < l2, "lengths {l0} {l1} {l2}");
    assert!(h0 < h1 && h1 < h2, "levels {h0} {h1} {h2}");
    // Layer lengths follow lerp(inner_length, 1, k / 2) × length (jitter averages out).
    assert!((l2 / p.length - 1.0).abs() < 0.1, "{l2}");
    assert!((l0 / l2 - p.inner_length).abs() < 0.1, "{}", l0 / l2);
}

#[test]
fn generation_is_deterministic_and_validated() {
    let a = generate_patches(&small()).unwrap();
    assert_eq!(a, generate_patches(&small()).unwrap());
    let b = generate_patches(&PatchParams { seed: 9, ..small() }).unwrap();
    assert_ne!(a.positions(), b.positions());
    for bad in [
        PatchParams {
            layers: 0,
            ..small()
        },
        PatchParams {
            segments: 0,
            ..small()
        },
        PatchParams {
            length: f32::NAN,
            ..small()
        },
        PatchParams {
            width: 0.0,
            ..small()
        },
        PatchParams {
            inner_length: 1.5,
            ..small()
        },
        PatchParams {
            patches_per_layer: u32::MAX,
            layers: u32::MAX,
            ..small()
        },
        PatchParams {
            head: Head {
                radii: Vec3::new(1.0, -1.0, 1.0),
                ..Head::default()
            },
            ..small()
        },
    ] {
        assert!(generate_patches(&bad).is_err(), "{bad:?}");
    }
}

#[test]
fn sorted_index_buffer_goes_inside_out_by_whole_components() {
    let mesh = generate_patches(&small()).unwrap();
    let centre = PatchParams::default().head.center;
    let sorted = sorted_indices(&mesh, centre);
    assert_eq!(sorted.len(), mesh.indices().len());

    // Every triangle exactly once.
    let mut original: Vec<[u32; 3]> = mesh
        .indices()
        .chunks_exact(3)
        .map(|t| [t[0], t[1], t[2]])
        .collect();
    let mut reordered: Vec<[u32; 3]> = sorted.chunks_exact(3).map(|t| [t[0], t[1], t[2]]).collect();
    original.sort_unstable();
    reordered.sort_unstable();
    assert_eq!(original, reordered);

    // Independent distances: the mean distance of each component's distinct vertices.
    let vertices = component_vertices(&mesh);
    let distance: Vec<f32> = vertices
        .iter()
        .map(|v| {
            v.iter()
                .map(|&i| mesh.positions()[i as usize].distance(centre))
                .sum::<f32>()
                / v.len() as f32
        })
        .collect();
    for (d, e) in distance.iter().zip(component_distances(&mesh, centre)) {
        assert!((d - e).abs() < 1e-3 * d.max(1.0), "{d} vs {e}");
    }
    let component_of_vertex = {
        let mut c = vec![u32::MAX; mesh.vertex_count()];
        for (k, v) in vertices.iter().enumerate() {
            for &i in v {
                c[i as usize] = k as u32;
            }
        }
        c
    };
    let order: Vec<u32> = sorted
        .chunks_exact(3)
        .map(|t| component_of_vertex[t[0] as usize])
        .collect();
    // Distances never decrease along the buffer (up to float rounding between the two sums).
    for w in order.windows(2) {
        assert!(
            distance[w[1] as usize] >= distance[w[0] as usize] - 1e-4,
            "component {} ({}) after {} ({})",
            w[1],
            distance[w[1] as usize],
            w[0],
            distance[w[0] as usize]
        );
    }
    // Components stay together: each appears in one contiguous run.
    let mut runs: Vec<u32> = order.clone();
    runs.dedup();
    assert_eq!(runs.len(), mesh.component_count());
    // The layered model's inner layer comes first on the whole.
    let first = distance[order[0] as usize];
    let last = distance[*order.last().unwrap() as usize];
    assert!(last > first + 2.0, "{first} .. {last}");
}

#[test]
fn strands_become_ribbons_that_follow_and_span_their_group() {
    // Two bundles of parallel vertical strands, each spread 2 units along x, 10 units apart.
    let mut positions = Vec::new();
    let mut counts = Vec::new();
    for bundle in [0.0f32, 10.0] {
        for i in 0..21 {
            let x = bundle + (i as f32 / 20.0 - 0.5) * 2.0;
            for k in 0..5 {
                positions.push(Vec3::new(x, -(k as f32) * 2.5, 0.0));
            }
            counts.push(5);
        }
    }
    let asset = HairAsset::from_counts(positions, &counts).unwrap();
    let params = CardParams {
        cards: 2,
        segments: 4,
        width_scale: 1.0,
        ..CardParams::default()
    };
    let mesh = PatchMesh::from_strands(&asset, &params).unwrap();
    assert_eq!(mesh.component_count(), 2);
    assert_eq!(mesh.vertex_count(), 2 * 2 * 5);
    check_frames(&mesh);
    // Uniform spread over [-1, 1]: σ² = (1/21) Σ x_i² = 0.11 · 21 / 21 ... computed directly.
    let sigma = ((0..21)
        .map(|i| ((i as f32 / 20.0 - 0.5) * 2.0).powi(2))
        .sum::<f32>()
        / 21.0)
        .sqrt();
    for ribbon in mesh.positions().chunks_exact(10) {
        for (r, pair) in ribbon.chunks_exact(2).enumerate() {
            let centre = (pair[0] + pair[1]) * 0.5;
            assert!(
                (centre.y + r as f32 * 2.5).abs() < 1e-4,
                "follows the mean strand"
            );
            assert!(
                (centre.x.abs() < 1e-4) || ((centre.x - 10.0).abs() < 1e-4),
                "{centre}"
            );
            let across = pair[1] - pair[0];
            // Oriented across the group (along x) and 2σ wide.
            assert!(across.normalize().x.abs() > 0.999, "{across}");
            assert!((across.length() - 2.0 * sigma).abs() < 1e-3, "{across}");
        }
    }
    for t in mesh.tangents() {
        assert!(t.dot(Vec3::NEG_Y) > 0.999, "tangent {t} runs root to tip");
    }
    // The OBJ writer serves `tress cards`: it parses back.
    let again = PatchMesh::from_obj(mesh.to_obj().as_bytes()).unwrap();
    assert_eq!(again.positions(), mesh.positions());
}

#[test]
fn cards_from_a_generated_style_cover_the_head() {
    let style = StyleParams {
        strands: 2000,
        vertices: 12,
        ..Style::Straight.default_params()
    };
    let asset = generate(Style::Straight, &style).unwrap();
    let params = CardParams {
        cards: 60,
        segments: 8,
        ..CardParams::default()
    };
    let mesh = PatchMesh::from_strands(&asset, &params).unwrap();
    assert_eq!(mesh.component_count(), 60);
    check_frames(&mesh);
    assert_eq!(mesh, PatchMesh::from_strands(&asset, &params).unwrap());
    // Roots near the scalp, normals mostly away from the head.
    let head = Head::default();
    let rows = 9;
    let mut out = 0;
    for (k, ribbon) in mesh.positions().chunks_exact(2 * rows).enumerate() {
        let root = (ribbon[0] + ribbon[1]) * 0.5;
        assert!(head.level(root) < 1.2, "root at level {}", head.level(root));
        let n = mesh.normals()[k * 2 * rows + rows];
        if n.dot(ribbon[rows] - head.center) > 0.0 {
            out += 1;
        }
    }
    assert!(out >= 55, "{out} of 60 ribbons face out");
    let widths: Vec<f32> = mesh
        .positions()
        .chunks_exact(2)
        .map(|q| q[0].distance(q[1]))
        .collect();
    assert!(widths.iter().all(|&w| w >= params.min_width - 1e-5));
    // More cards than strands: one card per strand, each at the minimum width.
    let few = HairAsset::from_counts(
        vec![Vec3::ZERO, Vec3::NEG_Y, Vec3::X, Vec3::X + Vec3::NEG_Y],
        &[2, 2],
    )
    .unwrap();
    let m = PatchMesh::from_strands(&few, &CardParams::default()).unwrap();
    assert_eq!(m.component_count(), 2);
    assert!(
        m.positions()
            .chunks_exact(2)
            .all(|q| (q[0].distance(q[1]) - 0.2).abs() < 1e-5)
    );
    assert!(
        PatchMesh::from_strands(
            &few,
            &CardParams {
                cards: 0,
                ..CardParams::default()
            }
        )
        .is_err()
    );
    assert!(
        PatchMesh::from_strands(
            &few,
            &CardParams {
                min_width: 0.0,
                ..CardParams::default()
            }
        )
        .is_err()
    );
}
