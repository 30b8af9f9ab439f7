//! [`Samples`](super::Samples) of one shape written in place: room for
//! many samples made at once, handed out as disjoint runs of slots to parts
//! that fill them on several cores, then settled in part order.
//!
//! A data file's reader knows every record's fields from the header (every
//! sample of a file has the same ones) and each part's line count before it
//! reads the part: a record is at most one line, so a part given a slot per
//! line writes each record straight into the columns, where the samples
//! stay. No row form is made and no part is copied after another; only the
//! slots a part left empty (comment and blank lines, or an error) close up
//! when it is settled ([`FilledSamples::settle`]).
//!
//! Room is zeroed memory from the allocator, which the system hands out
//! untouched: a page is first touched by the part that writes it, on its
//! core.
//!
//! ```
//! use gecaro_data::samples::{FilledSamples, SampleShape, Samples};
//!
//! let shape = SampleShape { joints: 2, position: true, ..SampleShape::default() };
//! let mut filled = FilledSamples::new(shape);
//! // Two parts of two lines each; the second part's first line is a comment.
//! let mut parts = filled.slots(&[2, 2]).into_iter();
//! let (mut first, mut second) = (parts.next().unwrap(), parts.next().unwrap());
//! for (line, q) in [(1, 0.1), (2, 0.2)] {
//!     let slot = first.next_slot().unwrap();
//!     slot.motor.copy_from_slice(&[q, -q]);
//!     slot.position.copy_from_slice(&[q, 0.0, 1.0]);
//!     *slot.line = line;
//!     first.commit();
//! }
//! let slot = second.next_slot().unwrap();
//! slot.motor.copy_from_slice(&[0.4, -0.4]);
//! slot.position.copy_from_slice(&[0.4, 0.0, 1.0]);
//! *slot.line = 4;
//! second.commit();
//! let filled_counts = [first.len(), second.len()];
//! filled.settle(&filled_counts);
//! let samples = Samples::from(filled);
//! assert_eq!(samples.len(), 3);
//! assert_eq!(samples.get(2).motor_positions(), &[0.4, -0.4]);
//! assert_eq!(samples.get(2).line(), Some(4));
//! ```

use std::sync::Arc;

use super::builder::Parts;
use super::column::Field;
use crate::sample::SampleLoads;

/// Which fields every sample of a [`FilledSamples`] has (each sample also
/// has its line).
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq)]
pub struct SampleShape {
    /// Motor variables per sample.
    pub joints: usize,
    /// `x, y, z`.
    pub position: bool,
    /// `qw, qx, qy, qz`.
    pub orientation: bool,
    /// A set or pair id.
    pub group: bool,
    /// A distance.
    pub distance: bool,
    /// A stated σ of lengths and of angles ([`crate::sample::RowSigma`]).
    pub sigma: bool,
    /// Loads (a payload).
    pub loads: bool,
}

impl SampleShape {
    /// The values each sample has in each column.
    fn widths(self) -> Widths {
        let width = |present: bool, width: usize| if present { width } else { 0 };
        Widths {
            motor: self.joints,
            position: width(self.position, 3),
            orientation: width(self.orientation, 4),
            group: width(self.group, 1),
            distance: width(self.distance, 1),
            sigma: width(self.sigma, 2),
            loads: width(self.loads, 1),
        }
    }
}

/// Values per sample of each column of a [`SampleShape`] (0: not held).
#[derive(Copy, Clone)]
struct Widths {
    motor: usize,
    position: usize,
    orientation: usize,
    group: usize,
    distance: usize,
    sigma: usize,
    loads: usize,
}

/// Samples of one [`SampleShape`] written in place; see the module docs.
pub struct FilledSamples {
    shape: SampleShape,
    /// Samples settled, at the start of every column.
    len: usize,
    /// Samples the columns have room for (their lengths over their widths).
    room: usize,
    motor: Vec<f64>,
    position: Vec<f64>,
    orientation: Vec<f64>,
    group: Vec<u64>,
    distance: Vec<f64>,
    sigma: Vec<f64>,
    lines: Vec<usize>,
    loads: Vec<Option<Box<SampleLoads>>>,
    /// Where each part of the last [`slots`](Self::slots) starts, and its
    /// slot count.
    handed_out: Vec<(usize, usize)>,
}

/// A run of slots of a [`FilledSamples`], for one part to fill in order.
pub struct SampleSlots<'a> {
    shape: SampleShape,
    /// Slots committed.
    len: usize,
    capacity: usize,
    motor: &'a mut [f64],
    position: &'a mut [f64],
    orientation: &'a mut [f64],
    group: &'a mut [u64],
    distance: &'a mut [f64],
    sigma: &'a mut [f64],
    lines: &'a mut [usize],
    loads: &'a mut [Option<Box<SampleLoads>>],
}

/// The fields of one slot, to be written whole before it is committed
/// ([`SampleSlots::commit`]). A field the shape lacks is an empty slice
/// (or `None`).
pub struct SlotMut<'s> {
    /// The motor variables (the shape's `joints`).
    pub motor: &'s mut [f64],
    /// `x, y, z` (m), or empty.
    pub position: &'s mut [f64],
    /// `w, x, y, z` of a unit quaternion, or empty.
    pub orientation: &'s mut [f64],
    /// The set or pair id.
    pub group: Option<&'s mut u64>,
    /// The distance (m).
    pub distance: Option<&'s mut f64>,
    /// The stated σ of lengths (m) and of angles (rad), 0 where not
    /// stated, or empty.
    pub sigma: &'s mut [f64],
    /// The line of the data file.
    pub line: &'s mut usize,
    /// The loads.
    pub loads: Option<&'s mut Option<Box<SampleLoads>>>,
}

impl FilledSamples {
    /// No samples of `shape` yet.
    pub fn new(shape: SampleShape) -> Self {
        FilledSamples {
            shape,
            len: 0,
            room: 0,
            motor: Vec::new(),
            position: Vec::new(),
            orientation: Vec::new(),
            group: Vec::new(),
            distance: Vec::new(),
            sigma: Vec::new(),
            lines: Vec::new(),
            loads: Vec::new(),
            handed_out: Vec::new(),
        }
    }

    /// The shape of every sample.
    pub fn shape(&self) -> SampleShape {
        self.shape
    }

    /// Samples settled.
    pub fn len(&self) -> usize {
        self.len
    }

    /// Whether none is settled.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// The line of settled sample `index`.
    pub fn line(&self, index: usize) -> Option<usize> {
        (index < self.len).then(|| self.lines[index])
    }

    /// Room for `room` samples in all, settled ones included (never less
    /// than is settled): zeroed memory, untouched until written. Growing
    /// copies the settled samples once.
    pub fn make_room(&mut self, room: usize) {
        if room <= self.room {
            return;
        }
        let (len, widths) = (self.len, self.shape.widths());
        grow(&mut self.motor, len * widths.motor, room * widths.motor);
        grow(
            &mut self.position,
            len * widths.position,
            room * widths.position,
        );
        grow(
            &mut self.orientation,
            len * widths.orientation,
            room * widths.orientation,
        );
        grow(&mut self.group, len * widths.group, room * widths.group);
        grow(
            &mut self.distance,
            len * widths.distance,
            room * widths.distance,
        );
        grow(&mut self.sigma, len * widths.sigma, room * widths.sigma);
        grow(&mut self.lines, len, room);
        if self.shape.loads {
            self.loads.resize_with(room, || None);
        }
        self.room = room;
    }

    /// Runs of `counts[i]` slots after the settled samples, in order, one
    /// for each part to fill (room is made for them all). Settle them with
    /// [`settle`](Self::settle) once the parts are done; slots handed out
    /// before and not settled are handed out again.
    pub fn slots(&mut self, counts: &[usize]) -> Vec<SampleSlots<'_>> {
        let total = counts
            .iter()
            .fold(0usize, |sum, count| sum.saturating_add(*count));
        self.make_room(self.len.saturating_add(total));
        let (shape, len, widths) = (self.shape, self.len, self.shape.widths());
        let mut motor = &mut self.motor[len * widths.motor..];
        let mut position = &mut self.position[len * widths.position..];
        let mut orientation = &mut self.orientation[len * widths.orientation..];
        let mut group = &mut self.group[len * widths.group..];
        let mut distance = &mut self.distance[len * widths.distance..];
        let mut sigma = &mut self.sigma[len * widths.sigma..];
        let mut lines = &mut self.lines[len..];
        let mut loads = &mut self.loads[len * widths.loads..];
        self.handed_out.clear();
        let mut start = len;
        let mut runs = Vec::with_capacity(counts.len());
        for &count in counts {
            self.handed_out.push((start, count));
            start += count;
            runs.push(SampleSlots {
                shape,
                len: 0,
                capacity: count,
                motor: cut(&mut motor, count * widths.motor),
                position: cut(&mut position, count * widths.position),
                orientation: cut(&mut orientation, count * widths.orientation),
                group: cut(&mut group, count * widths.group),
                distance: cut(&mut distance, count * widths.distance),
                sigma: cut(&mut sigma, count * widths.sigma),
                lines: cut(&mut lines, count),
                loads: cut(&mut loads, count * widths.loads),
            });
        }
        runs
    }

    /// Settles the first `filled.len()` runs of the last
    /// [`slots`](Self::slots), run i having filled its first `filled[i]`
    /// slots (the runs after them are dropped): their samples follow the
    /// settled ones in order, the empty slots between them closed up.
    pub fn settle(&mut self, filled: &[usize]) {
        let (shape, widths) = (self.shape, self.shape.widths());
        let runs = std::mem::take(&mut self.handed_out);
        for (&(start, count), &kept) in runs.iter().zip(filled) {
            let kept = kept.min(count);
            let to = self.len;
            if start != to {
                let close = |width: usize| (start * width..(start + kept) * width, to * width);
                let (from, at) = close(widths.motor);
                self.motor.copy_within(from, at);
                let (from, at) = close(widths.position);
                self.position.copy_within(from, at);
                let (from, at) = close(widths.orientation);
                self.orientation.copy_within(from, at);
                let (from, at) = close(widths.group);
                self.group.copy_within(from, at);
                let (from, at) = close(widths.distance);
                self.distance.copy_within(from, at);
                let (from, at) = close(widths.sigma);
                self.sigma.copy_within(from, at);
                self.lines.copy_within(start..start + kept, to);
                if shape.loads {
                    for offset in 0..kept {
                        self.loads[to + offset] = self.loads[start + offset].take();
                    }
                }
            }
            self.len = to + kept;
        }
        // Loads left in slots beyond the settled samples are not samples.
        let end = runs.last().map_or(self.len, |(start, count)| start + count);
        if shape.loads && end > self.len {
            self.loads[self.len..end]
                .iter_mut()
                .for_each(|loads| *loads = None);
        }
    }

    /// The first `len` samples only.
    pub fn truncate(&mut self, len: usize) {
        if len < self.len {
            if self.shape.loads {
                self.loads[len..self.len]
                    .iter_mut()
                    .for_each(|loads| *loads = None);
            }
            self.len = len;
        }
    }

    /// One more sample, written by `write` into its slot (made room for
    /// when there is none, doubling): settled when `write` succeeds. For
    /// readers that go record by record.
    ///
    /// # Errors
    /// `write`'s: the sample is not settled.
    pub fn push_with<E>(
        &mut self,
        write: impl FnOnce(SlotMut<'_>) -> Result<(), E>,
    ) -> Result<(), E> {
        if self.len == self.room {
            self.make_room(self.room.saturating_mul(2).max(16));
        }
        let mut run = self.run_at(self.len, 1);
        let slot = run.next_slot().expect("a slot was made");
        write(slot)?;
        self.len += 1;
        Ok(())
    }

    /// The run of `count` slots from sample `start` (room made for them).
    fn run_at(&mut self, start: usize, count: usize) -> SampleSlots<'_> {
        let (shape, widths) = (self.shape, self.shape.widths());
        let run = |width: usize| start * width..(start + count) * width;
        SampleSlots {
            shape,
            len: 0,
            capacity: count,
            motor: &mut self.motor[run(widths.motor)],
            position: &mut self.position[run(widths.position)],
            orientation: &mut self.orientation[run(widths.orientation)],
            group: &mut self.group[run(widths.group)],
            distance: &mut self.distance[run(widths.distance)],
            sigma: &mut self.sigma[run(widths.sigma)],
            lines: &mut self.lines[run(1)],
            loads: &mut self.loads[run(widths.loads)],
        }
    }

    pub(super) fn into_parts(mut self) -> Parts {
        let shape = self.shape;
        let len = self.len;
        let field = |mut values: Vec<f64>, present: bool, width: usize| {
            present.then(|| {
                values.truncate(len * width);
                Field {
                    values: values.into(),
                    missing: None,
                }
            })
        };
        let group = shape.group.then(|| {
            self.group.truncate(len);
            Field {
                values: std::mem::take(&mut self.group).into(),
                missing: None,
            }
        });
        self.motor.truncate(len * shape.joints);
        self.lines.truncate(len);
        self.loads.truncate(len);
        Parts {
            len,
            motor: self.motor,
            joints: shape.joints,
            offsets: None,
            position: field(self.position, shape.position, 3),
            orientation: field(self.orientation, shape.orientation, 4),
            group,
            distance: field(self.distance, shape.distance, 1),
            sigma: field(self.sigma, shape.sigma, 2),
            lines: Some(Field {
                values: self.lines.into(),
                missing: None,
            }),
            loads: (shape.loads && len > 0).then(|| Arc::new(self.loads)),
        }
    }
}

/// The first `len` values of `column`, which keeps the rest.
fn cut<'a, T>(column: &mut &'a mut [T], len: usize) -> &'a mut [T] {
    let (run, rest) = std::mem::take(column).split_at_mut(len);
    *column = rest;
    run
}

/// `column` (its first `kept` values those of the settled samples) with
/// room for `room` values: zeroed memory, the settled values copied.
fn grow<T: Copy + Default>(column: &mut Vec<T>, kept: usize, room: usize) {
    if room <= column.len() {
        return;
    }
    if kept == 0 {
        // Fresh zeroed memory (untouched until written) instead of writing
        // zeros into what is held.
        *column = vec![T::default(); room];
        return;
    }
    let mut grown = vec![T::default(); room];
    grown[..kept].copy_from_slice(&column[..kept]);
    *column = grown;
}

impl SampleSlots<'_> {
    /// Slots committed.
    pub fn len(&self) -> usize {
        self.len
    }

    /// Whether none is committed.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// Forgets the slots committed: the part is to be filled again.
    pub fn clear(&mut self) {
        self.len = 0;
    }

    /// The next slot, to be written whole and then committed; `None` when
    /// every slot is committed.
    pub fn next_slot(&mut self) -> Option<SlotMut<'_>> {
        if self.len == self.capacity {
            return None;
        }
        let (shape, widths) = (self.shape, self.shape.widths());
        let index = self.len;
        let at = |width: usize| index * width..(index + 1) * width;
        Some(SlotMut {
            motor: &mut self.motor[at(widths.motor)],
            position: &mut self.position[at(widths.position)],
            orientation: &mut self.orientation[at(widths.orientation)],
            group: shape.group.then(|| &mut self.group[index]),
            distance: shape.distance.then(|| &mut self.distance[index]),
            sigma: &mut self.sigma[at(widths.sigma)],
            line: &mut self.lines[index],
            loads: shape.loads.then(|| &mut self.loads[index]),
        })
    }

    /// Commits the slot last handed out by [`next_slot`](Self::next_slot).
    pub fn commit(&mut self) {
        self.len = (self.len + 1).min(self.capacity);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sample::Sample;
    use crate::samples::Samples;
    use gecaro_core::LinkMass;
    use nalgebra::{UnitQuaternion, Vector3};

    /// Sample `i` of the tests' data: every field, a payload on some.
    fn row(i: usize, loads: bool) -> Sample {
        let mut row = Sample::new(vec![i as f64 * 0.1, -(i as f64), 0.5]);
        row.position = Some(Vector3::new(i as f64, 1.0, 2.0));
        row.orientation = Some(UnitQuaternion::from_euler_angles(0.01 * i as f64, 0.2, 0.0));
        row.group = Some(i as u64 / 3);
        row.line = Some(2 + 2 * i);
        if loads {
            row.set_payload(Some(LinkMass {
                mass: i as f64,
                com: Vector3::zeros(),
            }));
        }
        row
    }

    fn write(slot: SlotMut<'_>, row: &Sample) {
        slot.motor.copy_from_slice(&row.motor_positions);
        let p = row.position.expect("a position");
        slot.position.copy_from_slice(&[p.x, p.y, p.z]);
        let q = row.orientation.expect("an orientation");
        slot.orientation.copy_from_slice(&[q.w, q.i, q.j, q.k]);
        *slot.group.expect("a group") = row.group.expect("a group");
        *slot.line = row.line.expect("a line");
        if let Some(loads) = slot.loads {
            *loads = row.loads.clone();
        }
    }

    /// Rows written in parts whose runs some leave partly empty, settled
    /// over several rounds (the room grown in between), or pushed one by
    /// one, are the samples of those rows as a builder makes them.
    #[test]
    fn parts_filled_in_place_are_the_rows_in_order() {
        for loads in [false, true] {
            let shape = SampleShape {
                joints: 3,
                position: true,
                orientation: true,
                group: true,
                loads,
                ..SampleShape::default()
            };
            let rows: Vec<Sample> = (0..40).map(|i| row(i, loads)).collect();
            // Rounds of parts: (slots, filled) per part; a round's parts
            // after a part of `None` are dropped, as after an error.
            let rounds: [&[(usize, Option<usize>)]; 4] = [
                &[(5, Some(5)), (4, Some(2)), (6, Some(6))],
                &[(3, Some(0)), (7, Some(7))],
                &[(9, Some(4)), (3, None), (5, Some(5))],
                &[(30, Some(16))],
            ];
            for room in [0, 3, 100] {
                let mut filled = FilledSamples::new(shape);
                filled.make_room(room);
                let mut next = rows.iter();
                let mut expected = Vec::new();
                for round in rounds {
                    let counts: Vec<usize> = round.iter().map(|(slots, _)| *slots).collect();
                    let mut kept = Vec::new();
                    let mut runs = filled.slots(&counts);
                    for ((_, fill), run) in round.iter().zip(&mut runs) {
                        let Some(fill) = fill else {
                            // A part with an error: it wrote a slot, not committed.
                            if let Some(slot) = run.next_slot() {
                                write(slot, &rows[39]);
                            }
                            break;
                        };
                        for _ in 0..*fill {
                            let row = next.next().expect("rows enough");
                            write(run.next_slot().expect("room"), row);
                            run.commit();
                            expected.push(row.clone());
                        }
                        kept.push(run.len());
                    }
                    drop(runs);
                    filled.settle(&kept);
                    assert_eq!(filled.len(), expected.len());
                }
                assert_eq!(filled.line(3), expected[3].line);
                assert_eq!(
                    Samples::from(filled),
                    expected,
                    "room {room}, loads {loads}"
                );
            }
            // One by one, and cut short.
            let mut pushed = FilledSamples::new(shape);
            for row in &rows {
                pushed
                    .push_with(|slot| {
                        write(slot, row);
                        Ok::<(), ()>(())
                    })
                    .expect("written");
            }
            assert!(
                pushed
                    .push_with(|slot| {
                        write(slot, &rows[0]);
                        Err(())
                    })
                    .is_err()
            );
            pushed.truncate(25);
            assert_eq!(Samples::from(pushed), rows[..25].to_vec());
        }
    }
}
