//! Where a job writes its file ([`Output`]): the name a front end gives
//! (`-o` on the command line, `path=` in Python, `"save_as"` on the web)
//! and whether an existing file may be replaced (`--force`,
//! `overwrite=True`, `"overwrite": true`). Flattened into the requests that
//! write one, so the JSON keeps its two keys.

use std::path::PathBuf;

use serde::Deserialize;

use crate::error::AppError;
use crate::files::Files;

/// A job's output file (see the module docs).
#[derive(Clone, Debug, Default, Deserialize, PartialEq, Eq)]
pub struct Output {
    /// Write the file here; nothing is written without it.
    #[serde(default)]
    pub save_as: Option<String>,
    /// Replace an existing file.
    #[serde(default)]
    pub overwrite: bool,
}

impl Output {
    /// The file `name`, not replacing one that exists.
    pub fn to(name: impl Into<String>) -> Self {
        Output {
            save_as: Some(name.into()),
            overwrite: false,
        }
    }

    /// Refuses, before any work, an output that exists (unless
    /// `overwrite`) or cannot be written ([`Files::check_output`]).
    ///
    /// # Errors
    /// As [`Files::check_output`].
    pub fn check(&self, files: &dyn Files, extension: &str) -> Result<(), AppError> {
        match &self.save_as {
            Some(name) => files.check_output(name, extension, self.overwrite),
            None => Ok(()),
        }
    }

    /// Writes `bytes` when a name is given; returns the path written.
    ///
    /// # Errors
    /// As [`Files::write`].
    pub fn write(
        &self,
        files: &dyn Files,
        extension: &str,
        bytes: &[u8],
    ) -> Result<Option<PathBuf>, AppError> {
        self.save_as
            .as_ref()
            .map(|name| files.write(name, extension, bytes, self.overwrite))
            .transpose()
    }
}
