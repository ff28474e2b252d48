//! Hair file formats: Cem Yuksel `.hair` and AMD TressFX `.tfx`.
//!
//! | format | read | write | module |
//! | --- | --- | --- | --- |
//! | Cem Yuksel `.hair` (with the vkhr extension) | yes | yes (plain Cem Yuksel layout) | [`hair`] |
//! | TressFX `.tfx` 3.x | yes (follow hairs generated) | no | [`tfx`] |
//! | TressFX `.tfx` 4.x | yes | yes | [`tfx`] |
//!
//! The submodules document the exact byte layouts and where they come from.
//!
//! # Validation
//!
//! Every reader checks each count in a header against the length of the data before it sizes a
//! `Vec` from it (design rule 11), so a lying header cannot allocate more than the file itself
//! justifies. Bad data is a [`HairError::Format`] naming the format and the problem; the
//! path-based functions wrap it with [`HairError::in_file`] so that it reads `path: problem`.
//! Nothing here panics on user data.
//!
//! # Speed
//!
//! Each array is decoded in one pass from the validated byte range straight into a vector of
//! exactly its size (no zero-fill, no per-element allocation); arrays of 1 MiB or more are split
//! over rayon's threads. `cargo bench -p tress-hair --bench read` measures both readers on a
//! 136k-strand × 16-vertex asset.

use std::path::{Path, PathBuf};

use crate::{HairAsset, HairError};

mod bytes;
pub mod hair;
pub mod tfx;

pub use hair::{read_hair, write_hair};
pub use tfx::{TfxFile, TfxVersion, parse_tfx, read_tfx, write_tfx};

/// A hair file format, chosen by file extension.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Format {
    /// Cem Yuksel's `.hair` format (see [`hair`]).
    Hair,
    /// AMD TressFX `.tfx` (see [`tfx`]): versions 3.x and 4.x are read, 4.x is written.
    Tfx,
}

impl Format {
    /// Every format, in a stable order.
    pub const ALL: [Format; 2] = [Format::Hair, Format::Tfx];

    /// The format of a path by its extension (case-insensitive): `.hair` or `.tfx`.
    ///
    /// The error names the path and the extensions that are understood.
    pub fn from_path(path: &Path) -> Result<Format, HairError> {
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        match ext.as_deref() {
            Some("hair") => Ok(Format::Hair),
            Some("tfx") => Ok(Format::Tfx),
            Some(other) => Err(HairError::format(
                "hair file",
                format!("unknown extension `.{other}`; tress reads and writes .hair and .tfx"),
            )
            .in_file(path)),
            None => Err(HairError::format(
                "hair file",
                "no file extension; tress reads and writes .hair and .tfx",
            )
            .in_file(path)),
        }
    }

    /// The file extension, without the dot.
    pub fn extension(self) -> &'static str {
        match self {
            Format::Hair => "hair",
            Format::Tfx => "tfx",
        }
    }

    /// Read an asset of this format from bytes.
    pub fn read(self, bytes: &[u8]) -> Result<HairAsset, HairError> {
        match self {
            Format::Hair => read_hair(bytes),
            Format::Tfx => read_tfx(bytes),
        }
    }

    /// Write an asset in this format.
    pub fn write(self, asset: &HairAsset) -> Result<Vec<u8>, HairError> {
        match self {
            Format::Hair => write_hair(asset),
            Format::Tfx => write_tfx(asset),
        }
    }
}

/// Read a hair file, its format chosen by extension. Errors read `path: problem`.
pub fn read_path(path: &Path) -> Result<HairAsset, HairError> {
    let format = Format::from_path(path)?;
    let bytes = std::fs::read(path).map_err(|e| HairError::from(e).in_file(path))?;
    format.read(&bytes).map_err(|e| e.in_file(path))
}

/// Write a hair file, its format chosen by extension. Errors read `path: problem`.
pub fn write_path(path: &Path, asset: &HairAsset) -> Result<(), HairError> {
    let format = Format::from_path(path)?;
    let bytes = format.write(asset).map_err(|e| e.in_file(path))?;
    std::fs::write(path, bytes).map_err(|e| HairError::from(e).in_file(path))
}

/// Read several hair files (each by its extension) and merge them in order with
/// [`HairAsset::merge`]: a TressFX character often comes as one `.tfx` per hair part.
pub fn read_paths(paths: &[PathBuf]) -> Result<HairAsset, HairError> {
    if paths.is_empty() {
        return Err(HairError::Parameter("no hair files given".into()));
    }
    let assets = paths
        .iter()
        .map(|p| read_path(p))
        .collect::<Result<Vec<_>, _>>()?;
    HairAsset::merge(&assets)
}
