//! The owner's base registered by the circles of joints 1 and 2 (issue
//! 74), as robot makers define a base: z along joint 1's axis, the origin
//! where the common normal of axes 1 and 2 meets it, x along that normal
//! with joint 1 at zero — placed as the nominal robot places them
//! ([`gecaro_calib::axis_circles`]).
//!
//! The file is a position data file (`qm1..qmn,x,y,z`, every format option
//! of a data file): a point on the arm (a reflector anywhere past joint 2)
//! measured while joint 1 turned alone, and while joint 2 turned alone with
//! joint 1 held. The rows are sorted by their readings: the rows whose
//! other joints read alike (within [`HELD`]) and whose joint 1 differs draw
//! joint 1's circle, likewise for joint 2; a row may belong to both (the
//! pose both circles start from). A row in neither is refused with its
//! line: it turned more than one joint.

use gecaro_calib::axis_circles::{Axis, TurnedJoint, register_by_circles};
use gecaro_calib::study::DataColumn;
use gecaro_core::{FrameType, Robot, frame_transform};
use nalgebra::{IsometryMatrix3, Unit, Vector3};

use crate::base_frame::{BaseBy, BaseRegistration, RegisteredPoint};
use crate::error::AppError;
use crate::files::Files;
use crate::sources::{DataFormatSpec, DataSource};

/// Two readings of a joint this close (rad, or m for a prismatic joint)
/// are the joint held: an encoder's jitter, not a turn.
pub const HELD: f64 = 1e-5;

/// The most rows a circles file holds: two circles of a few dozen points.
const MAX_CIRCLE_ROWS: usize = 1_000;

/// The base registered by the circles in `source`, for a robot whose
/// nominal model is `nominal` (see the module docs).
///
/// # Errors
/// A file that cannot be read, joints 1 or 2 not revolute, rows that turn
/// more than one joint, circles that cannot be fitted, parallel axes.
pub(crate) fn register_base_by_circles(
    source: &DataSource,
    files: &dyn Files,
    format: &DataFormatSpec,
    nominal: &Robot,
) -> Result<BaseRegistration, AppError> {
    let label = source.label();
    let refuse = |message: String| AppError::setting("base_circles", format!("{label}: {message}"));
    let types = gecaro_io::joint_types(nominal);
    if types.len() < 2 || types[..2].iter().any(|t| *t != FrameType::Revolute) {
        return Err(refuse(format!(
            "{} has joints {}: a base is registered by circles where joints 1 and 2 turn",
            nominal.name(),
            nominal.joint_letters()
        )));
    }
    let read = source.read(files, &types, &[DataColumn::Position], &format.format()?)?;
    let samples = &read.samples;
    if samples.len() > MAX_CIRCLE_ROWS {
        return Err(refuse(format!(
            "{} rows: a circles file holds the points of two circles (up to {MAX_CIRCLE_ROWS})",
            samples.len()
        )));
    }
    let mut rows = Vec::with_capacity(samples.len());
    for sample in samples.iter() {
        let line = sample.line().unwrap_or(rows.len() + 2);
        let joints = nominal
            .joint_positions(sample.motor_positions())
            .map_err(|error| refuse(format!("line {line}: {error}")))?;
        let point = sample
            .position()
            .ok_or_else(|| refuse(format!("line {line}: no x, y, z")))?;
        rows.push(Row {
            line,
            joints: joints.iter().copied().collect(),
            point,
        });
    }
    let first = turned_alone(&rows, 0);
    let second = turned_alone(&rows, 1);
    let (Some(first), Some(second)) = (first, second) else {
        return Err(refuse(format!(
            "no {} rows turn joint {} alone (the other joints held within {HELD}): a circle \
             is measured with one joint turning",
            gecaro_calib::axis_circles::MIN_CIRCLE_POINTS,
            if turned_alone(&rows, 0).is_none() {
                1
            } else {
                2
            }
        )));
    };
    if let Some(stray) = rows
        .iter()
        .enumerate()
        .find(|(i, _)| !first.contains(i) && !second.contains(i))
    {
        return Err(refuse(format!(
            "line {}: neither joint 1 nor joint 2 turned alone from the circles' poses (more \
             than one joint moved)",
            stray.1.line
        )));
    }
    let points = |indices: &[usize]| indices.iter().map(|i| rows[*i].point).collect::<Vec<_>>();
    let angles = |indices: &[usize], joint: usize| {
        indices
            .iter()
            .map(|i| rows[*i].joints[joint])
            .collect::<Vec<_>>()
    };
    let (one, two) = (points(&first), points(&second));
    let (angles1, angles2) = (angles(&first, 0), angles(&second, 1));
    let held = rows[second[0]].joints[0];
    let (fit, circles) = register_by_circles(
        TurnedJoint {
            points: &one,
            angles: &angles1,
        },
        TurnedJoint {
            points: &two,
            angles: &angles2,
        },
        held,
        (&nominal_axis(nominal, 1), &nominal_axis(nominal, 2)),
    )
    .map_err(refuse)?;
    let named = |indices: &[usize], joint: usize| {
        indices
            .iter()
            .map(|i| RegisteredPoint {
                name: format!("joint {joint}"),
                line: rows[*i].line,
            })
            .collect::<Vec<_>>()
    };
    let mut registered = named(&first, 1);
    registered.extend(named(&second, 2));
    Ok(BaseRegistration {
        by: BaseBy::Circles,
        points: registered,
        fit,
        radii: circles.iter().map(|circle| circle.radius).collect(),
    })
}

/// A row of a circles file: its line, joint values and point.
struct Row {
    line: usize,
    joints: Vec<f64>,
    point: Vector3<f64>,
}

/// The rows (indices) of the largest group in which every joint but
/// `joint` reads alike and `joint` differs, if it has enough points for a
/// circle.
fn turned_alone(rows: &[Row], joint: usize) -> Option<Vec<usize>> {
    let alike = |a: &Row, b: &Row| {
        a.joints
            .iter()
            .zip(&b.joints)
            .enumerate()
            .all(|(j, (x, y))| j == joint || (x - y).abs() <= HELD)
    };
    (0..rows.len())
        .map(|i| {
            (0..rows.len())
                .filter(|k| alike(&rows[i], &rows[*k]))
                .collect::<Vec<_>>()
        })
        .filter(|group| {
            let mut values: Vec<f64> = group.iter().map(|k| rows[*k].joints[joint]).collect();
            values.sort_by(f64::total_cmp);
            values.dedup_by(|a, b| (*a - *b).abs() <= HELD);
            values.len() >= gecaro_calib::axis_circles::MIN_CIRCLE_POINTS
        })
        .max_by_key(Vec::len)
}

/// Joint `joint`'s axis (1 or 2) of `robot` in its base frame, every joint
/// before it at zero.
fn nominal_axis(robot: &Robot, joint: usize) -> Axis {
    let pose: IsometryMatrix3<f64> = robot.frames()[..=joint]
        .iter()
        .fold(IsometryMatrix3::identity(), |pose, frame| {
            pose * frame_transform(frame, 0.0)
        });
    Axis {
        point: pose.translation.vector,
        direction: Unit::new_normalize(pose.rotation * Vector3::z()),
    }
}
