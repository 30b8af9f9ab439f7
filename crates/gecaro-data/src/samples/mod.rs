//! A data set as columns: what every calibration reads.
//!
//! [`Samples`] holds the configurations of a measurement set and what was
//! measured at each, one column per field (the motor variables qm1..qmn of
//! every configuration in one run of `m·n` values, the positions in one of
//! `3m`, …), in the units of [`Sample`]: metres, radians, unit quaternions
//! `(w, x, y, z)`. A column is shared, not copied: cloning a set's samples
//! clones pointers, and a column may be memory that someone else owns and
//! keeps alive (a numpy array, through [`Column::shared`]), read in place.
//!
//! Code reads samples through [`SampleSlice`] (a run of consecutive samples,
//! `Copy`) and [`SampleRef`] (one sample), whose accessors do not say how the
//! values are stored. A [`Sample`] is the row form, for building data one
//! configuration at a time ([`Samples::from`] a `Vec<Sample>`) and for
//! changing them ([`Samples::to_rows`]).
//!
//! ```
//! use gecaro_data::sample::Sample;
//! use gecaro_data::samples::Samples;
//! use nalgebra::Vector3;
//!
//! let mut row = Sample::new(vec![0.1, 0.2]);
//! row.position = Some(Vector3::new(1.0, 2.0, 3.0));
//! let samples = Samples::from(vec![row.clone(), Sample::new(vec![0.3, 0.4])]);
//! assert_eq!(samples.len(), 2);
//! assert_eq!(samples.get(0).motor_positions(), &[0.1, 0.2]);
//! assert_eq!(samples.get(0).position(), Some(Vector3::new(1.0, 2.0, 3.0)));
//! assert_eq!(samples.get(1).position(), None);
//! assert_eq!(samples.get(0).to_sample(), row);
//! ```

use std::fmt;
use std::ops::Range;
use std::sync::{Arc, LazyLock};

use gecaro_core::{LinkMass, Robot};
use nalgebra::{Quaternion, UnitQuaternion, Vector3};

use crate::sample::{DataColumn, RowSigma, Sample, SampleLoads};

mod builder;
mod column;
mod filled;

pub use builder::SamplesBuilder;
pub use column::Column;
use column::Field;
pub use filled::{FilledSamples, SampleShape, SampleSlots, SlotMut};

/// The line numbers of the samples in their data file.
#[derive(Clone)]
enum Lines {
    /// Sample i was row `first + i` (arrays: their row index).
    Counted(usize),
    /// Each sample's line, when known.
    Listed(Option<Field<usize>>),
}

/// The configurations of a data set and what was measured at each, as
/// columns; see the module docs.
#[derive(Clone)]
pub struct Samples {
    len: usize,
    /// The motor variables: `joints` per sample, or where `offsets` says
    /// when samples have different counts (`offsets[i]..offsets[i + 1]`).
    motor: Column<f64>,
    joints: usize,
    offsets: Option<Arc<[usize]>>,
    position: Option<Field<f64>>,
    orientation: Option<Field<f64>>,
    group: Option<Field<u64>>,
    distance: Option<Field<f64>>,
    /// Each sample's stated σ of lengths (m) and of angles (rad), 0 where
    /// not stated ([`RowSigma`]).
    sigma: Option<Field<f64>>,
    lines: Lines,
    loads: Option<Arc<Vec<Option<Box<SampleLoads>>>>>,
}

/// Columns read in place, to make [`Samples`] of ([`Samples::from_columns`]).
pub struct SampleColumns {
    /// Motor variables, `joints` per configuration (row-major).
    pub motor_positions: Column<f64>,
    /// Joints per configuration.
    pub joints: usize,
    /// Positions, 3 per configuration (m).
    pub position: Option<Column<f64>>,
    /// Unit quaternions `(w, x, y, z)`, 4 per configuration.
    pub orientation: Option<Column<f64>>,
    /// Set or pair ids, one per configuration.
    pub group: Option<Column<u64>>,
    /// Distances (m), one per configuration.
    pub distance: Option<Column<f64>>,
    /// Each configuration's stated σ of lengths (m) and of angles (rad),
    /// 2 per configuration, 0 where not stated ([`RowSigma`]).
    pub sigma: Option<Column<f64>>,
    /// Sample i's line, for messages: `first_line + i`.
    pub first_line: usize,
}

impl Samples {
    /// Samples of columns read in place (see [`SampleColumns`]).
    ///
    /// # Errors
    /// A sentence naming the column whose length is not a whole number of
    /// rows of the configurations' count.
    pub fn from_columns(columns: SampleColumns) -> Result<Samples, String> {
        let SampleColumns {
            motor_positions,
            joints,
            position,
            orientation,
            group,
            distance,
            sigma,
            first_line,
        } = columns;
        if joints == 0 || motor_positions.values().len() % joints != 0 {
            return Err(format!(
                "qm: {} values are not rows of {joints} joints",
                motor_positions.values().len()
            ));
        }
        let len = motor_positions.values().len() / joints;
        let field = |column: Option<Column<f64>>, width: usize, name: &str| {
            column
                .map(|values| {
                    let found = values.values().len();
                    if found == len * width {
                        Ok(Field {
                            values,
                            missing: None,
                        })
                    } else {
                        Err(format!(
                            "{name}: expected {width} values for each of {len} configurations, \
                             got {found}"
                        ))
                    }
                })
                .transpose()
        };
        let group = match group {
            Some(values) if values.values().len() != len => {
                return Err(format!(
                    "set/pair: expected {len} ids, got {}",
                    values.values().len()
                ));
            }
            values => values.map(|values| Field {
                values,
                missing: None,
            }),
        };
        Ok(Samples {
            len,
            motor: motor_positions,
            joints,
            offsets: None,
            position: field(position, 3, "position")?,
            orientation: field(orientation, 4, "orientation")?,
            group,
            distance: field(distance, 1, "distance")?,
            sigma: field(sigma, 2, "sigma")?,
            lines: Lines::Counted(first_line),
            loads: None,
        })
    }

    /// No samples.
    pub fn empty() -> Samples {
        Samples::from(Vec::new())
    }

    /// How many samples.
    pub fn len(&self) -> usize {
        self.len
    }

    /// Whether there are none.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// Sample `index` (panics beyond [`len`](Self::len), as slices do).
    pub fn get(&self, index: usize) -> SampleRef<'_> {
        self.as_slice().get(index)
    }

    /// The bytes its columns hold (shared or not), loads aside: what a
    /// job's memory estimate counts for its data.
    pub fn bytes(&self) -> usize {
        fn field<T: Send + Sync>(field: &Option<Field<T>>) -> usize {
            field.as_ref().map_or(0, |field| {
                std::mem::size_of_val(field.values.values())
                    + field.missing.as_ref().map_or(0, |missing| missing.len())
            })
        }
        let lines = match &self.lines {
            Lines::Counted(_) => 0,
            Lines::Listed(lines) => field(lines),
        };
        std::mem::size_of_val(self.motor.values())
            + self
                .offsets
                .as_ref()
                .map_or(0, |o| std::mem::size_of_val(&o[..]))
            + field(&self.position)
            + field(&self.orientation)
            + field(&self.group)
            + field(&self.distance)
            + field(&self.sigma)
            + lines
            + self.loads.as_ref().map_or(0, |loads| loads.len() * 8)
    }

    /// Whether some sample states its σ ([`Sample::sigma`]).
    pub fn has_row_sigma(&self) -> bool {
        self.sigma.is_some() && self.iter().any(|sample| sample.sigma().is_some())
    }

    /// All of them, as a slice.
    pub fn as_slice(&self) -> SampleSlice<'_> {
        SampleSlice {
            samples: self,
            start: 0,
            end: self.len,
        }
    }

    /// The samples `range`, as a slice.
    pub fn slice(&self, range: Range<usize>) -> SampleSlice<'_> {
        self.as_slice().slice(range)
    }

    /// The samples in order.
    pub fn iter(
        &self,
    ) -> impl DoubleEndedIterator<Item = SampleRef<'_>> + ExactSizeIterator + Clone {
        self.as_slice().iter()
    }

    /// The samples as rows (a copy), to change them.
    pub fn to_rows(&self) -> Vec<Sample> {
        self.as_slice().to_rows()
    }

    /// The samples at `indices`, in that order (a copy of those rows).
    pub fn gather(&self, indices: &[usize]) -> Samples {
        let motor = self.motor.values();
        let mut kept = Vec::with_capacity(indices.len() * self.joints);
        let mut offsets = self.offsets.as_ref().map(|_| vec![0]);
        for &index in indices {
            let range = self.motor_range(index);
            kept.extend_from_slice(&motor[range]);
            if let Some(offsets) = offsets.as_mut() {
                offsets.push(kept.len());
            }
        }
        Samples {
            len: indices.len(),
            motor: kept.into(),
            joints: self.joints,
            offsets: offsets.map(Into::into),
            position: self.position.as_ref().and_then(|f| f.gather(indices, 3)),
            orientation: self.orientation.as_ref().and_then(|f| f.gather(indices, 4)),
            group: self.group.as_ref().and_then(|f| f.gather(indices, 1)),
            distance: self.distance.as_ref().and_then(|f| f.gather(indices, 1)),
            sigma: self.sigma.as_ref().and_then(|f| f.gather(indices, 2)),
            lines: Lines::Listed(Field::of(indices, |&index| {
                self.get(index).line().map(|line| [line])
            })),
            loads: self
                .loads
                .as_ref()
                .map(|loads| Arc::new(indices.iter().map(|&index| loads[index].clone()).collect())),
        }
    }

    /// Every sample's loads, to change ([`Sample::loads`]; a copy of them
    /// when they are shared).
    pub fn loads_mut(&mut self) -> &mut [Option<Box<SampleLoads>>] {
        let len = self.len;
        Arc::make_mut(self.loads.get_or_insert_with(|| Arc::new(vec![None; len]))).as_mut_slice()
    }

    fn motor_range(&self, index: usize) -> Range<usize> {
        match &self.offsets {
            None => index * self.joints..(index + 1) * self.joints,
            Some(offsets) => offsets[index]..offsets[index + 1],
        }
    }
}

impl From<Vec<Sample>> for Samples {
    fn from(rows: Vec<Sample>) -> Self {
        Samples::from(rows.as_slice())
    }
}

impl From<&[Sample]> for Samples {
    fn from(rows: &[Sample]) -> Self {
        let mut builder = SamplesBuilder::with_capacity(rows.len());
        builder.extend(rows);
        Samples::from(builder)
    }
}

impl From<SamplesBuilder> for Samples {
    fn from(builder: SamplesBuilder) -> Self {
        Samples::from_parts(builder.into_parts())
    }
}

impl From<FilledSamples> for Samples {
    fn from(filled: FilledSamples) -> Self {
        Samples::from_parts(filled.into_parts())
    }
}

impl Samples {
    /// The samples a builder made.
    fn from_parts(parts: builder::Parts) -> Self {
        Samples {
            len: parts.len,
            motor: parts.motor.into(),
            joints: parts.joints,
            offsets: parts.offsets,
            position: parts.position,
            orientation: parts.orientation,
            group: parts.group,
            distance: parts.distance,
            sigma: parts.sigma,
            lines: Lines::Listed(parts.lines),
            loads: parts.loads,
        }
    }
}

impl FromIterator<Sample> for Samples {
    fn from_iter<I: IntoIterator<Item = Sample>>(iter: I) -> Self {
        let iter = iter.into_iter();
        let mut builder = SamplesBuilder::with_capacity(iter.size_hint().0);
        iter.for_each(|sample| builder.push(&sample));
        Samples::from(builder)
    }
}

impl Default for Samples {
    fn default() -> Self {
        Samples::empty()
    }
}

impl PartialEq for Samples {
    fn eq(&self, other: &Self) -> bool {
        self.len == other.len && self.iter().zip(other.iter()).all(|(a, b)| a == b)
    }
}

impl PartialEq<Vec<Sample>> for Samples {
    fn eq(&self, rows: &Vec<Sample>) -> bool {
        self.len == rows.len() && self.iter().zip(rows).all(|(a, b)| a == *b)
    }
}

impl PartialEq<Samples> for Vec<Sample> {
    fn eq(&self, samples: &Samples) -> bool {
        samples == self
    }
}

impl fmt::Debug for Samples {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_list().entries(self.iter()).finish()
    }
}

impl<'a> IntoIterator for &'a Samples {
    type Item = SampleRef<'a>;
    type IntoIter = SampleIter<'a>;

    fn into_iter(self) -> SampleIter<'a> {
        self.as_slice().iter()
    }
}

/// A run of consecutive samples (of one [`Samples`]); see the module docs.
#[derive(Clone, Copy)]
pub struct SampleSlice<'a> {
    samples: &'a Samples,
    start: usize,
    end: usize,
}

impl<'a> SampleSlice<'a> {
    /// No samples.
    pub fn empty() -> SampleSlice<'static> {
        static EMPTY: LazyLock<Samples> = LazyLock::new(Samples::empty);
        EMPTY.as_slice()
    }

    /// How many samples.
    pub fn len(self) -> usize {
        self.end - self.start
    }

    /// Whether there are none.
    pub fn is_empty(self) -> bool {
        self.start == self.end
    }

    /// Sample `index` of this slice (panics beyond its length, as slices do).
    pub fn get(self, index: usize) -> SampleRef<'a> {
        assert!(
            index < self.len(),
            "sample {index} of a slice of {}",
            self.len()
        );
        SampleRef {
            samples: self.samples,
            index: self.start + index,
        }
    }

    /// The samples `range` of this slice.
    pub fn slice(self, range: Range<usize>) -> SampleSlice<'a> {
        assert!(
            range.start <= range.end && range.end <= self.len(),
            "samples {range:?} of a slice of {}",
            self.len()
        );
        SampleSlice {
            samples: self.samples,
            start: self.start + range.start,
            end: self.start + range.end,
        }
    }

    /// Whether every sample of this slice passes `robot`'s
    /// [`check_configuration`](Robot::check_configuration) and
    /// [`SampleRef::check_column`] for each of `columns`, read column by
    /// column: the quick route of a study's check (a million samples in
    /// milliseconds), which the sample-by-sample route follows only when it
    /// fails, to name the first fault. False whenever some sample would
    /// fail (and for samples of different joint counts).
    pub fn plainly_sound(self, robot: &Robot, columns: &[DataColumn]) -> bool {
        let (samples, range) = (self.samples, self.start..self.end);
        let joints = samples.joints;
        samples.offsets.is_none()
            && joints == robot.joint_count()
            && robot.configurations_sound(
                &samples.motor.values()[range.start * joints..range.end * joints],
            )
            && columns.iter().all(|&column| {
                let (field, width) = match column {
                    DataColumn::Position => (&samples.position, 3),
                    DataColumn::Orientation => (&samples.orientation, 4),
                    DataColumn::Distance => (&samples.distance, 1),
                    DataColumn::Set | DataColumn::Pair => {
                        return samples
                            .group
                            .as_ref()
                            .is_some_and(|group| group.all_within(range.clone(), 1).is_some());
                    }
                };
                // Every value read (no early exit: the loop is vectorised).
                field
                    .as_ref()
                    .and_then(|field| field.all_within(range.clone(), width))
                    .is_some_and(|values| {
                        values
                            .iter()
                            .fold(true, |all, value| all & column.admits(*value))
                    })
            })
    }

    /// The motor values of this slice's samples, n a sample one after
    /// another, as stored; `None` when the samples do not all have n.
    pub fn motor_values(self) -> Option<&'a [f64]> {
        let joints = self.samples.joints;
        (self.samples.offsets.is_none() && joints > 0)
            .then(|| &self.samples.motor.values()[self.start * joints..self.end * joints])
    }

    /// Whether every sample of this slice has a measured position (finite
    /// or not), found without reading the samples.
    pub fn all_positioned(self) -> bool {
        let range = self.start..self.end;
        self.is_empty()
            || self
                .samples
                .position
                .as_ref()
                .is_some_and(|field| field.all_within(range, 3).is_some())
    }

    /// The samples in order.
    pub fn iter(self) -> SampleIter<'a> {
        SampleIter {
            samples: self.samples,
            range: self.start..self.end,
        }
    }

    /// Consecutive runs of `size` samples (the last shorter).
    pub fn chunks(self, size: usize) -> impl Iterator<Item = SampleSlice<'a>> + Clone {
        assert!(size > 0, "chunks of 0 samples");
        (self.start..self.end)
            .step_by(size)
            .map(move |start| SampleSlice {
                samples: self.samples,
                start,
                end: (start + size).min(self.end),
            })
    }

    /// The samples at `indices` of this slice, in that order (a copy of
    /// those rows of every column: [`Samples::gather`]).
    pub fn gather(self, indices: &[usize]) -> Samples {
        let within: Vec<usize> = indices
            .iter()
            .map(|&index| {
                assert!(
                    index < self.len(),
                    "sample {index} of a slice of {}",
                    self.len()
                );
                self.start + index
            })
            .collect();
        self.samples.gather(&within)
    }

    /// These samples on their own (a copy of their rows of every column).
    pub fn to_samples(self) -> Samples {
        self.samples
            .gather(&(self.start..self.end).collect::<Vec<_>>())
    }

    /// These samples as rows (a copy).
    pub fn to_rows(self) -> Vec<Sample> {
        self.iter().map(|sample| sample.to_sample()).collect()
    }
}

impl fmt::Debug for SampleSlice<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_list().entries(self.iter()).finish()
    }
}

impl<'a> IntoIterator for SampleSlice<'a> {
    type Item = SampleRef<'a>;
    type IntoIter = SampleIter<'a>;

    fn into_iter(self) -> SampleIter<'a> {
        self.iter()
    }
}

impl<'a> From<&'a Samples> for SampleSlice<'a> {
    fn from(samples: &'a Samples) -> Self {
        samples.as_slice()
    }
}

/// The samples of a [`SampleSlice`], in order.
#[derive(Clone)]
pub struct SampleIter<'a> {
    samples: &'a Samples,
    range: Range<usize>,
}

impl<'a> Iterator for SampleIter<'a> {
    type Item = SampleRef<'a>;

    fn next(&mut self) -> Option<SampleRef<'a>> {
        let index = self.range.next()?;
        Some(SampleRef {
            samples: self.samples,
            index,
        })
    }

    fn size_hint(&self) -> (usize, Option<usize>) {
        self.range.size_hint()
    }
}

impl DoubleEndedIterator for SampleIter<'_> {
    fn next_back(&mut self) -> Option<Self::Item> {
        let index = self.range.next_back()?;
        Some(SampleRef {
            samples: self.samples,
            index,
        })
    }
}

impl ExactSizeIterator for SampleIter<'_> {}

/// One sample of a [`Samples`]: the fields of [`Sample`], read where they
/// are stored.
#[derive(Clone, Copy)]
pub struct SampleRef<'a> {
    samples: &'a Samples,
    index: usize,
}

impl<'a> SampleRef<'a> {
    /// Motor variables qm (eq. 4): radians or metres.
    pub fn motor_positions(self) -> &'a [f64] {
        &self.samples.motor.values()[self.samples.motor_range(self.index)]
    }

    /// Measured position of the origin of frame n+1 in the world frame (m).
    pub fn position(self) -> Option<Vector3<f64>> {
        let xyz = self.samples.position.as_ref()?.at(self.index, 3)?;
        Some(Vector3::new(xyz[0], xyz[1], xyz[2]))
    }

    /// Measured orientation of frame n+1 in the world frame.
    pub fn orientation(self) -> Option<UnitQuaternion<f64>> {
        let q = self.samples.orientation.as_ref()?.at(self.index, 4)?;
        Some(UnitQuaternion::new_unchecked(Quaternion::new(
            q[0], q[1], q[2], q[3],
        )))
    }

    /// Set id (link methods) or pair id (distance method).
    pub fn group(self) -> Option<u64> {
        Some(self.samples.group.as_ref()?.at(self.index, 1)?[0])
    }

    /// Measured distance to the other configuration of the pair (m).
    pub fn distance(self) -> Option<f64> {
        Some(self.samples.distance.as_ref()?.at(self.index, 1)?[0])
    }

    /// The standard deviations the data state for this sample's
    /// measurement ([`Sample::sigma`]); `None`: the set's σ.
    pub fn sigma(self) -> Option<RowSigma> {
        let stored = self.samples.sigma.as_ref()?.at(self.index, 2)?;
        RowSigma::of_stored([stored[0], stored[1]])
    }

    /// Line of the data file this sample came from, for messages.
    pub fn line(self) -> Option<usize> {
        match &self.samples.lines {
            Lines::Counted(first) => Some(first + self.index),
            Lines::Listed(field) => Some(field.as_ref()?.at(self.index, 1)?[0]),
        }
    }

    /// The payload and the joint loads at this configuration, when the data
    /// state them ([`Sample::loads`]).
    pub fn loads(self) -> Option<&'a SampleLoads> {
        self.samples.loads.as_ref()?[self.index].as_deref()
    }

    /// The payload carried at this configuration, if the data state one.
    pub fn payload(self) -> Option<&'a LinkMass> {
        self.loads()?.payload.as_ref()
    }

    /// The gravity torque of every joint ([`SampleLoads::torques`]).
    pub fn torques(self) -> Option<&'a [f64]> {
        self.loads()?.torques.as_deref()
    }

    /// The torques' derivatives with respect to gravity's two tilts
    /// ([`SampleLoads::tilt_torques`]).
    pub fn tilt_torques(self) -> Option<&'a [f64]> {
        self.loads()?.tilt_torques.as_deref()
    }

    /// This sample as a row (a copy).
    pub fn to_sample(self) -> Sample {
        let mut sample = Sample::new(self.motor_positions());
        sample.position = self.position();
        sample.orientation = self.orientation();
        sample.group = self.group();
        sample.distance = self.distance();
        sample.line = self.line();
        sample.loads = self.loads().map(|loads| Box::new(loads.clone()));
        sample.sigma = self.sigma().map(Box::new);
        sample
    }

    /// Checks that this sample has the field of `column`, finite
    /// ([`Sample::check_column`]).
    ///
    /// # Errors
    /// What is missing or not finite, as a sentence.
    pub fn check_column(self, column: DataColumn) -> Result<(), String> {
        crate::sample::check_fields(
            column,
            self.position(),
            self.orientation(),
            self.group(),
            self.distance(),
        )
    }
}

impl PartialEq for SampleRef<'_> {
    fn eq(&self, other: &Self) -> bool {
        self.motor_positions() == other.motor_positions()
            && self.position() == other.position()
            && self.orientation() == other.orientation()
            && self.group() == other.group()
            && self.distance() == other.distance()
            && self.line() == other.line()
            && self.loads() == other.loads()
            && self.sigma() == other.sigma()
    }
}

impl PartialEq<Sample> for SampleRef<'_> {
    fn eq(&self, other: &Sample) -> bool {
        self.to_sample() == *other
    }
}

impl fmt::Debug for SampleRef<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        self.to_sample().fmt(f)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The quick check agrees with the sample-by-sample one: sound columns
    /// pass, and each kind of fault, in any one sample, fails it.
    #[test]
    fn the_quick_check_agrees_with_each_sample_checked() {
        let robot = Robot::template("three", "RRR").expect("template");
        let columns = [
            DataColumn::Position,
            DataColumn::Orientation,
            DataColumn::Set,
            DataColumn::Distance,
        ];
        let sound = |index: usize| {
            let mut row = Sample::new(vec![0.1 * index as f64, -0.2, 0.3]);
            row.position = Some(Vector3::new(1.0, -2.0, 999.0));
            row.orientation = Some(UnitQuaternion::from_euler_angles(0.1, 0.2, 0.3));
            row.group = Some(index as u64);
            row.distance = Some(0.25);
            row
        };
        type Spoil = fn(&mut Sample);
        let faults: [(&str, Spoil); 10] = [
            ("none", |_| {}),
            ("motor NaN", |row| row.motor_positions[1] = f64::NAN),
            ("motor ∞", |row| row.motor_positions[2] = f64::INFINITY),
            ("a joint short", |row| {
                row.motor_positions.pop();
            }),
            ("position beyond the cell", |row| {
                row.position = Some(Vector3::new(0.0, 1001.0, 0.0));
            }),
            ("position missing", |row| row.position = None),
            ("orientation NaN", |row| {
                row.orientation = Some(UnitQuaternion::new_unchecked(Quaternion::new(
                    f64::NAN,
                    0.0,
                    0.0,
                    0.0,
                )));
            }),
            ("group missing", |row| row.group = None),
            ("distance ∞", |row| row.distance = Some(f64::NEG_INFINITY)),
            ("distance missing", |row| row.distance = None),
        ];
        for (fault, spoil) in faults {
            for at in [0, 5, 9] {
                let mut rows: Vec<Sample> = (0..10).map(sound).collect();
                spoil(&mut rows[at]);
                let samples = Samples::from(rows.as_slice());
                let each_sound = samples.as_slice().iter().all(|sample| {
                    robot.check_configuration(sample.motor_positions()).is_ok()
                        && columns
                            .iter()
                            .all(|column| sample.check_column(*column).is_ok())
                });
                assert_eq!(each_sound, fault == "none", "{fault} at {at}");
                let slice = samples.as_slice();
                assert_eq!(
                    slice.plainly_sound(&robot, &columns),
                    each_sound,
                    "{fault} at {at}"
                );
                // Slices without the spoilt sample are sound (samples of
                // different joint counts always take the slow route).
                if fault != "a joint short" {
                    assert!(
                        slice.slice(0..at).plainly_sound(&robot, &columns),
                        "{fault}"
                    );
                    assert!(
                        slice.slice(at + 1..10).plainly_sound(&robot, &columns),
                        "{fault}"
                    );
                }
            }
        }
        // Another joint count, or columns a sample does not have.
        let samples = Samples::from((0..4).map(sound).collect::<Vec<_>>().as_slice());
        let four = Robot::template("four", "RRRR").expect("template");
        assert!(!samples.as_slice().plainly_sound(&four, &columns));
        let bare = Samples::from(vec![Sample::new(vec![0.1, 0.2, 0.3])].as_slice());
        assert!(bare.as_slice().plainly_sound(&robot, &[]));
        for column in columns {
            assert!(
                !bare.as_slice().plainly_sound(&robot, &[column]),
                "{column:?}"
            );
        }
    }

    fn rows() -> Vec<Sample> {
        let mut first = Sample::new(vec![0.1, 0.2, 0.3]);
        first.position = Some(Vector3::new(1.0, 2.0, 3.0));
        first.line = Some(2);
        first.group = Some(7);
        let mut second = Sample::new(vec![0.4, 0.5]);
        second.orientation = Some(UnitQuaternion::from_euler_angles(0.1, 0.2, 0.3));
        second.distance = Some(0.25);
        second.set_payload(Some(LinkMass {
            mass: 2.0,
            com: Vector3::new(0.0, 0.0, 0.1),
        }));
        let third = Sample::new(vec![0.6, 0.7, 0.8]);
        vec![first, second, third]
    }

    /// Rows with different fields, counts of joints and loads come back
    /// as they went in, and so does any selection of them.
    #[test]
    fn rows_survive_the_columns_whatever_each_holds() {
        let rows = rows();
        let samples = Samples::from(rows.clone());
        assert_eq!(samples.to_rows(), rows);
        assert_eq!(samples.get(1).motor_positions(), &[0.4, 0.5]);
        assert_eq!(samples.get(2).position(), None);
        assert_eq!(samples.get(0).line(), Some(2));
        assert_eq!(samples.get(1).line(), None);
        let picked = samples.gather(&[2, 0]);
        assert_eq!(picked.to_rows(), vec![rows[2].clone(), rows[0].clone()]);
        let middle = samples.as_slice().slice(1..3);
        assert_eq!(middle.to_rows(), rows[1..].to_vec());
        // A slice's indices are its own.
        assert_eq!(
            middle.gather(&[1, 0]).to_rows(),
            vec![rows[2].clone(), rows[1].clone()]
        );
        let chunks: Vec<usize> = samples.as_slice().chunks(2).map(SampleSlice::len).collect();
        assert_eq!(chunks, vec![2, 1]);
    }

    /// Columns read in place number their rows and refuse lengths that do
    /// not make whole rows.
    #[test]
    fn columns_read_in_place_are_checked_and_counted() {
        let columns = |position: Vec<f64>| SampleColumns {
            motor_positions: Column::shared(vec![0.0, 1.0, 2.0, 3.0]),
            joints: 2,
            position: Some(Column::shared(position)),
            orientation: None,
            group: None,
            distance: None,
            sigma: None,
            first_line: 0,
        };
        let samples =
            Samples::from_columns(columns(vec![1.0, 2.0, 3.0, 4.0, 5.0, 6.0])).expect("two rows");
        assert_eq!(samples.len(), 2);
        assert_eq!(samples.get(1).motor_positions(), &[2.0, 3.0]);
        assert_eq!(samples.get(1).position(), Some(Vector3::new(4.0, 5.0, 6.0)));
        assert_eq!(samples.get(1).line(), Some(1));
        // 4 motor values and 6 coordinates, the lines counted, not held.
        assert_eq!(samples.bytes(), 10 * 8);
        let error = Samples::from_columns(columns(vec![1.0; 5])).expect_err("5 values");
        assert!(error.contains("position"), "{error}");
    }
}
