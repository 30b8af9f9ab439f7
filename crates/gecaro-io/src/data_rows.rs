//! The rows of a data file after its header: each record read into the
//! samples' columns (joint values scaled to the robot's units, position,
//! unit quaternion, group id, distance), and a file held in memory read in
//! parts on all cores.
//!
//! A part starts at a line break, so records, comments and line numbers are
//! those of the whole file. Each part writes its records straight into the
//! samples' columns, in a run of slots of its own, one per line
//! ([`FilledSamples`]): the parts settled in order are the samples a single
//! pass reads, and the first error in part order is the first error in the
//! file. Parts are used only where that holds without further care: no
//! quoted field (a quote may hold a line break). A file too long to hold is
//! read in chunks the same way, each chunk's parts written after the
//! samples before it ([`RowReader::read_chunks`]).

use gecaro_core::LinkMass;
use gecaro_data::parallel::{PARTS_PER_THREAD, available_threads, run_parts};
use gecaro_data::sample::{RowSigma, SampleLoads};
use gecaro_data::samples::{FilledSamples, SampleShape, SampleSlots, SlotMut};
use nalgebra::Vector3;
use std::io::Read;
use std::path::Path;

use crate::Error;
use crate::columns::{field_number, not_a_number};
use crate::input::{LineLimit, NOT_TEXT, for_each_record};
use crate::line_chunks::{LineChunks, line_parts};
use crate::plain_body::{RecordFields, RecordSink, read_part_records};
use crate::pose::{quaternion_deviation, unit_quaternion};
use crate::rotation::RotationFormat;

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

/// Where each field of a sample comes from in a record, and its scale.
pub(crate) struct Fields {
    /// Column and scale of each joint's motor variable.
    pub(crate) joints: Vec<(usize, f64)>,
    /// Columns of x, y, z.
    pub(crate) position: Option<[usize; 3]>,
    /// Columns of qw, qx, qy, qz; of rx, ry, rz (and 0) when the file
    /// writes orientations in another `rotation` form.
    pub(crate) orientation: Option<[usize; 4]>,
    /// How the file writes orientations.
    pub(crate) rotation: RotationFormat,
    /// Column of the set or pair id.
    pub(crate) group: Option<usize>,
    /// Column of the distance.
    pub(crate) distance: Option<usize>,
    /// Columns of the payload, when the file states one.
    pub(crate) payload: Option<PayloadColumns>,
    /// Columns of each row's σ of lengths and of angles, when the file
    /// has either.
    pub(crate) sigma: Option<[Option<usize>; 2]>,
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

/// What the rows gave: their samples up to the first error, the
/// quaternions normalised, and the first error.
pub(crate) struct Rows {
    pub(crate) samples: FilledSamples,
    pub(crate) normalised: Normalised,
    pub(crate) error: Option<Error>,
}

/// What a part of the rows gave: the slots it filled, up to its first error.
struct PartRead {
    filled: usize,
    normalised: Normalised,
    error: Option<Error>,
}

/// A part's slots, filled by a [`RowReader`] record by record.
struct PartSink<'r, 'a, 's> {
    reader: &'r RowReader<'a>,
    slots: SampleSlots<'s>,
    normalised: Normalised,
}

impl RecordSink for PartSink<'_, '_, '_> {
    fn take(&mut self, record: &impl RecordFields, line: usize) -> Result<(), Error> {
        self.reader
            .put(&mut self.slots, &mut self.normalised, record, line)
    }

    fn restart(&mut self) {
        self.slots.clear();
        self.normalised = Normalised::default();
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
    /// Radians per angle unit of the file (Euler angles, rotation vectors).
    pub(crate) angle: f64,
}

impl RowReader<'_> {
    /// No rows yet.
    fn rows(&self) -> Rows {
        let fields = &self.fields;
        Rows {
            samples: FilledSamples::new(SampleShape {
                joints: fields.joints.len(),
                position: fields.position.is_some(),
                orientation: fields.orientation.is_some(),
                group: fields.group.is_some(),
                distance: fields.distance.is_some(),
                loads: fields.payload.is_some(),
                sigma: fields.sigma.is_some(),
            }),
            normalised: Normalised::default(),
            error: None,
        }
    }

    /// Reads the records of `csv` to its end or its first error, one by
    /// one (a stream whose quoted fields may hold line breaks); `lines_before`
    /// is the number of lines of the file before the reader's first byte. At
    /// most [`MAX_CONFIGURATIONS`] samples: one more record is an error.
    pub(crate) fn read<R: Read>(
        &self,
        csv: &mut csv::Reader<LineLimit<R>>,
        lines_before: usize,
    ) -> Rows {
        let mut rows = self.rows();
        let (samples, normalised) = (&mut rows.samples, &mut rows.normalised);
        rows.error = for_each_record(
            csv,
            self.path,
            lines_before,
            |record: &csv::ByteRecord, line| {
                if samples.len() == MAX_CONFIGURATIONS {
                    return Err(self.too_many(line));
                }
                samples.push_with(|slot| self.fill(record, line, normalised, slot))
            },
        );
        rows
    }

    /// Reads `body` (whole lines of the file after its header, the first
    /// being line `lines_before + 1`), in parts on all cores when it is long
    /// and holds no quote ([`read_body`](Self::read_body)). At most
    /// [`MAX_CONFIGURATIONS`] samples: one more record is an error.
    pub(crate) fn read_all(&self, body: &[u8], lines_before: usize, separator: u8) -> Rows {
        let mut rows = self.rows();
        let (reads, _) = self.read_body(body, lines_before, separator, &mut rows.samples, |_| 0);
        self.settle(&mut rows, reads, MAX_CONFIGURATIONS);
        rows
    }

    /// Reads `body` (whole lines, the first being line `lines_before + 1`)
    /// into slots after the settled `samples`, a slot per line (a record is
    /// at most one; room is first made for `room(lines)` samples in all,
    /// `lines` the body's): in parts on all cores when it is long and holds
    /// no quote (a quote may hold a line break), else in one part. Returns
    /// the parts' reads, in order, to be settled ([`settle`](Self::settle)),
    /// and the body's line breaks.
    fn read_body(
        &self,
        body: &[u8],
        lines_before: usize,
        separator: u8,
        samples: &mut FilledSamples,
        room: impl FnOnce(usize) -> usize,
    ) -> (Vec<PartRead>, usize) {
        let threads = available_threads();
        let parts =
            if threads < 2 || body.len() < PART_MIN_BYTES || memchr::memchr(b'"', body).is_some() {
                vec![(body, lines_before, memchr::memchr_iter(b'\n', body).count())]
            } else {
                // The threads take the parts in turn (see `run_parts`): several
                // each, so that one started late takes fewer.
                let parts = (threads * PARTS_PER_THREAD).min(body.len() / MIN_PART_BYTES);
                line_parts(body, lines_before, parts.max(threads))
            };
        let breaks: usize = parts.iter().map(|(_, _, own)| own).sum();
        // A slot per line: the last one's too when it lacks its line break
        // (at the file's end).
        let counts: Vec<usize> = parts
            .iter()
            .map(|(bytes, _, own)| own + usize::from(!bytes.ends_with(b"\n")))
            .collect();
        samples.make_room(room(counts.iter().sum()));
        let slots = samples.slots(&counts);
        let reads = run_parts(
            parts.into_iter().zip(slots).collect(),
            |((bytes, lines_before, _), slots)| {
                self.read_part(bytes, lines_before, slots, separator)
            },
        );
        (reads, breaks)
    }

    /// Reads a part of a body into its slots ([`read_part_records`]).
    fn read_part(
        &self,
        part: &[u8],
        lines_before: usize,
        slots: SampleSlots<'_>,
        separator: u8,
    ) -> PartRead {
        let mut sink = PartSink {
            reader: self,
            slots,
            normalised: Normalised::default(),
        };
        let error = read_part_records(part, lines_before, (separator, self.path), &mut sink);
        PartRead {
            filled: sink.slots.len(),
            normalised: sink.normalised,
            error,
        }
    }

    /// Writes the sample of `record` at `line` into the next slot.
    fn put(
        &self,
        slots: &mut SampleSlots<'_>,
        normalised: &mut Normalised,
        record: &impl RecordFields,
        line: usize,
    ) -> Result<(), Error> {
        let Some(slot) = slots.next_slot() else {
            // A record is at most one line, and a part has a slot per line.
            return Err(self.fail(
                line,
                None,
                "more records than lines in a part of the file (a bug of gecaro's reader)".into(),
            ));
        };
        self.fill(record, line, normalised, slot)?;
        slots.commit();
        Ok(())
    }

    /// Settles the parts' reads into `rows` in order, up to the first part
    /// with an error (its samples before the error kept) or to `limit`
    /// samples, one more being an error naming its line; false when
    /// reading stops there.
    fn settle(&self, rows: &mut Rows, reads: Vec<PartRead>, limit: usize) -> bool {
        let mut filled = Vec::with_capacity(reads.len());
        let mut count = rows.samples.len();
        let mut error = None;
        for read in reads {
            filled.push(read.filled);
            count = count.saturating_add(read.filled);
            rows.normalised = rows.normalised.then(read.normalised);
            if count > limit || read.error.is_some() {
                error = read.error;
                break;
            }
        }
        rows.samples.settle(&filled);
        if rows.samples.len() > limit {
            let line = rows.samples.line(limit).unwrap_or(0);
            rows.samples.truncate(limit);
            error = Some(self.too_many(line));
        }
        rows.error = error;
        rows.error.is_none()
    }

    /// Reads a body too long to hold at once: the bytes of `head` from
    /// `start` (a line start; `head` becomes the chunks' buffer) and then
    /// `rest`, in chunks of about `chunking.bytes`
    /// ([`CHUNK_BYTES`]) cut at line breaks, each read into the samples in
    /// parts on all cores ([`read_body`](Self::read_body)). Memory beyond
    /// the samples is one chunk; the samples, line numbers and first error
    /// are those of a single pass (a quoted field with a line break across
    /// a chunk's end aside: data files hold numbers). At most
    /// `chunking.limit` samples: one more is an error naming its line.
    pub(crate) fn read_chunks(
        &self,
        (head, start, rest): (Vec<u8>, usize, &mut dyn Read),
        lines_before: usize,
        separator: u8,
        chunking: Chunking,
    ) -> Rows {
        let mut rows = self.rows();
        let mut chunks =
            LineChunks::new((head, start), rest, lines_before, chunking.bytes, self.path);
        let mut first = true;
        loop {
            let (chunk, lines) = match chunks.next_chunk() {
                Ok(Some(chunk)) => chunk,
                Ok(None) => return rows,
                Err(error) => {
                    rows.error = Some(error);
                    return rows;
                }
            };
            // The first chunk makes room for the file's rows, at its rate
            // ([`Chunking::foreseen`]): the samples are then not copied as
            // they grow.
            let bytes = chunk.len();
            let room = |lines| {
                if first {
                    chunking.foreseen(lines, bytes)
                } else {
                    0
                }
            };
            let (reads, breaks) = self.read_body(chunk, lines, separator, &mut rows.samples, room);
            first = false;
            chunks.counted(breaks);
            if !self.settle(&mut rows, reads, chunking.limit) {
                return rows;
            }
        }
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

    /// One record written into `slot` (whole, when it succeeds).
    fn fill(
        &self,
        record: &impl RecordFields,
        line: usize,
        normalised: &mut Normalised,
        slot: SlotMut<'_>,
    ) -> Result<(), Error> {
        // The record is read as bytes (its numbers are parsed from them);
        // the file must still be text, as in a single pass of the `csv`
        // crate's text records (a binary file is named as such).
        if !record.is_text() {
            return Err(self.fail(line, None, NOT_TEXT.into()));
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
        for ((column, scale), motor_position) in fields.joints.iter().zip(slot.motor) {
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
            *motor_position = motor;
        }
        *slot.line = line;
        if let Some([x, y, z]) = fields.position {
            slot.position
                .copy_from_slice(&[length(x)?, length(y)?, length(z)?]);
        }
        if let Some([w, i, j, k]) = fields.orientation {
            let orientation = if fields.rotation == RotationFormat::Quaternion {
                let (qw, qx, qy, qz) = (value(w)?, value(i)?, value(j)?, value(k)?);
                if let Some(deviation) = quaternion_deviation(qw, qx, qy, qz) {
                    normalised.add(deviation, line);
                }
                unit_quaternion(qw, qx, qy, qz)
                    .map_err(|message| self.fail(line, Some(w), message))?
            } else {
                let angles = [value(w)?, value(i)?, value(j)?].map(|angle| angle * self.angle);
                fields.rotation.orientation(angles)
            };
            slot.orientation.copy_from_slice(&[
                orientation.w,
                orientation.i,
                orientation.j,
                orientation.k,
            ]);
        }
        if let (Some(column), Some(group)) = (fields.group, slot.group) {
            let id = std::str::from_utf8(record.field(column))
                .ok()
                .and_then(|id| id.trim().parse().ok());
            *group = id.ok_or_else(|| {
                self.fail(
                    line,
                    Some(column),
                    format!("`{}` is not an id (a whole number ≥ 0)", text(column)),
                )
            })?;
        }
        if let (Some(column), Some(distance)) = (fields.distance, slot.distance) {
            *distance = length(column)?;
        }
        if let Some(columns) = fields.sigma {
            // σ of lengths, then of angles, each a standard deviation above
            // zero that an instrument can state; an empty field states none.
            let scales = [(self.length, "m"), (self.angle, "rad")];
            for (index, ((column, (scale, unit)), stored)) in columns
                .into_iter()
                .zip(scales)
                .zip(slot.sigma.iter_mut())
                .enumerate()
            {
                *stored = 0.0;
                let Some(column) = column else { continue };
                if record.field(column).iter().all(u8::is_ascii_whitespace) {
                    continue;
                }
                let sigma = value(column)? * scale;
                let (admitted, largest) = if index == 0 {
                    (RowSigma::admits_length(sigma), RowSigma::MAX_LENGTH)
                } else {
                    (RowSigma::admits_angle(sigma), RowSigma::MAX_ANGLE)
                };
                if !admitted {
                    return Err(self.fail(
                        line,
                        Some(column),
                        format!(
                            "`{}` is not a standard deviation: above 0 and at most {largest} {unit} \
                             (leave the field empty where the row states none)",
                            text(column)
                        ),
                    ));
                }
                *stored = sigma;
            }
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
            let payload = LinkMass {
                mass: kilograms,
                com,
            };
            if let Err(message) = crate::payload::check_payload(&payload) {
                let column = if payload.mass > crate::payload::MAX_PAYLOAD_KG {
                    mass
                } else {
                    centre.map_or(mass, |[x, _, _]| x)
                };
                return Err(self.fail(line, Some(column), message));
            }
            if let Some(loads) = slot.loads {
                *loads = Some(Box::new(SampleLoads {
                    payload: Some(payload),
                    ..SampleLoads::default()
                }));
            }
        }
        Ok(())
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
