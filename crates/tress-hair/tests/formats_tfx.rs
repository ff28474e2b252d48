//! TressFX `.tfx` reader (3.x and 4.x) and writer (4.x): hand-built files checked against
//! expectations computed here, follow hairs, round trips, and every kind of bad input.

use glam::{Vec2, Vec3};
use tress_hair::formats::{TfxVersion, parse_tfx, read_tfx, write_tfx};
use tress_hair::{HairAsset, HairError};

fn put_u32s(b: &mut Vec<u8>, v: &[u32]) {
    v.iter().for_each(|x| b.extend(x.to_le_bytes()));
}

fn put_f32s(b: &mut Vec<u8>, v: &[f32]) {
    v.iter().for_each(|x| b.extend(x.to_le_bytes()));
}

fn u32_at(b: &[u8], at: usize) -> u32 {
    u32::from_le_bytes(b[at..at + 4].try_into().unwrap())
}

fn f32_at(b: &[u8], at: usize) -> f32 {
    f32::from_le_bytes(b[at..at + 4].try_into().unwrap())
}

fn format_error<T: std::fmt::Debug>(result: Result<T, HairError>) -> String {
    match result {
        Err(e @ HairError::Format { format: ".tfx", .. }) => e.to_string(),
        other => panic!("expected a .tfx format error, got {other:?}"),
    }
}

/// Position of vertex `v` of strand `s` in the hand-built files.
fn point(s: u32, v: u32) -> Vec3 {
    Vec3::new(s as f32 * 10.0, -(v as f32), 0.5 + v as f32 * 0.25)
}

/// A 4.x header: version, strands, vertices per strand, then the five offsets.
fn v4_header(strands: u32, vps: u32, offsets: [u32; 5]) -> Vec<u8> {
    let mut b = Vec::new();
    put_f32s(&mut b, &[4.0]);
    put_u32s(&mut b, &[strands, vps]);
    put_u32s(&mut b, &offsets);
    b.resize(160, 0);
    b
}

/// 2 strands × 3 vertices, float4 positions at 160 (w = 0.0, 0.0, 1.0), strand UVs after them.
fn v4_file() -> Vec<u8> {
    let uv_at = 160 + 16 * 6;
    let mut b = v4_header(2, 3, [160, uv_at, 0, 0, 0]);
    for s in 0..2 {
        for v in 0..3 {
            put_f32s(
                &mut b,
                &point(s, v).extend(if v < 2 { 0.0 } else { 1.0 }).to_array(),
            );
        }
    }
    put_f32s(&mut b, &[0.25, 0.75, 0.5, 0.125]);
    b
}

/// A 3.x header: version 3.0, strands, vertices per strand, follow hairs, and the six offsets.
fn v3_header(strands: u32, vps: u32, follow: u32, offsets: [u32; 6]) -> Vec<u8> {
    let mut b = Vec::new();
    put_f32s(&mut b, &[3.0]);
    put_u32s(&mut b, &[strands, vps, follow, 1]);
    b.resize(144, 0);
    put_u32s(&mut b, &offsets);
    b.resize(296, 0);
    b
}

/// 2 strands × 4 vertices, float3 positions at 296, then float4 vertex colors.
fn v3_file(follow: u32) -> Vec<u8> {
    let color_at = 296 + 12 * 8;
    let mut b = v3_header(2, 4, follow, [296, 0, 0, color_at, 0, 0]);
    for s in 0..2 {
        for v in 0..4 {
            put_f32s(&mut b, &point(s, v).to_array());
        }
    }
    for i in 0..8 {
        put_f32s(&mut b, &[0.1 * i as f32, 0.2, 0.3, 0.9]);
    }
    b
}

#[test]
fn reads_a_hand_built_v4_file() {
    let file = parse_tfx(&v4_file()).unwrap();
    assert_eq!(file.version, TfxVersion::V4);
    assert_eq!(file.follow_hairs_per_guide, 0);
    let h = file.guides;
    assert_eq!(h.strand_offsets(), &[0, 3, 6]);
    let expected: Vec<Vec3> = (0..2)
        .flat_map(|s| (0..3).map(move |v| point(s, v)))
        .collect();
    assert_eq!(h.positions(), expected.as_slice());
    assert_eq!(
        h.strand_uv().unwrap(),
        &[Vec2::new(0.25, 0.75), Vec2::new(0.5, 0.125)]
    );
    assert!(h.color().is_none() && h.thickness().is_none());
    assert_eq!(read_tfx(&v4_file()).unwrap(), h);
}

#[test]
fn reads_a_hand_built_v3_file() {
    let file = parse_tfx(&v3_file(0)).unwrap();
    assert_eq!(file.version, TfxVersion::V3);
    let h = file.guides;
    assert_eq!(h.strand_offsets(), &[0, 4, 8]);
    assert_eq!(
        h.strand(1),
        &[point(1, 0), point(1, 1), point(1, 2), point(1, 3)]
    );
    let colors: Vec<Vec3> = (0..8)
        .map(|i| Vec3::new(0.1 * i as f32, 0.2, 0.3))
        .collect();
    assert_eq!(h.color().unwrap(), colors.as_slice());
    assert!(h.strand_uv().is_none());
}

#[test]
fn v3_follow_hairs_are_generated_around_each_guide() {
    let file = parse_tfx(&v3_file(2)).unwrap();
    assert_eq!(file.follow_hairs_per_guide, 2);
    assert_eq!(file.guides.strand_count(), 2);

    let h = read_tfx(&v3_file(2)).unwrap();
    assert_eq!(h.strand_count(), 6);
    assert_eq!(h.vertex_count(), 24);
    for g in 0..2u32 {
        let guide: Vec<Vec3> = (0..4).map(|v| point(g, v)).collect();
        assert_eq!(
            h.strand(3 * g as usize),
            guide.as_slice(),
            "guide {g} comes first"
        );
        for f in 1..3 {
            let follower = h.strand(3 * g as usize + f);
            let root_offset = follower[0] - guide[0];
            // The default radius: 0.7 of the guides' root spacing (their roots are 10 apart).
            let radius = tress_hair::DEFAULT_RADIUS_FACTOR * 10.0;
            assert!(root_offset.length() > 0.0 && root_offset.length() <= radius + 1e-5);
            // Two guides are the corners of no triangle, so their followers are offset; with
            // no scalp plane from two roots, across the root tangent (the guide runs along -y
            // then +z).
            let tangent = (guide[1] - guide[0]).normalize();
            assert!(root_offset.dot(tangent).abs() < 1e-5);
        }
    }
    // Colors are copied from the guide to its followers.
    assert_eq!(h.color().unwrap()[4..8], h.color().unwrap()[0..4]);
}

#[test]
fn v3_strand_uvs_and_unread_arrays() {
    // Strand UVs at 392; the thickness, guide-flag and vertex-UV offsets point past the end of
    // the file, which is fine because tress does not read those arrays.
    let mut b = v3_header(2, 4, 0, [296, 9999, 392, 0, 9999, 9999]);
    (0..8).for_each(|i| put_f32s(&mut b, &point(i / 4, i % 4).to_array()));
    put_f32s(&mut b, &[0.5, 0.5, 1.0, 0.0]);
    let h = read_tfx(&b).unwrap();
    assert_eq!(
        h.strand_uv().unwrap(),
        &[Vec2::splat(0.5), Vec2::new(1.0, 0.0)]
    );
}

#[test]
fn accepts_minor_versions() {
    let mut b = v4_file();
    b[0..4].copy_from_slice(&4.1f32.to_le_bytes());
    assert_eq!(parse_tfx(&b).unwrap().version, TfxVersion::V4);
    let mut b = v3_file(0);
    b[0..4].copy_from_slice(&3.5f32.to_le_bytes());
    assert_eq!(parse_tfx(&b).unwrap().version, TfxVersion::V3);
}

fn fixed_asset(strands: u32, vps: u32) -> HairAsset {
    let positions = (0..strands)
        .flat_map(|s| (0..vps).map(move |v| point(s, v)))
        .collect();
    HairAsset::from_counts(positions, &vec![vps; strands as usize]).unwrap()
}

#[test]
fn writer_lays_out_a_v4_file() {
    let a = fixed_asset(3, 4);
    let uv = vec![
        Vec2::new(0.1, 0.2),
        Vec2::new(0.3, 0.4),
        Vec2::new(0.5, 0.6),
    ];
    let color: Vec<Vec3> = (0..12)
        .map(|i| Vec3::new(i as f32 / 12.0, 0.5, 0.25))
        .collect();
    let a = a.with_strand_uv(uv).unwrap().with_color(color).unwrap();
    let b = write_tfx(&a).unwrap();
    let (uv_at, color_at) = (160 + 16 * 12, 160 + 16 * 12 + 8 * 3);
    assert_eq!(b.len(), color_at + 16 * 12);
    assert_eq!(f32_at(&b, 0), 4.0);
    assert_eq!([u32_at(&b, 4), u32_at(&b, 8)], [3, 4]);
    assert_eq!(
        [
            u32_at(&b, 12),
            u32_at(&b, 16),
            u32_at(&b, 20),
            u32_at(&b, 24),
            u32_at(&b, 28)
        ],
        [160, uv_at as u32, 0, 0, color_at as u32]
    );
    assert!(
        b[32..160].iter().all(|&x| x == 0),
        "reserved words are zero"
    );
    assert_eq!([uv_at % 8, color_at % 8], [0, 0], "8-byte aligned arrays");
    // Vertex 6 is strand 1, vertex 2: xyz then w = 1 (movable); vertex 5 is pinned (w = 0).
    let v6 = 160 + 16 * 6;
    let xyzw: Vec<f32> = (0..4).map(|k| f32_at(&b, v6 + 4 * k)).collect();
    assert_eq!(xyzw, [10.0, -2.0, 1.0, 1.0]);
    assert_eq!(f32_at(&b, 160 + 16 * 5 + 12), 0.0);
    assert_eq!(f32_at(&b, uv_at + 8 + 4), 0.4);
    assert_eq!(f32_at(&b, color_at + 16 * 3), 0.25);
    assert_eq!(f32_at(&b, color_at + 16 * 3 + 12), 1.0, "alpha");
}

#[test]
fn round_trips_through_v4() {
    let a = fixed_asset(5, 8);
    assert_eq!(read_tfx(&write_tfx(&a).unwrap()).unwrap(), a);
    let uv: Vec<Vec2> = (0..5)
        .map(|s| Vec2::new(s as f32 * 0.2, 1.0 - s as f32 * 0.1))
        .collect();
    let color: Vec<Vec3> = (0..40)
        .map(|i| Vec3::new(0.5, i as f32 * 0.01, 0.0))
        .collect();
    let with_uv = a.clone().with_strand_uv(uv).unwrap();
    assert_eq!(read_tfx(&write_tfx(&with_uv).unwrap()).unwrap(), with_uv);
    let full = with_uv.with_color(color).unwrap();
    assert_eq!(read_tfx(&write_tfx(&full).unwrap()).unwrap(), full);
}

#[test]
fn thickness_and_transparency_are_not_written() {
    let a = fixed_asset(2, 4);
    let t = a
        .clone()
        .with_thickness(vec![0.1; 8])
        .unwrap()
        .with_transparency(vec![0.5; 8])
        .unwrap();
    assert_eq!(read_tfx(&write_tfx(&t).unwrap()).unwrap(), a);
}

#[test]
fn writer_rejects_strands_of_different_lengths() {
    let a = HairAsset::from_counts(vec![Vec3::ZERO; 7], &[4, 3]).unwrap();
    let e = format_error(write_tfx(&a));
    assert!(
        e.contains("3 to 4 vertices") && e.contains("resample"),
        "{e}"
    );
}

#[test]
fn rejects_unknown_versions_and_short_files() {
    assert!(format_error(read_tfx(&[])).contains("0 bytes"));
    assert!(format_error(read_tfx(&[0, 0, 0x80])).contains("3 bytes"));
    for v in [0.0f32, 2.0, 2.999, 5.0, 41.0, f32::NAN, f32::INFINITY] {
        let mut b = v4_file();
        b[0..4].copy_from_slice(&v.to_le_bytes());
        let e = format_error(read_tfx(&b));
        assert!(e.contains("unsupported TressFX version"), "{v}: {e}");
    }
    let e = format_error(read_tfx(&v4_file()[..159]));
    assert!(
        e.contains("159 bytes, fewer than the 160-byte TressFX 4.x header"),
        "{e}"
    );
    let e = format_error(read_tfx(&v3_file(0)[..200]));
    assert!(
        e.contains("fewer than the 296-byte TressFX 3.x header"),
        "{e}"
    );
}

#[test]
fn rejects_empty_geometry() {
    let mut b = v4_header(0, 4, [160, 0, 0, 0, 0]);
    put_f32s(&mut b, &[0.0; 16]);
    assert!(format_error(read_tfx(&b)).contains("no strands"));
    let b = v4_header(1, 0, [160, 0, 0, 0, 0]);
    assert!(format_error(read_tfx(&b)).contains("0 vertices per strand"));
    let mut b = v4_file();
    b[12..16].copy_from_slice(&0u32.to_le_bytes());
    assert!(format_error(read_tfx(&b)).contains("no vertex positions"));
}

#[test]
fn rejects_offsets_into_the_header_or_past_the_end() {
    let mut b = v4_file();
    b[12..16].copy_from_slice(&8u32.to_le_bytes());
    let e = format_error(read_tfx(&b));
    assert!(
        e.contains("vertex positions offset 8 points into the 160-byte header"),
        "{e}"
    );
    let mut b = v3_file(0);
    b[156..160].copy_from_slice(&200u32.to_le_bytes());
    assert!(format_error(read_tfx(&b)).contains("296-byte header"));

    let b = v4_file();
    let e = format_error(read_tfx(&b[..b.len() - 1]));
    let expected =
        "truncated: the strand UVs should occupy bytes 256..272 but the file has 271 bytes";
    assert!(e.contains(expected), "{e}");
    let e = format_error(read_tfx(&b[..200]));
    assert!(
        e.contains("vertex positions should occupy bytes 160..256 but the file has 200"),
        "{e}"
    );
    let mut b = v4_file();
    b[16..20].copy_from_slice(&u32::MAX.to_le_bytes());
    assert!(format_error(read_tfx(&b)).contains("strand UVs"));
}

#[test]
fn huge_counts_in_a_tiny_file_fail_before_allocating() {
    let b = v4_header(u32::MAX, u32::MAX, [160, 0, 0, 0, 0]);
    assert!(format_error(read_tfx(&b)).contains("more than 2^32 vertices"));
    let b = v4_header(1 << 20, 4095, [160, 0, 0, 0, 0]);
    let e = format_error(read_tfx(&b));
    assert!(
        e.contains("truncated") && e.contains("the file has 160 bytes"),
        "{e}"
    );
    let b = v3_header(1 << 26, 63, 0, [296, 0, 0, 0, 0, 0]);
    assert!(format_error(read_tfx(&b)).contains("truncated"));
    // A lying follow-hair count cannot multiply a small file into gigabytes.
    let mut b = v3_file(0);
    b[12..16].copy_from_slice(&1_000_000u32.to_le_bytes());
    let e = format_error(read_tfx(&b));
    assert!(
        e.contains("numFollowHairsPerGuideHair is 1000000; tress accepts at most 64"),
        "{e}"
    );
}

#[test]
fn rejects_non_finite_values() {
    for bad in [f32::NAN, f32::INFINITY] {
        let mut b = v4_file();
        let at = 160 + 16 * 4 + 8; // z of vertex 4
        b[at..at + 4].copy_from_slice(&bad.to_le_bytes());
        assert!(format_error(read_tfx(&b)).contains("vertex 4 has a non-finite position"));
        // A non-finite w (inverse mass) is ignored.
        let mut b = v4_file();
        b[160 + 16 * 4 + 12..160 + 16 * 5].copy_from_slice(&bad.to_le_bytes());
        assert!(read_tfx(&b).is_ok());
        let mut b = v4_file();
        let n = b.len();
        b[n - 4..].copy_from_slice(&bad.to_le_bytes());
        assert!(format_error(read_tfx(&b)).contains("UV of strand 1"));
        let mut b = v3_file(0);
        let at = 296 + 12 * 8 + 16 * 2 + 4; // green of color 2
        b[at..at + 4].copy_from_slice(&bad.to_le_bytes());
        assert!(format_error(read_tfx(&b)).contains("color of vertex 2"));
    }
}
