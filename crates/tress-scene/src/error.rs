//! Typed errors of scene loading.

use std::path::PathBuf;

use tress_hair::HairError;

/// Everything that can go wrong reading, overriding, validating or loading a scene.
///
/// Each message is one line, so a command-line tool can print it as is.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    /// The scene file could not be read.
    #[error("cannot read the scene: {0}")]
    Io(#[from] std::io::Error),
    /// The text is not valid TOML, or does not match the scene format (an unknown key, a wrong
    /// type, a missing field). Names the position in the text.
    #[error("line {line}, column {column}: {message}")]
    Toml {
        /// 1-based line of the offending key or value.
        line: usize,
        /// 1-based column (in characters).
        column: usize,
        /// What is wrong, e.g. ``unknown field `fov`, expected one of `eye`, `target`, ...``.
        message: String,
    },
    /// A TOML error without a position in any file (e.g. in a value built in code).
    #[error("{0}")]
    TomlValue(String),
    /// A `--set key=value` override could not be applied, or made the scene invalid.
    #[error("--set `{set}`: {reason}")]
    Override {
        /// The override as given.
        set: String,
        /// What is wrong with it.
        reason: String,
    },
    /// A value is out of its range or contradicts another (named by its dotted key).
    #[error("{key}: {reason}")]
    Invalid {
        /// Dotted key of the value, e.g. `camera.near` or `hair.0.strand_ratio`.
        key: String,
        /// What is wrong, in words.
        reason: String,
    },
    /// The scene could not be written as TOML.
    #[error("cannot write the scene as TOML: {0}")]
    Serialize(String),
    /// Loading or generating the hair of one `[[hair]]` entry failed.
    #[error("hair.{index}: {source}")]
    Hair {
        /// Index of the `[[hair]]` entry.
        index: usize,
        /// The underlying error.
        #[source]
        source: HairError,
    },
    /// An error in a specific scene file; wraps the underlying error.
    #[error("{}: {source}", path.display())]
    File {
        /// The scene file.
        path: PathBuf,
        /// What went wrong in it.
        #[source]
        source: Box<SceneError>,
    },
}

impl SceneError {
    /// An [`SceneError::Invalid`] error.
    pub(crate) fn invalid(key: impl Into<String>, reason: impl Into<String>) -> Self {
        SceneError::Invalid {
            key: key.into(),
            reason: reason.into(),
        }
    }

    /// Attach the scene file's path (once: an error that already names a file is kept).
    pub fn in_file(self, path: impl Into<PathBuf>) -> Self {
        match self {
            e @ SceneError::File { .. } => e,
            e => SceneError::File {
                path: path.into(),
                source: Box::new(e),
            },
        }
    }

    /// A TOML deserialization error, positioned in `text` when it has a span.
    pub(crate) fn from_toml(error: &toml::de::Error, text: &str) -> Self {
        let message = one_line(error.message());
        match error.span() {
            Some(span) => {
                let (line, column) = line_column(text, span.start);
                SceneError::Toml {
                    line,
                    column,
                    message,
                }
            }
            None => SceneError::TomlValue(message),
        }
    }
}

/// Join a multi-line message into one line.
pub(crate) fn one_line(message: &str) -> String {
    message
        .trim()
        .lines()
        .map(str::trim)
        .collect::<Vec<_>>()
        .join("; ")
}

/// 1-based line and column (in characters) of byte `offset` in `text`.
pub(crate) fn line_column(text: &str, offset: usize) -> (usize, usize) {
    let mut offset = offset.min(text.len());
    while !text.is_char_boundary(offset) {
        offset -= 1;
    }
    let before = &text[..offset];
    let line = before.matches('\n').count() + 1;
    let line_start = before.rfind('\n').map_or(0, |i| i + 1);
    let column = text[line_start..offset].chars().count() + 1;
    (line, column)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn line_and_column() {
        let text = "a = 1\nbé = 2\n\nc = 3";
        assert_eq!(line_column(text, 0), (1, 1));
        assert_eq!(line_column(text, 6), (2, 1));
        // "é" is two bytes: the "=" after "bé " is the 4th character of line 2.
        assert_eq!(line_column(text, text.find("= 2").unwrap()), (2, 4));
        assert_eq!(line_column(text, text.find('c').unwrap()), (4, 1));
        assert_eq!(line_column(text, 999), (4, 6));
    }

    #[test]
    fn file_errors_name_the_file_once() {
        let e = SceneError::invalid("camera.near", "must be positive")
            .in_file("a.toml")
            .in_file("b.toml");
        assert_eq!(e.to_string(), "a.toml: camera.near: must be positive");
    }
}
