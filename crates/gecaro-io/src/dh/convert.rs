//! A Denavit–Hartenberg table as a robot: its rows become Khalil–Kleinfinger
//! frames (standard rows shift by one frame: row j's a, α belong to frame
//! j+1), its base and tool transforms enter through
//! [`Robot::reframed`](gecaro_core::Robot::reframed), with the table's
//! joint variables.

use std::path::Path;

use gecaro_core::{Frame, FrameType, Joint, MassModel, Robot, RobotSpec};
use nalgebra::IsometryMatrix3;

use super::table::{DhConvention, Row, Table};
use crate::Error;
use crate::conversion::Imported;
use crate::robot_file::{AngleUnit, RobotFile, fallback_name};

/// The frames 0..n+1 of a table, before its base and tool transforms.
fn table_frames(rows: &[Row], convention: DhConvention) -> Vec<Frame> {
    let n = rows.len();
    let mut frames = vec![Frame::new(FrameType::Fixed)];
    for (j, row) in rows.iter().enumerate() {
        let frame = match convention {
            // Row j's a and α belong to the next frame; frame 1 starts on axis 1.
            DhConvention::Standard => {
                let previous = j.checked_sub(1).map(|i| rows[i].step).unwrap_or_default();
                Frame {
                    alpha: previous.alpha,
                    d: previous.a,
                    theta: row.step.theta,
                    r: row.step.d,
                    ..Frame::new(row.frame_type)
                }
            }
            DhConvention::Modified => Frame {
                alpha: row.step.alpha,
                d: row.step.a,
                theta: row.step.theta,
                r: row.step.d,
                ..Frame::new(row.frame_type)
            },
        };
        frames.push(frame);
    }
    frames.push(match convention {
        DhConvention::Standard => Frame {
            alpha: rows[n - 1].step.alpha,
            d: rows[n - 1].step.a,
            ..Frame::new(FrameType::Fixed)
        },
        DhConvention::Modified => Frame::new(FrameType::Fixed),
    });
    frames
}

/// The robot of `table` read in `convention` from `path` (which names it
/// in messages and notes).
///
/// # Errors
/// [`Error::Format`] when the table breaks a rule of the robot model.
pub(super) fn robot_of_table(
    table: &Table,
    convention: DhConvention,
    path: &Path,
) -> Result<Imported, Error> {
    let format_error = |message: String| Error::Format {
        path: path.to_owned(),
        message,
    };
    let mut notes = Vec::new();
    let joints = table
        .rows
        .iter()
        .enumerate()
        .map(|(index, row)| {
            let defaults = Joint::default_for(row.frame_type);
            let (qmin, qmax) = match row.limits {
                (Some(qmin), Some(qmax)) => (qmin, qmax),
                _ => {
                    notes.push(format!(
                        "joint {}: no limits in the table; defaults used",
                        index + 1
                    ));
                    (defaults.qmin, defaults.qmax)
                }
            };
            Joint {
                qmin,
                qmax,
                ..defaults
            }
        })
        .collect();
    let name = table.name.clone().unwrap_or_else(|| fallback_name(path));
    let robot = Robot::new(RobotSpec::rigid(
        name,
        table_frames(&table.rows, convention),
        joints,
    ))
    .map_err(|error| format_error(error.to_string()))?;
    let identity = IsometryMatrix3::identity();
    let world = table.world_from_base.unwrap_or(identity);
    let tool = table.last_from_tool.unwrap_or(identity);
    let robot = robot
        .reframed(&world, &tool)
        .map_err(|error| format_error(error.to_string()))?;
    let description = table.description.clone().unwrap_or_else(|| {
        format!(
            "imported from {} ({} table, {} joints)",
            path.file_name()
                .map_or_else(String::new, |f| f.to_string_lossy().into_owned()),
            match convention {
                DhConvention::Standard => "standard DH",
                DhConvention::Modified => "modified DH",
            },
            table.rows.len()
        )
    });
    Ok(Imported {
        file: RobotFile {
            masses: MassModel::new(robot.frames().len()),
            robot,
            description: Some(description),
            angle_unit: AngleUnit::Radians,
            urdf: None,
            measured_region: None,
            tools: Vec::new(),
            tool_frame_observed: true,
        },
        notes,
    })
}
