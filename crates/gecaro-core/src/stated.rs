//! The rules a stated robot meets (paper §2, eq. 4): how many joints, which
//! values are finite and within a robot cell's magnitudes, gains that are
//! not zero, couplings that invert, compliances that are physical. Every
//! front end's robot (a file, a table, Python's arrays) passes here when a
//! [`Robot`](crate::Robot) is made, and a field at fault is named.

use nalgebra::DMatrix;

use crate::frame::{Frame, FrameType, Joint};
use crate::parameters::ParameterSpace;
use crate::{Compact, Error, Field};

/// Most joints of a robot. Serial arms have up to ~10; the bound keeps a
/// malformed or hostile file from making every matrix of the model huge.
pub const MAX_JOINTS: usize = 64;

/// Largest magnitude of a stated value: lengths (d, r, prismatic joint
/// limits and offsets) up to 1 km, angles (α, θ, β, revolute joint limits and
/// offsets) up to 1,000 rad (159 turns). Beyond that a value is a typo or a
/// stand-in for "unlimited", and would make the model's arithmetic overflow.
pub const MAX_MAGNITUDE: f64 = 1e3;

/// The smallest transmission gain |K| a robot holds (eq. 4): below it, a
/// value is a typo or an underflow, and motor values would overflow.
pub const MIN_GAIN: f64 = 1e-12;

/// A stated value: finite, and within [`MAX_MAGNITUDE`].
pub(crate) fn check_magnitude(field: Field, value: f64) -> Result<(), Error> {
    if !value.is_finite() {
        return Err(Error::invalid(
            field,
            format!("{value} is not a finite number"),
        ));
    }
    if value.abs() > MAX_MAGNITUDE {
        return Err(Error::invalid(
            field,
            format!(
                "{value:e} is beyond ±{MAX_MAGNITUDE} (1 km for lengths, 1,000 rad for angles): \
                 a typo, or a stand-in for \"unlimited\"; give the real value"
            ),
        ));
    }
    Ok(())
}

pub(crate) fn validate_frames(frames: &[Frame]) -> Result<(), Error> {
    if frames.len() > MAX_JOINTS + 2 {
        return Err(Error::invalid(
            Field::Frames,
            format!(
                "{} frames: gecaro takes robots of up to {MAX_JOINTS} joints ({} frames)",
                frames.len(),
                MAX_JOINTS + 2
            ),
        ));
    }
    if frames.len() < 3 {
        return Err(Error::invalid(
            Field::Frames,
            format!(
                "a robot needs frame 0 (base), at least one joint frame and frame n+1 \
                 (end-effector); found {} frame(s)",
                frames.len()
            ),
        ));
    }
    let last = frames.len() - 1;
    for (index, frame) in frames.iter().enumerate() {
        let field = |key| Field::Frame { index, key };
        let is_end = index == 0 || index == last;
        match (is_end, frame.frame_type) {
            (true, FrameType::Fixed) | (false, FrameType::Revolute | FrameType::Prismatic) => {}
            (true, other) => {
                return Err(Error::invalid(
                    field("sigma"),
                    format!(
                        "frame {index} is the {} frame and must be fixed (sigma = 2), not sigma = {}",
                        if index == 0 {
                            "base"
                        } else {
                            "end-effector (n+1)"
                        },
                        other.sigma()
                    ),
                ));
            }
            (false, _) => {
                return Err(Error::invalid(
                    field("sigma"),
                    format!(
                        "frame {index} lies between the base and the end-effector, so it is a \
                         joint: sigma must be 0 (revolute) or 1 (prismatic), not 2; only \
                         frames 0 and {last} are fixed"
                    ),
                ));
            }
        }
        for (key, value) in [
            ("alpha", frame.alpha),
            ("d", frame.d),
            ("theta", frame.theta),
            ("r", frame.r),
            ("beta", frame.beta),
        ] {
            check_magnitude(field(key), value)?;
        }
        if index == 0 {
            for (key, value) in [("alpha", frame.alpha), ("d", frame.d), ("beta", frame.beta)] {
                if value != 0.0 {
                    return Err(Error::invalid(
                        field(key),
                        format!(
                            "frame 0 carries only theta and r (alpha0 = d0 = beta0 = 0 by \
                             definition of the base frame); got {key} = {value}"
                        ),
                    ));
                }
            }
        }
    }
    Ok(())
}

/// The largest compliance a joint may have, either sign (rad/(N·m), or
/// m/N): a radian under 100 N·m, a hundred times the softest joint of an
/// industrial arm (issue 75: 1e300 was read). A slightly negative one is an
/// identification's answer within its noise, which the plausibility check
/// names; it is no malformed file.
pub const MAX_COMPLIANCE: f64 = 1e-2;

/// The vocabulary of a robot of `n` joints with these compliances (checked
/// by [`validate_compliances`]): elastic with them, rigid without.
pub(crate) fn parameters_with(
    compliances: Option<&[f64]>,
    n: usize,
) -> Result<ParameterSpace, Error> {
    match compliances {
        Some(compliances) => {
            validate_compliances(compliances, n)?;
            Ok(ParameterSpace::elastic(n))
        }
        None => Ok(ParameterSpace::new(n)),
    }
}

/// n compliances, each finite and within [`MAX_MAGNITUDE`] (a negative one
/// is a modelling question the identification's plausibility check names,
/// not a malformed file).
pub(crate) fn validate_compliances(compliances: &[f64], n: usize) -> Result<(), Error> {
    if compliances.len() != n {
        return Err(Error::invalid(
            Field::Frames,
            format!(
                "an elastic robot of {n} joints needs {n} compliances, got {}",
                compliances.len()
            ),
        ));
    }
    for (index, value) in compliances.iter().enumerate() {
        let field = Field::Frame {
            index: index + 1,
            key: "compliance",
        };
        check_magnitude(field.clone(), *value)?;
        if value.abs() > MAX_COMPLIANCE {
            return Err(Error::invalid(
                field,
                format!(
                    "{value} rad/(N·m) (m/N if prismatic) is no joint's compliance: beyond \
                     ±{MAX_COMPLIANCE} (a radian under 100 N·m); a typo?"
                ),
            ));
        }
    }
    Ok(())
}

pub(crate) fn validate_joint(index: usize, joint: &Joint) -> Result<(), Error> {
    let field = |key| Field::Frame { index, key };
    for (key, value) in [
        ("qmin", joint.qmin),
        ("qmax", joint.qmax),
        ("offset", joint.offset),
    ] {
        check_magnitude(field(key), value)?;
    }
    if joint.qmin > joint.qmax {
        return Err(Error::invalid(
            field("qmin"),
            format!(
                "qmin = {} is greater than qmax = {}",
                Compact(joint.qmin),
                Compact(joint.qmax)
            ),
        ));
    }
    check_gain(field("K"), joint.gain)
}

/// A transmission gain K (eq. 4): finite, not zero, and within
/// [`MIN_GAIN`]..[`MAX_MAGNITUDE`] in magnitude.
pub(crate) fn check_gain(field: Field, gain: f64) -> Result<(), Error> {
    if !gain.is_finite() {
        return Err(Error::invalid(
            field,
            format!("{gain} is not a finite number"),
        ));
    }
    if gain == 0.0 {
        return Err(Error::invalid(field, "a transmission gain cannot be zero"));
    }
    if !(MIN_GAIN..=MAX_MAGNITUDE).contains(&gain.abs()) {
        return Err(Error::invalid(
            field,
            format!(
                "{gain:e} is not a transmission gain: |K| lies between {MIN_GAIN:e} (a \
                 24-bit encoder's count behind a 1:1000 gear is 4e-10) and {MAX_MAGNITUDE}"
            ),
        ));
    }
    Ok(())
}

pub(crate) fn validate_coupling(
    name: &'static str,
    matrix: Option<DMatrix<f64>>,
    n: usize,
) -> Result<DMatrix<f64>, Error> {
    let Some(matrix) = matrix else {
        return Ok(DMatrix::identity(n, n));
    };
    let field = Field::Coupling(name);
    if matrix.shape() != (n, n) {
        return Err(Error::invalid(
            field,
            format!(
                "{name} must be {n}×{n} (one row and column per joint), got {}×{}",
                matrix.nrows(),
                matrix.ncols()
            ),
        ));
    }
    if matrix.iter().any(|v| !v.is_finite()) {
        return Err(Error::invalid(
            field,
            format!("{name} holds a value that is not a finite number"),
        ));
    }
    if let Some(value) = matrix.iter().find(|v| v.abs() > MAX_MAGNITUDE) {
        return Err(Error::invalid(
            field,
            format!(
                "{name} holds {value:e}, beyond ±{MAX_MAGNITUDE}: a coupling ratio is a small number"
            ),
        ));
    }
    let singular_values = matrix.clone().svd(false, false).singular_values;
    let largest = singular_values.max();
    let smallest = singular_values.min();
    if largest == 0.0 || smallest <= 1e-12 * largest {
        return Err(Error::invalid(
            field,
            format!(
                "{name} is singular{}: motor variables could not be recovered from joint \
                 variables (eq. 4)",
                if smallest > 0.0 {
                    format!(" (condition number {:.1e})", largest / smallest)
                } else {
                    String::new()
                }
            ),
        ));
    }
    Ok(matrix)
}
