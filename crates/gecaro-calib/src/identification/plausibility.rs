//! Plausibility of the robot an identification writes: values no real
//! robot has, each named with its likely cause (see [`super::Verdict`]).
//!
//! Every parameter that the written robot changes is judged — the base
//! parameters, and those outside the base set that a later phase moved —
//! as a physical value against its nominal one:
//!
//! - a length moved by more than the robot's size (the sum of its |d| and
//!   |r|, at least 0.1 m; ten times that for frames 0 and 1, which place the
//!   robot in a measurement frame that may stand anywhere in the cell);
//! - an angle turned by more than 45° (beyond frames 0, 1 and n+1, which
//!   place the robot and its tool, turned any way);
//! - a gain off by more than 20 %;
//! - a deviation beyond 5 σ of a stated prior;
//! - a value that is not finite or beyond what a robot file holds
//!   ([`gecaro_core::MAX_MAGNITUDE`]): the iteration ran away along a
//!   direction the data do not determine.
//!
//! A regrouped base parameter carries the combination of Appendix III
//! (though a base length of frame 0 or 1 beyond the cell is implausible
//! whatever it carries: a nearly singular measurement frame wrote it),
//! `Δη_b + Σ β_j Δη_j`, not a physical deviation: it is judged expanded,
//! its deviation shared among the parameters of the combination in the way
//! the prior finds most likely (`Δη_j = σ_j² β_j Δ / Σ_k σ_k² β_k²`, the
//! minimum-norm split in units of each σ; 1 cm, 1°, 1 % without a prior),
//! so `θ6 − 525.8·r7` moved by 5 rad is r7 moved by 1 cm, which is
//! plausible, while a combination that needs metres everywhere is not.
//!
//! The robot's size is judged too: the inner links' lengths (d and r of
//! frames 2..n) against their nominal values by the scale that maps one
//! onto the other. A robot that comes out at less than a fifth or more than
//! five times its nominal size was fitted to data in the wrong unit (metres
//! read as millimetres shrink it 1000×), whatever its residuals say.

use gecaro_core::{MAX_MAGNITUDE, ParameterId, ParameterKind, Robot};

use super::parameter::IdentifiedParameter;
use super::verdict::Implausible;
use crate::prior::Prior;

/// Angles beyond frames 0 and 1 turned by more than this are implausible.
const ANGLE_LIMIT: f64 = std::f64::consts::FRAC_PI_4;
/// Gains off by more than this fraction are implausible.
const GAIN_LIMIT: f64 = 0.2;
/// Deviations beyond this many prior σ are implausible.
const PRIOR_LIMIT: f64 = 5.0;
/// Frames 0 and 1 may move this many robot sizes (a robot cell).
const CELL: f64 = 10.0;
/// The robot's size may change by at most this factor either way: a
/// length unit mixed up changes it 1000× (or 25.4× for inches), while the
/// inner links of a robot with few of them (the Stanford's r2 of 0.2 m)
/// may double at errors of 20 cm.
const SIZE_LIMIT: f64 = 5.0;

/// What plausibility is judged on.
pub(super) struct Written<'a> {
    /// The nominal robot.
    pub(super) nominal: &'a Robot,
    /// The robot written.
    pub(super) calibrated: &'a Robot,
    /// The identified base parameters.
    pub(super) parameters: &'a [IdentifiedParameter],
    /// Parameters outside the base set that the written robot moved.
    pub(super) moved: &'a [IdentifiedParameter],
    /// The prior, if one was given.
    pub(super) prior: Option<&'a Prior>,
    /// The σ that expands regrouped deviations: the prior's, or 1 cm, 1°, 1 %.
    pub(super) expansion: &'a Prior,
}

/// The values of the written robot that no real robot has (module docs).
pub(super) fn implausible(written: &Written<'_>) -> Vec<Implausible> {
    let size = robot_size(written.nominal);
    let last = written.nominal.frames().len() - 1;
    let mut found: Vec<Implausible> = written
        .parameters
        .iter()
        .chain(written.moved)
        .filter_map(|p| judge_parameter(written, p, size, last))
        .collect();
    if let Some(size) = size_change(written.nominal, written.calibrated) {
        found.push(size);
    }
    found
}

/// The robot's size: the sum of its frames' |d| and |r|, at least 0.1 m.
fn robot_size(robot: &Robot) -> f64 {
    robot
        .frames()
        .iter()
        .map(|frame| frame.d.abs() + frame.r.abs())
        .sum::<f64>()
        .max(0.1)
}

/// Why the deviation `deviation` of parameter `id` (nominal `nominal`) is
/// one no robot has, if it is (`size`: the robot's; `tool`: the index of
/// frame n+1).
fn beyond_limits(
    id: ParameterId,
    nominal: f64,
    deviation: f64,
    size: f64,
    tool: usize,
) -> Option<String> {
    use std::f64::consts::TAU;
    // Frames 0 and 1 place the robot in the measurement frame, which may
    // stand anywhere in the cell (a tracker metres away, turned any way):
    // only lengths beyond the cell are implausible there. The tool may be
    // turned any way too (a point tool's direction is written with α and θ
    // of frame n+1), and reach as far as the robot.
    let geometric = !matches!(
        id.kind,
        ParameterKind::Gain | ParameterKind::Compliance | ParameterKind::GravityTilt
    );
    let placement = geometric && id.frame <= 1;
    let turned_freely = placement || (geometric && id.frame == tool);
    let reach = if placement { CELL * size } else { size };
    match id.kind {
        ParameterKind::D | ParameterKind::R if deviation.abs() > reach => Some(format!(
            "moved by {deviation:.3} m, more than {} ({reach:.2} m)",
            if placement {
                "a robot cell"
            } else {
                "the robot's size"
            }
        )),
        ParameterKind::Alpha | ParameterKind::Theta | ParameterKind::Beta if !turned_freely => {
            let turned = deviation - TAU * (deviation / TAU).round();
            (turned.abs() > ANGLE_LIMIT).then(|| format!("turned by {:.1}°", turned.to_degrees()))
        }
        ParameterKind::Gain if deviation.abs() > GAIN_LIMIT * nominal.abs() => Some(format!(
            "off by {:+.1} %",
            100.0 * deviation / nominal.abs().max(f64::MIN_POSITIVE)
        )),
        _ => None,
    }
}

/// The softest joint a serial robot has (rad/(N·m), or m/N): 100 N·m would
/// turn it by 0.1 rad. Beyond, a compliance is not a joint's (issue 38).
const COMPLIANCE_LIMIT: f64 = 1e-3;

/// A compliance is implausible below zero (beyond 3σ: a joint stiffer than
/// rigid) or beyond [`COMPLIANCE_LIMIT`] (beyond 3σ too: a value the data
/// barely determine is named by the excitation check instead).
fn judge_compliance(p: &IdentifiedParameter) -> Option<Implausible> {
    let significant = p.std.is_finite() && p.identified < -3.0 * p.std;
    let (why, cause) = if significant {
        (
            format!(
                "is negative, {:.3e} (σ {:.1e}): a joint that straightens against its load",
                p.identified, p.std
            ),
            "the loads are wrong: the masses, the payloads or the gravity direction; or the \
             compliance absorbs a geometric error these data do not separate from it: measure \
             with two payloads or more"
                .to_owned(),
        )
    } else if p.identified.abs() > COMPLIANCE_LIMIT
        && (!p.std.is_finite() || p.identified.abs() - 3.0 * p.std > COMPLIANCE_LIMIT)
    {
        (
            format!(
                "is {:.3e}, softer than any joint ({COMPLIANCE_LIMIT:e} turns 0.1 rad under \
                 100 N·m)",
                p.identified
            ),
            "the masses or the payload are in another unit, or the compliance absorbs an \
             error that is not elastic"
                .to_owned(),
        )
    } else {
        return None;
    };
    Some(Implausible {
        name: p.name.clone(),
        why,
        cause,
    })
}

/// The farthest gravity's direction may lean from the one a robot file
/// states (radians): a tracker's frame set up by eye is levelled to a
/// degree or two; beyond this, the stated gravity is wrong.
const TILT_LIMIT: f64 = 5.0 * std::f64::consts::PI / 180.0;

/// A gravity tilt is implausible beyond [`TILT_LIMIT`] (beyond 3σ too).
fn judge_tilt(p: &IdentifiedParameter) -> Option<Implausible> {
    let beyond = p.identified.abs() > TILT_LIMIT
        && (!p.std.is_finite() || p.identified.abs() - 3.0 * p.std > TILT_LIMIT);
    beyond.then(|| Implausible {
        name: p.name.clone(),
        why: format!(
            "leans gravity by {:.1}° from the direction the robot file states, more than {:.0}°",
            p.identified.to_degrees(),
            TILT_LIMIT.to_degrees()
        ),
        cause: "the robot file's gravity is not stated in the measurement frame (gravity = \
                [x, y, z] in its mass section), or the tilts absorb an error that is not elastic"
            .to_owned(),
    })
}

/// The judgement of one written parameter (see the module docs).
fn judge_parameter(
    written: &Written<'_>,
    p: &IdentifiedParameter,
    size: f64,
    last: usize,
) -> Option<Implausible> {
    let id = p.parameter?;
    let deviation = p.identified - p.nominal;
    if !p.identified.is_finite() || p.identified.abs() > MAX_MAGNITUDE {
        return Some(Implausible {
            name: p.name.clone(),
            why: format!(
                "is {:.3e}, beyond what a robot file holds (±{MAX_MAGNITUDE})",
                p.identified
            ),
            cause: "the iteration ran away along a direction these data do not determine: \
                    identify with a prior, or add configurations that move it"
                .to_owned(),
        });
    }
    // Whatever the combination a regrouped value carries, a robot file that
    // puts the base farther than a robot cell from the measurement frame's
    // origin was written by a nearly singular frame.
    let length = matches!(id.kind, ParameterKind::D | ParameterKind::R);
    if p.is_regrouped() && length && id.frame <= 1 && p.identified.abs() > CELL * size {
        return Some(Implausible {
            name: p.name.clone(),
            why: format!(
                "is {:.3} m, farther than a robot cell ({:.2} m)",
                p.identified,
                CELL * size
            ),
            cause: "a nearly singular measurement frame: its z axis nearly parallel to axis 1 \
                    and far from it; state the frame in the robot file (robot reframe, world \
                    frame) and identify again"
                .to_owned(),
        });
    }
    // A joint's θ turned far is its zero, before any guess at its cause;
    // a combination only when no member can carry it (a tool turned any
    // way carries the last joint's).
    if p.is_regrouped() {
        let found = judge_expanded(written, p, id, size)?;
        return Some(joint_zero(written, p, id).unwrap_or(found));
    }
    if let Some(zero) = joint_zero(written, p, id) {
        return Some(zero);
    }
    if id.kind == ParameterKind::Compliance {
        return judge_compliance(p);
    }
    if id.kind == ParameterKind::GravityTilt {
        return judge_tilt(p);
    }
    // Why it is implausible, and whether it is against the prior (the
    // cause then differs), told apart by value, not by the words.
    let (why, against_prior) = match beyond_limits(id, p.nominal, deviation, size, last) {
        Some(why) => (why, false),
        None => {
            let prior = p.prior_std.filter(|_| written.prior.is_some())?;
            if deviation.abs() <= PRIOR_LIMIT * prior {
                return None;
            }
            let times = deviation.abs() / prior;
            (format!("moved {times:.1} times its prior σ"), true)
        }
    };
    let cause = if against_prior {
        "the data contradict the prior: widen it, or look for a model error that this \
         parameter absorbs"
            .to_owned()
    } else if p.std.is_nan() {
        "moved outside the base set to reproduce these data: the nominal structure does not \
         hold at this robot, or the data are in another unit or frame"
            .to_owned()
    } else if deviation.abs() < 3.0 * p.std || !p.std.is_finite() {
        format!(
            "not determined by these data, σ {:.2e}: add configurations that move it, or a prior",
            p.std
        )
    } else if id.kind != ParameterKind::Gain && id.frame <= 1 {
        "the measurement frame (world frame) is far from the nominal one, or the base is \
         tilted: state it in the robot file (robot reframe, world frame) and identify again"
            .to_owned()
    } else if id.kind != ParameterKind::Gain && id.frame == last {
        "the tool is far from the nominal one: state it in the robot file (robot reframe, tool \
         frame) and identify again"
            .to_owned()
    } else {
        "determined by the data: a model error elsewhere (an unmodelled tilt, coupling or \
         compliance, a wrong nominal) is absorbed here"
            .to_owned()
    };
    Some(Implausible {
        name: p.name.clone(),
        why,
        cause,
    })
}

/// A joint's zero far from the robot file's: θ_j of a revolute joint j ≥ 2
/// (its offset, eq. 4; as such or carrying a combination) turned by more
/// than [`ANGLE_LIMIT`], well determined. Nothing else a calibration finds
/// turns a joint's θ that far: the joint is mastered (zeroed) elsewhere
/// than the file says, often by a quarter or half turn. Named with the
/// angle wrapped to ±180°, before any guess at excitation. Joint 1's θ also
/// places the robot in the measurement frame (a tracker turned any way
/// about the robot's axis 1): no external measurement sees its zero.
fn joint_zero(
    written: &Written<'_>,
    p: &IdentifiedParameter,
    id: ParameterId,
) -> Option<Implausible> {
    use std::f64::consts::TAU;
    let robot = written.nominal;
    let joint = (2..=robot.joint_count()).contains(&id.frame)
        && robot.frames()[id.frame].frame_type == gecaro_core::FrameType::Revolute;
    if id.kind != ParameterKind::Theta || !joint {
        return None;
    }
    let deviation = p.identified - p.nominal;
    let turned = deviation - TAU * (deviation / TAU).round();
    let determined = p.std.is_finite() && turned.abs() > 3.0 * p.std;
    if turned.abs() <= ANGLE_LIMIT || !determined {
        return None;
    }
    let degrees = turned.to_degrees();
    let quarter = (degrees / 90.0).round() * 90.0;
    let near_quarter = (degrees - quarter).abs() < 5.0;
    Some(Implausible {
        name: p.name.clone(),
        why: format!(
            "joint {}'s zero is {degrees:+.1}° from the robot file's (wrapped to ±180°)",
            id.frame
        ),
        cause: format!(
            "a mastering question: joint {} is zeroed elsewhere than the robot file says{}; \
             check its zero mark and the file's θ{} (or offset), then identify again",
            id.frame,
            if near_quarter {
                format!(" (by {quarter:+.0}°: a mark read a quarter or half turn off?)")
            } else {
                String::new()
            },
            id.frame
        ),
    })
}

/// A regrouped base parameter judged expanded: its deviation shared among
/// the parameters of its combination as the prior finds most likely.
fn judge_expanded(
    written: &Written<'_>,
    p: &IdentifiedParameter,
    id: ParameterId,
    size: f64,
) -> Option<Implausible> {
    let nominal = written.nominal;
    let deviation = p.identified - p.nominal;
    let members: Vec<(ParameterId, f64)> = std::iter::once((id, 1.0))
        .chain(
            p.absorbs
                .iter()
                .filter_map(|(name, coefficient)| Some((name.parse().ok()?, *coefficient))),
        )
        .collect();
    let sigma = |member: ParameterId| written.expansion.sigma(member, nominal.parameter(member));
    let total: f64 = members
        .iter()
        .map(|(member, coefficient)| (sigma(*member) * coefficient).powi(2))
        .sum();
    if total <= 0.0 || !total.is_finite() {
        return None;
    }
    let shares: Vec<String> = members
        .iter()
        .filter_map(|(member, coefficient)| {
            let share = sigma(*member).powi(2) * coefficient * deviation / total;
            beyond_limits(
                *member,
                nominal.parameter(*member),
                share,
                size,
                nominal.frames().len() - 1,
            )
            .map(|why| format!("{member} {why}"))
        })
        .collect();
    if shares.is_empty() {
        return None;
    }
    Some(Implausible {
        name: p.name.clone(),
        why: format!(
            "stands for {} moved by {deviation:.3e}, which even shared out as the prior finds \
             most likely needs {}",
            p.combination().unwrap_or_default(),
            shares.join(", ")
        ),
        cause: "these data do not tell the parameters of the combination apart, and push it \
                beyond any real robot: a nearly singular measurement frame (a levelled tracker \
                seen through nearly parallel axes) or too little excitation"
            .to_owned(),
    })
}

/// The robot's size change when beyond [`SIZE_LIMIT`] (module docs).
fn size_change(nominal: &Robot, calibrated: &Robot) -> Option<Implausible> {
    let last = nominal.frames().len() - 1;
    let pairs: Vec<(f64, f64)> = nominal
        .frames()
        .iter()
        .zip(calibrated.frames())
        .take(last)
        .skip(2)
        .flat_map(|(n, c)| [(n.d, c.d), (n.r, c.r)])
        .collect();
    let nominal_square: f64 = pairs.iter().map(|(n, _)| n * n).sum();
    if nominal_square <= 0.0 {
        return None;
    }
    let scale = pairs.iter().map(|(n, c)| n * c).sum::<f64>() / nominal_square;
    let plausible = scale.is_finite() && (1.0 / SIZE_LIMIT..=SIZE_LIMIT).contains(&scale);
    (!plausible).then(|| Implausible {
        name: "size".to_owned(),
        why: format!("its links came out at {scale:.3}× their nominal lengths"),
        cause: if (scale - 1e-3).abs() < 0.5e-3 {
            "the data's lengths are likely in metres read as millimetres: state the data's \
             length unit"
                .to_owned()
        } else if (scale - 1e3).abs() < 0.5e3 {
            "the data's lengths are likely in millimetres read as metres: state the data's \
             length unit"
                .to_owned()
        } else {
            "the data are in another unit than the robot file, or belong to another robot"
                .to_owned()
        },
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tilt(identified: f64, std: f64) -> IdentifiedParameter {
        IdentifiedParameter {
            name: "tilt1".into(),
            parameter: Some(ParameterId::new(ParameterKind::GravityTilt, 1)),
            nominal: 0.0,
            identified,
            std,
            noise_std: std,
            prior_std: None,
            absorbs: Vec::new(),
        }
    }

    /// A gravity leaning by a few degrees is a frame set up by eye; beyond
    /// 5° (and beyond 3σ of it) the stated gravity is wrong, and said so.
    #[test]
    fn a_gravity_tilt_beyond_five_degrees_is_named() {
        assert!(judge_tilt(&tilt(3f64.to_radians(), 1e-3)).is_none());
        assert!(judge_tilt(&tilt(-6f64.to_radians(), 0.5f64.to_radians())).is_none());
        let named = judge_tilt(&tilt(-9f64.to_radians(), 1e-3)).expect("implausible");
        assert!(named.why.contains("-9.0°"), "{}", named.why);
        assert!(
            named.cause.contains("gravity = [x, y, z]"),
            "{}",
            named.cause
        );
    }
}
