//! Work regions as people write them: the range of each joint a calibrated
//! robot will be used in, `q1=-90..90deg,q3=0..120deg,q4=0.1..0.4m`.
//!
//! Each range names its joint (`q1`…`qn`) and carries its unit: on both
//! bounds (`-90deg..90deg`) or once at the end, for both (`-90..90deg`);
//! `deg` or `rad` for a revolute joint, `m`, `mm` or `um` for a prismatic
//! one. A joint not named keeps its limits. A bare range is refused rather
//! than read in a unit the writer may not have meant, and so is a range
//! beyond the joint's limits, where the robot is never used.
//!
//! A parallel robot's work region is written the same way over its
//! actuators, named as the configuration columns name them
//! (`qm1=-10..10mm,qm4=-5..5mm`; degrees or radians for a Delta's motors).

use gecaro_core::parallel_model::{ParallelModel, ParameterUnit};
use gecaro_core::{FrameType, JointRegion, Robot};

use crate::prior::signed_quantity;
use crate::written_lengths::Kind;

/// The work region of `text` for `robot` (see the module docs), joint
/// variables in radians and metres.
///
/// # Errors
/// A sentence naming the range at fault: no joint name, a joint the robot
/// does not have or named twice, no unit, a unit of the other kind, the
/// bounds in the wrong order, beyond the joint's limits.
///
/// ```
/// let robot = gecaro_io::load_robot("puma560").unwrap().robot;
/// let region = gecaro_io::parse_work_region("q1=-90..90deg, q3=-1rad..0deg", &robot).unwrap();
/// assert!((region.range(0).1 - std::f64::consts::FRAC_PI_2).abs() < 1e-15);
/// assert_eq!(region.range(2), (-1.0, 0.0));
/// assert_eq!(region.range(1), (robot.joints()[1].qmin, robot.joints()[1].qmax));
/// assert!(gecaro_io::parse_work_region("q1=-90..90", &robot).is_err());
/// ```
pub fn parse_work_region(text: &str, robot: &Robot) -> Result<JointRegion, String> {
    let limits: Vec<(f64, f64)> = robot
        .joints()
        .iter()
        .map(|joint| (joint.qmin, joint.qmax))
        .collect();
    let revolute: Vec<bool> = (1..=limits.len())
        .map(|joint| robot.frames()[joint].frame_type == FrameType::Revolute)
        .collect();
    parse_ranges(text, Names::JOINTS, &limits, &revolute)
}

/// The work region of `text` for the parallel robot `model`: the same
/// ranges as [`parse_work_region`]'s, over its actuators (m for legs, rad
/// for turning motors), named `qm1`… as the configuration columns name
/// them.
///
/// # Errors
/// As [`parse_work_region`], for actuators.
///
/// ```
/// let hexapod = gecaro_io::load_parallel_robot("hexapod").unwrap().robot;
/// let region = gecaro_io::parse_actuator_region("qm1=-10..10mm, qm4=-5mm..0mm", &hexapod).unwrap();
/// assert_eq!(region.range(0), (-0.01, 0.01));
/// assert_eq!(region.range(3), (-0.005, 0.0));
/// assert_eq!(region.range(1), (-0.1, 0.1));
/// assert!(gecaro_io::parse_actuator_region("q1=-10..10mm", &hexapod).is_err());
/// assert!(gecaro_io::parse_actuator_region("qm1=-10..10deg", &hexapod).is_err());
/// ```
pub fn parse_actuator_region(
    text: &str,
    model: &impl ParallelModel,
) -> Result<JointRegion, String> {
    let ranges: Vec<(f64, f64)> = (0..model.actuator_count())
        .map(|k| model.actuator_range(k))
        .collect();
    let angular = model.actuator_unit() == ParameterUnit::Angle;
    parse_ranges(
        text,
        Names::ACTUATORS,
        &ranges,
        &vec![angular; ranges.len()],
    )
}

/// How the ranges' owners are named: joints `q1`…, actuators `qm1`….
struct Names {
    prefix: &'static str,
    /// One of them, in words, and with its article.
    one: &'static str,
    a_one: &'static str,
    /// What makes its values angles, and lengths.
    turning: &'static str,
    sliding: &'static str,
}

impl Names {
    const JOINTS: Names = Names {
        prefix: "q",
        one: "joint",
        a_one: "a joint",
        turning: "the joint is revolute",
        sliding: "the joint is prismatic",
    };
    const ACTUATORS: Names = Names {
        prefix: "qm",
        one: "actuator",
        a_one: "an actuator",
        turning: "the actuator turns",
        sliding: "the actuator sets a length",
    };
}

/// The region of `text` (module docs) over ranges named by `names`, each
/// within its `limits` and an angle where `angular`.
fn parse_ranges(
    text: &str,
    names: Names,
    limits: &[(f64, f64)],
    angular: &[bool],
) -> Result<JointRegion, String> {
    let Names {
        prefix, one, a_one, ..
    } = names;
    let mut ranges = limits.to_vec();
    let mut named = vec![false; ranges.len()];
    let parts: Vec<&str> = text
        .split(',')
        .map(str::trim)
        .filter(|part| !part.is_empty())
        .collect();
    if parts.is_empty() {
        return Err(format!(
            "no {one} range given: write {prefix}1=-90..90deg,{prefix}2=-45..45deg"
        ));
    }
    // `qm1=-1,5..1,5mm`: a decimal comma splits a number in two parts, the
    // second of which names nothing and starts with a digit.
    for pair in parts.windows(2) {
        let (before, part) = (pair[0], pair[1]);
        if !part.contains('=')
            && part.starts_with(|c: char| c.is_ascii_digit())
            && before.ends_with(|c: char| c.is_ascii_digit())
        {
            return Err(format!(
                "'{text}' has a decimal comma (in '{before},{part}'): write decimals with a point \
                 ({prefix}1=-1.5..1.5mm); a comma separates the ranges"
            ));
        }
    }
    for part in parts {
        let (name, range) = part.split_once('=').ok_or_else(|| {
            format!(
                "'{part}' names no {one}: write {prefix}1=-90..90deg, {a_one}'s name and its range"
            )
        })?;
        let index = name
            .trim()
            .strip_prefix(prefix)
            .and_then(|number| number.parse::<usize>().ok())
            .filter(|index| (1..=ranges.len()).contains(index))
            .ok_or_else(|| {
                format!(
                    "'{}' is not {a_one} of this robot: {prefix}1 to {prefix}{}",
                    name.trim(),
                    ranges.len()
                )
            })?;
        if std::mem::replace(&mut named[index - 1], true) {
            return Err(format!("{prefix}{index} is given twice"));
        }
        let revolute = angular[index - 1];
        let (min, max) = bounds(range.trim(), revolute, &names)
            .map_err(|message| format!("{prefix}{index}: {message}"))?;
        let (qmin, qmax) = limits[index - 1];
        let shown = |value: f64| {
            if revolute {
                format!("{:.1}°", value.to_degrees())
            } else {
                format!("{:.1} mm", value * 1e3)
            }
        };
        let tolerance = gecaro_core::LIMIT_TOLERANCE;
        if min < qmin - tolerance || max > qmax + tolerance {
            return Err(format!(
                "{prefix}{index}: {}..{} reaches beyond the {one}'s limits {}..{}",
                shown(min),
                shown(max),
                shown(qmin),
                shown(qmax)
            ));
        }
        ranges[index - 1] = (min, max);
    }
    JointRegion::new(ranges).map_err(|(index, message)| format!("{prefix}{index}: {message}"))
}

/// The bounds of `MIN..MAX` with their units (module docs), in radians or
/// metres.
fn bounds(range: &str, revolute: bool, names: &Names) -> Result<(f64, f64), String> {
    let (low, high) = range
        .split_once("..")
        .ok_or_else(|| format!("'{range}' is not a range: write MIN..MAX with its unit"))?;
    let (low, high) = (low.trim(), high.trim());
    let unit_of = |text: &str| {
        text[crate::written_lengths::number_length(text)..]
            .trim()
            .to_owned()
    };
    // One unit at the end serves both bounds.
    let low = if unit_of(low).is_empty() && !unit_of(high).is_empty() {
        format!("{low}{}", unit_of(high))
    } else {
        low.to_owned()
    };
    let wanted = if revolute { Kind::Angle } else { Kind::Length };
    let value = |text: &str| -> Result<f64, String> {
        let (kind, value) = signed_quantity(text).map_err(|_| {
            format!(
                "'{range}' needs its unit: {}",
                if revolute {
                    "-90..90deg or -1.5..1.5rad"
                } else {
                    "0.1..0.4m or 100..400mm"
                }
            )
        })?;
        if kind != wanted {
            return Err(format!(
                "'{text}' is not {}",
                if revolute {
                    format!("an angle (deg, rad): {}", names.turning)
                } else {
                    format!("a length (m, mm, um): {}", names.sliding)
                }
            ));
        }
        Ok(value)
    };
    let (min, max) = (value(&low)?, value(high)?);
    if min > max {
        return Err(format!("'{range}' starts above its end"));
    }
    Ok((min, max))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranges_name_their_joint_and_unit_or_are_refused() {
        let robot = crate::load_robot("stanford").expect("ready").robot;
        let region = parse_work_region("q3=300..400mm,q1=-30..45deg", &robot).expect("region");
        assert!((region.range(2).0 - 0.3).abs() < 1e-15 && (region.range(2).1 - 0.4).abs() < 1e-15);
        assert!((region.range(0).0 + 30f64.to_radians()).abs() < 1e-15);
        let refused = |text: &str, words: &str| {
            let message = parse_work_region(text, &robot).expect_err(text);
            assert!(message.contains(words), "{text}: {message}");
        };
        refused("q1=-30..45", "needs its unit");
        refused("q3=-30..45deg", "is not a length");
        refused("q1=0.1..0.4m", "is not an angle");
        refused("q9=0..1deg", "not a joint of this robot");
        refused("q1=0..1deg,q1=0..2deg", "given twice");
        refused("q1=45..-30deg", "starts above its end");
        refused("-30..45deg", "names no joint");
        refused("q1=-1,5..1,5deg", "has a decimal comma");
        refused("q1=0..45deg,q2=-10,5..10deg", "has a decimal comma");
        refused("q1=-30deg", "is not a range");
        refused("q1=-400..400deg", "beyond the joint's limits");
        refused("", "no joint range");
    }
}
