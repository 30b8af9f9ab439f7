//! A calibration study: one or several measurement sets, each with its
//! method, its data and its sensor's standard deviation, stacked into one
//! observation matrix (rows of a set weighted by 1/σ). A single-method
//! calibration is a study of one set.

use gecaro_core::Robot;

use crate::Error;
use crate::methods::CalibrationMethod;
use crate::observation::{ColumnLayout, ObservationSystem, TerminalState, evaluate_states};
use crate::sample::{DataColumn, Sample};

/// One measurement set of a study.
#[derive(Debug)]
pub struct MeasurementSet {
    /// How the data constrain the robot.
    pub method: Box<dyn CalibrationMethod>,
    /// The configurations and what was measured there.
    pub samples: Vec<Sample>,
    /// The sensor's standard deviation (metres, and radians for orientations
    /// unless `sigma_rotation` is given); the rows are weighted by 1/σ. Use 1
    /// for an unweighted single-set study.
    pub sigma: f64,
    /// A separate standard deviation for the orientation rows (radians).
    pub sigma_rotation: Option<f64>,
    /// A name for messages (usually the data file).
    pub label: String,
}

/// A measured configuration that puts a joint outside its limits (eq. 4
/// maps the motor variables to joint variables first).
#[derive(Clone, Debug, PartialEq)]
pub struct LimitViolation {
    /// The set's label (usually its data file).
    pub label: String,
    /// The line of the data file, when known.
    pub line: Option<usize>,
    /// The joint, 1-based.
    pub joint: usize,
    /// Its joint variable q (radians or metres).
    pub value: f64,
    /// Its lower limit.
    pub qmin: f64,
    /// Its upper limit.
    pub qmax: f64,
}

impl std::fmt::Display for LimitViolation {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self.line {
            Some(line) => write!(f, "{}:{line}: ", self.label)?,
            None => write!(f, "{}: ", self.label)?,
        }
        let (bound, name) = if self.value < self.qmin {
            (self.qmin, "qmin")
        } else {
            (self.qmax, "qmax")
        };
        write!(
            f,
            "q{} = {} is {} {name} = {bound}",
            self.joint,
            self.value,
            if self.value < self.qmin {
                "below"
            } else {
                "above"
            }
        )
    }
}

/// One or more measurement sets calibrated together.
#[derive(Debug, Default)]
pub struct Study {
    /// The measurement sets.
    pub sets: Vec<MeasurementSet>,
}

/// Poses and Jacobians of every sample of a study, reused between iterations.
#[derive(Debug, Default)]
pub struct StudyStates {
    states: Vec<Vec<TerminalState>>,
}

impl StudyStates {
    /// The states of set `set`.
    pub fn set(&self, set: usize) -> &[TerminalState] {
        &self.states[set]
    }
}

impl Study {
    /// A study of one measurement set, unweighted.
    pub fn single(
        method: Box<dyn CalibrationMethod>,
        samples: Vec<Sample>,
        label: impl Into<String>,
    ) -> Self {
        Study {
            sets: vec![MeasurementSet {
                method,
                samples,
                sigma: 1.0,
                sigma_rotation: None,
                label: label.into(),
            }],
        }
    }

    /// Configurations whose joint variables lie outside the joint limits, in
    /// data order (one entry per joint out of range). Configurations that do
    /// not fit the robot are left to [`Study::check`].
    pub fn limit_violations(&self, robot: &Robot) -> Vec<LimitViolation> {
        let mut violations = Vec::new();
        for set in &self.sets {
            for sample in &set.samples {
                let Ok(joints) = robot.joint_positions(&sample.motor_positions) else {
                    continue;
                };
                for (index, (value, joint)) in joints.iter().zip(robot.joints()).enumerate() {
                    if *value < joint.qmin || *value > joint.qmax {
                        violations.push(LimitViolation {
                            label: set.label.clone(),
                            line: sample.line,
                            joint: index + 1,
                            value: *value,
                            qmin: joint.qmin,
                            qmax: joint.qmax,
                        });
                    }
                }
            }
        }
        violations
    }

    /// The method names, joined with `+`.
    pub fn method_names(&self) -> String {
        self.sets
            .iter()
            .map(|set| set.method.name())
            .collect::<Vec<_>>()
            .join("+")
    }

    /// Checks every set against the robot and its method: configurations of n
    /// finite values, the method's columns present and finite, unit
    /// quaternions, set and pair structure, a positive σ.
    ///
    /// # Errors
    /// [`Error::InvalidData`] naming the line at fault.
    pub fn check(&self, robot: &Robot) -> Result<(), Error> {
        if self.sets.is_empty() {
            return Err(Error::InvalidData {
                line: None,
                message: "the study has no measurement sets".into(),
            });
        }
        for set in &self.sets {
            let invalid = |line: Option<usize>, message: String| Error::InvalidData {
                line: None,
                message: match line {
                    Some(line) => format!("{}:{line}: {message}", set.label),
                    None => format!("{}: {message}", set.label),
                },
            };
            if let Some(sigma) = set.sigma_rotation
                && !(sigma.is_finite() && sigma > 0.0)
            {
                return Err(invalid(
                    None,
                    format!("sigma_rotation must be a positive number, not {sigma}"),
                ));
            }
            if !(set.sigma.is_finite() && set.sigma > 0.0) {
                return Err(invalid(
                    None,
                    format!("sigma must be a positive number, not {}", set.sigma),
                ));
            }
            if set.samples.is_empty() {
                return Err(invalid(None, "no configurations".into()));
            }
            for sample in &set.samples {
                robot
                    .check_configuration(&sample.motor_positions)
                    .map_err(|error| invalid(sample.line, error.to_string()))?;
                for column in set.method.data_columns() {
                    check_field(*column, sample)
                        .map_err(|message| invalid(sample.line, message))?;
                }
            }
            set.method
                .check_samples(&set.samples)
                .map_err(|error| match error {
                    Error::InvalidData { line, message } => invalid(line, message),
                    other => other,
                })?;
        }
        Ok(())
    }

    /// Names of all auxiliary unknowns, prefixed by the set's method when the study has several sets.
    pub fn auxiliary_names(&self) -> Vec<String> {
        self.sets
            .iter()
            .enumerate()
            .flat_map(|(index, set)| {
                let prefix = if self.sets.len() > 1 {
                    format!("{}[{}].", set.method.name(), index + 1)
                } else {
                    String::new()
                };
                set.method
                    .auxiliary_names()
                    .into_iter()
                    .map(move |name| format!("{prefix}{name}"))
            })
            .collect()
    }

    /// Whether some set measures a length (position, frame, distance), so that
    /// the robot's scale is observable; link and plane methods alone cannot see it.
    pub fn observes_scale(&self) -> bool {
        self.sets.iter().any(|set| !set.method.scale_invariant())
    }

    /// Total rows of W.
    pub fn row_count(&self) -> usize {
        self.sets
            .iter()
            .map(|set| set.method.row_count(&set.samples))
            .sum()
    }

    /// Independent equations: rows minus those used up by centring.
    pub fn equation_count(&self) -> usize {
        self.sets
            .iter()
            .map(|set| {
                set.method
                    .row_count(&set.samples)
                    .saturating_sub(set.method.dependent_rows(&set.samples))
            })
            .sum()
    }

    /// Evaluates the pose and Jacobian of every sample at the robot's parameters.
    ///
    /// # Errors
    /// When a configuration does not fit the robot.
    pub fn evaluate(&self, robot: &Robot, states: &mut StudyStates) -> Result<(), Error> {
        states.states.resize_with(self.sets.len(), Vec::new);
        for (set, buffer) in self.sets.iter().zip(&mut states.states) {
            evaluate_states(robot, &set.samples, buffer)?;
        }
        Ok(())
    }

    /// Initial auxiliary values of every set, from states at the starting parameters.
    ///
    /// # Errors
    /// When a method cannot initialise its unknowns from these data.
    pub fn initial_auxiliary(&self, states: &StudyStates) -> Result<Vec<f64>, Error> {
        let mut values = Vec::new();
        for (index, set) in self.sets.iter().enumerate() {
            values.extend(set.method.initial_auxiliary(states.set(index))?);
        }
        Ok(values)
    }

    /// Writes the stacked, weighted system at the evaluated states.
    pub fn assemble(
        &self,
        states: &StudyStates,
        auxiliary: &[f64],
        layout: &ColumnLayout,
        system: &mut ObservationSystem,
    ) {
        system.reset(self.row_count(), layout);
        let mut first_row = 0;
        let mut auxiliary_offset = 0;
        for (index, set) in self.sets.iter().enumerate() {
            let rows = set.method.row_count(&set.samples);
            let count = set.method.auxiliary_names().len();
            let own = &auxiliary[auxiliary_offset..auxiliary_offset + count];
            let mut writer = system.writer(
                layout,
                first_row,
                rows,
                auxiliary_offset,
                [
                    1.0 / set.sigma,
                    1.0 / set.sigma_rotation.unwrap_or(set.sigma),
                ],
            );
            set.method
                .linearise(&set.samples, states.set(index), own, &mut writer);
            debug_assert!(
                writer.is_complete(),
                "{} wrote fewer rows than promised",
                set.method.name()
            );
            first_row += rows;
            auxiliary_offset += count;
        }
    }
}

fn check_field(column: DataColumn, sample: &Sample) -> Result<(), String> {
    let missing = || format!("missing {}", column.headers().join(", "));
    match column {
        DataColumn::Position => {
            let position = sample.position.ok_or_else(missing)?;
            if !position.iter().all(|v| v.is_finite()) {
                return Err("the measured position is not finite".into());
            }
        }
        DataColumn::Orientation => {
            let orientation = sample.orientation.ok_or_else(missing)?;
            if !orientation.coords.iter().all(|v| v.is_finite()) {
                return Err("the measured orientation is not finite".into());
            }
        }
        DataColumn::Set | DataColumn::Pair => {
            sample.group.ok_or_else(missing)?;
        }
        DataColumn::Distance => {
            let distance = sample.distance.ok_or_else(missing)?;
            if !distance.is_finite() {
                return Err("the measured distance is not finite".into());
            }
        }
    }
    Ok(())
}
