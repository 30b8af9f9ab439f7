//! The priority matrix of paper §2.2 and its default rules (paper §4, NOTES.md).
//!
//! A (n+2)×6 matrix of non-negative integers: row j is frame j (0..=n+1),
//! columns are α, d, θ, r, β, K. When the identifiable parameters are computed,
//! the columns of the observation matrix are taken in decreasing priority, so
//! the base parameters are the highest-priority independent ones; a priority
//! of 0 means "do not identify". Cells that are not parameters (α0, d0, β0, the
//! gains of frames 0 and n+1) must be 0.
//!
//! Default rules, each parameter taking the highest one that applies:
//!
//! | priority | parameters |
//! |---|---|
//! | 5 | joint offsets (θ_j of a revolute joint, r_j of a prismatic one) and gains K_j |
//! | 4 | every r_j, and d_j ≠ 0 |
//! | 3 | α_j and θ_j that are not a multiple of π/2 |
//! | 2 | the parameters of frames 0 and n+1 |
//! | 1 | everything else (β_j of every frame j ≥ 1 is a candidate) |
//!
//! Ties are broken in column-major order of the matrix: all α (frames 0..=n+1),
//! then all d, θ, r, β, K — what a stable sort of `P(:)` gives in the paper's
//! MATLAB. This makes the base set a pure function of the matrix and of W,
//! independent of threads or platform.
//!
//! The compliances of an elastic robot (issue 38) have their own column
//! beside the six, read and set through the same [`PriorityMatrix::get`] and
//! [`PriorityMatrix::set`]. It is 0 by default: a compliance is identified
//! only when asked for (`--model elastic`, see [`PriorityMatrix::with_compliances`]),
//! so no existing file changes. Its candidates come after all six columns.
//! The two gravity tilts of an elastic robot (`tilt1`, `tilt2`) have a
//! priority each, 0 unless asked for (`--model elastic-gravity`, see
//! [`PriorityMatrix::with_gravity_tilt`]), taken after the compliances; a
//! priority file does not state them.

use crate::frame::{Frame, FrameType};
use crate::parameters::{ParameterId, ParameterKind, ParameterSpace};
use crate::{Error, Field};

/// The (n+2)×6 priority matrix; see the module docs.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct PriorityMatrix {
    rows: Vec<[u32; 6]>,
    /// The priority of c_j in row j (frames 0 and n+1 have none).
    compliance: Vec<u32>,
    /// The priorities of tilt1 and tilt2.
    gravity_tilt: [u32; 2],
}

impl PriorityMatrix {
    /// A matrix from its rows (frame 0 first). Check it against a robot with
    /// [`Robot::set_priority_override`](crate::Robot::set_priority_override) or [`Robot::new`](crate::Robot::new).
    pub fn from_rows(rows: Vec<[u32; 6]>) -> Self {
        PriorityMatrix {
            compliance: vec![0; rows.len()],
            rows,
            gravity_tilt: [0; 2],
        }
    }

    /// This matrix with the compliance of every joint at `priority` (an
    /// elastic identification; 0 identifies none).
    pub fn with_compliances(mut self, priority: u32) -> Self {
        let last = self.compliance.len().saturating_sub(1);
        for (frame, cell) in self.compliance.iter_mut().enumerate() {
            *cell = if frame == 0 || frame == last {
                0
            } else {
                priority
            };
        }
        self
    }

    /// This matrix with both gravity tilts at `priority` (gravity's
    /// direction identified with an elastic robot's compliances; 0
    /// identifies neither).
    pub fn with_gravity_tilt(mut self, priority: u32) -> Self {
        self.gravity_tilt = [priority; 2];
        self
    }

    /// Whether any compliance has a non-zero priority.
    pub fn identifies_compliances(&self) -> bool {
        self.compliance.iter().any(|priority| *priority > 0)
    }

    /// The default priorities of paper §4 for a robot of `frames` (0..=n+1;
    /// see the module docs).
    pub fn default_for(frames: &[Frame]) -> Self {
        let last = frames.len() - 1;
        let rows = frames
            .iter()
            .enumerate()
            .map(|(j, frame)| {
                let end_frame = j == 0 || j == last;
                let base_rule = if end_frame { 2 } else { 1 };
                let angle_rule = |value: f64| {
                    if is_multiple_of_half_pi(value) {
                        base_rule
                    } else {
                        3
                    }
                };
                let alpha = if j == 0 { 0 } else { angle_rule(frame.alpha) };
                let d = match j {
                    0 => 0,
                    _ if frame.d.abs() > LENGTH_ZERO => 4,
                    _ => base_rule,
                };
                let theta = if frame.frame_type == FrameType::Revolute {
                    5
                } else {
                    angle_rule(frame.theta)
                };
                let r = if frame.frame_type == FrameType::Prismatic {
                    5
                } else {
                    4
                };
                let beta = if j == 0 { 0 } else { base_rule };
                let gain = if end_frame { 0 } else { 5 };
                [alpha, d, theta, r, beta, gain]
            })
            .collect();
        Self::from_rows(rows)
    }

    /// The rows, frame 0 first; columns α, d, θ, r, β, K.
    pub fn rows(&self) -> &[[u32; 6]] {
        &self.rows
    }

    /// The priority of one parameter.
    ///
    /// # Panics
    /// If the frame is outside the matrix.
    pub fn get(&self, id: ParameterId) -> u32 {
        match id.kind {
            ParameterKind::Compliance => self.compliance[id.frame],
            ParameterKind::GravityTilt => match id.frame {
                axis @ 1..=2 => self.gravity_tilt[axis - 1],
                _ => 0,
            },
            kind => self.rows[id.frame][kind.column()],
        }
    }

    /// Sets the priority of one parameter.
    ///
    /// # Panics
    /// If the frame is outside the matrix, or the axis of a gravity tilt
    /// is not 1 or 2.
    pub fn set(&mut self, id: ParameterId, priority: u32) {
        match id.kind {
            ParameterKind::Compliance => self.compliance[id.frame] = priority,
            ParameterKind::GravityTilt => self.gravity_tilt[id.frame - 1] = priority,
            kind => self.rows[id.frame][kind.column()] = priority,
        }
    }

    /// The parameters with a non-zero priority, in the order the columns of W
    /// are taken: decreasing priority, ties in column-major order.
    pub fn ordered_candidates(&self, parameters: &ParameterSpace) -> Vec<ParameterId> {
        let mut candidates: Vec<(u32, ParameterId)> = ParameterKind::ALL
            .into_iter()
            .chain([ParameterKind::Compliance, ParameterKind::GravityTilt])
            .flat_map(|kind| (0..self.rows.len()).map(move |frame| ParameterId::new(kind, frame)))
            .filter(|id| parameters.contains(*id))
            .map(|id| (self.get(id), id))
            .filter(|(priority, _)| *priority > 0)
            .collect();
        // Stable: equal priorities keep their column-major order.
        candidates.sort_by_key(|(priority, _)| std::cmp::Reverse(*priority));
        candidates.into_iter().map(|(_, id)| id).collect()
    }

    /// Checks the shape (n+2 rows) and that only parameters have a non-zero priority.
    ///
    /// # Errors
    /// [`Error::Invalid`] on [`Field::Priority`].
    pub fn validate(&self, parameters: &ParameterSpace) -> Result<(), Error> {
        let expected = parameters.joint_count() + 2;
        if self.rows.len() != expected {
            return Err(Error::invalid(
                Field::Priority { row: None },
                format!(
                    "needs {expected} rows (frames 0..{}), one per frame, got {}",
                    expected - 1,
                    self.rows.len()
                ),
            ));
        }
        for frame in 0..self.rows.len() {
            for kind in ParameterKind::ALL {
                let id = ParameterId::new(kind, frame);
                let priority = self.get(id);
                if priority != 0 && !parameters.contains(id) {
                    return Err(Error::invalid(
                        Field::Priority { row: Some(frame) },
                        format!(
                            "{id} is not a parameter (frame 0 carries only theta0 and r0; \
                             fixed frames have no gain), so its priority must be 0, not {priority}"
                        ),
                    ));
                }
            }
            let id = ParameterId::new(ParameterKind::Compliance, frame);
            let priority = self.get(id);
            if priority != 0 && !parameters.contains(id) {
                return Err(Error::invalid(
                    Field::Priority { row: Some(frame) },
                    format!(
                        "{id} is not a parameter (only the joints of an elastic robot have a \
                         compliance), so its priority must be 0, not {priority}"
                    ),
                ));
            }
        }
        if self.gravity_tilt != [0; 2] && !parameters.is_elastic() {
            return Err(Error::invalid(
                Field::Priority { row: None },
                "gravity's tilt is identified with an elastic robot's compliances only (a rigid \
                 robot's joints do not yield to gravity), so its priority must be 0",
            ));
        }
        Ok(())
    }
}

/// Lengths below this (metres) count as zero for the default rules.
const LENGTH_ZERO: f64 = 1e-12;

fn is_multiple_of_half_pi(angle: f64) -> bool {
    let quarter_turns = angle / std::f64::consts::FRAC_PI_2;
    (quarter_turns - quarter_turns.round()).abs() < 1e-9
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ready_robot_for_tests as stanford;

    #[test]
    fn stanford_defaults_follow_the_rules() {
        let robot = stanford();
        let priority = PriorityMatrix::default_for(robot.frames());
        // Rows as derived by hand from Table 1 with the rules of NOTES.md.
        let expected: Vec<[u32; 6]> = vec![
            [0, 0, 2, 4, 0, 0], // frame 0: theta0 = π/2 → 2, r0 → 4
            [3, 1, 5, 4, 1, 5], // alpha1 = 0.1 → 3
            [1, 1, 5, 4, 1, 5],
            [1, 1, 1, 5, 1, 5], // prismatic: r3 → 5, theta3 = 0 → 1
            [1, 1, 5, 4, 1, 5],
            [1, 1, 5, 4, 1, 5],
            [1, 1, 5, 4, 1, 5],
            [3, 4, 2, 4, 2, 0], // frame 7: alpha7 = 1.3 → 3, d7 → 4, theta7 = π/2 → 2
        ];
        assert_eq!(priority.rows(), expected.as_slice());
        priority
            .validate(robot.parameters())
            .expect("defaults are valid");
    }

    #[test]
    fn candidates_are_sorted_by_priority_then_column_major() {
        let robot = stanford();
        let order =
            PriorityMatrix::default_for(robot.frames()).ordered_candidates(robot.parameters());
        assert_eq!(order.len(), 43);
        let names: Vec<String> = order.iter().map(ToString::to_string).collect();
        // Priority 5, column-major: θ of revolute joints, r3, then the gains.
        assert_eq!(
            &names[..12],
            [
                "theta1", "theta2", "theta4", "theta5", "theta6", "r3", "K1", "K2", "K3", "K4",
                "K5", "K6"
            ]
        );
        // Priority 4: d7 first (d column before r column), then r0, r1, ...
        assert_eq!(&names[12..15], ["d7", "r0", "r1"]);
    }

    #[test]
    fn compliances_are_candidates_of_an_elastic_robot_only_when_asked_for() {
        let robot = stanford();
        let rigid = PriorityMatrix::default_for(robot.frames());
        let elastic = crate::ParameterSpace::elastic(6);
        assert_eq!(rigid.ordered_candidates(&elastic).len(), 43);
        let asked = rigid.clone().with_compliances(1);
        assert!(asked.identifies_compliances() && !rigid.identifies_compliances());
        let names: Vec<String> = asked
            .ordered_candidates(&elastic)
            .iter()
            .map(ToString::to_string)
            .collect();
        assert_eq!(&names[43..], ["c1", "c2", "c3", "c4", "c5", "c6"]);
        asked.validate(&elastic).expect("elastic");
        // A rigid robot has no compliance to give a priority to.
        assert!(asked.validate(robot.parameters()).is_err());
        // The gravity tilts come last, when asked for, and only elastic.
        let tilted = asked.with_gravity_tilt(1);
        let names: Vec<String> = tilted
            .ordered_candidates(&elastic)
            .iter()
            .map(ToString::to_string)
            .collect();
        assert_eq!(&names[49..], ["tilt1", "tilt2"]);
        tilted.validate(&elastic).expect("elastic");
        let rigid_tilted = rigid.with_gravity_tilt(1);
        assert!(rigid_tilted.validate(robot.parameters()).is_err());
    }

    #[test]
    fn priority_for_a_non_parameter_is_rejected() {
        let robot = stanford();
        let mut priority = PriorityMatrix::default_for(robot.frames());
        priority.rows[0][0] = 1; // alpha0
        assert!(priority.validate(robot.parameters()).is_err());
        let short = PriorityMatrix::from_rows(priority.rows[..7].to_vec());
        assert!(short.validate(robot.parameters()).is_err());
    }
}
