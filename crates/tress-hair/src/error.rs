//! Typed errors of the hair data layer.

use std::path::PathBuf;

/// Everything that can go wrong when building, reading or writing a hair asset.
#[derive(Debug, thiserror::Error)]
pub enum HairError {
    /// The data is not a valid file of the format it claims to be.
    #[error("{format}: {reason}")]
    Format {
        /// The format being read, e.g. `.hair` or `.tfx`.
        format: &'static str,
        /// What is wrong, in words.
        reason: String,
    },
    /// The arrays handed to a constructor do not describe a valid asset.
    #[error("invalid hair asset: {0}")]
    Invalid(String),
    /// An operation got a parameter out of its range.
    #[error("invalid parameter: {0}")]
    Parameter(String),
    /// An I/O error while reading or writing a file.
    #[error("{0}")]
    Io(#[from] std::io::Error),
    /// An error that happened while handling a specific file; wraps the underlying error.
    #[error("{}: {source}", path.display())]
    File {
        /// The file in question.
        path: PathBuf,
        /// What went wrong with it.
        #[source]
        source: Box<HairError>,
    },
}

impl HairError {
    /// A format error with a reason.
    pub fn format(format: &'static str, reason: impl Into<String>) -> Self {
        HairError::Format {
            format,
            reason: reason.into(),
        }
    }

    /// Attach the file name to an error (once: an error that already names a file is kept).
    pub fn in_file(self, path: impl Into<PathBuf>) -> Self {
        match self {
            e @ HairError::File { .. } => e,
            e => HairError::File {
                path: path.into(),
                source: Box::new(e),
            },
        }
    }
}
