//! What point link and frame link share (paper §3.2): sets of configurations
//! that reach the same point (rows 1–3 of eq. 12) or the same frame (eq. 12),
//! written per set as mean-centred rows (see the parent module docs).
//!
//! For a set S, with y_i the terminal position (and, for frames, the rotation
//! vector δ(R_i, R_ref) of the orientation from the set's first member) and
//! J_i the matching Jacobian rows: `(J_i − J̄_S) Δη = −(y_i − ȳ_S)`.

use gecaro_core::{OrientationDifference, Robot, Target, orientation_difference, terminal_pose};
use nalgebra::IsometryMatrix3;

use super::sets::{centre, groups, set_sizes};
use crate::error::Error;
use crate::method::Sensor;
use crate::progress::{Observer, report_step};
use crate::rows::{RowKind, RowWriter};
use crate::sample::Sample;
use crate::sampler::Sampler;
use crate::samples::SampleSlice;
use crate::states::TerminalState;

/// Start configurations tried per set before generation gives up.
const SET_ATTEMPTS: usize = 10;

/// What the configurations of a set have in common.
#[derive(Copy, Clone, Debug)]
pub(super) enum Linked {
    /// The origin of frame n+1.
    Point,
    /// The whole frame n+1, orientations compared as given.
    Frame(OrientationDifference),
}

impl Linked {
    fn dimension(self) -> usize {
        match self {
            Linked::Point => 3,
            Linked::Frame(_) => 6,
        }
    }
}

/// The simulated session of a link method: sets of `set_size`
/// configurations (about) that reach one point or frame.
#[derive(Clone, Debug)]
pub(super) struct LinkSets {
    pub(super) linked: Linked,
    pub(super) set_size: usize,
}

impl LinkSets {
    /// Independent equations per configuration of sets of `set_size`: each
    /// set's mean uses up one configuration's worth.
    pub(super) fn equations_per_configuration(&self) -> f64 {
        self.linked.dimension() as f64 * (1.0 - 1.0 / self.set_size.max(2) as f64)
    }
}

impl Sensor for LinkSets {
    fn generate(
        &self,
        robot: &Robot,
        count: usize,
        noise: f64,
        sampler: &mut Sampler,
        observer: &mut dyn Observer,
    ) -> Result<Vec<Sample>, Error> {
        generate_sets(
            self.linked,
            robot,
            count,
            self.set_size,
            noise,
            sampler,
            observer,
        )
    }

    fn measure_at(
        &self,
        real: &Robot,
        planned: SampleSlice<'_>,
        noise: f64,
        sampler: &mut Sampler,
        observer: &mut dyn Observer,
    ) -> Result<Vec<Sample>, Error> {
        measure_sets(self.linked, real, planned, noise, sampler, observer)
    }
}

/// Rows of every set; one observation per configuration.
pub(super) fn linearise_sets(
    linked: Linked,
    samples: SampleSlice<'_>,
    states: &[TerminalState],
    rows: &mut RowWriter<'_>,
) {
    let dimension = linked.dimension();
    let parameters = states.first().map_or(0, TerminalState::parameter_count);
    for members in groups(samples) {
        let count = members.len();
        let mut values = vec![0.0; count * dimension];
        let mut coefficients = vec![0.0; count * dimension * parameters];
        let reference = states[members[0]].pose.rotation;
        for (slot, &index) in members.iter().enumerate() {
            let state = &states[index];
            let value = &mut values[slot * dimension..(slot + 1) * dimension];
            value[..3].copy_from_slice(state.pose.translation.vector.as_slice());
            if let Linked::Frame(method) = linked {
                let rotation = orientation_difference(&state.pose.rotation, &reference, method);
                value[3..].copy_from_slice(rotation.as_slice());
            }
            for axis in 0..dimension {
                let start = (slot * dimension + axis) * parameters;
                state.add_jacobian_row(axis, 1.0, &mut coefficients[start..start + parameters]);
            }
        }
        let weights: Vec<f64> = members
            .iter()
            .map(|&index| rows.observation_weight(index))
            .collect();
        centre(&mut values, &weights);
        centre(&mut coefficients, &weights);
        for (slot, &index) in members.iter().enumerate() {
            for axis in 0..dimension {
                let row = slot * dimension + axis;
                let kind = if axis < 3 {
                    RowKind::Length
                } else {
                    RowKind::Angle
                };
                let coefficient_row = &coefficients[row * parameters..(row + 1) * parameters];
                rows.push(kind, index, -values[row], coefficient_row, &[]);
            }
        }
    }
}

/// One equation per set and dimension is used up by the centring.
pub(super) fn dependent_rows(linked: Linked, samples: SampleSlice<'_>) -> usize {
    linked.dimension() * groups(samples).len()
}

/// Sets of `set_size` configurations that reach a common point or frame of
/// `robot`, each perturbed by `noise` (the contact's own scatter).
fn generate_sets(
    linked: Linked,
    robot: &Robot,
    count: usize,
    set_size: usize,
    noise: f64,
    sampler: &mut Sampler,
    observer: &mut dyn Observer,
) -> Result<Vec<Sample>, Error> {
    let mut samples = Vec::with_capacity(count);
    for (set, size) in set_sizes(count, set_size).into_iter().enumerate() {
        report_step(observer, samples.len(), count)?;
        let mut last_error = None;
        for _ in 0..SET_ATTEMPTS {
            match generate_set(linked, robot, size, noise, sampler) {
                Ok(members) => {
                    samples.extend(members.into_iter().map(|motor_positions| Sample {
                        group: Some(set as u64 + 1),
                        ..Sample::new(motor_positions)
                    }));
                    last_error = None;
                    break;
                }
                Err(error) => last_error = Some(error),
            }
        }
        if let Some(error) = last_error {
            return Err(error);
        }
    }
    Ok(samples)
}

/// The sets of `planned` measured on `real`: each set's first configuration
/// gives the point or frame (the socket), every member (the first too, with
/// the contact's scatter `noise`) is moved to reach it from its planned
/// configuration.
fn measure_sets(
    linked: Linked,
    real: &Robot,
    planned: SampleSlice<'_>,
    noise: f64,
    sampler: &mut Sampler,
    observer: &mut dyn Observer,
) -> Result<Vec<Sample>, Error> {
    let mut measured = planned.to_rows();
    let mut done = 0;
    for set in groups(planned) {
        report_step(observer, done, planned.len())?;
        done += set.len();
        if set.len() < 2 {
            return Err(Error::InvalidData {
                line: planned.get(set[0]).line(),
                message: format!(
                    "set {} has one configuration; a set needs at least 2",
                    planned.get(set[0]).group().unwrap_or(0)
                ),
            });
        }
        let pose = terminal_pose(real, planned.get(set[0]).motor_positions())?;
        let mut members: Vec<Vec<f64>> = Vec::with_capacity(set.len());
        for index in &set {
            let target = perturbed_target(linked, &pose, noise, sampler);
            let others: Vec<&[f64]> = members.iter().map(Vec::as_slice).collect();
            let reached = sampler.reach(
                real,
                &target,
                Some(planned.get(*index).motor_positions()),
                &others,
            )?;
            members.push(reached);
        }
        for (index, motor_positions) in set.into_iter().zip(members) {
            measured[index].motor_positions = motor_positions.into();
        }
    }
    Ok(measured)
}

fn generate_set(
    linked: Linked,
    robot: &Robot,
    size: usize,
    noise: f64,
    sampler: &mut Sampler,
) -> Result<Vec<Vec<f64>>, Error> {
    let first = sampler.configuration(robot);
    let pose = terminal_pose(robot, &first)?;
    let mut members: Vec<Vec<f64>> = Vec::with_capacity(size);
    for member in 0..size {
        let target = perturbed_target(linked, &pose, noise, sampler);
        let start = (member == 0).then_some(first.as_slice());
        let others: Vec<&[f64]> = members.iter().map(Vec::as_slice).collect();
        let reached = sampler.reach(robot, &target, start, &others)?;
        members.push(reached);
    }
    Ok(members)
}

fn perturbed_target(
    linked: Linked,
    pose: &IsometryMatrix3<f64>,
    noise: f64,
    sampler: &mut Sampler,
) -> Target {
    let position = pose.translation.vector + sampler.gaussian_vector(noise);
    match linked {
        Linked::Point => Target::Position(position),
        Linked::Frame(_) => Target::Frame(IsometryMatrix3::from_parts(
            position.into(),
            sampler.gaussian_rotation(noise) * pose.rotation,
        )),
    }
}
