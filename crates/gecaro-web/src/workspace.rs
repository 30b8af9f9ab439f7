//! The folder the server works in (`--dir`): the only place it reads robot
//! and data files from and writes them to.
//!
//! Names in requests are relative paths with `/` separators (`robots/arm.toml`).
//! A name is refused unless every component is a plain name of at most 255
//! bytes: no `..`, no absolute paths or drive letters, no hidden components
//! (`.git`), no backslashes, no control or bidirectional-override characters
//! (a newline or U+202E in a name would forge what a listing or a message
//! shows).
//!
//! Every file is reached from the folder's open handle
//! ([`cap_std::fs::Dir`]): each component is resolved beneath it (with
//! `openat2(RESOLVE_BENEATH)` on Linux), so no name, link or concurrent
//! rename of a subfolder can lead a read or a write out of the folder; a
//! link that would is refused. Writes are atomic
//! ([`gecaro_io::write_in_folder`], into the handle of the file's own
//! folder) and serialised, so a failed or concurrent save never leaves a
//! broken file, and never writes through a link.

use std::io::Read;
use std::path::{Component, Path, PathBuf};
use std::sync::Mutex;

use cap_std::ambient_authority;
use cap_std::fs::Dir;
use gecaro_io::OutputPolicy;
use serde::Serialize;

use crate::error::ApiError;
use crate::limits::{MAX_FILE_BYTES, MAX_LISTED};

/// Folders not worth listing: build outputs and dependencies.
const SKIPPED_FOLDERS: &[&str] = &["target", "node_modules"];
/// How deep the listing goes below the folder.
const LISTING_DEPTH: usize = 4;
/// The bytes of a data file read for its header when the folder is listed.
const HEADER_BYTES: u64 = 8192;
/// Longest component of a name, in bytes (the usual file-system limit).
const MAX_COMPONENT_BYTES: usize = 255;

/// The sandboxed folder.
#[derive(Debug)]
pub struct Workspace {
    root: PathBuf,
    folder: Dir,
    writing: Mutex<()>,
    /// Held across the writes of a pair of files (a URDF and its joint
    /// calibration): both from one save, or neither.
    pairs: Mutex<()>,
}

/// The robot and data files of the folder, as names relative to it.
#[derive(Debug, Default, Serialize)]
pub struct Listing {
    /// The folder (absolute), for display.
    pub folder: String,
    /// `*.toml` files.
    pub robots: Vec<String>,
    /// `*.csv` files.
    pub data: Vec<String>,
    /// Robots in other formats, converted when opened: `*.urdf`, `*.par`.
    pub imports: Vec<String>,
    /// The column names of each data file's header (read from its first
    /// `HEADER_BYTES` bytes), for menus that list only the files a method
    /// can read; a file whose header could not be read has none here.
    pub data_columns: std::collections::BTreeMap<String, Vec<String>>,
    /// Whether the listing stopped at its limit.
    pub truncated: bool,
}

impl Workspace {
    /// The workspace of `folder`, which must exist.
    ///
    /// # Errors
    /// When the folder does not exist or is not a folder.
    pub fn new(folder: &Path) -> std::io::Result<Self> {
        let root = folder.canonicalize()?;
        if !root.is_dir() {
            return Err(std::io::Error::new(
                std::io::ErrorKind::NotADirectory,
                format!("{} is not a folder", root.display()),
            ));
        }
        let handle = Dir::open_ambient_dir(&root, ambient_authority())?;
        Ok(Workspace {
            root,
            folder: handle,
            writing: Mutex::new(()),
            pairs: Mutex::new(()),
        })
    }

    /// The folder, absolute.
    pub fn root(&self) -> &Path {
        &self.root
    }

    /// Where the file `name` is, for display (nothing is resolved).
    ///
    /// # Errors
    /// [`ApiError::Forbidden`] for a name that is not one (see the module docs).
    pub fn display_path(&self, name: &str) -> Result<PathBuf, ApiError> {
        Ok(self.root.join(Self::relative(name)?))
    }

    /// The robot and data files, sorted, at most [`MAX_LISTED`] of each.
    pub fn list(&self) -> Listing {
        let mut listing = Listing {
            folder: self.root.display().to_string(),
            ..Listing::default()
        };
        walk(&self.folder, "", 0, &mut listing);
        listing.robots.sort();
        listing.data.sort();
        listing.imports.sort();
        listing
    }

    /// `name` checked as a relative path of plain components.
    fn relative(name: &str) -> Result<PathBuf, ApiError> {
        let refuse = |why: &str| Err(ApiError::Forbidden(format!("file name {name:?}: {why}")));
        if name.is_empty() {
            return refuse("empty");
        }
        if name.len() > 1024 {
            return refuse("too long (more than 1024 bytes)");
        }
        if name.contains('\\') || name.contains(':') {
            return refuse("use / between folders; no \\ or : characters");
        }
        if name.chars().any(gecaro_io::is_hidden_character) {
            return refuse(
                "control characters (newline, tab, escape) and text-direction marks are not allowed in names",
            );
        }
        // The name as written: `Path::components` would skip a `.` inside
        // (`a/./b.toml`) and a trailing `/` (`x.toml/`), and the name saved
        // would not be the name given.
        for part in name.split('/') {
            if part.is_empty() {
                return refuse("no empty folder names (`//`, a leading or trailing `/`)");
            }
            if part == "." {
                return refuse("no `.` components");
            }
        }
        let path = PathBuf::from(name);
        for component in path.components() {
            match component {
                Component::Normal(part) => {
                    if part.to_string_lossy().starts_with('.') {
                        return refuse("hidden files and folders are not served");
                    }
                    if part.len() > MAX_COMPONENT_BYTES {
                        return refuse("a folder or file name longer than 255 bytes");
                    }
                }
                Component::ParentDir => return refuse("`..` would leave the folder"),
                Component::RootDir | Component::Prefix(_) => {
                    return refuse("give a name relative to the folder, not an absolute path");
                }
                Component::CurDir => return refuse("no `.` components"),
            }
        }
        Ok(path)
    }

    /// The error of a file-system operation on `name` beneath the folder.
    fn io_error(&self, name: &str, error: &std::io::Error) -> ApiError {
        match error.kind() {
            std::io::ErrorKind::NotFound => {
                ApiError::NotFound(format!("no file {name} in {}", self.root.display()))
            }
            std::io::ErrorKind::PermissionDenied => ApiError::Forbidden(format!(
                "{name} leads outside the folder {} (through a link), or may not be read",
                self.root.display()
            )),
            _ => ApiError::Unprocessable(format!("cannot use {name}: {error}")),
        }
    }

    /// Whether `a` and `b` name one file of the folder (`./job.csv` and
    /// `job.csv`).
    pub fn is_same_file(&self, a: &str, b: &str) -> bool {
        matches!((Self::relative(a), Self::relative(b)), (Ok(a), Ok(b)) if a == b)
    }

    /// Whether `name` (with one of `extensions`) is an existing regular file.
    pub fn is_file(&self, name: &str, extensions: &[&str]) -> bool {
        Self::relative(name)
            .and_then(|relative| check_extensions(&relative, name, extensions).map(|()| relative))
            .is_ok_and(|relative| {
                self.folder
                    .metadata(relative)
                    .is_ok_and(|metadata| metadata.is_file())
            })
    }

    /// Removes the file `name` (one of `extensions`); failures are ignored.
    pub fn remove(&self, name: &str, extensions: &[&str]) {
        if let Ok(relative) = Self::relative(name)
            && check_extensions(&relative, name, extensions).is_ok()
        {
            let _ = self.folder.remove_file(relative);
        }
    }

    /// The text of the existing file `name` (at most [`MAX_FILE_BYTES`]),
    /// with its name as a path.
    ///
    /// # Errors
    /// [`ApiError::Forbidden`] for names outside the folder or of another
    /// kind, [`ApiError::NotFound`] when there is no such file,
    /// [`ApiError::TooLarge`] for big files.
    pub fn read_text(
        &self,
        name: &str,
        extensions: &[&str],
    ) -> Result<(PathBuf, String), ApiError> {
        let relative = Self::relative(name)?;
        check_extensions(&relative, name, extensions)?;
        // Not opened unless it is a regular file: a FIFO would block the open.
        let metadata = self
            .folder
            .metadata(&relative)
            .map_err(|error| self.io_error(name, &error))?;
        if !metadata.is_file() {
            return Err(ApiError::NotFound(format!("{name} is not a file")));
        }
        // Non-blocking, and checked again once open: a FIFO swapped in after
        // the check above must not hold a worker thread in `open`.
        let mut options = cap_std::fs::OpenOptions::new();
        options.read(true);
        #[cfg(unix)]
        {
            use cap_std::fs::OpenOptionsExt as _;
            options.custom_flags(rustix::fs::OFlags::NONBLOCK.bits() as i32);
        }
        let file = self
            .folder
            .open_with(&relative, &options)
            .map_err(|error| self.io_error(name, &error))?;
        let opened = file
            .metadata()
            .map_err(|error| self.io_error(name, &error))?;
        if !opened.is_file() {
            return Err(ApiError::NotFound(format!("{name} is not a file")));
        }
        let size = opened.len();
        if size > MAX_FILE_BYTES {
            return Err(ApiError::TooLarge(format!(
                "{name} has {size} bytes; the server reads files up to {} MiB",
                MAX_FILE_BYTES >> 20
            )));
        }
        let mut text = String::new();
        file.into_std()
            .take(MAX_FILE_BYTES)
            .read_to_string(&mut text)
            .map_err(|error| ApiError::Unprocessable(format!("cannot read {name}: {error}")))?;
        Ok((relative, text))
    }

    /// The handle of the folder holding the output `name` (extension
    /// `extension`), and the file's own name in it.
    fn output_place(&self, name: &str, extension: &str) -> Result<(Dir, PathBuf), ApiError> {
        let relative = Self::relative(name)?;
        check_extensions(&relative, name, &[extension])?;
        let file_name = relative
            .file_name()
            .map(PathBuf::from)
            .ok_or_else(|| ApiError::Forbidden(format!("file name {name:?}: not a file name")))?;
        let folder = match relative.parent() {
            Some(parent) if !parent.as_os_str().is_empty() => self
                .folder
                .open_dir(parent)
                .map_err(|error| match error.kind() {
                    std::io::ErrorKind::NotFound | std::io::ErrorKind::NotADirectory => {
                        ApiError::NotFound(format!("the folder of {name} does not exist"))
                    }
                    _ => self.io_error(name, &error),
                })?,
            _ => self
                .folder
                .try_clone()
                .map_err(|error| ApiError::Internal(error.to_string()))?,
        };
        Ok((folder, file_name))
    }

    /// Refuses, before any work, to write the file `name` (extension
    /// `extension`): a name outside the folder or of another kind, a missing
    /// subfolder, an existing file without `overwrite`.
    ///
    /// # Errors
    /// As [`write`](Self::write), but for the write itself.
    pub fn check_writable(
        &self,
        name: &str,
        extension: &str,
        overwrite: bool,
    ) -> Result<(), ApiError> {
        let (folder, file_name) = self.output_place(name, extension)?;
        if let Ok(metadata) = folder.symlink_metadata(&file_name) {
            // Refused here, before any file of a save is written, as the
            // write itself would refuse it (a URDF and its joint calibration
            // are both written or neither).
            refuse_unwritable(name, &metadata)?;
            if !overwrite {
                return Err(ApiError::Conflict(format!(
                    "{name} already exists; save with overwrite to replace it"
                )));
            }
        }
        Ok(())
    }

    /// Runs `write` (the writes of a pair of files) while no other pair is
    /// written: two saves of one URDF never leave the URDF of one and the
    /// joint calibration of the other.
    pub fn writing_pair<T>(&self, write: impl FnOnce() -> T) -> T {
        let _guard = self
            .pairs
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        write()
    }

    /// Writes `bytes` to the file `name` (extension `extension`) atomically;
    /// an existing file is replaced only when `overwrite` is set. Returns
    /// where it is, for display.
    ///
    /// # Errors
    /// [`ApiError::Forbidden`] outside the folder or onto a link,
    /// [`ApiError::NotFound`] when the subfolder does not exist,
    /// [`ApiError::Conflict`] when the file exists, [`ApiError::Internal`]
    /// when writing fails (nothing is left behind).
    pub fn write(
        &self,
        name: &str,
        extension: &str,
        bytes: &[u8],
        overwrite: bool,
    ) -> Result<PathBuf, ApiError> {
        let (folder, file_name) = self.output_place(name, extension)?;
        // Held across the check and the rename: saves do not interleave.
        let _guard = self
            .writing
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        if let Ok(metadata) = folder.symlink_metadata(&file_name) {
            refuse_unwritable(name, &metadata)?;
        }
        let policy = if overwrite {
            OutputPolicy::Overwrite
        } else {
            OutputPolicy::KeepExisting
        };
        gecaro_io::write_in_folder(&folder, &file_name, Path::new(name), bytes, policy).map_err(
            |error| match error {
                gecaro_io::Error::OutputExists { .. } => ApiError::Conflict(format!(
                    "{name} already exists; save with overwrite to replace it"
                )),
                other => ApiError::Internal(other.to_string()),
            },
        )?;
        self.display_path(name)
    }
}

/// Lists `folder` into `listing` (names prefixed by `prefix`), through
/// subfolder handles: links are neither listed nor followed.
fn walk(folder: &Dir, prefix: &str, depth: usize, listing: &mut Listing) {
    let Ok(entries) = folder.entries() else {
        return;
    };
    let mut entries: Vec<_> = entries.filter_map(Result::ok).collect();
    entries.sort_by_key(cap_std::fs::DirEntry::file_name);
    for entry in entries {
        let Some(name) = entry.file_name().to_str().map(str::to_owned) else {
            continue;
        };
        let Ok(kind) = entry.file_type() else {
            continue;
        };
        if name.starts_with('.')
            || kind.is_symlink()
            || name.chars().any(gecaro_io::is_hidden_character)
        {
            continue;
        }
        let relative = format!("{prefix}{name}");
        if kind.is_dir() {
            if depth + 1 < LISTING_DEPTH
                && !SKIPPED_FOLDERS.contains(&name.as_str())
                && let Ok(subfolder) = entry.open_dir()
            {
                walk(&subfolder, &format!("{relative}/"), depth + 1, listing);
            }
            continue;
        }
        if !kind.is_file() {
            continue;
        }
        let bucket = match Path::new(&name).extension().and_then(|e| e.to_str()) {
            Some("toml") => &mut listing.robots,
            Some("csv") => &mut listing.data,
            Some("urdf" | "par") => &mut listing.imports,
            _ => continue,
        };
        if bucket.len() >= MAX_LISTED {
            listing.truncated = true;
            continue;
        }
        bucket.push(relative.clone());
        if name.ends_with(".csv")
            && let Some(columns) = header_of(folder, &name)
        {
            listing.data_columns.insert(relative, columns);
        }
    }
}

/// The column names of data file `name` of `folder` (see [`Listing::data_columns`]).
fn header_of(folder: &Dir, name: &str) -> Option<Vec<String>> {
    let mut head = Vec::new();
    folder
        .open(name)
        .ok()?
        .take(HEADER_BYTES)
        .read_to_end(&mut head)
        .ok()?;
    gecaro_io::header_names(&head, (head.len() as u64) < HEADER_BYTES)
}

fn check_extensions(relative: &Path, name: &str, extensions: &[&str]) -> Result<(), ApiError> {
    // `ARM.TOML` is a `.toml` file, as the command line reads it (issue 75).
    let extension = relative.extension().and_then(|e| e.to_str());
    if extension.is_some_and(|extension| {
        extensions
            .iter()
            .any(|wanted| wanted.eq_ignore_ascii_case(extension))
    }) {
        Ok(())
    } else {
        Err(ApiError::Forbidden(format!(
            "file name {name:?}: only {} files here",
            extensions
                .iter()
                .map(|extension| format!(".{extension}"))
                .collect::<Vec<_>>()
                .join(", ")
        )))
    }
}

/// Refuses an existing output `name` that is a link (the server never
/// writes through one) or not a regular file.
fn refuse_unwritable(name: &str, metadata: &cap_std::fs::Metadata) -> Result<(), ApiError> {
    if metadata.file_type().is_symlink() {
        return Err(ApiError::Forbidden(format!(
            "{name} is a link; the server does not write through links"
        )));
    }
    if !metadata.is_file() {
        return Err(ApiError::Conflict(format!(
            "{name} exists and is not a file"
        )));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_that_leave_the_folder_are_refused() {
        let folder = tempfile::tempdir().expect("folder");
        let workspace = Workspace::new(folder.path()).expect("workspace");
        for name in [
            "../x.toml",
            "a/../../x.toml",
            "/etc/passwd.toml",
            ".hidden.toml",
            "a/.git/x.toml",
            "a\\..\\x.toml",
            "C:x.toml",
            "",
            "./x.toml",
        ] {
            assert!(
                matches!(
                    workspace.write(name, "toml", b"x", true),
                    Err(ApiError::Forbidden(_))
                ),
                "{name}"
            );
            assert!(
                matches!(
                    workspace.read_text(name, &["toml"]),
                    Err(ApiError::Forbidden(_))
                ),
                "{name}"
            );
        }
        assert!(matches!(
            workspace.write("robot.txt", "toml", b"x", true),
            Err(ApiError::Forbidden(_))
        ));
        assert_eq!(std::fs::read_dir(folder.path()).expect("list").count(), 0);
    }

    #[cfg(unix)]
    #[test]
    fn links_out_of_the_folder_are_refused() {
        let outside = tempfile::tempdir().expect("outside");
        let secret = outside.path().join("secret.toml");
        std::fs::write(&secret, "name = \"secret\"").expect("write");
        let folder = tempfile::tempdir().expect("folder");
        std::os::unix::fs::symlink(&secret, folder.path().join("link.toml")).expect("link");
        std::os::unix::fs::symlink(outside.path(), folder.path().join("out")).expect("link");
        let workspace = Workspace::new(folder.path()).expect("workspace");
        assert!(matches!(
            workspace.read_text("link.toml", &["toml"]),
            Err(ApiError::Forbidden(_))
        ));
        assert!(matches!(
            workspace.read_text("out/secret.toml", &["toml"]),
            Err(ApiError::Forbidden(_))
        ));
        assert!(matches!(
            workspace.write("out/new.toml", "toml", b"x", true),
            Err(ApiError::Forbidden(_))
        ));
        assert!(matches!(
            workspace.write("link.toml", "toml", b"x", true),
            Err(ApiError::Forbidden(_))
        ));
        assert_eq!(
            std::fs::read_to_string(&secret).expect("read"),
            "name = \"secret\""
        );
        assert!(!outside.path().join("new.toml").exists());
        // Links are not listed.
        assert!(workspace.list().robots.is_empty());
    }

    #[test]
    fn names_with_controls_or_overlong_components_are_refused() {
        let folder = tempfile::tempdir().expect("folder");
        let workspace = Workspace::new(folder.path()).expect("workspace");
        let long = format!("{}.toml", "a".repeat(300));
        for name in [
            "new\nline.toml",
            "tab\t.toml",
            "cr\r.toml",
            "esc\u{1b}[31m.toml",
            "evil\u{202e}lmot.toml",
            "nul\0.toml",
            "arabic\u{061c}mark.toml",
            "line\u{2028}sep.toml",
            "para\u{2029}sep.toml",
            "zero\u{200b}width.toml",
            "bom\u{feff}.toml",
            "x.toml/",
            "a/./b.toml",
            "a//b.toml",
            long.as_str(),
        ] {
            assert!(
                matches!(
                    workspace.write(name, "toml", b"x", true),
                    Err(ApiError::Forbidden(_))
                ),
                "{name:?}"
            );
            assert!(
                matches!(
                    workspace.check_writable(name, "toml", true),
                    Err(ApiError::Forbidden(_))
                ),
                "{name:?}"
            );
        }
        assert_eq!(std::fs::read_dir(folder.path()).expect("list").count(), 0);
    }

    /// A subfolder swapped for a link to another folder while saves and
    /// reads go on: no write lands outside, no read returns an outside
    /// file, no temporary file stays anywhere.
    #[cfg(unix)]
    #[test]
    fn a_subfolder_swapped_for_a_link_never_leads_out() {
        use std::sync::atomic::{AtomicBool, Ordering};
        let outside = tempfile::tempdir().expect("outside");
        std::fs::write(outside.path().join("secret.toml"), "outside").expect("write");
        let folder = tempfile::tempdir().expect("folder");
        let sub = folder.path().join("sub");
        let parked = folder.path().join("parked");
        std::fs::create_dir(&sub).expect("mkdir");
        std::fs::write(sub.join("secret.toml"), "inside").expect("write");
        let workspace = Workspace::new(folder.path()).expect("workspace");
        let stop = AtomicBool::new(false);
        std::thread::scope(|scope| {
            scope.spawn(|| {
                // sub ⇄ link to outside, 2,000 times.
                for _ in 0..2_000 {
                    let _ = std::fs::rename(&sub, &parked);
                    let _ = std::os::unix::fs::symlink(outside.path(), &sub);
                    std::thread::yield_now();
                    let _ = std::fs::remove_file(&sub);
                    let _ = std::fs::rename(&parked, &sub);
                }
                stop.store(true, Ordering::Relaxed);
            });
            let writer = scope.spawn(|| {
                let mut attempts = 0;
                while !stop.load(Ordering::Relaxed) {
                    let _ = workspace.write("sub/w1.toml", "toml", b"x", true);
                    attempts += 1;
                }
                attempts
            });
            let reader = scope.spawn(|| {
                let mut leaks = 0;
                while !stop.load(Ordering::Relaxed) {
                    if let Ok((_, text)) = workspace.read_text("sub/secret.toml", &["toml"])
                        && text == "outside"
                    {
                        leaks += 1;
                    }
                }
                leaks
            });
            assert!(writer.join().expect("writer") > 0);
            assert_eq!(
                reader.join().expect("reader"),
                0,
                "reads outside the folder"
            );
        });
        let outside_files: Vec<_> = std::fs::read_dir(outside.path())
            .expect("list")
            .map(|entry| entry.expect("entry").file_name())
            .collect();
        assert_eq!(outside_files, ["secret.toml"], "writes outside the folder");
        let mut pending = vec![folder.path().to_owned()];
        while let Some(current) = pending.pop() {
            for entry in std::fs::read_dir(&current).expect("list").flatten() {
                let name = entry.file_name().to_string_lossy().into_owned();
                assert!(!name.ends_with(".tmp"), "temporary file {name} left behind");
                if entry.file_type().expect("type").is_dir() {
                    pending.push(entry.path());
                }
            }
        }
    }

    #[test]
    fn files_are_written_listed_and_read_back() {
        let folder = tempfile::tempdir().expect("folder");
        std::fs::create_dir(folder.path().join("robots")).expect("mkdir");
        let workspace = Workspace::new(folder.path()).expect("workspace");
        workspace
            .write("robots/arm.toml", "toml", b"one", false)
            .expect("write");
        workspace
            .write("data.csv", "csv", b"qm1\n", false)
            .expect("write");
        assert!(matches!(
            workspace.write("robots/arm.toml", "toml", b"two", false),
            Err(ApiError::Conflict(_))
        ));
        workspace
            .write("robots/arm.toml", "toml", b"three", true)
            .expect("overwrite");
        assert_eq!(
            workspace
                .read_text("robots/arm.toml", &["toml"])
                .expect("read")
                .1,
            "three"
        );
        assert!(matches!(
            workspace.write("missing/arm.toml", "toml", b"x", true),
            Err(ApiError::NotFound(_))
        ));
        let listing = workspace.list();
        assert_eq!(listing.robots, ["robots/arm.toml"]);
        assert_eq!(listing.data, ["data.csv"]);
        assert!(matches!(
            workspace.read_text("nothing.csv", &["csv"]),
            Err(ApiError::NotFound(_))
        ));
    }
}
