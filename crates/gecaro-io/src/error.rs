//! The one error type of `gecaro-io`.

use std::path::PathBuf;

/// Errors reading or writing gecaro files. Every variant names the file; parse
/// errors also name the line and, where there is one, the key or column.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// The file could not be read.
    #[error("cannot read {}: {cause}", .path.display())]
    Read {
        /// The file.
        path: PathBuf,
        /// Why (in the message, so not a separate source).
        cause: std::io::Error,
    },
    /// The file could not be written (nothing was left behind).
    #[error("cannot write {}: {message}", .path.display())]
    Write {
        /// The file.
        path: PathBuf,
        /// Why.
        message: String,
    },
    /// The output file exists and overwriting was not asked for.
    #[error("{} already exists", .path.display())]
    OutputExists {
        /// The file.
        path: PathBuf,
    },
    /// The file's content is wrong at a known place.
    #[error("{}:{line}: {}{message}", .path.display(), field_prefix(.field))]
    Parse {
        /// The file (or `<name>` for text that is not a file).
        path: PathBuf,
        /// 1-based line number.
        line: usize,
        /// The key or column at fault, if any.
        field: Option<String>,
        /// What is wrong.
        message: String,
    },
    /// A file's format cannot be told, or it cannot carry what is asked.
    #[error("{}: {message}", .path.display())]
    Format {
        /// The file.
        path: PathBuf,
        /// What is wrong and what to do.
        message: String,
    },
    /// Neither a file nor a ready robot has this name.
    #[error(
        "no robot file `{name}` and no ready robot of that name; ready robots: {}",
        .available.join(", ")
    )]
    UnknownRobot {
        /// The name or path as given.
        name: String,
        /// The ready robots.
        available: Vec<String>,
    },
}

fn field_prefix(field: &Option<String>) -> String {
    match field {
        Some(field) => format!("{field}: "),
        None => String::new(),
    }
}

impl Error {
    /// A [`Error::Parse`] of `path` at `line`, naming `field` when known.
    pub fn parse(
        path: impl Into<PathBuf>,
        line: usize,
        field: Option<String>,
        message: impl Into<String>,
    ) -> Self {
        Error::Parse {
            path: path.into(),
            line,
            field,
            message: message.into(),
        }
    }
}

/// The message of a TOML error, naming the key where the parser does not
/// ("duplicate key" says which from the text its span covers).
pub fn toml_message(error: &toml::de::Error, text: &str) -> String {
    let message = error.message().trim();
    if message == "duplicate key"
        && let Some(key) = error.span().and_then(|span| text.get(span))
    {
        let key = key.trim().trim_matches('"');
        if !key.is_empty() && key.len() <= 100 && !key.contains('\n') {
            return format!("duplicate key `{key}`: each key is given once per table");
        }
    }
    message.to_owned()
}

/// The 1-based line of the byte `offset` of `text` (offsets past the end
/// count as the last line; an offset inside a character is fine).
pub fn line_at(text: &str, offset: usize) -> usize {
    text.as_bytes()[..offset.min(text.len())]
        .iter()
        .filter(|byte| **byte == b'\n')
        .count()
        + 1
}
