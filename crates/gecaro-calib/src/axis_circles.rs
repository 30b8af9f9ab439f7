//! A robot's base registered by the circles of its first two joints
//! (issue 74): joint 1 turned alone draws a circle about its axis, joint 2
//! turned alone (joint 1 held) one about its own; the two axes, measured
//! by any instrument in its own frame, fix the base as the robot's maker
//! defines it — z along axis 1, the origin where the common normal of axes
//! 1 and 2 meets axis 1, x along that normal with joint 1 at zero.
//!
//! ## The circle
//!
//! The points' plane is their least-squares plane (the centred points'
//! smallest singular direction `n`); in it, the circle's centre `c` and
//! radius `ρ` start from the algebraic (Kåsa) fit and are refined by
//! Gauss–Newton on the geometric distances `‖p⊥ − c‖ − ρ`. A point's
//! residual is its distance from the circle, `√(h² + (‖p⊥ − c‖ − ρ)²)` with
//! `h` its height over the plane: two components per point, six
//! parameters per circle.
//!
//! The axis is the line through `c` along `n`, oriented by the joint
//! readings: a joint turning by `+Δq` turns a point counter-clockwise about
//! its axis. The readings also check the points: the arc the points span
//! and the readings' span agree within [`ARC_TOLERANCE`] (degrees read as
//! radians, another joint's column, are refused).
//!
//! ## The base
//!
//! With the axes `(p₁, z₁)` and `(p₂, z₂)`, the common normal meets axis 1
//! at `O` and axis 2 at `F`; `x = F − O` normalised (or `z₁ × z₂` where the
//! robot's axes meet, as its nominal model says), turned by `−q₁` about
//! `z₁` (`q₁` joint 1's reading while joint 2 turned). The frame
//! `A = (O; x, z₁ × x, z₁)` is built alike from the nominal robot's axes
//! (in its base frame) and from the measured ones (in the instrument's):
//! the base's pose in the instrument's frame is `T = A_measured A_nominal⁻¹`.
//!
//! Its precision is the points' noise carried through the whole
//! construction: `Σ_T = s² J Jᵀ`, `J` the derivative of `T`'s translation
//! and rotation (measurement frame) with respect to every coordinate of
//! every point, by central differences, and `s² = Σ r² / (2N − 12)` from the
//! two circles' residuals.

use nalgebra::{
    IsometryMatrix3, Matrix3, Rotation3, Translation3, Unit, Vector2, Vector3, Vector6,
};

use crate::registration::PointRegistration;

/// The most a circle's arc and its joint readings' span may differ, as a
/// share of the span: a joint reading in another unit or of another joint
/// is far beyond it.
pub const ARC_TOLERANCE: f64 = 0.1;

/// The fewest points on a circle: three define it, a fourth checks it.
pub const MIN_CIRCLE_POINTS: usize = 4;

/// A circle in space: centre, unit normal, radius, and each point's
/// distance from it (the points' units).
#[derive(Clone, Debug, PartialEq)]
pub struct Circle {
    /// Its centre.
    pub centre: Vector3<f64>,
    /// Its plane's unit normal (oriented by the joint's readings when the
    /// circle is a joint's, [`joint_axis`]).
    pub normal: Unit<Vector3<f64>>,
    /// Its radius.
    pub radius: f64,
    /// Each point's distance from the circle.
    pub residuals: Vec<f64>,
}

/// A joint's axis: a point on it and its direction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Axis {
    /// A point on the axis (the circle's centre).
    pub point: Vector3<f64>,
    /// Its direction: a positive turn of the joint is counter-clockwise
    /// about it.
    pub direction: Unit<Vector3<f64>>,
}

/// The circle through `points` (see the module docs).
///
/// # Errors
/// Fewer than [`MIN_CIRCLE_POINTS`] points, or points on one line or
/// bunched in one place, as a sentence.
pub fn fit_circle(points: &[Vector3<f64>]) -> Result<Circle, String> {
    if points.len() < MIN_CIRCLE_POINTS {
        return Err(format!(
            "{} point(s): a circle is measured from at least {MIN_CIRCLE_POINTS} (three define \
             it, a fourth checks it)",
            points.len()
        ));
    }
    let mean = points.iter().sum::<Vector3<f64>>() / points.len() as f64;
    let spread: Matrix3<f64> = points
        .iter()
        .map(|p| (p - mean) * (p - mean).transpose())
        .sum();
    let eigen = spread.symmetric_eigen();
    let mut order = [0, 1, 2];
    order.sort_by(|a, b| eigen.eigenvalues[*b].total_cmp(&eigen.eigenvalues[*a]));
    let extent = |i: usize| (eigen.eigenvalues[order[i]].max(0.0) / points.len() as f64).sqrt();
    if !(extent(1) > 1e-6 && extent(1) > 1e-4 * extent(0)) {
        return Err(format!(
            "the {} points lie on one line or in one place: a circle needs an arc (turn the \
             joint farther between points)",
            points.len()
        ));
    }
    let u = eigen.eigenvectors.column(order[0]).into_owned();
    let v = eigen.eigenvectors.column(order[1]).into_owned();
    let normal = Unit::new_normalize(u.cross(&v));
    let planar: Vec<Vector2<f64>> = points
        .iter()
        .map(|p| Vector2::new((p - mean).dot(&u), (p - mean).dot(&v)))
        .collect();
    // Kåsa: x² + y² = 2a x + 2b y + c, linear in (a, b, c).
    let rows = nalgebra::DMatrix::from_fn(planar.len(), 3, |i, j| match j {
        0 => 2.0 * planar[i].x,
        1 => 2.0 * planar[i].y,
        _ => 1.0,
    });
    let right = nalgebra::DVector::from_fn(planar.len(), |i, _| planar[i].norm_squared());
    let solved = rows
        .svd(true, true)
        .solve(&right, 1e-14)
        .map_err(|message| format!("the circle's fit failed: {message}"))?;
    let mut centre = Vector2::new(solved[0], solved[1]);
    let mut radius = (solved[2] + centre.norm_squared()).max(0.0).sqrt();
    // Gauss–Newton on the geometric distances ‖p − c‖ − ρ.
    for _ in 0..20 {
        let mut normal_matrix = Matrix3::<f64>::zeros();
        let mut gradient = Vector3::<f64>::zeros();
        for p in &planar {
            let offset = p - centre;
            let distance = offset.norm();
            if distance == 0.0 {
                continue;
            }
            let row = Vector3::new(-offset.x / distance, -offset.y / distance, -1.0);
            normal_matrix += row * row.transpose();
            gradient += row * (distance - radius);
        }
        let Some(step) = normal_matrix.lu().solve(&(-gradient)) else {
            break;
        };
        centre += Vector2::new(step.x, step.y);
        radius += step.z;
        if step.norm() <= 1e-15 * (1.0 + radius) {
            break;
        }
    }
    if !(radius.is_finite() && radius > 0.0) {
        return Err("the points do not lie on a circle".into());
    }
    let residuals = points
        .iter()
        .zip(&planar)
        .map(|(p, q)| {
            let height = (p - mean).dot(&normal);
            height.hypot((q - centre).norm() - radius)
        })
        .collect();
    Ok(Circle {
        centre: mean + u * centre.x + v * centre.y,
        normal,
        radius,
        residuals,
    })
}

/// The axis of a joint turned alone, from the points it carried and its
/// readings (radians of the joint's variable), and the circle they drew.
///
/// # Errors
/// [`fit_circle`]'s, readings that do not turn, or readings whose span is
/// not the arc the points span (within [`ARC_TOLERANCE`]).
pub fn joint_axis(points: &[Vector3<f64>], angles: &[f64]) -> Result<(Axis, Circle), String> {
    let mut circle = fit_circle(points)?;
    let mut order: Vec<usize> = (0..points.len().min(angles.len())).collect();
    order.sort_by(|a, b| angles[*a].total_cmp(&angles[*b]));
    let (mut turn, mut arc) = (0.0, 0.0);
    for pair in order.windows(2) {
        let (a, b) = (pair[0], pair[1]);
        let (from, to) = (points[a] - circle.centre, points[b] - circle.centre);
        let signed = from.cross(&to).dot(&circle.normal).atan2(from.dot(&to));
        turn += signed;
        arc += signed.abs();
    }
    let span = angles[order[order.len() - 1]] - angles[order[0]];
    if span.is_nan() || span <= 1e-6 {
        return Err("the joint's readings do not change: it was not turned".into());
    }
    if turn < 0.0 {
        circle.normal = -circle.normal;
    }
    if (arc - span).abs() > ARC_TOLERANCE * span {
        return Err(format!(
            "the points span an arc of {:.2}° but the joint's readings {:.2}°: readings of \
             another joint, or in another unit",
            arc.to_degrees(),
            span.to_degrees()
        ));
    }
    Ok((
        Axis {
            point: circle.centre,
            direction: circle.normal,
        },
        circle,
    ))
}

/// How the common normal of axes 1 and 2 is taken: from axis 1 to axis 2
/// (axes apart), or as `z₁ × z₂` (axes that meet).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CommonNormal {
    /// `F − O`: the axes stand apart.
    Between,
    /// `z₁ × z₂`: the axes meet.
    Across,
}

/// Axes closer than this (m) are taken to meet.
const MEETING_DISTANCE: f64 = 1e-3;

/// The frame of axes 1 and 2 (see the module docs) with joint 1 at
/// `angle1` while axis 2 was where it is, and how its x was taken.
///
/// # Errors
/// Parallel axes (the origin's place along them is not fixed by them).
pub fn axes_frame(
    first: &Axis,
    second: &Axis,
    angle1: f64,
    normal: Option<CommonNormal>,
) -> Result<(IsometryMatrix3<f64>, CommonNormal), String> {
    let (d1, d2) = (first.direction.into_inner(), second.direction.into_inner());
    let cross = d1.cross(&d2);
    if cross.norm() < 1e-3 {
        return Err(format!(
            "axes 1 and 2 are parallel ({:.3}° apart): they do not fix the base's origin along \
             them; register the base by points",
            cross.norm().asin().to_degrees()
        ));
    }
    let w = first.point - second.point;
    let b = d1.dot(&d2);
    let (d, e) = (d1.dot(&w), d2.dot(&w));
    let denominator = 1.0 - b * b;
    let s = (b * e - d) / denominator;
    let t = (e - b * d) / denominator;
    let origin = first.point + s * d1;
    let foot = second.point + t * d2;
    let kind = normal.unwrap_or(if (foot - origin).norm() < MEETING_DISTANCE {
        CommonNormal::Across
    } else {
        CommonNormal::Between
    });
    let towards = match kind {
        CommonNormal::Between => foot - origin,
        CommonNormal::Across => cross,
    };
    let towards = (towards - d1 * d1.dot(&towards)).normalize();
    let x = Rotation3::from_axis_angle(&first.direction, -angle1) * towards;
    let rotation = Rotation3::from_basis_unchecked(&[x, d1.cross(&x), d1]);
    Ok((
        IsometryMatrix3::from_parts(Translation3::from(origin), rotation),
        kind,
    ))
}

/// A joint turned alone: the points it carried and its readings (rad).
#[derive(Clone, Copy, Debug)]
pub struct TurnedJoint<'a> {
    /// The points, in the instrument's frame.
    pub points: &'a [Vector3<f64>],
    /// The joint's variable at each point (rad).
    pub angles: &'a [f64],
}

/// The base registered by the circles of joints 1 and 2, with `angle1`
/// joint 1's variable while joint 2 turned, against `nominal_axes` (the
/// nominal robot's axis 1 and its axis 2 with joint 1 at zero, in its base
/// frame): the base's pose in the instrument's frame, each point's
/// distance from its circle (joint 1's points first), and the precision
/// (see the module docs).
///
/// # Errors
/// A circle that cannot be fitted (naming the joint), parallel axes.
pub fn register_by_circles(
    first: TurnedJoint<'_>,
    second: TurnedJoint<'_>,
    angle1: f64,
    nominal_axes: (&Axis, &Axis),
) -> Result<(PointRegistration, [Circle; 2]), String> {
    let (nominal, kind) = axes_frame(nominal_axes.0, nominal_axes.1, 0.0, None)
        .map_err(|message| format!("the nominal robot's {message}"))?;
    let solve = |one: &[Vector3<f64>], two: &[Vector3<f64>]| {
        let (axis1, circle1) =
            joint_axis(one, first.angles).map_err(|message| format!("joint 1: {message}"))?;
        let (axis2, circle2) =
            joint_axis(two, second.angles).map_err(|message| format!("joint 2: {message}"))?;
        let (measured, _) = axes_frame(&axis1, &axis2, angle1, Some(kind))?;
        Ok::<_, String>((measured * nominal.inverse(), [circle1, circle2]))
    };
    let (transform, circles) = solve(first.points, second.points)?;
    let residuals: Vec<f64> = circles
        .iter()
        .flat_map(|circle| circle.residuals.iter().copied())
        .collect();
    let freedom = 2 * residuals.len() as i64 - 12;
    let sigma = if freedom > 0 {
        (residuals.iter().map(|r| r * r).sum::<f64>() / freedom as f64).sqrt()
    } else {
        0.0
    };
    // J: the base's translation and rotation against each coordinate.
    let change = |moved: &IsometryMatrix3<f64>| {
        // The small turn's vector from the skew part (the axis-angle of a
        // rotation this close to the identity is lost to rounding).
        let r = (moved.rotation * transform.rotation.inverse()).into_inner();
        let turn = Vector3::new(
            r[(2, 1)] - r[(1, 2)],
            r[(0, 2)] - r[(2, 0)],
            r[(1, 0)] - r[(0, 1)],
        ) / 2.0;
        let shift = moved.translation.vector - transform.translation.vector;
        Vector6::new(shift.x, shift.y, shift.z, turn.x, turn.y, turn.z)
    };
    let mut covariance = nalgebra::Matrix6::<f64>::zeros();
    let step = 1e-6;
    let mut points: Vec<Vector3<f64>> = first.points.iter().chain(second.points).copied().collect();
    let split = first.points.len();
    for point in 0..points.len() {
        for axis in 0..3 {
            let held = points[point][axis];
            points[point][axis] = held + step;
            let ahead = solve(&points[..split], &points[split..])?.0;
            points[point][axis] = held - step;
            let behind = solve(&points[..split], &points[split..])?.0;
            points[point][axis] = held;
            let column = (change(&ahead) - change(&behind)) / (2.0 * step);
            covariance += column * column.transpose();
        }
    }
    let diagonal = covariance.diagonal() * sigma * sigma;
    Ok((
        PointRegistration {
            transform,
            residuals,
            sigma,
            origin_sigma: (diagonal.rows(0, 3).sum() / 3.0).sqrt(),
            rotation_sigma: (diagonal.rows(3, 3).sum() / 3.0).sqrt(),
        },
        circles,
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Points on the circle of `axis` through `start`, turned by `angles`.
    fn turned(axis: &Axis, start: &Vector3<f64>, angles: &[f64]) -> Vec<Vector3<f64>> {
        angles
            .iter()
            .map(|q| {
                axis.point + Rotation3::from_axis_angle(&axis.direction, *q) * (start - axis.point)
            })
            .collect()
    }

    #[test]
    fn a_circle_is_found_with_its_residuals() {
        let axis = Axis {
            point: Vector3::new(0.3, -1.2, 0.5),
            direction: Unit::new_normalize(Vector3::new(0.1, 0.2, 1.0)),
        };
        let angles = [-0.6, -0.2, 0.3, 0.9, 1.4];
        let points = turned(&axis, &Vector3::new(1.1, -0.9, 0.7), &angles);
        let (found, circle) = joint_axis(&points, &angles).expect("axis");
        assert!((found.direction.into_inner() - axis.direction.into_inner()).norm() < 1e-12);
        assert!(found.direction.cross(&(found.point - axis.point)).norm() < 1e-12);
        assert!(circle.residuals.iter().all(|r| *r < 1e-12));
        // Readings the other way turn the axis over.
        let reversed: Vec<f64> = angles.iter().map(|q| -q).collect();
        let (flipped, _) = joint_axis(&points, &reversed).expect("axis");
        assert!((flipped.direction.into_inner() + axis.direction.into_inner()).norm() < 1e-12);
        // Degrees read as radians.
        let degrees: Vec<f64> = angles.iter().map(|q| q.to_degrees()).collect();
        let message = joint_axis(&points, &degrees)
            .expect_err("units")
            .to_string();
        assert!(message.contains("another unit"), "{message}");
        let message = fit_circle(&points[..3]).expect_err("few").to_string();
        assert!(message.contains("at least 4"), "{message}");
        let line: Vec<Vector3<f64>> = (0..5)
            .map(|i| Vector3::new(f64::from(i), 0.0, 0.0))
            .collect();
        assert!(fit_circle(&line).expect_err("line").contains("one line"));
    }

    /// A base placed anywhere is found from exact circles, and its stated
    /// precision follows the points' noise (checked against the spread of
    /// 200 noisy draws).
    #[test]
    fn the_base_is_registered_by_two_circles() {
        // A robot's nominal axes: axis 1 vertical through the origin, axis 2
        // horizontal, 0.15 m along x and 0.45 m up, along −y.
        let nominal = (
            Axis {
                point: Vector3::zeros(),
                direction: Vector3::z_axis(),
            },
            Axis {
                point: Vector3::new(0.15, 0.0, 0.45),
                direction: -Vector3::y_axis(),
            },
        );
        let base = IsometryMatrix3::from_parts(
            Translation3::new(2.4, -0.6, -0.3),
            Rotation3::from_euler_angles(0.01, -0.008, 2.2),
        );
        let held = 0.4;
        let in_instrument = |axis: &Axis, turn: f64| Axis {
            point: (base
                * nalgebra::Point3::from(
                    Rotation3::from_axis_angle(&Vector3::z_axis(), turn) * axis.point,
                ))
            .coords,
            direction: Unit::new_normalize(
                base.rotation
                    * (Rotation3::from_axis_angle(&Vector3::z_axis(), turn)
                        * axis.direction.into_inner()),
            ),
        };
        let (axis1, axis2) = (
            in_instrument(&nominal.0, 0.0),
            in_instrument(&nominal.1, held),
        );
        let angles1 = [-1.2, -0.6, 0.0, 0.7, 1.3, 1.9];
        let angles2 = [-0.5, -0.2, 0.1, 0.4, 0.8];
        let start1 = base * nalgebra::Point3::new(1.2, 0.1, 1.1);
        let start2 = (base
            * nalgebra::Point3::from(
                Rotation3::from_axis_angle(&Vector3::z_axis(), held) * Vector3::new(1.0, 0.0, 1.3),
            ))
        .coords;
        let one = turned(&axis1, &start1.coords, &angles1);
        let two = turned(&axis2, &start2, &angles2);
        let (fit, _) = register_by_circles(
            TurnedJoint {
                points: &one,
                angles: &angles1,
            },
            TurnedJoint {
                points: &two,
                angles: &angles2,
            },
            held,
            (&nominal.0, &nominal.1),
        )
        .expect("registered");
        assert!(
            (fit.transform.to_homogeneous() - base.to_homogeneous()).norm() < 1e-9,
            "{} vs {}",
            fit.transform.to_homogeneous(),
            base.to_homogeneous()
        );
        // Noise: the stated σ of the origin against the draws' spread.
        let mut random = crate::simulation::Sampler::new(4);
        let sigma = 2e-5;
        let (mut stated, mut spread) = (0.0, 0.0);
        let draws = 200;
        for _ in 0..draws {
            let noisy = |points: &[Vector3<f64>], random: &mut crate::simulation::Sampler| {
                points
                    .iter()
                    .map(|p| p + random.gaussian_vector(sigma))
                    .collect::<Vec<_>>()
            };
            let (a, b) = (noisy(&one, &mut random), noisy(&two, &mut random));
            let (found, _) = register_by_circles(
                TurnedJoint {
                    points: &a,
                    angles: &angles1,
                },
                TurnedJoint {
                    points: &b,
                    angles: &angles2,
                },
                held,
                (&nominal.0, &nominal.1),
            )
            .expect("registered");
            stated += found.origin_sigma.powi(2);
            spread +=
                (found.transform.translation.vector - base.translation.vector).norm_squared() / 3.0;
        }
        let (stated, spread) = (
            (stated / draws as f64).sqrt(),
            (spread / draws as f64).sqrt(),
        );
        assert!(
            stated > 0.75 * spread && stated < 1.33 * spread,
            "stated {stated}, spread {spread}"
        );
    }
}
