//! The crate's error type.

/// Errors of the tracer and the image tools. Every message is one line.
#[derive(Debug, thiserror::Error)]
pub enum TraceError {
    /// A tracer setting is out of range or unknown.
    #[error("trace.{key}: {reason}")]
    Setting {
        /// The setting's name (without the `trace.` prefix).
        key: String,
        /// What is wrong.
        reason: String,
    },
    /// The scene could not be loaded or holds a bad value.
    #[error(transparent)]
    Scene(#[from] tress_scene::SceneError),
    /// A hair or mesh file could not be read or merged.
    #[error(transparent)]
    Hair(#[from] tress_hair::HairError),
    /// Something in the scene the tracer cannot use (named).
    #[error("{0}")]
    Invalid(String),
    /// An image could not be read or written.
    #[error("{path}: {reason}")]
    Image {
        /// The file.
        path: String,
        /// What went wrong.
        reason: String,
    },
    /// Two images to compare differ in size.
    #[error("the images differ in size: {a_width}x{a_height} and {b_width}x{b_height}")]
    SizeMismatch {
        /// Width of the first image.
        a_width: u32,
        /// Height of the first image.
        a_height: u32,
        /// Width of the second image.
        b_width: u32,
        /// Height of the second image.
        b_height: u32,
    },
}
