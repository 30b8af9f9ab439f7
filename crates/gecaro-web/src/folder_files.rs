//! The served folder as the jobs' [`Files`]: every name a request gives is
//! resolved inside the folder ([`Workspace`]), files are read whole within
//! [`MAX_FILE_BYTES`](crate::limits::MAX_FILE_BYTES) and named in messages
//! as the request named them; study files, whose data files could lie
//! anywhere, are not read here.

use std::path::PathBuf;

use gecaro_app::{AppError, ErrorKind, Files, Opened, OpenedBytes};

use crate::error::ApiError;
use crate::limits::MAX_SAMPLES;
use crate::workspace::Workspace;

/// An [`ApiError`] of the folder as the jobs' error.
fn app_error(error: ApiError) -> AppError {
    let kind = match &error {
        ApiError::BadRequest(_) => ErrorKind::Usage,
        ApiError::NotFound(_) => ErrorKind::NotFound,
        ApiError::Conflict(_) => ErrorKind::Exists,
        ApiError::Forbidden(_) => ErrorKind::Forbidden,
        ApiError::TooLarge(_) => ErrorKind::TooLarge,
        ApiError::Internal(_) => ErrorKind::Output,
        _ => ErrorKind::Input,
    };
    AppError::plain(kind, error.to_string())
}

impl Files for Workspace {
    fn open(&self, name: &str, extensions: &[&str]) -> Result<Opened, AppError> {
        let (_, text) = self.read_text(name, extensions).map_err(app_error)?;
        Ok(Opened {
            path: PathBuf::from(name),
            bytes: OpenedBytes::Whole(gecaro_io::WholeFile::Read(text.into_bytes())),
        })
    }

    fn read_text(&self, name: &str, extensions: &[&str]) -> Result<(PathBuf, String), AppError> {
        let (_, text) = Workspace::read_text(self, name, extensions).map_err(app_error)?;
        Ok((PathBuf::from(name), text))
    }

    fn is_file(&self, name: &str) -> bool {
        Workspace::is_file(self, name, &["toml", "csv", "urdf", "par", "yaml"])
    }

    fn is_same_file(&self, a: &str, b: &str) -> bool {
        Workspace::is_same_file(self, a, b)
    }

    fn check_output(&self, name: &str, extension: &str, overwrite: bool) -> Result<(), AppError> {
        self.check_writable(name, extension, overwrite)
            .map_err(app_error)
    }

    fn write(
        &self,
        name: &str,
        extension: &str,
        bytes: &[u8],
        overwrite: bool,
    ) -> Result<PathBuf, AppError> {
        Workspace::write(self, name, extension, bytes, overwrite).map_err(app_error)
    }

    fn remove(&self, name: &str) {
        Workspace::remove(self, name, &["yaml", "toml", "urdf", "csv", "svg"]);
    }

    fn max_samples(&self) -> usize {
        MAX_SAMPLES
    }
}
