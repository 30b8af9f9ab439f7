//! Parallel robot files: a Gough–Stewart platform or a Delta robot in
//! TOML, as a person writes it beside the serial robots' files.
//!
//! ```toml
//! kind = "parallel"              # what makes it a parallel robot's file
//! structure = "gough-stewart"    # optional: the only structure so far
//! name = "hexapod"
//! description = "a positioning hexapod"   # optional free text
//! length_unit = "mm"             # optional: "m" (default) or "mm", every length below
//! calibrated_from = "frame"      # written by a calibration: "frame" (poses),
//!                                # "position" (one point: the platform frame not observed),
//!                                # "distance" (the base frame not observed either) or
//!                                # "leg" (a measuring leg: the frames the joints' convention)
//!
//! [[leg]]                        # six legs, leg 1 first
//! base = [482.96, -129.41, 0]    # a: the base joint's centre, base frame
//! platform = [212.13, -212.13, 0]  # b: the platform joint's centre, platform frame
//! length = 600                   # l: the leg's length at actuator value zero
//! gain = 1                       # optional: K, leg length per actuator unit (1)
//! min = -100                     # optional: the actuator's range, in the
//! max = 100                      # length unit for a gain of 1 (±0.1 m)
//! # measured = [-20, 20]         # written by a calibration that holds only where its
//!                                # data were taken: the actuator values they covered
//!
//! [tool]                         # optional: a point on the platform (its origin)
//! position = [0, 0, 100]
//! ```
//!
//! A Delta robot (`structure = "delta"`) has three `[[arm]]` tables instead:
//!
//! ```toml
//! kind = "parallel"
//! structure = "delta"
//! name = "delta"
//! length_unit = "mm"             # lengths: base, platform, upper_arm, forearm, tool
//! angle_unit = "deg"             # angles: azimuth, offset, min, max ("rad" by default)
//!
//! [[arm]]                        # three arms, arm 1 first
//! base = [200, 0, 0]             # B: the motor axis's point in the arm's plane
//! azimuth = 0                    # φ: the arm's plane
//! offset = 0                     # θ0: the arm's angle at actuator value zero (down > 0)
//! gain = 1                       # optional: K (1)
//! upper_arm = 300                # La
//! forearm = 800                  # Lb
//! platform = [50, 0, 0]          # c: the plate's joint centre, plate frame
//! min = -40                      # the actuator's range (angles)
//! max = 80
//! ```
//!
//! The platform's pose is that of its frame in the base frame; data files
//! have the actuator values `qm1…qm6` and what is measured (`x, y, z` and
//! `qw, qx, qy, qz`), as a serial robot's. gecaro writes these files in
//! metres with every digit, so load → save → load is the identity.

use std::fmt::Write as _;
use std::path::Path;

use gecaro_core::JointRegion;
use gecaro_core::delta::{Arm, Delta};
use gecaro_core::gough_stewart::{GoughStewart, Leg};
use gecaro_core::parallel_model::ParallelModel;
use gecaro_core::parallel_robot::ParallelRobot;
use nalgebra::Vector3;
use serde::Deserialize;

use crate::Error;
use crate::input::{MAX_DESCRIPTION_BYTES, read_text};
use crate::problem::{Location, model_error};
use crate::robot_file::AngleUnit;
use crate::toml_source::Source;
use crate::units::LengthUnit;

/// The keys of a parallel robot file's top level, its legs and its tool.
const TOP_KEYS: &[&str] = &[
    "kind",
    "structure",
    "name",
    "description",
    "length_unit",
    "angle_unit",
    "calibrated_from",
    "leg",
    "arm",
    "tool",
];
const LEG_KEYS: &[&str] = &[
    "base", "platform", "length", "gain", "min", "max", "measured",
];
const ARM_KEYS: &[&str] = &[
    "base",
    "azimuth",
    "offset",
    "gain",
    "upper_arm",
    "forearm",
    "platform",
    "min",
    "max",
    "measured",
];
const TOOL_KEYS: &[&str] = &["position"];

/// The value of `kind` that makes a robot file a parallel robot's.
pub const PARALLEL_KIND: &str = "parallel";

/// A parallel robot as a file holds it.
#[derive(Clone, Debug, PartialEq)]
pub struct ParallelRobotFile {
    /// The robot.
    pub robot: ParallelRobot,
    /// Free text kept from the file's `description` key.
    pub description: Option<String>,
    /// What the calibration that made this platform measured (`frame`: its
    /// poses; `position`: one point, so the platform frame is not
    /// observed; `distance`; `leg`: a measuring leg, the frames held by its
    /// joints' convention); `None` for a platform no calibration made.
    pub calibrated_from: Option<String>,
    /// The actuator values a calibration's data covered (m for a leg, rad
    /// for an arm), written when its result holds there only; compensation
    /// flags targets outside it.
    pub measured_region: Option<JointRegion>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct ParallelDocument {
    kind: String,
    structure: Option<String>,
    name: Option<String>,
    description: Option<String>,
    length_unit: Option<String>,
    angle_unit: Option<String>,
    calibrated_from: Option<String>,
    #[serde(default)]
    leg: Vec<LegDocument>,
    #[serde(default)]
    arm: Vec<ArmDocument>,
    tool: Option<ToolDocument>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct ArmDocument {
    base: [f64; 3],
    azimuth: f64,
    offset: f64,
    gain: Option<f64>,
    upper_arm: f64,
    forearm: f64,
    platform: [f64; 3],
    min: f64,
    max: f64,
    measured: Option<[f64; 2]>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct LegDocument {
    base: [f64; 3],
    platform: [f64; 3],
    length: f64,
    gain: Option<f64>,
    min: Option<f64>,
    max: Option<f64>,
    measured: Option<[f64; 2]>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct ToolDocument {
    position: [f64; 3],
}

/// Whether a robot file's text is a parallel robot's: its top level (before
/// any table) says `kind = "parallel"`.
pub fn is_parallel_robot_text(text: &str) -> bool {
    text.lines()
        .map(str::trim)
        .take_while(|line| !line.starts_with('['))
        .filter_map(|line| line.split_once('='))
        .any(|(key, value)| {
            key.trim() == "kind"
                && value.split('#').next().map(str::trim) == Some(&format!("\"{PARALLEL_KIND}\""))
        })
}

/// Reads a parallel robot file.
///
/// # Errors
/// [`Error::Read`] if the file cannot be read, [`Error::Parse`] naming the
/// line and key of the first problem otherwise.
pub fn read_parallel_robot_file(path: &Path) -> Result<ParallelRobotFile, Error> {
    let text = read_text(path, MAX_DESCRIPTION_BYTES)?;
    parse_parallel_robot_file(&text, path)
}

/// Parses the text of a parallel robot file; `path` only names it in
/// messages.
///
/// # Errors
/// [`Error::Parse`] naming the line and key of the first problem: TOML
/// syntax, an unknown key (with the closest known one), a unit that is no
/// length unit's, a structure gecaro does not model, a value no platform has.
pub fn parse_parallel_robot_file(text: &str, path: &Path) -> Result<ParallelRobotFile, Error> {
    let source = Source { path, text };
    let document: ParallelDocument = toml::from_str(text)
        .map_err(|error| source.toml_error(&error, &[TOP_KEYS, LEG_KEYS, ARM_KEYS, TOOL_KEYS]))?;
    let at_key = |key: &str, message: String| {
        Error::parse(
            path,
            source.line_of_location(&Location::Key { key: key.into() }),
            Some(key.into()),
            message,
        )
    };
    if document.kind != PARALLEL_KIND {
        return Err(at_key(
            "kind",
            format!(
                "\"{}\" is no kind of robot file gecaro reads with legs: \"{PARALLEL_KIND}\", or \
                 no `kind` for a serial robot's frames",
                document.kind
            ),
        ));
    }
    let unit = match document.length_unit.as_deref() {
        Some(name) => LengthUnit::parse(name).map_err(|message| at_key("length_unit", message))?,
        None => LengthUnit::Metres,
    };
    let angle = match document.angle_unit.as_deref() {
        Some(name) => AngleUnit::parse(name).map_err(|message| at_key("angle_unit", message))?,
        None => AngleUnit::Radians,
    };
    let (scale, radians) = (unit.to_metres(), angle.to_radians());
    let vector = |values: [f64; 3]| Vector3::from(values) * scale;
    let tool = document
        .tool
        .as_ref()
        .map_or_else(Vector3::zeros, |tool| vector(tool.position));
    let name = document
        .name
        .clone()
        .unwrap_or_else(|| crate::robot_file::fallback_name(path));
    let located = |error| source.document_error(model_error(error));
    let robot = match document.structure.as_deref().unwrap_or("gough-stewart") {
        "gough-stewart" => {
            if !document.arm.is_empty() {
                return Err(at_key(
                    "arm",
                    "a Gough–Stewart platform has legs (`[[leg]]`), not arms".into(),
                ));
            }
            let legs: Vec<Leg> = document
                .leg
                .iter()
                .map(|leg| {
                    let default = Leg::new(Vector3::zeros(), Vector3::zeros(), 0.0);
                    Leg {
                        base: vector(leg.base),
                        platform: vector(leg.platform),
                        length: leg.length * scale,
                        gain: leg.gain.unwrap_or(default.gain),
                        min: leg.min.map_or(default.min, |min| min * scale),
                        max: leg.max.map_or(default.max, |max| max * scale),
                    }
                })
                .collect();
            ParallelRobot::GoughStewart(GoughStewart::new(&name, legs, tool).map_err(located)?)
        }
        "delta" => {
            if !document.leg.is_empty() {
                return Err(at_key(
                    "leg",
                    "a Delta robot has arms (`[[arm]]`), not legs".into(),
                ));
            }
            let arms: Vec<Arm> = document
                .arm
                .iter()
                .map(|arm| Arm {
                    base: vector(arm.base),
                    azimuth: arm.azimuth * radians,
                    offset: arm.offset * radians,
                    gain: arm.gain.unwrap_or(1.0),
                    upper_arm: arm.upper_arm * scale,
                    forearm: arm.forearm * scale,
                    platform: vector(arm.platform),
                    min: arm.min * radians,
                    max: arm.max * radians,
                })
                .collect();
            ParallelRobot::Delta(Delta::new(&name, arms, tool).map_err(located)?)
        }
        other => {
            return Err(at_key(
                "structure",
                format!(
                    "\"{other}\" is not a structure gecaro models: \"gough-stewart\" (six legs \
                     between a base and a platform) or \"delta\" (three arms and parallelograms)"
                ),
            ));
        }
    };
    // The measures a platform is calibrated from, by the names of
    // `gecaro_calib`'s `PlatformMeasure` (its tests read each back).
    const CALIBRATED_FROM: [&str; 4] = ["frame", "position", "distance", "leg"];
    if let Some(measured) = document.calibrated_from.as_deref()
        && !CALIBRATED_FROM.contains(&measured)
    {
        return Err(at_key(
            "calibrated_from",
            format!(
                "\"{measured}\" is not what a platform is calibrated from: \"frame\", \"position\", \
                 \"distance\" or \"leg\""
            ),
        ));
    }
    // The measured region: every actuator's range, or none.
    let measured: Vec<Option<[f64; 2]>> = match robot {
        ParallelRobot::GoughStewart(_) => document
            .leg
            .iter()
            .map(|leg| leg.measured.map(|range| range.map(|value| value * scale)))
            .collect(),
        ParallelRobot::Delta(_) => document
            .arm
            .iter()
            .map(|arm| arm.measured.map(|range| range.map(|value| value * radians)))
            .collect(),
    };
    let measured_region = if measured.iter().all(Option::is_none) {
        None
    } else {
        let ranges: Option<Vec<(f64, f64)>> = measured
            .iter()
            .map(|range| range.map(|[min, max]| (min, max)))
            .collect();
        let ranges = ranges.ok_or_else(|| {
            at_key(
                "measured",
                "the measured range is given for some actuators only: a calibration writes it \
                 for every one"
                    .into(),
            )
        })?;
        Some(JointRegion::new(ranges).map_err(|(actuator, message)| {
            at_key(
                "measured",
                format!("actuator {actuator}'s measured range: {message}"),
            )
        })?)
    };
    Ok(ParallelRobotFile {
        robot,
        description: document.description,
        calibrated_from: document.calibrated_from,
        measured_region,
    })
}

/// The text of a parallel robot file: metres, every digit (Rust's shortest
/// round-trip form), so that reading it gives the same platform.
pub fn format_parallel_robot_file(file: &ParallelRobotFile) -> String {
    let robot = &file.robot;
    let mut text = String::new();
    let _ = writeln!(text, "kind = \"{PARALLEL_KIND}\"");
    let _ = writeln!(text, "structure = \"{}\"", robot.structure());
    let _ = writeln!(text, "name = {}", toml_string(robot.name()));
    if let Some(description) = &file.description {
        let _ = writeln!(text, "description = {}", toml_string(description));
    }
    if let Some(measured) = &file.calibrated_from {
        let _ = writeln!(text, "calibrated_from = {}", toml_string(measured));
    }
    let triple = |v: &Vector3<f64>| format!("[{:?}, {:?}, {:?}]", v.x, v.y, v.z);
    match robot {
        ParallelRobot::GoughStewart(platform) => {
            for (index, leg) in platform.legs().iter().enumerate() {
                let _ = writeln!(text, "\n[[leg]]");
                let _ = writeln!(text, "base = {}", triple(&leg.base));
                let _ = writeln!(text, "platform = {}", triple(&leg.platform));
                let _ = writeln!(text, "length = {:?}", leg.length);
                let _ = writeln!(text, "gain = {:?}", leg.gain);
                let _ = writeln!(text, "min = {:?}", leg.min);
                let _ = writeln!(text, "max = {:?}", leg.max);
                measured_line(&mut text, file, index);
            }
        }
        ParallelRobot::Delta(delta) => {
            for (index, arm) in delta.arms().iter().enumerate() {
                let _ = writeln!(text, "\n[[arm]]");
                let _ = writeln!(text, "base = {}", triple(&arm.base));
                let _ = writeln!(text, "azimuth = {:?}", arm.azimuth);
                let _ = writeln!(text, "offset = {:?}", arm.offset);
                let _ = writeln!(text, "gain = {:?}", arm.gain);
                let _ = writeln!(text, "upper_arm = {:?}", arm.upper_arm);
                let _ = writeln!(text, "forearm = {:?}", arm.forearm);
                let _ = writeln!(text, "platform = {}", triple(&arm.platform));
                let _ = writeln!(text, "min = {:?}", arm.min);
                let _ = writeln!(text, "max = {:?}", arm.max);
                measured_line(&mut text, file, index);
            }
        }
    }
    let _ = writeln!(text, "\n[tool]\nposition = {}", triple(&robot.tool()));
    text
}

/// The `measured` line of actuator `index`, when the file has a measured
/// region.
fn measured_line(text: &mut String, file: &ParallelRobotFile, index: usize) {
    if let Some(region) = &file.measured_region {
        let (min, max) = region.range(index);
        let _ = writeln!(
            text,
            "measured = [{min:?}, {max:?}] # the range the calibration's data covered"
        );
    }
}

/// A TOML basic string.
fn toml_string(text: &str) -> String {
    toml::Value::String(text.to_owned()).to_string()
}

#[cfg(test)]
mod tests {
    use super::*;

    const HEXAPOD: &str = include_str!("../../../robots/hexapod.toml");

    #[test]
    fn the_ready_hexapod_reads_in_millimetres_and_writes_back_in_metres() {
        let path = Path::new("hexapod.toml");
        assert!(is_parallel_robot_text(HEXAPOD));
        let file = parse_parallel_robot_file(HEXAPOD, path).expect("hexapod");
        let ParallelRobot::GoughStewart(platform) = &file.robot else {
            panic!("a Gough–Stewart platform");
        };
        let first = &platform.legs()[0];
        assert!((first.length - 0.6).abs() < 1e-15);
        assert!((first.max - 0.1).abs() < 1e-15);
        let written = format_parallel_robot_file(&file);
        assert!(is_parallel_robot_text(&written));
        let again = parse_parallel_robot_file(&written, path).expect("written");
        assert_eq!(again, file);
    }

    #[test]
    fn mistakes_are_named_with_their_line_and_key() {
        let path = Path::new("bad.toml");
        let with = |from: &str, to: &str| {
            let text = HEXAPOD.replacen(from, to, 1);
            parse_parallel_robot_file(&text, path)
                .expect_err("refused")
                .to_string()
        };
        let error = with("gain = 1", "gian = 1");
        assert!(
            error.contains("unknown key `gian` (did you mean `gain`?)"),
            "{error}"
        );
        let error = with("length_unit = \"mm\"", "length_unit = \"inch\"");
        assert!(error.contains("must be \"m\" or \"mm\""), "{error}");
        // Leg 1's gain is on the file's line of `gain` in the first [[leg]].
        let line = HEXAPOD
            .lines()
            .position(|line| line.starts_with("gain"))
            .expect("gain")
            + 1;
        let error = with("gain = 1", "gain = 0");
        assert!(
            error.contains(&format!("bad.toml:{line}")) && error.contains("a gain of zero"),
            "{error}"
        );
        let error = with("structure = \"gough-stewart\"", "structure = \"stewart\"");
        assert!(error.contains("not a structure gecaro models"), "{error}");
        let error = with("structure = \"gough-stewart\"", "structure = \"delta\"");
        assert!(error.contains("a Delta robot has arms"), "{error}");
    }

    #[test]
    fn the_ready_delta_reads_in_millimetres_and_degrees_and_writes_back() {
        let text = include_str!("../../../robots/delta.toml");
        let path = Path::new("delta.toml");
        let file = parse_parallel_robot_file(text, path).expect("delta");
        let ParallelRobot::Delta(delta) = &file.robot else {
            panic!("a Delta robot");
        };
        let second = &delta.arms()[1];
        assert!((second.azimuth - 120f64.to_radians()).abs() < 1e-15);
        assert!((second.forearm - 0.8).abs() < 1e-15);
        assert!((second.min + 40f64.to_radians()).abs() < 1e-15);
        let again =
            parse_parallel_robot_file(&format_parallel_robot_file(&file), path).expect("written");
        assert_eq!(again, file);
        let error =
            parse_parallel_robot_file(&text.replacen("forearm = 800", "forearm = 0", 1), path)
                .expect_err("refused")
                .to_string();
        let line = text
            .lines()
            .position(|line| line.starts_with("forearm"))
            .expect("line")
            + 1;
        assert!(error.contains(&format!("delta.toml:{line}")), "{error}");
        assert!(error.contains("not the length of an arm"), "{error}");
    }

    /// A calibration's measured region is written per actuator and read
    /// back in the file's units; one given for some actuators only is
    /// refused with its key.
    #[test]
    fn a_measured_region_reads_back_and_is_whole_or_absent() {
        let path = Path::new("hexapod.toml");
        let mut file = parse_parallel_robot_file(HEXAPOD, path).expect("hexapod");
        let ranges: Vec<(f64, f64)> = (0..6)
            .map(|k| (-0.01 - 1e-3 * k as f64, 0.02 + 1e-4 * k as f64))
            .collect();
        file.measured_region = Some(JointRegion::new(ranges).expect("region"));
        let written = format_parallel_robot_file(&file);
        assert_eq!(
            parse_parallel_robot_file(&written, path).expect("written"),
            file
        );
        // In millimetres as the ready file states its legs.
        let once = HEXAPOD.replacen("gain = 1", "gain = 1\nmeasured = [-20, 30]", 1);
        let error = parse_parallel_robot_file(&once, path)
            .expect_err("refused")
            .to_string();
        assert!(error.contains("some actuators only"), "{error}");
        let every = HEXAPOD.replace("gain = 1", "gain = 1\nmeasured = [-20, 30]");
        let read = parse_parallel_robot_file(&every, path).expect("every leg");
        let region = read.measured_region.expect("a region");
        assert!(
            (region.range(5).0 + 0.02).abs() < 1e-15 && (region.range(5).1 - 0.03).abs() < 1e-15
        );
        let reversed = HEXAPOD.replace("gain = 1", "gain = 1\nmeasured = [30, -20]");
        let error = parse_parallel_robot_file(&reversed, path)
            .expect_err("refused")
            .to_string();
        assert!(error.contains("measured range"), "{error}");
    }

    #[test]
    fn a_serial_robot_file_is_not_a_parallel_one() {
        let stanford = include_str!("../../../robots/stanford.toml");
        assert!(!is_parallel_robot_text(stanford));
        assert!(!is_parallel_robot_text(
            "name = \"x\"\n[[frame]]\nkind = \"parallel\"\n"
        ));
    }
}
