//! [`Samples`](super::Samples) made sample by sample, without holding them
//! as rows: what generators and edits make, whose samples may differ in
//! their fields and joint counts (a data file's reader, whose records all
//! have the same fields, writes them in place: [`super::FilledSamples`]).

use std::sync::Arc;

use super::column::{Field, FieldBuilder};
use crate::sample::{Sample, SampleLoads};

/// Samples made one at a time ([`push`](Self::push)), then
/// [`Samples::from`](super::Samples) it.
///
/// ```
/// use gecaro_data::sample::Sample;
/// use gecaro_data::samples::{Samples, SamplesBuilder};
///
/// let mut builder = SamplesBuilder::with_capacity(2);
/// builder.push(&Sample::new(vec![0.1, 0.2]));
/// builder.push(&Sample::new(vec![0.3, 0.4]));
/// let samples = Samples::from(builder);
/// assert_eq!(samples.get(1).motor_positions(), &[0.3, 0.4]);
/// ```
pub struct SamplesBuilder {
    len: usize,
    /// Samples to make room for when the first comes.
    capacity: usize,
    motor: Vec<f64>,
    /// The first sample's joint count.
    joints: Option<usize>,
    /// Where each sample's motor variables start, once two samples have
    /// different counts (`offsets[i]..offsets[i + 1]`).
    offsets: Option<Vec<usize>>,
    position: FieldBuilder<f64, 3>,
    orientation: FieldBuilder<f64, 4>,
    group: FieldBuilder<u64, 1>,
    distance: FieldBuilder<f64, 1>,
    sigma: FieldBuilder<f64, 2>,
    lines: FieldBuilder<usize, 1>,
    /// `None` while no sample has loads; then one entry per sample.
    loads: Option<Vec<Option<Box<SampleLoads>>>>,
}

/// What a builder made, for [`Samples`](super::Samples) to hold.
pub(super) struct Parts {
    pub(super) len: usize,
    pub(super) motor: Vec<f64>,
    pub(super) joints: usize,
    pub(super) offsets: Option<Arc<[usize]>>,
    pub(super) position: Option<Field<f64>>,
    pub(super) orientation: Option<Field<f64>>,
    pub(super) group: Option<Field<u64>>,
    pub(super) distance: Option<Field<f64>>,
    pub(super) sigma: Option<Field<f64>>,
    pub(super) lines: Option<Field<usize>>,
    pub(super) loads: Option<Arc<Vec<Option<Box<SampleLoads>>>>>,
}

impl SamplesBuilder {
    /// A builder with room for `capacity` samples of up to seven joints.
    pub fn with_capacity(capacity: usize) -> Self {
        SamplesBuilder {
            len: 0,
            capacity,
            motor: Vec::new(),
            joints: None,
            offsets: None,
            position: FieldBuilder::with_capacity(capacity),
            orientation: FieldBuilder::with_capacity(capacity),
            group: FieldBuilder::with_capacity(capacity),
            distance: FieldBuilder::with_capacity(capacity),
            sigma: FieldBuilder::with_capacity(capacity),
            lines: FieldBuilder::with_capacity(capacity),
            loads: None,
        }
    }

    /// How many samples so far.
    pub fn len(&self) -> usize {
        self.len
    }

    /// Whether there are none yet.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// One more sample, copied into the columns.
    pub fn push(&mut self, sample: &Sample) {
        let joints = sample.motor_positions.len();
        if self.joints.is_none() {
            self.motor
                .reserve(self.capacity.max(1).saturating_mul(joints));
        }
        if *self.joints.get_or_insert(joints) != joints {
            self.offset_each();
        }
        self.motor.extend_from_slice(&sample.motor_positions);
        if let Some(offsets) = self.offsets.as_mut() {
            offsets.push(self.motor.len());
        }
        self.position.push(sample.position.map(|p| [p.x, p.y, p.z]));
        self.orientation
            .push(sample.orientation.map(|q| [q.w, q.i, q.j, q.k]));
        self.group.push(sample.group.map(|g| [g]));
        self.distance.push(sample.distance.map(|d| [d]));
        self.sigma
            .push(sample.sigma.as_deref().map(|sigma| sigma.stored()));
        self.lines.push(sample.line.map(|l| [l]));
        if sample.loads.is_some() {
            self.hold_loads();
        }
        if let Some(loads) = self.loads.as_mut() {
            loads.push(sample.loads.clone());
        }
        self.len += 1;
    }

    /// Loads held from here on: none for the samples so far.
    fn hold_loads(&mut self) {
        let len = self.len;
        self.loads.get_or_insert_with(|| vec![None; len]);
    }

    /// Offsets held from here on: every sample so far had `joints` values.
    fn offset_each(&mut self) {
        if self.offsets.is_none() {
            let joints = self.joints.unwrap_or(0);
            self.offsets = Some((0..=self.len).map(|i| i * joints).collect());
        }
    }

    pub(super) fn into_parts(self) -> Parts {
        Parts {
            len: self.len,
            motor: self.motor,
            joints: self.joints.unwrap_or(0),
            offsets: self.offsets.map(Into::into),
            position: self.position.finish(),
            orientation: self.orientation.finish(),
            group: self.group.finish(),
            distance: self.distance.finish(),
            sigma: self.sigma.finish(),
            lines: self.lines.finish(),
            loads: self.loads.map(Arc::new),
        }
    }
}

impl<'a> Extend<&'a Sample> for SamplesBuilder {
    fn extend<I: IntoIterator<Item = &'a Sample>>(&mut self, samples: I) {
        samples.into_iter().for_each(|sample| self.push(sample));
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sample::RowSigma;
    use crate::samples::Samples;
    use gecaro_core::LinkMass;
    use nalgebra::{UnitQuaternion, Vector3};

    /// Rows whose fields come and go, with two counts of joints and loads
    /// on one.
    fn rows() -> Vec<Sample> {
        (0..9)
            .map(|i| {
                let joints = if i == 5 { 2 } else { 3 };
                let mut row = Sample::new(vec![i as f64 * 0.1; joints]);
                if i % 2 == 0 {
                    row.position = Some(Vector3::new(i as f64, 1.0, 2.0));
                }
                if i > 3 {
                    row.orientation =
                        Some(UnitQuaternion::from_euler_angles(0.1 * i as f64, 0.0, 0.2));
                }
                if i % 3 != 1 {
                    row.line = Some(10 + i);
                }
                row.group = Some(i as u64 / 2);
                if i % 4 == 1 {
                    row.sigma = Some(Box::new(RowSigma {
                        length: Some(1e-5 * i as f64),
                        angle: (i > 4).then_some(1e-4),
                    }));
                }
                if i == 7 {
                    row.set_payload(Some(LinkMass {
                        mass: 1.5,
                        com: Vector3::zeros(),
                    }));
                }
                row
            })
            .collect()
    }

    /// Rows whose fields come and go, pushed one by one, are the rows.
    #[test]
    fn rows_pushed_are_the_whole() {
        let rows = rows();
        let mut builder = SamplesBuilder::with_capacity(0);
        builder.extend(&rows);
        assert_eq!(builder.len(), rows.len());
        assert_eq!(Samples::from(builder), rows);
        for cut in 0..=rows.len() {
            assert_eq!(Samples::from(&rows[..cut]), rows[..cut].to_vec(), "{cut}");
        }
    }
}
