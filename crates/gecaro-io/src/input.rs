//! Reading input files in bounded memory.
//!
//! Every reader of gecaro opens its input here: it must be a regular file
//! (a folder, FIFO or device such as `/dev/zero` could be endless), whole
//! files read into memory have a size limit, and streamed files a limit on
//! the length of one line, so that no input can exhaust memory.

use std::io::Read;
use std::path::Path;

use crate::Error;
use crate::columns::Delimiter;

/// Largest robot, study or priority file (TOML, URDF, tables).
pub(crate) const MAX_DESCRIPTION_BYTES: u64 = 64 << 20;

/// Longest line of a streamed (CSV) file.
pub(crate) const MAX_LINE_BYTES: usize = 1 << 20;

fn refuse(path: &Path, message: impl Into<String>) -> Error {
    Error::Read {
        path: path.to_owned(),
        cause: std::io::Error::other(message.into()),
    }
}

/// Opens a user's input file for reading: a regular file (see the module
/// docs), to be read record by record.
///
/// # Errors
/// [`Error::Read`] when it cannot be opened or is not a regular file.
pub fn open_input(path: &Path) -> Result<std::fs::File, Error> {
    open_regular(path).map(|(file, _)| file)
}

/// The whole text of a robot, study, table or URDF file: a regular UTF-8
/// file of at most 64 MiB.
///
/// # Errors
/// [`Error::Read`] for a file that cannot be read, is not a regular file or
/// is too large; [`Error::Parse`] for text that is not UTF-8.
pub fn read_description(path: &Path) -> Result<String, Error> {
    read_text(path, MAX_DESCRIPTION_BYTES)
}

/// Opens a regular file for reading.
pub(crate) fn open_regular(path: &Path) -> Result<(std::fs::File, u64), Error> {
    // Checked before opening too: opening a FIFO waits for a writer.
    if std::fs::metadata(path).is_ok_and(|metadata| !metadata.is_file()) {
        return Err(refuse(
            path,
            "not a regular file (a folder, FIFO or device); give a file",
        ));
    }
    let file = std::fs::File::open(path).map_err(|cause| Error::Read {
        path: path.to_owned(),
        cause,
    })?;
    let metadata = file.metadata().map_err(|cause| Error::Read {
        path: path.to_owned(),
        cause,
    })?;
    if !metadata.is_file() {
        return Err(refuse(
            path,
            "not a regular file (a folder, FIFO or device); give a file",
        ));
    }
    crate::roles::note_input(path, &file);
    Ok((file, metadata.len()))
}

/// The whole text of a regular UTF-8 file of at most `limit` bytes.
pub(crate) fn read_text(path: &Path, limit: u64) -> Result<String, Error> {
    let (file, length) = open_regular(path)?;
    let too_large = || {
        refuse(
            path,
            format!(
                "larger than {} MiB: not a file gecaro reads whole",
                limit >> 20
            ),
        )
    };
    if length > limit {
        return Err(too_large());
    }
    let mut bytes = Vec::with_capacity(usize::try_from(length).unwrap_or(0));
    file.take(limit + 1)
        .read_to_end(&mut bytes)
        .map_err(|cause| Error::Read {
            path: path.to_owned(),
            cause,
        })?;
    if bytes.len() as u64 > limit {
        return Err(too_large());
    }
    String::from_utf8(bytes).map_err(|error| {
        let line = 1 + error.as_bytes()[..error.utf8_error().valid_up_to()]
            .iter()
            .filter(|b| **b == b'\n')
            .count();
        Error::parse(path, line, None, "the file is not UTF-8 text")
    })
}

/// The CSV reader of every gecaro CSV file: the header is read as the first
/// record (so that its line is known), `#` starts a comment, rows may have
/// any length (callers check it and name the line), fields are not trimmed
/// (callers trim the slices they read), and lines are capped at
/// [`MAX_LINE_BYTES`]. The separator is `delimiter`, or found from the first
/// line that is not a comment; the byte chosen is returned too.
pub(crate) fn csv_reader<R: Read>(
    reader: R,
    delimiter: Delimiter,
) -> (csv::Reader<LineLimit<std::io::BufReader<R>>>, u8) {
    let mut buffered = std::io::BufReader::with_capacity(1 << 16, reader);
    let header = std::io::BufRead::fill_buf(&mut buffered)
        .ok()
        .and_then(|bytes| {
            bytes
                .split(|byte| *byte == b'\n')
                .find(|line| !line.starts_with(b"#") && !line.iter().all(u8::is_ascii_whitespace))
                .map(<[u8]>::to_vec)
        })
        .unwrap_or_default();
    let byte = delimiter.byte(&header);
    let reader = csv::ReaderBuilder::new()
        .has_headers(false)
        .delimiter(byte)
        .comment(Some(b'#'))
        .flexible(true)
        .from_reader(LineLimit::new(buffered, MAX_LINE_BYTES));
    (reader, byte)
}

/// A CSV error as a parse error naming the file and the line.
pub(crate) fn csv_error(path: &Path, error: &csv::Error) -> Error {
    let line = error
        .position()
        .map_or(1, |position| position.line() as usize);
    let message = match error.kind() {
        csv::ErrorKind::Utf8 { .. } => "the file is not UTF-8 text".to_owned(),
        csv::ErrorKind::Io(cause) => cause.to_string(),
        _ => error.to_string(),
    };
    Error::parse(path, line, None, message)
}

/// A reader that fails once a line grows longer than `limit` bytes: a CSV
/// reader keeps a whole record in memory.
pub(crate) struct LineLimit<R> {
    inner: R,
    limit: usize,
    current: usize,
}

impl<R> LineLimit<R> {
    pub(crate) fn new(inner: R, limit: usize) -> Self {
        LineLimit {
            inner,
            limit,
            current: 0,
        }
    }
}

impl<R: Read> Read for LineLimit<R> {
    /// Counts the bytes since the last line break; a line is caught within
    /// one read of passing the limit (reads are far shorter than the limit).
    fn read(&mut self, buffer: &mut [u8]) -> std::io::Result<usize> {
        let count = self.inner.read(buffer)?;
        let chunk = &buffer[..count];
        self.current = match chunk.iter().rposition(|byte| *byte == b'\n') {
            Some(last) => count - last - 1,
            None => self.current + count,
        };
        if self.current > self.limit {
            return Err(std::io::Error::other(format!(
                "a line longer than {} KiB: not a data file (no line breaks?)",
                self.limit >> 10
            )));
        }
        Ok(count)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn folders_devices_and_oversized_files_are_refused() {
        let folder = tempfile::tempdir().expect("temporary folder");
        let message = |result: Result<String, Error>| result.expect_err("refused").to_string();
        assert!(message(read_text(folder.path(), 10)).contains("not a regular file"));
        #[cfg(unix)]
        assert!(message(read_text(Path::new("/dev/zero"), 10)).contains("not a regular file"));
        let path = folder.path().join("big.toml");
        std::fs::write(&path, "x".repeat(2 << 20)).expect("write");
        assert!(message(read_text(&path, 1 << 20)).contains("larger than 1 MiB"));
        std::fs::write(&path, b"ok\n\xff\n").expect("write");
        assert!(message(read_text(&path, 1 << 20)).contains(":2: the file is not UTF-8"));
    }

    #[test]
    fn a_line_without_end_stops_the_reader() {
        let mut limited = LineLimit::new(std::io::repeat(b'1'), 1000);
        let mut sink = Vec::new();
        let error = limited.read_to_end(&mut sink).expect_err("stops");
        assert!(error.to_string().contains("longer than"));
        assert!(sink.len() < 10_000);
        let lines = "a\n".repeat(10_000);
        let mut fine = LineLimit::new(lines.as_bytes(), 4);
        assert_eq!(fine.read_to_end(&mut sink).expect("short lines"), 20_000);
    }
}
