//! The folder the server works in (`--dir`): the only place it reads robot
//! and data files from and writes them to.
//!
//! Names in requests are relative paths with `/` separators (`robots/arm.toml`).
//! A name is refused unless every component is a plain name: no `..`, no
//! absolute paths or drive letters, no hidden components (`.git`), no
//! backslashes. Files are resolved through symbolic links and refused when
//! the target lies outside the folder, so a link cannot lead out of it either.
//! Writes are atomic ([`gecaro_io::write_atomically`]) and serialised, so a
//! failed or concurrent save never leaves a broken file.

use std::path::{Component, Path, PathBuf};
use std::sync::Mutex;

use gecaro_io::OutputPolicy;
use serde::Serialize;

use crate::error::ApiError;
use crate::limits::{MAX_FILE_BYTES, MAX_LISTED};

/// Folders not worth listing: build outputs and dependencies.
const SKIPPED_FOLDERS: &[&str] = &["target", "node_modules"];
/// How deep the listing goes below the folder.
const LISTING_DEPTH: usize = 4;

/// The sandboxed folder.
#[derive(Debug)]
pub struct Workspace {
    root: PathBuf,
    writing: Mutex<()>,
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
        Ok(Workspace {
            root,
            writing: Mutex::new(()),
        })
    }

    /// The folder, absolute.
    pub fn root(&self) -> &Path {
        &self.root
    }

    /// The robot and data files, sorted, at most [`MAX_LISTED`] of each.
    pub fn list(&self) -> Listing {
        let mut listing = Listing {
            folder: self.root.display().to_string(),
            ..Listing::default()
        };
        self.walk(&self.root, "", 0, &mut listing);
        listing.robots.sort();
        listing.data.sort();
        listing.imports.sort();
        listing
    }

    fn walk(&self, folder: &Path, prefix: &str, depth: usize, listing: &mut Listing) {
        let Ok(entries) = std::fs::read_dir(folder) else {
            return;
        };
        let mut entries: Vec<_> = entries.filter_map(Result::ok).collect();
        entries.sort_by_key(std::fs::DirEntry::file_name);
        for entry in entries {
            let Some(name) = entry.file_name().to_str().map(str::to_owned) else {
                continue;
            };
            // Links are not followed when listing; hidden entries are skipped.
            let Ok(kind) = entry.file_type() else {
                continue;
            };
            if name.starts_with('.') || kind.is_symlink() {
                continue;
            }
            let relative = format!("{prefix}{name}");
            if kind.is_dir() {
                if depth + 1 < LISTING_DEPTH && !SKIPPED_FOLDERS.contains(&name.as_str()) {
                    self.walk(&entry.path(), &format!("{relative}/"), depth + 1, listing);
                }
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
            } else {
                bucket.push(relative);
            }
        }
    }

    /// `name` checked as a relative path of plain components.
    fn relative(name: &str) -> Result<PathBuf, ApiError> {
        let refuse = |why: &str| Err(ApiError::Forbidden(format!("file name {name:?}: {why}")));
        if name.is_empty() {
            return refuse("empty");
        }
        if name.len() > 1024 {
            return refuse("too long");
        }
        if name.contains('\\') || name.contains('\0') || name.contains(':') {
            return refuse("use / between folders; no \\, : or NUL characters");
        }
        let path = PathBuf::from(name);
        for component in path.components() {
            match component {
                Component::Normal(part) => {
                    if part.to_string_lossy().starts_with('.') {
                        return refuse("hidden files and folders are not served");
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

    fn inside(&self, resolved: &Path, name: &str) -> Result<(), ApiError> {
        if resolved.starts_with(&self.root) {
            Ok(())
        } else {
            Err(ApiError::Forbidden(format!(
                "{name} leads outside the folder {} (through a link)",
                self.root.display()
            )))
        }
    }

    /// The path of the existing file `name`, with one of `extensions`.
    ///
    /// # Errors
    /// [`ApiError::Forbidden`] for names outside the folder or of another
    /// kind, [`ApiError::NotFound`] when there is no such file.
    pub fn existing(&self, name: &str, extensions: &[&str]) -> Result<PathBuf, ApiError> {
        let relative = Self::relative(name)?;
        check_extensions(&relative, name, extensions)?;
        let resolved = self.root.join(&relative).canonicalize().map_err(|_| {
            ApiError::NotFound(format!("no file {name} in {}", self.root.display()))
        })?;
        self.inside(&resolved, name)?;
        if !resolved.is_file() {
            return Err(ApiError::NotFound(format!("{name} is not a file")));
        }
        Ok(resolved)
    }

    /// The text of the existing file `name` (at most [`MAX_FILE_BYTES`]).
    ///
    /// # Errors
    /// As [`existing`](Self::existing); [`ApiError::TooLarge`] for big files.
    pub fn read_text(
        &self,
        name: &str,
        extensions: &[&str],
    ) -> Result<(PathBuf, String), ApiError> {
        let path = self.existing(name, extensions)?;
        let size = std::fs::metadata(&path).map(|m| m.len()).unwrap_or(0);
        if size > MAX_FILE_BYTES {
            return Err(ApiError::TooLarge(format!(
                "{name} has {size} bytes; the server reads files up to {} MiB",
                MAX_FILE_BYTES >> 20
            )));
        }
        let text = std::fs::read_to_string(&path)
            .map_err(|error| ApiError::Unprocessable(format!("cannot read {name}: {error}")))?;
        Ok((path, text))
    }

    /// Where an output `name` (extension `extension`) goes: its path
    /// relative to the folder, its target, and its folder (resolved, and
    /// inside the served folder).
    fn output_place(
        &self,
        name: &str,
        extension: &str,
    ) -> Result<(PathBuf, PathBuf, PathBuf), ApiError> {
        let relative = Self::relative(name)?;
        check_extensions(&relative, name, &[extension])?;
        let target = self.root.join(&relative);
        let parent = target
            .parent()
            .and_then(|parent| parent.canonicalize().ok())
            .ok_or_else(|| ApiError::NotFound(format!("the folder of {name} does not exist")))?;
        self.inside(&parent, name)?;
        Ok((relative, target, parent))
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
        let (_, target, _) = self.output_place(name, extension)?;
        if !overwrite && std::fs::symlink_metadata(&target).is_ok() {
            return Err(ApiError::Conflict(format!(
                "{name} already exists; save with overwrite to replace it"
            )));
        }
        Ok(())
    }

    /// Writes `bytes` to the file `name` (extension `extension`) atomically;
    /// an existing file is replaced only when `overwrite` is set.
    ///
    /// # Errors
    /// [`ApiError::Forbidden`] outside the folder, [`ApiError::NotFound`] when
    /// the subfolder does not exist, [`ApiError::Conflict`] when the file
    /// exists, [`ApiError::Internal`] when writing fails (nothing is left behind).
    pub fn write(
        &self,
        name: &str,
        extension: &str,
        bytes: &[u8],
        overwrite: bool,
    ) -> Result<PathBuf, ApiError> {
        let (relative, _, parent) = self.output_place(name, extension)?;
        let file_name = relative
            .file_name()
            .ok_or_else(|| ApiError::Forbidden(format!("file name {name:?}: not a file name")))?;
        let destination = parent.join(file_name);
        // Held across the check and the rename: saves do not interleave.
        let _guard = self
            .writing
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        if let Ok(metadata) = std::fs::symlink_metadata(&destination) {
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
        }
        let policy = if overwrite {
            OutputPolicy::Overwrite
        } else {
            OutputPolicy::KeepExisting
        };
        gecaro_io::write_atomically(&destination, bytes, policy).map_err(|error| match error {
            gecaro_io::Error::OutputExists { .. } => ApiError::Conflict(format!(
                "{name} already exists; save with overwrite to replace it"
            )),
            other => ApiError::Internal(other.to_string()),
        })?;
        Ok(destination)
    }
}

fn check_extensions(relative: &Path, name: &str, extensions: &[&str]) -> Result<(), ApiError> {
    let extension = relative.extension().and_then(|e| e.to_str());
    if extension.is_some_and(|extension| extensions.contains(&extension)) {
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
                    workspace.existing(name, &["toml"]),
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
            workspace.existing("link.toml", &["toml"]),
            Err(ApiError::Forbidden(_))
        ));
        assert!(matches!(
            workspace.existing("out/secret.toml", &["toml"]),
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
            workspace.existing("nothing.csv", &["csv"]),
            Err(ApiError::NotFound(_))
        ));
    }
}
