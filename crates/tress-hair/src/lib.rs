//! Hair strand assets for tress: the [`HairAsset`] data model (structure of arrays), its
//! operations (transform, resample, subset, merge, follow hairs), file formats (Cem Yuksel `.hair`,
//! TressFX `.tfx`), procedural generators (a head and hair styles grown from its scalp) and the
//! polygon-patch hair model ([`patches`]: patch meshes, their textures, AO bake and sort).
//!
//! This crate has no GPU dependency. Everything that reads user data returns a typed [`HairError`]
//! and never panics.
//!
//! ```
//! use glam::Vec3;
//! use tress_hair::HairAsset;
//! use tress_hair::formats::Format;
//! use tress_hair::generate::{Style, StyleParams, generate};
//!
//! // 300 curly strands grown from the generated head's scalp.
//! let params = StyleParams { strands: 300, ..Style::Curly.default_params() };
//! assert_eq!(generate(Style::Curly, &params)?.strand_count(), 300);
//!
//! // Two strands of 3 and 2 vertices, resampled to 8 vertices each, through a `.hair` file.
//! let points = vec![Vec3::ZERO, Vec3::Y, 2.0 * Vec3::Y, Vec3::X, Vec3::X + Vec3::Y];
//! let asset = HairAsset::from_counts(points, &[3, 2])?.resample_count(8)?;
//! let bytes = Format::Hair.write(&asset)?;
//! assert_eq!(Format::Hair.read(&bytes)?.vertex_count(), 16);
//! # Ok::<(), tress_hair::HairError>(())
//! ```

mod asset;
pub mod bvh;
mod error;
mod follow;
pub mod formats;
pub mod generate;
mod kdtree;
mod merge;
mod ops;
pub mod panic_guard;
pub mod patches;
pub mod rng;

pub use asset::{Aabb, HairAsset, HairParts, LengthStats};
pub use error::HairError;
pub use follow::{DEFAULT_RADIUS_FACTOR, FollowMode, FollowParams, FollowRadius, FollowReport};
