//! Nearly parallel consecutive axes (Hayati, paper eq. 3): the offset r_j
//! along axis j is not identified.
//!
//! Where axis j−1 and axis j are parallel, moving frames j..n+1 along axis
//! j−1 (r_{j−1}) and moving frames j+1..n+1 along axis j (r_j) are one
//! motion: the structural analysis regroups r_j. Where they are *nearly*
//! parallel — a levelled laser tracker whose z axis is 0.03° from the robot's
//! axis 1, or axes 2 ∥ 3 after a calibration has put a β of 1e-3 rad between
//! them — the two columns differ by the sine of that angle: Appendix III
//! counts both, and the fit writes r0 = +821 m, r1 = −821 m (a condition
//! number of 1e9) to move the robot by a millimetre: the common normal of
//! two lines 3.8 m apart and 1° from parallel lies 220 m away. gecaro's
//! tables place such a frame by Hayati's rule within
//! [`NEARLY_PARALLEL_DEGREES`] (docs/conventions.md): r_j = 0 where the
//! β-turned x axis of frame j−1 meets axis j, the tilt in β_j. r_j is a
//! convention there, not a dimension of the robot, and identification holds
//! it where it is; the tilt is identified, in β_j and α_j. A frame placed on
//! a common normal (β_j = 0) keeps r_j: the Stanford's axis 1 is 5.7° from
//! the world z axis by design and crosses it (Table 1), so that its base
//! has six degrees of freedom.

use gecaro_core::{NEARLY_PARALLEL_DEGREES, ParameterId, ParameterKind, PriorityMatrix, Robot};

/// `priority` with r_j set to 0 for every joint j placed by Hayati's rule
/// (β_j ≠ 0) whose axis is within [`NEARLY_PARALLEL_DEGREES`] of axis j−1
/// (the world z axis for j = 1) but not exactly parallel to it (exactly
/// parallel axes are regrouped by the structural analysis itself, as in
/// Table 2).
pub(super) fn hayati_priority(robot: &Robot, priority: &PriorityMatrix) -> PriorityMatrix {
    let mut held = priority.clone();
    let limit = NEARLY_PARALLEL_DEGREES.to_radians().cos();
    for (j, frame) in robot
        .frames()
        .iter()
        .enumerate()
        .take(robot.joint_count() + 1)
        .skip(1)
    {
        // Axis j relative to frame j−1: Rot(y, β_j) Rot(x, α_j) z, whose
        // cosine with z is cos α_j cos β_j (axes as lines: either sense).
        let cosine = (frame.alpha.cos() * frame.beta.cos()).abs();
        if frame.beta != 0.0 && cosine > limit && cosine < 1.0 - 1e-15 {
            held.set(
                ParameterId {
                    frame: j,
                    kind: ParameterKind::R,
                },
                0,
            );
        }
    }
    held
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_nearly_parallel_axes_hold_their_offset() {
        let mut robot = gecaro_io_free_robot();
        let priority = robot.priority();
        // Exactly parallel world z and axis 1: left to the structural analysis.
        assert_eq!(hayati_priority(&robot, &priority), priority);
        // A levelled tracker: 0.03° between them, placed by Hayati's rule.
        let beta1 = ParameterId {
            frame: 1,
            kind: ParameterKind::Beta,
        };
        robot
            .set_parameter(beta1, 0.03_f64.to_radians())
            .expect("beta1");
        let held = hayati_priority(&robot, &robot.priority());
        let r1 = ParameterId {
            frame: 1,
            kind: ParameterKind::R,
        };
        assert_eq!(held.get(r1), 0);
        // The Stanford's 5.7° on a common normal: r1 a dimension again.
        robot.set_parameter(beta1, 0.0).expect("beta1");
        let alpha1 = ParameterId {
            frame: 1,
            kind: ParameterKind::Alpha,
        };
        robot.set_parameter(alpha1, 0.1).expect("alpha1");
        assert_eq!(
            hayati_priority(&robot, &robot.priority()).get(r1),
            robot.priority().get(r1)
        );
    }

    /// A two-joint arm whose axis 1 is the world z axis.
    fn gecaro_io_free_robot() -> Robot {
        Robot::template("two", "RR").expect("template")
    }
}
