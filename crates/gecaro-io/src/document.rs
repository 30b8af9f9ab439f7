//! The robot file as a plain document, shared by the TOML files and the JSON
//! API of the web page, and its conversion to a validated [`Robot`].
//!
//! A document holds the values as written (angles in the document's unit,
//! omitted keys as `None`). [`RobotDocument::to_robot_file`] applies the
//! defaults, converts degrees, refuses likely degree/radian mix-ups, and
//! checks every rule of the model; each error carries the [`Location`] of the
//! key at fault, which the TOML reader turns into a line and the web page into
//! a highlighted cell.

use std::f64::consts::TAU;

use gecaro_core::{
    Frame, FrameType, Joint, JointRegion, LinkMass, MassModel, PriorityMatrix, Robot, RobotSpec,
    upright_gravity,
};
use nalgebra::{DMatrix, IsometryMatrix3, Translation3, Vector3};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

use crate::problem::{DocumentError, Location, model_error};
use crate::robot_file::{AngleUnit, IdentifiedTool, RobotFile};
use crate::urdf::names::UrdfDocument;

/// A robot file's content (see the robot file format in the README).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RobotDocument {
    /// The robot's name.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
    /// Free text.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub description: Option<String>,
    /// `rad` (default) or `deg`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub angle_unit: Option<String>,
    /// Frames 0..n+1.
    #[serde(default)]
    pub frame: Vec<FrameDocument>,
    /// Coupling matrices of eq. 4.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub coupling: Option<CouplingDocument>,
    /// A priority matrix overriding the defaults.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub priority: Option<PriorityDocument>,
    /// Names kept from an imported URDF.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub urdf: Option<UrdfDocument>,
    /// Gravity in the world frame (m/s²); standard gravity along −z when
    /// omitted (the loads of elastic joints: [`MassModel`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub gravity: Option<[f64; 3]>,
    /// `false` when the calibration that made the robot did not observe
    /// frame n+1 (every set measured a named tool); `true` when omitted.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tool_frame_observed: Option<bool>,
    /// Tools identified with the robot, by name: their poses in frame n+1.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub tools: BTreeMap<String, ToolDocument>,
}

/// A `[tools.NAME]` table: a tool's pose in the robot's frame n+1.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ToolDocument {
    /// Its origin (m).
    pub position: [f64; 3],
    /// Its orientation, `[w, x, y, z]`; none when omitted.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub quaternion: Option<[f64; 4]>,
}

impl ToolDocument {
    fn of(pose: &IsometryMatrix3<f64>) -> Self {
        let [x, y, z, w, i, j, k] = crate::pose::to_seven(pose);
        ToolDocument {
            position: [x, y, z],
            quaternion: Some([w, i, j, k]),
        }
    }

    fn read(&self, name: &str) -> Result<IdentifiedTool, DocumentError> {
        let at = |message: String| {
            DocumentError::new(
                Location::Key {
                    key: format!("tools.{name}"),
                },
                message,
            )
        };
        if name.trim().is_empty() {
            return Err(at("a tool needs a name".into()));
        }
        if !self
            .position
            .iter()
            .all(|v| v.is_finite() && v.abs() <= gecaro_core::MAX_MAGNITUDE)
        {
            return Err(at(format!(
                "position {:?} is not a point in metres",
                self.position
            )));
        }
        let rotation = match self.quaternion {
            None => nalgebra::Rotation3::identity(),
            Some([w, x, y, z]) => crate::pose::unit_quaternion(w, x, y, z)
                .map_err(|message| at(format!("quaternion: {message}")))?
                .to_rotation_matrix(),
        };
        let [x, y, z] = self.position;
        Ok(IdentifiedTool {
            name: name.to_owned(),
            pose: IsometryMatrix3::from_parts(Translation3::new(x, y, z), rotation),
        })
    }
}

/// One frame as written; omitted keys take their defaults.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
#[allow(missing_docs)]
pub struct FrameDocument {
    pub sigma: Option<i64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub alpha: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub d: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub theta: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub r: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub beta: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub qmin: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub qmax: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub offset: Option<f64>,
    #[serde(rename = "K", default, skip_serializing_if = "Option::is_none")]
    pub gain: Option<f64>,
    /// The mass (kg) of the body that moves with this frame: link j, the
    /// base (frame 0) or the tool (frame n+1).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mass: Option<f64>,
    /// Its centre of mass in this frame's coordinates (m); the frame's origin
    /// when omitted.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub com: Option<[f64; 3]>,
    /// The joint's compliance (rad/(N·m), or m/N for a prismatic joint,
    /// whatever the file's angle unit): stated on any joint, it makes the
    /// robot elastic, the other joints at 0 (issue 38).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub compliance: Option<f64>,
    /// The range of the joint variable a calibration's data covered
    /// (`[min, max]`, in the unit of `qmin`, `qmax`): outside it the
    /// calibrated model is extrapolated. Written by an identification whose
    /// result holds in the measured region only.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub measured: Option<[f64; 2]>,
}

/// The `[coupling]` table.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
#[allow(non_snake_case, missing_docs)]
pub struct CouplingDocument {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub Cm: Option<Vec<Vec<f64>>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub Cj: Option<Vec<Vec<f64>>>,
}

/// The `[priority]` table.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PriorityDocument {
    /// (n+2) rows of `[alpha, d, theta, r, beta, K]`.
    pub matrix: Vec<Vec<i64>>,
}

impl RobotDocument {
    /// The document of a robot file (every key written out, in the file's angle unit).
    pub fn from_robot_file(file: &RobotFile) -> Self {
        let robot = &file.robot;
        let unit = file.angle_unit;
        let angle = |value: f64| match unit {
            AngleUnit::Radians => value,
            AngleUnit::Degrees => value.to_degrees(),
        };
        let last = robot.frames().len() - 1;
        let frame = robot
            .frames()
            .iter()
            .enumerate()
            .map(|(j, frame)| {
                let joint = (j >= 1 && j < last).then(|| robot.joints()[j - 1]);
                let joint_angle = |value: f64| {
                    if frame.frame_type == FrameType::Revolute {
                        angle(value)
                    } else {
                        value
                    }
                };
                FrameDocument {
                    sigma: Some(i64::from(frame.frame_type.sigma())),
                    alpha: (j != 0).then(|| angle(frame.alpha)),
                    d: (j != 0).then_some(frame.d),
                    theta: Some(angle(frame.theta)),
                    r: Some(frame.r),
                    beta: (j != 0).then(|| angle(frame.beta)),
                    qmin: joint.map(|joint| joint_angle(joint.qmin)),
                    qmax: joint.map(|joint| joint_angle(joint.qmax)),
                    offset: joint.map(|joint| joint_angle(joint.offset)),
                    gain: joint.map(|joint| joint.gain),
                    mass: file.masses.link(j).map(|link| link.mass),
                    com: file.masses.link(j).map(|link| link.com.into()),
                    compliance: robot
                        .compliances()
                        .filter(|_| joint.is_some())
                        .map(|compliances| compliances[j - 1]),
                    measured: file
                        .measured_region
                        .as_ref()
                        .filter(|_| joint.is_some())
                        .map(|region| {
                            let (min, max) = region.range(j - 1);
                            [joint_angle(min), joint_angle(max)]
                        }),
                }
            })
            .collect();
        let n = robot.joint_count();
        let identity = DMatrix::<f64>::identity(n, n);
        let rows = |matrix: &DMatrix<f64>| {
            matrix
                .row_iter()
                .map(|row| row.iter().copied().collect())
                .collect()
        };
        let coupling = (*robot.motor_coupling() != identity || *robot.joint_coupling() != identity)
            .then(|| CouplingDocument {
                Cm: Some(rows(robot.motor_coupling())),
                Cj: Some(rows(robot.joint_coupling())),
            });
        let priority = robot.priority_override().map(|priority| PriorityDocument {
            matrix: priority
                .rows()
                .iter()
                .map(|row| row.iter().map(|p| i64::from(*p)).collect())
                .collect(),
        });
        RobotDocument {
            name: Some(robot.name().to_owned()),
            description: file.description.clone(),
            angle_unit: (unit == AngleUnit::Degrees).then(|| "deg".to_owned()),
            frame,
            coupling,
            priority,
            urdf: file.urdf.as_ref().map(UrdfDocument::from_names),
            gravity: Some(file.stated_gravity())
                .filter(|gravity| *gravity != upright_gravity())
                .map(Into::into),
            tool_frame_observed: (!file.tool_frame_observed).then_some(false),
            tools: file
                .tools
                .iter()
                .map(|tool| (tool.name.clone(), ToolDocument::of(&tool.pose)))
                .collect(),
        }
    }

    /// Every problem of the document: those of each frame on its own, then,
    /// when the frames are fine, the first problem of the whole (joint count,
    /// coupling, priority). Empty for a valid document.
    pub fn problems(&self) -> Vec<DocumentError> {
        let mut problems = Vec::new();
        if let Err(problem) = self.angle_unit() {
            problems.push(problem);
        }
        let unit = self.angle_unit().unwrap_or(AngleUnit::Radians);
        let last = self.frame.len().saturating_sub(1);
        for (index, frame) in self.frame.iter().enumerate() {
            if let Err(problem) = frame.read(index, last, unit) {
                problems.push(problem);
            }
        }
        if problems.is_empty()
            && let Err(problem) = self.to_robot_file("robot")
        {
            problems.push(problem);
        }
        problems
    }

    fn angle_unit(&self) -> Result<AngleUnit, DocumentError> {
        match self.angle_unit.as_deref() {
            None => Ok(AngleUnit::Radians),
            Some(name) => AngleUnit::parse(name).map_err(|message| {
                DocumentError::new(
                    Location::Key {
                        key: "angle_unit".into(),
                    },
                    message,
                )
            }),
        }
    }

    /// The validated robot file (see the module docs); `fallback_name` names
    /// a document without a name.
    ///
    /// # Errors
    /// The first problem found, with its location.
    pub fn to_robot_file(&self, fallback_name: &str) -> Result<RobotFile, DocumentError> {
        let angle_unit = self.angle_unit()?;
        if self.frame.is_empty() {
            return Err(DocumentError::new(
                Location::Document,
                "no [[frame]] tables: a robot needs frames 0..n+1 (base, joints, end-effector)",
            ));
        }
        let last = self.frame.len() - 1;
        let mut frames = Vec::with_capacity(self.frame.len());
        let mut joints = Vec::new();
        for (index, document) in self.frame.iter().enumerate() {
            let (frame, joint) = document.read(index, last, angle_unit)?;
            frames.push(frame);
            joints.extend(joint);
        }
        let (motor_coupling, joint_coupling) = match &self.coupling {
            None => (None, None),
            Some(coupling) => (
                read_matrix("Cm", coupling.Cm.as_ref())?,
                read_matrix("Cj", coupling.Cj.as_ref())?,
            ),
        };
        let priority = self
            .priority
            .as_ref()
            .map(PriorityDocument::read)
            .transpose()?;
        let robot = Robot::new(RobotSpec {
            name: self
                .name
                .clone()
                .unwrap_or_else(|| fallback_name.to_owned()),
            frames,
            joints,
            motor_coupling,
            joint_coupling,
            priority,
            compliances: self.compliances()?,
        })
        .map_err(model_error)?;
        let urdf = self
            .urdf
            .as_ref()
            .map(|urdf| urdf.read(robot.joint_count()))
            .transpose()?;
        let masses = self.masses()?;
        let measured_region = self.measured_region(&robot, angle_unit)?;
        let tools = self
            .tools
            .iter()
            .map(|(name, tool)| tool.read(name))
            .collect::<Result<_, _>>()?;
        Ok(RobotFile {
            robot,
            description: self.description.clone(),
            angle_unit,
            urdf,
            masses,
            measured_region,
            tools,
            tool_frame_observed: self.tool_frame_observed.unwrap_or(true),
        })
    }

    /// The region a calibration's data covered, when any joint states its
    /// `measured` range (a joint that does not is unrestricted: its limits).
    fn measured_region(
        &self,
        robot: &Robot,
        unit: AngleUnit,
    ) -> Result<Option<JointRegion>, DocumentError> {
        if self.frame.iter().all(|frame| frame.measured.is_none()) {
            return Ok(None);
        }
        let mut ranges = Vec::with_capacity(robot.joint_count());
        for (j, joint) in robot.joints().iter().enumerate() {
            let index = j + 1;
            let at = |message: String| frame_error(index, "measured", message);
            let Some([min, max]) = self.frame[index].measured else {
                ranges.push((joint.qmin, joint.qmax));
                continue;
            };
            if !(min.is_finite() && max.is_finite()) || min > max {
                return Err(at(format!(
                    "[{min}, {max}] is no range: two finite numbers, the smaller first"
                )));
            }
            let convert = |value: f64| match (robot.frames()[index].frame_type, unit) {
                (FrameType::Revolute, AngleUnit::Degrees) => value.to_radians(),
                _ => value,
            };
            ranges.push((convert(min), convert(max)));
        }
        if let Some(index) = [0, self.frame.len() - 1]
            .into_iter()
            .find(|index| self.frame[*index].measured.is_some())
        {
            return Err(frame_error(
                index,
                "measured",
                format!("frame {index} is fixed and has no joint, so no measured range"),
            ));
        }
        JointRegion::new(ranges)
            .map(Some)
            .map_err(|(joint, message)| frame_error(joint, "measured", message))
    }

    /// The joints' compliances when any frame states one (then the robot is
    /// elastic; the others are 0).
    fn compliances(&self) -> Result<Option<Vec<f64>>, DocumentError> {
        let last = self.frame.len().saturating_sub(1);
        if let Some(index) = self
            .frame
            .iter()
            .enumerate()
            .find(|(index, frame)| (*index == 0 || *index == last) && frame.compliance.is_some())
            .map(|(index, _)| index)
        {
            return Err(frame_error(
                index,
                "compliance",
                "a fixed frame has no joint to be compliant".into(),
            ));
        }
        if self.frame.iter().all(|frame| frame.compliance.is_none()) {
            return Ok(None);
        }
        Ok(Some(
            self.frame[1..last]
                .iter()
                .map(|frame| frame.compliance.unwrap_or(0.0))
                .collect(),
        ))
    }

    /// The masses the frames state, and gravity.
    fn masses(&self) -> Result<MassModel, DocumentError> {
        let mut masses = MassModel::new(self.frame.len());
        for (index, frame) in self.frame.iter().enumerate() {
            let at = |key: &str, message: String| frame_error(index, key, message);
            let mass = match (frame.mass, frame.com) {
                (None, None) => continue,
                (None, Some(_)) => {
                    return Err(at("com", "a centre of mass without its `mass` (kg)".into()));
                }
                (Some(mass), com) => LinkMass {
                    mass,
                    com: com.map_or_else(Vector3::zeros, Vector3::from),
                },
            };
            masses.set_link(index, mass).map_err(model_error)?;
        }
        if let Some(gravity) = self.gravity {
            masses
                .set_gravity(Vector3::from(gravity))
                .map_err(model_error)?;
        }
        Ok(masses)
    }
}

impl FrameDocument {
    fn read(
        &self,
        index: usize,
        last: usize,
        unit: AngleUnit,
    ) -> Result<(Frame, Option<Joint>), DocumentError> {
        let at = |key: &str, message: String| frame_error(index, key, message);
        let sigma = self.sigma.ok_or_else(|| {
            at(
                "sigma",
                "every frame needs `sigma` (0 revolute, 1 prismatic, 2 fixed)".into(),
            )
        })?;
        let frame_type = FrameType::from_sigma(sigma).ok_or_else(|| {
            at(
                "sigma",
                format!("sigma = {sigma} is not a frame type: 0 revolute, 1 prismatic, 2 fixed"),
            )
        })?;
        // `is_angle`: converted from the file's angle unit; angles other than
        // joint limits and offsets (values of the joint variable, which may
        // span several turns: ABB axis 6 turns ±400°, a mimic's offset) are
        // also held within a turn, which catches degrees written in a
        // radians file.
        let value = |key: &str,
                     given: Option<f64>,
                     default: f64,
                     is_angle: bool|
         -> Result<f64, DocumentError> {
            let Some(given) = given else {
                return Ok(default);
            };
            if !given.is_finite() {
                return Err(at(key, format!("{given} is not a finite number")));
            }
            if !is_angle {
                return Ok(given);
            }
            match unit {
                AngleUnit::Degrees => Ok(given.to_radians()),
                AngleUnit::Radians
                    if given.abs() > TAU + 1e-9 && !matches!(key, "qmin" | "qmax" | "offset") =>
                {
                    Err(at(
                        key,
                        format!(
                            "{} rad is more than a full turn; the file's angles are in radians \
                         — if it is written in degrees, add angle_unit = \"deg\" at the top",
                            gecaro_core::Compact(given)
                        ),
                    ))
                }
                AngleUnit::Radians => Ok(given),
            }
        };
        let frame = Frame {
            frame_type,
            alpha: value("alpha", self.alpha, 0.0, true)?,
            d: value("d", self.d, 0.0, false)?,
            theta: value("theta", self.theta, 0.0, true)?,
            r: value("r", self.r, 0.0, false)?,
            beta: value("beta", self.beta, 0.0, true)?,
        };
        let joint_keys = [
            ("qmin", self.qmin),
            ("qmax", self.qmax),
            ("offset", self.offset),
            ("K", self.gain),
        ];
        if index == 0 || index == last || frame_type == FrameType::Fixed {
            if let Some((key, _)) = joint_keys.iter().find(|(_, given)| given.is_some()) {
                return Err(at(
                    key,
                    format!("frame {index} is fixed (sigma = 2) and has no joint, so no `{key}`"),
                ));
            }
            return Ok((frame, None));
        }
        let defaults = Joint::default_for(frame_type);
        let revolute = frame_type == FrameType::Revolute;
        let joint = Joint {
            qmin: value("qmin", self.qmin, defaults.qmin, revolute)?,
            qmax: value("qmax", self.qmax, defaults.qmax, revolute)?,
            offset: value("offset", self.offset, defaults.offset, revolute)?,
            gain: value("K", self.gain, defaults.gain, false)?,
        };
        Ok((frame, Some(joint)))
    }
}

/// A problem of key `key` of frame `index`.
fn frame_error(index: usize, key: &str, message: String) -> DocumentError {
    DocumentError::new(
        Location::Frame {
            frame: index,
            key: key.into(),
        },
        message,
    )
}

fn read_matrix(
    name: &str,
    rows: Option<&Vec<Vec<f64>>>,
) -> Result<Option<DMatrix<f64>>, DocumentError> {
    let Some(rows) = rows else { return Ok(None) };
    let columns = rows.first().map_or(0, Vec::len);
    if let Some(row) = rows.iter().find(|row| row.len() != columns) {
        return Err(DocumentError::new(
            Location::Coupling {
                matrix: name.into(),
            },
            format!(
                "rows of different lengths ({} and {columns}): a coupling matrix is n×n",
                row.len()
            ),
        ));
    }
    Ok(Some(DMatrix::from_fn(rows.len(), columns, |i, j| {
        rows[i][j]
    })))
}

impl PriorityDocument {
    /// The matrix, with its shape and signs checked (the rest is the robot's check).
    ///
    /// # Errors
    /// A row that does not have 6 entries, or a negative entry.
    pub fn read(&self) -> Result<PriorityMatrix, DocumentError> {
        let mut rows = Vec::with_capacity(self.matrix.len());
        for (frame, values) in self.matrix.iter().enumerate() {
            let at = |message: String| {
                DocumentError::new(Location::Priority { row: Some(frame) }, message)
            };
            if values.len() != 6 {
                return Err(at(format!(
                    "has {} entries; each row is [alpha, d, theta, r, beta, K] (6 entries)",
                    values.len()
                )));
            }
            let mut cells = [0_u32; 6];
            for (cell, value) in cells.iter_mut().zip(values) {
                *cell = u32::try_from(*value).map_err(|_| {
                    at(format!("{value} is not a priority: priorities are integers ≥ 0 (0 = do not identify)"))
                })?;
            }
            rows.push(cells);
        }
        Ok(PriorityMatrix::from_rows(rows))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn stanford() -> RobotDocument {
        let file = crate::ready_robot("stanford")
            .expect("ready")
            .expect("valid");
        RobotDocument::from_robot_file(&file)
    }

    #[test]
    fn a_valid_document_has_no_problems_and_round_trips() {
        let document = stanford();
        assert!(document.problems().is_empty());
        let file = document.to_robot_file("x").expect("valid");
        assert_eq!(RobotDocument::from_robot_file(&file), document);
    }

    #[test]
    fn every_bad_frame_is_reported_at_its_cell() {
        let mut document = stanford();
        document.frame[2].sigma = Some(7);
        document.frame[4].alpha = Some(f64::NAN);
        document.frame[5].qmin = Some(2.0);
        document.frame[5].qmax = Some(1.0);
        let problems = document.problems();
        let locations: Vec<String> = problems.iter().map(|p| p.location.to_string()).collect();
        // Frame-level problems are all found; qmin > qmax is a rule of the whole model,
        // reported once the frames themselves are fine.
        assert_eq!(
            locations,
            ["frame 2, sigma", "frame 4, alpha"],
            "{problems:?}"
        );
        document.frame[2].sigma = Some(0);
        document.frame[4].alpha = Some(0.0);
        let problems = document.problems();
        assert_eq!(problems.len(), 1, "{problems:?}");
        assert_eq!(
            problems[0].location,
            Location::Frame {
                frame: 5,
                key: "qmin".into()
            }
        );
    }

    #[test]
    fn an_unknown_angle_unit_is_reported_with_the_frames() {
        let mut document = stanford();
        document.angle_unit = Some("grad".into());
        document.frame[1].d = Some(f64::INFINITY);
        let locations: Vec<String> = document
            .problems()
            .iter()
            .map(|p| p.location.to_string())
            .collect();
        assert_eq!(locations, ["angle_unit", "frame 1, d"]);
    }
}
