//! Hair file formats: what tress reads and writes, chosen by extension.
//!
//! | format | extensions | read | write | module |
//! | --- | --- | --- | --- | --- |
//! | Cem Yuksel `.hair` (with the vkhr extension) | `.hair` | yes | yes (plain Cem Yuksel layout) | [`hair`] |
//! | TressFX 3.x / 4.x | `.tfx` | yes (3.x: follow hairs generated) | 4.x | [`tfx`] |
//! | USD `BasisCurves` / `NurbsCurves` (+ `Mesh`) | `.usda` `.usdc` `.usdz` `.usd` | yes | `.usda`, `.usdc` (linear; also animated caches) | [`usd`] |
//! | Alembic `ICurves` (Ogawa) | `.abc` | yes | yes (also animated caches) | [`abc`] |
//! | USC-HairSalon | `.data` | yes (1-vertex strands skipped) | yes | [`usc`] |
//! | CT2Hair | `.bin` | yes | no | [`ct2hair`] |
//!
//! The submodules document the exact layouts and where they come from. Cubic and NURBS curves are
//! tessellated by the rule in [`curves`] at [`ReadOptions::cubic_segments`]. Head and body
//! meshes (OBJ, glTF, USD `Mesh`) are read by [`mesh`]. Animated caches (a simulation's frames) are
//! written by [`write_cache_path`] and read a frame at a time ([`ReadOptions::frame`]); a read
//! reports how many frames the file has and their rate ([`Details::frames`], [`Details::fps`]).
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
//! over rayon's threads. `cargo bench -p tress-hair --bench read` measures the readers on a
//! 136k-strand × 16-vertex asset.

use std::path::{Path, PathBuf};

use crate::{HairAsset, HairError};

pub mod abc;
mod bytes;
pub mod ct2hair;
pub mod curves;
pub mod gltf;
pub mod hair;
pub mod mesh;
pub mod tfx;
pub mod usc;
pub mod usd;

pub use abc::{AbcInfo, read_abc};
pub use ct2hair::read_ct2hair;
pub use curves::ReadOptions;
pub use hair::{read_hair, write_hair};
pub use mesh::read_mesh;
pub use tfx::{TfxFile, TfxVersion, parse_tfx, read_tfx, write_tfx};
pub use usc::{DataInfo, read_data, write_data};
pub use usd::{UsdFlavor, UsdInfo, read_usd, read_usd_bytes, write_usd};

/// A hair file format, chosen by file extension.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Format {
    /// Cem Yuksel's `.hair` format (see [`hair`]).
    Hair,
    /// AMD TressFX `.tfx` (see [`tfx`]): versions 3.x and 4.x are read, 4.x is written.
    Tfx,
    /// USD text `.usda` (see [`usd`]): read and written.
    Usda,
    /// USD binary `.usdc`: read and written.
    Usdc,
    /// USD package `.usdz`: read.
    Usdz,
    /// `.usd`: text or binary, told apart by the file's first bytes; read, and written as binary.
    Usd,
    /// Alembic `.abc`, Ogawa (see [`abc`]): read.
    Abc,
    /// USC-HairSalon `.data` (see [`usc`]): read and written.
    Data,
    /// CT2Hair `.bin` (see [`ct2hair`]): read.
    Ct2Hair,
}

/// The extensions tress reads, for messages.
const READS: &str = ".hair, .tfx, .usda, .usdc, .usdz, .usd, .abc, .data and .bin";
/// The extensions tress writes, for messages.
const WRITES: &str = ".hair, .tfx, .usda, .usdc, .usd, .abc and .data";

impl Format {
    /// Every format, in a stable order.
    pub const ALL: [Format; 9] = [
        Format::Hair,
        Format::Tfx,
        Format::Usda,
        Format::Usdc,
        Format::Usdz,
        Format::Usd,
        Format::Abc,
        Format::Data,
        Format::Ct2Hair,
    ];

    /// The format of a path by its extension (case-insensitive).
    ///
    /// The error names the path and the extensions that are understood.
    pub fn from_path(path: &Path) -> Result<Format, HairError> {
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        let found = Format::ALL
            .into_iter()
            .find(|f| Some(f.extension()) == ext.as_deref());
        match (found, ext) {
            (Some(f), _) => Ok(f),
            (None, Some(other)) => Err(HairError::format(
                "hair file",
                format!("unknown extension `.{other}`; tress reads {READS}"),
            )
            .in_file(path)),
            (None, None) => Err(HairError::format(
                "hair file",
                format!("no file extension; tress reads {READS}"),
            )
            .in_file(path)),
        }
    }

    /// The file extension, without the dot.
    pub fn extension(self) -> &'static str {
        match self {
            Format::Hair => "hair",
            Format::Tfx => "tfx",
            Format::Usda => "usda",
            Format::Usdc => "usdc",
            Format::Usdz => "usdz",
            Format::Usd => "usd",
            Format::Abc => "abc",
            Format::Data => "data",
            Format::Ct2Hair => "bin",
        }
    }

    /// The format's name in words, e.g. for `tress info`.
    pub fn name(self) -> &'static str {
        match self {
            Format::Hair => "Cem Yuksel .hair",
            Format::Tfx => "TressFX .tfx",
            Format::Usda => "USD text (.usda)",
            Format::Usdc => "USD binary (.usdc)",
            Format::Usdz => "USD package (.usdz)",
            Format::Usd => "USD (.usd)",
            Format::Abc => "Alembic (Ogawa)",
            Format::Data => "USC-HairSalon .data",
            Format::Ct2Hair => "CT2Hair .bin",
        }
    }

    /// Whether [`Format::write`] writes this format.
    pub fn is_writable(self) -> bool {
        matches!(
            self,
            Format::Hair | Format::Tfx | Format::Usda | Format::Usdc | Format::Usd | Format::Data
        )
    }

    /// Read an asset of this format from bytes, with the default [`ReadOptions`].
    pub fn read(self, bytes: &[u8]) -> Result<HairAsset, HairError> {
        Ok(self.read_with(bytes, &ReadOptions::default())?.asset)
    }

    /// Read an asset of this format from bytes. A USD stage read from bytes cannot resolve
    /// references to other files; [`load_path`] can.
    pub fn read_with(self, bytes: &[u8], options: &ReadOptions) -> Result<Loaded, HairError> {
        let plain = |asset| Loaded {
            asset,
            format: self,
            details: Details::default(),
        };
        match self {
            Format::Hair => read_hair(bytes).map(plain),
            Format::Tfx => read_tfx(bytes).map(plain),
            Format::Data => {
                let (asset, info) = read_data(bytes)?;
                let mut l = plain(asset);
                l.details.single_vertex_skipped = info.single_vertex_skipped;
                Ok(l)
            }
            Format::Ct2Hair => read_ct2hair(bytes).map(plain),
            Format::Abc => {
                let (asset, info) = read_abc(bytes, options)?;
                let mut l = plain(asset);
                l.details.objects = info.objects;
                l.details.guides_skipped = info.guides_skipped;
                l.details.frames = info.frames.max(1);
                l.details.fps = info.fps;
                Ok(l)
            }
            Format::Usda | Format::Usdc | Format::Usdz | Format::Usd => {
                let ext = match self {
                    Format::Usd if bytes.starts_with(b"PXR-USDC") => "usdc",
                    Format::Usd => "usda",
                    other => other.extension(),
                };
                usd_loaded(self, read_usd_bytes(bytes, ext, options)?)
            }
        }
    }

    /// Write an asset in this format.
    pub fn write(self, asset: &HairAsset) -> Result<Vec<u8>, HairError> {
        match self {
            Format::Hair => write_hair(asset),
            Format::Tfx => write_tfx(asset),
            Format::Data => write_data(asset),
            Format::Usda => write_usd(asset, UsdFlavor::Text),
            Format::Usdc | Format::Usd => write_usd(asset, UsdFlavor::Binary),
            Format::Abc => abc::write_abc(asset, &[], 24.0),
            Format::Usdz | Format::Ct2Hair => Err(HairError::format(
                "hair file",
                format!(
                    "tress reads {} but does not write it; it writes {WRITES}",
                    self.name()
                ),
            )),
        }
    }
}

/// What a read found beyond the asset: shown by `tress info`.
#[derive(Clone, Debug, PartialEq)]
pub struct Details {
    /// USD prims or Alembic objects the curves came from.
    pub objects: Vec<String>,
    /// USD `Mesh` prims (the head/body mesh; not part of the hair).
    pub meshes: Vec<String>,
    /// Alembic guide curves left out.
    pub guides_skipped: usize,
    /// `.data` strands of one vertex left out.
    pub single_vertex_skipped: usize,
    /// The USD stage's `Mesh` prims merged (world space): the head or body that came with the
    /// groom.
    pub mesh: Option<crate::generate::TriMesh>,
    /// Frames of an animated cache, the samples [`ReadOptions::frame`] picks from: the most
    /// samples of Alembic `P` over the curves objects, or of USD `points` time samples over the
    /// curves prims; 1 for a still file (and for the formats that hold no animation).
    pub frames: u32,
    /// Frames a second of an animated cache, where the file says (Alembic: `P`'s time
    /// sampling; USD: `timeCodesPerSecond` over the spacing of the `points` time samples);
    /// `None` for a still file or one that does not say.
    pub fps: Option<f64>,
}

impl Default for Details {
    /// Nothing found: no prims, objects or skips, one frame.
    fn default() -> Self {
        Details {
            objects: Vec::new(),
            meshes: Vec::new(),
            guides_skipped: 0,
            single_vertex_skipped: 0,
            mesh: None,
            frames: 1,
            fps: None,
        }
    }
}

/// An asset read from one file, with its format and what the read found.
#[derive(Clone, Debug)]
pub struct Loaded {
    /// The strands.
    pub asset: HairAsset,
    /// The file's format.
    pub format: Format,
    /// Prims, objects and skipped strands.
    pub details: Details,
}

fn usd_loaded(format: Format, c: usd::UsdContents) -> Result<Loaded, HairError> {
    let asset = c.hair.ok_or_else(|| {
        HairError::format(
            "USD",
            if c.info.meshes.is_empty() {
                "the stage has no BasisCurves or NurbsCurves prims".to_string()
            } else {
                format!(
                    "the stage has no curves, only meshes ({}); give it as a head mesh instead",
                    c.info.meshes.join(", ")
                )
            },
        )
    })?;
    Ok(Loaded {
        asset,
        format,
        details: Details {
            objects: c.info.prims,
            meshes: c.info.meshes,
            mesh: c.mesh,
            frames: c.info.frames.max(1),
            fps: c.info.fps,
            ..Details::default()
        },
    })
}

/// Read a hair file, its format chosen by extension, with the default [`ReadOptions`]. Errors
/// read `path: problem`.
pub fn read_path(path: &Path) -> Result<HairAsset, HairError> {
    Ok(load_path(path, &ReadOptions::default())?.asset)
}

/// Read a hair file, its format chosen by extension, with what the read found. USD stages are
/// opened from the file, so their references resolve. Errors read `path: problem`.
pub fn load_path(path: &Path, options: &ReadOptions) -> Result<Loaded, HairError> {
    let format = Format::from_path(path)?;
    options.validate()?;
    if matches!(
        format,
        Format::Usda | Format::Usdc | Format::Usdz | Format::Usd
    ) {
        let c = read_usd(path, options).map_err(|e| e.in_file(path))?;
        return usd_loaded(format, c).map_err(|e| e.in_file(path));
    }
    let bytes = std::fs::read(path).map_err(|e| HairError::from(e).in_file(path))?;
    format
        .read_with(&bytes, options)
        .map_err(|e| e.in_file(path))
}

/// Write a hair file, its format chosen by extension. Errors read `path: problem`.
pub fn write_path(path: &Path, asset: &HairAsset) -> Result<(), HairError> {
    let format = Format::from_path(path)?;
    let bytes = format.write(asset).map_err(|e| e.in_file(path))?;
    std::fs::write(path, bytes).map_err(|e| HairError::from(e).in_file(path))
}

/// Write an animated cache of `asset` (its strands, widths and colours) moving through `frames`
/// (each as many vertices as the asset), `fps` frames a second, its format chosen by
/// extension: `.abc` (Alembic `ICurves` with `P` sampled once a frame on a uniform time
/// sampling) or `.usda` / `.usdc` / `.usd` (`BasisCurves` with `points.timeSamples` at time
/// codes 1…N and `timeCodesPerSecond = fps`). Read a frame back with [`ReadOptions::frame`].
/// Errors read `path: problem`.
pub fn write_cache_path(
    path: &Path,
    asset: &HairAsset,
    frames: &[Vec<glam::Vec3>],
    fps: f64,
) -> Result<(), HairError> {
    let format = Format::from_path(path)?;
    let bytes = match format {
        Format::Abc => abc::write_abc(asset, frames, fps),
        Format::Usda => usd::write_usd_animated(asset, frames, fps, UsdFlavor::Text),
        Format::Usdc | Format::Usd => {
            usd::write_usd_animated(asset, frames, fps, UsdFlavor::Binary)
        }
        other => Err(HairError::format(
            "cache",
            format!(
                "{} holds no animation; a cache is written as .abc, .usda, .usdc or .usd",
                other.name()
            ),
        )),
    }
    .map_err(|e| e.in_file(path))?;
    std::fs::write(path, bytes).map_err(|e| HairError::from(e).in_file(path))
}

/// Why `frames` at `fps` cannot be an animated cache of `asset` (a rate that is not finite and
/// positive, or a frame with another point count), shared by the Alembic and USD writers.
pub(crate) fn check_frames(
    asset: &HairAsset,
    frames: &[Vec<glam::Vec3>],
    fps: f64,
) -> Result<(), String> {
    if !(fps.is_finite() && fps > 0.0) {
        return Err(format!("frames per second must be positive, not {fps}"));
    }
    match frames
        .iter()
        .position(|f| f.len() != asset.positions().len())
    {
        Some(k) => Err(format!(
            "frame {k} has {} points, the hair {}",
            frames[k].len(),
            asset.positions().len()
        )),
        None => Ok(()),
    }
}

/// Read several hair files (each by its extension) and merge them in order with
/// [`HairAsset::merge`]: a TressFX character often comes as one `.tfx` per hair part.
pub fn read_paths(paths: &[PathBuf]) -> Result<HairAsset, HairError> {
    Ok(load_paths(paths, &ReadOptions::default())?.0)
}

/// [`read_paths`] with options, also giving each file's format and what its read found (in
/// order).
pub fn load_paths(
    paths: &[PathBuf],
    options: &ReadOptions,
) -> Result<(HairAsset, Vec<(Format, Details)>), HairError> {
    if paths.is_empty() {
        return Err(HairError::Parameter("no hair files given".into()));
    }
    let mut assets = Vec::with_capacity(paths.len());
    let mut found = Vec::with_capacity(paths.len());
    for p in paths {
        let l = load_path(p, options)?;
        assets.push(l.asset);
        found.push((l.format, l.details));
    }
    let asset = HairAsset::merge_owned(assets)?;
    Ok((asset, found))
}
