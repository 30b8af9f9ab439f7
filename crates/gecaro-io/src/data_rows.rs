//! The rows of a data file after its header: each record read into a
//! [`Sample`] (joint values scaled to the robot's units, position, unit
//! quaternion, group id, distance), and a file held in memory read in parts
//! on all cores.
//!
//! A part starts at a line break, so records, comments and line numbers are
//! those of the whole file: the parts' samples joined in part order are the
//! samples a single pass reads, and the first error in part order is the
//! first error in the file. Parts are used only where that holds without
//! further care: no quoted field (a quote may hold a line break) and fewer
//! lines than [`MAX_CONFIGURATIONS`] (the limit cannot fall inside a part).
//! A file too long to hold is read in chunks the same way, each chunk's
//! parts joined to the samples while the next chunk is read
//! ([`RowReader::read_chunks`]).

use gecaro_calib::parallel::{PARTS_PER_THREAD, alongside, available_threads, run_parts};
use gecaro_calib::study::{MotorPositions, Sample, SamplesBuilder};
use gecaro_core::LinkMass;
use nalgebra::Vector3;
use std::io::Read;
use std::path::Path;

use crate::Error;
use crate::columns::{field_number, not_a_number};
use crate::input::{LineLimit, MAX_LINE_BYTES, csv_reader_with, for_each_record};
use crate::line_chunks::{LineChunks, line_parts};
use crate::plain_body::{RecordFields, for_each_plain_record};
use crate::pose::{quaternion_deviation, unit_quaternion};

/// The largest motor value a data file holds: 2⁵³, beyond which a double
/// no longer tells one encoder count from the next.
const MAX_MOTOR_VALUE: f64 = 9.007_199_254_740_992e15;

/// Most configurations a data file may hold. Longer files are streamed, so
/// a larger one (or an endless stream) stops here with an error naming the
/// line, instead of exhausting memory; no calibration needs this many.
pub const MAX_CONFIGURATIONS: usize = 1_000_000;

/// Bodies shorter than this are read in one part: a thread costs more.
pub(crate) const PART_MIN_BYTES: usize = 1 << 17;

/// The shortest part of a body read in parts (about 180 position rows).
const MIN_PART_BYTES: usize = 1 << 15;

/// Bytes of a long file read at once ([`RowReader::read_chunks`]).
pub(crate) const CHUNK_BYTES: usize = 16 << 20;

/// Chunks the first one makes room for when the file's length is not
/// known (a million position rows are about ten): the samples are then not
/// copied as they grow.
const CHUNKS_FORESEEN: usize = 10;

/// How a body too long to hold at once is read ([`RowReader::read_chunks`]).
#[derive(Copy, Clone, Debug)]
pub(crate) struct Chunking {
    /// Bytes read at once (about: chunks end at line breaks).
    pub(crate) bytes: usize,
    /// Samples read at most ([`MAX_CONFIGURATIONS`]): one more is an error
    /// naming its line.
    pub(crate) limit: usize,
    /// The whole file's length in bytes, when known: the samples are given
    /// room for all its rows once the first chunk's are read (rows per byte
    /// of that chunk, 1 % more), else for [`CHUNKS_FORESEEN`] more chunks.
    pub(crate) length: Option<u64>,
}

impl Chunking {
    /// The samples to make room for, once the first chunk, of `bytes`
    /// bytes, gave `read` of them.
    fn foreseen(&self, read: usize, bytes: usize) -> usize {
        let foreseen = match self.length {
            Some(length) if bytes > 0 => {
                let per_byte = read as f64 / bytes as f64;
                // Saturating (as casts are) for any length.
                (per_byte * length as f64 * 1.01).ceil() as usize
            }
            _ => read.saturating_mul(1 + CHUNKS_FORESEEN),
        };
        // No room beyond the limit, nor beyond [`MAX_CONFIGURATIONS`]
        // whatever the limit (room is memory).
        foreseen.max(read).min(self.limit).min(MAX_CONFIGURATIONS)
    }
}

/// A chunk read in parts, not yet joined to the samples before it.
struct ChunkRead {
    parts: Vec<Rows>,
    /// The file's lines before the chunk.
    lines: usize,
    /// The chunk's length in bytes.
    bytes: usize,
}

/// Where each field of a sample comes from in a record, and its scale.
pub(crate) struct Fields {
    /// Column and scale of each joint's motor variable.
    pub(crate) joints: Vec<(usize, f64)>,
    /// Columns of x, y, z.
    pub(crate) position: Option<[usize; 3]>,
    /// Columns of qw, qx, qy, qz.
    pub(crate) orientation: Option<[usize; 4]>,
    /// Column of the set or pair id.
    pub(crate) group: Option<usize>,
    /// Column of the distance.
    pub(crate) distance: Option<usize>,
    /// Columns of the payload, when the file states one.
    pub(crate) payload: Option<PayloadColumns>,
}

/// Columns of the payload's mass (kg) and, when given, of its centre in
/// frame n+1 (a length each).
#[derive(Copy, Clone, Debug)]
pub(crate) struct PayloadColumns {
    pub(crate) mass: usize,
    pub(crate) centre: Option<[usize; 3]>,
}

/// Quaternions normalised on reading, for a note: how many, the largest
/// deviation of their norm from 1, and the line of the first with it.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Normalised {
    pub(crate) count: usize,
    pub(crate) largest: f64,
    pub(crate) line: usize,
}

impl Normalised {
    fn add(&mut self, deviation: f64, line: usize) {
        self.count += 1;
        if deviation > self.largest {
            self.largest = deviation;
            self.line = line;
        }
    }

    /// This and a later part's counts (the first line with the largest
    /// deviation stays).
    fn then(self, later: Normalised) -> Normalised {
        let mut joined = if later.largest > self.largest {
            later
        } else {
            self
        };
        joined.count = self.count + later.count;
        joined
    }
}

/// What a part of the rows gave: its samples up to its first error.
pub(crate) struct Rows {
    pub(crate) samples: SamplesBuilder,
    pub(crate) normalised: Normalised,
    pub(crate) error: Option<Error>,
}

impl Rows {
    /// No rows yet, with room for `capacity` samples (at most
    /// [`MAX_CONFIGURATIONS`]).
    fn with_capacity(capacity: usize) -> Rows {
        Rows {
            samples: SamplesBuilder::with_capacity(capacity.min(MAX_CONFIGURATIONS)),
            normalised: Normalised::default(),
            error: None,
        }
    }

    /// The rows of a later part after these: its samples, its normalised
    /// quaternions, and its first error, which ends the reading (`false`:
    /// read no further). A part after an error is not to be appended.
    fn append(&mut self, later: Rows) -> bool {
        debug_assert!(self.error.is_none());
        self.samples.append(later.samples);
        self.normalised = self.normalised.then(later.normalised);
        self.error = later.error;
        self.error.is_none()
    }
}

/// How the records of one file are read.
pub(crate) struct RowReader<'a> {
    pub(crate) path: &'a Path,
    /// The header's names (for messages and the field count).
    pub(crate) names: &'a [String],
    pub(crate) fields: Fields,
    pub(crate) decimal_comma: bool,
    /// Metres per length unit of the file.
    pub(crate) length: f64,
}

impl RowReader<'_> {
    /// Reads the records of `csv` to its end or its first error;
    /// `lines_before` is the number of lines of the file before the reader's
    /// first byte, `capacity` the samples to make room for at once (a
    /// growing list of a million samples is copied, into fresh memory, at
    /// each doubling). At most [`MAX_CONFIGURATIONS`] samples: one more
    /// record is an error.
    pub(crate) fn read<R: Read>(
        &self,
        csv: &mut csv::Reader<LineLimit<R>>,
        lines_before: usize,
        capacity: usize,
    ) -> Rows {
        let mut rows = Rows::with_capacity(capacity);
        let (samples, normalised) = (&mut rows.samples, &mut rows.normalised);
        rows.error = for_each_record(
            csv,
            self.path,
            lines_before,
            |record: &csv::ByteRecord, line| self.push_sample(samples, normalised, record, line),
        );
        rows
    }

    /// [`read`](Self::read) of a part of a body, the way of
    /// [`crate::plain_body`] when the part is plain.
    fn read_part(&self, part: &[u8], lines_before: usize, capacity: usize, separator: u8) -> Rows {
        let mut rows = Rows::with_capacity(capacity);
        let (samples, normalised) = (&mut rows.samples, &mut rows.normalised);
        match for_each_plain_record(part, lines_before, separator, |record, line| {
            self.push_sample(samples, normalised, record, line)
        }) {
            Some(error) => {
                rows.error = error;
                rows
            }
            None => {
                let mut csv = csv_reader_with(LineLimit::new(part, MAX_LINE_BYTES), separator);
                self.read(&mut csv, lines_before, capacity)
            }
        }
    }

    /// Adds the sample of `record` at `line`, unless it is one too many.
    fn push_sample(
        &self,
        samples: &mut SamplesBuilder,
        normalised: &mut Normalised,
        record: &impl RecordFields,
        line: usize,
    ) -> Result<(), Error> {
        if samples.len() == MAX_CONFIGURATIONS {
            return Err(self.too_many(line));
        }
        samples.push(&self.sample(record, line, normalised)?);
        Ok(())
    }

    /// Reads `body` (whole lines of the file after its header, the first
    /// being line `lines_before + 1`) in parts on all cores when it is
    /// long and holds no quote; `None` when it is to be read in one pass.
    pub(crate) fn read_in_parts(
        &self,
        body: &[u8],
        lines_before: usize,
        separator: u8,
    ) -> Option<(Rows, usize)> {
        let (parts, breaks) = self.read_parts(body, lines_before, separator, true)?;
        let mut read = parts.into_iter();
        let mut joined = read.next()?;
        if joined.error.is_none() {
            for rows in read {
                if !joined.append(rows) {
                    break;
                }
            }
        }
        Some((joined, breaks))
    }

    /// The parts of [`read_in_parts`](Self::read_in_parts), in order, each
    /// up to its first error (the parts after an error are not to be
    /// read), and the body's line breaks; with `room_in_first`, the first
    /// part makes room for every line, the parts to be moved after its own.
    fn read_parts(
        &self,
        body: &[u8],
        lines_before: usize,
        separator: u8,
        room_in_first: bool,
    ) -> Option<(Vec<Rows>, usize)> {
        let threads = available_threads();
        if threads < 2 || body.len() < PART_MIN_BYTES || memchr::memchr(b'"', body).is_some() {
            return None;
        }
        // The threads take the parts in turn (see `run_parts`): several
        // each, so that one started late takes fewer.
        let parts = (threads * PARTS_PER_THREAD).min(body.len() / MIN_PART_BYTES);
        let cut = line_parts(body, lines_before, parts.max(threads));
        let breaks: usize = cut.iter().map(|(_, _, own)| own).sum();
        if breaks >= MAX_CONFIGURATIONS {
            return None;
        }
        // Each part makes room for its own lines, the first for every line
        // when the others' samples are to be moved after its own.
        let parts: Vec<(&[u8], usize, usize)> = cut
            .iter()
            .enumerate()
            .map(|(index, &(bytes, lines, own))| {
                let capacity = if index == 0 && room_in_first {
                    breaks + 1
                } else {
                    own + 1
                };
                (bytes, lines, capacity)
            })
            .collect();
        let read = run_parts(parts, |(bytes, lines_before, capacity)| {
            self.read_part(bytes, lines_before, capacity, separator)
        });
        Some((read, breaks))
    }

    /// Reads a body too long to hold at once: the bytes of `head` from
    /// `start` (a line start; `head` becomes the chunks' buffer) and then
    /// `rest`, in chunks of about `chunking.bytes`
    /// ([`CHUNK_BYTES`]) cut at line breaks, each read in parts on all cores
    /// ([`read_in_parts`](Self::read_in_parts)) or, holding a quote, in one
    /// pass. Memory beyond the samples is one chunk; the samples, line
    /// numbers and first error are those of a single pass (a quoted field
    /// with a line break across a chunk's end aside: data files hold
    /// numbers). At most `chunking.limit` samples: one more is an error
    /// naming its line.
    pub(crate) fn read_chunks(
        &self,
        (head, start, rest): (Vec<u8>, usize, &mut dyn Read),
        lines_before: usize,
        separator: u8,
        chunking: Chunking,
    ) -> Rows {
        let mut joined = Rows {
            samples: SamplesBuilder::with_capacity(0),
            normalised: Normalised::default(),
            error: None,
        };
        let mut chunks =
            LineChunks::new((head, start), rest, lines_before, chunking.bytes, self.path);
        // A chunk's parts are joined to the samples (a copy, single-threaded)
        // while the next chunk is read and cut into parts: the same samples,
        // in the same order, with the same first error.
        let mut pending: Option<ChunkRead> = None;
        loop {
            let (whole, next) = alongside(
                || {
                    pending
                        .take()
                        .is_none_or(|read| self.join(&mut joined, read, chunking))
                },
                || -> Result<Option<ChunkRead>, Error> {
                    let Some((chunk, lines)) = chunks.next_chunk()? else {
                        return Ok(None);
                    };
                    let bytes = chunk.len();
                    let parts = match self.read_parts(chunk, lines, separator, false) {
                        Some((parts, breaks)) => {
                            chunks.counted(breaks);
                            parts
                        }
                        None => {
                            let mut csv =
                                csv_reader_with(LineLimit::new(chunk, MAX_LINE_BYTES), separator);
                            vec![self.read(&mut csv, lines, 0)]
                        }
                    };
                    Ok(Some(ChunkRead {
                        parts,
                        lines,
                        bytes,
                    }))
                },
            );
            if !whole {
                return joined;
            }
            match next {
                Ok(Some(read)) => pending = Some(read),
                Ok(None) => return joined,
                Err(error) => {
                    joined.error = Some(error);
                    return joined;
                }
            }
        }
    }

    /// Appends the parts of a chunk to `joined` (the first chunk's make
    /// room for the file's rows, [`Chunking::foreseen`]); false when
    /// reading stops there, at a part's error or at the limit.
    fn join(&self, joined: &mut Rows, read: ChunkRead, chunking: Chunking) -> bool {
        let ChunkRead {
            parts,
            lines,
            bytes,
        } = read;
        if joined.samples.is_empty() {
            let read: usize = parts.iter().map(|rows| rows.samples.len()).sum();
            joined.samples.reserve(chunking.foreseen(read, bytes));
        }
        for rows in parts {
            let room = chunking.limit.saturating_sub(joined.samples.len());
            if rows.samples.len() > room {
                let line = rows.samples.line(room).unwrap_or(lines + 1);
                let mut kept = rows.samples;
                kept.truncate(room);
                joined.samples.append(kept);
                joined.error = Some(self.too_many(line));
                return false;
            }
            if !joined.append(rows) {
                return false;
            }
        }
        true
    }

    /// The error of one record beyond [`MAX_CONFIGURATIONS`], at `line`.
    fn too_many(&self, line: usize) -> Error {
        self.fail(
            line,
            None,
            format!(
                "more than {MAX_CONFIGURATIONS} configurations; reading stopped here \
                 (calibration needs far fewer: split or subsample the file)"
            ),
        )
    }

    fn fail(&self, line: usize, column: Option<usize>, message: String) -> Error {
        Error::parse(
            self.path,
            line,
            column.map(|column| self.names[column].clone()),
            message,
        )
    }

    /// One record as a sample.
    fn sample(
        &self,
        record: &impl RecordFields,
        line: usize,
        normalised: &mut Normalised,
    ) -> Result<Sample, Error> {
        // The record is read as bytes (its numbers are parsed from them);
        // the file must still be text, as in a single pass of the `csv`
        // crate's text records (a binary file is named as such).
        let bytes = record.bytes();
        if !bytes.is_ascii() && std::str::from_utf8(bytes).is_err() {
            return Err(self.fail(line, None, "the file is not UTF-8 text".into()));
        }
        // A field as text, for a message.
        let text = |column: usize| {
            String::from_utf8_lossy(record.field(column))
                .trim()
                .to_owned()
        };
        let names = self.names;
        if record.field_count() != names.len() {
            return Err(self.fail(
                line,
                None,
                format!(
                    "{} values for {} columns ({})",
                    record.field_count(),
                    names.len(),
                    names.join(",")
                ),
            ));
        }
        let value = |column: usize| -> Result<f64, Error> {
            match field_number(record.field(column), self.decimal_comma) {
                Some(number) if number.is_finite() => Ok(number),
                Some(_) => Err(self.fail(
                    line,
                    Some(column),
                    format!("`{}` is not a finite number", text(column)),
                )),
                None => Err(self.fail(
                    line,
                    Some(column),
                    not_a_number(&text(column), self.decimal_comma),
                )),
            }
        };
        // A measured length beyond what a cell holds (1 km, as a robot
        // file's lengths) is a typo or a corrupted field, refused at its line
        // as NaN is.
        let length = |column: usize| -> Result<f64, Error> {
            let metres = value(column)? * self.length;
            if metres.abs() > gecaro_core::MAX_MAGNITUDE {
                return Err(self.fail(
                    line,
                    Some(column),
                    format!(
                        "`{}` is {} m: beyond ±{} m, no measurement in a robot cell",
                        text(column),
                        gecaro_core::Compact(metres),
                        gecaro_core::MAX_MAGNITUDE
                    ),
                ));
            }
            Ok(metres)
        };
        let fields = &self.fields;
        let mut motor_positions = MotorPositions::with_capacity(fields.joints.len());
        for (column, scale) in &fields.joints {
            let motor = value(*column)? * scale;
            if motor.abs() > MAX_MOTOR_VALUE {
                return Err(self.fail(
                    line,
                    Some(*column),
                    format!(
                        "`{}` is beyond ±{MAX_MOTOR_VALUE:e}, where a double no longer \
                         counts an encoder's steps",
                        text(*column)
                    ),
                ));
            }
            motor_positions.push(motor);
        }
        let mut sample = Sample {
            line: Some(line),
            ..Sample::new(motor_positions)
        };
        if let Some([x, y, z]) = fields.position {
            sample.position = Some(Vector3::new(length(x)?, length(y)?, length(z)?));
        }
        if let Some([w, i, j, k]) = fields.orientation {
            let (qw, qx, qy, qz) = (value(w)?, value(i)?, value(j)?, value(k)?);
            let orientation = unit_quaternion(qw, qx, qy, qz)
                .map_err(|message| self.fail(line, Some(w), message))?;
            if let Some(deviation) = quaternion_deviation(qw, qx, qy, qz) {
                normalised.add(deviation, line);
            }
            sample.orientation = Some(orientation);
        }
        if let Some(column) = fields.group {
            let id = std::str::from_utf8(record.field(column))
                .ok()
                .and_then(|id| id.trim().parse().ok());
            sample.group = Some(id.ok_or_else(|| {
                self.fail(
                    line,
                    Some(column),
                    format!("`{}` is not an id (a whole number ≥ 0)", text(column)),
                )
            })?);
        }
        if let Some(column) = fields.distance {
            sample.distance = Some(length(column)?);
        }
        if let Some(PayloadColumns { mass, centre }) = fields.payload {
            let kilograms = value(mass)?;
            if kilograms < 0.0 {
                return Err(self.fail(
                    line,
                    Some(mass),
                    format!("`{}` is not a mass in kg (≥ 0)", text(mass)),
                ));
            }
            let com = match centre {
                Some([x, y, z]) => Vector3::new(length(x)?, length(y)?, length(z)?),
                None => Vector3::zeros(),
            };
            sample.set_payload(Some(LinkMass {
                mass: kilograms,
                com,
            }));
        }
        Ok(sample)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Room for the rows of the whole file, read at the first chunk's rate
    /// with 1 % more; without a length, for ten more chunks; never beyond
    /// the limit nor below what was read.
    #[test]
    fn the_samples_foreseen() {
        let chunking = |length| Chunking {
            bytes: 1000,
            limit: 1_000_000,
            length,
        };
        // 100 rows in the first 10,000 bytes of a 1,000,000-byte file.
        assert_eq!(chunking(Some(1_000_000)).foreseen(100, 10_000), 10_100);
        assert_eq!(chunking(None).foreseen(100, 10_000), 1_100);
        assert_eq!(chunking(Some(u64::MAX)).foreseen(100, 10_000), 1_000_000);
        // Past every limit: no more than a file may hold.
        let unlimited = Chunking {
            limit: usize::MAX,
            ..chunking(Some(u64::MAX))
        };
        assert_eq!(unlimited.foreseen(100, 10_000), MAX_CONFIGURATIONS);
        assert_eq!(chunking(Some(10)).foreseen(100, 10_000), 100);
        assert_eq!(chunking(Some(1_000_000)).foreseen(0, 0), 0);
    }
}
