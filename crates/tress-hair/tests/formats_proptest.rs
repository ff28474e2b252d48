//! Property tests of the readers: random bytes and mutated valid files never panic (every reader
//! returns `Ok` or `Err`), and random assets survive a write/read round trip unchanged.

use glam::{Vec2, Vec3};
use proptest::prelude::*;
use tress_hair::HairAsset;
use tress_hair::formats::{parse_tfx, read_hair, read_tfx, write_hair, write_tfx};

/// Every reader on the same bytes: none may panic. What a reader accepts must be a valid asset
/// that its writer writes and reads back unchanged.
fn read_all(bytes: &[u8]) {
    let hair = read_hair(bytes);
    let tfx = read_tfx(bytes);
    let guides = parse_tfx(bytes).map(|f| f.guides);
    for asset in [&hair, &tfx, &guides].into_iter().flatten() {
        assert!(asset.strand_count() > 0);
        assert!(asset.positions().iter().all(|p| p.is_finite()));
        assert_eq!(
            *asset.strand_offsets().last().unwrap() as usize,
            asset.vertex_count()
        );
    }
    if let Ok(asset) = hair {
        assert_eq!(read_hair(&write_hair(&asset).unwrap()).unwrap(), asset);
    }
    if let Ok(guides) = guides {
        assert_eq!(read_tfx(&write_tfx(&guides).unwrap()).unwrap(), guides);
    }
}

fn coord() -> impl Strategy<Value = f32> {
    -1.0e3f32..1.0e3
}

fn vec3() -> impl Strategy<Value = Vec3> {
    (coord(), coord(), coord()).prop_map(|(x, y, z)| Vec3::new(x, y, z))
}

/// Optional per-vertex thickness, transparency and color.
type Attributes = (Option<Vec<f32>>, Option<Vec<f32>>, Option<Vec<Vec3>>);

/// Per-vertex attributes for `n` vertices, each optional.
fn attributes(n: usize) -> impl Strategy<Value = Attributes> {
    (
        proptest::option::of(proptest::collection::vec(0.0f32..2.0, n)),
        proptest::option::of(proptest::collection::vec(0.0f32..1.0, n)),
        proptest::option::of(proptest::collection::vec(vec3(), n)),
    )
}

/// A random asset with strands of 1 to 12 vertices and any of the `.hair` attributes.
fn hair_asset() -> impl Strategy<Value = HairAsset> {
    proptest::collection::vec(1u32..12, 1..16)
        .prop_flat_map(|counts| {
            let n = counts.iter().sum::<u32>() as usize;
            (
                Just(counts),
                proptest::collection::vec(vec3(), n),
                attributes(n),
            )
        })
        .prop_map(|(counts, positions, (thickness, transparency, color))| {
            let mut a = HairAsset::from_counts(positions, &counts).unwrap();
            if let Some(t) = thickness {
                a = a.with_thickness(t).unwrap();
            }
            if let Some(t) = transparency {
                a = a.with_transparency(t).unwrap();
            }
            if let Some(c) = color {
                a = a.with_color(c).unwrap();
            }
            a
        })
}

/// A random asset with equal strands, optional strand UVs and colors (what `.tfx` 4.x holds).
fn tfx_asset() -> impl Strategy<Value = HairAsset> {
    (1u32..10, 1u32..12)
        .prop_flat_map(|(strands, vps)| {
            let n = (strands * vps) as usize;
            (
                Just((strands, vps)),
                proptest::collection::vec(vec3(), n),
                proptest::option::of(proptest::collection::vec(
                    (0.0f32..1.0, 0.0f32..1.0),
                    strands as usize,
                )),
                proptest::option::of(proptest::collection::vec(vec3(), n)),
            )
        })
        .prop_map(|((strands, vps), positions, uv, color)| {
            let mut a = HairAsset::from_counts(positions, &vec![vps; strands as usize]).unwrap();
            if let Some(uv) = uv {
                a = a
                    .with_strand_uv(uv.into_iter().map(|(u, v)| Vec2::new(u, v)).collect())
                    .unwrap();
            }
            if let Some(c) = color {
                a = a.with_color(c).unwrap();
            }
            a
        })
}

/// A byte mutation of a valid file.
#[derive(Clone, Debug)]
enum Mutation {
    /// Set the byte at (index modulo length) to a value.
    Byte(usize, u8),
    /// Overwrite the 4-byte word at (word index modulo header words) with a value.
    HeaderWord(usize, u32),
    /// Cut the file at (index modulo length).
    Truncate(usize),
}

fn mutation() -> impl Strategy<Value = Mutation> {
    let word = prop_oneof![
        Just(0u32),
        Just(1),
        Just(3),
        Just(u32::MAX),
        Just(0x8000_0000),
        Just(0x4040_0000), // 3.0f32
        Just(0x4080_0000), // 4.0f32
        Just(160),
        Just(296),
        any::<u32>(),
    ];
    prop_oneof![
        (any::<usize>(), any::<u8>()).prop_map(|(i, b)| Mutation::Byte(i, b)),
        (any::<usize>(), word).prop_map(|(i, w)| Mutation::HeaderWord(i, w)),
        any::<usize>().prop_map(Mutation::Truncate),
    ]
}

fn mutate(mut bytes: Vec<u8>, header_len: usize, mutations: &[Mutation]) -> Vec<u8> {
    for m in mutations {
        if bytes.is_empty() {
            break;
        }
        match *m {
            Mutation::Byte(i, b) => {
                let i = i % bytes.len();
                bytes[i] = b;
            }
            Mutation::HeaderWord(i, w) => {
                let at = 4 * (i % (header_len.min(bytes.len()) / 4).max(1));
                if at + 4 <= bytes.len() {
                    bytes[at..at + 4].copy_from_slice(&w.to_le_bytes());
                }
            }
            Mutation::Truncate(i) => bytes.truncate(i % bytes.len()),
        }
    }
    bytes
}

proptest! {
    #[test]
    fn random_bytes_never_panic(bytes in proptest::collection::vec(any::<u8>(), 0..1200)) {
        read_all(&bytes);
    }

    #[test]
    fn random_bodies_behind_valid_magic_never_panic(
        body in proptest::collection::vec(any::<u8>(), 0..1200),
        magic in prop_oneof![Just(*b"HAIR"), Just(3.0f32.to_le_bytes()), Just(4.0f32.to_le_bytes())],
    ) {
        let mut bytes = magic.to_vec();
        bytes.extend(body);
        read_all(&bytes);
    }

    #[test]
    fn mutated_hair_files_never_panic(
        asset in hair_asset(),
        mutations in proptest::collection::vec(mutation(), 1..6),
    ) {
        read_all(&mutate(write_hair(&asset).unwrap(), 128, &mutations));
    }

    #[test]
    fn mutated_tfx_files_never_panic(
        asset in tfx_asset(),
        mutations in proptest::collection::vec(mutation(), 1..6),
        as_v3 in any::<bool>(),
    ) {
        let mut bytes = write_tfx(&asset).unwrap();
        if as_v3 {
            // Reinterpret as a 3.x file: the 4.x header words become 3.x fields.
            bytes[0..4].copy_from_slice(&3.0f32.to_le_bytes());
        }
        read_all(&mutate(bytes, if as_v3 { 296 } else { 160 }, &mutations));
    }

    #[test]
    fn hair_round_trip(asset in hair_asset()) {
        prop_assert_eq!(read_hair(&write_hair(&asset).unwrap()).unwrap(), asset);
    }

    #[test]
    fn tfx_round_trip(asset in tfx_asset()) {
        prop_assert_eq!(read_tfx(&write_tfx(&asset).unwrap()).unwrap(), asset);
    }
}
