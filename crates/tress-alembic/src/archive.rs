//! The Alembic layer on Ogawa: the archive's root, objects, their compound properties and the
//! first sample of scalar and array properties.
//!
//! # Layout
//!
//! From the Alembic sources (`lib/Alembic/AbcCoreOgawa/ArImpl.cpp`, `OrData.cpp`, `CprData.cpp`,
//! `ReadUtil.cpp`); checked against files written by the Alembic library itself
//! (`crates/tress-hair/tests/data/make_abc.py`).
//!
//! - Root group: data 0 archive version (`i32`), data 1 library version (`i32`), group 2 the
//!   top object, data 3 archive metadata, data 4 time samplings (per sampling a `u32` most
//!   samples, an `f64` time per cycle, a `u32` count of times a cycle and that many `f64` times;
//!   `WriteTimeSampling` in `WriteUtil.cpp`), data 5 indexed metadata (a list of `u8` length +
//!   text; index 0 is the empty metadata).
//! - Object group: group 0 its compound property, groups 1..n−1 its child objects, the last child
//!   the data of the child objects' headers: per child a `u32` name length, the name, a `u8`
//!   metadata index (`0xff`: a `u32` length and the metadata text follow); then 32 bytes of hashes.
//! - Compound property group: one group per sub-property, the last child the data of their headers:
//!   per property a `u32` info word (bits 0–1 kind: 0 compound, 1 scalar, 2 array; 2–3 the width
//!   of the sizes that follow: 1, 2 or 4 bytes; 4–7 POD type; 8 has a time sampling index; 9 has
//!   first/last changed indices; 11 constant; 12–19 extent; 20–27 metadata index), then for
//!   scalar and array properties the sample count, the first/last changed indices if bit 9, the
//!   time sampling index if bit 8; then the name length, the name, and the metadata if its index
//!   is `0xff`.
//! - Scalar property group: one data block per stored sample. Array property group: two per
//!   sample, the values and their dimensions (empty: one dimension, from the values' size).
//!   Every non-empty sample block starts with a 16-byte digest before the values.
//!
//! One sample of a property is read: the first, or for `P` the one asked for
//! ([`crate::read_frame`]; Alembic stores sample 0, then the changed samples
//! `first..=last`, and the rest repeat one of those).
//!
//! # Validation
//!
//! Every group is visited at most once ([`Reader::enter`]), so a file whose offsets form a cycle
//! or share a group is rejected instead of recursing forever; object nesting is limited to
//! [`MAX_DEPTH`]. Sizes come from the data blocks, which the Ogawa layer has already checked
//! against the file, so nothing is allocated beyond what the file holds.

use std::collections::HashSet;

use crate::AlembicError;
use crate::ogawa::{Child, Group, Ogawa};

/// Deepest object nesting read.
pub(crate) const MAX_DEPTH: usize = 256;
const DIGEST_LEN: usize = 16;
const HASHES_LEN: usize = 32;

fn malformed(reason: impl Into<String>) -> AlembicError {
    AlembicError::Malformed(reason.into())
}

/// Alembic's plain-old-data types, in the file's numbering.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Pod {
    Bool,
    U8,
    I8,
    U16,
    I16,
    U32,
    I32,
    U64,
    I64,
    F16,
    F32,
    F64,
    String,
    WString,
}

impl Pod {
    fn from_code(code: u32) -> Result<Pod, AlembicError> {
        use Pod::*;
        Ok(match code {
            0 => Bool,
            1 => U8,
            2 => I8,
            3 => U16,
            4 => I16,
            5 => U32,
            6 => I32,
            7 => U64,
            8 => I64,
            9 => F16,
            10 => F32,
            11 => F64,
            12 => String,
            13 => WString,
            other => return Err(malformed(format!("unknown POD type {other}"))),
        })
    }

    /// Bytes per element (strings: none fixed).
    pub(crate) fn size(self) -> Option<usize> {
        use Pod::*;
        match self {
            Bool | U8 | I8 => Some(1),
            U16 | I16 | F16 => Some(2),
            U32 | I32 | F32 => Some(4),
            U64 | I64 | F64 => Some(8),
            String | WString => None,
        }
    }
}

/// What kind of property a header describes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Kind {
    Compound,
    Scalar,
    Array,
}

/// A property's header.
#[derive(Clone, Debug)]
pub(crate) struct PropertyHeader {
    pub(crate) name: String,
    pub(crate) kind: Kind,
    pub(crate) pod: Pod,
    pub(crate) extent: usize,
    pub(crate) samples: u32,
    /// The index of its time sampling in the archive's table (0, the identity, when unsaid).
    pub(crate) time_sampling: u32,
    /// The first and last sample stored apart from sample 0 (Alembic stores sample 0, then
    /// `first..=last`; samples before `first` repeat sample 0, those after `last` repeat it).
    pub(crate) changed: (u32, u32),
    pub(crate) metadata: String,
}

impl PropertyHeader {
    /// Which stored sample holds sample `k` (Alembic's `ReadUtil` rule).
    pub(crate) fn stored(&self, k: u32) -> u32 {
        let (first, last) = self.changed;
        if (first == 0 && last == 0) || k < first || first > last {
            0
        } else if k >= last {
            last - first + 1
        } else {
            k - first + 1
        }
    }
}

/// A time sampling of the archive's table: the times of a property's samples.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct TimeSampling {
    /// Seconds per cycle (Alembic's `AcyclicTimePerCycle`, `f64::MAX / 32`, for acyclic).
    pub(crate) time_per_cycle: f64,
    /// The sample times of the first cycle (every sample's, acyclic), seconds.
    pub(crate) times: Vec<f64>,
}

/// Alembic's time per cycle of an acyclic sampling (`TimeSamplingType::AcyclicTimePerCycle`).
const ACYCLIC_TIME_PER_CYCLE: f64 = f64::MAX / 32.0;

impl TimeSampling {
    /// The mean seconds between samples: the cycle over its times (uniform: the cycle; cyclic:
    /// the cycle over its count), or acyclic the span of the times over their gaps. `None`
    /// where that is not a positive finite number (an acyclic sampling of one time).
    pub(crate) fn seconds_per_sample(&self) -> Option<f64> {
        let n = self.times.len();
        let s = if self.time_per_cycle >= ACYCLIC_TIME_PER_CYCLE {
            let (first, last) = (self.times.first()?, self.times.last()?);
            (last - first) / n.checked_sub(1).filter(|&g| g > 0)? as f64
        } else {
            self.time_per_cycle / n.max(1) as f64
        };
        (s.is_finite() && s > 0.0).then_some(s)
    }
}

/// The archive's time samplings (root data 4). A table that does not parse reads as empty: the
/// times only give a cache its rate, so a damaged table costs that, not the file.
fn time_samplings(data: &[u8]) -> Vec<TimeSampling> {
    let mut cursor = Cursor {
        bytes: data,
        at: 0,
        what: "time samplings",
    };
    let mut table = Vec::new();
    while !cursor.done() {
        match time_sampling(&mut cursor) {
            Ok(t) => table.push(t),
            Err(_) => return Vec::new(),
        }
    }
    table
}

/// One entry of the time samplings, its times checked to be in the block before any is kept.
fn time_sampling(cursor: &mut Cursor<'_>) -> Result<TimeSampling, AlembicError> {
    cursor.u32()?;
    let time_per_cycle = cursor.f64()?;
    let n = cursor.u32()? as usize;
    let bytes = cursor.take(n.saturating_mul(8))?;
    let times = bytes
        .chunks_exact(8)
        .map(|b| f64::from_le_bytes([b[0], b[1], b[2], b[3], b[4], b[5], b[6], b[7]]))
        .collect();
    Ok(TimeSampling {
        time_per_cycle,
        times,
    })
}

/// An object's header (its name and metadata).
#[derive(Clone, Debug)]
pub(crate) struct ObjectHeader {
    pub(crate) name: String,
    pub(crate) metadata: String,
}

/// A compound property: its group and its sub-properties' headers.
#[derive(Clone, Debug)]
pub(crate) struct Compound<'a> {
    group: Group<'a>,
    pub(crate) headers: Vec<PropertyHeader>,
}

/// The value of `key` in Alembic metadata text (`key=value;key=value`).
pub(crate) fn meta_value<'m>(metadata: &'m str, key: &str) -> Option<&'m str> {
    metadata
        .split(';')
        .filter_map(|pair| pair.split_once('='))
        .find(|(k, _)| *k == key)
        .map(|(_, v)| v)
}

/// Reads objects and properties from an Ogawa file, visiting every group once.
pub(crate) struct Reader<'a> {
    pub(crate) ogawa: Ogawa<'a>,
    indexed_metadata: Vec<String>,
    visited: HashSet<u64>,
    /// The sample of `P` to read (0: the first).
    pub(crate) frame: u32,
    /// The archive's time samplings, by index.
    pub(crate) time_samplings: Vec<TimeSampling>,
}

/// A cursor over packed little-endian header bytes.
struct Cursor<'b> {
    bytes: &'b [u8],
    at: usize,
    what: &'static str,
}

impl<'b> Cursor<'b> {
    fn take(&mut self, n: usize) -> Result<&'b [u8], AlembicError> {
        let end = self.at.checked_add(n).filter(|&e| e <= self.bytes.len());
        let end = end.ok_or_else(|| {
            malformed(format!(
                "truncated {}: {n} more bytes wanted at byte {} of {}",
                self.what,
                self.at,
                self.bytes.len()
            ))
        })?;
        let s = &self.bytes[self.at..end];
        self.at = end;
        Ok(s)
    }

    fn u8(&mut self) -> Result<u8, AlembicError> {
        Ok(self.take(1)?[0])
    }

    fn u32(&mut self) -> Result<u32, AlembicError> {
        let b = self.take(4)?;
        Ok(u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
    }

    fn f64(&mut self) -> Result<f64, AlembicError> {
        let b = self.take(8)?;
        Ok(f64::from_le_bytes([
            b[0], b[1], b[2], b[3], b[4], b[5], b[6], b[7],
        ]))
    }

    /// A size of the width the header's size hint gives (0: u8, 1: u16, 2: u32).
    fn size(&mut self, hint: u32) -> Result<u32, AlembicError> {
        match hint {
            0 => Ok(u32::from(self.u8()?)),
            1 => {
                let b = self.take(2)?;
                Ok(u32::from(u16::from_le_bytes([b[0], b[1]])))
            }
            _ => self.u32(),
        }
    }

    fn text(&mut self, n: usize) -> Result<String, AlembicError> {
        let b = self.take(n)?;
        String::from_utf8(b.to_vec()).map_err(|_| malformed(format!("{} is not UTF-8", self.what)))
    }

    fn done(&self) -> bool {
        self.at >= self.bytes.len()
    }
}

impl<'a> Reader<'a> {
    /// Check the root group and read the indexed metadata.
    pub(crate) fn new(ogawa: Ogawa<'a>) -> Result<Self, AlembicError> {
        let root = ogawa.root()?;
        let kinds_ok = root.len() >= 6
            && matches!(root.child(2), Some(Child::Group(_)))
            && [0, 1, 3, 4, 5]
                .iter()
                .all(|&i| matches!(root.child(i), Some(Child::Data(_))));
        if !kinds_ok {
            return Err(malformed(format!(
                "the root group has {} children, not Alembic's versions, top object, metadata, \
                 time samplings and indexed metadata",
                root.len()
            )));
        }
        let table = ogawa.child_data(&root, 5, "indexed metadata")?;
        let mut cursor = Cursor {
            bytes: table,
            at: 0,
            what: "indexed metadata",
        };
        let mut indexed_metadata = vec![String::new()];
        while !cursor.done() {
            let n = cursor.u8()? as usize;
            indexed_metadata.push(cursor.text(n)?);
        }
        let time_samplings = time_samplings(ogawa.child_data(&root, 4, "time samplings")?);
        let mut visited = HashSet::new();
        visited.insert(root.offset);
        Ok(Reader {
            ogawa,
            indexed_metadata,
            visited,
            frame: 0,
            time_samplings,
        })
    }

    /// The top object's group.
    pub(crate) fn top(&mut self) -> Result<Group<'a>, AlembicError> {
        let root = self.ogawa.root()?;
        let top = self.ogawa.child_group(&root, 2, "top object")?;
        self.enter(top)
    }

    /// Mark a group visited; a second visit means a cycle or a shared group.
    fn enter(&mut self, group: Group<'a>) -> Result<Group<'a>, AlembicError> {
        if group.offset != 0 && !self.visited.insert(group.offset) {
            return Err(malformed(format!(
                "the group at byte {} is reached twice (a cycle in the file's offsets)",
                group.offset
            )));
        }
        Ok(group)
    }

    fn metadata(
        &self,
        index: u32,
        cursor: &mut Cursor<'_>,
        hint: u32,
    ) -> Result<String, AlembicError> {
        if index == 0xff {
            let n = cursor.size(hint)? as usize;
            return cursor.text(n);
        }
        self.indexed_metadata
            .get(index as usize)
            .cloned()
            .ok_or_else(|| malformed(format!("metadata index {index} is not in the table")))
    }

    /// An object's child objects: their headers and groups, in order.
    pub(crate) fn children(
        &mut self,
        object: &Group<'a>,
    ) -> Result<Vec<(ObjectHeader, Group<'a>)>, AlembicError> {
        let n = object.len();
        if n < 2 || !matches!(object.child(n - 1), Some(Child::Data(_))) {
            return Ok(Vec::new());
        }
        let data = self.ogawa.child_data(object, n - 1, "object headers")?;
        let body = &data[..data.len().saturating_sub(HASHES_LEN)];
        let mut cursor = Cursor {
            bytes: body,
            at: 0,
            what: "object headers",
        };
        let mut headers = Vec::new();
        while !cursor.done() {
            let len = cursor.u32()? as usize;
            let name = cursor.text(len)?;
            let index = u32::from(cursor.u8()?);
            let metadata = if index == 0xff {
                let len = cursor.u32()? as usize;
                cursor.text(len)?
            } else {
                self.metadata(index, &mut cursor, 2)?
            };
            headers.push(ObjectHeader { name, metadata });
        }
        if headers.len() != n - 2 {
            return Err(malformed(format!(
                "an object lists {} child headers for {} child groups",
                headers.len(),
                n - 2
            )));
        }
        headers
            .into_iter()
            .enumerate()
            .map(|(i, h)| {
                let g = self.ogawa.child_group(object, i + 1, "child object")?;
                Ok((h, self.enter(g)?))
            })
            .collect()
    }

    /// An object's own compound property (its first child), or none.
    pub(crate) fn properties(
        &mut self,
        object: &Group<'a>,
    ) -> Result<Option<Compound<'a>>, AlembicError> {
        match object.child(0) {
            Some(Child::Group(offset)) => {
                let g = self.ogawa.group(offset)?;
                Ok(Some(self.compound(g)?))
            }
            _ => Ok(None),
        }
    }

    /// A compound property from its group.
    fn compound(&mut self, group: Group<'a>) -> Result<Compound<'a>, AlembicError> {
        let group = self.enter(group)?;
        let n = group.len();
        if n == 0 || !matches!(group.child(n - 1), Some(Child::Data(_))) {
            return Ok(Compound {
                group,
                headers: Vec::new(),
            });
        }
        let data = self.ogawa.child_data(&group, n - 1, "property headers")?;
        let mut cursor = Cursor {
            bytes: data,
            at: 0,
            what: "property headers",
        };
        let mut headers = Vec::new();
        while !cursor.done() {
            let info = cursor.u32()?;
            let kind = match info & 0x3 {
                0 => Kind::Compound,
                1 => Kind::Scalar,
                _ => Kind::Array,
            };
            let hint = (info >> 2) & 0x3;
            let meta_index = (info >> 20) & 0xff;
            let (mut pod, mut extent, mut samples, mut changed) = (Pod::U8, 1, 0, (0, 0));
            let mut time_sampling = 0;
            if kind != Kind::Compound {
                pod = Pod::from_code((info >> 4) & 0xf)?;
                extent = ((info >> 12) & 0xff) as usize;
                samples = cursor.size(hint)?;
                changed = (1, samples.saturating_sub(1));
                if info & 0x200 != 0 {
                    changed = (cursor.size(hint)?, cursor.size(hint)?);
                }
                if info & 0x800 != 0 {
                    changed = (0, 0);
                }
                if info & 0x100 != 0 {
                    time_sampling = cursor.size(hint)?;
                }
            }
            let len = cursor.size(hint)? as usize;
            let name = cursor.text(len)?;
            let metadata = self.metadata(meta_index, &mut cursor, hint)?;
            headers.push(PropertyHeader {
                name,
                kind,
                pod,
                extent,
                samples,
                time_sampling,
                changed,
                metadata,
            });
        }
        if headers.len() != n - 1 {
            return Err(malformed(format!(
                "a compound property lists {} headers for {} property groups",
                headers.len(),
                n - 1
            )));
        }
        Ok(Compound { group, headers })
    }

    /// Sub-property `name` of a compound: its header and index.
    pub(crate) fn find<'c>(
        compound: &'c Compound<'a>,
        name: &str,
    ) -> Option<(usize, &'c PropertyHeader)> {
        compound
            .headers
            .iter()
            .enumerate()
            .find(|(_, h)| h.name == name)
    }

    /// The compound sub-property `name`, if there is one.
    pub(crate) fn sub_compound(
        &mut self,
        compound: &Compound<'a>,
        name: &str,
    ) -> Result<Option<Compound<'a>>, AlembicError> {
        let Some((i, h)) = Self::find(compound, name) else {
            return Ok(None);
        };
        if h.kind != Kind::Compound {
            return Err(malformed(format!("property {name} is not a compound")));
        }
        let g = self.ogawa.child_group(&compound.group, i, name)?;
        Ok(Some(self.compound(g)?))
    }

    /// The raw bytes of the first sample of scalar or array property `index` (digest removed),
    /// checked to be whole elements of its POD and extent.
    pub(crate) fn first_sample(
        &mut self,
        compound: &Compound<'a>,
        index: usize,
    ) -> Result<&'a [u8], AlembicError> {
        self.sample(compound, index, 0)
    }

    /// The raw bytes of sample `k` of scalar or array property `index` (digest removed; a
    /// sample past the last is the last), checked as [`Reader::first_sample`] checks.
    pub(crate) fn sample(
        &mut self,
        compound: &Compound<'a>,
        index: usize,
        k: u32,
    ) -> Result<&'a [u8], AlembicError> {
        let h = &compound.headers[index];
        let g = self.ogawa.child_group(&compound.group, index, &h.name)?;
        let g = self.enter(g)?;
        if h.samples == 0 || g.len() == 0 {
            return Ok(&[]);
        }
        let stored = h.stored(k.min(h.samples - 1)) as usize;
        let child = if h.kind == Kind::Array {
            2 * stored
        } else {
            stored
        };
        if child >= g.len() {
            return Err(malformed(format!(
                "{} has {} samples but stores {} groups, too few for sample {k}",
                h.name,
                h.samples,
                g.len()
            )));
        }
        let data = self.ogawa.child_data(&g, child, &h.name)?;
        if data.is_empty() {
            return Ok(&[]);
        }
        if data.len() < DIGEST_LEN {
            return Err(malformed(format!(
                "the sample of {} has {} bytes, fewer than its 16-byte digest",
                h.name,
                data.len()
            )));
        }
        let values = &data[DIGEST_LEN..];
        if let Some(size) = h.pod.size() {
            let element = size * h.extent.max(1);
            if values.len() % element != 0 {
                return Err(malformed(format!(
                    "the sample of {} has {} bytes, not a whole number of {element}-byte elements",
                    h.name,
                    values.len()
                )));
            }
        }
        Ok(values)
    }
}

#[cfg(test)]
mod tests {
    use super::{ACYCLIC_TIME_PER_CYCLE, TimeSampling, meta_value, time_samplings};

    #[test]
    fn metadata_values() {
        let m = "schema=AbcGeom_Curve_v2;schemaObjTitle=AbcGeom_Curve_v2:.geom";
        assert_eq!(meta_value(m, "schema"), Some("AbcGeom_Curve_v2"));
        assert_eq!(meta_value(m, "geoScope"), None);
        assert_eq!(meta_value("", "x"), None);
    }

    /// The table as Alembic writes it: most samples, time per cycle, count, times.
    fn table(entries: &[(f64, &[f64])]) -> Vec<u8> {
        let mut b = Vec::new();
        for (tpc, times) in entries {
            b.extend_from_slice(&9u32.to_le_bytes());
            b.extend_from_slice(&tpc.to_le_bytes());
            b.extend_from_slice(&(times.len() as u32).to_le_bytes());
            for t in *times {
                b.extend_from_slice(&t.to_le_bytes());
            }
        }
        b
    }

    #[test]
    fn time_samplings_give_the_seconds_between_samples() {
        let acyclic = ACYCLIC_TIME_PER_CYCLE;
        let bytes = table(&[
            (1.0, &[0.0]),
            (0.04, &[0.04]),
            (0.1, &[0.0, 0.02, 0.07, 0.08]),
            (acyclic, &[1.0, 1.5, 2.5]),
            (acyclic, &[3.0]),
        ]);
        let t = time_samplings(&bytes);
        let spacing: Vec<Option<f64>> = t.iter().map(TimeSampling::seconds_per_sample).collect();
        assert_eq!(
            spacing,
            [Some(1.0), Some(0.04), Some(0.025), Some(0.75), None]
        );
        // A table cut short reads as none (the file still reads; only the rate is lost).
        assert!(time_samplings(&bytes[..bytes.len() - 3]).is_empty());
        assert!(time_samplings(&[]).is_empty());
    }
}
