//! Cem Yuksel's `.hair` format, and the vkhr extension of it.
//!
//! # Layout
//!
//! From the specification at <http://www.cemyuksel.com/research/hairmodels/> and the `Header`
//! of cyCodeBase's `cyHairFile.h`. All numbers are little-endian.
//!
//! | bytes | type | field |
//! | --- | --- | --- |
//! | 0..4 | `[u8; 4]` | magic `"HAIR"` |
//! | 4..8 | `u32` | hair (strand) count |
//! | 8..12 | `u32` | point count |
//! | 12..16 | `u32` | flags: which arrays follow (below) |
//! | 16..20 | `u32` | default segment count (used when there is no segments array) |
//! | 20..24 | `f32` | default thickness |
//! | 24..28 | `f32` | default transparency |
//! | 28..40 | `[f32; 3]` | default color |
//! | 40..128 | `[u8; 88]` | free-form information string |
//!
//! The arrays follow the 128-byte header back to back, in this order, each present only if its
//! flag bit is set:
//!
//! | bit | array | element | count |
//! | --- | --- | --- | --- |
//! | 0 | segments | `u16` | hair count |
//! | 1 | points | `[f32; 3]` | point count |
//! | 2 | thickness | `f32` | point count |
//! | 3 | transparency | `f32` | point count |
//! | 4 | color | `[f32; 3]` | point count |
//! | 5 (vkhr) | tangents | `[f32; 3]` | point count |
//! | 6 (vkhr) | indices | `u32` | 2 × (point count − hair count) |
//!
//! A strand of `s` segments has `s + 1` points. Because the segments array holds `u16`s, every
//! later array may start at an odd 2-byte boundary: arrays are read by copying bytes, never by
//! casting them in place.
//!
//! # The vkhr extension
//!
//! vkhr (Erik S. V. Jansson, <https://github.com/CaffeineViking/vkhr>,
//! `include/vkhr/scene_graph/hair_style.hh` and `src/vkhr/scene_graph/hair_style.cc`), the
//! renderer of the hybrid-hair paper, extends the flags with bit 5 (a per-point tangent array),
//! bit 6 (a line-segment index array: two `u32` per segment) and bit 7 (a bounding box stored in
//! the last 24 bytes of the information string as `[f32; 3]` min and max). tress reads such files:
//! the tangents are skipped ([`HairAsset::tangents`] derives its own from the points), the
//! indices are skipped (they are implied by the strand structure), and the bounding box is ignored
//! ([`HairAsset::bounds`]). Both arrays must still fit in the file. Other flag bits are ignored, as
//! cyHairFile ignores them. Bytes after the last array are ignored.
//!
//! # Defaults and absent arrays
//!
//! - No points array (bit 1 unset): rejected, there is no geometry.
//! - No segments array: every strand has the header's default segment count, and the hair count
//!   times `default segments + 1` must equal the point count.
//! - No thickness, transparency or color array: the header default becomes a per-vertex array only
//!   when it carries information. cyHairFile initialises a header to thickness 1, transparency 0
//!   and color (1, 1, 1), and many writers never change those placeholders, so they are treated as
//!   "not given": thickness is kept if finite, positive and not 1; transparency if finite and not
//!   0; color if finite and neither (0, 0, 0) nor (1, 1, 1). A model whose intended default
//!   thickness is exactly 1 world unit therefore loads without thickness (renderers then use their
//!   own width setting).
//!
//! # Writing
//!
//! [`write_hair`] writes the plain Cem Yuksel layout: the points array, the segments array, and
//! the thickness, transparency and color arrays the asset has. Absent arrays get cyHairFile's
//! placeholder defaults, so reading the file back gives the same asset. A strand of more than
//! 65,536 vertices does not fit the `u16` segments array; such an asset is written with the
//! default segment count instead when all its strands have the same vertex count, and is an error
//! otherwise. Strand UVs have no place in the format and are not written.

use glam::Vec3;

use super::bytes::{
    array, f32_at, in_format, put_f32, put_u32, read_f32s, read_vec3s, u32_at, write_words,
};
use crate::{HairAsset, HairError};

/// Size of the `.hair` header in bytes.
pub const HEADER_LEN: usize = 128;

const FORMAT: &str = ".hair";
const MAGIC: &[u8; 4] = b"HAIR";

/// Flag bits of the header's array field.
mod flag {
    pub(super) const SEGMENTS: u32 = 1 << 0;
    pub(super) const POINTS: u32 = 1 << 1;
    pub(super) const THICKNESS: u32 = 1 << 2;
    pub(super) const TRANSPARENCY: u32 = 1 << 3;
    pub(super) const COLOR: u32 = 1 << 4;
    pub(super) const VKHR_TANGENTS: u32 = 1 << 5;
    pub(super) const VKHR_INDICES: u32 = 1 << 6;
}

/// cyHairFile's initial header values, which mean "not set" (see the module docs).
const PLACEHOLDER_THICKNESS: f32 = 1.0;
const PLACEHOLDER_TRANSPARENCY: f32 = 0.0;
const PLACEHOLDER_COLOR: Vec3 = Vec3::ONE;

/// Most vertices one strand can have in the `u16` segments array.
const MAX_SEGMENT_VERTICES: u32 = u16::MAX as u32 + 1;

fn err(reason: impl Into<String>) -> HairError {
    HairError::format(FORMAT, reason)
}

/// Read a `.hair` file from memory (layout and rules in the [module docs](self)).
pub fn read_hair(bytes: &[u8]) -> Result<HairAsset, HairError> {
    let Some(header) = bytes.first_chunk::<HEADER_LEN>() else {
        return Err(err(format!(
            "truncated: the file has {} bytes, fewer than the {HEADER_LEN}-byte header",
            bytes.len()
        )));
    };
    if &header[0..4] != MAGIC {
        return Err(err(format!(
            "not a .hair file: it starts with \"{}\" instead of \"HAIR\"",
            header[0..4].escape_ascii()
        )));
    }
    let hairs = u32_at(header, 4);
    let points = u32_at(header, 8);
    let flags = u32_at(header, 12);
    let d_segments = u32_at(header, 16);
    let d_thickness = f32_at(header, 20);
    let d_transparency = f32_at(header, 24);
    let d_color = Vec3::new(f32_at(header, 28), f32_at(header, 32), f32_at(header, 36));

    if flags & flag::POINTS == 0 {
        return Err(err(
            "the file has no points array (flag bit 1 is unset), so no geometry",
        ));
    }
    if hairs == 0 {
        return Err(err("the file has no strands (its hair count is 0)"));
    }
    if points < hairs {
        return Err(err(format!(
            "the header says {hairs} strands but only {points} points; every strand needs one"
        )));
    }

    // Locate every array before allocating anything: each must fit in the file.
    let (h, p) = (u64::from(hairs), u64::from(points));
    let mut at = HEADER_LEN as u64;
    let mut take = |present: bool, what: &str, len: u64| -> Result<Option<&[u8]>, HairError> {
        if !present {
            return Ok(None);
        }
        let slice = array(FORMAT, bytes, what, at, len)?;
        at += len;
        Ok(Some(slice))
    };
    let segments = take(flags & flag::SEGMENTS != 0, "segments array", 2 * h)?;
    let positions = take(true, "points array", 12 * p)?.unwrap_or_default();
    let thickness = take(flags & flag::THICKNESS != 0, "thickness array", 4 * p)?;
    let transparency = take(flags & flag::TRANSPARENCY != 0, "transparency array", 4 * p)?;
    let color = take(flags & flag::COLOR != 0, "color array", 12 * p)?;
    take(
        flags & flag::VKHR_TANGENTS != 0,
        "tangent array (vkhr extension)",
        12 * p,
    )?;
    take(
        flags & flag::VKHR_INDICES != 0,
        "index array (vkhr extension)",
        8 * (p - h),
    )?;

    let offsets = match segments {
        Some(seg) => offsets_from_segments(seg, points)?,
        None => {
            let per_strand = u64::from(d_segments) + 1;
            if h.checked_mul(per_strand) != Some(p) {
                return Err(err(format!(
                    "there is no segments array, so every strand has the default {d_segments} \
                     segments, but {hairs} strands of {per_strand} points do not make the \
                     header's {points} points"
                )));
            }
            // per_strand <= points <= u32::MAX here, and so is every prefix.
            (0..=h).map(|i| (i * per_strand) as u32).collect()
        }
    };

    let n = points as usize;
    let mut asset =
        HairAsset::from_offsets(read_vec3s(positions), offsets).map_err(in_format(FORMAT))?;
    let thickness = match thickness {
        Some(t) => Some(read_f32s(t)),
        None => {
            (d_thickness.is_finite() && d_thickness > 0.0 && d_thickness != PLACEHOLDER_THICKNESS)
                .then(|| vec![d_thickness; n])
        }
    };
    let transparency = match transparency {
        Some(t) => Some(read_f32s(t)),
        None => (d_transparency.is_finite() && d_transparency != PLACEHOLDER_TRANSPARENCY)
            .then(|| vec![d_transparency; n]),
    };
    let color = match color {
        Some(c) => Some(read_vec3s(c)),
        None => (d_color.is_finite() && d_color != Vec3::ZERO && d_color != PLACEHOLDER_COLOR)
            .then(|| vec![d_color; n]),
    };
    if let Some(t) = thickness {
        asset = asset.with_thickness(t).map_err(in_format(FORMAT))?;
    }
    if let Some(t) = transparency {
        asset = asset.with_transparency(t).map_err(in_format(FORMAT))?;
    }
    if let Some(c) = color {
        asset = asset.with_color(c).map_err(in_format(FORMAT))?;
    }
    Ok(asset)
}

/// Strand offsets from the `u16` segments array; their sum must match the point count.
fn offsets_from_segments(seg: &[u8], points: u32) -> Result<Vec<u32>, HairError> {
    let mut offsets = Vec::with_capacity(seg.len() / 2 + 1);
    offsets.push(0u32);
    let mut total: u64 = 0;
    for pair in seg.chunks_exact(2) {
        total += u64::from(u16::from_le_bytes([pair[0], pair[1]])) + 1;
        // Truncation is harmless: a total over `points` is rejected below.
        offsets.push(total as u32);
    }
    if total != u64::from(points) {
        return Err(err(format!(
            "the segments array describes {total} points but the header gives {points}"
        )));
    }
    Ok(offsets)
}

/// Write an asset as a `.hair` file (see the [module docs](self) for what is written).
///
/// Fails only when a strand has more than 65,536 vertices and the strands' vertex counts differ.
pub fn write_hair(asset: &HairAsset) -> Result<Vec<u8>, HairError> {
    let n = asset.vertex_count();
    let strands = asset.strand_count();
    let (min, max) = asset.vertices_per_strand_range();
    let with_segments = max <= MAX_SEGMENT_VERTICES;
    if !with_segments && min != max {
        let long = asset
            .vertex_counts()
            .position(|c| c > MAX_SEGMENT_VERTICES)
            .unwrap_or(0);
        return Err(err(format!(
            "strand {long} has {max} vertices; the segments array holds at most \
             {MAX_SEGMENT_VERTICES} a strand, and strands of different lengths need it"
        )));
    }
    let too_many = |_| err("more than 2^32 strands or vertices");
    let strands_u32 = u32::try_from(strands).map_err(too_many)?;
    let points_u32 = u32::try_from(n).map_err(too_many)?;

    let mut flags = flag::POINTS;
    let mut len = HEADER_LEN + 12 * n;
    if with_segments {
        flags |= flag::SEGMENTS;
        len += 2 * strands;
    }
    if asset.thickness().is_some() {
        flags |= flag::THICKNESS;
        len += 4 * n;
    }
    if asset.transparency().is_some() {
        flags |= flag::TRANSPARENCY;
        len += 4 * n;
    }
    if asset.color().is_some() {
        flags |= flag::COLOR;
        len += 12 * n;
    }

    let mut out = Vec::with_capacity(len);
    out.extend_from_slice(MAGIC);
    put_u32(&mut out, strands_u32);
    put_u32(&mut out, points_u32);
    put_u32(&mut out, flags);
    // With equal strands the default segment count is meaningful even beside a segments array.
    put_u32(&mut out, if min == max { max - 1 } else { 0 });
    put_f32(&mut out, PLACEHOLDER_THICKNESS);
    put_f32(&mut out, PLACEHOLDER_TRANSPARENCY);
    write_words(&mut out, &[PLACEHOLDER_COLOR]);
    let mut info = [0u8; 88];
    let text = b"written by tress";
    info[..text.len()].copy_from_slice(text);
    out.extend_from_slice(&info);

    if with_segments {
        for count in asset.vertex_counts() {
            // count is in 1..=65536 here, so count - 1 fits a u16.
            out.extend_from_slice(&((count - 1) as u16).to_le_bytes());
        }
    }
    write_words(&mut out, asset.positions());
    if let Some(t) = asset.thickness() {
        write_words(&mut out, t);
    }
    if let Some(t) = asset.transparency() {
        write_words(&mut out, t);
    }
    if let Some(c) = asset.color() {
        write_words(&mut out, c);
    }
    debug_assert_eq!(out.len(), len);
    Ok(out)
}
