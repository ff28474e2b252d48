//! A structural check of a `.usdc` ("crate") file before openusd reads it.
//!
//! openusd 0.6 sizes buffers from counts in the file without comparing them with the file's size
//! (a lying array length asked it for 84 PB in our property test, which aborts the process) and
//! reaches `todo!()` for crate versions before 0.4.0 and for chunked LZ4 blocks. This check
//! walks what openusd will read and refuses a file whose counts cannot be true, so every
//! allocation openusd then makes is bounded by a small multiple of the file's size. It follows
//! the crate layout of Pixar's `crateFile.cpp` as openusd reads it:
//!
//! - bootstrap: `"PXR-USDC"`, version bytes (major, minor, patch), `u64` TOC offset;
//! - TOC: `u64` section count (1–63), then per section a 16-byte name, `u64` start and size;
//! - sections `TOKENS` (count, uncompressed size, compressed block), `STRINGS` (count, `u32`s),
//!   `FIELDS` (count, compressed token indices, compressed value representations),
//!   `FIELDSETS`, `PATHS`, `SPECS` (counts and compressed integer blocks);
//! - a compressed block is a `u64` size and that many bytes, the first of which (the chunk count
//!   of Pixar's `TfFastCompression`) must be 0;
//! - every array value of a field (a value representation with the array bit set and not
//!   inlined) has its element count at its offset, checked against the bytes after it; so do
//!   dictionaries, token / path / string / double / layer-offset vectors and list ops. Time
//!   samples are not followed.
//!
//! Counts of compressed integers may exceed their bytes (integer coding and LZ4 together pack up
//! to about a thousand values a byte), so they are bounded by [`PACKED`] values per byte.

const MAGIC: &[u8; 8] = b"PXR-USDC";
/// Most values a byte of compressed data is allowed to stand for.
const PACKED: u64 = 1024;

fn u64_at(bytes: &[u8], at: u64) -> Result<u64, String> {
    let s = usize::try_from(at)
        .ok()
        .and_then(|a| bytes.get(a..a.checked_add(8)?))
        .ok_or_else(|| format!("truncated: no 8-byte count at byte {at} of {}", bytes.len()))?;
    Ok(u64::from_le_bytes(s.try_into().unwrap_or_default()))
}

fn u32_at(bytes: &[u8], at: u64) -> Result<u32, String> {
    let s = usize::try_from(at)
        .ok()
        .and_then(|a| bytes.get(a..a.checked_add(4)?))
        .ok_or_else(|| format!("truncated: no 4-byte count at byte {at} of {}", bytes.len()))?;
    Ok(u32::from_le_bytes(s.try_into().unwrap_or_default()))
}

/// A read position inside one section.
struct Cursor<'a> {
    bytes: &'a [u8],
    at: u64,
    end: u64,
    section: &'a str,
}

impl Cursor<'_> {
    fn count(&mut self) -> Result<u64, String> {
        if self.at + 8 > self.end {
            return Err(format!("truncated {} section", self.section));
        }
        let v = u64_at(self.bytes, self.at)?;
        self.at += 8;
        Ok(v)
    }

    /// A count of values that compressed blocks in this section hold.
    fn packed_count(&mut self) -> Result<u64, String> {
        let n = self.count()?;
        let room = (self.end - self.at).saturating_mul(PACKED);
        if n > room {
            return Err(format!(
                "the {} section claims {n} entries, more than its bytes can hold",
                self.section
            ));
        }
        Ok(n)
    }

    /// A compressed block: its size, then its bytes (chunk count first, which must be 0).
    fn block(&mut self) -> Result<&[u8], String> {
        let size = self.count()?;
        if size > self.end - self.at {
            return Err(format!(
                "a compressed block of {size} bytes runs past the {} section",
                self.section
            ));
        }
        let start = self.at as usize;
        let data = &self.bytes[start..start + size as usize];
        self.at += size;
        if data.first().is_some_and(|&c| c != 0) {
            return Err("chunked LZ4 blocks are not supported".into());
        }
        Ok(data)
    }
}

/// Check a `.usdc` file (see the module docs); the error says what cannot be true.
pub(crate) fn check(bytes: &[u8]) -> Result<(), String> {
    if bytes.len() < 88 {
        return Err(format!(
            "truncated: {} bytes, fewer than the 88-byte crate header",
            bytes.len()
        ));
    }
    if &bytes[..8] != MAGIC {
        return Err(format!(
            "not a .usdc file: it starts with \"{}\" instead of \"PXR-USDC\"",
            bytes[..8].escape_ascii()
        ));
    }
    let version = (bytes[8], bytes[9], bytes[10]);
    if version < (0, 4, 0) {
        return Err(format!(
            "crate version {}.{}.{} is older than 0.4.0, which openusd cannot read",
            version.0, version.1, version.2
        ));
    }
    let len = bytes.len() as u64;
    let toc = u64_at(bytes, 16)?;
    let sections = u64_at(bytes, toc)?;
    if !(1..64).contains(&sections) || toc + 8 + 32 * sections > len {
        return Err(format!(
            "the table of contents at byte {toc} lists {sections} sections"
        ));
    }
    for i in 0..sections {
        let at = toc + 8 + 32 * i;
        let name_bytes = &bytes[at as usize..at as usize + 16];
        let name_len = name_bytes.iter().position(|&b| b == 0).unwrap_or(16);
        let name = std::str::from_utf8(&name_bytes[..name_len]).unwrap_or("?");
        let start = u64_at(bytes, at + 16)?;
        let size = u64_at(bytes, at + 24)?;
        let end = start.checked_add(size).filter(|&e| e <= len);
        let end = end.ok_or_else(|| {
            format!(
                "section {name} ({size} bytes at {start}) lies past the end of the {len}-byte file"
            )
        })?;
        let mut c = Cursor {
            bytes,
            at: start,
            end,
            section: name,
        };
        match name {
            "TOKENS" => {
                let count = c.count()?;
                let uncompressed = c.count()?;
                let block = c.block()?;
                if uncompressed > (block.len() as u64).saturating_mul(256)
                    || count > uncompressed + 1
                {
                    return Err("the TOKENS section's sizes cannot be true".into());
                }
            }
            "STRINGS" => {
                let count = c.count()?;
                if count.saturating_mul(4) > end - c.at {
                    return Err(format!("the STRINGS section claims {count} strings"));
                }
            }
            "FIELDS" => {
                let count = c.packed_count()?;
                c.block()?;
                let reps = c.block()?;
                check_arrays(bytes, version, count, reps)?;
            }
            "FIELDSETS" => {
                c.packed_count()?;
                c.block()?;
            }
            "PATHS" => {
                c.packed_count()?;
                c.packed_count()?;
                for _ in 0..3 {
                    c.block()?;
                }
            }
            "SPECS" => {
                c.packed_count()?;
                for _ in 0..3 {
                    c.block()?;
                }
            }
            _ => {}
        }
    }
    Ok(())
}

/// Decompress the FIELDS value representations and check every array's element count.
fn check_arrays(
    bytes: &[u8],
    version: (u8, u8, u8),
    count: u64,
    block: &[u8],
) -> Result<(), String> {
    let Some(lz4) = block.get(1..) else {
        return Ok(());
    };
    let size =
        usize::try_from(count.saturating_mul(8)).map_err(|_| "too many fields".to_string())?;
    let reps = lz4_flex::block::decompress(lz4, size)
        .map_err(|e| format!("the FIELDS value representations do not decompress: {e}"))?;
    let len = bytes.len() as u64;
    for rep in reps.as_chunks::<8>().0 {
        let rep = u64::from_le_bytes(*rep);
        let (array, inlined, compressed) =
            (rep >> 63 & 1 == 1, rep >> 62 & 1 == 1, rep >> 61 & 1 == 1);
        let payload = rep & ((1 << 48) - 1);
        let kind = (rep >> 48) & 0xff;
        // Dictionaries, list ops, vectors and variant selections are read as such whether
        // or not their array bit is set.
        let counted = matches!(kind, 31..=41 | 45 | 48..=50 | 54 | 55);
        // An array at 0 is empty; any other value at 0 would be read from the header.
        if inlined || (array && !counted && payload == 0) {
            continue;
        }
        if counted || !array {
            // Non-array values that start with an element count: dictionaries (31), path,
            // token, double, layer-offset and string vectors (40, 41, 48, 49, 50), variant
            // selections (45); list ops (32–39, 54, 55) start with a header byte.
            if let Some(element) = list_op_element(kind) {
                check_list_op(bytes, payload, element)
                    .map_err(|e| format!("the list op at byte {payload}: {e}"))?;
                continue;
            }
            let at = match kind {
                31 | 40 | 41 | 45 | 48..=50 => payload,
                35 | 54 | 55 => payload + 1,
                _ => continue,
            };
            let n = u64_at(bytes, at)?;
            let after = len.saturating_sub(at + 8);
            if n > after {
                return Err(format!(
                    "a value at byte {payload} claims {n} elements but the file has {after} bytes after it"
                ));
            }
            continue;
        }
        let mut at = payload;
        if version < (0, 5, 0) {
            at += 4;
        }
        let n = if version < (0, 7, 0) {
            u64::from(u32_at(bytes, at)?)
        } else {
            u64_at(bytes, at)?
        };
        let after = len.saturating_sub(at + 8);
        let room = if compressed {
            after.saturating_mul(PACKED)
        } else {
            after
        };
        if n > room {
            return Err(format!(
                "an array at byte {payload} claims {n} elements but the file has {after} bytes after it"
            ));
        }
        // openusd reads an array as compressed only from 4 elements on, integer arrays from
        // crate 0.5.0 and floating point arrays from 0.6.0.
        let since = if kind <= 6 { (0, 5, 0) } else { (0, 6, 0) };
        if compressed && n >= 4 && version >= since {
            let width = if version < (0, 7, 0) { 4 } else { 8 };
            check_compressed_array(bytes, kind, at + width)
                .map_err(|e| format!("the compressed array at byte {payload}: {e}"))?;
        }
    }
    Ok(())
}

/// The bytes of one item of a list op of value type `kind` whose items have a fixed size: token,
/// string and path list ops hold `u32` indices, the integer ones their integers.
fn list_op_element(kind: u64) -> Option<u64> {
    match kind {
        32..=34 | 36 | 38 => Some(4),
        37 | 39 => Some(8),
        _ => None,
    }
}

/// Walk a list op of fixed-size items at `at`: a header byte whose bits 1–6 say which item
/// lists follow, each an element count and its items; every count must fit the file (openusd
/// allocates it before reading).
fn check_list_op(bytes: &[u8], at: u64, element: u64) -> Result<(), String> {
    let len = bytes.len() as u64;
    let header = *bytes
        .get(at as usize)
        .ok_or("truncated before its header")?;
    let lists = (header >> 1 & 0x3f).count_ones();
    let mut at = at + 1;
    for _ in 0..lists {
        let n = u64_at(bytes, at)?;
        let after = len.saturating_sub(at + 8);
        if n > after / element {
            return Err(format!(
                "a list of {n} items, but the file has {after} bytes after it"
            ));
        }
        at += 8 + n * element;
    }
    Ok(())
}

/// Check the compressed payload of an array value after its element count at `at`: openusd
/// allocates a compressed block's stated size before reading it, so every size must fit the
/// file. Integer arrays (value types 3–6) are one block; half, float and double arrays (7–9)
/// start with a code: `i` (one block of integers) or `t` (a lookup table, then one block of
/// indices).
fn check_compressed_array(bytes: &[u8], kind: u64, at: u64) -> Result<(), String> {
    let len = bytes.len() as u64;
    let block = |at: u64| -> Result<(), String> {
        let size = u64_at(bytes, at)?;
        let after = len.saturating_sub(at + 8);
        if size > after {
            return Err(format!(
                "a block of {size} bytes, but the file has {after} bytes after it"
            ));
        }
        Ok(())
    };
    match kind {
        3..=6 => block(at),
        7..=9 => {
            let code = *bytes.get(at as usize).ok_or("truncated before its code")?;
            match code {
                b'i' => block(at + 1),
                b't' => {
                    let table = u64::from(u32_at(bytes, at + 1)?);
                    let element = [2, 4, 8][(kind - 7) as usize];
                    let end = at + 5 + table.saturating_mul(element);
                    if end > len {
                        return Err(format!(
                            "a lookup table of {table} values past the file's end"
                        ));
                    }
                    block(end)
                }
                other => Err(format!("an unknown compression code {other}")),
            }
        }
        _ => Ok(()),
    }
}
