//! `gecaro.Data`: the configurations of a data set and what was measured at
//! each, as numpy arrays (one row per configuration, in the order of the
//! data file's rows).
//!
//! Units: metres and radians. `orientation` is a unit quaternion
//! `(qw, qx, qy, qz)` of frame n+1 in the world frame; `set` (link methods)
//! and `pair` (distance) are integer ids; `distance` is in metres.

use gecaro_app::{DataSource, LocalFiles, angle_unit, delimiter, length_unit, rotation_format};
use gecaro_calib::study::{Column, DataColumn, SampleColumns, Samples};
use gecaro_io::{ColumnMap, DataFormat, DataUnits, format_samples, joint_types};
use nalgebra::Vector3;
use numpy::PyArrayDyn;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::path::PathBuf;

use crate::arrays::{Real, array, column_of, identifiers};
use crate::data_set::ARRAYS;
pub(crate) use crate::data_set::PyData;
use crate::errors::{IntoPyResult, input};
use crate::files::write_text;
use crate::methods::method_of;
use crate::robot::PyRobot;

/// The column map of `columns`: a dict {gecaro name: file column} or text
/// `"x=X_mm,y=Y_mm"`.
fn column_map(columns: Option<&Bound<'_, PyAny>>) -> PyResult<ColumnMap> {
    let Some(columns) = columns else {
        return Ok(ColumnMap::default());
    };
    if let Ok(text) = columns.extract::<String>() {
        return ColumnMap::parse(&text).map_err(|message| input(format!("columns: {message}")));
    }
    let pairs: Vec<(String, String)> = columns
        .cast::<PyDict>()
        .map_err(|_| input("columns: expected a dict {gecaro name: file column} or \"x=X_mm,…\""))?
        .iter()
        .map(|(ours, theirs)| Ok((ours.extract()?, theirs.extract()?)))
        .collect::<PyResult<_>>()?;
    Ok(ColumnMap::from_pairs(pairs))
}

#[pymethods]
impl PyData {
    /// Data from arrays: `qm` of shape (m, n), and what the method measures:
    /// `position` (m, 3), `orientation` (m, 4) unit quaternions qw, qx, qy, qz,
    /// `set` or `pair` (m,) integer ids, `distance` (m,); and the payload
    /// carried at each row for elastic joints, `payload` (m,) masses in kg
    /// or (m, 4) mass and centre x, y, z in the tool frame (metres); and
    /// the σ the instrument states for each row, `sigma` (m,) of its
    /// lengths in metres and `sigma_angle` (m,) of its angles in radians
    /// (NaN: none stated, the set's σ there).
    #[new]
    #[pyo3(signature = (qm, *, position = None, orientation = None, set = None, pair = None, distance = None, payload = None, sigma = None, sigma_angle = None, label = None))]
    fn new(
        qm: &Bound<'_, PyAny>,
        position: Option<&Bound<'_, PyAny>>,
        orientation: Option<&Bound<'_, PyAny>>,
        set: Option<&Bound<'_, PyAny>>,
        pair: Option<&Bound<'_, PyAny>>,
        distance: Option<&Bound<'_, PyAny>>,
        payload: Option<&Bound<'_, PyAny>>,
        sigma: Option<&Bound<'_, PyAny>>,
        sigma_angle: Option<&Bound<'_, PyAny>>,
        label: Option<String>,
    ) -> PyResult<Self> {
        // The large columns are copied once (see `column_of`).
        let (shape, motor_positions) = column_of(qm, "qm", &[None, None])?;
        let (m, n) = (shape[0], shape[1]);
        if n == 0 {
            return Err(input(format!(
                "qm: expected an array of shape (m, n) with n ≥ 1 joints, got an array of \
                 shape ({m}, 0)"
            )));
        }
        let position = position
            .map(|position| column_of(position, "position", &[Some(m), Some(3)]))
            .transpose()?
            .map(|(_, column)| column);
        let orientation = orientation
            .map(|orientation| -> PyResult<Column<f64>> {
                let orientation = Real::shaped(orientation, "orientation", &[Some(m), Some(4)])?;
                let mut unit = Vec::with_capacity(orientation.values.len());
                for (row, q) in orientation.values.chunks_exact(4).enumerate() {
                    let q = gecaro_io::unit_quaternion(q[0], q[1], q[2], q[3])
                        .map_err(|message| input(format!("orientation: row {row}: {message}")))?;
                    unit.extend([q.w, q.i, q.j, q.k]);
                }
                Ok(unit.into())
            })
            .transpose()?;
        let group = match (set, pair) {
            (Some(_), Some(_)) => {
                return Err(input(
                    "give `set` (link methods) or `pair` (distance), not both",
                ));
            }
            (Some(ids), None) => Some(identifiers(ids, "set")?),
            (None, Some(ids)) => Some(identifiers(ids, "pair")?),
            (None, None) => None,
        };
        if let Some(group) = &group
            && group.len() != m
        {
            return Err(input(format!(
                "{}: expected an array of shape ({m},), got {} values",
                if set.is_some() { "set" } else { "pair" },
                group.len()
            )));
        }
        let distance = distance
            .map(|distance| column_of(distance, "distance", &[Some(m)]))
            .transpose()?
            .map(|(_, column)| column);
        let sigma = row_sigmas(m, sigma, sigma_angle)?;
        let mut samples = Samples::from_columns(SampleColumns {
            motor_positions,
            joints: n,
            position,
            orientation,
            group: group.map(Column::from),
            distance,
            sigma,
            first_line: 0,
        })
        .map_err(input)?;
        if let Some(payload) = payload {
            let payloads = Real::shaped(payload, "payload", &[Some(m)])
                .map(|masses| {
                    masses
                        .values
                        .into_iter()
                        .map(|mass| [mass, 0.0, 0.0, 0.0])
                        .collect()
                })
                .or_else(|_| {
                    Real::shaped(payload, "payload", &[Some(m), Some(4)]).map(|rows| {
                        rows.values
                            .chunks_exact(4)
                            .map(|row| [row[0], row[1], row[2], row[3]])
                            .collect::<Vec<[f64; 4]>>()
                    })
                })?;
            for (row, (loads, [mass, x, y, z])) in
                samples.loads_mut().iter_mut().zip(payloads).enumerate()
            {
                let payload = gecaro_core::LinkMass {
                    mass,
                    com: Vector3::new(x, y, z),
                };
                gecaro_io::check_payload(&payload)
                    .map_err(|message| input(format!("payload: row {row}: {message}")))?;
                loads.get_or_insert_with(Box::default).payload = Some(payload);
            }
        }
        Ok(PyData::from_samples(
            samples,
            n,
            label.unwrap_or_else(|| ARRAYS.to_owned()),
        ))
    }

    /// Reads a data file (CSV) for `robot` and `method`, as the command line's
    /// `--data`: columns found by name in any order, other names through
    /// `columns` ({"x": "X_mm"} or "x=X_mm,…"), lengths in `length_unit`
    /// ("m", "mm"), revolute joint values in `angle_unit` ("rad", "deg").
    /// Columns the method does not use are listed in `unused_columns`.
    /// Fields are separated by `delimiter` ("comma", "semicolon", "tab";
    /// by default found from the header), and numbers may have a decimal
    /// comma where fields are not comma-separated (`decimal_comma` True
    /// requires, False refuses it). Orientations are `qw,qx,qy,qz` unless
    /// `rotation` says "rpy", "euler-xyz", "euler-zyz" or "rotation-vector"
    /// (`rx,ry,rz` in `angle_unit`).
    #[staticmethod]
    #[pyo3(signature = (path, robot, method, *, length_unit = None, angle_unit = None, columns = None, delimiter = None, decimal_comma = None, rotation = None))]
    fn read(
        path: PathBuf,
        robot: PyRef<'_, PyRobot>,
        method: &Bound<'_, PyAny>,
        length_unit: Option<&str>,
        angle_unit: Option<&str>,
        columns: Option<&Bound<'_, PyAny>>,
        delimiter: Option<&str>,
        decimal_comma: Option<bool>,
        rotation: Option<String>,
    ) -> PyResult<Self> {
        let method = method_of(method)?;
        let format = DataFormat {
            units: DataUnits {
                length: self::length_unit(length_unit).py()?.unwrap_or_default(),
                angle: self::angle_unit(angle_unit).py()?.unwrap_or_default(),
            },
            columns: column_map(columns)?,
            delimiter: self::delimiter(delimiter).py()?,
            decimal_comma,
            rotation: rotation_format(rotation.as_deref()).py()?,
        };
        let file = DataSource::File(path.display().to_string())
            .read(
                &LocalFiles,
                &joint_types(robot.robot()),
                method.get().method.data_columns(),
                &format,
            )
            .py()?;
        Ok(PyData {
            samples: file.samples,
            joint_count: robot.robot().joint_count(),
            label: path.display().to_string(),
            unused_columns: file.unused_columns,
        })
    }

    /// The data file's text (CSV) for `method`, as `gecaro generate` writes it
    /// (values written to round trip exactly).
    fn to_csv(&self, method: &Bound<'_, PyAny>) -> PyResult<String> {
        let method = method_of(method)?;
        let columns = method.get().method.data_columns();
        self.check_columns(columns)?;
        Ok(format_samples(
            self.joint_count,
            columns,
            self.samples.as_slice(),
        ))
    }

    /// Writes the data file for `method` atomically; an existing file is kept
    /// unless `overwrite`.
    #[pyo3(signature = (path, method, *, overwrite = false))]
    fn write(&self, path: PathBuf, method: &Bound<'_, PyAny>, overwrite: bool) -> PyResult<()> {
        let text = self.to_csv(method)?;
        write_text(&path, "csv", &text, overwrite)
    }

    /// Motor variables, shape (m, n).
    #[getter]
    fn qm<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
        let values = self
            .samples
            .iter()
            .flat_map(|sample| sample.motor_positions().iter().copied())
            .collect();
        array(py, &[self.samples.len(), self.joint_count], values)
    }

    /// Measured positions (m, 3), or None.
    #[getter]
    fn position<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyArrayDyn<f64>>>> {
        self.field(py, 3, |sample| {
            sample.position().map(|p| p.as_slice().to_vec())
        })
    }

    /// Measured orientations (m, 4) as qw, qx, qy, qz, or None.
    #[getter]
    fn orientation<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyArrayDyn<f64>>>> {
        self.field(py, 4, |sample| {
            sample.orientation().map(|q| vec![q.w, q.i, q.j, q.k])
        })
    }

    /// Set ids (link methods) or pair ids (distance), (m,), or None.
    #[getter]
    fn group<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyArrayDyn<i64>>>> {
        if self.samples.iter().all(|sample| sample.group().is_none()) {
            return Ok(None);
        }
        let ids = self
            .samples
            .iter()
            .map(|sample| sample.group().map_or(-1, |id| id as i64))
            .collect();
        array(py, &[self.samples.len()], ids).map(Some)
    }

    /// Measured distances (m,), or None.
    #[getter]
    fn distance<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyArrayDyn<f64>>>> {
        self.field(py, 1, |sample| sample.distance().map(|d| vec![d]))
    }

    /// The payload of each row (m, 4): mass (kg) and centre x, y, z in the
    /// tool frame (m), or None when the data state none.
    #[getter]
    fn payload<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyArrayDyn<f64>>>> {
        self.field(py, 4, |sample| {
            sample
                .payload()
                .map(|p| vec![p.mass, p.com.x, p.com.y, p.com.z])
        })
    }

    /// The σ each row states (m, 2): of its lengths (m) and of its angles
    /// (rad), NaN where it states none; None when no row states one.
    #[getter]
    fn sigma<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyArrayDyn<f64>>>> {
        self.field(py, 2, |sample| {
            sample.sigma().map(|sigma| {
                vec![
                    sigma.length.unwrap_or(f64::NAN),
                    sigma.angle.unwrap_or(f64::NAN),
                ]
            })
        })
    }

    /// The file it was read from, or `"<arrays>"`.
    #[getter]
    fn label(&self) -> &str {
        &self.label
    }

    /// Columns of the file that the method does not use.
    #[getter]
    fn unused_columns(&self) -> Vec<String> {
        self.unused_columns.clone()
    }

    /// Number of joints n.
    #[getter]
    fn joint_count(&self) -> usize {
        self.joint_count
    }

    fn __len__(&self) -> usize {
        self.samples.len()
    }

    fn __repr__(&self) -> String {
        format!(
            "Data({} configurations of {} joints, {})",
            self.samples.len(),
            self.joint_count,
            self.label
        )
    }
}

impl PyData {
    /// Every sample has the fields of `columns`.
    fn check_columns(&self, columns: &[DataColumn]) -> PyResult<()> {
        for (row, sample) in self.samples.iter().enumerate() {
            for column in columns {
                sample
                    .check_column(*column)
                    .map_err(|message| input(format!("{}: row {row}: {message}", self.label)))?;
            }
        }
        Ok(())
    }
}

/// The column of each row's σ of lengths (m) and of angles (rad) from
/// `sigma` and `sigma_angle`, arrays of shape (m,) with NaN where a row
/// states none ([`gecaro_calib::study::RowSigma`]); `None` when neither is
/// given.
fn row_sigmas(
    m: usize,
    sigma: Option<&Bound<'_, PyAny>>,
    sigma_angle: Option<&Bound<'_, PyAny>>,
) -> PyResult<Option<Column<f64>>> {
    if sigma.is_none() && sigma_angle.is_none() {
        return Ok(None);
    }
    let mut stored = vec![0.0; 2 * m];
    for (slot, (values, name)) in [(sigma, "sigma"), (sigma_angle, "sigma_angle")]
        .into_iter()
        .enumerate()
    {
        let Some(values) = values else { continue };
        let values = Real::shaped(values, name, &[Some(m)])?;
        for (row, value) in values.values.into_iter().enumerate() {
            if value.is_nan() {
                continue;
            }
            let sigma = if slot == 0 {
                gecaro_calib::study::RowSigma {
                    length: Some(value),
                    angle: None,
                }
            } else {
                gecaro_calib::study::RowSigma {
                    length: None,
                    angle: Some(value),
                }
            };
            sigma
                .check()
                .map_err(|message| input(format!("{name}: row {row}: {message}")))?;
            stored[2 * row + slot] = value;
        }
    }
    Ok(Some(stored.into()))
}
