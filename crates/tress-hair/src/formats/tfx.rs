//! AMD TressFX `.tfx` files, versions 3.x (read) and 4.x (read and write).
//!
//! A `.tfx` file holds guide strands that all have the same vertex count. Arrays sit at byte
//! offsets given in the header (0 means absent); all numbers are little-endian. The file has no
//! magic number: the version float at byte 0 tells the layouts apart. tress accepts any version in
//! `[3, 4)` as 3.x and any in `[4, 5)` as 4.x; AMD's own loaders compare with exactly 3 and 4.
//!
//! # TressFX 4.x: `TressFXTFXFileHeader`, 160 bytes
//!
//! From `src/TressFX/TressFXFileFormat.h` of AMD's TressFX 4.x
//! (<https://github.com/GPUOpen-Effects/TressFX>), confirmed by the 4.x Maya exporter
//! (`SaveTFXBinaryFile` writes version 4.0 and positions at offset 160) and by the loader
//! `TressFXAsset::LoadV4`.
//!
//! | bytes | type | field | array at the offset |
//! | --- | --- | --- | --- |
//! | 0..4 | `f32` | `version` (4.0) | |
//! | 4..8 | `u32` | `numHairStrands` | |
//! | 8..12 | `u32` | `numVerticesPerStrand` | |
//! | 12..16 | `u32` | `offsetVertexPosition` | `[f32; 4]` per vertex: xyz, w = inverse mass |
//! | 16..20 | `u32` | `offsetStrandUV` | `[f32; 2]` per strand |
//! | 20..24 | `u32` | `offsetVertexUV` | `[f32; 2]` per vertex |
//! | 24..28 | `u32` | `offsetStrandThickness` | `f32` per strand |
//! | 28..32 | `u32` | `offsetVertexColor` | `[f32; 4]` per vertex |
//! | 32..160 | `[u32; 32]` | `reserved` | |
//!
//! # TressFX 3.x: `TressFXFileObject`, 296 bytes
//!
//! From `amd_tressfx/src/TressFXFileFormat.h` of AMD's TressFX 3.0 (same repository, older
//! history), confirmed by the 3.0 Maya exporter (writes version 3.0, `[f32; 3]` points at offset
//! `sizeof(TressFXFileObject)`) and by the 3.0 loader `TressFXAssetLoader::LoadAppend`, which reads
//! three floats per vertex.
//!
//! | bytes | type | field | array at the offset |
//! | --- | --- | --- | --- |
//! | 0..4 | `f32` | `version` (3.0) | |
//! | 4..8 | `u32` | `numGuideHairStrands` | |
//! | 8..12 | `u32` | `numVerticesPerStrand` | |
//! | 12..16 | `u32` | `numFollowHairsPerGuideHair` | |
//! | 16..20 | `u32` | `bothEndsImmovable` (a BOOL; ignored) | |
//! | 20..144 | `[u32; 31]` | `reserved1` | |
//! | 144..148 | `u32` | `verticesOffset` | `[f32; 3]` per vertex |
//! | 148..152 | `u32` | `perStrandThicknessOffset` | `f32` per strand |
//! | 152..156 | `u32` | `perStrandTexCoordOffset` | `[f32; 2]` per strand |
//! | 156..160 | `u32` | `perVertexColorOffset` | `[f32; 4]` per vertex |
//! | 160..164 | `u32` | `guideHairStrandOffset` | `u32` per strand |
//! | 164..168 | `u32` | `perVertexTexCoordOffset` | `[f32; 2]` per vertex |
//! | 168..296 | `[u32; 32]` | `reserved2` | |
//!
//! Not verified: the header comments say the per-vertex color is `FLOAT4`, but no AMD exporter
//! or loader we could read writes or reads it (nor the 3.x per-strand thickness, guide flags and
//! per-vertex UVs), so their meaning beyond the element type is unconfirmed.
//!
//! # What tress reads
//!
//! - Positions (required; offset 0 or an offset inside the header is an error). The 4.x `w`
//!   (inverse mass: 0 for pinned vertices) is ignored.
//! - Strand UVs into [`HairAsset::strand_uv`].
//! - Per-vertex color: its first three components into [`HairAsset::color`]; the fourth is ignored.
//! - Ignored, not even bounds-checked (AMD's loaders never read them either): per-vertex UVs,
//!   per-strand thickness (its unit, world width or a multiplier, is not documented), and the 3.x
//!   guide flags.
//! - 3.x `numFollowHairsPerGuideHair` is honoured: [`read_tfx`] generates that many followers per
//!   guide with [`HairAsset::with_follow_hairs`] and [`FollowParams::default`]'s mode, radius and
//!   tip separation (interpolated between guides, the radius derived from the guides' root
//!   spacing; the file stores neither: AMD's runtimes take them from their settings, and the 3.0
//!   loader even replaces the file's count with its own). At most 64 followers per guide are
//!   accepted, so a 4-byte header value cannot blow a small file up into gigabytes.
//!   [`parse_tfx`] returns the guides and the count without generating anything.
//! - AMD's runtimes pad the strand count to a multiple of 64 at load time; that is a GPU concern
//!   and tress does not do it.
//!
//! # What tress writes
//!
//! [`write_tfx`] writes 4.x: positions at offset 160 with `w` = 0 for the first two vertices of
//! each strand and 1 for the others (as AMD's exporters do), then the strand UVs and the vertex
//! colors (alpha 1) when the asset has them. Every array starts on an 8-byte boundary, as the
//! header comments require. TressFX stores one vertex count for all strands, so an asset whose
//! strands differ in length is an error (resample it first). Thickness and transparency have no
//! place in the format and are not written. AMD's runtime additionally requires 4, 8, 16, 32 or 64
//! vertices per strand; tress reads and writes any count, so check that before handing a file to
//! TressFX itself.

use super::bytes::{
    array, in_format, put_f32, put_u32, read_vec2s, read_vec3s, read_xyz_of_vec4s, u32_at,
    write_words,
};
use crate::{FollowParams, HairAsset, HairError};

const FORMAT: &str = ".tfx";

/// Size of the TressFX 4.x header in bytes.
pub const HEADER_LEN_V4: usize = 160;
/// Size of the TressFX 3.x header in bytes.
pub const HEADER_LEN_V3: usize = 296;
/// Most follow hairs per guide that a 3.x file may ask for.
pub const MAX_FOLLOW_HAIRS_PER_GUIDE: u32 = 64;

/// The two `.tfx` layouts.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum TfxVersion {
    /// TressFX 3.x: 296-byte header, `[f32; 3]` positions, follow-hair count in the header.
    V3,
    /// TressFX 4.x: 160-byte header, `[f32; 4]` positions.
    V4,
}

/// A parsed `.tfx` file: its guide strands, before any follow hairs are generated.
#[derive(Clone, Debug, PartialEq)]
pub struct TfxFile {
    /// Which layout the file used.
    pub version: TfxVersion,
    /// The guide strands with the attributes the file holds.
    pub guides: HairAsset,
    /// Follow hairs per guide the file asks for (3.x only; 0 for 4.x).
    pub follow_hairs_per_guide: u32,
}

fn err(reason: impl Into<String>) -> HairError {
    HairError::format(FORMAT, reason)
}

/// Read a `.tfx` file (3.x or 4.x) from memory, generating the follow hairs a 3.x file asks for.
pub fn read_tfx(bytes: &[u8]) -> Result<HairAsset, HairError> {
    let file = parse_tfx(bytes)?;
    if file.follow_hairs_per_guide == 0 {
        return Ok(file.guides);
    }
    let params = FollowParams {
        count: file.follow_hairs_per_guide,
        ..FollowParams::default()
    };
    file.guides.with_follow_hairs(&params)
}

/// Parse a `.tfx` file (3.x or 4.x) into its guide strands and follow-hair count.
pub fn parse_tfx(bytes: &[u8]) -> Result<TfxFile, HairError> {
    let Some(head) = bytes.first_chunk::<4>() else {
        return Err(err(format!(
            "truncated: the file has {} bytes, too few for a TressFX header",
            bytes.len()
        )));
    };
    let version = f32::from_le_bytes(*head);
    if (3.0..4.0).contains(&version) {
        parse_v3(bytes)
    } else if (4.0..5.0).contains(&version) {
        parse_v4(bytes)
    } else {
        Err(err(format!(
            "unsupported TressFX version {version} (tress reads 3.x and 4.x)"
        )))
    }
}

/// Header fields common to both layouts, in the order they are used.
struct Layout<'a> {
    header_len: usize,
    strands: u32,
    vertices_per_strand: u32,
    positions: u32,
    position_stride: u64,
    strand_uv: u32,
    vertex_color: u32,
    bytes: &'a [u8],
}

fn parse_v4(bytes: &[u8]) -> Result<TfxFile, HairError> {
    let h = header::<HEADER_LEN_V4>(bytes, "4.x")?;
    let guides = Layout {
        header_len: HEADER_LEN_V4,
        strands: u32_at(h, 4),
        vertices_per_strand: u32_at(h, 8),
        positions: u32_at(h, 12),
        position_stride: 16,
        strand_uv: u32_at(h, 16),
        vertex_color: u32_at(h, 28),
        bytes,
    }
    .read()?;
    Ok(TfxFile {
        version: TfxVersion::V4,
        guides,
        follow_hairs_per_guide: 0,
    })
}

fn parse_v3(bytes: &[u8]) -> Result<TfxFile, HairError> {
    let h = header::<HEADER_LEN_V3>(bytes, "3.x")?;
    let follow = u32_at(h, 12);
    if follow > MAX_FOLLOW_HAIRS_PER_GUIDE {
        return Err(err(format!(
            "numFollowHairsPerGuideHair is {follow}; tress accepts at most \
             {MAX_FOLLOW_HAIRS_PER_GUIDE}"
        )));
    }
    let guides = Layout {
        header_len: HEADER_LEN_V3,
        strands: u32_at(h, 4),
        vertices_per_strand: u32_at(h, 8),
        positions: u32_at(h, 144),
        position_stride: 12,
        strand_uv: u32_at(h, 152),
        vertex_color: u32_at(h, 156),
        bytes,
    }
    .read()?;
    Ok(TfxFile {
        version: TfxVersion::V3,
        guides,
        follow_hairs_per_guide: follow,
    })
}

fn header<'a, const N: usize>(bytes: &'a [u8], version: &str) -> Result<&'a [u8; N], HairError> {
    bytes.first_chunk::<N>().ok_or_else(|| {
        err(format!(
            "truncated: the file has {} bytes, fewer than the {N}-byte TressFX {version} header",
            bytes.len()
        ))
    })
}

impl Layout<'_> {
    fn read(&self) -> Result<HairAsset, HairError> {
        let (s, vps) = (self.strands, self.vertices_per_strand);
        if s == 0 {
            return Err(err("the file has no strands (its strand count is 0)"));
        }
        if vps == 0 {
            return Err(err("the file has 0 vertices per strand"));
        }
        let vertices = u64::from(s) * u64::from(vps);
        if vertices > u64::from(u32::MAX) {
            return Err(err(format!(
                "{s} strands of {vps} vertices is more than 2^32 vertices"
            )));
        }
        if self.positions == 0 {
            return Err(err("the file has no vertex positions (their offset is 0)"));
        }

        // Locate every array before allocating anything: each must fit in the file.
        let positions = self.array(
            "vertex positions",
            self.positions,
            vertices * self.position_stride,
        )?;
        let strand_uv = self.optional("strand UVs", self.strand_uv, u64::from(s) * 8)?;
        let color = self.optional("vertex colors", self.vertex_color, vertices * 16)?;

        let positions = if self.position_stride == 12 {
            read_vec3s(positions)
        } else {
            read_xyz_of_vec4s(positions)
        };
        let offsets = (0..=u64::from(s))
            .map(|i| (i * u64::from(vps)) as u32)
            .collect();
        let mut asset = HairAsset::from_offsets(positions, offsets).map_err(in_format(FORMAT))?;
        if let Some(uv) = strand_uv {
            asset = asset
                .with_strand_uv(read_vec2s(uv))
                .map_err(in_format(FORMAT))?;
        }
        if let Some(c) = color {
            asset = asset
                .with_color(read_xyz_of_vec4s(c))
                .map_err(in_format(FORMAT))?;
        }
        Ok(asset)
    }

    fn array(&self, what: &str, offset: u32, len: u64) -> Result<&[u8], HairError> {
        if (offset as usize) < self.header_len {
            return Err(err(format!(
                "the {what} offset {offset} points into the {}-byte header",
                self.header_len
            )));
        }
        array(FORMAT, self.bytes, what, u64::from(offset), len)
    }

    fn optional(&self, what: &str, offset: u32, len: u64) -> Result<Option<&[u8]>, HairError> {
        if offset == 0 {
            Ok(None)
        } else {
            self.array(what, offset, len).map(Some)
        }
    }
}

/// Write an asset as a TressFX 4.x `.tfx` file (see the [module docs](self) for what is
/// written). Fails when the strands do not all have the same vertex count.
pub fn write_tfx(asset: &HairAsset) -> Result<Vec<u8>, HairError> {
    let (min, max) = asset.vertices_per_strand_range();
    if min != max {
        return Err(err(format!(
            "TressFX stores one vertex count for all strands, but these strands have {min} to \
             {max} vertices; resample the asset to a fixed count first"
        )));
    }
    let n = asset.vertex_count();
    let strands = asset.strand_count();
    let too_many = |_| err("more than 2^32 bytes do not fit the 32-bit offsets of a .tfx file");
    let positions_at = HEADER_LEN_V4;
    let mut end = positions_at + 16 * n;
    let uv_at = asset.strand_uv().map(|_| end);
    end += uv_at.map_or(0, |_| 8 * strands);
    let color_at = asset.color().map(|_| end);
    end += color_at.map_or(0, |_| 16 * n);
    let offset = |at: Option<usize>| u32::try_from(at.unwrap_or(0)).map_err(too_many);
    let (uv_offset, color_offset) = (offset(uv_at)?, offset(color_at)?);
    u32::try_from(end).map_err(too_many)?;

    let mut out = Vec::with_capacity(end);
    put_f32(&mut out, 4.0);
    // strands <= vertices <= u32::MAX: strand offsets are u32.
    put_u32(&mut out, strands as u32);
    put_u32(&mut out, max);
    put_u32(&mut out, positions_at as u32);
    put_u32(&mut out, uv_offset);
    put_u32(&mut out, 0); // per-vertex UVs
    put_u32(&mut out, 0); // per-strand thickness
    put_u32(&mut out, color_offset);
    out.resize(HEADER_LEN_V4, 0); // reserved

    let vps = max as usize;
    for (i, p) in asset.positions().iter().enumerate() {
        let inverse_mass = if i % vps < 2 { 0.0 } else { 1.0 };
        write_words(&mut out, &[p.extend(inverse_mass)]);
    }
    if let Some(uv) = asset.strand_uv() {
        write_words(&mut out, uv);
    }
    if let Some(color) = asset.color() {
        for c in color {
            write_words(&mut out, &[c.extend(1.0)]);
        }
    }
    debug_assert_eq!(out.len(), end);
    Ok(out)
}
