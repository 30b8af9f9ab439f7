//! The base columns a plan is judged on, and the rows each unit of a pool
//! contributes to them.

use std::ops::Range;

use gecaro_core::{ChainBuffer, JacobianRows, KinematicModel, PriorityMatrix, Robot};
use nalgebra::DMatrix;

use crate::Error;
use crate::frames::measuring_robot;
use crate::identifiability::{RankReport, structural_parameters};
use crate::method::CalibrationMethod;
use crate::observability::{AUXILIARY_UNIT, column_unit};
use crate::observation::ObservationSystem;
use crate::progress::Quiet;
use crate::rows::ColumnLayout;
use crate::sample::{DataColumn, Sample};
use crate::sampler::Sampler;
use crate::samples::{SampleSlice, Samples};
use crate::study::{Study, StudyStates};

/// `samples` reordered unit by unit, and each unit's range in the result:
/// the rows of W then come unit by unit too.
pub(super) fn contiguous(
    samples: SampleSlice<'_>,
    units: &[Vec<usize>],
) -> (Samples, Vec<Range<usize>>) {
    let mut ordered = Vec::with_capacity(samples.len());
    let ranges = units
        .iter()
        .map(|unit| {
            let start = ordered.len();
            ordered.extend_from_slice(unit);
            start..ordered.len()
        })
        .collect();
    (samples.gather(&ordered), ranges)
}

/// `samples` with what the sensor would read on the nominal robot, exactly,
/// for the methods that read something at a configuration (position, frame,
/// distance): W at the nominal robot does not depend on the readings, but a
/// study needs them, and planned configurations have none. Link and plane
/// data have no readings and stay as they are.
fn nominal_readings(
    robot: &Robot,
    method: &dyn CalibrationMethod,
    samples: SampleSlice<'_>,
) -> Result<Vec<Sample>, Error> {
    let reads = method.data_columns().iter().any(|column| {
        matches!(
            column,
            DataColumn::Position | DataColumn::Orientation | DataColumn::Distance
        )
    });
    if reads && !samples.is_empty() {
        method
            .sensor()
            // Forward models only: quick.
            .measure_at(robot, samples, 0.0, &mut Sampler::new(0), &mut Quiet)
    } else {
        Ok(samples.to_rows())
    }
}

/// `study` with what every set's sensor would read on the nominal robot
/// (through the set's tool and station, [`crate::frames::measuring_robot`]):
/// as [`nominal_readings`], for every set.
pub(crate) fn nominal_study(robot: &Robot, study: &Study) -> Result<Study, Error> {
    let mut nominal = study.clone();
    for set in &mut nominal.sets {
        let frame = |index: Option<usize>| index.map(|i| &study.frames[i]);
        let measuring = measuring_robot(robot, frame(set.tool), frame(set.station))?;
        set.samples =
            nominal_readings(&measuring, set.method.as_ref(), set.samples.as_slice())?.into();
    }
    Ok(nominal)
}

/// The scaled rows of W_b of every unit, one matrix X_u per unit.
pub(super) struct Blocks {
    pub(super) units: Vec<DMatrix<f64>>,
    pub(super) width: usize,
}

impl Blocks {
    pub(super) fn of(&self, unit: usize) -> &DMatrix<f64> {
        &self.units[unit]
    }

    /// The ridge that keeps M invertible while a design is short: 1e-9 of
    /// the mean diagonal of a unit's information.
    pub(super) fn ridge(&self) -> f64 {
        let diagonal: f64 = self.units.iter().map(|block| block.norm_squared()).sum();
        (1e-9 * diagonal / (self.units.len().max(1) * self.width.max(1)) as f64)
            .max(f64::MIN_POSITIVE)
    }

    /// Σ X_uᵀX_u over `chosen`, added to `base`.
    pub(super) fn information(
        &self,
        base: &DMatrix<f64>,
        chosen: impl Iterator<Item = usize>,
    ) -> DMatrix<f64> {
        let mut information = base.clone();
        for unit in chosen {
            let block = self.of(unit);
            information += block.transpose() * block;
        }
        information
    }
}

/// The base columns of a set of configurations: the structural base set
/// (Appendix III, on random data like them), its layout, and each column's
/// name and error unit (auxiliary unknowns first).
pub(crate) struct BaseColumns {
    pub(crate) layout: ColumnLayout,
    /// Vocabulary indices of the base robot parameters, in column order.
    pub(crate) parameters: Vec<usize>,
    /// Number of base auxiliary unknowns (the first columns).
    pub(crate) auxiliary: usize,
    pub(crate) names: Vec<String>,
    /// Each column's error unit (see [`Observability`](crate::observability::Observability)).
    pub(crate) scale: Vec<f64>,
}

impl BaseColumns {
    pub(crate) fn of(
        robot: &Robot,
        method: &dyn CalibrationMethod,
        samples: SampleSlice<'_>,
        priority: &PriorityMatrix,
    ) -> Result<Self, Error> {
        let samples = nominal_readings(robot, method, samples)?;
        let study = Study::single(method.clone_method(), samples, "candidates");
        Self::of_study(robot, &study, priority)
    }

    /// The base columns of a study whose readings are the nominal robot's
    /// ([`nominal_study`]).
    pub(crate) fn of_study(
        robot: &Robot,
        study: &Study,
        priority: &PriorityMatrix,
    ) -> Result<Self, Error> {
        let report = structural_parameters(robot, study, priority, 1)?;
        Ok(Self::of_report(robot, study, report))
    }

    /// The base columns of `report`'s base set (Appendix III on `study`,
    /// or on random data like it).
    pub(crate) fn of_report(robot: &Robot, study: &Study, report: RankReport) -> Self {
        let layout = ColumnLayout::with_auxiliary(
            robot.parameters().len(),
            &report.base_parameters,
            study.auxiliary_names().len(),
            &report.base_auxiliary,
        );
        let scale = report
            .base_auxiliary
            .iter()
            .map(|_| AUXILIARY_UNIT)
            .chain(report.base_parameters.iter().map(|index| {
                let id = robot.parameters().id(*index);
                column_unit(id.kind, robot.parameter(id))
            }))
            .collect();
        let names = report
            .base_auxiliary
            .iter()
            .map(|index| report.auxiliary[*index].name.clone())
            .chain(
                report
                    .base_parameters
                    .iter()
                    .map(|index| report.parameters[*index].name.clone()),
            )
            .collect();
        BaseColumns {
            layout,
            auxiliary: report.base_auxiliary.len(),
            parameters: report.base_parameters,
            names,
            scale,
        }
    }

    /// W_b of `samples` at the nominal robot (parameter units, rows as eq. 10).
    pub(crate) fn system(
        &self,
        robot: &Robot,
        method: &dyn CalibrationMethod,
        samples: SampleSlice<'_>,
    ) -> Result<ObservationSystem, Error> {
        let samples = nominal_readings(robot, method, samples)?;
        let study = Study::single(method.clone_method(), samples, "candidates");
        self.system_of_study(robot, &study)
    }

    /// W_b of a study at the nominal robot, its rows weighted by 1/σ of
    /// their set (readings as [`nominal_study`] gives them).
    pub(crate) fn system_of_study(
        &self,
        robot: &Robot,
        study: &Study,
    ) -> Result<ObservationSystem, Error> {
        let mut states = StudyStates::default();
        study.evaluate_poses(robot, &mut states)?;
        let auxiliary = study.initial_auxiliary(&states)?;
        let mut system = ObservationSystem::default();
        study.linearise(robot, &auxiliary, &self.layout, &mut states, &mut system)?;
        Ok(system)
    }

    /// The terminal frame's 6 × L Jacobian (position rows, then orientation)
    /// at each of `poses` (motor variables) with respect to the base columns,
    /// auxiliary columns zero (they do not move the robot); columns scaled
    /// by their error units when `scaled`.
    pub(crate) fn pose_jacobians(
        &self,
        robot: &Robot,
        poses: &[Vec<f64>],
        scaled: bool,
    ) -> Result<Vec<DMatrix<f64>>, Error> {
        let model = KinematicModel::new(robot);
        let mut chain = ChainBuffer::default();
        let mut rows = Vec::new();
        let count = model.parameter_count();
        let width = self.layout.columns();
        poses
            .iter()
            .map(|pose| {
                model.forward(pose, &mut chain)?;
                model.jacobian_rows(&chain, &mut rows, JacobianRows::Full);
                Ok(DMatrix::from_fn(6, width, |axis, column| {
                    let Some(parameter) = column.checked_sub(self.auxiliary) else {
                        return 0.0;
                    };
                    let unit = if scaled { self.scale[column] } else { 1.0 };
                    rows[axis * count + self.parameters[parameter]] * unit
                }))
            })
            .collect()
    }

    /// The scaled W_b of `samples`, whose units are the contiguous `ranges`,
    /// one block per unit.
    pub(super) fn blocks(
        &self,
        robot: &Robot,
        method: &dyn CalibrationMethod,
        samples: SampleSlice<'_>,
        ranges: &[Range<usize>],
    ) -> Result<Blocks, Error> {
        let system = self.system(robot, method, samples)?;
        self.slice(
            &system,
            ranges
                .iter()
                .map(|range| method.row_count(samples.slice(range.clone()))),
        )
    }

    /// `system` (W_b of units whose rows come one unit after the other,
    /// `rows` of them each) cut into one scaled block per unit.
    ///
    /// # Errors
    /// When the units' rows are not those of `system`.
    pub(super) fn slice(
        &self,
        system: &ObservationSystem,
        rows: impl ExactSizeIterator<Item = usize>,
    ) -> Result<Blocks, Error> {
        let width = self.layout.columns();
        let units = rows.len();
        let mut blocks = Vec::with_capacity(units);
        let mut start = 0;
        for count in rows {
            if start + count > system.rows() {
                break;
            }
            let rows = &system.matrix()[start * width..(start + count) * width];
            blocks.push(DMatrix::from_fn(count, width, |row, column| {
                rows[row * width + column] * self.scale[column]
            }));
            start += count;
        }
        if start != system.rows() || blocks.len() != units {
            return Err(Error::Numerical {
                message: format!(
                    "planning: the units give {start} rows, W has {}",
                    system.rows()
                ),
            });
        }
        Ok(Blocks {
            units: blocks,
            width,
        })
    }
}
