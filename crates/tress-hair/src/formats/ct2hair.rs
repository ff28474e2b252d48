//! CT2Hair `.bin` (Shen et al. 2023, "CT2Hair: High-Fidelity 3D Hair Modeling using Computed
//! Tomography"): the strands its pipeline writes and its released models use.
//!
//! # Layout
//!
//! Little-endian, no header or magic: an `i32` strand count, then per strand an `i32` point
//! count and per point seven `f32`: the position `x, y, z` and four more values (CT2Hair's
//! per-point attributes, written as zeros by tools that have none), which tress ignores.
//!
//! # Validation
//!
//! As for `.data`: the strand count against the file's size, each point count against the bytes
//! left, before any allocation; bytes after the last strand are an error. Strands of a single
//! point are kept (they are valid, if invisible, strands).

use glam::Vec3;

use super::bytes::in_format;
use crate::{HairAsset, HairError};

const FORMAT: &str = "CT2Hair .bin";
const POINT: usize = 28;

fn err(reason: impl Into<String>) -> HairError {
    HairError::format(FORMAT, reason)
}

fn i32_at(bytes: &[u8], at: usize) -> Option<i32> {
    Some(i32::from_le_bytes(bytes.get(at..at + 4)?.try_into().ok()?))
}

/// Read a CT2Hair `.bin` file from memory (see the [module docs](self)).
pub fn read_ct2hair(bytes: &[u8]) -> Result<HairAsset, HairError> {
    let strands = i32_at(bytes, 0)
        .ok_or_else(|| err(format!("truncated: {} bytes, no strand count", bytes.len())))?;
    let room = (bytes.len() as u64 - 4) / 4;
    if strands <= 0 || strands as u64 > room {
        return Err(err(format!(
            "the file says {strands} strands but its {} bytes hold 1 to {room}",
            bytes.len()
        )));
    }
    let mut at = 4usize;
    let mut counts = Vec::with_capacity(strands as usize);
    let mut total = 0usize;
    for i in 0..strands as usize {
        let n = i32_at(bytes, at).ok_or_else(|| {
            err(format!(
                "truncated: strand {i} of {strands} has no point count"
            ))
        })?;
        let left = (bytes.len() - at - 4) as u64 / POINT as u64;
        if n <= 0 || n as u64 > left {
            return Err(err(format!(
                "strand {i} says {n} points but the file has room for 1 to {left} more"
            )));
        }
        at += 4 + POINT * n as usize;
        total += n as usize;
        counts.push(n as u32);
    }
    if at != bytes.len() {
        return Err(err(format!(
            "{} bytes follow the last strand (not a CT2Hair .bin file?)",
            bytes.len() - at
        )));
    }
    let mut positions = Vec::with_capacity(total);
    let mut at = 4usize;
    for &n in &counts {
        at += 4;
        for p in bytes[at..at + POINT * n as usize].as_chunks::<POINT>().0 {
            let f = |k: usize| f32::from_le_bytes([p[k], p[k + 1], p[k + 2], p[k + 3]]);
            positions.push(Vec3::new(f(0), f(4), f(8)));
        }
        at += POINT * n as usize;
    }
    HairAsset::from_counts(positions, &counts).map_err(in_format(FORMAT))
}
