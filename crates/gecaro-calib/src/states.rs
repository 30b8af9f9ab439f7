//! The terminal states of configurations: the end-effector pose `(−1)T(n+1)`
//! (eq. 1) and the parameter Jacobian of Appendix II, evaluated for every
//! sample of a data set, over all cores for large sets.
//!
//! Each state depends only on its own configuration, so the states are the
//! same, bit for bit, whatever the number of threads.

use gecaro_core::{
    CONFIGURATION_LANES, Error as ModelError, JacobianRows, KinematicModel, LaneBuffer, Robot,
};
use nalgebra::IsometryMatrix3;

use crate::parallel::{PARTS_PER_THREAD, available_threads, run_parts_with};
use crate::samples::SampleSlice;

/// The end-effector pose and parameter Jacobian at one configuration.
#[derive(Clone, Debug)]
pub struct TerminalState {
    /// `(−1)T(n+1)` (eq. 1).
    pub pose: IsometryMatrix3<f64>,
    /// The Jacobian of Appendix II, row-major: `jacobian[axis * Np + k]`;
    /// rows 0–2 (position) and, when evaluated, 3–5 (rotation).
    jacobian: Vec<f64>,
    parameters: usize,
    /// Rows of the Jacobian held: 3 or 6.
    rows: usize,
}

impl TerminalState {
    pub(crate) fn empty(model: &KinematicModel) -> Self {
        TerminalState {
            pose: IsometryMatrix3::identity(),
            jacobian: Vec::new(),
            parameters: model.parameter_count(),
            rows: 0,
        }
    }

    /// A state from its pose and its row-major Jacobian of `rows` rows and
    /// `parameters` columns (a named frame's state, see [`crate::frames`]).
    pub(crate) fn from_parts(
        pose: IsometryMatrix3<f64>,
        jacobian: Vec<f64>,
        parameters: usize,
        rows: usize,
    ) -> Self {
        debug_assert_eq!(jacobian.len(), rows * parameters);
        TerminalState {
            pose,
            jacobian,
            parameters,
            rows,
        }
    }

    /// The state as one whose `rows` Jacobian rows have no columns: for rows
    /// of which no column reads a coefficient (the errors alone), so that
    /// the Jacobian need not be computed.
    pub(crate) fn with_empty_jacobian(&mut self, rows: JacobianRows) {
        self.jacobian.clear();
        self.parameters = 0;
        self.rows = rows.count();
    }

    /// Number of parameters Np (length of a Jacobian row).
    pub fn parameter_count(&self) -> usize {
        self.parameters
    }

    /// Row `axis` of the Jacobian (0–2 position, 3–5 rotation), Np entries.
    ///
    /// # Panics
    /// For a row that was not evaluated: a rotation row of a state evaluated
    /// with [`JacobianRows::Position`] (a method that reads rotation rows must
    /// say so in [`CalibrationMethod::jacobian_rows`](crate::methods::CalibrationMethod::jacobian_rows)), or any row of a state
    /// from [`evaluate_poses`].
    pub fn jacobian_row(&self, axis: usize) -> &[f64] {
        assert!(
            axis < self.rows,
            "Jacobian row {axis} was not evaluated (the method asks for {} rows)",
            self.rows
        );
        &self.jacobian[axis * self.parameters..(axis + 1) * self.parameters]
    }

    /// Adds `scale ×` row `axis` of the Jacobian to `out`.
    pub fn add_jacobian_row(&self, axis: usize, scale: f64, out: &mut [f64]) {
        for (value, coefficient) in out.iter_mut().zip(self.jacobian_row(axis)) {
            *value += scale * coefficient;
        }
    }
}

/// Below this many samples, a set is evaluated on one thread.
const PARALLEL_MINIMUM: usize = 1024;

/// Configurations evaluated and linearised together by
/// [`crate::observation`]: their states (2 kB each for 43 parameters)
/// stay in the core's cache between the model and the method.
pub(crate) const BLOCK: usize = 32;

/// Evaluates the pose and the `rows` of the Jacobian of every sample,
/// reusing `states`' storage.
///
/// Large data sets are split over the available cores. Each state depends
/// only on its own configuration, so the result is the same, bit for bit,
/// whatever the number of threads.
///
/// # Errors
/// When a sample's configuration does not fit the robot (the first such sample).
pub fn evaluate_states(
    robot: &Robot,
    samples: SampleSlice<'_>,
    rows: JacobianRows,
    states: &mut Vec<TerminalState>,
) -> Result<(), ModelError> {
    evaluate_into(robot, samples, Some(rows), states)
}

/// The poses of every sample only, as [`evaluate_states`] does (the states
/// hold no Jacobian rows): what initial auxiliary values and data-like
/// random configurations need.
///
/// # Errors
/// As [`evaluate_states`].
pub fn evaluate_poses(
    robot: &Robot,
    samples: SampleSlice<'_>,
    states: &mut Vec<TerminalState>,
) -> Result<(), ModelError> {
    evaluate_into(robot, samples, None, states)
}

fn evaluate_into(
    robot: &Robot,
    samples: SampleSlice<'_>,
    rows: Option<JacobianRows>,
    states: &mut Vec<TerminalState>,
) -> Result<(), ModelError> {
    let model = KinematicModel::new(robot);
    states.truncate(samples.len());
    states.resize_with(samples.len(), || TerminalState::empty(&model));
    let part = part_size(samples.len());
    let parts = samples.chunks(part).zip(states.chunks_mut(part)).collect();
    run_parts_with(parts, LaneBuffer::default, |lanes, (samples, states)| {
        evaluate_chunk(&model, samples, rows, states, lanes)
    })
    .into_iter()
    .collect()
}

/// The fewest samples of a part evaluated on its own.
const MIN_PART: usize = 256;

/// Samples per part: all of them below [`PARALLEL_MINIMUM`], else about
/// [`PARTS_PER_THREAD`] parts per thread (the threads take them in turn,
/// see [`run_parts`](crate::parallel::run_parts)) of at least [`MIN_PART`].
pub(crate) fn part_size(samples: usize) -> usize {
    if samples < PARALLEL_MINIMUM {
        samples.max(1)
    } else {
        samples
            .div_ceil(available_threads() * PARTS_PER_THREAD)
            .max(MIN_PART)
    }
}

/// The poses and, unless `rows` is `None`, those Jacobian rows of `samples`,
/// evaluated in `lanes` (a buffer its caller keeps from one call to the next).
pub(crate) fn evaluate_chunk(
    model: &KinematicModel,
    samples: SampleSlice<'_>,
    rows: Option<JacobianRows>,
    states: &mut [TerminalState],
    lanes: &mut LaneBuffer,
) -> Result<(), ModelError> {
    for (group, states) in samples
        .chunks(CONFIGURATION_LANES)
        .zip(states.chunks_mut(CONFIGURATION_LANES))
    {
        lanes.clear();
        for sample in group.iter() {
            lanes.push(
                model,
                sample.motor_positions(),
                sample.torques(),
                sample.tilt_torques(),
            )?;
        }
        model.forward_lanes(lanes);
        for (lane, state) in states.iter_mut().enumerate() {
            state.pose = lanes.world_from_tool(lane);
            state.parameters = model.parameter_count();
            state.rows = rows.map_or(0, JacobianRows::count);
        }
        match rows {
            Some(rows) => model.jacobian_rows_lanes(
                lanes,
                states.iter_mut().map(|state| &mut state.jacobian),
                rows,
            ),
            None => states.iter_mut().for_each(|state| state.jacobian.clear()),
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sample::Sample;
    use crate::samples::Samples;
    use crate::simulation::Sampler;

    #[test]
    fn parallel_evaluation_is_bit_identical_to_serial() {
        let robot = Robot::template("arm", "RRPRRR").expect("template");
        let mut sampler = Sampler::new(9);
        let samples: Vec<Sample> = (0..PARALLEL_MINIMUM * 2 + 17)
            .map(|_| Sample::new(sampler.configuration(&robot)))
            .collect();
        let model = KinematicModel::new(&robot);
        for rows in [JacobianRows::Full, JacobianRows::Position] {
            let mut parallel = Vec::new();
            evaluate_states(
                &robot,
                Samples::from(samples.as_slice()).as_slice(),
                rows,
                &mut parallel,
            )
            .expect("states");
            let mut serial: Vec<TerminalState> = samples
                .iter()
                .map(|_| TerminalState::empty(&model))
                .collect();
            evaluate_chunk(
                &model,
                Samples::from(samples.as_slice()).as_slice(),
                Some(rows),
                &mut serial,
                &mut LaneBuffer::default(),
            )
            .expect("states");
            for (a, b) in parallel.iter().zip(&serial) {
                assert_eq!(a.pose, b.pose);
                let bits =
                    |values: &[f64]| values.iter().map(|v| v.to_bits()).collect::<Vec<u64>>();
                assert_eq!(bits(&a.jacobian), bits(&b.jacobian));
                assert_eq!(a.jacobian.len(), rows.count() * model.parameter_count());
            }
        }
    }

    #[test]
    #[should_panic(expected = "Jacobian row 3 was not evaluated")]
    fn rotation_rows_of_a_position_state_are_refused() {
        let robot = Robot::template("arm", "RRR").expect("template");
        let samples = [Sample::new(vec![0.1, 0.2, 0.3])];
        let mut states = Vec::new();
        evaluate_states(
            &robot,
            Samples::from(samples.as_slice()).as_slice(),
            JacobianRows::Position,
            &mut states,
        )
        .expect("states");
        assert_eq!(states[0].jacobian_row(2).len(), robot.parameters().len());
        let _ = states[0].jacobian_row(3);
    }
}
