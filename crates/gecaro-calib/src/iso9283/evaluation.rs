//! The test evaluated (clauses 7.2, 7.2.4 and 7.3): the measured visits of
//! the program's poses, registered into the robot's base frame, grouped by
//! pose and approach direction, and their characteristics.
//!
//! - **Registration** ([`Registration`]): the measurements are in the base
//!   frame already, or in an instrument frame whose pose in the base frame
//!   is stated, or registered by the rigid fit of the barycentres of every
//!   pose and direction onto the commanded positions (closed form,
//!   [`rigid_fit`]). A best fit absorbs whatever error of the robot looks
//!   like a rigid motion of the five poses; the report says which was used.
//! - **Pose accuracy and repeatability** are computed over the visits of
//!   direction 1 (the pose test's); **vAP** over the three directions when
//!   the test has them.
//! - **Distance accuracy and repeatability** between P2 and P4, over the
//!   cycles (direction 1) that measured both.
//! - Orientation characteristics when every visit's orientation was
//!   measured; positions only otherwise.

use std::collections::HashMap;

use nalgebra::{IsometryMatrix3, Rotation3, Translation3, Vector3};

use super::characteristics::{
    DirectionalVariation, DistanceCharacteristics, PoseCharacteristics, distance_characteristics,
    multi_directional, pose_characteristics,
};
use crate::Error;
use crate::registration::rigid_fit;

/// One measured visit of a pose.
#[derive(Clone, Debug, PartialEq)]
pub struct Visit {
    /// The pose (1–5).
    pub pose: usize,
    /// The cycle.
    pub cycle: usize,
    /// The approach direction (1–3).
    pub direction: usize,
    /// The commanded pose of frame n+1 (base frame).
    pub commanded: IsometryMatrix3<f64>,
    /// The attained position (the measurement frame).
    pub position: Vector3<f64>,
    /// The attained orientation, when measured (the measurement frame).
    pub orientation: Option<Rotation3<f64>>,
}

/// How the measurement frame is brought into the robot's base frame.
#[derive(Clone, Debug, PartialEq)]
pub enum Registration {
    /// The measurements are in the base frame.
    Base,
    /// The measurement frame's pose in the base frame.
    Stated(IsometryMatrix3<f64>),
    /// The rigid fit of the barycentres onto the commanded positions.
    BestFit,
}

/// One pose's results.
#[derive(Clone, Debug, PartialEq)]
pub struct PoseResult {
    /// The pose (1–5).
    pub pose: usize,
    /// Its commanded pose.
    pub commanded: IsometryMatrix3<f64>,
    /// AP and RP (direction 1).
    pub characteristics: PoseCharacteristics,
    /// vAP, with three directions.
    pub variation: Option<DirectionalVariation>,
    /// The attained positions of direction 1, registered (base frame).
    pub attained: Vec<Vector3<f64>>,
}

/// The evaluated test.
#[derive(Clone, Debug, PartialEq)]
pub struct TestEvaluation {
    /// The measurement frame's pose in the base frame (as stated, fitted,
    /// or the identity).
    pub frame: IsometryMatrix3<f64>,
    /// How it was found.
    pub registration: Registration,
    /// Whether orientations were measured (the orientation characteristics
    /// of [`PoseResult`] mean nothing otherwise).
    pub oriented: bool,
    /// Approach directions.
    pub directions: usize,
    /// Per pose measured, in order.
    pub poses: Vec<PoseResult>,
    /// Between P2 and P4, when both were measured in two cycles or more.
    pub distance: Option<DistanceCharacteristics>,
}

impl TestEvaluation {
    /// The largest AP_P of the poses (m).
    pub fn worst_accuracy(&self) -> f64 {
        self.poses
            .iter()
            .map(|pose| pose.characteristics.accuracy)
            .fold(0.0, f64::max)
    }

    /// The largest RP_l of the poses (m).
    pub fn worst_repeatability(&self) -> f64 {
        self.poses
            .iter()
            .map(|pose| pose.characteristics.repeatability)
            .fold(0.0, f64::max)
    }
}

/// The attained pose of `visit` in the base frame (`frame` maps the
/// measurement frame into it); its orientation the commanded one when not
/// measured.
fn attained(visit: &Visit, frame: &IsometryMatrix3<f64>) -> IsometryMatrix3<f64> {
    let rotation = visit
        .orientation
        .map_or(visit.commanded.rotation, |rotation| {
            frame.rotation * rotation
        });
    IsometryMatrix3::from_parts(
        Translation3::from(frame * nalgebra::Point3::from(visit.position)),
        rotation,
    )
}

/// Evaluates the test from its measured `visits` (module docs).
///
/// # Errors
/// [`Error::InvalidData`] for no visit, a pose outside 1–5, a pose
/// commanded at two places, a pose with fewer than two cycles, or a best
/// fit on fewer than three poses.
pub fn evaluate_test(
    visits: &[Visit],
    registration: &Registration,
) -> Result<TestEvaluation, Error> {
    let invalid = |message: String| Error::InvalidData {
        line: None,
        message,
    };
    if visits.is_empty() {
        return Err(invalid("no measured visit of the test's poses".into()));
    }
    if let Some(visit) = visits.iter().find(|visit| !(1..=5).contains(&visit.pose)) {
        return Err(invalid(format!(
            "pose {} is none of the test's P1–P5",
            visit.pose
        )));
    }
    let directions = visits
        .iter()
        .map(|visit| visit.direction)
        .max()
        .unwrap_or(1);
    // Each pose is commanded at one place.
    let mut commanded: [Option<IsometryMatrix3<f64>>; 5] = [None; 5];
    for visit in visits {
        let slot = &mut commanded[visit.pose - 1];
        match slot {
            None => *slot = Some(visit.commanded),
            Some(first) => {
                let apart = (first.translation.vector - visit.commanded.translation.vector).norm();
                // (The matrices' difference: an angle from a trace is only
                // good to 1e-8 rad near zero.)
                let turned = (first.rotation.matrix() - visit.commanded.rotation.matrix()).norm();
                if apart > 1e-9 || turned > 1e-9 {
                    return Err(invalid(format!(
                        "P{} is commanded at two poses {:.6} mm and {:.6}° apart (cycle {}); \
                         every visit of a pose is commanded at the same one",
                        visit.pose,
                        apart * 1e3,
                        (first.rotation.inverse() * visit.commanded.rotation)
                            .angle()
                            .to_degrees(),
                        visit.cycle
                    )));
                }
            }
        }
    }
    // The visits of each pose and direction, grouped once.
    let mut groups: HashMap<(usize, usize), Vec<&Visit>> = HashMap::new();
    for visit in visits {
        groups
            .entry((visit.pose, visit.direction))
            .or_default()
            .push(visit);
    }
    let group = |pose: usize, direction: usize| -> &[&Visit] {
        groups.get(&(pose, direction)).map_or(&[], Vec::as_slice)
    };
    let frame = match registration {
        Registration::Base => IsometryMatrix3::identity(),
        Registration::Stated(frame) => *frame,
        Registration::BestFit => {
            let mut from = Vec::new();
            let mut to = Vec::new();
            for pose in 1..=5 {
                for direction in 1..=directions {
                    let members = group(pose, direction);
                    if members.is_empty() {
                        continue;
                    }
                    let sum: Vector3<f64> = members.iter().map(|visit| visit.position).sum();
                    from.push(sum / members.len() as f64);
                    to.push(members[0].commanded.translation.vector);
                }
            }
            let distinct = commanded.iter().flatten().count();
            if distinct < 3 {
                return Err(invalid(format!(
                    "a best fit of the measurement frame needs 3 poses or more; {distinct} \
                     measured"
                )));
            }
            rigid_fit(&from, &to)
        }
    };
    let oriented = visits.iter().all(|visit| visit.orientation.is_some());
    let mut poses = Vec::new();
    for (index, commanded) in commanded.iter().enumerate() {
        let Some(commanded) = commanded else {
            continue;
        };
        let pose = index + 1;
        let first: Vec<IsometryMatrix3<f64>> = group(pose, 1)
            .iter()
            .map(|visit| attained(visit, &frame))
            .collect();
        let characteristics = pose_characteristics(commanded, &first)
            .map_err(|error| invalid(format!("P{pose}: {error}")))?;
        let variation = if directions > 1 {
            let approaches: Vec<Vec<IsometryMatrix3<f64>>> = (1..=directions)
                .map(|direction| {
                    group(pose, direction)
                        .iter()
                        .map(|visit| attained(visit, &frame))
                        .collect()
                })
                .collect();
            Some(
                multi_directional(commanded, &approaches)
                    .map_err(|error| invalid(format!("P{pose}: {error}")))?,
            )
        } else {
            None
        };
        poses.push(PoseResult {
            pose,
            commanded: *commanded,
            characteristics,
            variation,
            attained: first.iter().map(|pose| pose.translation.vector).collect(),
        });
    }
    let distance = match (commanded[1], commanded[3]) {
        (Some(p2), Some(p4)) => {
            let position = |visit: &Visit| attained(visit, &frame).translation.vector;
            let fourth: HashMap<usize, Vector3<f64>> = group(4, 1)
                .iter()
                .map(|visit| (visit.cycle, position(visit)))
                .collect();
            // The cycles that measured both, in P2's order.
            let (first, second): (Vec<_>, Vec<_>) = group(2, 1)
                .iter()
                .filter_map(|visit| {
                    fourth
                        .get(&visit.cycle)
                        .map(|other| (position(visit), *other))
                })
                .unzip();
            (first.len() >= 2)
                .then(|| {
                    distance_characteristics(
                        (p2.translation.vector, p4.translation.vector),
                        &first,
                        &second,
                    )
                })
                .transpose()?
        }
        _ => None,
    };
    Ok(TestEvaluation {
        frame,
        registration: registration.clone(),
        oriented,
        directions,
        poses,
        distance,
    })
}
