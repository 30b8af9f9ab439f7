//! The records of a plain body: whole lines of a data file, one record a
//! line, split into fields a vector at a time.
//!
//! The `csv` crate's reader is a byte-at-a-time state machine, about 1.3 ns
//! a byte here, and most of a long file's reading. A body that holds no
//! quote, no comment (`#`), no blank line and no carriage return outside
//! a `\r\n` is plain: each of its lines is one record, its fields are the
//! bytes between separators, and the `csv` crate reads it as `simd-csv`'s
//! zero-copy reader does, several times faster (docs/performance.md, "a
//! plain body"). So a record's line is the line after the one before,
//! with no position to track. Anything else, or a line longer than
//! [`MAX_LINE_BYTES`], goes the `csv` crate's way, which has the last word
//! on every error.

use std::path::Path;

use crate::Error;
use crate::input::{LineLimit, MAX_LINE_BYTES, csv_reader_with, for_each_record};

/// A record's fields as a tokenizer gives them: the `csv` crate's or the
/// zero-copy reader of a plain body.
pub(crate) trait RecordFields {
    /// Its fields.
    fn field_count(&self) -> usize;
    /// Field `column` (`column < field_count()`).
    fn field(&self, column: usize) -> &[u8];
    /// Its bytes (for the check that the file is text).
    fn bytes(&self) -> &[u8];

    /// Whether its bytes are UTF-8 text, as the `csv` crate's text records
    /// must be (a record read as bytes, its numbers parsed from them, must
    /// still be text: a binary file is named as such,
    /// [`NOT_TEXT`](crate::input::NOT_TEXT)).
    fn is_text(&self) -> bool {
        let bytes = self.bytes();
        bytes.is_ascii() || std::str::from_utf8(bytes).is_ok()
    }
}

/// What takes the records of a part of a body, in order
/// ([`read_part_records`]).
pub(crate) trait RecordSink {
    /// Takes `record`, at `line` of the file.
    ///
    /// # Errors
    /// The record's: reading stops there.
    fn take(&mut self, record: &impl RecordFields, line: usize) -> Result<(), Error>;

    /// Forgets every record taken: the part is read again from its start.
    fn restart(&mut self);
}

/// Hands each record of `part` (whole lines, from a line start; its first
/// line is line `lines_before + 1` of `path`) to `sink` with its line: the
/// plain way when the part is plain (see the module docs), else, or again
/// from its start after a line too long for it, the `csv` crate's. The
/// first error (the reader's or the sink's); `None` when every record was
/// taken.
pub(crate) fn read_part_records(
    part: &[u8],
    lines_before: usize,
    (separator, path): (u8, &Path),
    sink: &mut impl RecordSink,
) -> Option<Error> {
    let plain = for_each_plain_record(part, lines_before, separator, |record, line| {
        sink.take(record, line)
    });
    plain.unwrap_or_else(|| {
        sink.restart();
        let mut csv = csv_reader_with(LineLimit::new(part, MAX_LINE_BYTES), separator);
        for_each_record(
            &mut csv,
            path,
            lines_before,
            |record: &csv::ByteRecord, line| sink.take(record, line),
        )
    })
}

impl RecordFields for csv::ByteRecord {
    fn field_count(&self) -> usize {
        self.len()
    }

    fn field(&self, column: usize) -> &[u8] {
        &self[column]
    }

    fn bytes(&self) -> &[u8] {
        self.as_slice()
    }
}

impl RecordFields for csv::StringRecord {
    fn field_count(&self) -> usize {
        self.len()
    }

    fn field(&self, column: usize) -> &[u8] {
        self[column].as_bytes()
    }

    fn bytes(&self) -> &[u8] {
        self.as_byte_record().as_slice()
    }
}

impl RecordFields for simd_csv::ZeroCopyByteRecord<'_> {
    fn field_count(&self) -> usize {
        self.len()
    }

    fn field(&self, column: usize) -> &[u8] {
        &self[column]
    }

    fn bytes(&self) -> &[u8] {
        self.as_slice()
    }
}

/// Whether `body` (whole lines from a line start) is plain (see the module
/// docs): one record a line for both readers.
pub(crate) fn is_plain(body: &[u8]) -> bool {
    const BYTE_ORDER_MARK: &[u8] = b"\xEF\xBB\xBF";
    // Two passes over a long body: one for the bytes a plain body holds
    // only as the `\r` of a `\r\n` that ends a line with bytes (no quote,
    // no `#`, no lone `\r`, no `\n\r`), one for a blank line.
    !body.starts_with(b"\n")
        && !body.starts_with(b"\r")
        && !body.starts_with(BYTE_ORDER_MARK)
        && memchr::memchr3_iter(b'"', b'#', b'\r', body).all(|at| {
            body[at] == b'\r'
                && body.get(at + 1) == Some(&b'\n')
                && body[..at].last() != Some(&b'\n')
        })
        && memchr::memmem::find(body, b"\n\n").is_none()
}

/// Hands each record of the plain `body` (see [`is_plain`]; its first line
/// is line `lines_before + 1` of the file) to `each` with its line, to the
/// end or `each`'s first error, which is returned. `None` when the body is
/// not plain or holds a line longer than [`MAX_LINE_BYTES`]: the records
/// handed out until then are to be read again the `csv` crate's way.
fn for_each_plain_record<E>(
    body: &[u8],
    lines_before: usize,
    separator: u8,
    mut each: impl FnMut(&simd_csv::ZeroCopyByteRecord<'_>, usize) -> Result<(), E>,
) -> Option<Option<E>> {
    if !is_plain(body) {
        return None;
    }
    let mut reader = simd_csv::ZeroCopyReaderBuilder::new()
        .delimiter(separator)
        .has_headers(false)
        .flexible(true)
        .from_reader(body);
    let mut line = lines_before;
    loop {
        let record = match reader.read_byte_record() {
            Ok(Some(record)) => record,
            Ok(None) => return Some(None),
            // Only the reading of a slice could fail, which it does not.
            Err(_) => return None,
        };
        if record.as_slice().len() > MAX_LINE_BYTES {
            return None;
        }
        line += 1;
        if let Err(error) = each(&record, line) {
            return Some(Some(error));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::input::{LineLimit, csv_reader_with, for_each_record};

    /// Each record's fields and line, by the `csv` crate.
    fn by_csv(body: &[u8], lines_before: usize) -> Vec<(Vec<Vec<u8>>, usize)> {
        let mut csv = csv_reader_with(LineLimit::new(body, MAX_LINE_BYTES), b',');
        let mut records = Vec::new();
        let error = for_each_record(
            &mut csv,
            std::path::Path::new("t.csv"),
            lines_before,
            |record: &csv::ByteRecord, line| {
                records.push((record.iter().map(<[u8]>::to_vec).collect(), line));
                Ok(())
            },
        );
        assert!(error.is_none(), "{error:?}");
        records
    }

    /// The same by the plain route, `None` when the body is not plain.
    fn by_plain(body: &[u8], lines_before: usize) -> Option<Vec<(Vec<Vec<u8>>, usize)>> {
        let mut records = Vec::new();
        let error = for_each_plain_record(body, lines_before, b',', |record, line| {
            let fields = (0..record.field_count())
                .map(|column| record.field(column).to_vec())
                .collect();
            records.push((fields, line));
            Ok::<(), ()>(())
        })?;
        assert!(error.is_none());
        Some(records)
    }

    #[test]
    fn plain_bodies_give_the_csv_crates_records_and_lines() {
        for body in [
            &b"1,2,3\n4,5,6\n"[..],
            b"1,2,3\n4,5,6",
            b"1,2,3\r\n4, 5 ,6\r\n7,8\r\n",
            b" 1,2\n,\n3,,4,\n",
            b"0.25,-1e-3,1E5\n\t2 ,3\n",
        ] {
            let plain = by_plain(body, 7).expect("plain");
            assert_eq!(plain, by_csv(body, 7), "{}", String::from_utf8_lossy(body));
        }
    }

    #[test]
    fn bodies_the_csv_crate_reads_otherwise_are_not_plain() {
        for body in [
            &b"1,2\n\n3,4\n"[..],
            b"\n1,2\n",
            b"1,2\n# a comment\n3,4\n",
            b"1,\"2\"\n",
            b"1,2\r3,4\n",
            b"1,2\n\r\n3,4\n",
            b"\xEF\xBB\xBF1,2\n",
        ] {
            assert!(
                by_plain(body, 0).is_none(),
                "{}",
                String::from_utf8_lossy(body)
            );
        }
        let long = format!("{}\n1,2\n", "1,".repeat(MAX_LINE_BYTES / 2 + 1));
        assert!(by_plain(long.as_bytes(), 0).is_none());
    }

    /// The plain test is the rule it states, checked rule by rule, on
    /// bodies of bytes that make or break it.
    #[test]
    fn plain_is_each_rule_of_the_module() {
        use rand::{RngExt, SeedableRng};
        let by_rules = |body: &[u8]| {
            !body.starts_with(b"\n")
                && !body.starts_with(b"\r")
                && !body.starts_with(b"\xEF\xBB\xBF")
                && !body.contains(&b'"')
                && !body.contains(&b'#')
                && !body
                    .windows(2)
                    .any(|pair| pair == b"\n\n" || pair == b"\n\r")
                && body
                    .iter()
                    .enumerate()
                    .all(|(at, byte)| *byte != b'\r' || body.get(at + 1) == Some(&b'\n'))
        };
        let alphabet = b"1,\n\n\n\r\r\"# \xEF\xBB\xBF";
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(5);
        let mut plain = 0;
        for _ in 0..20_000 {
            let length = rng.random_range(0..12);
            let body: Vec<u8> = (0..length)
                .map(|_| alphabet[rng.random_range(0..alphabet.len())])
                .collect();
            assert_eq!(is_plain(&body), by_rules(&body), "{body:?}");
            plain += usize::from(by_rules(&body));
        }
        // Both answers are met often.
        assert!(plain > 1_000 && plain < 19_000, "{plain}");
    }
}
