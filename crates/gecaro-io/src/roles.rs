//! Which files one command reads and writes, so that an output never
//! replaces an input and two outputs never land in one file.
//!
//! A command-line process runs one command: once [`protect_inputs`] is
//! called (the `gecaro` binary does so first thing), every input opened
//! through this crate is remembered by its identity (device and inode on
//! Unix, the canonical path elsewhere), an output that is one of them is
//! refused ([`check_not_input`]), and each output is claimed for one kind of
//! file ([`claim_output`]): `generate -o same.csv --real-out same.csv` is
//! refused before any work instead of leaving the robot where the data
//! should be. Libraries and the server, whose processes run many jobs (a
//! robot saved over the file it was opened from is their normal case), do
//! not call it, and nothing is remembered.

use std::path::{Path, PathBuf};
use std::sync::{Mutex, OnceLock, PoisonError};

use crate::Error;

/// What makes two names one file.
#[derive(Clone, Debug, PartialEq, Eq)]
enum Identity {
    /// An existing file: its device and inode (Unix).
    Inode(u64, u64),
    /// A file by its canonical path (files that do not exist yet; other systems).
    Path(PathBuf),
}

#[derive(Debug, Default)]
struct Roles {
    inputs: Vec<(Identity, PathBuf)>,
    outputs: Vec<(Vec<Identity>, PathBuf, String)>,
}

fn roles() -> Option<&'static Mutex<Roles>> {
    ROLES.get()
}

static ROLES: OnceLock<Mutex<Roles>> = OnceLock::new();

/// Remember inputs and claimed outputs from now on (see the module docs).
pub fn protect_inputs() {
    let _ = ROLES.set(Mutex::new(Roles::default()));
}

#[cfg(unix)]
fn inode(metadata: &std::fs::Metadata) -> Option<Identity> {
    use std::os::unix::fs::MetadataExt as _;
    Some(Identity::Inode(metadata.dev(), metadata.ino()))
}

#[cfg(not(unix))]
fn inode(_: &std::fs::Metadata) -> Option<Identity> {
    None
}

/// Every identity of `path`: its inode when it exists, and its canonical
/// path (of its folder, for a file not yet written).
fn identities(path: &Path) -> Vec<Identity> {
    let mut found = Vec::new();
    if let Ok(metadata) = std::fs::metadata(path) {
        found.extend(inode(&metadata));
    }
    let canonical = path.canonicalize().ok().or_else(|| {
        let folder = match path.parent() {
            Some(parent) if !parent.as_os_str().is_empty() => parent,
            _ => Path::new("."),
        };
        Some(folder.canonicalize().ok()?.join(path.file_name()?))
    });
    found.extend(canonical.map(Identity::Path));
    found
}

/// Refuses the output name `-`, which many tools take for the standard
/// output: written as it is, it would make a file named `-` in the current
/// folder, and the standard output already carries the command's report.
///
/// # Errors
/// [`Error::Write`] for `-`.
pub fn check_output_name(path: &Path) -> Result<(), Error> {
    if path == Path::new("-") {
        return Err(Error::Write {
            path: path.to_owned(),
            message: "`-` is not taken for the standard output (the command's report is \
                      printed there): name a file, or /dev/stdout to have the output and \
                      the report in one stream"
                .into(),
        });
    }
    Ok(())
}

/// Records an opened input (see the module docs).
pub(crate) fn note_input(path: &Path, file: &std::fs::File) {
    let Some(roles) = roles() else {
        return;
    };
    let mut found: Vec<Identity> = file
        .metadata()
        .ok()
        .as_ref()
        .and_then(inode)
        .into_iter()
        .collect();
    found.extend(path.canonicalize().ok().map(Identity::Path));
    let mut roles = roles.lock().unwrap_or_else(PoisonError::into_inner);
    for identity in found {
        roles.inputs.push((identity, path.to_owned()));
    }
}

/// Refuses an output `path` that is an input of this command.
///
/// # Errors
/// [`Error::Write`] naming both.
pub fn check_not_input(path: &Path) -> Result<(), Error> {
    let Some(roles) = roles() else {
        return Ok(());
    };
    let mine = identities(path);
    let roles = roles.lock().unwrap_or_else(PoisonError::into_inner);
    if let Some((_, input)) = roles
        .inputs
        .iter()
        .find(|(identity, _)| mine.contains(identity))
    {
        return Err(Error::Write {
            path: path.to_owned(),
            message: if input == path {
                "it is an input of this command; an output never replaces an input: write to \
                 another file"
                    .into()
            } else {
                format!(
                    "it is the input {} of this command; an output never replaces an input: \
                     write to another file",
                    input.display()
                )
            },
        });
    }
    Ok(())
}

/// Claims `path` as the output of kind `kind` (its extension, say) of this
/// command, after [`check_not_input`]; claiming it again for the same kind
/// is allowed (a check before the work, then the write).
///
/// # Errors
/// [`Error::Write`] when it is an input, or the output of another kind.
pub fn claim_output(path: &Path, kind: &str) -> Result<(), Error> {
    check_output_name(path)?;
    check_not_input(path)?;
    let Some(roles) = roles() else {
        return Ok(());
    };
    let mine = identities(path);
    let mut roles = roles.lock().unwrap_or_else(PoisonError::into_inner);
    let other = roles.outputs.iter().find(|(identities, _, claimed)| {
        claimed != kind && identities.iter().any(|identity| mine.contains(identity))
    });
    if let Some((_, other, _)) = other {
        return Err(Error::Write {
            path: path.to_owned(),
            message: format!(
                "{} is already an output of this command; give each output its own file",
                other.display()
            ),
        });
    }
    roles.outputs.push((mine, path.to_owned(), kind.to_owned()));
    Ok(())
}
