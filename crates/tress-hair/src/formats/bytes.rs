//! Little-endian byte helpers shared by the readers and writers.
//!
//! Every array read here (`f32`, `Vec2`, `Vec3`, the xyz of `[f32; 4]`) is made of 4-byte
//! little-endian words. The source bytes may sit at any alignment (the `.hair` arrays after the
//! `u16` segments often do): they are decoded with `from_le_bytes`, never cast in place.

use bytemuck::Pod;
use glam::{Vec2, Vec3};
use rayon::prelude::*;

use crate::HairError;

/// A `u32` at byte `at` of a fixed-size header.
pub(crate) fn u32_at<const N: usize>(header: &[u8; N], at: usize) -> u32 {
    let mut word = [0u8; 4];
    word.copy_from_slice(&header[at..at + 4]);
    u32::from_le_bytes(word)
}

/// An `f32` at byte `at` of a fixed-size header.
pub(crate) fn f32_at<const N: usize>(header: &[u8; N], at: usize) -> f32 {
    f32::from_bits(u32_at(header, at))
}

/// `f32`s from little-endian bytes (a trailing partial element is ignored).
pub(crate) fn read_f32s(src: &[u8]) -> Vec<f32> {
    collect::<1, 4, _>(src, |[x]| x)
}

/// `Vec2`s from little-endian `[f32; 2]`.
pub(crate) fn read_vec2s(src: &[u8]) -> Vec<Vec2> {
    collect::<2, 8, _>(src, Vec2::from_array)
}

/// `Vec3`s from little-endian `[f32; 3]`.
pub(crate) fn read_vec3s(src: &[u8]) -> Vec<Vec3> {
    collect::<3, 12, _>(src, Vec3::from_array)
}

/// The `xyz` of little-endian `[f32; 4]`.
pub(crate) fn read_xyz_of_vec4s(src: &[u8]) -> Vec<Vec3> {
    collect::<3, 16, _>(src, Vec3::from_array)
}

/// Arrays at least this long are decoded on several threads.
const PARALLEL_BYTES: usize = 1 << 20;

/// One element per `S` bytes, made from the first `W` little-endian `f32` words of each.
///
/// A single pass into a vector of exactly the right capacity, with no zero-fill first; on
/// little-endian machines the compiler turns the word assembly into plain vector loads and
/// stores. Large arrays are split over rayon's threads, which also spreads the cost of the
/// kernel's first-touch page faults of the fresh output.
fn collect<const W: usize, const S: usize, T: Send>(
    src: &[u8],
    make: impl Fn([f32; W]) -> T + Sync,
) -> Vec<T> {
    let chunks = src.as_chunks::<S>().0;
    let element = |chunk: &[u8; S]| {
        let words = chunk.as_chunks::<4>().0;
        make(std::array::from_fn(|i| f32::from_le_bytes(words[i])))
    };
    if src.len() >= PARALLEL_BYTES {
        chunks
            .par_iter()
            .with_min_len(PARALLEL_BYTES / S / 4)
            .map(element)
            .collect()
    } else {
        chunks.iter().map(element).collect()
    }
}

/// Append the little-endian bytes of `values` (made of 4-byte words) to `out`.
pub(crate) fn write_words<T: Pod>(out: &mut Vec<u8>, values: &[T]) {
    let src: &[u8] = bytemuck::cast_slice(values);
    if cfg!(target_endian = "big") {
        for word in src.chunks_exact(4) {
            out.extend(word.iter().rev());
        }
    } else {
        out.extend_from_slice(src);
    }
}

/// Append a little-endian `u32`.
pub(crate) fn put_u32(out: &mut Vec<u8>, v: u32) {
    out.extend_from_slice(&v.to_le_bytes());
}

/// Append a little-endian `f32`.
pub(crate) fn put_f32(out: &mut Vec<u8>, v: f32) {
    out.extend_from_slice(&v.to_le_bytes());
}

/// The `len`-byte range starting at `offset`, if the file holds it. `what` names the array for
/// the error message.
pub(crate) fn array<'a>(
    format: &'static str,
    bytes: &'a [u8],
    what: &str,
    offset: u64,
    len: u64,
) -> Result<&'a [u8], HairError> {
    let end = offset.checked_add(len);
    match end {
        Some(end) if end <= bytes.len() as u64 => Ok(&bytes[offset as usize..end as usize]),
        _ => Err(HairError::format(
            format,
            format!(
                "truncated: the {what} should occupy bytes {offset}..{} but the file has {} bytes",
                offset as u128 + len as u128,
                bytes.len()
            ),
        )),
    }
}

/// Turn an asset-invariant error from a constructor into a format error of the file being read,
/// so that the message names the format rather than "invalid hair asset".
pub(crate) fn in_format(format: &'static str) -> impl Fn(HairError) -> HairError {
    move |e| match e {
        HairError::Invalid(reason) => HairError::format(format, reason),
        other => other,
    }
}
