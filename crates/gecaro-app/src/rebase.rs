//! A calibrated robot re-expressed in its own base frame as a job
//! ([`RebaseRequest`]): split into the measurement frame's pose and the
//! robot seen from its nominal's base frame
//! ([`Robot::rebased`](gecaro_core::Robot::rebased)), so that programs
//! taught in robot coordinates can be corrected and URDFs exported in the
//! robot's frame. Compensation and export use the same split
//! ([`rebased_file`]), and compensation refuses two robots that are not in
//! one frame ([`check_same_frame`]).

use std::path::{Path, PathBuf};

use gecaro_core::{Compact, Robot};
use gecaro_io::RobotFile;
use nalgebra::IsometryMatrix3;
use serde::Deserialize;

use crate::base_circles::register_base_by_circles;
use crate::base_frame::{BasePointsSource, BaseRegistration, load_base_points};
use crate::error::{AppError, ErrorKind, Hint, Part};
use crate::files::Files;
use crate::measurements::Unknown;
use crate::output::Output;
use crate::sources::{DataFormatSpec, DataSource, RobotSource};

/// A calibrated robot to re-express in its nominal's base frame.
#[derive(Clone, Debug, Deserialize)]
pub struct RebaseRequest {
    /// The calibrated robot (in a measurement frame).
    pub robot: RobotSource,
    /// The nominal robot, whose base frame is the robot's own.
    pub nominal: RobotSource,
    /// Points measured in the calibration's frame beside their place in
    /// the owner's base frame (a drawing's): the base registered by them
    /// (`crate::base_frame`) rather than by the nominal's convention.
    #[serde(default)]
    pub base_points: Option<BasePointsSource>,
    /// A position data file of joints 1 and 2 turned alone: the base
    /// registered by their circles (`crate::base_circles`).
    #[serde(default)]
    pub base_circles: Option<DataSource>,
    /// Units and column names of the base-points or circles file.
    #[serde(default)]
    pub format: DataFormatSpec,
    /// Where the output is written (`save_as`) and whether it may replace a
    /// file (`overwrite`).
    #[serde(flatten)]
    pub output: Output,
    #[serde(flatten)]
    unknown: Unknown,
}

/// A calibrated robot split into the measurement frame and the robot in its
/// own frame.
#[derive(Clone, Debug)]
pub struct Rebased {
    /// The pose of the measurement frame in the robot's base frame (maps
    /// measurement coordinates to robot coordinates).
    pub measurement_frame: IsometryMatrix3<f64>,
    /// The robot in its own base frame.
    pub robot: RobotFile,
    /// The base registered by points, when they were given.
    pub registration: Option<BaseRegistration>,
    /// With points: the owner's base against the base the nominal's
    /// convention gives the calibrated robot (frame 0 from joint 1's axis)
    /// — the pose of the convention's base frame in the owner's.
    pub from_convention: Option<IsometryMatrix3<f64>>,
    /// Where it was written, if asked for.
    pub saved: Option<PathBuf>,
}

impl RebaseRequest {
    /// `robot` re-expressed in `nominal`'s base frame.
    pub fn new(robot: RobotSource, nominal: RobotSource) -> Self {
        RebaseRequest {
            robot,
            nominal,
            base_points: None,
            base_circles: None,
            format: DataFormatSpec::default(),
            output: Output::default(),
            unknown: Unknown::default(),
        }
    }

    /// Splits the robot and writes it if asked (checked before any work).
    ///
    /// # Errors
    /// Files that cannot be read or written, robots of other joints.
    pub fn run(&self, files: &dyn Files) -> Result<Rebased, AppError> {
        self.unknown.check()?;
        self.output.check(files, "toml")?;
        let robot = self.robot.load(files)?;
        let nominal = self.nominal.load(files)?;
        let registration = owner_base(
            files,
            (self.base_points.as_ref(), self.base_circles.as_ref()),
            &self.format,
            &robot,
            &nominal,
        )?;
        let (measurement_frame, robot, from_convention) = match &registration {
            None => {
                let (frame, robot) = rebased_file(&robot, &nominal.robot)?;
                (frame, robot, None)
            }
            Some(registration) => {
                let rebased = registration.rebased(&robot)?;
                // Where the convention would have put the base, seen from
                // the owner's.
                let (convention, _) = rebased.robot.rebased(&nominal.robot)?;
                (
                    registration.base_in_measurement_frame().inverse(),
                    rebased,
                    Some(convention.inverse()),
                )
            }
        };
        let saved = match &self.output.save_as {
            Some(name) => Some(files.write(
                name,
                "toml",
                gecaro_io::robot_file_text(&robot, Path::new(name))?.as_bytes(),
                self.output.overwrite,
            )?),
            None => None,
        };
        Ok(Rebased {
            measurement_frame,
            robot,
            registration,
            from_convention,
            saved,
        })
    }
}

/// The owner's base registered by `points` or by `circles` (not both), if
/// either is given, for `robot` calibrated from `nominal`.
///
/// # Errors
/// Both given, robots of other joints, and the registrations' own.
pub(crate) fn owner_base(
    files: &dyn Files,
    (points, circles): (Option<&BasePointsSource>, Option<&DataSource>),
    format: &DataFormatSpec,
    robot: &RobotFile,
    nominal: &RobotFile,
) -> Result<Option<BaseRegistration>, AppError> {
    if points.is_some() && circles.is_some() {
        return Err(AppError::setting(
            "base_circles",
            "the base is registered by its points or by the circles of joints 1 and 2: give one \
             of them",
        ));
    }
    if (points.is_some() || circles.is_some())
        && robot.robot.joint_letters() != nominal.robot.joint_letters()
    {
        return Err(AppError::plain(
            ErrorKind::Input,
            format!(
                "the robot has joints {}, the nominal one {}",
                robot.robot.joint_letters(),
                nominal.robot.joint_letters()
            ),
        ));
    }
    if let Some(source) = points {
        return Ok(Some(BaseRegistration::new(
            load_base_points(source, files, format)?,
            &source.label(),
        )?));
    }
    circles
        .map(|source| register_base_by_circles(source, files, format, &nominal.robot))
        .transpose()
}

/// `calibrated` in `nominal`'s base frame, as a robot file that says so,
/// and the pose of the measurement frame in that base frame.
///
/// # Errors
/// Robots of other joints.
pub fn rebased_file(
    calibrated: &RobotFile,
    nominal: &Robot,
) -> Result<(IsometryMatrix3<f64>, RobotFile), AppError> {
    // Gravity's tilts, found by an identification, lean gravity about axes
    // chosen from its direction in the measurement frame: folded into the
    // file's gravity first, they turn with the frame (left on the robot,
    // `rebased` dropped them).
    let calibrated = &calibrated.clone().with_gravity_tilt_folded();
    let (measurement_frame, robot) = calibrated.robot.rebased(nominal)?;
    let t = measurement_frame.translation.vector;
    let (roll, pitch, yaw) = measurement_frame.rotation.euler_angles();
    let note = format!(
        "re-expressed in {}'s base frame (the measurement frame stood at x {} y {} z {} m, \
         rpy {} {} {} rad in it)",
        nominal.name(),
        Compact(t.x),
        Compact(t.y),
        Compact(t.z),
        Compact(roll),
        Compact(pitch),
        Compact(yaw)
    );
    let description = match &calibrated.description {
        Some(text) => format!("{text}; {note}"),
        None => note,
    };
    // Each link keeps its body: its centre moves into the new frames, gravity
    // into the base frame.
    let masses = calibrated
        .masses
        .reframed(&calibrated.robot, &robot, &measurement_frame)?;
    Ok((
        measurement_frame,
        RobotFile {
            robot,
            description: Some(description),
            masses,
            ..calibrated.clone()
        },
    ))
}

/// Refuses a calibrated robot that is not described in the nominal's frame
/// (its joint 1 farther than a calibration moves a base, e.g. identified in
/// a tracker's frame): a program in one frame is not corrected with a robot
/// in another.
///
/// # Errors
/// [`ErrorKind::Input`] naming the offset and the `rebase` setting.
pub fn check_same_frame(nominal: &Robot, calibrated: &Robot) -> Result<(), AppError> {
    // Robots of other joints are refused as such by the compensation.
    if nominal.same_frame_as(calibrated) || nominal.joint_count() != calibrated.joint_count() {
        return Ok(());
    }
    let (distance, angle) = nominal.base_offset(calibrated);
    Err(AppError::new(
        ErrorKind::Input,
        vec![Part::Text(format!(
            "the calibrated robot's joint 1 stands {distance:.3} m and {:.1}° from the \
             nominal's: the two robots are not described in the same frame (a robot \
             calibrated in a tracker's frame stands where the tracker saw it)",
            angle.to_degrees()
        ))],
    )
    .with_help(vec![
        Part::Text("re-express the calibrated robot in the robot's base frame with ".into()),
        Part::Hint(Hint::Rebase),
        Part::Text(
            " (a program in robot coordinates), or give the nominal robot in the \
                    calibration's measurement frame"
                .into(),
        ),
    ]))
}
