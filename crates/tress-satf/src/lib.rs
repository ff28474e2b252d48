//! SATF (lib docs placeholder)
pub mod bspline;
pub mod cylinder;
pub mod density;
mod error;
pub mod hierarchy;
pub mod shell;

pub use error::{DatabaseError, SatfError};
