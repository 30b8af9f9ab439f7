//! A calibration study: one or several measurement sets, each with its
//! method, its data and its sensor's standard deviation, stacked into one
//! observation matrix (rows of a set weighted by 1/σ). A single-method
//! calibration is a study of one set.

use gecaro_core::{JacobianRows, KinematicModel, Robot};

use crate::Error;
use crate::frames::{FRAME_UNKNOWNS, FrameRole, NamedFrame, SetFrames, UNKNOWN_NAMES};
use crate::linearise::{linearise_independent, write_rows};
use crate::method::CalibrationMethod;
use crate::methods::units;
use crate::observation::ObservationSystem;
use crate::parallel::run_parts;
use crate::rows::{ColumnLayout, RowWriter};

pub use crate::sample::{DataColumn, MotorPositions, RowSigma, Sample, SampleLoads};
pub use crate::samples::{
    Column, FilledSamples, SampleColumns, SampleIter, SampleRef, SampleShape, SampleSlice,
    SampleSlots, Samples, SamplesBuilder, SlotMut,
};
use crate::states::{TerminalState, evaluate_poses, evaluate_states, part_size};

/// One measurement set of a study.
#[derive(Debug)]
pub struct MeasurementSet {
    /// How the data constrain the robot.
    pub method: Box<dyn CalibrationMethod>,
    /// The configurations and what was measured there.
    pub samples: Samples,
    /// The sensor's standard deviation (metres, and radians for orientations
    /// unless `sigma_rotation` is given), when it is known: the rows are
    /// weighted by 1/σ, and the identification's verdict tests the residuals
    /// against it. `None`: unweighted rows (σ = 1), no test.
    pub sigma: Option<f64>,
    /// A separate standard deviation for the orientation rows (radians).
    pub sigma_rotation: Option<f64>,
    /// Where `sigma` was measured (a repeatability file of poses revisited),
    /// when it was not stated: the verdict says which.
    pub sigma_source: Option<String>,
    /// A name for messages (usually the data file).
    pub label: String,
    /// The named tool the set measures (index into [`Study::frames`]);
    /// `None`: the robot's own frame n+1.
    pub tool: Option<usize>,
    /// The station the set measures from (index into [`Study::frames`]);
    /// `None`: the world frame.
    pub station: Option<usize>,
}

impl MeasurementSet {
    /// The same set (method, σ, label) with other samples.
    pub fn with_samples(&self, samples: impl Into<Samples>) -> MeasurementSet {
        MeasurementSet {
            method: self.method.clone_method(),
            samples: samples.into(),
            sigma: self.sigma,
            sigma_rotation: self.sigma_rotation,
            sigma_source: self.sigma_source.clone(),
            label: self.label.clone(),
            tool: self.tool,
            station: self.station,
        }
    }

    /// Whether the set names a tool or a station.
    pub fn uses_named_frames(&self) -> bool {
        self.tool.is_some() || self.station.is_some()
    }
}

impl MeasurementSet {
    /// The weights of the set's length and angle rows: 1/σ (1 when no σ is
    /// stated; the angle rows' σ is `sigma_rotation` when given).
    pub fn row_weights(&self) -> [f64; 2] {
        let length = self.sigma.unwrap_or(1.0);
        [1.0 / length, 1.0 / self.sigma_rotation.unwrap_or(length)]
    }

    /// The sensor weights of each configuration's length and angle rows
    /// when the data state a σ per row ([`RowSigma`]): 1/σ of the row,
    /// the set's ([`row_weights`](Self::row_weights)) where the row states
    /// none; empty when no row states one. A configuration is an
    /// observation of the methods whose configurations are independent,
    /// the only ones whose data may state σ per row
    /// ([`Study::check`]).
    pub fn observation_sensors(&self) -> Vec<[f64; 2]> {
        if !self.samples.has_row_sigma() {
            return Vec::new();
        }
        let [length, angle] = self.row_weights();
        self.samples
            .iter()
            .map(|sample| match sample.sigma() {
                None => [length, angle],
                Some(sigma) => [
                    sigma.length.map_or(length, f64::recip),
                    sigma.angle.map_or(angle, f64::recip),
                ],
            })
            .collect()
    }

    /// Whether the set states the σ of its sensor: as the set's `sigma`,
    /// or for every row (its lengths' σ, and its angles' where the method
    /// measures angles and the set states no `sigma_rotation`).
    pub fn states_sigma(&self) -> bool {
        let angles = self
            .method
            .data_columns()
            .contains(&DataColumn::Orientation)
            && self.sigma_rotation.is_none();
        self.sigma.is_some()
            || (!self.samples.is_empty()
                && self.samples.iter().all(|sample| {
                    sample.sigma().is_some_and(|sigma| {
                        sigma.length.is_some() && (!angles || sigma.angle.is_some())
                    })
                }))
    }
}

impl Clone for MeasurementSet {
    fn clone(&self) -> Self {
        // The samples are shared: a set's copy copies them only when it
        // changes them (`Arc::make_mut`).
        self.with_samples(self.samples.clone())
    }
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
            "q{} = {} is {} {name} = {}",
            self.joint,
            gecaro_core::Compact(self.value),
            if self.value < self.qmin {
                "below"
            } else {
                "above"
            },
            gecaro_core::Compact(bound)
        )
    }
}

/// The most measurement sets a study holds.
pub const MAX_SETS: usize = 256;

/// The most tools and stations a study names (six unknowns each).
pub const MAX_NAMED_FRAMES: usize = 64;

/// Where a study's statement breaks a rule ([`Study::statement_problem`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StudySite {
    /// The named frame [`Study::frames`]`[i]`.
    Frame(usize),
    /// A field of set [`Study::sets`]`[i]`: `sigma`, `sigma_rotation`,
    /// `tool` or `station`.
    Set(usize, &'static str),
}

/// A rule of a study's statement broken, and where.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct StudyProblem {
    /// Where.
    pub site: StudySite,
    /// What is wrong, as a sentence without the place.
    pub message: String,
}

impl StudyProblem {
    /// The message with its place in `study` (a set's label and field).
    pub fn describe(&self, study: &Study) -> String {
        match self.site {
            StudySite::Frame(_) => self.message.clone(),
            StudySite::Set(index, field) => match study.sets.get(index) {
                Some(set) => format!("{}: {field}: {}", set.label, self.message),
                None => self.message.clone(),
            },
        }
    }
}

/// One or more measurement sets calibrated together.
#[derive(Clone, Debug, Default)]
pub struct Study {
    /// The measurement sets.
    pub sets: Vec<MeasurementSet>,
    /// The named tools and stations the sets measure with, identified with
    /// the robot (see [`crate::frames`]); their unknowns are the first
    /// auxiliary unknowns.
    pub frames: Vec<NamedFrame>,
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
        samples: impl Into<Samples>,
        label: impl Into<String>,
    ) -> Self {
        Study {
            sets: vec![MeasurementSet {
                method,
                samples: samples.into(),
                sigma: None,
                sigma_rotation: None,
                sigma_source: None,
                label: label.into(),
                tool: None,
                station: None,
            }],
            frames: Vec::new(),
        }
    }

    /// The same study with its named frames stated at other poses (e.g.
    /// those an identification found, [`crate::identification::Identification::frames`]).
    ///
    /// # Panics
    /// When `frames` does not hold as many frames as the study.
    pub fn with_frames(&self, frames: Vec<NamedFrame>) -> Study {
        assert_eq!(frames.len(), self.frames.len(), "one pose per named frame");
        Study {
            sets: self.sets.clone(),
            frames,
        }
    }

    /// Unknowns of the named frames ([`FRAME_UNKNOWNS`] each), the first
    /// auxiliary unknowns.
    pub fn frame_unknowns(&self) -> usize {
        self.frames.len() * FRAME_UNKNOWNS
    }

    /// The named frames of set `set` at the auxiliary values `auxiliary`,
    /// or `None` when it names none.
    fn set_frames<'a>(
        &'a self,
        robot: &Robot,
        set: &MeasurementSet,
        auxiliary: &'a [f64],
    ) -> Option<SetFrames<'a>> {
        set.uses_named_frames().then(|| {
            SetFrames::new(
                robot,
                &self.frames,
                &auxiliary[..self.frame_unknowns()],
                set.tool,
                set.station,
                self.sets.iter().any(|set| set.tool.is_none()),
            )
        })
    }

    /// Configurations whose joint variables lie outside the joint limits, in
    /// data order (one entry per joint out of range). Configurations that do
    /// not fit the robot are left to [`Study::check`].
    pub fn limit_violations(&self, robot: &Robot) -> Vec<LimitViolation> {
        let mut violations = Vec::new();
        for set in &self.sets {
            let parts = run_parts(checked_parts(set.samples.as_slice()), |samples| {
                let mut found = Vec::new();
                let mut joints = vec![0.0; robot.joint_count()];
                for sample in samples.iter() {
                    if robot
                        .joint_positions_into(sample.motor_positions(), &mut joints)
                        .is_err()
                    {
                        continue;
                    }
                    for (index, (value, joint)) in joints.iter().zip(robot.joints()).enumerate() {
                        if *value < joint.qmin || *value > joint.qmax {
                            found.push(LimitViolation {
                                label: set.label.clone(),
                                line: sample.line(),
                                joint: index + 1,
                                value: *value,
                                qmin: joint.qmin,
                                qmax: joint.qmax,
                            });
                        }
                    }
                }
                found
            });
            violations.extend(parts.into_iter().flatten());
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
    /// quaternions, set and pair structure, a positive σ (a set's, and a
    /// row's where the data state one, only for methods whose
    /// configurations are independent).
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
        if let Some(problem) = self.statement_problem(true) {
            return Err(Error::InvalidData {
                line: None,
                message: problem.describe(self),
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
            if set.samples.is_empty() {
                return Err(invalid(None, "no configurations".into()));
            }
            // The parts' first faults, in order: the first is the set's.
            let columns = set.method.data_columns();
            run_parts(checked_parts(set.samples.as_slice()), |samples| {
                if samples.plainly_sound(robot, columns) {
                    return Ok(());
                }
                for sample in samples.iter() {
                    robot
                        .check_configuration(sample.motor_positions())
                        .map_err(|error| invalid(sample.line(), error.to_string()))?;
                    for column in columns {
                        sample
                            .check_column(*column)
                            .map_err(|message| invalid(sample.line(), message))?;
                    }
                }
                Ok(())
            })
            .into_iter()
            .collect::<Result<Vec<()>, Error>>()?;
            if set.samples.has_row_sigma() {
                if !set.method.independent_configurations() {
                    return Err(invalid(
                        None,
                        format!(
                            "the data state a σ per row, and the {} method's equations join \
                             several configurations (a set, a pair): state the set's σ instead",
                            set.method.name()
                        ),
                    ));
                }
                for sample in set.samples.iter() {
                    if let Some(sigma) = sample.sigma() {
                        sigma
                            .check()
                            .map_err(|message| invalid(sample.line(), message))?;
                    }
                }
            }
            set.method
                .check_samples(set.samples.as_slice())
                .map_err(|error| match error {
                    Error::InvalidData { line, message } => invalid(line, message),
                    other => other,
                })?;
        }
        Ok(())
    }

    /// The first rule of a study's statement it breaks, or `None`: a
    /// positive finite σ per set; named frames with distinct names and
    /// finite poses within [`gecaro_core::MAX_MAGNITUDE`] of their parent
    /// frame; tools and stations named where they belong, on methods that
    /// measure the tool in a measurement frame (position and frame measure);
    /// and, when the study is `complete`, every named frame measured by some
    /// set. Every front end's study (a study file, a request's
    /// [`StudySpec`](https://docs.rs/gecaro-io), Python's `Study`) meets
    /// these rules here; a front end names the place from
    /// [`StudyProblem::site`].
    pub fn statement_problem(&self, complete: bool) -> Option<StudyProblem> {
        let problem = |site: StudySite, message: String| Some(StudyProblem { site, message });
        if self.sets.len() > MAX_SETS {
            return problem(
                StudySite::Set(MAX_SETS, "method"),
                format!(
                    "{} measurement sets: a study holds at most {MAX_SETS}",
                    self.sets.len()
                ),
            );
        }
        if self.frames.len() > MAX_NAMED_FRAMES {
            return problem(
                StudySite::Frame(MAX_NAMED_FRAMES),
                format!(
                    "{} tools and stations: a study names at most {MAX_NAMED_FRAMES} ({} unknowns)",
                    self.frames.len(),
                    MAX_NAMED_FRAMES * FRAME_UNKNOWNS
                ),
            );
        }
        for (index, set) in self.sets.iter().enumerate() {
            for (field, sigma) in [("sigma", set.sigma), ("sigma_rotation", set.sigma_rotation)] {
                if let Some(sigma) = sigma
                    && !(sigma.is_finite() && sigma > 0.0)
                {
                    return problem(
                        StudySite::Set(index, field),
                        format!("must be a positive standard deviation, not {sigma}"),
                    );
                }
            }
        }
        for (index, frame) in self.frames.iter().enumerate() {
            let site = StudySite::Frame(index);
            let what = format!("{} `{}`", frame.role.as_str(), frame.name);
            if self.frames[..index].iter().any(|f| f.name == frame.name) {
                return problem(
                    site,
                    format!("two tools or stations are named `{}`", frame.name),
                );
            }
            if !frame.pose.to_homogeneous().iter().all(|v| v.is_finite()) {
                return problem(site, format!("{what} has a non-finite pose"));
            }
            let distance = frame.pose.translation.vector.norm();
            if distance > gecaro_core::MAX_MAGNITUDE {
                return problem(
                    site,
                    format!(
                        "{what} is stated {} m from its parent frame (at most {} m)",
                        gecaro_core::Compact(distance),
                        gecaro_core::MAX_MAGNITUDE
                    ),
                );
            }
            if complete
                && !self
                    .sets
                    .iter()
                    .any(|set| set.tool == Some(index) || set.station == Some(index))
            {
                return problem(
                    site,
                    format!(
                        "{what} is measured by no measurement set (name it with {} = {:?})",
                        frame.role.as_str(),
                        frame.name
                    ),
                );
            }
        }
        for (set_index, set) in self.sets.iter().enumerate() {
            for (used, role) in [
                (set.tool, FrameRole::Tool),
                (set.station, FrameRole::Station),
            ] {
                let Some(index) = used else { continue };
                let site = StudySite::Set(set_index, role.as_str());
                let Some(frame) = self.frames.get(index) else {
                    return problem(
                        site,
                        format!(
                            "names {} {index}, and the study has {} named frames",
                            role.as_str(),
                            self.frames.len()
                        ),
                    );
                };
                if frame.role != role {
                    return problem(
                        site,
                        format!(
                            "`{}` is a {}, not a {}",
                            frame.name,
                            frame.role.as_str(),
                            role.as_str()
                        ),
                    );
                }
                if !set.method.data_columns().contains(&DataColumn::Position) {
                    return problem(
                        site,
                        format!(
                            "the {} method measures no pose in a measurement frame; tools and \
                             stations go with position and frame measures",
                            set.method.name()
                        ),
                    );
                }
            }
        }
        None
    }

    /// The index of the named frame `name` of `role`.
    ///
    /// # Errors
    /// A sentence naming what is missing.
    pub fn frame_index(&self, name: &str, role: FrameRole) -> Result<usize, String> {
        self.frames
            .iter()
            .position(|frame| frame.name == name && frame.role == role)
            .ok_or_else(
                || match self.frames.iter().find(|frame| frame.name == name) {
                    Some(frame) => format!(
                        "`{name}` is a {}, not a {}",
                        frame.role.as_str(),
                        role.as_str()
                    ),
                    None => format!("no {} named `{name}` in this study", role.as_str()),
                },
            )
    }

    /// One sentence on the data's joint values outside the joint limits
    /// (how many, and the first), or `None` when all are within them.
    pub fn limit_summary(&self, robot: &Robot) -> Option<String> {
        let violations = self.limit_violations(robot);
        let first = violations.first()?;
        Some(format!(
            "{} joint value{} outside the joint limits; first: {first}",
            violations.len(),
            if violations.len() == 1 {
                " is"
            } else {
                "s are"
            },
        ))
    }

    /// Names of all auxiliary unknowns, prefixed by the set's method when the study has several sets.
    /// The named frames' unknowns come first, as `name.x` … `name.rz`.
    pub fn auxiliary_names(&self) -> Vec<String> {
        let frames = self.frames.iter().flat_map(|frame| {
            UNKNOWN_NAMES
                .iter()
                .map(move |unknown| format!("{}.{unknown}", frame.name))
        });
        frames
            .chain(self.sets.iter().enumerate().flat_map(|(index, set)| {
                let prefix = if self.sets.len() > 1 {
                    format!("{}[{}].", set.method.name(), index + 1)
                } else {
                    String::new()
                };
                set.method
                    .auxiliary_names()
                    .into_iter()
                    .map(move |name| format!("{prefix}{name}"))
            }))
            .collect()
    }

    /// The study without some samples: `dropped[s]` lists sample indices of
    /// set `s` (sets beyond `dropped` keep everything). A set or pair left
    /// with a single configuration goes too: it constrains nothing (link and
    /// distance methods compare configurations with each other).
    pub fn without_samples(&self, dropped: &[Vec<usize>]) -> Study {
        let sets = self
            .sets
            .iter()
            .enumerate()
            .map(|(index, set)| {
                let mut keep = vec![true; set.samples.len()];
                for &sample in dropped.get(index).map_or(&[][..], Vec::as_slice) {
                    if let Some(kept) = keep.get_mut(sample) {
                        *kept = false;
                    }
                }
                for unit in units(set.method.as_ref(), set.samples.as_slice()) {
                    let kept: Vec<usize> = unit.iter().copied().filter(|i| keep[*i]).collect();
                    if unit.len() > 1 && kept.len() < 2 {
                        kept.into_iter().for_each(|i| keep[i] = false);
                    }
                }
                let kept: Vec<usize> = (0..keep.len()).filter(|i| keep[*i]).collect();
                set.with_samples(set.samples.gather(&kept))
            })
            .collect();
        Study {
            sets,
            frames: self.frames.clone(),
        }
    }

    /// Whether some set measures a length (position, frame, distance), so that
    /// the robot's scale is observable; link and plane methods alone cannot see it.
    pub fn observes_scale(&self) -> bool {
        self.sets.iter().any(|set| !set.method.scale_invariant())
    }

    /// Whether this study's systems are streamed (folded as they are
    /// written; docs/methods.md, "Streamed systems") from `streamed_rows`
    /// rows on: every set's configurations independent (written block by
    /// block) and at least that many rows.
    pub fn is_streamed(&self, streamed_rows: usize) -> bool {
        self.foldable() && self.row_count() >= streamed_rows
    }

    /// Whether every set's rows can be folded as they are written: its
    /// configurations are independent.
    fn foldable(&self) -> bool {
        self.sets
            .iter()
            .all(|set| set.method.independent_configurations())
    }

    /// Total rows of W.
    pub fn row_count(&self) -> usize {
        self.sets
            .iter()
            .map(|set| set.method.row_count(set.samples.as_slice()))
            .sum()
    }

    /// Independent equations: rows minus those used up by centring.
    pub fn equation_count(&self) -> usize {
        self.sets
            .iter()
            .map(|set| {
                set.method
                    .row_count(set.samples.as_slice())
                    .saturating_sub(set.method.dependent_rows(set.samples.as_slice()))
            })
            .sum()
    }

    /// Evaluates the pose and Jacobian (the rows its method reads) of every
    /// sample at the robot's parameters, and at the named frames' unknowns
    /// in `auxiliary` (their states are those of the measured poses,
    /// [`crate::frames`]).
    ///
    /// # Errors
    /// When a configuration does not fit the robot.
    pub fn evaluate(
        &self,
        robot: &Robot,
        auxiliary: &[f64],
        states: &mut StudyStates,
    ) -> Result<(), Error> {
        states.states.resize_with(self.sets.len(), Vec::new);
        for (set, buffer) in self.sets.iter().zip(&mut states.states) {
            self.evaluate_set(robot, set, auxiliary, buffer)?;
        }
        Ok(())
    }

    /// The states of one set (see [`evaluate`](Self::evaluate)).
    fn evaluate_set(
        &self,
        robot: &Robot,
        set: &MeasurementSet,
        auxiliary: &[f64],
        buffer: &mut Vec<TerminalState>,
    ) -> Result<(), Error> {
        let rows = set.method.jacobian_rows();
        match self.set_frames(robot, set, auxiliary) {
            None => evaluate_states(robot, set.samples.as_slice(), rows, buffer)?,
            Some(frames) => {
                // A tool moves the point with the flange's rotation: all six rows.
                evaluate_states(robot, set.samples.as_slice(), JacobianRows::Full, buffer)?;
                for state in buffer.iter_mut() {
                    frames.apply(state, rows.count());
                }
            }
        }
        Ok(())
    }

    /// Evaluates the pose (no Jacobian) of every sample at the robot's
    /// parameters, for the sets whose method uses them
    /// ([`CalibrationMethod::uses_starting_poses`]; the others get no
    /// states): enough for [`initial_auxiliary`](Self::initial_auxiliary) and
    /// for random data like these; [`linearise`](Self::linearise) evaluates
    /// the Jacobians it needs.
    ///
    /// # Errors
    /// When a configuration does not fit the robot.
    pub fn evaluate_poses(&self, robot: &Robot, states: &mut StudyStates) -> Result<(), Error> {
        states.states.resize_with(self.sets.len(), Vec::new);
        for (set, buffer) in self.sets.iter().zip(&mut states.states) {
            if set.method.uses_starting_poses() {
                evaluate_poses(robot, set.samples.as_slice(), buffer)?;
            } else {
                buffer.clear();
            }
        }
        Ok(())
    }

    /// Initial auxiliary values of every set, from states at the starting parameters.
    ///
    /// # Errors
    /// When a method cannot initialise its unknowns from these data.
    pub fn initial_auxiliary(&self, states: &StudyStates) -> Result<Vec<f64>, Error> {
        let mut values: Vec<f64> = self
            .frames
            .iter()
            .flat_map(NamedFrame::initial_values)
            .collect();
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
        self.write_sets(auxiliary, layout, system, |index, set, own, writer| {
            Ok(write_rows(
                writer,
                set.method.as_ref(),
                set.samples.as_slice(),
                states.set(index),
                own,
            ))
        })
        .expect("writing evaluated states cannot fail");
    }

    /// [`evaluate`](Self::evaluate) at `robot` then [`assemble`](Self::assemble),
    /// with the same result, bit for bit; sets whose configurations are
    /// independent ([`CalibrationMethod::independent_configurations`]) are
    /// evaluated and written block by block, in parallel, without keeping
    /// their states (`states` holds those of the other sets afterwards).
    ///
    /// # Errors
    /// When a configuration does not fit the robot.
    pub fn linearise(
        &self,
        robot: &Robot,
        auxiliary: &[f64],
        layout: &ColumnLayout,
        states: &mut StudyStates,
        system: &mut ObservationSystem,
    ) -> Result<(), Error> {
        let model = KinematicModel::new(robot);
        states.states.resize_with(self.sets.len(), Vec::new);
        self.write_sets(auxiliary, layout, system, |index, set, own, writer| {
            if set.method.independent_configurations() {
                return Ok(linearise_independent(
                    &model,
                    set.method.as_ref(),
                    set.samples.as_slice(),
                    own,
                    self.set_frames(robot, set, auxiliary).as_ref(),
                    writer,
                )?);
            }
            let buffer = &mut states.states[index];
            self.evaluate_set(robot, set, auxiliary, buffer)?;
            Ok(write_rows(
                writer,
                set.method.as_ref(),
                set.samples.as_slice(),
                buffer,
                own,
            ))
        })
    }

    /// Sizes `system` and hands each set's rows to `write`, with the set's
    /// own auxiliary values and its row weights (1/σ); `write` returns the
    /// end of the observations it wrote.
    fn write_sets(
        &self,
        auxiliary: &[f64],
        layout: &ColumnLayout,
        system: &mut ObservationSystem,
        mut write: impl FnMut(usize, &MeasurementSet, &[f64], RowWriter<'_>) -> Result<usize, Error>,
    ) -> Result<(), Error> {
        system.reset(self.row_count(), layout, self.foldable());
        let mut first_row = 0;
        let mut auxiliary_offset = self.frame_unknowns();
        for (index, set) in self.sets.iter().enumerate() {
            let rows = set.method.row_count(set.samples.as_slice());
            let count = set.method.auxiliary_names().len();
            let own = &auxiliary[auxiliary_offset..auxiliary_offset + count];
            let weights = (set.row_weights(), set.observation_sensors());
            let writer = system.writer(layout, first_row, rows, auxiliary_offset, weights);
            let end = write(index, set, own, writer)?;
            system.record_observations(end);
            system.record_set(first_row..first_row + rows, set.row_weights());
            first_row += rows;
            auxiliary_offset += count;
        }
        Ok(())
    }
}

/// Below this many samples, a set is checked on one thread (a thread's
/// start costs about what checking a few thousand samples does).
const PARALLEL_CHECKS: usize = 16_384;

/// `samples` in the parts that [`Study::check`] and
/// [`Study::limit_violations`] read on all cores: one part for a small set.
fn checked_parts(samples: SampleSlice<'_>) -> Vec<SampleSlice<'_>> {
    let size = if samples.len() < PARALLEL_CHECKS {
        samples.len().max(1)
    } else {
        part_size(samples.len())
    };
    samples.chunks(size).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::method::MethodOptions;
    use crate::methods::METHODS;
    use crate::progress::Quiet;
    use crate::rows::RowKind;
    use crate::simulation::{Sampler, perturbed_robot, simulate_measurements};
    use crate::table2::default_plane;

    /// Everything a system holds, as bits.
    fn fingerprint(system: &ObservationSystem) -> (Vec<u64>, Vec<u64>, Vec<RowKind>, Vec<u64>) {
        let bits = |values: &[f64]| values.iter().map(|v| v.to_bits()).collect::<Vec<u64>>();
        let errors: Vec<f64> = system
            .observation_errors()
            .iter()
            .flat_map(|(length, angle)| [length, angle])
            .collect();
        (
            bits(system.matrix()),
            bits(&system.weighted_residuals()),
            system.kinds().to_vec(),
            bits(&errors),
        )
    }

    fn two_phase(
        study: &Study,
        robot: &Robot,
        auxiliary: &[f64],
        layout: &ColumnLayout,
    ) -> ObservationSystem {
        let mut states = StudyStates::default();
        study
            .evaluate(robot, auxiliary, &mut states)
            .expect("states");
        let mut system = ObservationSystem::default();
        study.assemble(&states, auxiliary, layout, &mut system);
        system
    }

    /// A large set is checked in parts on all cores, and says what one pass
    /// would: its first fault (the lowest line, though a later part holds
    /// another), and every joint value beyond its limits, in line order.
    #[test]
    fn large_sets_are_checked_in_parts_in_line_order() {
        let robot = Robot::template("arm", "RRPRRR").expect("template");
        let mut sampler = Sampler::new(7);
        let count = 3 * PARALLEL_CHECKS;
        let mut outside = Vec::new();
        let samples: Vec<Sample> = (0..count)
            .map(|index| {
                let mut configuration = sampler.configuration(&robot);
                // Joint 2 beyond its upper limit, here and there.
                if index % 3001 == 17 {
                    configuration[1] = robot.joints()[1].qmax + 0.5;
                    outside.push(index + 2);
                }
                Sample {
                    position: Some(nalgebra::Vector3::new(0.1, 0.2, 0.3)),
                    line: Some(index + 2),
                    ..Sample::new(configuration)
                }
            })
            .collect();
        let position =
            crate::methods::method("position", &MethodOptions::default()).expect("position");
        let mut study = Study {
            sets: vec![MeasurementSet {
                method: position,
                samples: samples.clone().into(),
                sigma: Some(1e-5),
                sigma_rotation: None,
                sigma_source: None,
                label: "data.csv".into(),
                tool: None,
                station: None,
            }],
            frames: Vec::new(),
        };
        assert!(checked_parts(study.sets[0].samples.as_slice()).len() > 2);
        study.check(&robot).expect("valid");
        let lines: Vec<Option<usize>> = study
            .limit_violations(&robot)
            .iter()
            .map(|violation| violation.line)
            .collect();
        assert_eq!(
            lines,
            outside.iter().map(|line| Some(*line)).collect::<Vec<_>>()
        );
        assert!(outside.len() > 10);
        // Two faults in different parts: the first line is named.
        let mut faulty = samples;
        faulty[count - 10].position = None;
        faulty[count / 2].motor_positions[3] = f64::NAN;
        study.sets[0].samples = faulty.into();
        let message = study.check(&robot).expect_err("faults").to_string();
        assert!(
            message.contains(&format!("data.csv:{}:", count / 2 + 2)),
            "{message}"
        );
    }

    /// The fused, blocked and parallel route writes exactly what evaluation
    /// followed by assembly writes: every method, small sets, and large
    /// independent sets (several threads, a partial last block), stacked
    /// with another set so that observations are numbered across sets. The
    /// layout keeps every other parameter, backwards (gains without their
    /// joints' columns among them), so the fused route's states, which
    /// hold only the kept columns (`KinematicModel::selecting`), are
    /// written through another map than the whole states.
    #[test]
    fn fused_linearisation_is_bit_identical_to_evaluate_then_assemble() {
        let nominal = Robot::template("arm", "RRPRRR").expect("template");
        let mut sampler = Sampler::new(5);
        let real = perturbed_robot(&nominal, 1.0, &mut sampler).expect("real");
        let options = MethodOptions {
            plane: Some(default_plane(&nominal).expect("plane")),
            plane_unknown: true,
            ..MethodOptions::default()
        };
        let parameters: Vec<usize> = (0..nominal.parameters().len()).rev().step_by(2).collect();
        for info in METHODS {
            let method = info.build(&options).expect("method");
            let large = method.independent_configurations();
            let count = if large { 2 * 1024 + 45 } else { 12 };
            let samples = if info.name == "plane1" {
                // No measured columns: random configurations will do.
                (0..count)
                    .map(|_| Sample::new(sampler.configuration(&nominal)))
                    .collect()
            } else {
                simulate_measurements(
                    &real,
                    method.as_ref(),
                    count,
                    1e-4,
                    &mut sampler,
                    &mut Quiet,
                )
                .expect("data")
            };
            let position = crate::methods::method("position", &options).expect("position");
            let study = Study {
                sets: vec![
                    MeasurementSet {
                        method: position.clone_method(),
                        samples: simulate_measurements(
                            &real,
                            position.as_ref(),
                            3,
                            0.0,
                            &mut sampler,
                            &mut Quiet,
                        )
                        .expect("data")
                        .into(),
                        sigma: Some(1e-3),
                        sigma_rotation: None,
                        sigma_source: None,
                        label: "first".into(),
                        // A reflector seen from a station: states with
                        // the frames' columns, on the fused route too.
                        tool: Some(0),
                        station: Some(1),
                    },
                    MeasurementSet {
                        method,
                        samples: samples.into(),
                        sigma: Some(2e-4),
                        sigma_rotation: Some(1e-3),
                        sigma_source: None,
                        label: info.name.into(),
                        tool: None,
                        station: None,
                    },
                ],
                frames: vec![
                    NamedFrame {
                        name: "smr".into(),
                        role: FrameRole::Tool,
                        pose: nalgebra::IsometryMatrix3::translation(0.03, -0.02, 0.08),
                    },
                    NamedFrame {
                        name: "tracker".into(),
                        role: FrameRole::Station,
                        pose: nalgebra::IsometryMatrix3::new(
                            nalgebra::Vector3::new(2.0, 0.5, 0.3),
                            nalgebra::Vector3::new(0.0, 0.1, 0.7),
                        ),
                    },
                ],
            };
            let mut states = StudyStates::default();
            study.evaluate_poses(&nominal, &mut states).expect("states");
            let auxiliary = study.initial_auxiliary(&states).expect("auxiliary");
            let layout =
                ColumnLayout::new(nominal.parameters().len(), &parameters, auxiliary.len());
            let expected = two_phase(&study, &nominal, &auxiliary, &layout);
            let mut fused = ObservationSystem::default();
            // Storage from a different study must not leak into the result.
            let mut recycled = StudyStates::default();
            let junk = two_phase(&study, &real, &auxiliary, &layout);
            fused.clone_from(&junk);
            study
                .linearise(&nominal, &auxiliary, &layout, &mut recycled, &mut fused)
                .expect("fused");
            assert_eq!(fingerprint(&fused), fingerprint(&expected), "{}", info.name);
            assert_eq!(
                fused.observation_errors().len(),
                3 + if info.name == "distance" { 6 } else { count }
            );
        }
    }
}
