//! Placing Khalil–Kleinfinger frames on given joint axes (paper §2.1, eq.
//! 2–3), shared by [`AxisChain`](crate::AxisChain) (a chain drawn with its
//! axes) and [`Robot::reframed`](crate::Robot::reframed) (a new world or
//! tool frame).
//!
//! A frame on axis j facing the next axis (axis j+1, or the tool's z axis):
//!
//! - **Common normal** when the two axes are more than
//!   [`NEARLY_PARALLEL_DEGREES`] from parallel: x_j along the common normal,
//!   the origin where it meets axis j; the next frame needs no β.
//! - **Hayati β** when they are parallel or nearly so: the origin is chosen
//!   by the caller on axis j, and x_j, perpendicular to z_j, points towards
//!   the next axis so that `Rot(y,β)·Rot(x,α)·Trans(x,d)` of eq. 3 reaches it
//!   exactly. Lengths stay of the order of the distance between the axes.
//!
//! The free sense of x follows a preferred direction (a drawing's own x axis)
//! so that θ stays near the drawing's zero. [`decompose`] reads the five
//! parameters of eq. 3 back from two placed frames.

use nalgebra::{IsometryMatrix3, Rotation3, Translation3, Unit, Vector3};

use crate::frame::{Frame, FrameType};

/// Axes closer than this to parallel (as lines, in degrees) are placed with
/// Hayati's β instead of a common normal. Nominally parallel axes (exactly, or
/// off by the rounding of a drawing, or by a calibration) fall below it; the
/// axes of real arms that are not parallel are tens of degrees apart. Above
/// it, a common normal lies at most 1/sin(10°) ≈ 5.8 times the distance
/// between the axes from them.
pub const NEARLY_PARALLEL_DEGREES: f64 = 10.0;

/// Values closer than this to a round number are written as that number.
const TIDY: f64 = 1e-14;

/// A line through `point` along `direction`.
#[derive(Copy, Clone, Debug)]
pub(crate) struct Line {
    pub(crate) point: Vector3<f64>,
    pub(crate) direction: Unit<Vector3<f64>>,
}

impl Line {
    /// The point of this line closest to `other` (non-parallel lines).
    pub(crate) fn closest_point_to(&self, other: &Line) -> Vector3<f64> {
        let between = self.point - other.point;
        let cosine = self.direction.dot(&other.direction);
        let along_self = self.direction.dot(&between);
        let along_other = other.direction.dot(&between);
        let s = (cosine * along_other - along_self) / (1.0 - cosine * cosine);
        self.point + self.direction.into_inner() * s
    }
}

/// A placed frame: origin and unit x, z axes in the world frame.
#[derive(Copy, Clone, Debug)]
pub(crate) struct Placed {
    pub(crate) origin: Vector3<f64>,
    pub(crate) x: Unit<Vector3<f64>>,
    pub(crate) z: Unit<Vector3<f64>>,
}

impl Placed {
    pub(crate) fn pose(&self) -> IsometryMatrix3<f64> {
        let x =
            Unit::new_normalize(self.x.into_inner() - self.z.into_inner() * self.z.dot(&self.x));
        let y = self.z.cross(&x);
        IsometryMatrix3::from_parts(
            Translation3::from(self.origin),
            Rotation3::from_basis_unchecked(&[x.into_inner(), y, self.z.into_inner()]),
        )
    }
}

pub(crate) fn nearly_parallel(a: &Vector3<f64>, b: &Vector3<f64>) -> bool {
    a.cross(b).norm() < NEARLY_PARALLEL_DEGREES.to_radians().sin()
}

/// `x` or `-x`, whichever points like the first of `preferences` that is not
/// (nearly) along `z`.
fn oriented(
    x: Unit<Vector3<f64>>,
    z: &Vector3<f64>,
    preferences: &[Vector3<f64>],
) -> Unit<Vector3<f64>> {
    for preference in preferences {
        let alignment = x.dot(&(preference - z * z.dot(preference)));
        if alignment.abs() > 1e-6 {
            return if alignment > 0.0 { x } else { -x };
        }
    }
    x
}

/// A unit vector perpendicular to `z` along the first usable preference.
fn perpendicular_preference(z: &Vector3<f64>, preferences: &[Vector3<f64>]) -> Unit<Vector3<f64>> {
    preferences
        .iter()
        .chain(&[Vector3::x(), Vector3::y()])
        .find_map(|preference| Unit::try_new(preference - z * z.dot(preference), 1e-6))
        .unwrap_or_else(Vector3::x_axis)
}

/// The x axis of a frame at `origin` on axis `z` whose next axis `next` is
/// (nearly) parallel to `z`: perpendicular to `z`, and such that the next axis
/// meets the line through `origin` along `Rot(y,β)·x`, with β, α those that
/// turn `z` onto the next axis (eq. 3) — so the next frame needs no common
/// normal.
///
/// In the frame (x, y, z), with the next axis crossing the plane z = 0 at
/// (ρ cos ψ, −ρ sin ψ, 0) and directed along u, that condition reads
/// `tan ψ = −u_x·u_y / (u_x² + u_z²)`: ψ = 0 for exactly parallel axes, and a
/// fixed point that converges fast (its slope is of the order of the tilt²).
fn hayati_x(
    origin: &Vector3<f64>,
    z: &Unit<Vector3<f64>>,
    next: &Line,
    preferences: &[Vector3<f64>],
) -> Unit<Vector3<f64>> {
    let u = next.direction;
    let t = (origin - next.point).dot(z) / u.dot(z);
    let towards = next.point + u.into_inner() * t - origin;
    // Rounding leaves a component along z that matters once the next axis
    // passes close to the origin: keep the direction in the plane.
    let Some(x0) = Unit::try_new(towards - z.into_inner() * z.dot(&towards), 1e-12) else {
        // The next axis passes through the origin: any x works.
        return perpendicular_preference(z, preferences);
    };
    let y0 = z.cross(&x0);
    let mut psi = 0.0_f64;
    for _ in 0..100 {
        let (sin, cos) = psi.sin_cos();
        let x = x0.into_inner() * cos + y0 * sin;
        let y = z.cross(&x);
        let (ux, uy, uz) = (u.dot(&x), u.dot(&y), u.dot(z));
        let next_psi = (-ux * uy / (ux * ux + uz * uz)).atan();
        let converged = (next_psi - psi).abs() <= 1e-17;
        psi = next_psi;
        if converged {
            break;
        }
    }
    let (sin, cos) = psi.sin_cos();
    oriented(
        Unit::new_normalize(x0.into_inner() * cos + y0 * sin),
        z,
        preferences,
    )
}

/// The x axis of frame j−1 turned by Rot(y, β_j) (eq. 3): x_{j−1} itself
/// where frame j−1 lies on a common normal (β_j = 0), else the unit vector of
/// the plane (x_{j−1}, z_{j−1}) that is perpendicular to z_j, on the side of
/// x_{j−1}.
pub(crate) fn turned_x(previous: &Placed, z: &Vector3<f64>) -> Unit<Vector3<f64>> {
    if !nearly_parallel(&previous.z, z) {
        return previous.x;
    }
    let along_z = z.dot(&previous.z);
    let along_x = z.dot(&previous.x);
    let sign = if along_z < 0.0 { -1.0 } else { 1.0 };
    Unit::new_normalize(
        previous.x.into_inner() * (sign * along_z) - previous.z.into_inner() * (sign * along_x),
    )
}

/// The parameters of eq. 3 of `relative = (j−1)T(j)`, with β = 0 (common
/// normal) or with β (Hayati); q = 0.
pub(crate) fn decompose(
    relative: &IsometryMatrix3<f64>,
    frame_type: FrameType,
    hayati: bool,
) -> Frame {
    let u = relative.rotation * Vector3::z();
    let (alpha, beta) = if hayati {
        let sign = if u.z < 0.0 { -1.0 } else { 1.0 };
        let beta = (sign * u.x).atan2(sign * u.z);
        let cos_alpha = sign * u.x.hypot(u.z);
        ((-u.y).atan2(cos_alpha), beta)
    } else {
        ((-u.y).atan2(u.z), 0.0)
    };
    let turned = Vector3::new(beta.cos(), 0.0, -beta.sin());
    let x = relative.rotation * Vector3::x();
    let theta = turned.cross(&x).dot(&u).atan2(turned.dot(&x));
    let position = relative.translation.vector;
    Frame {
        frame_type,
        alpha: tidy_angle(alpha),
        d: tidy(position.dot(&turned)),
        theta: tidy_angle(theta),
        r: tidy(position.dot(&u)),
        beta: tidy_angle(beta),
    }
}

/// A length, or the round number within [`TIDY`] of it: 0 or a number with
/// ten decimals.
pub(crate) fn tidy(value: f64) -> f64 {
    let decimal = (value * 1e10).round() / 1e10;
    if (value - decimal).abs() < TIDY {
        decimal
    } else {
        value
    }
}

/// An angle, or the round number within [`TIDY`] of it: a multiple of π/2
/// (a half turn written +π, never −π), 0, or a number with ten decimals.
pub(crate) fn tidy_angle(value: f64) -> f64 {
    let quarter_turns = (value / std::f64::consts::FRAC_PI_2).round();
    if (value - quarter_turns * std::f64::consts::FRAC_PI_2).abs() < TIDY {
        let quarter_turns = if quarter_turns == -2.0 {
            2.0
        } else {
            quarter_turns
        };
        return quarter_turns * std::f64::consts::FRAC_PI_2;
    }
    tidy(value)
}

/// The frame on `line` facing `next` (see the module docs): on the common
/// normal, or, when the axes are nearly parallel, at `parallel_origin` (a
/// point of `line`) with Hayati's x. The sense of x follows `preferences`.
pub(crate) fn place_facing(
    line: &Line,
    next: &Line,
    parallel_origin: impl FnOnce() -> Vector3<f64>,
    preferences: &[Vector3<f64>],
) -> Placed {
    if nearly_parallel(&line.direction, &next.direction) {
        let origin = parallel_origin();
        Placed {
            origin,
            x: hayati_x(&origin, &line.direction, next, preferences),
            z: line.direction,
        }
    } else {
        Placed {
            origin: line.closest_point_to(next),
            x: oriented(
                Unit::new_normalize(line.direction.cross(&next.direction)),
                &line.direction,
                preferences,
            ),
            z: line.direction,
        }
    }
}

/// The z axis of a pose.
pub(crate) fn z_axis_of(pose: &IsometryMatrix3<f64>) -> Unit<Vector3<f64>> {
    Unit::new_normalize(pose.rotation * Vector3::z())
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::{FRAC_PI_2, PI};

    #[test]
    #[allow(clippy::approx_constant)] // a drawing's rounded π/2 must stay rounded
    fn round_numbers_are_written_as_such_and_nothing_else_moves() {
        assert_eq!(tidy(2e-17), 0.0);
        assert_eq!(tidy(-0.6127000000000002), -0.6127);
        assert_eq!(tidy(-PI), -PI, "a length is not an angle");
        assert_eq!(tidy(0.123456789012345), 0.123456789012345);
        assert_eq!(tidy_angle(-PI), PI);
        assert_eq!(tidy_angle(PI - 1e-15), PI);
        assert_eq!(tidy_angle(-3.0 * FRAC_PI_2 + 3e-15), -3.0 * FRAC_PI_2);
        assert_eq!(tidy_angle(-FRAC_PI_2), -FRAC_PI_2);
        assert_eq!(
            tidy_angle(1.570796327),
            1.570796327,
            "a drawing's rounded π/2 stays"
        );
        assert_eq!(tidy_angle(-1e-16), 0.0);
    }
}
