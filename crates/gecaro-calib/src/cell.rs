//! The measuring cell: which configurations can really be measured.
//!
//! Random configurations within the joint limits are not all measurable: an
//! arm mounted on a floor cannot put its wrist below it, and a laser
//! tracker sees its reflector only when the reflector faces it (within the
//! reflector's acceptance cone) and no part of the arm is in the way. A
//! [`Cell`] states these conditions; points generation and planning draw
//! only configurations it admits ([`Sampler::with_cell`](crate::simulation::Sampler::with_cell)).
//!
//! Conventions (world frame −1 of the robot, metres, radians):
//! - **floor** `z_f`: the origins of frames 1..=n+1 (the joints and the tool)
//!   satisfy `z ≥ z_f`. Frame 0, the base, stands on whatever it stands on.
//! - **station** `s`, **maximum incidence** `θ_max`: with `t` the origin and
//!   `z_t` the z axis of frame n+1 (the reflector and the way it faces),
//!   `angle(z_t, s − t) ≤ θ_max`.
//! - **line of sight**: the arm is modelled at the level of its joint origins,
//!   as the segments between the origins of frames 0..=n; the sight line
//!   from `t` to `s`, less its first `clearance` metres (the tool itself),
//!   keeps at least `clearance` from each segment.

use gecaro_core::{Robot, forward_kinematics};
use nalgebra::Vector3;

use crate::Error;
use crate::error::Setting;

/// A tracker station: where it stands and what its reflector must do to be seen.
#[derive(Clone, Debug, PartialEq)]
pub struct Station {
    /// The station's position in the world frame (m).
    pub position: Vector3<f64>,
    /// The largest angle between the reflector's axis (z of frame n+1) and
    /// the direction to the station (rad); `None`: any.
    pub max_incidence: Option<f64>,
    /// The smallest distance of the sight line from the arm (m).
    pub clearance: f64,
}

/// Default clearance of the sight line from the arm: 5 cm.
pub const DEFAULT_CLEARANCE: f64 = 0.05;

/// The conditions a configuration must meet to be measured; see the module docs.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Cell {
    /// The floor's height in the world frame (m).
    pub floor: Option<f64>,
    /// The tracker station.
    pub station: Option<Station>,
}

impl Cell {
    /// Whether the cell admits every configuration.
    pub fn is_open(&self) -> bool {
        self.floor.is_none() && self.station.is_none()
    }

    /// Checks the cell's numbers.
    ///
    /// # Errors
    /// [`Error::InvalidOption`] naming the setting: values that are not
    /// finite, an incidence outside (0, 90°], a negative clearance.
    pub fn check(&self) -> Result<(), Error> {
        let invalid = |setting, message: String| Err(Error::InvalidOption { setting, message });
        if let Some(floor) = self.floor
            && !floor.is_finite()
        {
            return invalid(Setting::Floor, format!("{floor} is not a height (metres)"));
        }
        if let Some(station) = &self.station {
            if !station.position.iter().all(|v| v.is_finite()) {
                return invalid(
                    Setting::Station,
                    "needs three finite coordinates (metres)".into(),
                );
            }
            if let Some(angle) = station.max_incidence
                && !(angle > 0.0 && angle <= std::f64::consts::FRAC_PI_2)
            {
                return invalid(
                    Setting::MaxIncidence,
                    format!(
                        "{:.3}° is not an acceptance half-angle: between 0 and 90°",
                        angle.to_degrees()
                    ),
                );
            }
            if !(station.clearance.is_finite() && station.clearance >= 0.0) {
                return invalid(
                    Setting::Station,
                    format!("a clearance of {} m is not a distance", station.clearance),
                );
            }
        }
        Ok(())
    }

    /// Whether `robot` at `motor_positions` can be measured in this cell.
    pub fn admits(&self, robot: &Robot, motor_positions: &[f64]) -> bool {
        if self.is_open() {
            return true;
        }
        let Ok(chain) = forward_kinematics(robot, motor_positions) else {
            return false;
        };
        let origins: Vec<Vector3<f64>> = chain
            .poses()
            .iter()
            .map(|pose| pose.translation.vector)
            .collect();
        if let Some(floor) = self.floor
            && origins[1..].iter().any(|origin| origin.z < floor - 1e-9)
        {
            return false;
        }
        let Some(station) = &self.station else {
            return true;
        };
        let tool = chain.world_from_tool();
        let reflector = tool.translation.vector;
        let sight = station.position - reflector;
        let Some(direction) = sight.try_normalize(1e-12) else {
            return false;
        };
        if let Some(limit) = station.max_incidence {
            let axis = tool.rotation * Vector3::z();
            if axis.dot(&direction).clamp(-1.0, 1.0).acos() > limit {
                return false;
            }
        }
        if station.clearance > 0.0 {
            let length = sight.norm();
            if length <= station.clearance {
                return true;
            }
            let start = reflector + direction * station.clearance;
            let joints = &origins[..origins.len() - 1];
            for pair in joints.windows(2) {
                if segment_distance(start, station.position, pair[0], pair[1]) < station.clearance {
                    return false;
                }
            }
        }
        true
    }
}

/// The smallest distance between the segments [p1, q1] and [p2, q2]
/// (closest points of two segments, Ericson, *Real-Time Collision
/// Detection*, §5.1.9).
fn segment_distance(p1: Vector3<f64>, q1: Vector3<f64>, p2: Vector3<f64>, q2: Vector3<f64>) -> f64 {
    let (d1, d2, r) = (q1 - p1, q2 - p2, p1 - p2);
    let (a, e, f) = (d1.dot(&d1), d2.dot(&d2), d2.dot(&r));
    let tiny = 1e-15;
    let (s, t) = if a <= tiny && e <= tiny {
        (0.0, 0.0)
    } else if a <= tiny {
        (0.0, (f / e).clamp(0.0, 1.0))
    } else {
        let c = d1.dot(&r);
        if e <= tiny {
            ((-c / a).clamp(0.0, 1.0), 0.0)
        } else {
            let b = d1.dot(&d2);
            let denominator = a * e - b * b;
            let mut s = if denominator > tiny {
                ((b * f - c * e) / denominator).clamp(0.0, 1.0)
            } else {
                0.0
            };
            let mut t = (b * s + f) / e;
            if t < 0.0 {
                t = 0.0;
                s = (-c / a).clamp(0.0, 1.0);
            } else if t > 1.0 {
                t = 1.0;
                s = ((b - c) / a).clamp(0.0, 1.0);
            }
            (s, t)
        }
    };
    ((p1 + d1 * s) - (p2 + d2 * t)).norm()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn segment_distances_match_hand_cases() {
        let v = |x: f64, y: f64, z: f64| Vector3::new(x, y, z);
        // Crossing at right angles, 1 apart.
        let d = segment_distance(v(-1., 0., 0.), v(1., 0., 0.), v(0., -1., 1.), v(0., 1., 1.));
        assert!((d - 1.0).abs() < 1e-12);
        // Parallel, offset 2, overlapping.
        let d = segment_distance(v(0., 0., 0.), v(2., 0., 0.), v(1., 2., 0.), v(3., 2., 0.));
        assert!((d - 2.0).abs() < 1e-12);
        // End to end, beyond each other.
        let d = segment_distance(v(0., 0., 0.), v(1., 0., 0.), v(4., 0., 0.), v(5., 0., 0.));
        assert!((d - 3.0).abs() < 1e-12);
        // A point against a segment.
        let d = segment_distance(v(0., 1., 0.), v(0., 1., 0.), v(-1., 0., 0.), v(1., 0., 0.));
        assert!((d - 1.0).abs() < 1e-12);
    }

    #[test]
    fn an_open_cell_admits_everything_and_a_floor_cuts() {
        let robot = gecaro_core::Robot::template("arm", "RRR").expect("robot");
        let open = Cell::default();
        assert!(open.admits(&robot, &[0.3, -0.2, 0.1]));
        // The template arm: frame 2 turns about x of frame 1 (α2 = −π/2), so q2 tips the arm down.
        let cell = Cell {
            floor: Some(0.0),
            station: None,
        };
        let up = [0.0, 0.0, 0.0];
        let chain = forward_kinematics(&robot, &up).expect("fk");
        let lowest = chain
            .poses()
            .iter()
            .skip(1)
            .map(|pose| pose.translation.vector.z)
            .fold(f64::INFINITY, f64::min);
        assert_eq!(cell.admits(&robot, &up), lowest >= -1e-9);
    }
}
