//! Writing outputs so that a failure never leaves a broken file.
//!
//! The bytes go to a temporary file in the destination folder, are flushed to
//! disk, and the temporary file is renamed over the destination: readers see
//! the old file or the new one, never a half-written one. An error at any step
//! removes the temporary file and leaves an existing destination untouched.
//!
//! Temporary files are named `.gecaro-<pid>-<n>.tmp` (a name a killed
//! process of the same pid left is removed and another taken). A process stopped by a
//! signal removes its own ([`remove_temporary_files`], called by the
//! `gecaro` binary's signal handler); one killed outright leaves them, and
//! the next write into that folder removes those of processes that no
//! longer run (Linux).
//!
//! An output that exists and is a FIFO or a character device (`/dev/null`,
//! a terminal) is written to, not replaced; a folder, a socket or a block
//! device is refused. An output that is an input of the same command is
//! refused ([`crate::roles`]).

use std::ffi::OsString;
use std::io::Write;
use std::path::Path;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Mutex, PoisonError};

use cap_std::ambient_authority;
use cap_std::fs::{Dir, OpenOptions};

use crate::{Error, roles};

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
/// [`Error::Write`] when the folder is missing or not writable, when `path`
/// is an input of this command, a folder, a socket or a block device, or
/// `-` ([`roles::check_output_name`]).
pub fn write_atomically(path: &Path, bytes: &[u8], policy: OutputPolicy) -> Result<(), Error> {
    write_with(path, policy, |file| file.write_all(bytes))
}

/// Writes `bytes` to the file `name` of the folder `folder` atomically, the
/// folder given by its handle, so that nothing a path could be swapped for
/// (a link, a renamed folder) moves the write elsewhere; `shown` names the
/// file in messages. An existing `name` must be a regular file.
///
/// # Errors
/// As [`write_atomically`].
pub fn write_in_folder(
    folder: &Dir,
    name: &Path,
    shown: &Path,
    bytes: &[u8],
    policy: OutputPolicy,
) -> Result<(), Error> {
    write_in(folder, name, shown, policy, |file| file.write_all(bytes))
}

/// Like [`write_atomically`], with the content produced by a writer callback
/// (a file written as it is computed); an error from the callback aborts the
/// write and leaves nothing behind.
///
/// # Errors
/// As [`write_atomically`]; the callback's error as [`Error::Write`].
pub fn write_with(
    path: &Path,
    policy: OutputPolicy,
    produce: impl FnOnce(&mut std::fs::File) -> std::io::Result<()>,
) -> Result<(), Error> {
    match Target::of(path)? {
        Target::Stream(mut file) => produce(&mut file).map_err(|error| Error::Write {
            path: path.to_owned(),
            message: error.to_string(),
        }),
        Target::Folder(dir, name) => write_in(&dir, Path::new(&name), path, policy, produce),
    }
}

/// Writes every one of `outputs` (path, bytes) or none (issue 75: an
/// identification's robot written, then its residuals failing on a full
/// disk): each is written to a temporary file and flushed first, and only
/// then are they all put in place. A failure before that replaces nothing;
/// putting them in place is a rename each. A FIFO or a terminal among them
/// is written last.
///
/// # Errors
/// As [`write_atomically`], for the first output at fault.
pub fn write_all_atomically(outputs: &[(&Path, &[u8])], policy: OutputPolicy) -> Result<(), Error> {
    let targets = outputs
        .iter()
        .map(|(path, _)| Target::of(path))
        .collect::<Result<Vec<_>, _>>()?;
    let mut staged = Vec::with_capacity(outputs.len());
    for (target, (path, bytes)) in targets.iter().zip(outputs) {
        if let Target::Folder(dir, name) = target {
            staged.push(stage(dir, Path::new(name), path, policy, |file| {
                file.write_all(bytes)
            })?);
        }
    }
    for staged in staged {
        staged.place()?;
    }
    for (target, (path, bytes)) in targets.into_iter().zip(outputs) {
        if let Target::Stream(mut file) = target {
            file.write_all(bytes).map_err(|error| Error::Write {
                path: path.to_path_buf(),
                message: error.to_string(),
            })?;
        }
    }
    Ok(())
}

/// Where an output goes: a stream written to as it is, or a name in a
/// folder, replaced atomically.
enum Target {
    /// A FIFO or a character device, opened for writing.
    Stream(std::fs::File),
    /// The folder (by its handle) and the file's name in it.
    Folder(Dir, std::ffi::OsString),
}

impl Target {
    /// The target of `path`, checked: not `-`, not an input of this
    /// command, not a folder, a socket or a block device, in a folder that
    /// exists.
    ///
    /// # Errors
    /// As [`write_atomically`].
    fn of(path: &Path) -> Result<Target, Error> {
        let failure = |message: String| Error::Write {
            path: path.to_owned(),
            message,
        };
        roles::check_output_name(path)?;
        roles::check_not_input(path)?;
        if let Ok(metadata) = std::fs::metadata(path) {
            if metadata.is_dir() {
                return Err(failure("it is a folder".into()));
            }
            if is_stream(&metadata) {
                let file = std::fs::OpenOptions::new()
                    .write(true)
                    .open(path)
                    .map_err(|error| failure(error.to_string()))?;
                return Ok(Target::Stream(file));
            }
            if !metadata.is_file() {
                return Err(failure(
                    "not a regular file, FIFO or terminal (a socket or a block device); give a file"
                        .into(),
                ));
            }
        }
        let folder = match path.parent() {
            Some(parent) if !parent.as_os_str().is_empty() => parent,
            _ => Path::new("."),
        };
        let name = path
            .file_name()
            .ok_or_else(|| failure("not a file name".into()))?;
        let dir = Dir::open_ambient_dir(folder, ambient_authority()).map_err(|error| {
            failure(
                if error.kind() == std::io::ErrorKind::NotFound || !folder.is_dir() {
                    format!("the folder {} does not exist", folder.display())
                } else {
                    error.to_string()
                },
            )
        })?;
        Ok(Target::Folder(dir, name.to_owned()))
    }
}

/// The atomic write itself, in a folder given by its handle.
fn write_in(
    folder: &Dir,
    name: &Path,
    shown: &Path,
    policy: OutputPolicy,
    produce: impl FnOnce(&mut std::fs::File) -> std::io::Result<()>,
) -> Result<(), Error> {
    stage(folder, name, shown, policy, produce)?.place()
}

/// An output written to its temporary file and flushed, to be put in place.
struct Staged<'a> {
    folder: &'a Dir,
    temporary: Temporary<'a>,
    name: &'a Path,
    shown: &'a Path,
    policy: OutputPolicy,
}

/// `produce`'s bytes in a temporary file beside `name`, flushed to disk.
fn stage<'a>(
    folder: &'a Dir,
    name: &'a Path,
    shown: &'a Path,
    policy: OutputPolicy,
    produce: impl FnOnce(&mut std::fs::File) -> std::io::Result<()>,
) -> Result<Staged<'a>, Error> {
    let failure = |message: String| Error::Write {
        path: shown.to_owned(),
        message,
    };
    let existing = folder.symlink_metadata(name).ok();
    if policy == OutputPolicy::KeepExisting && existing.is_some() {
        return Err(Error::OutputExists {
            path: shown.to_owned(),
        });
    }
    remove_stale_temporaries(folder);
    // A temporary name left by a killed process of the same pid (routine in
    // containers, issue 75) is taken: the dropped reservation removes that
    // stale file, and the next name is tried.
    let mut attempts = 0;
    let (temporary, mut file) = loop {
        let temporary = Temporary::create(folder, permissions_for(folder, name))
            .map_err(|error| failure(error.to_string()))?;
        match folder.open_with(&temporary.name, &temporary.options) {
            Ok(file) => break (temporary, file.into_std()),
            Err(error)
                if error.kind() == std::io::ErrorKind::AlreadyExists && attempts < 10_000 =>
            {
                attempts += 1;
            }
            Err(error) => return Err(failure(error.to_string())),
        }
    };
    produce(&mut file).map_err(|error| failure(error.to_string()))?;
    file.sync_all()
        .map_err(|error| failure(error.to_string()))?;
    drop(file);
    Ok(Staged {
        folder,
        temporary,
        name,
        shown,
        policy,
    })
}

impl Staged<'_> {
    /// Puts the staged file in place (the temporary file goes when dropped).
    fn place(self) -> Result<(), Error> {
        let (folder, name) = (self.folder, self.name);
        let placed = match self.policy {
            OutputPolicy::Overwrite => folder.rename(&self.temporary.name, folder, name),
            // A hard link fails when the name exists: no check-then-write race.
            OutputPolicy::KeepExisting => folder.hard_link(&self.temporary.name, folder, name),
        };
        placed.map_err(|error| {
            if error.kind() == std::io::ErrorKind::AlreadyExists {
                Error::OutputExists {
                    path: self.shown.to_owned(),
                }
            } else {
                Error::Write {
                    path: self.shown.to_owned(),
                    message: error.to_string(),
                }
            }
        })
    }
}

/// A FIFO or a character device: written to, never replaced.
fn is_stream(metadata: &std::fs::Metadata) -> bool {
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt as _;
        let kind = metadata.file_type();
        kind.is_fifo() || kind.is_char_device()
    }
    #[cfg(not(unix))]
    {
        let _ = metadata;
        false
    }
}

/// Temporary files being written, to remove on a signal.
static TEMPORARIES: Mutex<Vec<(u64, Dir, OsString)>> = Mutex::new(Vec::new());
static NEXT_TEMPORARY: AtomicU64 = AtomicU64::new(0);

/// One temporary file, removed when dropped (renamed away or not).
struct Temporary<'a> {
    folder: &'a Dir,
    name: OsString,
    id: u64,
    options: OpenOptions,
}

impl<'a> Temporary<'a> {
    /// Reserves a fresh name (the file is created by opening it with `options`).
    fn create(folder: &'a Dir, mode: Option<u32>) -> std::io::Result<Self> {
        let mut options = OpenOptions::new();
        options.write(true).create_new(true);
        #[cfg(unix)]
        if let Some(mode) = mode {
            use cap_std::fs::OpenOptionsExt as _;
            options.mode(mode);
        }
        #[cfg(not(unix))]
        let _ = mode;
        let id = NEXT_TEMPORARY.fetch_add(1, Ordering::Relaxed);
        let name = OsString::from(format!(".gecaro-{}-{id}.tmp", std::process::id()));
        TEMPORARIES
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .push((id, folder.try_clone()?, name.clone()));
        Ok(Temporary {
            folder,
            name,
            id,
            options,
        })
    }
}

impl Drop for Temporary<'_> {
    fn drop(&mut self) {
        let _ = self.folder.remove_file(&self.name);
        TEMPORARIES
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .retain(|(id, _, _)| *id != self.id);
    }
}

/// Removes the temporary files this process is writing, and keeps any
/// other from being created (writes that start afterwards wait forever):
/// for a signal handler, just before the process exits.
pub fn remove_temporary_files() {
    let temporaries = TEMPORARIES.lock().unwrap_or_else(PoisonError::into_inner);
    for (_, folder, name) in temporaries.iter() {
        let _ = folder.remove_file(name);
    }
    // Held until the process ends: a write racing the exit cannot create a
    // temporary file behind the removal.
    std::mem::forget(temporaries);
}

/// Removes the temporary files of gecaro processes that no longer run
/// (killed while writing), and those of this pid it is not writing (a
/// killed namesake's).
fn remove_stale_temporaries(folder: &Dir) {
    #[cfg(target_os = "linux")]
    {
        // Every write scans its folder: a cache by the folder's inode would
        // skip a new folder that took a removed one's inode.
        let Ok(metadata) = folder.dir_metadata() else {
            return;
        };
        let key = (
            cap_std::fs::MetadataExt::dev(&metadata),
            cap_std::fs::MetadataExt::ino(&metadata),
        );
        let Ok(entries) = folder.entries() else {
            return;
        };
        let own = std::process::id();
        for entry in entries.flatten() {
            let name = entry.file_name();
            let Some(pid) = name
                .to_str()
                .and_then(|name| name.strip_prefix(".gecaro-"))
                .and_then(|rest| rest.strip_suffix(".tmp"))
                .and_then(|rest| rest.split_once('-'))
                .and_then(|(pid, _)| pid.parse::<u32>().ok())
            else {
                continue;
            };
            // This process's own names are its temporaries being written;
            // any other of its pid is a killed namesake's.
            let alive = if pid == own {
                TEMPORARIES
                    .lock()
                    .unwrap_or_else(PoisonError::into_inner)
                    .iter()
                    .any(|(_, written_in, written)| {
                        *written == name
                            && written_in.dir_metadata().is_ok_and(|metadata| {
                                (
                                    cap_std::fs::MetadataExt::dev(&metadata),
                                    cap_std::fs::MetadataExt::ino(&metadata),
                                ) == key
                            })
                    })
            } else {
                Path::new(&format!("/proc/{pid}")).exists()
            };
            if !alive {
                let _ = folder.remove_file(&name);
            }
        }
    }
    #[cfg(not(target_os = "linux"))]
    let _ = folder;
}

/// The mode of the written file: that of the file it replaces, or read-write
/// for the owner and readable by others (0644) for a new one (Unix).
fn permissions_for(folder: &Dir, name: &Path) -> Option<u32> {
    #[cfg(unix)]
    {
        use cap_std::fs::PermissionsExt as _;
        Some(
            folder
                .metadata(name)
                .map_or(0o644, |metadata| metadata.permissions().mode() & 0o7777),
        )
    }
    #[cfg(not(unix))]
    {
        let _ = (folder, name);
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

    /// Temporary names a killed process of this pid left (containers reuse
    /// pids: issue 75, "cannot write X: File exists") are removed and the
    /// write goes through.
    #[test]
    fn a_killed_namesake_s_temporaries_do_not_stop_a_write() {
        let folder = tempfile::tempdir().expect("temporary folder");
        let next = NEXT_TEMPORARY.load(Ordering::Relaxed);
        for id in next..next + 64 {
            let stale = folder
                .path()
                .join(format!(".gecaro-{}-{id}.tmp", std::process::id()));
            std::fs::write(stale, "left by a killed process").expect("stale");
        }
        let path = folder.path().join("out.csv");
        write_atomically(&path, b"written", OutputPolicy::KeepExisting).expect("written");
        assert_eq!(std::fs::read_to_string(&path).expect("read"), "written");
        let left: Vec<_> = std::fs::read_dir(folder.path())
            .expect("list")
            .flatten()
            .map(|entry| entry.file_name())
            .collect();
        assert_eq!(left, ["out.csv"], "{left:?}");
    }

    /// Outputs written as a set: all, or none replaced (issue 75).
    #[test]
    fn a_set_of_outputs_is_written_whole_or_not_at_all() {
        let folder = tempfile::tempdir().expect("temporary folder");
        let (robot, residuals) = (folder.path().join("cal.toml"), folder.path().join("r.csv"));
        std::fs::write(&robot, "old robot").expect("old");
        let blocked = folder.path().join("a folder");
        std::fs::create_dir(&blocked).expect("folder");
        let refused = write_all_atomically(
            &[(&robot, b"new robot"), (&blocked, b"residuals")],
            OutputPolicy::Overwrite,
        );
        assert!(matches!(refused, Err(Error::Write { .. })), "{refused:?}");
        assert_eq!(std::fs::read_to_string(&robot).expect("read"), "old robot");
        // An existing output kept (the policy) stops the set before any is placed.
        std::fs::write(&residuals, "old residuals").expect("old");
        let kept = write_all_atomically(
            &[(&robot, b"new robot"), (&residuals, b"residuals")],
            OutputPolicy::KeepExisting,
        );
        assert!(matches!(kept, Err(Error::OutputExists { .. })), "{kept:?}");
        assert_eq!(std::fs::read_to_string(&robot).expect("read"), "old robot");
        write_all_atomically(
            &[(&robot, b"new robot"), (&residuals, b"residuals")],
            OutputPolicy::Overwrite,
        )
        .expect("written");
        assert_eq!(std::fs::read_to_string(&robot).expect("read"), "new robot");
        assert_eq!(
            std::fs::read_to_string(&residuals).expect("read"),
            "residuals"
        );
        let left = std::fs::read_dir(folder.path()).expect("list").count();
        assert_eq!(left, 3, "no temporary left");
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
