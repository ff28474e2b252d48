//! The CPU side of the semantics-aware texture function (SATF) hair renderer of Xu et al. 2006,
//! "A Hybrid Off-line/On-line Approach to Hair Rendering" (`papers/xu-2006-satf.txt`): hair
//! clusters as generalized cylinders, their density fields, the off-line HRIR database and the
//! CPU twins of the on-line phase's math. The GPU renderer lives in `tress-render/src/satf/`.
//! No GPU dependency.
//!
//! | paper | module |
//! | --- | --- |
//! | §3.1 four-level hierarchy | [`hierarchy`]: [`HairVolume`] → [`MacroCluster`] → [`Cluster`] → [`LocalStrand`] |
//! | §3.2 generalized cylinder, equations 1–2 | [`bspline`], [`cylinder`] |
//! | §3.2 shells, HSVs, sectors, equation 3 | [`shell`] |
//! | §3.3 density field; §5.2 feature vector | [`density`] |
//! | clusters from a generator / from any strand asset | [`generate`], [`fit`] |
//! | §4, §5.1 planar ray tracing, equation 5, smoothing | [`hrir`] |
//! | §4–5 HRIR database and bake, equation 4; §6.2 equations 6–7 | [`database`], file format [`format`](mod@format) |
//! | §6.3–6.5 lighting, shadows, shading, blending, equations 8–14 | [`online`] |
//!
//! # Using it
//!
//! ```
//! use tress_hair::generate::{Style, StyleParams, generate};
//! use tress_satf::{database, fit, shell};
//! # fn main() -> Result<(), tress_satf::SatfError> {
//! // Any strand asset (`tress_hair::formats::read_path` reads a file); 300 generated strands.
//! let params = StyleParams { strands: 300, vertices: 16, ..Style::Straight.default_params() };
//! let asset = generate(Style::Straight, &params)?;
//! let volume = fit::fit_clusters(&asset, &fit::FitSettings::default())?;
//! let sampling = shell::ShellSampling::default();
//! assert_eq!(volume.stats(&sampling).strands, 300);
//! // The off-line HRIR database: 2048 random sectors by default, 16 here.
//! let bake = database::BakeSettings { samples: 16, ..Default::default() };
//! let db = database::bake(&bake, |_done, _total| {})?;
//! for (_geometry, cluster) in volume.clusters() {
//!     let features = shell::cluster_features(cluster, &sampling, &db.settings().density);
//!     assert_eq!(features.len(), sampling.sector_count());
//!     // … per HSV: online::sector_params, database::Database::hsv_maps, online::lighting …
//! }
//! # Ok(()) }
//! ```
//!
//! Every choice the paper leaves open is documented, with its section, in the module that makes
//! it, and is a setting where it changes results.

pub mod bspline;
pub mod cylinder;
pub mod database;
pub mod density;
mod error;
pub mod fit;
pub mod format;
pub mod generate;
pub mod hierarchy;
pub mod hrir;
pub mod online;
pub mod shell;

pub use cylinder::{GeneralizedCylinder, TwistMode};
pub use database::{BakeSettings, Database, HrirRecord, LookupSettings, Params, bake};
pub use error::{DatabaseError, SatfError};
pub use hierarchy::{Cluster, HairVolume, LocalPoint, LocalStrand, MacroCluster, SkippedStrands};
pub use shell::ShellSampling;
