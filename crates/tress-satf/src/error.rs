//! Typed errors of the SATF CPU side.

use std::path::PathBuf;

use tress_hair::HairError;

/// Everything that can go wrong when building clusters, baking or reading an HRIR database.
#[derive(Debug, thiserror::Error)]
pub enum SatfError {
    /// A setting or argument is out of its range.
    #[error("invalid parameter: {0}")]
    Parameter(String),
    /// The strands give no cluster geometry (no length, or a mean strand that collapses to a
    /// point); [`crate::fit::fit_clusters`] then fits them one by one or counts them as skipped.
    #[error("degenerate cluster: {0}")]
    Degenerate(String),
    /// An error from the hair data layer (reading or building a strand asset).
    #[error(transparent)]
    Hair(#[from] HairError),
    /// The bytes are not a valid HRIR database.
    #[error("HRIR database: {0}")]
    Database(#[from] DatabaseError),
    /// An I/O error on a named file.
    #[error("{}: {source}", path.display())]
    Io {
        /// The file in question.
        path: PathBuf,
        /// What went wrong.
        #[source]
        source: std::io::Error,
    },
    /// An error while handling a named file; wraps the underlying error.
    #[error("{}: {source}", path.display())]
    File {
        /// The file in question.
        path: PathBuf,
        /// What went wrong with it.
        #[source]
        source: Box<SatfError>,
    },
}

/// Why an HRIR database file was rejected (see [`crate::database`] for the layout).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum DatabaseError {
    /// The file does not start with the magic bytes.
    #[error("not an HRIR database (bad magic bytes)")]
    BadMagic,
    /// The file has a format version this build does not read.
    #[error(
        "format version {found} is not supported (this build reads version {supported}); re-bake the database"
    )]
    UnsupportedVersion {
        /// Version in the file.
        found: u32,
        /// Version this build reads and writes.
        supported: u32,
    },
    /// The file is shorter or longer than its header says.
    #[error(
        "file is {found} bytes but its header describes {expected} bytes (truncated or padded)"
    )]
    Truncated {
        /// Size the header implies.
        expected: u64,
        /// Actual size.
        found: u64,
    },
    /// The checksum over the file does not match the stored one.
    #[error(
        "checksum mismatch (stored {stored:#018x}, computed {computed:#018x}): the file is corrupt"
    )]
    Checksum {
        /// Checksum stored in the file.
        stored: u64,
        /// Checksum of the bytes read.
        computed: u64,
    },
    /// The file was baked with settings other than the ones expected.
    #[error("baked with {field} = {found}, but {expected} is expected; re-bake the database")]
    SettingsMismatch {
        /// Name of the first differing setting.
        field: &'static str,
        /// Value in the file.
        found: String,
        /// Value expected by the caller.
        expected: String,
    },
    /// A header field or value is out of range.
    #[error("{0}")]
    Invalid(String),
}

impl SatfError {
    /// Attach the file name to an error (once).
    pub fn in_file(self, path: impl Into<PathBuf>) -> Self {
        match self {
            e @ (SatfError::File { .. } | SatfError::Io { .. }) => e,
            e => SatfError::File {
                path: path.into(),
                source: Box::new(e),
            },
        }
    }
}

/// Whether `x` lies in `(0, max]` (false for NaN).
pub(crate) fn in_open_closed(x: f32, max: f32) -> bool {
    x > 0.0 && x <= max
}

/// Shorthand for a [`SatfError::Parameter`] error.
pub(crate) fn param(msg: impl Into<String>) -> SatfError {
    SatfError::Parameter(msg.into())
}
