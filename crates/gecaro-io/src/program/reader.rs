//! A program read a block of targets at a time: a million-target program
//! is compensated and written as it is read, in memory that does not grow
//! with it.
//!
//! A file without quotes is read in chunks of whole lines
//! ([`CHUNK_BYTES`]), each read in parts on all cores; a file with quotes
//! (whose fields may hold line breaks) record by record, [`RECORDS`] at a
//! time. Blocks come in the order of the file; lines are those of the file.

use std::io::{Cursor, Read};
use std::path::Path;

use gecaro_core::Robot;
use gecaro_data::parallel::{available_threads, run_parts};

use super::layout::{ProgramBlock, ProgramLayout, target_columns};
use crate::Error;
use crate::data_file::DataFormat;
use crate::data_rows::{CHUNK_BYTES, MAX_CONFIGURATIONS, PART_MIN_BYTES};
use crate::input::{
    LineLimit, MAX_LINE_BYTES, csv_reader, csv_reader_with, next_record, read_record,
};
use crate::line_chunks::{LineChunks, line_parts};
use crate::plain_body::{RecordFields, RecordSink, read_part_records};
use crate::stated_units::{stated_units, units_to_read};

/// Most targets a program may hold (as many as a data file's configurations).
pub(super) const MAX_TARGETS: usize = MAX_CONFIGURATIONS;

/// A part of a program's chunk read into a block.
struct PartBlock<'a> {
    layout: &'a ProgramLayout,
    path: &'a Path,
    block: ProgramBlock,
}

impl RecordSink for PartBlock<'_> {
    fn take(&mut self, record: &impl RecordFields, line: usize) -> Result<(), Error> {
        self.block.add(self.layout, self.path, record, line)
    }

    fn restart(&mut self) {
        self.block = ProgramBlock::default();
    }
}

/// Targets of a block read record by record (a file with quotes).
const RECORDS: usize = 1 << 16;

/// The rest of a quoted file, after its head.
type Quoted<'a> =
    csv::Reader<LineLimit<std::io::BufReader<std::io::Chain<Cursor<Vec<u8>>, &'a mut dyn Read>>>>;

/// Where the rows come from.
enum Rows<'a> {
    /// Record by record, after `lines_before` lines and `bytes_before` bytes.
    Records {
        csv: Box<Quoted<'a>>,
        lines_before: usize,
        bytes_before: u64,
    },
    /// Chunks of whole lines.
    Chunks(LineChunks<'a>),
}

/// A program read a block at a time; see the module docs.
pub struct ProgramReader<'a> {
    layout: ProgramLayout,
    path: &'a Path,
    rows: Rows<'a>,
    /// Targets handed out so far.
    targets: usize,
}

impl<'a> ProgramReader<'a> {
    /// Reads the header of the program `input` (`path` names it in
    /// messages) for `robot`, written as `format` says (units, column
    /// names, separator, decimal mark).
    ///
    /// # Errors
    /// [`Error::Read`] when the stream fails, [`Error::Parse`] with the line
    /// for a header that is missing or names no targets.
    pub fn new(
        input: &'a mut dyn Read,
        path: &'a Path,
        robot: &Robot,
        format: &DataFormat,
    ) -> Result<Self, Error> {
        Self::in_chunks(input, path, robot, format, CHUNK_BYTES)
    }

    /// [`new`](Self::new), reading chunks of about `chunk_bytes`.
    pub(super) fn in_chunks(
        input: &'a mut dyn Read,
        path: &'a Path,
        robot: &Robot,
        format: &DataFormat,
        chunk_bytes: usize,
    ) -> Result<Self, Error> {
        // A program's poses are read as quaternions: another form is refused,
        // not ignored.
        if format.rotation != crate::rotation::RotationFormat::Quaternion {
            return Err(Error::Format {
                path: path.to_owned(),
                message: format!(
                    "a program's pose targets are read as quaternions (qw,qx,qy,qz), not as {}",
                    format.rotation.name()
                ),
            });
        }
        // The head of the file, whose rows are read in parts on all cores
        // (and then the rest in chunks) when it holds no quote.
        let mut head = Vec::with_capacity(chunk_bytes + 1);
        (&mut *input)
            .take(chunk_bytes as u64)
            .read_to_end(&mut head)
            .map_err(|cause| Error::Read {
                path: path.to_owned(),
                cause,
            })?;
        // A program that states its units (as gecaro writes one in other
        // units than its own) is read in them where the request leaves
        // gecaro's own.
        let stated = stated_units(&head)
            .map_err(|(line, message)| Error::parse(path, line, None, message))?;
        let units_stated = stated.is_some();
        let format = &match stated {
            Some((line, stated)) => DataFormat {
                units: units_to_read(format.units, stated)
                    .map_err(|message| Error::parse(path, line, None, message))?,
                ..format.clone()
            },
            None => format.clone(),
        };
        let (mut reader, separator) = csv_reader((&head[..]).chain(&mut *input), format.delimiter);
        let Some((header, header_line)) = next_record(&mut reader, path)? else {
            return Err(Error::parse(
                path,
                1,
                None,
                format!(
                    "the file is empty; a program's header names {}",
                    target_columns(robot.joint_count())
                ),
            ));
        };
        let mut layout =
            ProgramLayout::new(&header, (path, header_line), robot, format, separator)?;
        layout.units_stated = units_stated;
        let start = (reader.position().byte() as usize).min(head.len());
        drop(reader);
        let lines_before = memchr::memchr_iter(b'\n', &head[..start]).count();
        let rows = if memchr::memchr(b'"', &head).is_some() {
            // Quoted fields may hold line breaks: one pass over the stream.
            let mut rest = Cursor::new(head);
            rest.set_position(start as u64);
            let csv = csv_reader_with(
                LineLimit::new(
                    std::io::BufReader::with_capacity(1 << 16, rest.chain(input)),
                    MAX_LINE_BYTES,
                ),
                separator,
            );
            Rows::Records {
                csv: Box::new(csv),
                lines_before,
                bytes_before: start as u64,
            }
        } else {
            Rows::Chunks(LineChunks::new(
                (head, start),
                input,
                lines_before,
                chunk_bytes,
                path,
            ))
        };
        Ok(ProgramReader {
            layout,
            path,
            rows,
            targets: 0,
        })
    }

    /// The program's columns.
    pub fn layout(&self) -> &ProgramLayout {
        &self.layout
    }

    /// Targets read so far.
    pub fn targets(&self) -> usize {
        self.targets
    }

    /// Bytes of the file read through so far (for progress).
    pub fn bytes_read(&self) -> u64 {
        match &self.rows {
            Rows::Records {
                csv, bytes_before, ..
            } => bytes_before + csv.position().byte(),
            Rows::Chunks(chunks) => chunks.bytes_read(),
        }
    }

    /// The next targets of the program, in its order; `None` at its end.
    ///
    /// # Errors
    /// [`Error::Parse`] with line and column for any problem of content,
    /// a program with no target, or more than `MAX_TARGETS`;
    /// [`Error::Read`] when the stream fails.
    pub fn next_block(&mut self) -> Result<Option<ProgramBlock>, Error> {
        let (layout, path) = (&self.layout, self.path);
        let mut block = ProgramBlock::default();
        match &mut self.rows {
            Rows::Records {
                csv, lines_before, ..
            } => {
                let mut record = csv::StringRecord::new();
                while block.len() < RECORDS {
                    let Some(line) = read_record(csv, path, *lines_before, &mut record)? else {
                        break;
                    };
                    block.add(layout, path, &record, line)?;
                }
            }
            Rows::Chunks(chunks) => {
                if let Some((chunk, lines)) = chunks.next_chunk()? {
                    // A short chunk is one part: a thread costs more.
                    let count = if chunk.len() < PART_MIN_BYTES {
                        1
                    } else {
                        available_threads()
                    };
                    let parts = line_parts(chunk, lines, count);
                    // Room for a target a line, made once: the whole block's
                    // and each part's (a part grown a target at a time moves
                    // as it grows).
                    block = ProgramBlock::with_capacity(parts.iter().map(|part| part.2).sum());
                    let parts = run_parts(parts, |(bytes, lines_before, own_lines)| {
                        let mut part = PartBlock {
                            layout,
                            path,
                            block: ProgramBlock::with_capacity(own_lines),
                        };
                        let error = read_part_records(
                            bytes,
                            lines_before,
                            (layout.separator, path),
                            &mut part,
                        );
                        (part.block, error)
                    });
                    for (part, error) in parts {
                        block.append(part);
                        if let Some(error) = error {
                            // (Targets beyond the limit before the error
                            // are named first.)
                            self.check_room(&block)?;
                            return Err(error);
                        }
                    }
                }
            }
        }
        self.check_room(&block)?;
        if block.is_empty() {
            return if self.targets == 0 {
                Err(Error::parse(
                    path,
                    self.layout.header_line + 1,
                    None,
                    "the program has a header but no targets",
                ))
            } else {
                Ok(None)
            };
        }
        self.targets += block.len();
        Ok(Some(block))
    }

    /// Refuses a block that would take the program beyond [`MAX_TARGETS`],
    /// naming the first line beyond.
    fn check_room(&self, block: &ProgramBlock) -> Result<(), Error> {
        let room = MAX_TARGETS - self.targets;
        if block.len() > room {
            return Err(Error::parse(
                self.path,
                block.line(room),
                None,
                format!(
                    "more than {MAX_TARGETS} targets; reading stopped here (split the program)"
                ),
            ));
        }
        Ok(())
    }
}
