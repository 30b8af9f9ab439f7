//! Reading input files in bounded memory.
//!
//! Every reader of gecaro opens its input here: it must be a regular file
//! (a folder, FIFO or device such as `/dev/zero` could be endless), whole
//! files read into memory have a size limit, and streamed files a limit on
//! the length of one line, so that no input can exhaust memory.

use std::collections::VecDeque;
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
        Error::parse(path, line, None, NOT_TEXT)
    })
}

/// What is said of a file whose bytes are not UTF-8 text.
pub(crate) const NOT_TEXT: &str = "the file is not UTF-8 text";

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
    (
        csv_reader_with(LineLimit::new(buffered, MAX_LINE_BYTES), byte),
        byte,
    )
}

/// A CSV reader as [`csv_reader`] makes them, with the separator `byte`.
pub(crate) fn csv_reader_with<R: Read>(reader: R, byte: u8) -> csv::Reader<R> {
    csv::ReaderBuilder::new()
        .has_headers(false)
        .delimiter(byte)
        .comment(Some(b'#'))
        .flexible(true)
        .from_reader(reader)
}

/// The next record of `csv` with its line ([`record_line`]); `None` at the
/// end.
///
/// # Errors
/// The reader's error, naming the file and the line.
pub(crate) fn next_record<R: Read>(
    csv: &mut csv::Reader<LineLimit<R>>,
    path: &Path,
) -> Result<Option<(csv::StringRecord, usize)>, Error> {
    let mut record = csv::StringRecord::new();
    Ok(read_record(csv, path, 0, &mut record)?.map(|line| (record, line)))
}

/// A record the `csv` crate reads: as text ([`csv::StringRecord`]) or as
/// the bytes of the file ([`csv::ByteRecord`], not checked for UTF-8: a
/// data row's fields are numbers, parsed from the bytes by a caller that
/// checks the record is text).
pub(crate) trait CsvRecord: Default {
    /// Reads the next record of `csv` into this one; `false` at the end.
    fn read_next<R: Read>(&mut self, csv: &mut csv::Reader<R>) -> csv::Result<bool>;
}

impl CsvRecord for csv::StringRecord {
    fn read_next<R: Read>(&mut self, csv: &mut csv::Reader<R>) -> csv::Result<bool> {
        csv.read_record(self)
    }
}

impl CsvRecord for csv::ByteRecord {
    fn read_next<R: Read>(&mut self, csv: &mut csv::Reader<R>) -> csv::Result<bool> {
        csv.read_byte_record(self)
    }
}

/// Reads the next record of `csv` (a reader that started after
/// `lines_before` lines of the file) into `record`; returns its line
/// ([`record_line`]), `None` at the end.
///
/// # Errors
/// The reader's error, naming the file and the line.
pub(crate) fn read_record<R: Read>(
    csv: &mut csv::Reader<LineLimit<R>>,
    path: &Path,
    lines_before: usize,
    record: &mut impl CsvRecord,
) -> Result<Option<usize>, Error> {
    match record.read_next(csv) {
        Ok(true) => Ok(Some(lines_before + record_line(csv))),
        Ok(false) => Ok(None),
        Err(error) => Err(csv_error_after(path, &error, lines_before)),
    }
}

/// Hands every record of `csv` (a reader that started after `lines_before`
/// lines of the file) to `each` with its line ([`record_line`]), to the end
/// or the first error: the reader's (naming the file and the line) or
/// `each`'s, which is returned.
pub(crate) fn for_each_record<R: Read, T: CsvRecord>(
    csv: &mut csv::Reader<LineLimit<R>>,
    path: &Path,
    lines_before: usize,
    mut each: impl FnMut(&T, usize) -> Result<(), Error>,
) -> Option<Error> {
    let mut record = T::default();
    loop {
        let line = match read_record(csv, path, lines_before, &mut record) {
            Ok(Some(line)) => line,
            Ok(None) => return None,
            Err(error) => return Some(error),
        };
        if let Err(error) = each(&record, line) {
            return Some(error);
        }
    }
}

/// A CSV error as a parse error naming the file and the line.
pub(crate) fn csv_error(path: &Path, error: &csv::Error) -> Error {
    csv_error_after(path, error, 0)
}

/// [`csv_error`] of a reader that started after `lines_before` lines of the
/// file.
pub(crate) fn csv_error_after(path: &Path, error: &csv::Error, lines_before: usize) -> Error {
    // A line too long names itself: the csv reader's position is that of
    // the record it began, lines before it (issue 75).
    let long = match error.kind() {
        csv::ErrorKind::Io(cause) => cause
            .get_ref()
            .and_then(|inner| inner.downcast_ref::<LongLine>()),
        _ => None,
    };
    let line = lines_before
        + long.map_or_else(
            || {
                error
                    .position()
                    .map_or(1, |position| position.line() as usize)
            },
            |long| long.line,
        );
    let message = match error.kind() {
        csv::ErrorKind::Utf8 { .. } => NOT_TEXT.to_owned(),
        csv::ErrorKind::Io(cause) => cause.to_string(),
        _ => error.to_string(),
    };
    Error::parse(path, line, None, message)
}

/// A line longer than a reader takes: its 1-based line among the lines
/// the reader passed on.
#[derive(Debug)]
pub(crate) struct LongLine {
    line: usize,
    limit: usize,
}

impl std::fmt::Display for LongLine {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "a line longer than {} KiB: not a data file (no line breaks?)",
            self.limit >> 10
        )
    }
}

impl std::error::Error for LongLine {}

/// A reader that fails once a line grows longer than `limit` bytes (a CSV
/// reader keeps a whole record in memory), and knows the line of any byte
/// it has passed on ([`record_line`]).
pub(crate) struct LineLimit<R> {
    inner: R,
    limit: usize,
    current: usize,
    /// Bytes passed on so far.
    read: u64,
    /// Offsets of the line breaks passed on and not yet asked about.
    breaks: VecDeque<u64>,
    /// Line breaks before the first of `breaks`.
    lines_passed: usize,
}

impl<R> LineLimit<R> {
    pub(crate) fn new(inner: R, limit: usize) -> Self {
        LineLimit {
            inner,
            limit,
            current: 0,
            read: 0,
            breaks: VecDeque::new(),
            lines_passed: 0,
        }
    }

    /// The 1-based line of the byte at `offset`; offsets asked about never
    /// decrease (a reader's records come in order).
    fn line_of(&mut self, offset: u64) -> usize {
        while self.breaks.front().is_some_and(|at| *at < offset) {
            self.breaks.pop_front();
            self.lines_passed += 1;
        }
        self.lines_passed + 1
    }
}

impl<R: Read> Read for LineLimit<R> {
    /// Counts the bytes since the last line break; a line is caught within
    /// one read of passing the limit (reads are far shorter than the limit).
    fn read(&mut self, buffer: &mut [u8]) -> std::io::Result<usize> {
        let count = self.inner.read(buffer)?;
        let chunk = &buffer[..count];
        let start = self.read;
        self.breaks
            .extend(memchr::memchr_iter(b'\n', chunk).map(|at| start + at as u64));
        self.read += count as u64;
        self.current = match memchr::memrchr(b'\n', chunk) {
            Some(last) => count - last - 1,
            None => self.current + count,
        };
        if self.current > self.limit {
            return Err(std::io::Error::other(LongLine {
                line: self.lines_passed + self.breaks.len() + 1,
                limit: self.limit,
            }));
        }
        Ok(count)
    }
}

/// The 1-based line of the record `csv` has just read: the line of its last
/// byte (its terminator, or the end of the file). A record's own position in
/// the `csv` crate is where reading began, before the comment and blank
/// lines it skipped and before the `\n` of a `\r\n` it had stopped at, so
/// it names an earlier line. A record spans one line unless a quoted field
/// holds a line break; such a record is named by its last line.
pub(crate) fn record_line<R: Read>(csv: &mut csv::Reader<LineLimit<R>>) -> usize {
    let end = csv.position().byte();
    csv.get_mut().line_of(end.saturating_sub(1))
}

/// Whether `c` hides or rearranges what is displayed, so that a name or a
/// message holding it would not read as it is: control characters (escape
/// sequences, BEL, CR, newlines), bidirectional marks, embeddings, overrides
/// and isolates (U+202E turns `cod.exe` into `exe.doc`, U+061C is Arabic's
/// mark), invisible separators and joiners (U+200B–U+200D, U+2060–U+2064,
/// U+FEFF, U+180E), and the line and paragraph separators U+2028/U+2029.
/// The web page refuses such names; the command line prints them escaped.
pub fn is_hidden_character(c: char) -> bool {
    c.is_control()
        || matches!(
            c,
            '\u{061c}'
                | '\u{180e}'
                | '\u{200b}'..='\u{200f}'
                | '\u{2028}'..='\u{202e}'
                | '\u{2060}'..='\u{2069}'
                | '\u{feff}'
        )
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
