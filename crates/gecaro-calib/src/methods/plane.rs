//! What the two plane methods share (paper §3.3): the plane they were given,
//! and their sensor, which generates configurations whose terminal point lies
//! in a plane (a touch probe on a surface).

use gecaro_core::{InverseOptions, InverseSolver, Robot, Target};
use nalgebra::Vector3;

use crate::error::{Error, Setting};
use crate::method::Sensor;
use crate::plane::Plane;
use crate::progress::{Observer, report_step};
use crate::sample::Sample;
use crate::sampler::Sampler;
use crate::samples::SampleSlice;
use crate::states::TerminalState;

/// The simulated session of a plane method: the terminal point touches
/// `plane`. `method` names it in messages (`plane1`).
#[derive(Clone, Debug)]
pub(super) struct PlaneContact {
    pub(super) plane: Option<Plane>,
    pub(super) method: &'static str,
}

impl Sensor for PlaneContact {
    fn generate(
        &self,
        robot: &Robot,
        count: usize,
        noise: f64,
        sampler: &mut Sampler,
        observer: &mut dyn Observer,
    ) -> Result<Vec<Sample>, Error> {
        let plane = required(self.plane, &format!("generating {} points", self.method))?;
        generate_in_plane(robot, &plane, count, noise, sampler, observer)
    }

    fn measure_at(
        &self,
        real: &Robot,
        planned: SampleSlice<'_>,
        noise: f64,
        sampler: &mut Sampler,
        observer: &mut dyn Observer,
    ) -> Result<Vec<Sample>, Error> {
        let plane = required(self.plane, &format!("measuring {} points", self.method))?;
        measure_in_plane(real, &plane, planned, noise, sampler, observer)
    }

    fn generate_like(
        &self,
        robot: &Robot,
        _samples: SampleSlice<'_>,
        states: &[TerminalState],
        count: usize,
        sampler: &mut Sampler,
        observer: &mut dyn Observer,
    ) -> Result<Vec<Sample>, Error> {
        let plane = plane_like(self.plane, states)?;
        generate_in_plane(robot, &plane, count, 0.0, sampler, observer)
    }
}

/// The plane to generate data like `states` in: the given one, or the
/// least-squares plane of the terminal points.
fn plane_like(plane: Option<Plane>, states: &[TerminalState]) -> Result<Plane, Error> {
    match plane {
        Some(plane) => Ok(plane),
        None => Plane::fit(states.iter().map(|state| state.pose.translation.vector)),
    }
}

/// The names of a plane method's unknowns: a, b, c when the plane is
/// `unknown`, none when it is known.
pub(super) fn plane_unknowns(unknown: bool) -> Vec<String> {
    if unknown {
        ["a", "b", "c"].map(String::from).to_vec()
    } else {
        Vec::new()
    }
}

/// The starting values of a plane method's unknowns: `of` the least-squares
/// plane of the terminal points at the starting parameters (its equation's
/// coefficients or its normal), none when the plane is known.
pub(super) fn fitted_unknowns(
    unknown: bool,
    states: &[TerminalState],
    of: impl Fn(&Plane) -> Result<Vector3<f64>, Error>,
) -> Result<Vec<f64>, Error> {
    if !unknown {
        return Ok(Vec::new());
    }
    let fitted = Plane::fit(states.iter().map(|state| state.pose.translation.vector))?;
    Ok(of(&fitted)?.as_slice().to_vec())
}

/// The plane a method was given, or the error that says how to give one.
pub(super) fn required(plane: Option<Plane>, method: &str) -> Result<Plane, Error> {
    plane.ok_or_else(|| Error::InvalidOption {
        setting: Setting::Plane,
        message: format!("{method} needs a plane: its normal and a point of it"),
    })
}

/// Configurations of `robot` whose terminal point lies in `plane`, to within
/// Gaussian `noise` along the normal (the contact's own scatter).
fn generate_in_plane(
    robot: &Robot,
    plane: &Plane,
    count: usize,
    noise: f64,
    sampler: &mut Sampler,
    observer: &mut dyn Observer,
) -> Result<Vec<Sample>, Error> {
    const STARTS_PER_POINT: usize = 20;
    let mut samples = Vec::with_capacity(count);
    let solver = InverseSolver::new(robot);
    for done in 0..count {
        report_step(observer, done, count)?;
        let mut reached = None;
        for _ in 0..STARTS_PER_POINT {
            // From a random configuration, slide to the nearest point of the
            // (noise-shifted) plane: points spread over its reachable part.
            let start = sampler.configuration(robot);
            let target = Target::Plane {
                normal: plane.normal(),
                offset: plane.normal().dot(&plane.point()) + sampler.gaussian(noise),
            };
            if let Ok(solution) = solver.solve(&target, &start, &InverseOptions::default()) {
                reached = Some(solution.motor_positions);
                break;
            }
        }
        let motor_positions = reached.ok_or_else(|| Error::Generation {
            message:
                "the plane is out of reach: no configuration within the joint limits puts the \
                      terminal point on it; choose a plane through the workspace"
                    .into(),
        })?;
        samples.push(Sample::new(motor_positions));
    }
    Ok(samples)
}

/// Configurations of `planned` moved onto `plane` (shifted by Gaussian noise
/// σ = `noise` along its normal) on `real`, each from its planned
/// configuration: where the touch probe meets the plane.
fn measure_in_plane(
    real: &Robot,
    plane: &Plane,
    planned: SampleSlice<'_>,
    noise: f64,
    sampler: &mut Sampler,
    observer: &mut dyn Observer,
) -> Result<Vec<Sample>, Error> {
    planned
        .iter()
        .enumerate()
        .map(|(done, sample)| {
            report_step(observer, done, planned.len())?;
            let target = Target::Plane {
                normal: plane.normal(),
                offset: plane.normal().dot(&plane.point()) + sampler.gaussian(noise),
            };
            let reached = sampler.reach(real, &target, Some(sample.motor_positions()), &[])?;
            Ok(Sample {
                motor_positions: reached.into(),
                ..sample.to_sample()
            })
        })
        .collect()
}
