//! Priors as people write them: standard deviations with their units.
//!
//! On the command line, `--prior 5mm,0.5deg,1%`: one σ for lengths (`m`,
//! `mm`, `um`), one for angles (`rad`, `deg`) and one for gains (`%`), in any
//! order, each recognised by its unit. In a study file, a `[prior]` table with
//! the same three and per-parameter overrides:
//!
//! ```toml
//! [prior]
//! length = "5mm"
//! angle = "0.5deg"
//! gain = "1%"
//! parameters = { d3 = "0.5mm", theta2 = "2deg", K1 = "0.2%" }
//! ```
//!
//! gecaro works in metres, radians and fractions of the gain
//! ([`gecaro_data::prior::Prior`]).

use gecaro_core::{ParameterId, ParameterKind};
use gecaro_data::prior::Prior;
use serde::Deserialize;

use crate::columns::DataUnits;
use crate::robot_file::AngleUnit;
use crate::written_lengths::{Kind, number_length, written_unit};

/// A value written with its unit, any sign, in gecaro's units (m, rad,
/// fraction): the unit table of priors and angles alike.
pub(crate) fn signed_quantity(text: &str) -> Result<(Kind, f64), String> {
    let text = text.trim();
    let (number, unit) = text.split_at(number_length(text));
    let value: f64 = number
        .trim()
        .parse()
        .map_err(|_| format!("'{text}' is not a number with a unit (e.g. 5mm, 0.5deg, 1%)"))?;
    let (kind, factor) = match unit.trim() {
        "" => return Err(format!("'{text}' has no unit: write 5mm, 0.5deg or 1%")),
        unit => written_unit(unit).ok_or_else(|| {
            format!("unknown unit '{unit}' in '{text}' (m, mm, um, rad, deg or %)")
        })?,
    };
    if !value.is_finite() {
        return Err(format!("'{text}' is not a finite number"));
    }
    Ok((kind, value * factor))
}

/// A σ written with its unit, in gecaro's units (m, rad, fraction).
pub(crate) fn quantity(text: &str) -> Result<(Kind, f64), String> {
    let (kind, value) = signed_quantity(text)?;
    if value <= 0.0 {
        return Err(format!(
            "'{}': a standard deviation must be positive",
            text.trim()
        ));
    }
    if value > gecaro_core::MAX_MAGNITUDE {
        return Err(format!(
            "'{}' is no prior (beyond 1000 m, rad or gain): leave the prior out instead",
            text.trim()
        ));
    }
    Ok((kind, value))
}

/// A sensor's standard deviation as people write it: a number in the data's
/// own unit (their length unit for lengths, their angle unit for
/// orientations), or a text with its unit (`"20um"`, `"0.02mm"`,
/// `"0.01deg"`). The command line's `--sigma`, a request's `sigma`, a study
/// file's `sigma` and Python's `sigma=` read it alike.
#[derive(Clone, Debug, PartialEq, Deserialize, serde::Serialize)]
#[serde(untagged)]
pub enum StandardDeviation {
    /// A number in the data's unit.
    Number(f64),
    /// A number with its unit.
    WithUnit(String),
}

impl std::str::FromStr for StandardDeviation {
    type Err = std::convert::Infallible;

    /// A number (`0.02`) or a number with its unit (`20um`).
    fn from_str(text: &str) -> Result<Self, Self::Err> {
        Ok(match text.trim().parse::<f64>() {
            Ok(number) => StandardDeviation::Number(number),
            Err(_) => StandardDeviation::WithUnit(text.trim().to_owned()),
        })
    }
}

/// The σ a sensor may have, of lengths (m): a nanometre to a metre.
pub(crate) const SENSOR_SIGMA: (f64, f64) = (1e-9, 1.0);

/// The largest σ of a sensor's rotations (rad): half a radian (29°).
pub(crate) const SENSOR_ROTATION_MAX: f64 = 0.5;

/// The σ a prior may have, per kind — lengths (m), angles (rad), gains
/// (relative): from 1e-9 (a parameter held) to far beyond any robot's
/// (none held).
pub(crate) const PRIOR_SIGMA: (f64, f64) = (1e-9, 1e3);

impl StandardDeviation {
    /// In metres (of a length, `rotation` false) or radians (of an
    /// orientation), with the data's `units` for a bare number.
    ///
    /// # Errors
    /// A sentence: not positive, not finite, a unit of the other kind.
    pub fn value(&self, rotation: bool, units: DataUnits) -> Result<f64, String> {
        let (sigma, shown) = match self {
            StandardDeviation::Number(number) => {
                let scale = if rotation {
                    match units.angle {
                        AngleUnit::Degrees => std::f64::consts::PI / 180.0,
                        AngleUnit::Radians => 1.0,
                    }
                } else {
                    units.length.to_metres()
                };
                (number * scale, gecaro_core::Compact(*number).to_string())
            }
            StandardDeviation::WithUnit(text) => {
                let (found, sigma) = quantity(text)?;
                let wanted = if rotation { Kind::Angle } else { Kind::Length };
                if found != wanted {
                    return Err(format!(
                        "{text:?} must be {}",
                        if rotation {
                            "an angle (rad, deg)"
                        } else {
                            "a length (m, mm, um)"
                        }
                    ));
                }
                (sigma, text.clone())
            }
        };
        if !(sigma.is_finite() && sigma > 0.0) {
            return Err(format!(
                "must be a positive standard deviation, not {shown}"
            ));
        }
        // No instrument measures below a nanometre (or nanoradian), and none
        // errs by a metre (or half a radian): such a σ is a typo or another
        // unit, and would make the fit's arithmetic overflow (issue 75).
        let (low, high, range) = if rotation {
            (
                SENSOR_SIGMA.0,
                SENSOR_ROTATION_MAX,
                "a nanoradian to half a radian",
            )
        } else {
            (SENSOR_SIGMA.0, SENSOR_SIGMA.1, "a nanometre to a metre")
        };
        if sigma < low || sigma > high {
            return Err(format!(
                "{shown} is no sensor's σ ({range}): a typo, or a number in another unit?"
            ));
        }
        Ok(sigma)
    }
}

/// An angle written with its unit (`30deg`, `0.5rad`), in radians.
///
/// # Errors
/// A sentence saying what is wrong: no unit, not an angle, not positive.
pub fn parse_angle(text: &str) -> Result<f64, String> {
    match quantity(text)? {
        (Kind::Angle, radians) => Ok(radians),
        _ => Err(format!("'{text}' is not an angle: write 30deg or 0.5rad")),
    }
}

/// An angle written with its unit and any sign (`-1.5deg`, `0.02rad`,
/// `0deg`), in radians: a value, not a σ.
///
/// # Errors
/// A sentence saying what is wrong: not a number, no unit, not an angle's.
///
/// ```
/// assert_eq!(gecaro_io::parse_signed_angle("-90deg").unwrap(), -std::f64::consts::FRAC_PI_2);
/// assert_eq!(gecaro_io::parse_signed_angle("0rad").unwrap(), 0.0);
/// assert!(gecaro_io::parse_signed_angle("2").is_err());
/// ```
pub fn parse_signed_angle(text: &str) -> Result<f64, String> {
    match signed_quantity(text) {
        Ok((Kind::Angle, radians)) => Ok(radians),
        _ => Err(format!(
            "'{}' is not an angle: write -1.5deg or 0.02rad",
            text.trim()
        )),
    }
}

/// Parses `5mm,0.5deg,1%` (see the module docs).
///
/// # Errors
/// A sentence saying what is wrong: a value without a unit, a kind given
/// twice or missing.
pub fn parse_prior(text: &str) -> Result<Prior, String> {
    let mut sigmas: [Option<f64>; 3] = [None; 3];
    for part in text.split(',').filter(|part| !part.trim().is_empty()) {
        let (kind, value) = quantity(part)?;
        let slot = &mut sigmas[kind as usize];
        if slot.is_some() {
            return Err(format!("'{text}' gives the {} σ twice", name(kind)));
        }
        *slot = Some(value);
    }
    let [Some(length), Some(angle), Some(gain)] = sigmas else {
        let missing: Vec<&str> = [Kind::Length, Kind::Angle, Kind::Gain]
            .into_iter()
            .filter(|kind| sigmas[*kind as usize].is_none())
            .map(name)
            .collect();
        return Err(format!(
            "'{text}' lacks the {} σ: give lengths, angles and gains, e.g. 5mm,0.5deg,1%",
            missing.join(" and ")
        ));
    };
    for (kind, value) in [
        (Kind::Length, length),
        (Kind::Angle, angle),
        (Kind::Gain, gain),
    ] {
        if value.is_finite() && !(PRIOR_SIGMA.0..=PRIOR_SIGMA.1).contains(&value) {
            return Err(format!(
                "'{text}': the {} σ {value:.3e} is beyond the σ a prior may have (1e-9 to 1e3, \
                 in metres, radians or a share of the gain): a typo, or another unit?",
                name(kind)
            ));
        }
    }
    Prior::new(length, angle, gain).map_err(|error| error.to_string())
}

/// The override of one parameter: `d3 = "0.5mm"`, in its kind's units.
///
/// # Errors
/// An unknown parameter name, or a unit of another kind.
pub fn parse_override(name_text: &str, value: &str) -> Result<(ParameterId, f64), String> {
    let id: ParameterId = name_text
        .parse()
        .map_err(|_| format!("'{name_text}' is not a parameter name (d3, theta2, K1, …)"))?;
    if id.kind == ParameterKind::Compliance {
        // A compliance's σ is a bare number in rad/(N·m), or m/N (issue 38).
        return match value.trim().parse::<f64>() {
            Ok(sigma) if sigma.is_finite() && sigma > 0.0 => Ok((id, sigma)),
            _ => Err(format!(
                "{name_text} is a compliance: its σ is a positive number in rad/(N·m) \
                 (m/N for a prismatic joint), e.g. 1e-5, not '{value}'"
            )),
        };
    }
    let (kind, sigma) = quantity(value)?;
    let expected = match id.kind {
        ParameterKind::D | ParameterKind::R => Kind::Length,
        ParameterKind::Alpha
        | ParameterKind::Theta
        | ParameterKind::Beta
        | ParameterKind::GravityTilt => Kind::Angle,
        ParameterKind::Gain | ParameterKind::Compliance => Kind::Gain,
    };
    if kind != expected {
        return Err(format!(
            "{name_text} is {} but '{value}' is {}",
            article(expected),
            article(kind)
        ));
    }
    Ok((id, sigma))
}

fn name(kind: Kind) -> &'static str {
    match kind {
        Kind::Length => "length",
        Kind::Angle => "angle",
        Kind::Gain => "gain",
    }
}

fn article(kind: Kind) -> &'static str {
    match kind {
        Kind::Length => "a length",
        Kind::Angle => "an angle",
        Kind::Gain => "a gain",
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn priors_are_read_in_any_order() {
        let prior = parse_prior("1%, 0.5deg ,5mm").expect("prior");
        assert!((prior.length - 0.005).abs() < 1e-15);
        assert!((prior.angle - 0.5_f64.to_radians()).abs() < 1e-15);
        assert!((prior.gain - 0.01).abs() < 1e-15);
        // Exponents belong to the number, not the unit.
        let prior = parse_prior("5e-1mm,1E-2deg,2.5e+0%").expect("prior");
        assert!((prior.length - 5e-4).abs() < 1e-18);
        assert!((prior.angle - 0.01_f64.to_radians()).abs() < 1e-18);
        assert!((prior.gain - 0.025).abs() < 1e-15);
        let (id, sigma) = parse_override("theta2", "2deg").expect("override");
        assert_eq!(id.to_string(), "theta2");
        assert!((sigma - 2_f64.to_radians()).abs() < 1e-15);
    }

    #[test]
    fn bad_priors_say_why() {
        for (text, expected) in [
            ("5mm,0.5deg", "lacks the gain σ"),
            ("5,0.5deg,1%", "has no unit"),
            ("5mm,3mm,0.5deg,1%", "length σ twice"),
            ("5ft,0.5deg,1%", "unknown unit 'ft'"),
            ("-5mm,0.5deg,1%", "must be positive"),
            ("abc", "not a number"),
            ("1e308mm,0.5deg,1%", "is no prior"),
            ("1e400mm,0.5deg,1%", "not a finite number"),
        ] {
            let error = parse_prior(text).expect_err(text);
            assert!(error.contains(expected), "{text}: {error}");
        }
        let error = parse_override("d3", "1deg").expect_err("kind");
        assert!(error.contains("d3 is a length"), "{error}");
        assert!(parse_override("x9", "1mm").is_err());
    }
}
