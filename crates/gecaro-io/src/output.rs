//! Writing outputs so that a failure never leaves a broken file.
//!
//! The bytes go to a temporary file in the destination folder, are flushed to
//! disk, and the temporary file is renamed over the destination: readers see
//! the old file or the new one, never a half-written one. An error at any step
//! removes the temporary file and leaves an existing destination untouched.

use std::io::Write;
use std::path::Path;

use crate::Error;

/// What to do when the destination already exists.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum OutputPolicy {
    /// Refuse with [`Error::OutputExists`].
    KeepExisting,
    /// Replace it (atomically).
    Overwrite,
}

/// Writes `bytes` to `path` atomically (see the module docs).
///
/// # Errors
/// [`Error::OutputExists`] when `path` exists and the policy keeps it;
/// [`Error::Write`] when the folder is missing or not writable.
pub fn write_atomically(path: &Path, bytes: &[u8], policy: OutputPolicy) -> Result<(), Error> {
    write_with(path, policy, |file| file.write_all(bytes))
}

/// Like [`write_atomically`], with the content produced by a writer callback;
/// an error from the callback aborts the write.
pub(crate) fn write_with(
    path: &Path,
    policy: OutputPolicy,
    produce: impl FnOnce(&mut std::fs::File) -> std::io::Result<()>,
) -> Result<(), Error> {
    let failure = |message: String| Error::Write {
        path: path.to_owned(),
        message,
    };
    if policy == OutputPolicy::KeepExisting && path.exists() {
        return Err(Error::OutputExists {
            path: path.to_owned(),
        });
    }
    let folder = match path.parent() {
        Some(parent) if !parent.as_os_str().is_empty() => parent,
        _ => Path::new("."),
    };
    if !folder.is_dir() {
        return Err(failure(format!(
            "the folder {} does not exist",
            folder.display()
        )));
    }
    let mut builder = tempfile::Builder::new();
    builder.prefix(".gecaro-").suffix(".tmp");
    if let Some(permissions) = permissions_for(path) {
        builder.permissions(permissions);
    }
    let mut temporary = builder
        .tempfile_in(folder)
        .map_err(|error| failure(error.to_string()))?;
    produce(temporary.as_file_mut()).map_err(|error| failure(error.to_string()))?;
    temporary
        .as_file()
        .sync_all()
        .map_err(|error| failure(error.to_string()))?;
    let persisted = match policy {
        OutputPolicy::Overwrite => temporary.persist(path).map(|_| ()),
        OutputPolicy::KeepExisting => temporary.persist_noclobber(path).map(|_| ()),
    };
    persisted.map_err(|error| {
        if error.error.kind() == std::io::ErrorKind::AlreadyExists {
            Error::OutputExists {
                path: path.to_owned(),
            }
        } else {
            failure(error.error.to_string())
        }
    })
}

/// The permissions of the written file: those of the file it replaces, or
/// read-write for the owner and readable by others (0644 on Unix) for a new
/// one. Temporary files are created private; an output must not stay so.
fn permissions_for(path: &Path) -> Option<std::fs::Permissions> {
    if let Ok(metadata) = std::fs::metadata(path) {
        return Some(metadata.permissions());
    }
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt as _;
        Some(std::fs::Permissions::from_mode(0o644))
    }
    #[cfg(not(unix))]
    {
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_failed_write_leaves_the_old_file_and_no_temporary() {
        let folder = tempfile::tempdir().expect("temporary folder");
        let path = folder.path().join("robot.toml");
        std::fs::write(&path, "old").expect("write");
        let result = write_with(&path, OutputPolicy::Overwrite, |file| {
            file.write_all(b"half")?;
            Err(std::io::Error::other("disk on fire"))
        });
        assert!(matches!(result, Err(Error::Write { .. })));
        assert_eq!(std::fs::read_to_string(&path).expect("read"), "old");
        assert_eq!(std::fs::read_dir(folder.path()).expect("list").count(), 1);
    }

    #[test]
    fn existing_files_are_kept_unless_asked() {
        let folder = tempfile::tempdir().expect("temporary folder");
        let path = folder.path().join("out.csv");
        write_atomically(&path, b"one", OutputPolicy::KeepExisting).expect("new file");
        assert!(matches!(
            write_atomically(&path, b"two", OutputPolicy::KeepExisting),
            Err(Error::OutputExists { .. })
        ));
        write_atomically(&path, b"three", OutputPolicy::Overwrite).expect("overwrite");
        assert_eq!(std::fs::read_to_string(&path).expect("read"), "three");
        #[cfg(unix)]
        {
            use std::os::unix::fs::PermissionsExt as _;
            let mode = std::fs::metadata(&path)
                .expect("metadata")
                .permissions()
                .mode();
            assert_eq!(
                mode & 0o777,
                0o644,
                "outputs are not private temporary files"
            );
        }
        let missing = folder.path().join("no/such/folder/out.csv");
        assert!(matches!(
            write_atomically(&missing, b"x", OutputPolicy::Overwrite),
            Err(Error::Write { .. })
        ));
    }
}
