//! Distance measure (paper §3.4): pairs of configurations with the measured
//! distance between their terminal points. Eq. 19–20 divided by 2D, so that the
//! residual is in metres: with `d = P_j − P_i`, `D = ‖d‖`, `u = d/D`,
//! `u·(J_j − J_i) Δη = D_measured − D`. Data: `pair` ids (two rows each) and
//! `distance` (the same on both rows).

use gecaro_core::{JacobianRows, Robot, terminal_pose};

use super::sets::{check_group_sizes, groups};
use crate::error::Error;
use crate::method::{CalibrationMethod, MethodInfo, Sensor};
use crate::progress::{Observer, report_step};
use crate::rows::{RowKind, RowWriter};
use crate::sample::{DataColumn, Sample};
use crate::sampler::Sampler;
use crate::samples::SampleSlice;
use crate::states::TerminalState;

pub(super) const INFO: MethodInfo = MethodInfo::new(
    "distance",
    "Distance measure",
    &[DataColumn::Pair, DataColumn::Distance],
    JacobianRows::Position,
    0,
    |_| Ok(Box::new(DistanceMeasure)),
);

/// Distance measure; see the module docs.
#[derive(Clone, Debug)]
pub(crate) struct DistanceMeasure;

impl CalibrationMethod for DistanceMeasure {
    fn info(&self) -> &'static MethodInfo {
        &INFO
    }

    fn sensor(&self) -> &dyn Sensor {
        self
    }

    fn check_samples(&self, samples: SampleSlice<'_>) -> Result<(), Error> {
        check_group_sizes(samples, 2, 2, "pair")?;
        for pair in groups(samples) {
            let (first, second) = (&samples.get(pair[0]), &samples.get(pair[1]));
            let (a, b) = (
                first.distance().unwrap_or(f64::NAN),
                second.distance().unwrap_or(f64::NAN),
            );
            if (a - b).abs() > 1e-9 * a.abs().max(1.0) {
                return Err(Error::InvalidData {
                    line: second.line(),
                    message: format!(
                        "pair {} gives two different distances ({a} and {b}); both rows of a pair carry the same measured distance",
                        first.group().unwrap_or(0)
                    ),
                });
            }
            if a < 0.0 {
                return Err(Error::InvalidData {
                    line: first.line(),
                    message: format!(
                        "pair {}: a distance cannot be negative ({a})",
                        first.group().unwrap_or(0)
                    ),
                });
            }
        }
        Ok(())
    }

    fn row_count(&self, samples: SampleSlice<'_>) -> usize {
        groups(samples).len()
    }

    /// One observation per pair.
    fn grouped_observations(&self, samples: SampleSlice<'_>) -> Option<Vec<Vec<usize>>> {
        Some(groups(samples))
    }

    fn equations_per_configuration(&self) -> f64 {
        0.5
    }

    fn linearise(
        &self,
        samples: SampleSlice<'_>,
        states: &[TerminalState],
        _auxiliary: &[f64],
        rows: &mut RowWriter<'_>,
    ) {
        let mut coefficients = vec![0.0; states.first().map_or(0, TerminalState::parameter_count)];
        for (pair, members) in groups(samples).into_iter().enumerate() {
            let (first, second) = (&states[members[0]], &states[members[1]]);
            let difference = second.pose.translation.vector - first.pose.translation.vector;
            let distance = difference.norm();
            coefficients.fill(0.0);
            if distance > 0.0 {
                let direction = difference / distance;
                for axis in 0..3 {
                    second.add_jacobian_row(axis, direction[axis], &mut coefficients);
                    first.add_jacobian_row(axis, -direction[axis], &mut coefficients);
                }
            }
            let measured = samples.get(members[0]).distance().unwrap_or(distance);
            rows.push(
                RowKind::Length,
                pair,
                measured - distance,
                &coefficients,
                &[],
            );
        }
    }
}

/// The simulated session: pairs of configurations and the distance a
/// length bar or laser tracker measures between their terminal points.
impl Sensor for DistanceMeasure {
    fn generate(
        &self,
        robot: &Robot,
        count: usize,
        noise: f64,
        sampler: &mut Sampler,
        observer: &mut dyn Observer,
    ) -> Result<Vec<Sample>, Error> {
        let pairs = (count / 2).max(1);
        let mut samples = Vec::with_capacity(2 * pairs);
        for pair in 0..pairs {
            report_step(observer, 2 * pair, 2 * pairs)?;
            let first = sampler.configuration(robot);
            let second = sampler.configuration(robot);
            let distance = (terminal_pose(robot, &second)?.translation.vector
                - terminal_pose(robot, &first)?.translation.vector)
                .norm()
                + sampler.gaussian(noise);
            for motor_positions in [first, second] {
                samples.push(Sample {
                    group: Some(pair as u64 + 1),
                    distance: Some(distance),
                    ..Sample::new(motor_positions)
                });
            }
        }
        Ok(samples)
    }

    fn measure_at(
        &self,
        real: &Robot,
        planned: SampleSlice<'_>,
        noise: f64,
        sampler: &mut Sampler,
        observer: &mut dyn Observer,
    ) -> Result<Vec<Sample>, Error> {
        check_group_sizes(planned, 2, 2, "pair")?;
        let mut measured = planned.to_rows();
        for (done, pair) in groups(planned).into_iter().enumerate() {
            report_step(observer, 2 * done, planned.len())?;
            let point = |index: usize| -> Result<_, Error> {
                Ok(terminal_pose(real, planned.get(index).motor_positions())?
                    .translation
                    .vector)
            };
            let distance = (point(pair[1])? - point(pair[0])?).norm() + sampler.gaussian(noise);
            for index in pair {
                measured[index].distance = Some(distance);
            }
        }
        Ok(measured)
    }
}
