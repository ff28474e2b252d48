//! The Ogawa container: a tree of groups and data blocks addressed by byte offsets.
//!
//! # Layout
//!
//! From the Alembic sources (`lib/Alembic/Ogawa/IArchive.cpp`, `IGroup.cpp`, `IData.cpp`). All
//! numbers are little-endian.
//!
//! | bytes | field |
//! | --- | --- |
//! | 0..5 | magic `"Ogawa"` |
//! | 5 | `0xff` once the writer finished ("frozen"), `0x00` while it was writing |
//! | 6..8 | file version, big-endian `u16`: 1 |
//! | 8..16 | `u64` offset of the root group |
//!
//! A group at offset `o` is a `u64` child count `n` and `n` `u64` children. A child whose top
//! bit is set is a data block, otherwise a group; the other 63 bits are its offset, where offset
//! 0 means an empty block or group. A data block is a `u64` byte count and the bytes.
//!
//! # Validation
//!
//! Every offset and size is checked against the file before anything is read or sized from it,
//! so a lying count can neither read past the end nor allocate: [`Group`] and data blocks are
//! borrowed slices of the file. Cycles are the caller's concern (the Alembic layer visits each
//! group once, see `archive.rs`).

use crate::AlembicError;

/// The 8-byte signature an HDF5 file starts with (HDF5 Alembic archives are HDF5 files).
pub(crate) const HDF5_MAGIC: &[u8; 8] = b"\x89HDF\r\n\x1a\n";
const MAGIC: &[u8; 5] = b"Ogawa";
const HEADER_LEN: usize = 16;
const DATA_BIT: u64 = 1 << 63;

/// One child of a group.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Child {
    /// A group at this offset (0: empty).
    Group(u64),
    /// A data block at this offset (0: empty).
    Data(u64),
}

/// A parsed Ogawa file: the bytes and the root group's offset.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Ogawa<'a> {
    bytes: &'a [u8],
    root: u64,
}

/// A group: its children, still encoded, borrowed from the file.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Group<'a> {
    /// The offset it was read from (0 for an empty group).
    pub(crate) offset: u64,
    children: &'a [u8],
}

fn malformed(reason: impl Into<String>) -> AlembicError {
    AlembicError::Malformed(reason.into())
}

impl<'a> Ogawa<'a> {
    /// Check the header; HDF5 files and other magics get their own errors.
    pub(crate) fn parse(bytes: &'a [u8]) -> Result<Self, AlembicError> {
        if bytes.starts_with(HDF5_MAGIC) {
            return Err(AlembicError::Hdf5);
        }
        let Some(header) = bytes.first_chunk::<HEADER_LEN>() else {
            return Err(
                if MAGIC.starts_with(&bytes[..bytes.len().min(5)]) && !bytes.is_empty() {
                    malformed(format!(
                        "truncated: {} bytes, fewer than the 16-byte Ogawa header",
                        bytes.len()
                    ))
                } else {
                    AlembicError::NotAlembic(format!("{} bytes and no Ogawa header", bytes.len()))
                },
            );
        };
        if &header[..5] != MAGIC {
            return Err(AlembicError::NotAlembic(format!(
                "it starts with \"{}\" instead of \"Ogawa\"",
                header[..5].escape_ascii()
            )));
        }
        let root = u64::from_le_bytes(header[8..16].try_into().unwrap_or_default());
        let ogawa = Ogawa { bytes, root };
        // The root must be a readable group.
        ogawa.group(root)?;
        Ok(ogawa)
    }

    /// The root group.
    pub(crate) fn root(&self) -> Result<Group<'a>, AlembicError> {
        self.group(self.root)
    }

    /// The `u64` at `offset`, if the file holds it.
    fn u64_at(&self, offset: u64, what: &str) -> Result<u64, AlembicError> {
        let start = usize::try_from(offset).ok();
        let word = start
            .and_then(|s| self.bytes.get(s..s.checked_add(8)?))
            .ok_or_else(|| {
                malformed(format!(
                    "truncated: the {what} at byte {offset} lies past the end of the {}-byte file",
                    self.bytes.len()
                ))
            })?;
        Ok(u64::from_le_bytes(word.try_into().unwrap_or_default()))
    }

    /// The group at `offset` (offset 0 is the empty group).
    pub(crate) fn group(&self, offset: u64) -> Result<Group<'a>, AlembicError> {
        if offset == 0 {
            return Ok(Group {
                offset,
                children: &[],
            });
        }
        let count = self.u64_at(offset, "group")?;
        let room = (self.bytes.len() as u64).saturating_sub(offset + 8) / 8;
        if count > room {
            return Err(malformed(format!(
                "the group at byte {offset} claims {count} children but the file has room for {room}"
            )));
        }
        let start = (offset + 8) as usize;
        Ok(Group {
            offset,
            children: &self.bytes[start..start + 8 * count as usize],
        })
    }

    /// The bytes of the data block at `offset` (offset 0 is the empty block).
    pub(crate) fn data(&self, offset: u64) -> Result<&'a [u8], AlembicError> {
        if offset == 0 {
            return Ok(&[]);
        }
        let size = self.u64_at(offset, "data block")?;
        let room = (self.bytes.len() as u64).saturating_sub(offset + 8);
        if size > room {
            return Err(malformed(format!(
                "truncated: the data block at byte {offset} claims {size} bytes but the file has {room} after it"
            )));
        }
        let start = (offset + 8) as usize;
        Ok(&self.bytes[start..start + size as usize])
    }

    /// The data block that is child `index` of `group`; an error if it is missing or a group.
    pub(crate) fn child_data(
        &self,
        group: &Group<'a>,
        index: usize,
        what: &str,
    ) -> Result<&'a [u8], AlembicError> {
        match group.child(index) {
            Some(Child::Data(offset)) => self.data(offset),
            Some(Child::Group(_)) => Err(malformed(format!("the {what} is a group, not data"))),
            None => Err(malformed(format!(
                "the {what} is missing (the group at byte {} has {} children)",
                group.offset,
                group.len()
            ))),
        }
    }

    /// The group that is child `index` of `group`; an error if it is missing or data.
    pub(crate) fn child_group(
        &self,
        group: &Group<'a>,
        index: usize,
        what: &str,
    ) -> Result<Group<'a>, AlembicError> {
        match group.child(index) {
            Some(Child::Group(offset)) => self.group(offset),
            Some(Child::Data(_)) => Err(malformed(format!("the {what} is data, not a group"))),
            None => Err(malformed(format!(
                "the {what} is missing (the group at byte {} has {} children)",
                group.offset,
                group.len()
            ))),
        }
    }
}

impl Group<'_> {
    /// Number of children.
    pub(crate) fn len(&self) -> usize {
        self.children.len() / 8
    }

    /// Child `index`, if there is one.
    pub(crate) fn child(&self, index: usize) -> Option<Child> {
        let word = self.children.get(index * 8..index * 8 + 8)?;
        let v = u64::from_le_bytes(word.try_into().ok()?);
        Some(if v & DATA_BIT != 0 {
            Child::Data(v & !DATA_BIT)
        } else {
            Child::Group(v)
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn file(root: u64, rest: &[u8]) -> Vec<u8> {
        let mut f = b"Ogawa\xff\x00\x01".to_vec();
        f.extend_from_slice(&root.to_le_bytes());
        f.extend_from_slice(rest);
        f
    }

    #[test]
    fn groups_and_data_are_checked_against_the_file() {
        // root group at 16: two children, a data block at 40 and an empty group
        let mut rest = Vec::new();
        rest.extend_from_slice(&2u64.to_le_bytes());
        rest.extend_from_slice(&(40u64 | DATA_BIT).to_le_bytes());
        rest.extend_from_slice(&0u64.to_le_bytes());
        rest.extend_from_slice(&3u64.to_le_bytes());
        rest.extend_from_slice(b"abc");
        let bytes = file(16, &rest);
        let o = Ogawa::parse(&bytes).unwrap();
        let root = o.root().unwrap();
        assert_eq!(root.len(), 2);
        assert_eq!(o.child_data(&root, 0, "x").unwrap(), b"abc");
        assert_eq!(o.child_group(&root, 1, "y").unwrap().len(), 0);
        assert!(o.child_group(&root, 0, "x").is_err());
        assert!(o.child_data(&root, 2, "z").is_err());

        let huge = file(16, &u64::MAX.to_le_bytes());
        assert!(
            Ogawa::parse(&huge)
                .unwrap_err()
                .to_string()
                .contains("claims")
        );
        let past = file(1 << 40, &[]);
        assert!(Ogawa::parse(&past).is_err());
    }

    #[test]
    fn magics() {
        assert!(matches!(
            Ogawa::parse(b"\x89HDF\r\n\x1a\n"),
            Err(AlembicError::Hdf5)
        ));
        assert!(matches!(
            Ogawa::parse(b"PK\x03\x04 and more bytes"),
            Err(AlembicError::NotAlembic(_))
        ));
        assert!(matches!(
            Ogawa::parse(b"Ogaw"),
            Err(AlembicError::Malformed(_))
        ));
    }
}
