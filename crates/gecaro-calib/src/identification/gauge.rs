//! The gauge row that holds a robot's scale where it is, in a step over
//! every parameter of a study that does not observe it (the score tests,
//! the damped descent; see [`super::scale`]).

use gecaro_core::{FrameType, ParameterId, ParameterKind, Robot};

use crate::observation::ObservationSystem;
use crate::prior::Prior;
use crate::rows::ColumnLayout;

/// The weight of the gauge row per square root of a data row (rows in units
/// of their σ): a step along the scale direction, whose column is the
/// residuals themselves, gains at most about 1e-8 of the scale.
const GAUGE_WEIGHT: f64 = 1e4;

/// Whether scaling the robot multiplies parameter `id` of `robot`: every d
/// and r, and the gains of prismatic joints.
pub(super) fn scales(robot: &Robot, id: ParameterId) -> bool {
    match id.kind {
        ParameterKind::D | ParameterKind::R => true,
        ParameterKind::Gain => robot.frames()[id.frame].frame_type == FrameType::Prismatic,
        _ => false,
    }
}

/// The row that holds the robot's scale while every parameter moves, for a
/// study that does not observe it (the score tests, the damped descent):
/// `Σ_k a_k Δη_k = 0` over the lengths and prismatic gains among the
/// system's columns, with `a_k = η_k/σ_k² / Σ_j η_j²/σ_j²` (σ the prior's),
/// the first-order change of the scale along the direction that multiplies
/// every length. Without it a step over every parameter takes that
/// direction, whose column is the residuals themselves (the points of a
/// link set move towards their common centre as the robot shrinks), for
/// structure. A base set needs none: it leaves out a length that pins the
/// scale.
#[derive(Clone, Debug)]
pub(super) struct Gauge {
    /// Column of W, vocabulary index and prior σ of each length.
    entries: Vec<(usize, usize, f64)>,
    /// The row's weight.
    weight: f64,
}

impl Gauge {
    /// The gauge over the lengths among the columns of `layout` (robot
    /// `robot`), for `data_rows` rows, with the σ of `prior`.
    pub(super) fn new(
        robot: &Robot,
        layout: &ColumnLayout,
        prior: &Prior,
        data_rows: usize,
    ) -> Gauge {
        let entries = layout
            .parameter_columns()
            .iter()
            .filter_map(|&(index, column)| {
                let id = robot.parameters().id(index);
                scales(robot, id).then(|| (column, index, prior.sigma(id, robot.parameter(id))))
            })
            .collect();
        Gauge {
            entries,
            weight: GAUGE_WEIGHT * (data_rows.max(1) as f64).sqrt(),
        }
    }

    /// Appends the row at `robot` to `system` (written at `robot`).
    pub(super) fn append_to(&self, system: &mut ObservationSystem, robot: &Robot) {
        let values: Vec<(usize, f64, f64)> = self
            .entries
            .iter()
            .map(|&(column, index, sigma)| {
                (column, robot.parameter(robot.parameters().id(index)), sigma)
            })
            .collect();
        let norm: f64 = values
            .iter()
            .map(|(_, value, sigma)| (value / sigma).powi(2))
            .sum();
        if !(norm > 0.0 && norm.is_finite()) {
            return;
        }
        let row: Vec<(usize, f64)> = values
            .iter()
            .map(|(column, value, sigma)| (*column, value / (sigma * sigma) / norm))
            .collect();
        system.append_row(&row, self.weight, 0.0);
    }
}
