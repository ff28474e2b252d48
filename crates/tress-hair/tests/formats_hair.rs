//! Cem Yuksel `.hair` reader and writer: hand-built files checked against expectations computed
//! here, round trips, the vkhr extension, and every kind of bad input.

use glam::{Vec2, Vec3};
use tress_hair::formats::{read_hair, write_hair};
use tress_hair::{HairAsset, HairError};

const SEGMENTS: u32 = 1;
const POINTS: u32 = 2;
const THICKNESS: u32 = 4;
const TRANSPARENCY: u32 = 8;
const COLOR: u32 = 16;
const VKHR_TANGENTS: u32 = 32;
const VKHR_INDICES: u32 = 64;
const VKHR_BOUNDS: u32 = 128;

/// A `.hair` header, written field by field as the specification lists them.
struct Header {
    magic: [u8; 4],
    hairs: u32,
    points: u32,
    flags: u32,
    d_segments: u32,
    d_thickness: f32,
    d_transparency: f32,
    d_color: [f32; 3],
}

impl Header {
    fn new(hairs: u32, points: u32, flags: u32) -> Header {
        Header {
            magic: *b"HAIR",
            hairs,
            points,
            flags,
            d_segments: 0,
            d_thickness: 1.0,
            d_transparency: 0.0,
            d_color: [1.0; 3],
        }
    }

    fn bytes(&self) -> Vec<u8> {
        let mut b = self.magic.to_vec();
        for v in [self.hairs, self.points, self.flags, self.d_segments] {
            b.extend(v.to_le_bytes());
        }
        for v in [self.d_thickness, self.d_transparency] {
            b.extend(v.to_le_bytes());
        }
        for v in self.d_color {
            b.extend(v.to_le_bytes());
        }
        b.resize(128, 0);
        b
    }
}

fn put_u16s(b: &mut Vec<u8>, v: &[u16]) {
    v.iter().for_each(|x| b.extend(x.to_le_bytes()));
}

fn put_f32s(b: &mut Vec<u8>, v: &[f32]) {
    v.iter().for_each(|x| b.extend(x.to_le_bytes()));
}

fn format_error(result: Result<HairAsset, HairError>) -> String {
    match result {
        Err(
            e @ HairError::Format {
                format: ".hair", ..
            },
        ) => e.to_string(),
        other => panic!("expected a .hair format error, got {other:?}"),
    }
}

/// Three strands of 2, 1 and 3 points: the 6-byte segments array leaves the points array at byte
/// 134, which is not 4-byte aligned.
fn three_strands_file(extra_flags: u32) -> (Vec<u8>, Vec<Vec3>) {
    let points: Vec<Vec3> = (0..6)
        .map(|i| Vec3::new(i as f32, -(i as f32) * 0.5, 0.25))
        .collect();
    let mut b = Header::new(3, 6, SEGMENTS | POINTS | extra_flags).bytes();
    put_u16s(&mut b, &[1, 0, 2]);
    for p in &points {
        put_f32s(&mut b, &p.to_array());
    }
    (b, points)
}

#[test]
fn reads_a_hand_built_file_with_unaligned_arrays() {
    let (mut b, points) = three_strands_file(THICKNESS | TRANSPARENCY | COLOR);
    let thickness = [0.1, 0.2, 0.3, 0.4, 0.5, 0.6];
    let transparency = [0.0, 0.5, 0.25, 0.125, 1.0, 0.75];
    put_f32s(&mut b, &thickness);
    put_f32s(&mut b, &transparency);
    let colors: Vec<Vec3> = (0..6)
        .map(|i| Vec3::new(0.1 * i as f32, 0.5, 1.0))
        .collect();
    colors.iter().for_each(|c| put_f32s(&mut b, &c.to_array()));
    assert_eq!(b.len(), 128 + 6 + 6 * 12 + 6 * 4 + 6 * 4 + 6 * 12);

    let h = read_hair(&b).unwrap();
    assert_eq!(h.strand_count(), 3);
    assert_eq!(h.strand_offsets(), &[0, 2, 3, 6]);
    assert_eq!(h.positions(), points.as_slice());
    assert_eq!(h.thickness().unwrap(), &thickness);
    assert_eq!(h.transparency().unwrap(), &transparency);
    assert_eq!(h.color().unwrap(), colors.as_slice());
    assert!(h.strand_uv().is_none());
}

#[test]
fn without_segments_array_every_strand_has_the_default_count() {
    let mut header = Header::new(2, 8, POINTS);
    header.d_segments = 3;
    let mut b = header.bytes();
    let points: Vec<f32> = (0..24).map(|i| i as f32).collect();
    put_f32s(&mut b, &points);
    let h = read_hair(&b).unwrap();
    assert_eq!(h.strand_offsets(), &[0, 4, 8]);
    assert_eq!(h.strand(1)[0], Vec3::new(12.0, 13.0, 14.0));
    assert!(h.thickness().is_none() && h.transparency().is_none() && h.color().is_none());
}

#[test]
fn meaningful_header_defaults_become_per_vertex_arrays() {
    let (b, _) = three_strands_file(0);
    let with_defaults = |t: f32, a: f32, c: [f32; 3]| {
        let mut b = b.clone();
        let mut header = Header::new(3, 6, SEGMENTS | POINTS);
        header.d_thickness = t;
        header.d_transparency = a;
        header.d_color = c;
        b[..128].copy_from_slice(&header.bytes());
        read_hair(&b).unwrap()
    };
    let h = with_defaults(0.05, 0.3, [0.4, 0.3, 0.2]);
    assert_eq!(h.thickness().unwrap(), &[0.05; 6]);
    assert_eq!(h.transparency().unwrap(), &[0.3; 6]);
    assert_eq!(h.color().unwrap(), &[Vec3::new(0.4, 0.3, 0.2); 6]);

    // cyHairFile's placeholders (thickness 1, transparency 0, white), zeros and non-finite values
    // carry no information.
    for (t, a, c) in [
        (1.0, 0.0, [1.0, 1.0, 1.0]),
        (0.0, 0.0, [0.0, 0.0, 0.0]),
        (f32::NAN, f32::INFINITY, [f32::NAN, 0.5, 0.5]),
        (-2.0, 0.0, [1.0, 1.0, 1.0]),
    ] {
        let h = with_defaults(t, a, c);
        assert!(h.thickness().is_none(), "thickness default {t}");
        assert!(h.transparency().is_none(), "transparency default {a}");
        assert!(h.color().is_none(), "color default {c:?}");
    }
}

#[test]
fn arrays_override_header_defaults() {
    let (mut b, _) = three_strands_file(THICKNESS);
    let mut header = Header::new(3, 6, SEGMENTS | POINTS | THICKNESS);
    header.d_thickness = 0.05;
    b[..128].copy_from_slice(&header.bytes());
    put_f32s(&mut b, &[0.5; 6]);
    assert_eq!(read_hair(&b).unwrap().thickness().unwrap(), &[0.5; 6]);
}

#[test]
fn reads_the_vkhr_extension_and_skips_its_arrays() {
    let (plain, _) = three_strands_file(THICKNESS);
    let mut plain = plain;
    put_f32s(&mut plain, &[0.1; 6]);
    let expected = read_hair(&plain).unwrap();

    let mut b = plain.clone();
    let flags = SEGMENTS | POINTS | THICKNESS | VKHR_TANGENTS | VKHR_INDICES | VKHR_BOUNDS;
    b[12..16].copy_from_slice(&flags.to_le_bytes());
    // The bounding box in the last 24 bytes of the information string.
    let mut bounds = Vec::new();
    put_f32s(&mut bounds, &[0.0, -2.5, 0.25, 5.0, 0.0, 0.25]);
    b[104..128].copy_from_slice(&bounds);
    // Tangents: one per point; indices: two per segment (6 points - 3 strands = 3 segments).
    put_f32s(&mut b, &[0.0, 1.0, 0.0].repeat(6));
    for i in [0u32, 1, 3, 4, 4, 5] {
        b.extend(i.to_le_bytes());
    }
    assert_eq!(read_hair(&b).unwrap(), expected);

    // The extension's arrays must still be in the file.
    let e = format_error(read_hair(&b[..b.len() - 1]));
    assert!(e.contains("index array (vkhr extension)"), "{e}");
    let short = &b[..b.len() - 24 - 4];
    let e = format_error(read_hair(short));
    assert!(e.contains("tangent array (vkhr extension)"), "{e}");
}

#[test]
fn trailing_bytes_are_ignored() {
    let (mut b, points) = three_strands_file(0);
    b.extend([0xAB; 7]);
    assert_eq!(read_hair(&b).unwrap().positions(), points.as_slice());
}

fn sample_asset() -> HairAsset {
    let counts = [3u32, 1, 5, 2];
    let n: u32 = counts.iter().sum();
    let positions =
        (0..n).map(|i| Vec3::new(i as f32 * 0.5, (i * i) as f32 * -0.01, 1.0 / (i + 1) as f32));
    HairAsset::from_counts(positions.collect(), &counts).unwrap()
}

#[test]
fn writer_lays_out_the_header_and_arrays_as_specified() {
    let a = sample_asset();
    let n = a.vertex_count();
    let a = a
        .with_thickness((0..n).map(|i| 0.01 * i as f32).collect())
        .unwrap();
    let b = write_hair(&a).unwrap();
    assert_eq!(b.len(), 128 + 2 * 4 + 12 * n + 4 * n);
    let u32_at = |at: usize| u32::from_le_bytes(b[at..at + 4].try_into().unwrap());
    let f32_at = |at: usize| f32::from_le_bytes(b[at..at + 4].try_into().unwrap());
    assert_eq!(&b[0..4], b"HAIR");
    assert_eq!(u32_at(4), 4);
    assert_eq!(u32_at(8), 11);
    assert_eq!(u32_at(12), SEGMENTS | POINTS | THICKNESS);
    assert_eq!((f32_at(20), f32_at(24)), (1.0, 0.0));
    let segments: Vec<u16> = b[128..136]
        .chunks(2)
        .map(|c| u16::from_le_bytes([c[0], c[1]]))
        .collect();
    assert_eq!(segments, [2, 0, 4, 1]);
    // Vertex 7 (x = 3.5) starts at 128 + 8 + 7 * 12.
    assert_eq!(f32_at(136 + 7 * 12), 3.5);
    assert_eq!(f32_at(136 + 12 * n + 4 * 10), 0.01 * 10.0);
}

#[test]
fn round_trips_with_and_without_optional_arrays() {
    let a = sample_asset();
    let n = a.vertex_count();
    assert_eq!(read_hair(&write_hair(&a).unwrap()).unwrap(), a);

    let full = a
        .clone()
        .with_thickness((0..n).map(|i| 0.02 + i as f32 * 1e-3).collect())
        .unwrap()
        .with_transparency((0..n).map(|i| i as f32 / n as f32).collect())
        .unwrap()
        .with_color(
            (0..n)
                .map(|i| Vec3::new(0.3, 0.2, i as f32 * 0.05))
                .collect(),
        )
        .unwrap();
    assert_eq!(read_hair(&write_hair(&full).unwrap()).unwrap(), full);

    // Each optional array on its own, including a constant 1.0 thickness array (the value the
    // writer puts in the header's default slot).
    let only_color = a.clone().with_color(vec![Vec3::ONE; n]).unwrap();
    assert_eq!(
        read_hair(&write_hair(&only_color).unwrap()).unwrap(),
        only_color
    );
    let ones = a.clone().with_thickness(vec![1.0; n]).unwrap();
    assert_eq!(read_hair(&write_hair(&ones).unwrap()).unwrap(), ones);
    let only_transparency = a.clone().with_transparency(vec![0.5; n]).unwrap();
    let back = read_hair(&write_hair(&only_transparency).unwrap()).unwrap();
    assert_eq!(back, only_transparency);
}

#[test]
fn strand_uvs_are_not_written() {
    let a = sample_asset();
    let with_uv = a
        .clone()
        .with_strand_uv(vec![Vec2::new(0.5, 0.25); 4])
        .unwrap();
    assert_eq!(read_hair(&write_hair(&with_uv).unwrap()).unwrap(), a);
}

#[test]
fn very_long_equal_strands_use_the_default_segment_count() {
    let n = 70_000u32;
    let positions: Vec<Vec3> = (0..2 * n)
        .map(|i| Vec3::new(0.0, -(i as f32) * 1e-3, 0.0))
        .collect();
    let a = HairAsset::from_counts(positions, &[n, n]).unwrap();
    let b = write_hair(&a).unwrap();
    let flags = u32::from_le_bytes(b[12..16].try_into().unwrap());
    assert_eq!(flags & SEGMENTS, 0, "no segments array");
    assert_eq!(u32::from_le_bytes(b[16..20].try_into().unwrap()), n - 1);
    assert_eq!(b.len(), 128 + 12 * 2 * n as usize);
    assert_eq!(read_hair(&b).unwrap(), a);

    let uneven =
        HairAsset::from_counts(a.positions()[..(n + 3) as usize].to_vec(), &[n, 3]).unwrap();
    let e = write_hair(&uneven).unwrap_err().to_string();
    assert!(e.contains("strand 0 has 70000 vertices"), "{e}");
}

#[test]
fn rejects_short_or_foreign_files() {
    let e = format_error(read_hair(&[]));
    assert!(e.contains("0 bytes, fewer than the 128-byte header"), "{e}");
    let (b, _) = three_strands_file(0);
    assert!(format_error(read_hair(&b[..127])).contains("127 bytes"));
    let mut foreign = b.clone();
    foreign[..4].copy_from_slice(b"HAI\0");
    let e = format_error(read_hair(&foreign));
    assert!(
        e.contains("not a .hair file") && e.contains("HAI\\x00"),
        "{e}"
    );
}

#[test]
fn rejects_files_without_points_or_strands() {
    let (mut b, _) = three_strands_file(0);
    b[12..16].copy_from_slice(&SEGMENTS.to_le_bytes());
    assert!(format_error(read_hair(&b)).contains("no points array"));

    let b = Header::new(0, 0, POINTS).bytes();
    assert!(format_error(read_hair(&b)).contains("no strands"));

    let mut b = Header::new(5, 2, POINTS).bytes();
    put_f32s(&mut b, &[0.0; 6]);
    assert!(format_error(read_hair(&b)).contains("5 strands but only 2 points"));
}

#[test]
fn rejects_truncated_arrays() {
    let (b, _) = three_strands_file(0);
    let e = format_error(read_hair(&b[..b.len() - 1]));
    assert!(
        e.contains("truncated: the points array should occupy bytes 134..206"),
        "{e}"
    );
    let e = format_error(read_hair(&b[..130]));
    assert!(e.contains("segments array"), "{e}");

    let (mut b, _) = three_strands_file(COLOR);
    put_f32s(&mut b, &[0.5; 17]);
    assert!(format_error(read_hair(&b)).contains("color array"));
}

#[test]
fn huge_counts_in_a_tiny_file_fail_before_allocating() {
    for flags in [
        POINTS,
        SEGMENTS | POINTS,
        POINTS | THICKNESS | COLOR | VKHR_INDICES,
    ] {
        let mut header = Header::new(u32::MAX, u32::MAX, flags);
        header.d_segments = 0;
        let e = format_error(read_hair(&header.bytes()));
        assert!(
            e.contains("truncated") && e.contains("has 128 bytes"),
            "{e}"
        );
    }
    // A lying hair count with a small valid points array: the segments array cannot fit.
    let (mut b, _) = three_strands_file(0);
    b[4..8].copy_from_slice(&0x4000_0000u32.to_le_bytes());
    b[8..12].copy_from_slice(&0x4000_0000u32.to_le_bytes());
    assert!(
        format_error(read_hair(&b)).contains("segments array should occupy bytes 128..2147483776")
    );
}

#[test]
fn rejects_inconsistent_counts() {
    let (mut b, _) = three_strands_file(0);
    b[8..12].copy_from_slice(&5u32.to_le_bytes());
    let e = format_error(read_hair(&b));
    assert!(
        e.contains("segments array describes 6 points but the header gives 5"),
        "{e}"
    );

    let mut header = Header::new(2, 8, POINTS);
    header.d_segments = 2;
    let mut b = header.bytes();
    put_f32s(&mut b, &[0.0; 24]);
    let e = format_error(read_hair(&b));
    assert!(e.contains("default 2 segments"), "{e}");
    header.d_segments = u32::MAX;
    let mut b = header.bytes();
    put_f32s(&mut b, &[0.0; 24]);
    assert!(format_error(read_hair(&b)).contains("default 4294967295 segments"));
}

#[test]
fn rejects_non_finite_values_and_negative_thickness() {
    for bad in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY] {
        let (mut b, _) = three_strands_file(0);
        let at = 134 + 4 * 12 + 4; // y of point 4
        b[at..at + 4].copy_from_slice(&bad.to_le_bytes());
        let e = format_error(read_hair(&b));
        assert!(e.contains("vertex 4 has a non-finite position"), "{e}");
    }
    let (mut b, _) = three_strands_file(THICKNESS);
    put_f32s(&mut b, &[0.1, 0.1, -0.1, 0.1, 0.1, 0.1]);
    assert!(format_error(read_hair(&b)).contains("thickness of vertex 2"));
    let (mut b, _) = three_strands_file(TRANSPARENCY);
    put_f32s(&mut b, &[0.0, 0.0, 0.0, f32::NAN, 0.0, 0.0]);
    assert!(format_error(read_hair(&b)).contains("transparency of vertex 3"));
}
