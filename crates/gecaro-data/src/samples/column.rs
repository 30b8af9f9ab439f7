//! The columns [`Samples`](super::Samples) are made of: shared values, and
//! optional fields that some samples may lack.

use std::ops::Range;
use std::sync::Arc;

/// The values of one column: owned, or memory kept alive by its owner and
/// read in place ([`Column::shared`]).
#[derive(Clone)]
pub struct Column<T: 'static>(Arc<dyn AsRef<[T]> + Send + Sync>);

impl<T: 'static + Send + Sync> Column<T> {
    /// A column read in place from `owner` (whatever keeps the values alive
    /// and unchanged while the column lives: a numpy array's handle).
    pub fn shared(owner: impl AsRef<[T]> + Send + Sync + 'static) -> Self {
        Column(Arc::new(owner))
    }

    pub(super) fn values(&self) -> &[T] {
        (*self.0).as_ref()
    }
}

impl<T: 'static + Send + Sync> From<Vec<T>> for Column<T> {
    fn from(values: Vec<T>) -> Self {
        Column(Arc::new(values))
    }
}

/// An optional field of `width` values per sample: absent, or a column
/// with, when some samples lack it, which do.
#[derive(Clone)]
pub(super) struct Field<T: 'static> {
    pub(super) values: Column<T>,
    /// `missing[i]`: sample i has no value (its slots hold zeros).
    pub(super) missing: Option<Arc<[bool]>>,
}

impl<T: Copy + Default + Send + Sync + 'static> Field<T> {
    /// The field of `rows` (`W` values each, `None`: not there), or
    /// `None` when no row has it.
    pub(super) fn of<R, const W: usize>(
        rows: &[R],
        value: impl Fn(&R) -> Option<[T; W]>,
    ) -> Option<Self> {
        let mut field = FieldBuilder::with_capacity(rows.len());
        for row in rows {
            field.push(value(row));
        }
        field.finish()
    }

    pub(super) fn at(&self, index: usize, width: usize) -> Option<&[T]> {
        if self.missing.as_ref().is_some_and(|missing| missing[index]) {
            return None;
        }
        Some(&self.values.values()[index * width..(index + 1) * width])
    }

    /// The values of samples `range` (`width` each), when every one of
    /// them has the field.
    pub(super) fn all_within(&self, range: Range<usize>, width: usize) -> Option<&[T]> {
        if self
            .missing
            .as_ref()
            .is_some_and(|missing| missing[range.clone()].contains(&true))
        {
            return None;
        }
        Some(&self.values.values()[range.start * width..range.end * width])
    }

    /// The rows `indices` of this field.
    pub(super) fn gather(&self, indices: &[usize], width: usize) -> Option<Self> {
        let values = self.values.values();
        let kept: Vec<T> = indices
            .iter()
            .flat_map(|&index| &values[index * width..(index + 1) * width])
            .copied()
            .collect();
        let missing = self.missing.as_ref().map(|missing| {
            indices
                .iter()
                .map(|&index| missing[index])
                .collect::<Arc<[bool]>>()
        });
        if missing
            .as_ref()
            .is_some_and(|missing| missing.iter().all(|m| *m))
        {
            return None;
        }
        Some(Field {
            values: kept.into(),
            missing: missing.filter(|missing| missing.iter().any(|m| *m)),
        })
    }
}

/// An optional field of `W` values per sample, filled sample by sample
/// (see [`SamplesBuilder`](super::SamplesBuilder)): nothing is held until a
/// sample has it, and which samples lack it only once one does.
pub(super) struct FieldBuilder<T, const W: usize> {
    values: Vec<T>,
    /// Empty while no sample lacks the field; then one flag per sample.
    missing: Vec<bool>,
    /// Whether a sample has the field (`values` then has `W·len` values).
    any: bool,
    len: usize,
    /// Samples to make room for when the first value comes.
    capacity: usize,
}

impl<T: Copy + Default + Send + Sync + 'static, const W: usize> FieldBuilder<T, W> {
    pub(super) fn with_capacity(capacity: usize) -> Self {
        FieldBuilder {
            values: Vec::new(),
            missing: Vec::new(),
            any: false,
            len: 0,
            capacity,
        }
    }

    /// One more sample's value (`None`: it lacks the field).
    pub(super) fn push(&mut self, value: Option<[T; W]>) {
        match value {
            Some(value) => {
                self.hold_values();
                self.values.extend_from_slice(&value);
                if !self.missing.is_empty() {
                    self.missing.push(false);
                }
            }
            None => {
                self.flag_missing();
                self.missing.push(true);
                if self.any {
                    self.values.extend_from_slice(&[T::default(); W]);
                }
            }
        }
        self.len += 1;
    }

    /// The field, or `None` when no sample has it.
    pub(super) fn finish(self) -> Option<Field<T>> {
        let lacking = self.missing.iter().any(|m| *m);
        self.any.then(|| Field {
            values: self.values.into(),
            missing: lacking.then(|| self.missing.into()),
        })
    }

    /// Values held from here on: zeros for the samples before.
    fn hold_values(&mut self) {
        if !self.any {
            self.any = true;
            self.values
                .reserve(self.capacity.max(self.len + 1).saturating_mul(W));
            self.values.resize(self.len * W, T::default());
        }
    }

    /// Flags held from here on: none missing before.
    fn flag_missing(&mut self) {
        if self.missing.is_empty() {
            self.missing.resize(self.len, false);
        }
    }
}
