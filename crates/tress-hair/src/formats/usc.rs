//! USC-HairSalon `.data` (Hu et al. 2015, "Single-view hair modeling using a hairstyle
//! database"; also the format of Hair Photobooth, Paris et al. 2008).
//!
//! # Layout
//!
//! Little-endian, no header or magic: an `i32` strand count, then per strand an `i32` vertex
//! count and that many `[f32; 3]` positions. The dataset's scalp grid has strands of a single
//! vertex (roots where no hair grows); they carry no segment and are skipped, and the count of
//! skipped strands is returned ([`DataInfo::single_vertex_skipped`], shown by `tress info`).
//!
//! # Validation
//!
//! The strand count is checked against the file's size (every strand needs at least 4 bytes)
//! and every vertex count against the bytes left, before anything is allocated; a file with
//! bytes after the last strand is refused (it is not this format).

use glam::Vec3;

use super::bytes::{in_format, put_u32, read_vec3s, write_words};
use crate::{HairAsset, HairError};

const FORMAT: &str = ".data";

/// What a read skipped.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct DataInfo {
    /// Strands of a single vertex, left out.
    pub single_vertex_skipped: usize,
}

fn err(reason: impl Into<String>) -> HairError {
    HairError::format(FORMAT, reason)
}

fn i32_at(bytes: &[u8], at: usize) -> Option<i32> {
    Some(i32::from_le_bytes(bytes.get(at..at + 4)?.try_into().ok()?))
}

/// Read a `.data` file from memory (see the [module docs](self)).
pub fn read_data(bytes: &[u8]) -> Result<(HairAsset, DataInfo), HairError> {
    let strands = i32_at(bytes, 0)
        .ok_or_else(|| err(format!("truncated: {} bytes, no strand count", bytes.len())))?;
    let room = (bytes.len() as u64 - 4) / 4;
    if strands < 0 || strands as u64 > room {
        return Err(err(format!(
            "the file says {strands} strands but its {} bytes hold at most {room}",
            bytes.len()
        )));
    }
    // First pass: validate every count against the bytes and size the arrays exactly.
    let mut at = 4usize;
    let mut counts = Vec::with_capacity(strands as usize);
    let mut kept_vertices = 0usize;
    let mut info = DataInfo::default();
    for i in 0..strands as usize {
        let n = i32_at(bytes, at).ok_or_else(|| {
            err(format!(
                "truncated: strand {i} of {strands} has no vertex count"
            ))
        })?;
        let left = (bytes.len() - at - 4) as u64 / 12;
        if n < 0 || n as u64 > left {
            return Err(err(format!(
                "strand {i} says {n} vertices but the file has room for {left} more"
            )));
        }
        at += 4 + 12 * n as usize;
        match n {
            0 => return Err(err(format!("strand {i} has no vertices"))),
            1 => info.single_vertex_skipped += 1,
            _ => kept_vertices += n as usize,
        }
        counts.push(n as u32);
    }
    if at != bytes.len() {
        return Err(err(format!(
            "{} bytes follow the last strand (not a .data file?)",
            bytes.len() - at
        )));
    }
    let mut positions = Vec::with_capacity(kept_vertices);
    let mut kept = Vec::with_capacity(counts.len() - info.single_vertex_skipped);
    let mut at = 4usize;
    for &n in &counts {
        let len = 12 * n as usize;
        if n > 1 {
            positions.extend(read_vec3s(&bytes[at + 4..at + 4 + len]));
            kept.push(n);
        }
        at += 4 + len;
    }
    if kept.is_empty() {
        return Err(err(format!(
            "no strand has two vertices ({} single-vertex strands)",
            info.single_vertex_skipped
        )));
    }
    let asset = HairAsset::from_counts(positions, &kept).map_err(in_format(FORMAT))?;
    Ok((asset, info))
}

/// Write an asset as `.data` (positions only: the format has no other arrays).
pub fn write_data(asset: &HairAsset) -> Result<Vec<u8>, HairError> {
    let strands = i32::try_from(asset.strand_count()).map_err(|_| err("more than 2^31 strands"))?;
    let mut out = Vec::with_capacity(4 + 4 * asset.strand_count() + 12 * asset.vertex_count());
    out.extend_from_slice(&strands.to_le_bytes());
    for s in asset.strands() {
        put_u32(&mut out, s.len() as u32);
        write_words::<Vec3>(&mut out, s);
    }
    Ok(out)
}
