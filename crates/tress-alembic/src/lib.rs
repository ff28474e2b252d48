//! A reader for the curves in Alembic files (the Ogawa container): every `ICurves` object with
//! its world transform (the Xform objects above it composed), positions, vertex counts, curve
//! type, wrap and basis, widths, NURBS orders/knots/weights, and Unreal Engine's groom
//! attributes (`groom_color`, `groom_root_uv`, `groom_guide`). `P` is read at the frame asked
//! for ([`read_frame`], an animated cache); every other property at its first sample.
//!
//! This crate turns bytes into [`Curves`]; it knows nothing about hair assets. `tress-hair`
//! tessellates them (`tress_hair::formats::abc`).
//!
//! ```
//! use tress_alembic::write::{CurvesOut, write};
//!
//! // Two straight curves of two vertices, written by the minimal writer (feature `write`);
//! // `bytes` could as well be `std::fs::read("groom.abc")?`.
//! let bytes = write(&[CurvesOut {
//!     name: "strands".into(),
//!     positions: vec![[0.0, 0.0, 0.0], [0.0, 1.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0]],
//!     vertex_counts: vec![2, 2],
//!     ..CurvesOut::default()
//! }]);
//! let contents = tress_alembic::read(&bytes)?;
//! assert_eq!(contents.curves[0].vertex_counts, [2, 2]);
//! assert_eq!(contents.curves[0].positions[3], [1.0, 1.0, 0.0]);
//! # Ok::<(), tress_alembic::AlembicError>(())
//! ```
//!
//! No maintained pure-Rust Alembic reader exists. `ogawa-rs` 0.4 was evaluated against the test
//! files first: it finds `ICurves` and reads `P`, `nVertices` and `width`, but has no reader for
//! `.arbGeomParams` (the groom attributes) nor indexed geometry parameters, composes no Xform
//! matrices, and sizes buffers from header counts before checking them against the file (see
//! ARCHITECTURE.md). So the reader is written here, from the Alembic C++ sources' description
//! of the layout, documented in [`ogawa`](self#layers) and the modules below.
//!
//! # Layers
//!
//! - `ogawa`: the container (groups and data blocks), every offset and size checked against
//!   the file.
//! - `archive`: Alembic's objects and properties on Ogawa, every group visited once (so cyclic
//!   offsets are an error, not a hang) and nesting limited.
//! - `schema`: the Xform and Curve schemas.
//!
//! HDF5-based Alembic files (the format before Ogawa) are recognised by their signature and
//! refused with [`AlembicError::Hdf5`].
//!
//! # Validation
//!
//! Nothing is allocated from a count before the bytes it describes are known to be in the file;
//! no input makes the reader panic (a cargo-fuzz target, `fuzz/fuzz_targets/read_abc.rs`, and
//! property tests check it).

mod archive;
mod ogawa;
mod schema;
#[cfg(feature = "write")]
pub mod write;

/// Why an Alembic file could not be read.
#[derive(Debug, thiserror::Error)]
pub enum AlembicError {
    /// The file is an HDF5-based Alembic archive.
    #[error("HDF5 Alembic is not supported, re-export as Ogawa")]
    Hdf5,
    /// The file is neither Ogawa nor HDF5.
    #[error("not an Alembic file: {0}")]
    NotAlembic(String),
    /// The file is Ogawa but its contents are inconsistent (truncated, out-of-range offsets,
    /// cycles, counts that do not match the data).
    #[error("{0}")]
    Malformed(String),
}

/// What a curve's vertices mean (`curveBasisAndType[0]`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CurveType {
    /// Cubic segments in [`Curves::basis`].
    Cubic,
    /// Straight segments between the vertices.
    Linear,
    /// NURBS: per-curve orders and a knot vector.
    VariableOrder,
}

/// Whether the curves close on themselves.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Wrap {
    /// Open curves.
    NonPeriodic,
    /// Closed curves.
    Periodic,
}

/// The cubic basis.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Basis {
    /// No basis (linear curves).
    None,
    /// Bézier: spans of four vertices sharing ends.
    Bezier,
    /// Uniform cubic B-spline.
    Bspline,
    /// Catmull-Rom.
    CatmullRom,
    /// Hermite (not tessellated by tress).
    Hermite,
    /// Power basis (not tessellated by tress).
    Power,
}

/// What a geometry parameter's values are attached to (`geoScope`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Scope {
    /// One value for all curves.
    Constant,
    /// One value per curve.
    Uniform,
    /// One value per segment end (per span end for cubic curves).
    Varying,
    /// One value per vertex.
    Vertex,
    /// Face-varying (meshes only; curves treat it like varying).
    FaceVarying,
    /// No scope in the metadata: the value count decides.
    Unknown,
}

/// A geometry parameter's first sample, expanded through its indices if it was indexed.
#[derive(Clone, Debug, PartialEq)]
pub struct Param<T> {
    /// What the values are attached to.
    pub scope: Scope,
    /// The values.
    pub values: Vec<T>,
}

/// One `ICurves` object's first sample.
#[derive(Clone, Debug, PartialEq)]
pub struct Curves {
    /// The object's full name, e.g. `/groom/strands`.
    pub path: String,
    /// Object to world: column-major 4×4 for column vectors (the parent Xforms composed).
    pub world: [f64; 16],
    /// `P`: every vertex, curves back to back.
    pub positions: Vec<[f32; 3]>,
    /// `nVertices`: the vertex count of each curve (they add up to `positions.len()`).
    pub vertex_counts: Vec<u32>,
    /// Curve type.
    pub kind: CurveType,
    /// Wrap.
    pub wrap: Wrap,
    /// Basis of cubic curves.
    pub basis: Basis,
    /// `width`: strand diameters.
    pub widths: Option<Param<f32>>,
    /// `w`: position weights (NURBS).
    pub weights: Option<Vec<f32>>,
    /// `.orders`: the order of each curve (variable-order curves).
    pub orders: Option<Vec<u8>>,
    /// `.knots`: the knot vectors of all curves, back to back (variable-order curves).
    pub knots: Option<Vec<f32>>,
    /// Unreal's `groom_color` (linear RGB).
    pub colors: Option<Param<[f32; 3]>>,
    /// Unreal's `groom_root_uv`.
    pub root_uv: Option<Param<[f32; 2]>>,
    /// Unreal's `groom_guide`: non-zero marks a guide curve.
    pub guide: Option<Param<i64>>,
    /// How many samples `P` has (an animated cache has one a frame; at least 1).
    pub position_samples: u32,
    /// Seconds between `P`'s samples by its time sampling (uniform: the time per cycle; cyclic
    /// and acyclic: the mean spacing), `None` for one sample or a sampling that gives no
    /// positive spacing.
    pub seconds_per_position_sample: Option<f64>,
}

/// Everything read from an archive.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Contents {
    /// Every `ICurves` object, in depth-first order.
    pub curves: Vec<Curves>,
    /// Objects of other schemas (not read): full name and schema.
    pub ignored: Vec<(String, String)>,
}

/// Read every curves object of an Ogawa Alembic file held in memory.
pub fn read(bytes: &[u8]) -> Result<Contents, AlembicError> {
    read_frame(bytes, 0)
}

/// [`read`] with every curves object's `P` at sample `frame` (an animated cache: sample `k` is
/// the `k`-th frame written; a frame past the last reads the last). The curve counts and
/// attributes are read at their first sample: a cache whose topology changes is not modelled.
pub fn read_frame(bytes: &[u8], frame: u32) -> Result<Contents, AlembicError> {
    let ogawa = ogawa::Ogawa::parse(bytes)?;
    let mut reader = archive::Reader::new(ogawa)?;
    reader.frame = frame;
    let top = reader.top()?;
    let mut out = Contents::default();
    schema::walk(&mut reader, top, "", schema::IDENTITY, 0, &mut out)?;
    Ok(out)
}

/// Whether `bytes` start like an Alembic file of either container (Ogawa or HDF5).
pub fn is_alembic(bytes: &[u8]) -> bool {
    bytes.starts_with(b"Ogawa") || bytes.starts_with(ogawa::HDF5_MAGIC)
}
