//! The tool a program's targets are for (issue 74): compensation moves the
//! point that works, not a frame nobody measured.
//!
//! A program taught or written for a tool (a welding torch, a gripper's
//! centre, a reflector) commands that tool's point: `compensate --tool`
//! names it. With it, both robots get the tool as their frame n+1 (the
//! same pose: the tool as the controller knows it), so a joint target
//! means the pose the nominal model gives that tool, and a Cartesian
//! target is a pose or point of the tool. The tool is
//!
//! - a tool the calibration identified, by its name in the calibrated
//!   robot file's `[tools]` (a study's reflectors, written there by
//!   `identify`): its identified pose; or
//! - a pose in frame n+1, `x,y,z` with the lengths' units and optionally
//!   `,qw,qx,qy,qz` ([`gecaro_io::parse_tool_pose`]).
//!
//! Where every set of the calibration measured a named tool, frame n+1
//! itself was never observed: it keeps its nominal pose, and the last
//! joint's errors live in the tools' identified poses (docs/studies.md).
//! Frame n+1 there — `tool0`, or a tool posed in it — carries those
//! errors uncorrected (7× the noise floor in the trial of issue 74, with
//! "500 reached" printed): it is refused, with the tools that were
//! calibrated named.

use gecaro_io::RobotFile;
use nalgebra::IsometryMatrix3;

use crate::error::AppError;

/// The pose in frame n+1 of the tool `tool` names on `calibrated`; `None`
/// for frame n+1 itself.
///
/// # Errors
/// Frame n+1, or a tool posed in it, on a robot whose calibration did not
/// observe frame n+1; a name the calibrated file does not hold and a text
/// that is no pose.
pub(super) fn program_tool(
    calibrated: &RobotFile,
    tool: Option<&str>,
) -> Result<Option<IsometryMatrix3<f64>>, AppError> {
    let identified: Vec<&str> = calibrated
        .tools
        .iter()
        .map(|tool| tool.name.as_str())
        .collect();
    let unobserved = |what: &str| {
        AppError::setting(
            "tool",
            format!(
                "{what} of {} is not calibrated: every set of its calibration measured a named \
                 tool, so frame n+1 kept its nominal pose and the last joint's errors sit in \
                 the tools' identified poses; compensate a tool the calibration identified \
                 (tool {}), or measure the working tool in a set of the study",
                calibrated.robot.name(),
                identified.join(", ")
            ),
        )
    };
    let Some(text) = tool.map(str::trim) else {
        return if calibrated.tool_frame_observed {
            Ok(None)
        } else {
            Err(unobserved("frame n+1 (tool0)"))
        };
    };
    if let Some(found) = calibrated.tools.iter().find(|tool| tool.name == text) {
        return Ok(Some(found.pose));
    }
    if !text.contains(',') {
        let held = if identified.is_empty() {
            "identifies no tool".to_owned()
        } else {
            format!("identifies {}", identified.join(", "))
        };
        return Err(AppError::setting(
            "tool",
            format!(
                "no tool '{text}' in {}: it {held}; or give the tool's pose in frame n+1 \
                 (0,0,120mm)",
                calibrated.robot.name()
            ),
        ));
    }
    let pose =
        gecaro_io::parse_tool_pose(text).map_err(|message| AppError::setting("tool", message))?;
    if !calibrated.tool_frame_observed {
        return Err(unobserved(&format!("a tool posed in frame n+1 ({text})")));
    }
    Ok(Some(pose))
}

#[cfg(test)]
mod tests {
    use super::*;
    use gecaro_io::IdentifiedTool;

    #[test]
    fn the_tool_is_named_posed_or_refused_where_frame_n1_was_not_seen() {
        let mut file = gecaro_io::load_robot("industrial6").expect("ready");
        assert_eq!(program_tool(&file, None).expect("tool0"), None);
        let posed = program_tool(&file, Some("0,0,120mm")).expect("posed");
        assert!((posed.expect("a pose").translation.vector.z - 0.12).abs() < 1e-15);
        let message = program_tool(&file, Some("torch"))
            .expect_err("unknown")
            .to_string();
        assert!(message.contains("no tool 'torch'") && message.contains("identifies no tool"));
        let message = program_tool(&file, Some("10,0,120mm"))
            .expect_err("mixed")
            .to_string();
        assert!(message.contains("mixes units"), "{message}");
        file.tools.push(IdentifiedTool {
            name: "smr_a".into(),
            pose: IsometryMatrix3::translation(0.04, 0.025, 0.09),
        });
        file.tool_frame_observed = false;
        let named = program_tool(&file, Some("smr_a"))
            .expect("named")
            .expect("a pose");
        assert_eq!(named.translation.vector.x, 0.04);
        for tool in [None, Some("0,0,120mm")] {
            let message = program_tool(&file, tool)
                .expect_err("unobserved")
                .to_string();
            assert!(
                message.contains("is not calibrated") && message.contains("tool smr_a"),
                "{message}"
            );
        }
    }
}
