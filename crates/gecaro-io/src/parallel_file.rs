//! Parallel robot files: a Gough–Stewart platform in TOML, as a person
//! writes it beside the serial robots' files.
//!
//! ```toml
//! kind = "parallel"              # what makes it a parallel robot's file
//! structure = "gough-stewart"    # optional: the only structure so far
//! name = "hexapod"
//! description = "a positioning hexapod"   # optional free text
//! length_unit = "mm"             # optional: "m" (default) or "mm", every length below
//! calibrated_from = "frame"      # written by a calibration: "frame" (poses) or
//!                                # "position" (one point: the platform frame not observed)
//!
//! [[leg]]                        # six legs, leg 1 first
//! base = [482.96, -129.41, 0]    # a: the base joint's centre, base frame
//! platform = [212.13, -212.13, 0]  # b: the platform joint's centre, platform frame
//! length = 600                   # l: the leg's length at actuator value zero
//! gain = 1                       # optional: K, leg length per actuator unit (1)
//! min = -100                     # optional: the actuator's range, in the
//! max = 100                      # length unit for a gain of 1 (±0.1 m)
//!
//! [tool]                         # optional: a point on the platform (its origin)
//! position = [0, 0, 100]
//! ```
//!
//! The platform's pose is that of its frame in the base frame; data files
//! have the actuator values `qm1…qm6` and what is measured (`x, y, z` and
//! `qw, qx, qy, qz`), as a serial robot's. gecaro writes these files in
//! metres with every digit, so load → save → load is the identity.

use std::fmt::Write as _;
use std::path::Path;

use gecaro_core::gough_stewart::{GoughStewart, Leg};
use nalgebra::Vector3;
use serde::Deserialize;

use crate::Error;
use crate::input::{MAX_DESCRIPTION_BYTES, read_text};
use crate::problem::{Location, model_error};
use crate::toml_source::Source;
use crate::units::LengthUnit;

/// The keys of a parallel robot file's top level, its legs and its tool.
const TOP_KEYS: &[&str] = &[
    "kind",
    "structure",
    "name",
    "description",
    "length_unit",
    "calibrated_from",
    "leg",
    "tool",
];
const LEG_KEYS: &[&str] = &["base", "platform", "length", "gain", "min", "max"];
const TOOL_KEYS: &[&str] = &["position"];

/// The value of `kind` that makes a robot file a parallel robot's.
pub const PARALLEL_KIND: &str = "parallel";

/// A parallel robot as a file holds it.
#[derive(Clone, Debug, PartialEq)]
pub struct ParallelRobotFile {
    /// The platform.
    pub platform: GoughStewart,
    /// Free text kept from the file's `description` key.
    pub description: Option<String>,
    /// What the calibration that made this platform measured (`frame`: its
    /// poses; `position`: one point, so the platform frame is not
    /// observed); `None` for a platform no calibration made.
    pub calibrated_from: Option<String>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct ParallelDocument {
    kind: String,
    structure: Option<String>,
    name: Option<String>,
    description: Option<String>,
    length_unit: Option<String>,
    calibrated_from: Option<String>,
    #[serde(default)]
    leg: Vec<LegDocument>,
    tool: Option<ToolDocument>,
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
        .map_err(|error| source.toml_error(&error, &[TOP_KEYS, LEG_KEYS, TOOL_KEYS]))?;
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
    if let Some(structure) = document.structure.as_deref()
        && structure != "gough-stewart"
    {
        return Err(at_key(
            "structure",
            format!(
                "\"{structure}\" is not a structure gecaro models yet; it models \"gough-stewart\" \
                 (six legs between a base and a platform)"
            ),
        ));
    }
    let unit = match document.length_unit.as_deref() {
        Some(name) => LengthUnit::parse(name).map_err(|message| at_key("length_unit", message))?,
        None => LengthUnit::Metres,
    };
    let scale = unit.to_metres();
    let vector = |values: [f64; 3]| Vector3::from(values) * scale;
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
    let tool = document
        .tool
        .as_ref()
        .map_or_else(Vector3::zeros, |tool| vector(tool.position));
    let name = document
        .name
        .clone()
        .unwrap_or_else(|| crate::robot_file::fallback_name(path));
    let platform = GoughStewart::new(&name, legs, tool)
        .map_err(|error| source.document_error(model_error(error)))?;
    if let Some(measured) = document.calibrated_from.as_deref()
        && !["frame", "position"].contains(&measured)
    {
        return Err(at_key(
            "calibrated_from",
            format!(
                "\"{measured}\" is not what a platform is calibrated from: \"frame\" or \"position\""
            ),
        ));
    }
    Ok(ParallelRobotFile {
        platform,
        description: document.description,
        calibrated_from: document.calibrated_from,
    })
}

/// The text of a parallel robot file: metres, every digit (Rust's shortest
/// round-trip form), so that reading it gives the same platform.
pub fn format_parallel_robot_file(file: &ParallelRobotFile) -> String {
    let platform = &file.platform;
    let mut text = String::new();
    let _ = writeln!(text, "kind = \"{PARALLEL_KIND}\"");
    let _ = writeln!(text, "structure = \"gough-stewart\"");
    let _ = writeln!(text, "name = {}", toml_string(platform.name()));
    if let Some(description) = &file.description {
        let _ = writeln!(text, "description = {}", toml_string(description));
    }
    if let Some(measured) = &file.calibrated_from {
        let _ = writeln!(text, "calibrated_from = {}", toml_string(measured));
    }
    let triple = |v: &Vector3<f64>| format!("[{:?}, {:?}, {:?}]", v.x, v.y, v.z);
    for leg in platform.legs() {
        let _ = writeln!(text, "\n[[leg]]");
        let _ = writeln!(text, "base = {}", triple(&leg.base));
        let _ = writeln!(text, "platform = {}", triple(&leg.platform));
        let _ = writeln!(text, "length = {:?}", leg.length);
        let _ = writeln!(text, "gain = {:?}", leg.gain);
        let _ = writeln!(text, "min = {:?}", leg.min);
        let _ = writeln!(text, "max = {:?}", leg.max);
    }
    let _ = writeln!(text, "\n[tool]\nposition = {}", triple(&platform.tool()));
    text
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
        let first = &file.platform.legs()[0];
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
        let error = with("structure = \"gough-stewart\"", "structure = \"delta\"");
        assert!(
            error.contains("not a structure gecaro models yet"),
            "{error}"
        );
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
