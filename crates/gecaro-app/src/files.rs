//! Where a front end's files are: the jobs read and write files only
//! through [`Files`], so that the command line and Python work on the file
//! system as it is ([`LocalFiles`]) while the web page stays inside its
//! served folder.
//!
//! Names are what the user gave: a path on the command line and in Python,
//! a name relative to the served folder on the web page. Every output is
//! checked before any work ([`Files::check_output`]) and written atomically
//! ([`gecaro_io::write_atomically`]).

use std::io::{Read, Write};
use std::path::{Path, PathBuf};

use gecaro_io::OutputPolicy;

use crate::error::{AppError, ErrorKind};

/// An opened input: its path for messages, and its bytes.
pub struct Opened {
    /// The file as messages name it.
    pub path: PathBuf,
    /// Its content.
    pub bytes: OpenedBytes,
}

/// An opened input's content.
pub enum OpenedBytes {
    /// All of it in memory, read where it lies: a small local file mapped
    /// ([`gecaro_io::map_small`]), a served folder's text.
    Whole(gecaro_io::WholeFile),
    /// A stream to be read once, and its length in bytes when known (for
    /// progress, and room for a long file's rows).
    Stream {
        /// The content.
        reader: Box<dyn Read + Send>,
        /// Its length in bytes, when known.
        length: Option<u64>,
    },
}

impl OpenedBytes {
    /// The content as a reader of it takes it.
    pub fn content(&mut self) -> gecaro_io::Content<'_> {
        match self {
            OpenedBytes::Whole(whole) => gecaro_io::Content::Whole(whole),
            OpenedBytes::Stream { reader, length } => gecaro_io::Content::Stream(reader, *length),
        }
    }

    /// Its length in bytes, when known.
    pub fn length(&self) -> Option<u64> {
        match self {
            OpenedBytes::Whole(whole) => u64::try_from(whole.len()).ok(),
            OpenedBytes::Stream { length, .. } => *length,
        }
    }

    /// The content as a stream, read once from its start.
    pub fn into_reader(self) -> Box<dyn Read + Send> {
        match self {
            OpenedBytes::Whole(whole) => Box::new(std::io::Cursor::new(whole)),
            OpenedBytes::Stream { reader, .. } => reader,
        }
    }
}

/// Reading and writing the files a request names; see the module docs.
pub trait Files: Sync {
    /// Opens `name` for reading, record by record (data and program files).
    /// `extensions` are those the job expects; a front end may refuse others.
    ///
    /// # Errors
    /// A file that cannot be opened, is not a regular file, or may not be used.
    fn open(&self, name: &str, extensions: &[&str]) -> Result<Opened, AppError>;

    /// The whole text of `name` (robot files, URDFs, tables), with its path
    /// for messages.
    ///
    /// # Errors
    /// As [`open`](Self::open), and text that is not UTF-8 or too large.
    fn read_text(&self, name: &str, extensions: &[&str]) -> Result<(PathBuf, String), AppError>;

    /// Whether `name` is a file this front end can read.
    fn is_file(&self, name: &str) -> bool;

    /// Whether `a` and `b` name one existing file (an output named as an
    /// input; issue 75). By name here; [`LocalFiles`] by the file itself.
    fn is_same_file(&self, a: &str, b: &str) -> bool {
        a == b
    }

    /// Refuses, before any work, an output `name` that exists (unless
    /// `overwrite`), cannot be written, or is an input or another output of
    /// the same command; `extension` is the one expected, and tells the job's
    /// outputs apart.
    ///
    /// # Errors
    /// [`ErrorKind::Exists`], or a name or folder that cannot be used.
    fn check_output(&self, name: &str, extension: &str, overwrite: bool) -> Result<(), AppError>;

    /// Writes `bytes` to `name` atomically; returns the path written.
    ///
    /// # Errors
    /// As [`check_output`](Self::check_output), and a failed write (which
    /// leaves nothing behind).
    fn write(
        &self,
        name: &str,
        extension: &str,
        bytes: &[u8],
        overwrite: bool,
    ) -> Result<PathBuf, AppError>;

    /// Writes every one of `outputs` (name, extension, bytes) or none, as
    /// far as the front end can: [`LocalFiles`] stages them all before it
    /// replaces any (`gecaro_io::write_all_atomically`); this default writes
    /// them one after the other. Returns the paths written.
    ///
    /// # Errors
    /// As [`write`](Self::write).
    fn write_all(
        &self,
        outputs: &[(&str, &str, &[u8])],
        overwrite: bool,
    ) -> Result<Vec<PathBuf>, AppError> {
        outputs
            .iter()
            .map(|(name, extension, bytes)| self.write(name, extension, bytes, overwrite))
            .collect()
    }

    /// Writes to `name` atomically what `produce` writes, as it produces it
    /// (a corrected program written as it is read); returns the path
    /// written. An error of `produce` leaves nothing behind and is returned.
    /// This default holds the bytes in memory and writes them at the end;
    /// [`LocalFiles`] writes them as they come.
    ///
    /// # Errors
    /// As [`write`](Self::write), and `produce`'s.
    fn write_streamed(
        &self,
        name: &str,
        extension: &str,
        overwrite: bool,
        produce: &mut dyn FnMut(&mut dyn Write) -> Result<(), AppError>,
    ) -> Result<PathBuf, AppError> {
        let mut bytes = Vec::new();
        produce(&mut bytes)?;
        self.write(name, extension, &bytes, overwrite)
    }

    /// Removes the file `name` written by this job (a half of a pair of
    /// files whose other half could not be written); failures are ignored.
    fn remove(&self, name: &str);

    /// The most configurations a data set may hold here.
    fn max_samples(&self) -> usize {
        gecaro_io::MAX_CONFIGURATIONS
    }
}

/// The file system as it is: the command line's and Python's files.
#[derive(Copy, Clone, Debug, Default)]
pub struct LocalFiles;

/// What an overwrite flag says of an existing output.
pub(crate) fn policy(overwrite: bool) -> OutputPolicy {
    if overwrite {
        OutputPolicy::Overwrite
    } else {
        OutputPolicy::KeepExisting
    }
}

impl Files for LocalFiles {
    fn open(&self, name: &str, _: &[&str]) -> Result<Opened, AppError> {
        let path = PathBuf::from(name);
        let file = gecaro_io::open_input(&path)?;
        let length = file.metadata().ok().map(|metadata| metadata.len());
        let bytes = match length.and_then(|length| gecaro_io::map_small(&file, length)) {
            Some(whole) => OpenedBytes::Whole(whole),
            None => OpenedBytes::Stream {
                reader: Box::new(std::io::BufReader::with_capacity(1 << 16, file)),
                length,
            },
        };
        Ok(Opened { path, bytes })
    }

    fn read_text(&self, name: &str, _: &[&str]) -> Result<(PathBuf, String), AppError> {
        let path = PathBuf::from(name);
        let text = gecaro_io::read_description(&path)?;
        Ok((path, text))
    }

    fn is_file(&self, name: &str) -> bool {
        Path::new(name).is_file()
    }

    fn is_same_file(&self, a: &str, b: &str) -> bool {
        match (std::fs::canonicalize(a), std::fs::canonicalize(b)) {
            (Ok(a), Ok(b)) => a == b,
            _ => false,
        }
    }

    fn check_output(&self, name: &str, extension: &str, overwrite: bool) -> Result<(), AppError> {
        let path = Path::new(name);
        gecaro_io::roles::claim_output(path, extension)?;
        // A FIFO or a device is written to, not replaced: no --force needed.
        let replaced = std::fs::metadata(path).map_or_else(
            |_| std::fs::symlink_metadata(path).is_ok(),
            |metadata| metadata.is_file() || metadata.is_dir(),
        );
        if !overwrite && replaced {
            return Err(AppError::exists(path));
        }
        let folder = path
            .parent()
            .filter(|p| !p.as_os_str().is_empty())
            .unwrap_or(Path::new("."));
        if !folder.is_dir() {
            return Err(AppError::plain(
                ErrorKind::Output,
                format!(
                    "cannot write {}: the folder {} does not exist",
                    path.display(),
                    folder.display()
                ),
            ));
        }
        Ok(())
    }

    fn write(
        &self,
        name: &str,
        _: &str,
        bytes: &[u8],
        overwrite: bool,
    ) -> Result<PathBuf, AppError> {
        let path = PathBuf::from(name);
        gecaro_io::write_atomically(&path, bytes, policy(overwrite))?;
        Ok(path)
    }

    fn write_all(
        &self,
        outputs: &[(&str, &str, &[u8])],
        overwrite: bool,
    ) -> Result<Vec<PathBuf>, AppError> {
        let paths: Vec<PathBuf> = outputs
            .iter()
            .map(|(name, _, _)| PathBuf::from(name))
            .collect();
        let staged: Vec<(&Path, &[u8])> = paths
            .iter()
            .zip(outputs)
            .map(|(path, (_, _, bytes))| (path.as_path(), *bytes))
            .collect();
        gecaro_io::write_all_atomically(&staged, policy(overwrite))?;
        Ok(paths)
    }

    fn write_streamed(
        &self,
        name: &str,
        _: &str,
        overwrite: bool,
        produce: &mut dyn FnMut(&mut dyn Write) -> Result<(), AppError>,
    ) -> Result<PathBuf, AppError> {
        let path = PathBuf::from(name);
        // The producer's own error, carried through the write it stops.
        let mut stopped = None;
        let written = gecaro_io::write_with(&path, policy(overwrite), |file| {
            produce(file).map_err(|error| {
                stopped = Some(error);
                std::io::Error::other("stopped")
            })
        });
        match (stopped, written) {
            (Some(error), _) => Err(error),
            (None, written) => Ok(written.map(|()| path)?),
        }
    }

    fn remove(&self, name: &str) {
        let _ = std::fs::remove_file(name);
    }
}
