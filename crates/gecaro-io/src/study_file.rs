//! Study files: several measurement sets calibrated together.
//!
//! ```toml
//! robot = "panda-ball.toml"     # relative to this file, or a ready robot's name
//! priority = "priority.toml"    # optional, as for `--priority`
//!
//! [[measurements]]
//! method = "point-link"
//! data = "sets.csv"             # relative to this file
//! sigma = 0.0003                # the sensor's standard deviation: metres (radians for orientations)
//! # sigma_rotation = 0.005      # optional: a separate σ for orientation rows (radians)
//!
//! [[measurements]]
//! method = "distance"
//! data = "pairs.csv"
//! sigma = 0.0001
//! # plane methods add: plane = "known" | "unknown", plane_normal = [..], plane_point = [..]
//! # optional: set_size = 4, orientation = "axis-angle" | "cross-products"
//!
//! [[measurements]]
//! method = "position"
//! data = "tracker.csv"          # as the tracker wrote it:
//! length_unit = "mm"            # positions (and prismatic joints) in mm
//! angle_unit = "deg"            # joint angles in degrees
//! columns = { x = "X", y = "Y", z = "Z", qm1 = "A1" }   # other column names
//! delimiter = ";"               # optional: found from the header by default
//! decimal_comma = true          # optional: allowed by default where fields are not comma-separated
//! sigma = 0.02                  # in the set's length unit (here mm): 20 µm
//! # sigma_rotation = 0.01       # in the set's angle unit (here degrees)
//! ```
//!
//! A σ is a number in its set's units (`length_unit`, `angle_unit`: metres and
//! radians unless said), or a text with its own unit: `sigma = "0.02mm"`,
//! `sigma_rotation = "0.01deg"`.
//!
//! `length_unit` and `angle_unit` may also stand at the top, for every set.
//! An optional `[prior]` table puts a Gaussian prior on the parameters
//! (`length = "5mm"`, `angle = "0.5deg"`, `gain = "1%"`, and
//! `parameters = { d3 = "0.5mm" }` to override one parameter; see
//! [`crate::parse_prior`]).
//! Each set's rows are weighted by 1/σ, so that sets measured in different
//! units and with different sensors count by their precision. Columns a set
//! does not use are left alone and listed in [`StudyFile::notes`].

use gecaro_calib::{
    frames::{FrameRole, NamedFrame},
    identification::Prior,
    methods::{MethodOptions, Plane},
    study::{DataColumn, MeasurementSet, Study},
};
use gecaro_core::{OrientationDifference, PriorityMatrix};
use nalgebra::{IsometryMatrix3, Rotation3, Translation3, Vector3};
use serde::Deserialize;
use std::path::{Path, PathBuf};
use toml::Spanned;

use crate::Error;
use crate::columns::{ColumnMap, DataUnits, Delimiter, joint_types};
use crate::data_file::{DataFormat, read_samples};
use crate::input::{MAX_DESCRIPTION_BYTES, read_text};
use crate::prior::{Kind, StandardDeviation};
use crate::ready::load_robot;
use crate::robot_file::AngleUnit;
use crate::robot_file::RobotFile;
use crate::robot_toml::read_priority_file;
use crate::units::LengthUnit;

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawStudy {
    robot: Spanned<String>,
    priority: Option<Spanned<String>>,
    length_unit: Option<Spanned<String>>,
    angle_unit: Option<Spanned<String>>,
    measurements: Spanned<Vec<Spanned<RawMeasurement>>>,
    prior: Option<Spanned<RawPrior>>,
    #[serde(default)]
    tools: std::collections::BTreeMap<String, Spanned<RawFrame>>,
    #[serde(default)]
    stations: std::collections::BTreeMap<String, Spanned<RawFrame>>,
}

/// A `[tools.NAME]` or `[stations.NAME]` table: the stated pose.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawFrame {
    position: Spanned<Vec<f64>>,
    rpy: Option<Spanned<Vec<f64>>>,
    quaternion: Option<Spanned<Vec<f64>>>,
    length_unit: Option<Spanned<String>>,
    angle_unit: Option<Spanned<String>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawPrior {
    length: Spanned<String>,
    angle: Spanned<String>,
    gain: Spanned<String>,
    parameters: Option<Spanned<std::collections::BTreeMap<String, String>>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawMeasurement {
    method: Spanned<String>,
    data: Spanned<String>,
    sigma: Spanned<StandardDeviation>,
    sigma_rotation: Option<Spanned<StandardDeviation>>,
    plane: Option<Spanned<String>>,
    plane_normal: Option<Spanned<Vec<f64>>>,
    plane_point: Option<Spanned<Vec<f64>>>,
    set_size: Option<Spanned<usize>>,
    orientation: Option<Spanned<String>>,
    length_unit: Option<Spanned<String>>,
    angle_unit: Option<Spanned<String>>,
    columns: Option<Spanned<std::collections::BTreeMap<String, String>>>,
    delimiter: Option<Spanned<String>>,
    decimal_comma: Option<bool>,
    tool: Option<Spanned<String>>,
    station: Option<Spanned<String>>,
}

/// A study read from a file, with its robot.
#[derive(Debug)]
pub struct StudyFile {
    /// The nominal robot.
    pub robot: RobotFile,
    /// The measurement sets.
    pub study: Study,
    /// The priority matrix given by the study, if any.
    pub priority: Option<PriorityMatrix>,
    /// The prior of its `[prior]` table, if any.
    pub prior: Option<Prior>,
    /// What the user should know: columns of data files left unused.
    pub notes: Vec<String>,
}

/// What a study's data files are read for.
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq)]
pub enum StudyData {
    /// The measurements: every column of each set's method.
    #[default]
    Measured,
    /// The configurations only (joint values, and set or pair ids): a plan
    /// before it is measured, for a prediction. Measurement columns, if
    /// present, are left alone.
    Configurations,
}

/// Reads a study file and everything it refers to.
///
/// # Errors
/// [`Error::Parse`] with the line of the study file at fault, or the errors
/// of the robot and data files it names.
pub fn read_study_file(path: &Path) -> Result<StudyFile, Error> {
    read_study_file_for(path, StudyData::Measured)
}

/// [`read_study_file`], its data files read for `data`.
///
/// # Errors
/// As [`read_study_file`].
pub fn read_study_file_for(path: &Path, data: StudyData) -> Result<StudyFile, Error> {
    let text = read_text(path, MAX_DESCRIPTION_BYTES)?;
    let line_of = |offset: usize| crate::error::line_at(&text, offset);
    let fail = |span: std::ops::Range<usize>, field: &str, message: String| {
        Error::parse(path, line_of(span.start), Some(field.to_owned()), message)
    };
    let raw: RawStudy = toml::from_str(&text).map_err(|error| {
        let line = error.span().map_or(1, |span| line_of(span.start));
        Error::parse(path, line, None, crate::error::toml_message(&error, &text))
    })?;
    let folder = path.parent().unwrap_or(Path::new("."));
    let relative = |name: &str| -> PathBuf { folder.join(name) };
    let robot_path = relative(raw.robot.get_ref());
    let robot = if robot_path.is_file() {
        load_robot(&robot_path.to_string_lossy())?
    } else {
        load_robot(raw.robot.get_ref())?
    };
    let priority = match &raw.priority {
        Some(name) => Some(read_priority_file(&relative(name.get_ref()), &robot.robot)?),
        None => None,
    };
    let prior = match &raw.prior {
        None => None,
        Some(table) => {
            let table = table.get_ref();
            let text = format!(
                "{},{},{}",
                table.length.get_ref(),
                table.angle.get_ref(),
                table.gain.get_ref()
            );
            let mut prior = crate::parse_prior(&text)
                .map_err(|message| fail(table.length.span(), "prior", message))?;
            if let Some(parameters) = &table.parameters {
                for (name, value) in parameters.get_ref() {
                    let entry = crate::parse_override(name, value)
                        .map_err(|message| fail(parameters.span(), "prior.parameters", message))?;
                    prior.overrides.push(entry);
                }
                prior.check(&robot.robot).map_err(|error| {
                    fail(parameters.span(), "prior.parameters", error.to_string())
                })?;
            }
            Some(prior)
        }
    };
    if raw.measurements.get_ref().is_empty() {
        return Err(fail(
            raw.measurements.span(),
            "measurements",
            "a study needs at least one [[measurements]] table".into(),
        ));
    }
    let length_unit = |unit: &Option<Spanned<String>>, default: LengthUnit| match unit {
        None => Ok(default),
        Some(unit) => LengthUnit::from_name(unit.get_ref()).ok_or_else(|| {
            fail(
                unit.span(),
                "length_unit",
                format!("must be \"m\" or \"mm\", not {:?}", unit.get_ref()),
            )
        }),
    };
    let angle_unit = |unit: &Option<Spanned<String>>, default: AngleUnit| match unit {
        None => Ok(default),
        Some(unit) => AngleUnit::from_name(unit.get_ref()).ok_or_else(|| {
            fail(
                unit.span(),
                "angle_unit",
                format!("must be \"rad\" or \"deg\", not {:?}", unit.get_ref()),
            )
        }),
    };
    let study_units = DataUnits {
        length: length_unit(&raw.length_unit, LengthUnit::Metres)?,
        angle: angle_unit(&raw.angle_unit, AngleUnit::Radians)?,
    };
    let mut frames = Vec::new();
    for (tables, role) in [
        (&raw.tools, FrameRole::Tool),
        (&raw.stations, FrameRole::Station),
    ] {
        for (name, table) in tables {
            let field = format!("{}s.{name}", role.as_str());
            let units = DataUnits {
                length: length_unit(&table.get_ref().length_unit, study_units.length)?,
                angle: angle_unit(&table.get_ref().angle_unit, study_units.angle)?,
            };
            let pose = frame_pose(table.get_ref(), units)
                .map_err(|(span, key, message)| fail(span, &format!("{field}.{key}"), message))?;
            if frames.iter().any(|frame: &NamedFrame| frame.name == *name) {
                return Err(fail(
                    table.span(),
                    &field,
                    format!("`{name}` names both a tool and a station; give them different names"),
                ));
            }
            frames.push(NamedFrame {
                name: name.clone(),
                role,
                pose,
            });
        }
    }
    let find_frame =
        |name: &Option<Spanned<String>>, role: FrameRole| -> Result<Option<usize>, Error> {
            let Some(name) = name else { return Ok(None) };
            match frames
                .iter()
                .position(|frame| frame.name == *name.get_ref() && frame.role == role)
            {
                Some(index) => Ok(Some(index)),
                None => Err(fail(
                    name.span(),
                    role.as_str(),
                    format!(
                        "no [{}s.{}] table in this study",
                        role.as_str(),
                        name.get_ref()
                    ),
                )),
            }
        };
    let types = joint_types(&robot.robot);
    let mut sets = Vec::new();
    let mut notes = Vec::new();
    for measurement in raw.measurements.get_ref() {
        let table = measurement.get_ref();
        let units = DataUnits {
            length: length_unit(&table.length_unit, study_units.length)?,
            angle: angle_unit(&table.angle_unit, study_units.angle)?,
        };
        let sigma = standard_deviation(&table.sigma, "sigma", Kind::Length, units)
            .map_err(|(span, message)| fail(span, "sigma", message))?;
        let sigma_rotation = match &table.sigma_rotation {
            None => None,
            Some(value) => Some(
                standard_deviation(value, "sigma_rotation", Kind::Angle, units)
                    .map_err(|(span, message)| fail(span, "sigma_rotation", message))?,
            ),
        };
        let vector = |field: &Option<Spanned<Vec<f64>>>,
                      name: &str|
         -> Result<Option<Vector3<f64>>, Error> {
            match field {
                None => Ok(None),
                Some(values) => match values.get_ref().as_slice() {
                    [x, y, z] => Ok(Some(Vector3::new(*x, *y, *z))),
                    other => Err(fail(
                        values.span(),
                        name,
                        format!("needs three numbers, got {}", other.len()),
                    )),
                },
            }
        };
        let plane = match (
            vector(&table.plane_normal, "plane_normal")?,
            vector(&table.plane_point, "plane_point")?,
        ) {
            (Some(normal), Some(point)) => Some(Plane::new(normal, point).map_err(|error| {
                fail(
                    table
                        .plane_normal
                        .as_ref()
                        .map_or(measurement.span(), Spanned::span),
                    "plane_normal",
                    error.to_string(),
                )
            })?),
            (None, None) => None,
            _ => {
                return Err(fail(
                    measurement.span(),
                    "plane_normal",
                    "a plane needs both plane_normal and plane_point".into(),
                ));
            }
        };
        let plane_unknown = match table
            .plane
            .as_ref()
            .map(|p| (p.get_ref().as_str(), p.span()))
        {
            None => plane.is_none(),
            Some(("known", span)) => {
                if plane.is_none() {
                    return Err(fail(
                        span,
                        "plane",
                        "plane = \"known\" needs plane_normal and plane_point".into(),
                    ));
                }
                false
            }
            Some(("unknown", _)) => true,
            Some((other, span)) => {
                return Err(fail(
                    span,
                    "plane",
                    format!("must be \"known\" or \"unknown\", not {other:?}"),
                ));
            }
        };
        let orientation = match table
            .orientation
            .as_ref()
            .map(|o| (o.get_ref().as_str(), o.span()))
        {
            None | Some(("axis-angle", _)) => OrientationDifference::AxisAngle,
            Some(("cross-products", _)) => OrientationDifference::CrossProducts,
            Some((other, span)) => {
                return Err(fail(
                    span,
                    "orientation",
                    format!("must be \"axis-angle\" or \"cross-products\", not {other:?}"),
                ));
            }
        };
        let options = MethodOptions {
            plane,
            plane_unknown,
            orientation,
            set_size: table.set_size.as_ref().map(|s| *s.get_ref()),
        };
        let method = gecaro_calib::methods::method(table.method.get_ref(), &options)
            .map_err(|error| fail(table.method.span(), "method", error.to_string()))?;
        let tool = find_frame(&table.tool, FrameRole::Tool)?;
        let station = find_frame(&table.station, FrameRole::Station)?;
        if (tool.is_some() || station.is_some())
            && !method.data_columns().contains(&DataColumn::Position)
        {
            let span = table
                .tool
                .as_ref()
                .or(table.station.as_ref())
                .map_or(measurement.span(), Spanned::span);
            return Err(fail(
                span,
                if tool.is_some() { "tool" } else { "station" },
                format!(
                    "the {} method measures no pose in a measurement frame; tools and stations \
                     go with position and frame measures",
                    method.name()
                ),
            ));
        }
        let data_path = relative(table.data.get_ref());
        let delimiter = match &table.delimiter {
            None => Delimiter::Detect,
            Some(name) => Delimiter::from_name(name.get_ref()).ok_or_else(|| {
                fail(
                    name.span(),
                    "delimiter",
                    format!(
                        "must be one of {}, not {:?}",
                        Delimiter::NAMES.join(", "),
                        name.get_ref()
                    ),
                )
            })?,
        };
        let format = DataFormat {
            units,
            columns: table
                .columns
                .as_ref()
                .map_or_else(ColumnMap::default, |columns| {
                    ColumnMap::from_pairs(columns.get_ref().clone())
                }),
            delimiter,
            decimal_comma: table.decimal_comma,
        };
        let columns = match data {
            StudyData::Measured => method.data_columns().to_vec(),
            StudyData::Configurations => DataColumn::grouping(method.data_columns()),
        };
        let read = read_samples(&data_path, &types, &columns, &format)?;
        if !read.unused_columns.is_empty() && data == StudyData::Measured {
            notes.push(format!(
                "{}: columns {} are not used by the {} method (left alone)",
                data_path.display(),
                read.unused_columns.join(", "),
                method.name()
            ));
        }
        notes.extend(read.notes);
        let samples = read.samples;
        sets.push(MeasurementSet {
            method,
            samples,
            sigma: Some(sigma),
            sigma_rotation,
            label: data_path.display().to_string(),
            tool,
            station,
        });
    }
    let all_frames = raw.tools.iter().chain(&raw.stations);
    for ((name, table), index) in all_frames.zip(0..) {
        if !sets
            .iter()
            .any(|set| set.tool == Some(index) || set.station == Some(index))
        {
            return Err(fail(
                table.span(),
                name,
                format!(
                    "{} `{name}` is measured by no [[measurements]] set (name it with {} = {name:?})",
                    frames[index].role.as_str(),
                    frames[index].role.as_str()
                ),
            ));
        }
    }
    Ok(StudyFile {
        robot,
        study: Study { sets, frames },
        priority,
        prior,
        notes,
    })
}

/// The pose a `[tools.NAME]` or `[stations.NAME]` table states: `position`
/// in its length unit, `rpy` (roll, pitch, yaw about the fixed x, y, z
/// axes, as URDF writes them) in its angle unit, or a unit `quaternion`
/// `[w, x, y, z]`; neither: the parent frame's orientation.
fn frame_pose(
    table: &RawFrame,
    units: DataUnits,
) -> Result<IsometryMatrix3<f64>, (std::ops::Range<usize>, &'static str, String)> {
    let three = |values: &Spanned<Vec<f64>>, key: &'static str| match values.get_ref().as_slice() {
        [x, y, z] if [x, y, z].iter().all(|v| v.is_finite()) => Ok(Vector3::new(*x, *y, *z)),
        [_, _, _] => Err((values.span(), key, "needs finite numbers".to_owned())),
        other => Err((
            values.span(),
            key,
            format!("needs three numbers, got {}", other.len()),
        )),
    };
    let position = three(&table.position, "position")? * units.length.to_metres();
    let rotation = match (&table.rpy, &table.quaternion) {
        (Some(_), Some(quaternion)) => {
            return Err((
                quaternion.span(),
                "quaternion",
                "give the orientation as rpy or as a quaternion, not both".into(),
            ));
        }
        (Some(rpy), None) => {
            let scale = match units.angle {
                AngleUnit::Degrees => std::f64::consts::PI / 180.0,
                AngleUnit::Radians => 1.0,
            };
            let angles = three(rpy, "rpy")? * scale;
            Rotation3::from_euler_angles(angles.x, angles.y, angles.z)
        }
        (None, Some(quaternion)) => match quaternion.get_ref().as_slice() {
            [w, x, y, z] => crate::pose::unit_quaternion(*w, *x, *y, *z)
                .map_err(|message| (quaternion.span(), "quaternion", message))?
                .to_rotation_matrix(),
            other => {
                return Err((
                    quaternion.span(),
                    "quaternion",
                    format!("needs four numbers [w, x, y, z], got {}", other.len()),
                ));
            }
        },
        (None, None) => Rotation3::identity(),
    };
    if position.norm() > gecaro_core::MAX_MAGNITUDE {
        return Err((
            table.position.span(),
            "position",
            format!(
                "is {} m from its parent frame (at most {} m)",
                gecaro_core::Compact(position.norm()),
                gecaro_core::MAX_MAGNITUDE
            ),
        ));
    }
    Ok(IsometryMatrix3::from_parts(
        Translation3::from(position),
        rotation,
    ))
}

/// A set's σ in metres (`Kind::Length`) or radians (`Kind::Angle`): a number
/// is in the set's length or angle unit, a text carries its own unit.
fn standard_deviation(
    value: &Spanned<StandardDeviation>,
    key: &str,
    kind: Kind,
    units: DataUnits,
) -> Result<f64, (std::ops::Range<usize>, String)> {
    value
        .get_ref()
        .value(kind == Kind::Angle, units)
        .map_err(|message| {
            let message = if message.starts_with('"') {
                format!("{key} = {message}")
            } else {
                message
            };
            (value.span(), message)
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A study of one position set in `folder`, with `sigma_line` in its table.
    fn study(folder: &Path, sigma_line: &str) -> Result<StudyFile, Error> {
        std::fs::write(
            folder.join("data.csv"),
            "qm1;qm2;qm3;qm4;qm5;qm6;X;Y;Z\n\
             0,1;0,2;0,3;0,1;0,2;0,3;100,5;200,25;300\n",
        )
        .expect("data");
        let path = folder.join("study.toml");
        std::fs::write(
            &path,
            format!(
                "robot = \"stanford\"\n[[measurements]]\nmethod = \"position\"\n\
                 data = \"data.csv\"\nlength_unit = \"mm\"\n\
                 columns = {{ x = \"X\", y = \"Y\", z = \"Z\" }}\n{sigma_line}\n"
            ),
        )
        .expect("study");
        read_study_file(&path)
    }

    #[test]
    fn sigmas_are_in_the_sets_units_or_their_own() {
        let folder = tempfile::tempdir().expect("folder");
        for line in [
            "sigma = 0.02",
            "sigma = \"0.02mm\"",
            "sigma = \"20um\"",
            "sigma = \"2e-5m\"",
        ] {
            let file = study(folder.path(), line).unwrap_or_else(|error| panic!("{line}: {error}"));
            let sigma = file.study.sets[0].sigma.expect("sigma");
            assert!((sigma - 2e-5).abs() < 1e-15, "{line}: {sigma}");
            // Fields separated by `;` with decimal commas, in millimetres.
            let position = file.study.sets[0].samples[0].position.expect("position");
            assert!((position.x - 0.1005).abs() < 1e-12, "{position}");
        }
        let error = study(folder.path(), "sigma = \"0.02deg\"").expect_err("an angle");
        assert!(error.to_string().contains("must be a length"), "{error}");
        let error = study(folder.path(), "sigma = -1").expect_err("negative");
        assert!(
            error.to_string().contains("positive standard deviation"),
            "{error}"
        );
    }
}
