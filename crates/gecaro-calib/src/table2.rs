//! The paper's Table 2: the identifiable parameters of every method for one
//! robot, nine columns (NOTES.md).
//!
//! | column | method |
//! |---|---|
//! | 1 | position measure |
//! | 2 | frame measure |
//! | 3 | point link |
//! | 4 | frame link |
//! | 5 | plane link 1, plane known |
//! | 6 | plane link 1, plane unknown (a, b, c identified too, not counted) |
//! | 7 | plane link 2, normal known |
//! | 8 | plane link 2, normal unknown (2 of a, b, c identified, not counted) |
//! | 9 | distance measure |

use gecaro_core::{PriorityMatrix, Robot, terminal_pose};
use nalgebra::Vector3;

use crate::Error;
use crate::identifiability::{RankReport, identifiable_parameters, random_samples};
use crate::method::MethodOptions;
use crate::methods::method;
use crate::plane::Plane;
use crate::progress::Quiet;
use crate::sampler::Sampler;
use crate::study::Study;

/// One column of Table 2: a method and whether its plane is unknown.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub struct Table2Column {
    /// Short heading.
    pub heading: &'static str,
    /// Method name.
    pub method: &'static str,
    /// Plane (plane1) or normal (plane2) unknown.
    pub plane_unknown: bool,
}

/// The nine columns, in the paper's order.
pub const TABLE2_COLUMNS: [Table2Column; 9] = [
    Table2Column {
        heading: "position",
        method: "position",
        plane_unknown: false,
    },
    Table2Column {
        heading: "frame",
        method: "frame",
        plane_unknown: false,
    },
    Table2Column {
        heading: "point link",
        method: "point-link",
        plane_unknown: false,
    },
    Table2Column {
        heading: "frame link",
        method: "frame-link",
        plane_unknown: false,
    },
    Table2Column {
        heading: "plane1 known",
        method: "plane1",
        plane_unknown: false,
    },
    Table2Column {
        heading: "plane1 unknown",
        method: "plane1",
        plane_unknown: true,
    },
    Table2Column {
        heading: "plane2 known",
        method: "plane2",
        plane_unknown: false,
    },
    Table2Column {
        heading: "plane2 unknown",
        method: "plane2",
        plane_unknown: true,
    },
    Table2Column {
        heading: "distance",
        method: "distance",
        plane_unknown: false,
    },
];

/// The plane normal of the paper's Table 2 (NOTES.md): oblique, so that no
/// axis of the world frame lies in it.
pub const TABLE2_PLANE_NORMAL: [f64; 3] = [0.3, 0.5, 0.81];

/// The point the Table 2 plane passes through for the Stanford arm (NOTES.md).
pub const STANFORD_PLANE_POINT: [f64; 3] = [0.3, 0.2, 0.6];

/// A plane through the middle of `robot`'s workspace with the Table 2 normal:
/// through the mean terminal point of 200 random configurations (seeded, so
/// always the same).
///
/// # Errors
/// Never for a valid robot; passes kinematic errors on.
pub fn default_plane(robot: &Robot) -> Result<Plane, Error> {
    let mut sampler = Sampler::new(0x7AB1E2);
    let mut sum = Vector3::zeros();
    const COUNT: usize = 200;
    for _ in 0..COUNT {
        sum += terminal_pose(robot, &sampler.configuration(robot))?
            .translation
            .vector;
    }
    Plane::new(Vector3::from(TABLE2_PLANE_NORMAL), sum / COUNT as f64)
}

/// All nine columns of Table 2 for `robot`, with the plane `plane` for the
/// plane methods, from random configurations drawn with `seed`.
///
/// # Errors
/// When a column's data cannot be generated (a plane out of reach).
pub fn table2(
    robot: &Robot,
    plane: Plane,
    priority: &PriorityMatrix,
    seed: u64,
) -> Result<Vec<RankReport>, Error> {
    TABLE2_COLUMNS
        .iter()
        .enumerate()
        .map(|(index, column)| {
            let options = MethodOptions {
                plane: Some(plane),
                plane_unknown: column.plane_unknown,
                ..MethodOptions::default()
            };
            let method = method(column.method, &options)?;
            let samples = random_samples(
                robot,
                method.as_ref(),
                None,
                seed.wrapping_add(index as u64),
                &mut Quiet,
            )?;
            let study = Study::single(method, samples, column.heading);
            identifiable_parameters(robot, &study, priority)
        })
        .collect()
}
