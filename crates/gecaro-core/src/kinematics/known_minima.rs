//! Least-squares minima short of a target that earlier solves of it settled
//! at, so that later solves from other starts give up on the way there
//! ([`InverseSolver::solve_avoiding`](super::InverseSolver::solve_avoiding)).
//!
//! A search for a configuration that meets a hard target (a pose beside a
//! fold of the workspace, or out of reach) starts the inverse model from
//! many configurations; most starts fall into the same few basins and each
//! solve crawls down to a minimum already found, ten to twenty iterations
//! for nothing. A solve whose joint positions come within
//! [`KnownMinima::radius`] of a known minimum, every joint at once (radians
//! for a revolute joint, metres for a prismatic one), is given up there.
//!
//! The radius is a joint-space distance. A basin's minimum is an isolated
//! point where the gradient of ‖Δx‖² vanishes, so an iterate that close to
//! one ends there, unless the minimum is a saddle the descent passes by;
//! the radius is kept small for that.

/// The minima found so far, for one target and one set of options (the
/// minima with the joint limits respected are not those without).
///
/// # Example
///
/// ```
/// use gecaro_core::KnownMinima;
///
/// let mut known = KnownMinima::new(0.01);
/// known.record(&[0.5, -1.0]);
/// known.record(&[0.505, -0.995]); // the same minimum
/// assert!(known.is_near(&[0.505, -0.995]));
/// assert!(!known.is_near(&[0.5, -0.98]));
/// assert_eq!(known.len(), 1);
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct KnownMinima {
    radius: f64,
    minima: Vec<Vec<f64>>,
}

impl KnownMinima {
    /// No minima yet; a solve is given up within `radius` of one (per
    /// joint: rad, or m).
    pub fn new(radius: f64) -> Self {
        KnownMinima {
            radius,
            minima: Vec::new(),
        }
    }

    /// The distance, per joint, within which a solve is given up.
    pub fn radius(&self) -> f64 {
        self.radius
    }

    /// Minima recorded.
    pub fn len(&self) -> usize {
        self.minima.len()
    }

    /// Whether none is recorded.
    pub fn is_empty(&self) -> bool {
        self.minima.is_empty()
    }

    /// Records the joint positions where a solve settled short of the
    /// target, unless they are near a minimum already recorded (a solve
    /// given up there, or one that settled at it again).
    pub fn record(&mut self, joint_positions: &[f64]) {
        if !self.is_near(joint_positions) {
            self.minima.push(joint_positions.to_vec());
        }
    }

    /// Whether every joint of `joint_positions` is within the radius of a
    /// recorded minimum's.
    pub fn is_near(&self, joint_positions: &[f64]) -> bool {
        self.minima.iter().any(|minimum| {
            minimum.len() == joint_positions.len()
                && minimum
                    .iter()
                    .zip(joint_positions)
                    .all(|(a, b)| (a - b).abs() < self.radius)
        })
    }
}
