//! The HRIR database file (`.satfdb`): compact, versioned and checksummed. All numbers are
//! little-endian.
//!
//! | offset | size | content |
//! | --- | --- | --- |
//! | 0 | 8 | magic `TRESSATF` |
//! | 8 | 4 | format version `u32` ([`FORMAT_VERSION`]) |
//! | 12 | 88 | settings: the 21 fields of [`BakeSettings::fields`] in order; `seed` is `u64`, counts `u32`, reals `f32`, the feature kind `u32` (0 centroid, 1 histogram mean) |
//! | 100 | `12 n` | features: `n = samples` × 3 `f32` |
//! | … | `2 n V P` | `α̂`: unorm16, `[sample][view][pixel]` |
//! | … | `2 n V L P` | `r̂e`: unorm16, `[sample][view][light][pixel]` |
//! | end − 8 | 8 | FNV-1a 64 of every byte before it |
//!
//! The reader checks, before allocating anything the size of the payload: the magic, the
//! version, the settings' ranges ([`BakeSettings::validate`]), that the file's length is exactly
//! what the header implies (so a lying count cannot allocate), then the checksum, then that every
//! feature is finite.

use std::path::Path;

use crate::database::{BakeSettings, Database};
use crate::density::{DensitySettings, FeatureKind};
use crate::error::{DatabaseError, SatfError};
use crate::hrir::{HrirSettings, PhongSettings};

/// The magic bytes at the start of a database file.
pub const MAGIC: [u8; 8] = *b"TRESSATF";
/// The format version this build reads and writes.
pub const FORMAT_VERSION: u32 = 1;
/// Size of magic, version and settings.
pub const HEADER_LEN: usize = 100;
/// Size of the checksum trailer.
const TRAILER_LEN: usize = 8;
/// Largest file [`Database::load`] reads (4 GiB).
pub const MAX_FILE_LEN: u64 = 1 << 32;

/// FNV-1a 64-bit hash, the file's checksum.
pub fn fnv1a64(bytes: &[u8]) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for &b in bytes {
        h ^= u64::from(b);
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    h
}

struct Reader<'a> {
    bytes: &'a [u8],
    pos: usize,
}

impl Reader<'_> {
    fn take<const N: usize>(&mut self) -> [u8; N] {
        // Callers only read within the length checked before.
        let mut out = [0u8; N];
        out.copy_from_slice(&self.bytes[self.pos..self.pos + N]);
        self.pos += N;
        out
    }
    fn u32(&mut self) -> u32 {
        u32::from_le_bytes(self.take())
    }
    fn u64(&mut self) -> u64 {
        u64::from_le_bytes(self.take())
    }
    fn f32(&mut self) -> f32 {
        f32::from_le_bytes(self.take())
    }
}

fn write_settings(out: &mut Vec<u8>, s: &BakeSettings) {
    let d = &s.density;
    let h = &s.hrir;
    out.extend(s.samples.to_le_bytes());
    out.extend(s.seed.to_le_bytes());
    out.extend(s.max_strands.to_le_bytes());
    for x in [d.grid_s, d.grid_depth] {
        out.extend(x.to_le_bytes());
    }
    for x in [d.depth, d.sigma, d.strand_mass, d.reference_strands] {
        out.extend(x.to_le_bytes());
    }
    let kind: u32 = match d.feature_kind {
        FeatureKind::Centroid => 0,
        FeatureKind::HistogramMean => 1,
    };
    out.extend(kind.to_le_bytes());
    for x in [h.pixels, h.view_angles, h.light_angles] {
        out.extend(x.to_le_bytes());
    }
    let p = &h.phong;
    for x in [
        h.opacity_scale,
        h.opacity_cutoff,
        h.max_path,
        h.smoothing_ratio,
        p.ambient,
        p.diffuse,
        p.specular,
        p.exponent,
    ] {
        out.extend(x.to_le_bytes());
    }
}

fn read_settings(r: &mut Reader<'_>) -> Result<BakeSettings, DatabaseError> {
    let samples = r.u32();
    let seed = r.u64();
    let max_strands = r.u32();
    let (grid_s, grid_depth) = (r.u32(), r.u32());
    let (depth, sigma, strand_mass, reference_strands) = (r.f32(), r.f32(), r.f32(), r.f32());
    let feature_kind = match r.u32() {
        0 => FeatureKind::Centroid,
        1 => FeatureKind::HistogramMean,
        k => return Err(DatabaseError::Invalid(format!("unknown feature kind {k}"))),
    };
    let (pixels, view_angles, light_angles) = (r.u32(), r.u32(), r.u32());
    let (opacity_scale, opacity_cutoff, max_path, smoothing_ratio) =
        (r.f32(), r.f32(), r.f32(), r.f32());
    let phong = PhongSettings {
        ambient: r.f32(),
        diffuse: r.f32(),
        specular: r.f32(),
        exponent: r.f32(),
    };
    Ok(BakeSettings {
        samples,
        seed,
        max_strands,
        density: DensitySettings {
            grid_s,
            grid_depth,
            depth,
            sigma,
            strand_mass,
            reference_strands,
            feature_kind,
        },
        hrir: HrirSettings {
            pixels,
            view_angles,
            light_angles,
            opacity_scale,
            opacity_cutoff,
            max_path,
            smoothing_ratio,
            phong,
        },
    })
}

/// Payload sizes `(features, alpha values, re values)` and the whole file length for `s`.
fn layout(s: &BakeSettings) -> Option<(usize, usize, usize, u64)> {
    let n = u64::from(s.samples);
    let (p, v, l) = (
        u64::from(s.hrir.pixels),
        u64::from(s.hrir.view_angles),
        u64::from(s.hrir.light_angles),
    );
    let alpha = n.checked_mul(v)?.checked_mul(p)?;
    let re = alpha.checked_mul(l)?;
    let len = (HEADER_LEN as u64)
        .checked_add(n.checked_mul(12)?)?
        .checked_add(alpha.checked_mul(2)?)?
        .checked_add(re.checked_mul(2)?)?
        .checked_add(TRAILER_LEN as u64)?;
    Some((
        usize::try_from(n).ok()?,
        usize::try_from(alpha).ok()?,
        usize::try_from(re).ok()?,
        len,
    ))
}

impl Database {
    /// The database as file bytes (see the module docs).
    pub fn to_bytes(&self) -> Vec<u8> {
        let mut out = Vec::with_capacity(
            HEADER_LEN
                + 12 * self.features.len()
                + 2 * (self.alpha.len() + self.re.len())
                + TRAILER_LEN,
        );
        out.extend(MAGIC);
        out.extend(FORMAT_VERSION.to_le_bytes());
        write_settings(&mut out, &self.settings);
        debug_assert_eq!(out.len(), HEADER_LEN);
        for f in &self.features {
            for x in f {
                out.extend(x.to_le_bytes());
            }
        }
        for x in self.alpha.iter().chain(&self.re) {
            out.extend(x.to_le_bytes());
        }
        let sum = fnv1a64(&out);
        out.extend(sum.to_le_bytes());
        out
    }

    /// A database from file bytes, validated (see the module docs).
    pub fn from_bytes(bytes: &[u8]) -> Result<Database, DatabaseError> {
        let found = bytes.len() as u64;
        if bytes.len() < 8 || bytes[..8] != MAGIC {
            return Err(DatabaseError::BadMagic);
        }
        if bytes.len() < 12 {
            return Err(DatabaseError::Truncated {
                expected: (HEADER_LEN + TRAILER_LEN) as u64,
                found,
            });
        }
        let mut r = Reader { bytes, pos: 8 };
        let version = r.u32();
        if version != FORMAT_VERSION {
            return Err(DatabaseError::UnsupportedVersion {
                found: version,
                supported: FORMAT_VERSION,
            });
        }
        if bytes.len() < HEADER_LEN + TRAILER_LEN {
            return Err(DatabaseError::Truncated {
                expected: (HEADER_LEN + TRAILER_LEN) as u64,
                found,
            });
        }
        let settings = read_settings(&mut r)?;
        settings
            .validate()
            .map_err(|e| DatabaseError::Invalid(format!("header settings: {e}")))?;
        let (n, n_alpha, n_re, expected) = layout(&settings)
            .ok_or_else(|| DatabaseError::Invalid("header counts overflow".into()))?;
        if expected != found {
            return Err(DatabaseError::Truncated { expected, found });
        }
        let body = bytes.len() - TRAILER_LEN;
        let stored = u64::from_le_bytes(bytes[body..].try_into().unwrap_or([0; 8]));
        let computed = fnv1a64(&bytes[..body]);
        if stored != computed {
            return Err(DatabaseError::Checksum { stored, computed });
        }
        let mut features = Vec::with_capacity(n);
        for i in 0..n {
            let f = [r.f32(), r.f32(), r.f32()];
            if f.iter().any(|x| !x.is_finite()) {
                return Err(DatabaseError::Invalid(format!(
                    "features of sample {i} are not finite"
                )));
            }
            features.push(f);
        }
        let u16s = |r: &mut Reader<'_>, count: usize| -> Vec<u16> {
            (0..count).map(|_| u16::from_le_bytes(r.take())).collect()
        };
        let alpha = u16s(&mut r, n_alpha);
        let re = u16s(&mut r, n_re);
        Ok(Database {
            settings,
            features,
            alpha,
            re,
        })
    }

    /// A database from file bytes that must have been baked with `expected` settings; the error
    /// names the first setting that differs.
    pub fn from_bytes_expecting(
        bytes: &[u8],
        expected: &BakeSettings,
    ) -> Result<Database, DatabaseError> {
        let db = Database::from_bytes(bytes)?;
        db.check_settings(expected)?;
        Ok(db)
    }

    /// `Ok` when the database was baked with `expected`, else the first setting that differs.
    fn check_settings(&self, expected: &BakeSettings) -> Result<(), DatabaseError> {
        let ours = self.settings.fields();
        for ((field, found), (_, want)) in ours.into_iter().zip(expected.fields()) {
            if found != want {
                return Err(DatabaseError::SettingsMismatch {
                    field,
                    found,
                    expected: want,
                });
            }
        }
        Ok(())
    }

    /// Write the database file. Errors name the file.
    pub fn save(&self, path: &Path) -> Result<(), SatfError> {
        std::fs::write(path, self.to_bytes()).map_err(|source| SatfError::Io {
            path: path.into(),
            source,
        })
    }

    /// Read and validate a database file (at most [`MAX_FILE_LEN`] bytes). Errors name the file.
    pub fn load(path: &Path) -> Result<Database, SatfError> {
        let io = |source| SatfError::Io {
            path: path.into(),
            source,
        };
        let len = std::fs::metadata(path).map_err(io)?.len();
        if len > MAX_FILE_LEN {
            return Err(SatfError::from(DatabaseError::Invalid(format!(
                "file is {len} bytes, more than the {MAX_FILE_LEN} accepted"
            )))
            .in_file(path));
        }
        let bytes = std::fs::read(path).map_err(io)?;
        Database::from_bytes(&bytes).map_err(|e| SatfError::from(e).in_file(path))
    }

    /// [`Database::load`] of a file that must have been baked with `expected` settings
    /// ([`Database::from_bytes_expecting`]). Errors name the file.
    pub fn load_expecting(path: &Path, expected: &BakeSettings) -> Result<Database, SatfError> {
        let db = Database::load(path)?;
        db.check_settings(expected)
            .map_err(|e| SatfError::from(e).in_file(path))?;
        Ok(db)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::database::bake;

    fn small() -> Database {
        let s = BakeSettings {
            samples: 6,
            hrir: HrirSettings {
                pixels: 4,
                view_angles: 2,
                light_angles: 3,
                ..Default::default()
            },
            density: DensitySettings {
                grid_s: 8,
                grid_depth: 4,
                sigma: 0.1,
                ..Default::default()
            },
            ..Default::default()
        };
        bake(&s, |_, _| {}).unwrap()
    }

    #[test]
    fn fnv1a64_known_values() {
        // Published FNV-1a 64 test vectors.
        assert_eq!(fnv1a64(b""), 0xcbf2_9ce4_8422_2325);
        assert_eq!(fnv1a64(b"a"), 0xaf63_dc4c_8601_ec8c);
        assert_eq!(fnv1a64(b"foobar"), 0x8594_4171_f739_67e8);
    }

    #[test]
    fn round_trip_and_size() {
        let db = small();
        let bytes = db.to_bytes();
        assert_eq!(
            bytes.len(),
            100 + 6 * 12 + 2 * 6 * 2 * 4 + 2 * 6 * 2 * 3 * 4 + 8
        );
        assert_eq!(Database::from_bytes(&bytes).unwrap(), db);
        assert_eq!(
            Database::from_bytes_expecting(&bytes, db.settings()).unwrap(),
            db
        );
    }

    #[test]
    fn corrupt_files_give_clear_errors() {
        let db = small();
        let bytes = db.to_bytes();
        // A flipped payload byte.
        let mut b = bytes.clone();
        b[200] ^= 0x10;
        assert!(matches!(
            Database::from_bytes(&b),
            Err(DatabaseError::Checksum { .. })
        ));
        // Truncated and padded.
        assert_eq!(
            Database::from_bytes(&bytes[..bytes.len() - 5]),
            Err(DatabaseError::Truncated {
                expected: bytes.len() as u64,
                found: bytes.len() as u64 - 5
            })
        );
        assert!(matches!(
            Database::from_bytes(&bytes[..50]),
            Err(DatabaseError::Truncated { .. })
        ));
        let mut b = bytes.clone();
        b.push(0);
        assert!(matches!(
            Database::from_bytes(&b),
            Err(DatabaseError::Truncated { .. })
        ));
        // Wrong version and magic.
        let mut b = bytes.clone();
        b[8] = 2;
        assert_eq!(
            Database::from_bytes(&b),
            Err(DatabaseError::UnsupportedVersion {
                found: 2,
                supported: 1
            })
        );
        assert_eq!(
            Database::from_bytes(b"NOTADB at all, nope"),
            Err(DatabaseError::BadMagic)
        );
        assert_eq!(Database::from_bytes(b"TRE"), Err(DatabaseError::BadMagic));
        // A sample count that lies (a billion samples) is rejected by size, before allocating.
        let mut b = bytes.clone();
        b[12..16].copy_from_slice(&1_000_000u32.to_le_bytes());
        assert!(matches!(
            Database::from_bytes(&b),
            Err(DatabaseError::Truncated { .. })
        ));
        b[12..16].copy_from_slice(&u32::MAX.to_le_bytes());
        assert!(matches!(
            Database::from_bytes(&b),
            Err(DatabaseError::Invalid(_))
        ));
        // Settings mismatch names the field.
        let other = BakeSettings {
            seed: 9,
            ..*db.settings()
        };
        match Database::from_bytes_expecting(&bytes, &other) {
            Err(DatabaseError::SettingsMismatch {
                field,
                found,
                expected,
            }) => {
                assert_eq!(
                    (field, found.as_str(), expected.as_str()),
                    ("seed", "0", "9")
                );
            }
            r => panic!("expected a settings mismatch, got {r:?}"),
        }
        let msg = SatfError::from(DatabaseError::Checksum {
            stored: 1,
            computed: 2,
        })
        .to_string();
        assert!(msg.contains("corrupt"), "{msg}");
    }

    #[test]
    fn load_and_save_name_the_file() {
        let dir = std::env::temp_dir().join(format!("tress-satf-format-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("db.satfdb");
        let db = small();
        db.save(&path).unwrap();
        assert_eq!(Database::load(&path).unwrap(), db);
        assert_eq!(Database::load_expecting(&path, db.settings()).unwrap(), db);
        let other = BakeSettings {
            samples: 7,
            ..*db.settings()
        };
        let msg = Database::load_expecting(&path, &other)
            .unwrap_err()
            .to_string();
        assert!(
            msg.contains("db.satfdb") && msg.contains("samples = 6") && msg.contains("re-bake"),
            "{msg}"
        );
        std::fs::write(&path, b"garbage").unwrap();
        let msg = Database::load(&path).unwrap_err().to_string();
        assert!(msg.contains("db.satfdb") && msg.contains("magic"), "{msg}");
        let msg = Database::load(&dir.join("missing.satfdb"))
            .unwrap_err()
            .to_string();
        assert!(msg.contains("missing.satfdb"), "{msg}");
        std::fs::remove_dir_all(&dir).ok();
    }
}
