//! A robot as a Denavit–Hartenberg table (TOML, SI units), its offsets
//! folded into θ (or d) and what a table cannot carry (gains, couplings)
//! in a joint calibration file.

use gecaro_core::{Frame, FrameType, frame_transform};
use nalgebra::IsometryMatrix3;
use serde::Serialize;

use super::table::{DhConvention, RowDocument, TransformDocument};
use crate::conversion::Exported;
use crate::joint_calibration::numbered_joint_calibration;
use crate::pose::rpy;
use crate::robot_file::RobotFile;

/// The document gecaro writes (same keys as read).
#[derive(Serialize)]
struct TableOutput {
    name: String,
    description: String,
    convention: &'static str,
    angle_unit: &'static str,
    length_unit: &'static str,
    #[serde(skip_serializing_if = "Option::is_none")]
    base: Option<TransformDocument>,
    #[serde(skip_serializing_if = "Option::is_none")]
    tool: Option<TransformDocument>,
    joint: Vec<RowDocument>,
}

fn transform_document(pose: &IsometryMatrix3<f64>) -> Option<TransformDocument> {
    (*pose != IsometryMatrix3::identity()).then(|| TransformDocument {
        xyz: pose.translation.vector.into(),
        rpy: rpy(&pose.rotation),
    })
}

/// The DH or MDH table of a robot (SI units), with its offsets folded into
/// θ (or d): the table's joint values are q − offset.
///
/// Hayati's β of frame 1 (before joint 1) goes into the table's base
/// transform and that of frame n+1 into its tool transform (in the
/// standard convention the last row's `a` and `alpha` then go there too):
/// both are fixed transforms, and the table carries them exactly.
///
/// # Errors
/// A frame between two joints with β ≠ 0 (not expressible in a DH table),
/// naming it.
pub(crate) fn export_table(file: &RobotFile, convention: DhConvention) -> Result<Exported, String> {
    let robot = &file.robot;
    let frames = robot.frames();
    let n = robot.joint_count();
    if let Some((j, frame)) = frames
        .iter()
        .enumerate()
        .find(|(j, f)| (2..=n).contains(j) && f.beta != 0.0)
    {
        return Err(format!(
            "frame {j} has beta = {} rad: Hayati's β has no place in a DH table; export to URDF instead",
            frame.beta
        ));
    }
    let mut notes = Vec::new();
    let fold = |j: usize, frame: &Frame| -> (f64, f64) {
        let offset = robot.joints()[j - 1].offset;
        match frame.frame_type {
            FrameType::Prismatic => (frame.theta, frame.r + offset),
            _ => (frame.theta + offset, frame.r),
        }
    };
    if robot.joints().iter().any(|joint| joint.offset != 0.0) {
        notes.push("joint offsets are folded into theta (d for prismatic joints): the table's joint value is q − offset".into());
    }
    let row = |j: usize, a: f64, alpha: f64| {
        let frame = &frames[j];
        let (theta, d) = fold(j, frame);
        let joint = &robot.joints()[j - 1];
        let offset = joint.offset;
        RowDocument {
            joint_type: match frame.frame_type {
                FrameType::Prismatic => "P".into(),
                _ => "R".into(),
            },
            a,
            alpha,
            d,
            theta,
            qmin: Some(joint.qmin - offset),
            qmax: Some(joint.qmax - offset),
            name: None,
        }
    };
    let zero = |frame: &Frame| frame_transform(frame, 0.0);
    // β of frame 1 stands before its α: in the base transform.
    let tilt = |frame: &Frame| {
        zero(&Frame {
            beta: frame.beta,
            ..Frame::new(FrameType::Fixed)
        })
    };
    let (base, rows, tool) = match convention {
        DhConvention::Modified => (
            zero(&frames[0]) * tilt(&frames[1]),
            (1..=n)
                .map(|j| row(j, frames[j].d, frames[j].alpha))
                .collect(),
            zero(&frames[n + 1]),
        ),
        DhConvention::Standard => {
            // The last row carries frame n+1's a and alpha, unless its β
            // stands before them: then the whole frame is the tool.
            let tool_tilted = frames[n + 1].beta != 0.0;
            (
                zero(&frames[0])
                    * zero(&Frame {
                        alpha: frames[1].alpha,
                        d: frames[1].d,
                        beta: frames[1].beta,
                        ..Frame::new(FrameType::Fixed)
                    }),
                (1..=n)
                    .map(|j| {
                        if j == n && tool_tilted {
                            row(j, 0.0, 0.0)
                        } else {
                            row(j, frames[j + 1].d, frames[j + 1].alpha)
                        }
                    })
                    .collect(),
                if tool_tilted {
                    zero(&frames[n + 1])
                } else {
                    zero(&Frame {
                        theta: frames[n + 1].theta,
                        r: frames[n + 1].r,
                        ..Frame::new(FrameType::Fixed)
                    })
                },
            )
        }
    };
    let output = TableOutput {
        name: robot.name().to_owned(),
        description: format!(
            "{} as a {} table, written by gecaro robot export",
            robot.name(),
            match convention {
                DhConvention::Standard => "standard DH",
                DhConvention::Modified => "modified DH",
            }
        ),
        convention: convention.name(),
        angle_unit: "rad",
        length_unit: "m",
        base: transform_document(&base),
        tool: transform_document(&tool),
        joint: rows,
    };
    let text = toml::to_string(&output).map_err(|error| error.to_string())?;
    let joint_calibration = numbered_joint_calibration(robot, ("table", "a DH table"), &mut notes);
    Ok(Exported {
        text: format!(
            "# {} table (gecaro robot export): one [[joint]] per joint; q is added to theta (R) or d (P).\n{text}",
            match convention {
                DhConvention::Standard =>
                    "Standard Denavit–Hartenberg: Rz(theta)·Tz(d)·Tx(a)·Rx(alpha) per row",
                DhConvention::Modified =>
                    "Modified (Craig) Denavit–Hartenberg: Rx(alpha)·Tx(a)·Rz(theta)·Tz(d) per row",
            }
        ),
        joint_calibration,
        notes,
    })
}
