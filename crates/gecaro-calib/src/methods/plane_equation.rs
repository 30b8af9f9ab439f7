//! Plane link 1, with the plane equation (paper §3.3.1): the terminal points
//! lie in a plane `a x + b y + c z + 1 = 0` (eq. 13–14). One row per
//! configuration (eq. 15). The plane is known, or unknown and identified with
//! η, starting from the best-fit plane of the nominal points.
//!
//! Rows are eq. 15 divided by ‖(a, b, c)‖ so that the residual is the distance
//! of the terminal point from the plane, in metres:
//! `f = (a·P + 1)/‖a‖`, `(a·J_P/‖a‖) Δη + ∂f/∂a Δa = −f`.

use gecaro_core::JacobianRows;
use nalgebra::Vector3;

use super::plane::{PlaneContact, fitted_unknowns, plane_unknowns, required};
use crate::error::Error;
use crate::method::{CalibrationMethod, MethodInfo, Sensor};
use crate::plane::Plane;
use crate::rows::{RowKind, RowWriter};
use crate::samples::SampleSlice;
use crate::states::TerminalState;

pub(super) const INFO: MethodInfo = MethodInfo::new(
    "plane1",
    "Plane link 1",
    &[],
    JacobianRows::Position,
    1,
    |options| {
        let known = if options.plane_unknown {
            None
        } else {
            Some(required(options.plane, "plane1 with a known plane")?.coefficients()?)
        };
        Ok(Box::new(PlaneEquation {
            sensor: PlaneContact {
                plane: options.plane,
                method: "plane1",
            },
            known,
        }))
    },
)
.independent()
.scale_invariant()
.with_plane();

/// Plane link 1; see the module docs.
#[derive(Clone, Debug)]
pub(crate) struct PlaneEquation {
    /// The plane to generate points in.
    sensor: PlaneContact,
    /// The coefficients (a, b, c) when the plane is known.
    known: Option<Vector3<f64>>,
}

impl CalibrationMethod for PlaneEquation {
    fn info(&self) -> &'static MethodInfo {
        &INFO
    }

    fn sensor(&self) -> &dyn Sensor {
        &self.sensor
    }

    fn auxiliary_names(&self) -> Vec<String> {
        plane_unknowns(self.known.is_none())
    }

    fn initial_auxiliary(&self, states: &[TerminalState]) -> Result<Vec<f64>, Error> {
        fitted_unknowns(self.known.is_none(), states, Plane::coefficients)
    }

    fn linearise(
        &self,
        _samples: SampleSlice<'_>,
        states: &[TerminalState],
        auxiliary: &[f64],
        rows: &mut RowWriter<'_>,
    ) {
        let unknown = self.known.is_none();
        let abc = self
            .known
            .unwrap_or_else(|| Vector3::from_column_slice(&auxiliary[..3]));
        let norm = abc.norm();
        let mut coefficients = vec![0.0; states.first().map_or(0, TerminalState::parameter_count)];
        for (index, state) in states.iter().enumerate() {
            let point = state.pose.translation.vector;
            let distance = (abc.dot(&point) + 1.0) / norm;
            coefficients.fill(0.0);
            for axis in 0..3 {
                state.add_jacobian_row(axis, abc[axis] / norm, &mut coefficients);
            }
            let derivative = point / norm - abc * (distance / norm);
            let auxiliary_row: &[f64] = if unknown { derivative.as_slice() } else { &[] };
            rows.push(
                RowKind::Length,
                index,
                -distance,
                &coefficients,
                auxiliary_row,
            );
        }
    }
}
