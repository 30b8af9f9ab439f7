//! The kinematic model under load (issue 38): a configuration's joint
//! variables (eq. 4) deflected by the torques an elastic robot's joints
//! carry, and by gravity's tilts, before the poses are computed.

use super::model::{ChainBuffer, KinematicModel};
use crate::Error;

impl KinematicModel {
    /// Direct model at `motor_positions` with the joints carrying `torques`
    /// (N·m, or N for a prismatic joint; `None`: no load): an elastic
    /// robot's joint j is deflected by `c_j·τ_j` (see the module docs); a
    /// rigid robot ignores them.
    ///
    /// # Errors
    /// When `motor_positions` does not hold n finite values, or `torques`
    /// not n finite values.
    pub fn forward_loaded(
        &self,
        motor_positions: &[f64],
        torques: Option<&[f64]>,
        chain: &mut ChainBuffer,
    ) -> Result<(), Error> {
        self.forward_tilted(motor_positions, torques, None, chain)
    }

    /// [`forward_loaded`](Self::forward_loaded) with the torques'
    /// derivatives with respect to gravity's tilts (`tilt_torques`, 2n
    /// values: `∂τ_j/∂tilt1` for j = 1..n, then `∂τ_j/∂tilt2`;
    /// `gecaro_core::gravity_loads_in`): an elastic robot's joints carry
    /// `τ_j + Σ_k tilt_k ∂τ_j/∂tilt_k` and the Jacobian has the tilts'
    /// columns (module docs). Without them the tilts have no effect.
    ///
    /// # Errors
    /// As [`forward_loaded`](Self::forward_loaded); `tilt_torques` not 2n
    /// finite values.
    pub fn forward_tilted(
        &self,
        motor_positions: &[f64],
        torques: Option<&[f64]>,
        tilt_torques: Option<&[f64]>,
        chain: &mut ChainBuffer,
    ) -> Result<(), Error> {
        self.load(motor_positions, torques, tilt_torques, chain)?;
        self.chain_of_joints(chain);
        Ok(())
    }

    /// The configuration-dependent inputs of the poses, checked, into
    /// `chain`: the joint variables (eq. 4, deflected under load), the
    /// coupled motor variables the gain columns read, and the loads.
    pub(super) fn load(
        &self,
        motor_positions: &[f64],
        torques: Option<&[f64]>,
        tilt_torques: Option<&[f64]>,
        chain: &mut ChainBuffer,
    ) -> Result<(), Error> {
        let n = self.joint_count();
        chain.torques.clear();
        chain.tilt_torques.clear();
        // A rigid robot reads no torque: its forward model stays as it was.
        match torques.filter(|_| !self.compliances.is_empty()) {
            Some(torques) => {
                if torques.len() != n {
                    return Err(Error::ConfigurationLength {
                        expected: n,
                        found: torques.len(),
                    });
                }
                if let Some((index, value)) =
                    torques.iter().enumerate().find(|(_, v)| !v.is_finite())
                {
                    return Err(Error::NonFiniteConfiguration {
                        joint: index + 1,
                        value: *value,
                    });
                }
                chain.torques.extend_from_slice(torques);
            }
            None if self.compliances.is_empty() => {}
            None => chain.torques.resize(n, 0.0),
        }
        if let Some(tilt_torques) = tilt_torques.filter(|_| !chain.torques.is_empty()) {
            if tilt_torques.len() != 2 * n {
                return Err(Error::ConfigurationLength {
                    expected: 2 * n,
                    found: tilt_torques.len(),
                });
            }
            if let Some((index, value)) = tilt_torques
                .iter()
                .enumerate()
                .find(|(_, v)| !v.is_finite())
            {
                return Err(Error::NonFiniteConfiguration {
                    joint: index % n + 1,
                    value: *value,
                });
            }
            chain.tilt_torques.extend_from_slice(tilt_torques);
            let [first, second] = self.gravity_tilt;
            for (joint, torque) in chain.torques.iter_mut().enumerate() {
                *torque += first * tilt_torques[joint] + second * tilt_torques[n + joint];
            }
        }
        if motor_positions.len() != n {
            return Err(Error::ConfigurationLength {
                expected: n,
                found: motor_positions.len(),
            });
        }
        if let Some((index, value)) = motor_positions
            .iter()
            .enumerate()
            .find(|(_, v)| !v.is_finite())
        {
            return Err(Error::NonFiniteConfiguration {
                joint: index + 1,
                value: *value,
            });
        }
        chain.joint_positions.clear();
        chain.coupled_motor_positions.clear();
        if self.uncoupled {
            chain
                .coupled_motor_positions
                .extend_from_slice(motor_positions);
            chain
                .joint_positions
                .extend((0..n).map(|j| {
                    self.motor_to_joint[j * n + j] * motor_positions[j] + self.offsets[j]
                }));
        } else {
            let matrix_vector = |matrix: &[f64], row: usize| {
                (0..n)
                    .map(|j| matrix[row * n + j] * motor_positions[j])
                    .sum::<f64>()
            };
            chain
                .joint_positions
                .extend((0..n).map(|i| matrix_vector(&self.motor_to_joint, i) + self.offsets[i]));
            chain
                .coupled_motor_positions
                .extend((0..n).map(|i| matrix_vector(&self.motor_coupling, i)));
        }
        for ((q, compliance), torque) in chain
            .joint_positions
            .iter_mut()
            .zip(&self.compliances)
            .zip(&chain.torques)
        {
            *q += compliance * torque;
        }
        Ok(())
    }
}
