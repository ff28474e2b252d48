//! Hair strand assets for tress: the [`HairAsset`] data model (structure of arrays), its
//! operations (transform, resample, subset, merge, follow hairs), file formats (Cem Yuksel `.hair`,
//! TressFX `.tfx`), procedural generators (a head and hair styles grown from its scalp) and the
//! polygon-patch hair model ([`patches`]: patch meshes, their textures, AO bake and sort).
//!
//! This crate has no GPU dependency. Everything that reads user data returns a typed [`HairError`]
//! and never panics.

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
