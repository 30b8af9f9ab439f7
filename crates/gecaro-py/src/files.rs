//! Paths as Python gives them and files written from Python: through the
//! application layer's [`LocalFiles`], atomically, an existing file kept
//! unless `overwrite`, an input never replaced.

use std::path::Path;

use gecaro_app::{Files, LocalFiles};
use pyo3::prelude::*;

use crate::errors::IntoPyResult;

/// A path or a ready robot's name as given (`str` or `os.PathLike`).
pub(crate) fn path_text(path: &Path) -> String {
    path.to_string_lossy().into_owned()
}

/// Writes `text` to `path` (a file of kind `extension`: "csv", "html", "toml").
pub(crate) fn write_text(
    path: &Path,
    extension: &str,
    text: &str,
    overwrite: bool,
) -> PyResult<()> {
    LocalFiles
        .write(&path_text(path), extension, text.as_bytes(), overwrite)
        .map(|_| ())
        .py()
}
