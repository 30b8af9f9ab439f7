//! The direct geometric model of a Gough–Stewart platform: the pose from the
//! actuator values, by Newton's method on the inverse model.
//!
//! The leg equations `F(x) = ℓ(x) − (l + K·qm) = 0` are solved for the pose
//! x by `δx = −J(x)⁻¹ F(x)` with J the platform's inverse kinematic Jacobian
//! ([`GoughStewart::pose_jacobian`]), the rotation updated as
//! `R ← exp(ω)·R`. From a start in the basin of one assembly mode Newton's
//! method stays in it: a program is solved target after target, each from
//! the previous pose.

use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};

use super::{GoughStewart, LEGS};
use crate::error::Error;

/// Newton iterations at most: from a start a platform's stroke away,
/// convergence takes 4–6.
const MAX_ITERATIONS: usize = 50;

/// The legs' residual below which the pose is solved (m): far below any
/// measurement, above the rounding of lengths of a few metres.
const TOLERANCE: f64 = 1e-12;

impl GoughStewart {
    /// The pose the actuator values put the platform at, from the pose
    /// `start` (which fixes the assembly mode; [`home`](Self::home) for a
    /// platform above its base).
    ///
    /// # Errors
    /// [`Error::NonFiniteConfiguration`] for a value that is not a number;
    /// [`Error::NoAssembly`] when Newton's method does not close the legs
    /// (actuator values no platform can take, or a start across a
    /// singularity).
    pub fn direct(
        &self,
        actuators: &[f64; LEGS],
        start: &Isometry3<f64>,
    ) -> Result<Isometry3<f64>, Error> {
        if let Some((index, value)) = actuators.iter().enumerate().find(|(_, v)| !v.is_finite()) {
            return Err(Error::NonFiniteConfiguration {
                joint: index + 1,
                value: *value,
            });
        }
        let mut pose = *start;
        let mut residual = self.leg_residuals(&pose, actuators);
        for _ in 0..MAX_ITERATIONS {
            if residual.amax() < TOLERANCE {
                return Ok(pose);
            }
            let Some(step) = self.pose_jacobian(&pose).lu().solve(&(-residual)) else {
                break;
            };
            // Newton's full step, halved while it does not lower the
            // residual (far from the solution it may overshoot).
            let lowered = (0..30)
                .map(|halvings| step * 0.5f64.powi(halvings))
                .find_map(|step| {
                    let next = moved(
                        &pose,
                        &step.fixed_rows::<3>(0).into(),
                        &step.fixed_rows::<3>(3).into(),
                    );
                    let next_residual = self.leg_residuals(&next, actuators);
                    (next_residual.norm() < residual.norm()).then_some((next, next_residual))
                });
            let Some((next, next_residual)) = lowered else {
                break;
            };
            (pose, residual) = (next, next_residual);
        }
        Err(Error::NoAssembly {
            residual: residual.amax(),
        })
    }
}

/// `pose` moved by `δp` and turned by `ω` (base frame): `R ← exp(ω)·R`.
pub(super) fn moved(
    pose: &Isometry3<f64>,
    translation: &Vector3<f64>,
    rotation: &Vector3<f64>,
) -> Isometry3<f64> {
    Isometry3::from_parts(
        Translation3::from(pose.translation.vector + translation),
        UnitQuaternion::from_scaled_axis(*rotation) * pose.rotation,
    )
}
