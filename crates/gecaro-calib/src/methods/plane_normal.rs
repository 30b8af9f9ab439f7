//! Plane link 2, with the plane normal (paper §3.3.2): the terminal points lie
//! in a plane whose normal (a, b, c) is known (an inclinometer gives it) or
//! unknown. The vector between any two points of the plane is orthogonal to
//! the normal (eq. 16–17); written for all pairs at once by centring on the
//! mean point, one row per configuration:
//! `(n·(J_i − J̄)/‖n‖) Δη + ∂f/∂n Δn = −n·(P_i − P̄)/‖n‖`.
//!
//! An unknown normal is identified with η. Its scale has no effect, so one of
//! a, b, c comes out non-identifiable ('n') and stays fixed: "2 of a, b, c
//! identified", as in Table 2.

use gecaro_core::JacobianRows;
use nalgebra::Vector3;

use super::plane::{PlaneContact, fitted_unknowns, plane_unknowns, required};
use super::sets::centre;
use crate::error::Error;
use crate::method::{CalibrationMethod, MethodInfo, Sensor};
use crate::rows::{RowKind, RowWriter};
use crate::samples::SampleSlice;
use crate::states::TerminalState;

pub(super) const INFO: MethodInfo = MethodInfo::new(
    "plane2",
    "Plane link 2",
    &[],
    JacobianRows::Position,
    1,
    |options| {
        let known = if options.plane_unknown {
            None
        } else {
            Some(required(options.plane, "plane2 with a known normal")?.normal())
        };
        Ok(Box::new(PlaneNormal {
            sensor: PlaneContact {
                plane: options.plane,
                method: "plane2",
            },
            known,
        }))
    },
)
.scale_invariant()
.with_plane();

/// Plane link 2; see the module docs.
#[derive(Clone, Debug)]
pub(crate) struct PlaneNormal {
    sensor: PlaneContact,
    known: Option<Vector3<f64>>,
}

impl CalibrationMethod for PlaneNormal {
    fn info(&self) -> &'static MethodInfo {
        &INFO
    }

    fn sensor(&self) -> &dyn Sensor {
        &self.sensor
    }

    fn dependent_rows(&self, _samples: SampleSlice<'_>) -> usize {
        1
    }

    fn auxiliary_names(&self) -> Vec<String> {
        plane_unknowns(self.known.is_none())
    }

    fn initial_auxiliary(&self, states: &[TerminalState]) -> Result<Vec<f64>, Error> {
        fitted_unknowns(self.known.is_none(), states, |plane| Ok(plane.normal()))
    }

    fn linearise(
        &self,
        _samples: SampleSlice<'_>,
        states: &[TerminalState],
        auxiliary: &[f64],
        rows: &mut RowWriter<'_>,
    ) {
        let unknown = self.known.is_none();
        let normal = self
            .known
            .unwrap_or_else(|| Vector3::from_column_slice(&auxiliary[..3]));
        let norm = normal.norm();
        let parameters = states.first().map_or(0, TerminalState::parameter_count);
        let count = states.len();
        let mut values = vec![0.0; count];
        let mut coefficients = vec![0.0; count * parameters];
        let mut derivatives = vec![0.0; count * 3];
        for (index, state) in states.iter().enumerate() {
            let point = state.pose.translation.vector;
            values[index] = normal.dot(&point) / norm;
            let row = &mut coefficients[index * parameters..(index + 1) * parameters];
            for axis in 0..3 {
                state.add_jacobian_row(axis, normal[axis] / norm, row);
            }
            let derivative = point / norm - normal * (values[index] / norm);
            derivatives[index * 3..(index + 1) * 3].copy_from_slice(derivative.as_slice());
        }
        let weights: Vec<f64> = (0..count)
            .map(|index| rows.observation_weight(index))
            .collect();
        for buffer in [&mut values, &mut coefficients, &mut derivatives] {
            centre(buffer, &weights);
        }
        for index in 0..count {
            let auxiliary_row: &[f64] = if unknown {
                &derivatives[index * 3..(index + 1) * 3]
            } else {
                &[]
            };
            let row = &coefficients[index * parameters..(index + 1) * parameters];
            rows.push(RowKind::Length, index, -values[index], row, auxiliary_row);
        }
    }
}
