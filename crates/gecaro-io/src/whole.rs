//! A file's content as its reader takes it: the whole of it in memory, or
//! a stream read once.
//!
//! A small data file (at most [`MAPPED_MAX_BYTES`]) is mapped into memory
//! rather than copied: its pages are the system's file cache, shared, where
//! a copy fills as many fresh pages of the process. On the 2-core machine of
//! `docs/performance.md` a fresh page costs 1.5–2 µs to fault in and give
//! back, and the 0.9 MB of a 5,000-row file were 220 of the ~1,300 pages an
//! identification faults: mapped, `gecaro identify` of those 5,000 rows takes
//! 0.3 ms less. Larger files are read in chunks of bounded memory as before
//! (a mapping would let a huge file's rows be counted and given room all at
//! once).
//!
//! # The one `unsafe` of the workspace
//!
//! Mapping a file is `unsafe` in Rust because another program may change or
//! shorten the file while it is mapped: a change shows in the bytes being
//! read (as a change during a `read` would, in a different place), and a
//! file shortened under the mapping ends the process with `SIGBUS` when a
//! page past its new end is touched. gecaro maps only regular files (checked
//! when opened), of at most 16 MiB, read within milliseconds of opening, as
//! ripgrep maps the files it searches; where mapping fails, the file is read.

#![allow(unsafe_code)]

use std::fs::File;
use std::io::Read;

/// The largest file mapped rather than read (bytes): beyond, a data file is
/// read in chunks.
pub const MAPPED_MAX_BYTES: u64 = 16 << 20;

/// A whole file in memory: mapped, or read (a workspace's text, an upload).
pub enum WholeFile {
    /// A regular file mapped read-only ([`map_small`]).
    Mapped(memmap2::Mmap),
    /// Bytes read or given.
    Read(Vec<u8>),
}

impl std::ops::Deref for WholeFile {
    type Target = [u8];

    fn deref(&self) -> &[u8] {
        match self {
            WholeFile::Mapped(map) => map,
            WholeFile::Read(bytes) => bytes,
        }
    }
}

impl AsRef<[u8]> for WholeFile {
    fn as_ref(&self) -> &[u8] {
        self
    }
}

impl std::fmt::Debug for WholeFile {
    fn fmt(&self, formatter: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let how = match self {
            WholeFile::Mapped(_) => "mapped",
            WholeFile::Read(_) => "read",
        };
        write!(formatter, "WholeFile({how}, {} bytes)", self.len())
    }
}

/// `file`, a regular file of `length` bytes, mapped when it is not empty
/// and at most [`MAPPED_MAX_BYTES`]; `None` otherwise, and where the system
/// cannot map it (the caller then reads it).
pub fn map_small(file: &File, length: u64) -> Option<WholeFile> {
    if length == 0 || length > MAPPED_MAX_BYTES {
        return None;
    }
    // SAFETY: see the module docs. The file is regular (its opener checked),
    // and its bytes are read as untrusted text: a concurrent change gives
    // other text, never other memory.
    let map = unsafe { memmap2::Mmap::map(file) }.ok()?;
    Some(WholeFile::Mapped(map))
}

/// A file's content as a reader takes it.
pub enum Content<'a> {
    /// All of it in memory.
    Whole(&'a [u8]),
    /// A stream read once from its start, and its length in bytes when known
    /// (a file's: room for its rows is made from it).
    Stream(&'a mut dyn Read, Option<u64>),
}

impl<'a> Content<'a> {
    /// The content as a stream, for readers that take one.
    pub fn reader(&mut self) -> &mut (dyn Read + 'a) {
        match self {
            Content::Whole(bytes) => bytes,
            Content::Stream(reader, _) => *reader,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_small_file_is_mapped_and_reads_as_its_bytes() {
        let folder = tempfile::tempdir().expect("a folder");
        let path = folder.path().join("d.csv");
        std::fs::write(&path, b"qm1,x\n0.5,1\n").expect("written");
        let file = File::open(&path).expect("opened");
        let whole = map_small(&file, 12).expect("mapped");
        assert!(matches!(whole, WholeFile::Mapped(_)));
        assert_eq!(&whole[..], b"qm1,x\n0.5,1\n");
        let mut text = String::new();
        Content::Whole(&whole)
            .reader()
            .read_to_string(&mut text)
            .expect("read");
        assert_eq!(text, "qm1,x\n0.5,1\n");
    }

    #[test]
    fn empty_and_large_files_are_not_mapped() {
        let folder = tempfile::tempdir().expect("a folder");
        let path = folder.path().join("e.csv");
        std::fs::write(&path, b"").expect("written");
        let file = File::open(&path).expect("opened");
        assert!(map_small(&file, 0).is_none());
        assert!(map_small(&file, MAPPED_MAX_BYTES + 1).is_none());
    }
}
