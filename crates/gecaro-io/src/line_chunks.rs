//! A long file's body read in chunks cut after line breaks, and a chunk cut
//! into parts for the cores.
//!
//! Every chunk and every part starts at a line start, and each comes with
//! the number of lines of the file before it, so that records, comments
//! and line numbers are those of a single pass over the file. A quoted
//! field may hold a line break: callers cut only bodies without a quote.

use std::io::Read;
use std::path::Path;

use crate::Error;

/// Whether `head` (a file's first bytes) ends its lines with a carriage
/// return alone — Excel's "CSV (Macintosh)" — rather than `\n` or `\r\n`.
pub(crate) fn carriage_returns_only(head: &[u8]) -> bool {
    head.contains(&b'\r') && !head.contains(&b'\n')
}

/// A stream whose carriage returns are read as line feeds (a file of
/// [`carriage_returns_only`], read as any other).
pub(crate) struct CarriageReturnLines<'a>(pub(crate) &'a mut dyn Read);

impl Read for CarriageReturnLines<'_> {
    fn read(&mut self, buffer: &mut [u8]) -> std::io::Result<usize> {
        let read = self.0.read(buffer)?;
        for byte in &mut buffer[..read] {
            if *byte == b'\r' {
                *byte = b'\n';
            }
        }
        Ok(read)
    }
}

/// A body in chunks of about `chunk_bytes`: the bytes of a head already
/// read, then the rest of the stream. Memory beyond the caller's is one
/// chunk.
pub(crate) struct LineChunks<'a> {
    /// The unread part of the body, from a line start, in its first
    /// `filled` bytes (the rest is room, zeroed once when it was made).
    buffer: Vec<u8>,
    filled: usize,
    /// Bytes at the buffer's start handed out by the last chunk.
    handed_out: usize,
    /// Line breaks of the last chunk, when the caller counted them.
    handed_out_lines: Option<usize>,
    /// Bytes of the file before the buffer's first byte.
    bytes_before: u64,
    /// Lines of the file before the buffer's first byte.
    lines_before: usize,
    rest: &'a mut dyn Read,
    ended: bool,
    chunk_bytes: usize,
    /// The file, for messages.
    path: &'a Path,
}

impl<'a> LineChunks<'a> {
    /// The body from byte `start` of `head` (a line start after
    /// `lines_before` lines; `head` becomes the chunks' buffer), then
    /// `rest`.
    pub(crate) fn new(
        (head, start): (Vec<u8>, usize),
        rest: &'a mut dyn Read,
        lines_before: usize,
        chunk_bytes: usize,
        path: &'a Path,
    ) -> Self {
        let mut buffer = head;
        buffer.drain(..start);
        LineChunks {
            filled: buffer.len(),
            buffer,
            handed_out: 0,
            handed_out_lines: None,
            bytes_before: start as u64,
            lines_before,
            rest,
            ended: false,
            chunk_bytes,
            path,
        }
    }

    /// Bytes of the file up to the end of the last chunk handed out.
    pub(crate) fn bytes_read(&self) -> u64 {
        self.bytes_before + self.handed_out as u64
    }

    /// The next chunk, whole lines (the last one may lack its line break at
    /// the end of the file), with the lines of the file before it; `None`
    /// at the end.
    ///
    /// # Errors
    /// [`Error::Read`] when the stream fails.
    pub(crate) fn next_chunk(&mut self) -> Result<Option<(&[u8], usize)>, Error> {
        if self.handed_out > 0 {
            self.lines_before += self.handed_out_lines.take().unwrap_or_else(|| {
                memchr::memchr_iter(b'\n', &self.buffer[..self.handed_out]).count()
            });
            self.buffer.copy_within(self.handed_out..self.filled, 0);
            self.filled -= self.handed_out;
            self.bytes_before += self.handed_out as u64;
            self.handed_out = 0;
        }
        while !self.ended && self.filled < self.chunk_bytes {
            let room = self.chunk_bytes.max(self.filled + 1);
            if self.buffer.len() < room {
                self.buffer.resize(room, 0);
            }
            match self.rest.read(&mut self.buffer[self.filled..]) {
                Ok(0) => self.ended = true,
                Ok(count) => self.filled += count,
                Err(cause) if cause.kind() == std::io::ErrorKind::Interrupted => {}
                Err(cause) => {
                    return Err(Error::Read {
                        path: self.path.to_owned(),
                        cause,
                    });
                }
            }
        }
        let filled = &self.buffer[..self.filled];
        let cut = if self.ended {
            filled.len()
        } else {
            memchr::memrchr(b'\n', filled).map_or(filled.len(), |at| at + 1)
        };
        if cut == 0 {
            return Ok(None);
        }
        self.handed_out = cut;
        Ok(Some((&filled[..cut], self.lines_before)))
    }

    /// Tells the line breaks of the last chunk, which its caller counted:
    /// the next chunk does not count them again.
    pub(crate) fn counted(&mut self, lines: usize) {
        self.handed_out_lines = Some(lines);
    }
}

/// A piece of a body: its bytes, the lines of the file before it, and its
/// own line breaks.
pub(crate) type LinePart<'a> = (&'a [u8], usize, usize);

/// `body` (whole lines, the first after `lines_before` lines of the file)
/// cut at line breaks into at most `parts` pieces of about equal length
/// ([`LinePart`]s).
pub(crate) fn line_parts(body: &[u8], lines_before: usize, parts: usize) -> Vec<LinePart<'_>> {
    let mut cut = Vec::with_capacity(parts);
    let (mut start, mut lines) = (0, lines_before);
    for part in 1..=parts {
        let target = (body.len() * part / parts).max(start);
        let end = if part == parts {
            body.len()
        } else {
            memchr::memchr(b'\n', &body[target..]).map_or(body.len(), |offset| target + offset + 1)
        };
        if end > start {
            let own = memchr::memchr_iter(b'\n', &body[start..end]).count();
            cut.push((&body[start..end], lines, own));
            lines += own;
            start = end;
        }
    }
    cut
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `count` numbered lines.
    fn numbered(count: usize) -> String {
        (1..=count).map(|line| format!("line {line}\n")).collect()
    }

    /// The first line's number in `bytes`, which must start one.
    fn first_number(bytes: &[u8]) -> usize {
        let text = std::str::from_utf8(bytes).expect("text");
        text.lines().next().expect("a line")[5..]
            .parse()
            .expect("a number")
    }

    #[test]
    fn chunks_are_whole_lines_with_the_lines_before_them() {
        let text = numbered(1000);
        for (head_bytes, chunk_bytes) in [(0, 100), (37, 64), (500, 4096), (9000, 7)] {
            let head_bytes = head_bytes.min(text.len());
            let (head, mut rest) = text.as_bytes().split_at(head_bytes);
            // The head starts after the first line, as after a header.
            let start = memchr::memchr(b'\n', head).map_or(0, |at| at + 1);
            let lines = usize::from(start > 0);
            let mut chunks = LineChunks::new(
                (head.to_vec(), start),
                &mut rest,
                lines,
                chunk_bytes,
                Path::new("lines.txt"),
            );
            let mut joined = Vec::new();
            let mut told = false;
            while let Some((chunk, before)) = chunks.next_chunk().expect("read") {
                assert!(chunk.ends_with(b"\n"), "{chunk:?}");
                assert_eq!(first_number(chunk), before + 1);
                joined.extend_from_slice(chunk);
                // Every other chunk's lines told, as a caller counted them.
                let lines = chunk.iter().filter(|byte| **byte == b'\n').count();
                if told {
                    chunks.counted(lines);
                }
                told = !told;
            }
            let skipped = if start > 0 { start } else { 0 };
            assert_eq!(
                joined,
                text.as_bytes()[skipped..],
                "{head_bytes}, {chunk_bytes}"
            );
        }
    }

    #[test]
    fn parts_are_whole_lines_that_join_to_the_body() {
        let text = numbered(333);
        for parts in [1, 2, 3, 8, 1000] {
            let cut = line_parts(text.as_bytes(), 0, parts);
            assert!(cut.len() <= parts);
            let mut joined = Vec::new();
            for (part, before, own) in &cut {
                assert_eq!(first_number(part), before + 1);
                assert_eq!(*own, part.iter().filter(|byte| **byte == b'\n').count());
                joined.extend_from_slice(part);
            }
            assert_eq!(joined, text.as_bytes(), "{parts} parts");
        }
        assert!(line_parts(b"", 4, 2).is_empty());
    }
}
