//! `gecaro.Robot`: a robot file in memory (paper §2: the Khalil–Kleinfinger
//! table of frames 0..n+1, joint limits, offsets, gains K, couplings Cm and Cj
//! of eq. 4, the priority matrix), with its direct, differential and inverse
//! models.
//!
//! Units: metres and radians; motor variables `qm` (eq. 4) in, world-frame
//! poses of frame n+1 out, as 4×4 homogeneous matrices.

use std::path::PathBuf;

use gecaro_app::LocalFiles;
use gecaro_core::{
    ChainBuffer, Frame, FrameType, InverseOptions, JacobianRows, Joint, KinematicModel,
    ParameterId, Robot, RobotSpec, Target,
};
use gecaro_io::{RobotFile, format_robot_file, parse_robot_file};
use nalgebra::{DMatrix, IsometryMatrix3, Vector3};
use numpy::PyArrayDyn;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::arrays::{Real, array, columns, priority_array};
use crate::errors::{IntoPyResult, input};
use crate::files::{path_text, write_text};
use crate::interrupt::Watch;
use crate::robot_inputs::{
    batch_output, column, homogeneous_rows, pose, pose_of, priority_matrix, square,
};

/// A serial robot (see the module docs). Load one with `Robot.load`, build one
/// with `Robot.from_table`, convert one with `Robot.import_file`.
#[pyclass(name = "Robot", module = "gecaro")]
pub(crate) struct PyRobot {
    pub(crate) file: RobotFile,
    /// The robot compiled for kinematics, rebuilt after every change.
    model: KinematicModel,
    /// What an import changed or could not carry.
    notes: Vec<String>,
}

impl PyRobot {
    pub(crate) fn new(file: RobotFile) -> Self {
        let model = KinematicModel::new(&file.robot);
        PyRobot {
            file,
            model,
            notes: Vec::new(),
        }
    }

    pub(crate) fn robot(&self) -> &Robot {
        &self.file.robot
    }

    /// Replaces the robot (after a validated change).
    fn replace(&mut self, robot: Robot) {
        self.model = KinematicModel::new(&robot);
        self.file.robot = robot;
    }

    fn parameter_id(&self, name: &str) -> PyResult<ParameterId> {
        let parameters = self.robot().parameters();
        let index = parameters.index_of_name(name).py()?;
        Ok(parameters.id(index))
    }

    /// Calls `each(model, chain, configuration, output)` for every row of
    /// `qm`, without the GIL, stopping on Ctrl-C; `width` values per row out.
    fn batch<'py>(
        &self,
        py: Python<'py>,
        qm: &Bound<'py, PyAny>,
        shape: &[usize],
        mut each: impl FnMut(&KinematicModel, &mut ChainBuffer, &[f64], &mut [f64]) -> PyResult<()>
        + Send,
    ) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
        let n = self.robot().joint_count();
        let (values, single) = Real::rows(qm, "qm", n)?;
        let count = values.len() / n;
        let width: usize = shape.iter().product();
        let mut output = batch_output(count, width)?;
        let model = &self.model;
        let output = py.detach(move || {
            let mut watch = Watch::new();
            let mut chain = ChainBuffer::default();
            for (row, (configuration, out)) in values
                .chunks_exact(n)
                .zip(output.chunks_exact_mut(width))
                .enumerate()
            {
                if row % 1024 == 1023 && watch.poll().is_break() {
                    break;
                }
                each(model, &mut chain, configuration, out)?;
            }
            watch.finish::<_, gecaro_core::Error>(Ok(output))
        })?;
        let mut full_shape = if single { Vec::new() } else { vec![count] };
        full_shape.extend_from_slice(shape);
        array(py, &full_shape, output)
    }
}

/// `request` run: its base registration as `robot rebase --json` gives it,
/// and the robot in that base.
fn rebased_with_registration<'py>(
    py: Python<'py>,
    request: &gecaro_app::RebaseRequest,
) -> PyResult<(Bound<'py, PyAny>, PyRobot)> {
    let rebased = request.run(&LocalFiles).py()?;
    let registration = rebased
        .registration
        .as_ref()
        .map(gecaro_app::BaseRegistration::document);
    Ok((
        crate::documents::to_python(py, &registration)?,
        PyRobot::new(rebased.robot),
    ))
}

#[pymethods]
impl PyRobot {
    /// A robot from a robot file (TOML) or, when no such file exists, a ready
    /// robot's name (`gecaro.ready_robots()`), as the command line's ROBOT.
    #[staticmethod]
    fn load(source: PathBuf) -> PyResult<Self> {
        Ok(PyRobot::new(
            gecaro_app::RobotSource::Named(path_text(&source))
                .load(&LocalFiles)
                .py()?,
        ))
    }

    /// A robot from the text of a robot file; `name` labels it in messages.
    #[staticmethod]
    #[pyo3(signature = (text, name = "<string>"))]
    fn from_toml(text: &str, name: &str) -> PyResult<Self> {
        Ok(PyRobot::new(parse_robot_file(text, name.as_ref()).py()?))
    }

    /// A robot converted from a URDF, a DH or modified-DH table, or a SYMORO
    /// `.par` file (`format`: "urdf", "dh", "mdh", "symoro"; default from the
    /// extension), as `gecaro robot import`. What the conversion changed is in
    /// `notes`.
    #[staticmethod]
    #[pyo3(signature = (path, format = None, *, base = None, tip = None, name = None, length_unit = None, angle_unit = None))]
    fn import_file(
        path: PathBuf,
        format: Option<&str>,
        base: Option<String>,
        tip: Option<String>,
        name: Option<String>,
        length_unit: Option<&str>,
        angle_unit: Option<&str>,
    ) -> PyResult<Self> {
        let mut request = gecaro_app::ImportRequest::new(path_text(&path));
        request.format = format.map(str::to_owned);
        request.base = base;
        request.tip = tip;
        request.name = name;
        request.length_unit = length_unit.map(str::to_owned);
        request.angle_unit = angle_unit.map(str::to_owned);
        let imported = request.run(&LocalFiles).py()?.imported;
        let mut robot = PyRobot::new(imported.file);
        robot.notes = imported.notes;
        Ok(robot)
    }

    /// A robot from its table (paper §2.1, frames 0..n+1): `sigma` 0 revolute,
    /// 1 prismatic, 2 fixed (frames 0 and n+1 are fixed); angles in radians,
    /// lengths in metres. Joint limits default to ±π (revolute) and 0..1 m
    /// (prismatic), offsets to 0, gains K to 1, couplings Cm, Cj to identity.
    #[staticmethod]
    #[pyo3(signature = (name, sigma, alpha, d, theta, r, *, beta = None, qmin = None, qmax = None, offset = None, gain = None, motor_coupling = None, joint_coupling = None, priority = None))]
    fn from_table(
        name: String,
        sigma: &Bound<'_, PyAny>,
        alpha: &Bound<'_, PyAny>,
        d: &Bound<'_, PyAny>,
        theta: &Bound<'_, PyAny>,
        r: &Bound<'_, PyAny>,
        beta: Option<&Bound<'_, PyAny>>,
        qmin: Option<&Bound<'_, PyAny>>,
        qmax: Option<&Bound<'_, PyAny>>,
        offset: Option<&Bound<'_, PyAny>>,
        gain: Option<&Bound<'_, PyAny>>,
        motor_coupling: Option<&Bound<'_, PyAny>>,
        joint_coupling: Option<&Bound<'_, PyAny>>,
        priority: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Self> {
        let sigma = Real::shaped(sigma, "sigma", &[None])?.values;
        let frames_count = sigma.len();
        if frames_count < 3 {
            return Err(input(format!(
                "sigma: a robot has frames 0..n+1 with n ≥ 1 joints, so at least 3 rows; got {frames_count}"
            )));
        }
        let n = frames_count - 2;
        let columns = [
            column(Some(alpha), "alpha", frames_count, |_| 0.0)?,
            column(Some(d), "d", frames_count, |_| 0.0)?,
            column(Some(theta), "theta", frames_count, |_| 0.0)?,
            column(Some(r), "r", frames_count, |_| 0.0)?,
            column(beta, "beta", frames_count, |_| 0.0)?,
        ];
        let mut frames = Vec::with_capacity(frames_count);
        for (j, value) in sigma.iter().enumerate() {
            let frame_type = (value.fract() == 0.0)
                .then(|| FrameType::from_sigma(*value as i64))
                .flatten()
                .ok_or_else(|| {
                    input(format!("sigma: frame {j} has σ = {value}; use 0 (revolute), 1 (prismatic) or 2 (fixed)"))
                })?;
            let mut frame = Frame::new(frame_type);
            [frame.alpha, frame.d, frame.theta, frame.r, frame.beta] =
                [0, 1, 2, 3, 4].map(|c| columns[c][j]);
            frames.push(frame);
        }
        let types: Vec<FrameType> = frames[1..=n].iter().map(|f| f.frame_type).collect();
        let defaults: Vec<Joint> = types.iter().map(|t| Joint::default_for(*t)).collect();
        let qmin = column(qmin, "qmin", n, |j| defaults[j].qmin)?;
        let qmax = column(qmax, "qmax", n, |j| defaults[j].qmax)?;
        let offset = column(offset, "offset", n, |_| 0.0)?;
        let gain = column(gain, "gain", n, |_| 1.0)?;
        let joints = (0..n)
            .map(|j| Joint {
                qmin: qmin[j],
                qmax: qmax[j],
                offset: offset[j],
                gain: gain[j],
            })
            .collect();
        let robot = Robot::new(RobotSpec {
            name,
            frames,
            joints,
            motor_coupling: square(motor_coupling, "motor_coupling", n)?,
            joint_coupling: square(joint_coupling, "joint_coupling", n)?,
            priority: None,
            compliances: None,
        })
        .py()?;
        let mut robot = PyRobot::new(RobotFile::of(robot));
        if let Some(priority) = priority {
            robot.set_priority(Some(priority))?;
        }
        Ok(robot)
    }

    /// Writes the robot file (TOML), atomically; an existing file is kept
    /// unless `overwrite`.
    #[pyo3(signature = (path, *, overwrite = false))]
    fn save(&self, path: PathBuf, overwrite: bool) -> PyResult<()> {
        let text = gecaro_io::robot_file_text(&self.file, &path).py()?;
        write_text(&path, "toml", &text, overwrite)
    }

    /// The robot file's text (TOML), as `save` writes it.
    fn to_toml(&self) -> String {
        format_robot_file(&self.file)
    }

    /// The robot in another format: "urdf", "dh", "mdh" or "symoro", as
    /// `gecaro robot export` (docs/interchange.md).
    fn export(&self, to: &str) -> PyResult<Exported> {
        let exported = gecaro_app::ExportRequest::new(
            gecaro_app::RobotSource::Loaded(Box::new(self.file.clone())),
            to,
        )
        .run(&LocalFiles)
        .py()?;
        Ok(Exported {
            exported: exported.exported,
            format: exported.format,
        })
    }

    /// The robot's name.
    #[getter]
    fn name(&self) -> &str {
        self.robot().name()
    }

    #[setter]
    fn set_name(&mut self, name: String) {
        self.file.robot.set_name(name);
    }

    /// The robot file's description, if any.
    #[getter]
    fn description(&self) -> Option<&str> {
        self.file.description.as_deref()
    }

    /// What an import changed or could not carry (empty for robot files).
    #[getter]
    fn notes(&self) -> Vec<String> {
        self.notes.clone()
    }

    /// Number of joints n.
    #[getter]
    fn joint_count(&self) -> usize {
        self.robot().joint_count()
    }

    /// The joints' compliances c1..cn of an elastic robot (rad/(N·m), m/N
    /// for a prismatic joint), or None for a rigid one.
    #[getter]
    fn compliances(&self) -> Option<Vec<f64>> {
        self.robot().compliances().map(<[f64]>::to_vec)
    }

    /// The tools a calibration identified with the robot (a study's
    /// reflectors): `{name: (position (m), quaternion (w, x, y, z))}` in
    /// frame n+1, what `compensate(tool=name)` compensates.
    #[getter]
    fn tools(&self) -> std::collections::BTreeMap<String, ([f64; 3], [f64; 4])> {
        self.file
            .tools
            .iter()
            .map(|tool| {
                let t = tool.pose.translation.vector;
                let q = nalgebra::UnitQuaternion::from_rotation_matrix(&tool.pose.rotation);
                (tool.name.clone(), ([t.x, t.y, t.z], [q.w, q.i, q.j, q.k]))
            })
            .collect()
    }

    /// Whether the calibration that made this robot observed its frame n+1
    /// (False when every set measured a named tool: frame n+1 is then the
    /// nominal's, and only the tools are calibrated).
    #[getter]
    fn tool_frame_observed(&self) -> bool {
        self.file.tool_frame_observed
    }

    /// Gravity in the robot's world frame (m/s², `[0, 0, -9.80665]` unless
    /// the robot file states it): what loads an elastic robot's joints. An
    /// identification with `model="elastic-gravity"` states in its
    /// calibrated robot the gravity it found.
    #[getter]
    fn gravity(&self) -> [f64; 3] {
        self.file.stated_gravity().into()
    }

    #[setter]
    fn set_gravity(&mut self, gravity: [f64; 3]) -> PyResult<()> {
        self.file.masses.set_gravity(gravity.into()).py()
    }

    /// The torque gravity exerts about each joint at motor values `qm`
    /// (N·m; N for a prismatic joint), from the masses the robot file states
    /// and an optional `payload` (`"6kg"`, `"6kg,0,0,80mm"`), as the elastic
    /// model loads its joints. `qm` of shape (n,) gives (n,); (m, n) gives
    /// (m, n), in one call without the GIL.
    #[pyo3(signature = (qm, *, payload = None))]
    fn gravity_torques<'py>(
        &self,
        py: Python<'py>,
        qm: &Bound<'py, PyAny>,
        payload: Option<&str>,
    ) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
        let payload = payload
            .map(gecaro_io::parse_payload)
            .transpose()
            .map_err(|message| crate::errors::input(format!("payload: {message}")))?;
        let n = self.robot().joint_count();
        let (robot, masses) = (self.robot(), &self.file.masses);
        self.batch(py, qm, &[n], |_, _, configuration, out| {
            let torques =
                gecaro_core::gravity_torques(robot, masses, payload.as_ref(), configuration)
                    .py()?;
            out.copy_from_slice(torques.as_slice());
            Ok(())
        })
    }

    /// The joint types 1..n as letters: `R` revolute, `P` prismatic.
    #[getter]
    fn joint_types(&self) -> String {
        self.robot().joint_letters()
    }

    /// Names of the geometric parameters, in the order of `parameters` and of
    /// the Jacobian's columns (`alpha1`, `d1`, …, `beta2`, `K1`, …).
    #[getter]
    fn parameter_names(&self) -> Vec<String> {
        self.robot().parameters().names()
    }

    /// Values of the geometric parameters, in `parameter_names` order.
    #[getter]
    fn parameters<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
        let values = self.robot().parameter_values();
        array(py, &[values.len()], values.as_slice().to_vec())
    }

    #[setter]
    fn set_parameters(&mut self, values: &Bound<'_, PyAny>) -> PyResult<()> {
        let count = self.robot().parameters().len();
        let values = Real::shaped(values, "parameters", &[Some(count)])?.values;
        let mut robot = self.robot().clone();
        for (index, value) in values.iter().enumerate() {
            let id = robot.parameters().id(index);
            robot.set_parameter(id, *value).py()?;
        }
        robot.check_stated().py()?;
        self.replace(robot);
        Ok(())
    }

    /// The value of one parameter: `robot["theta2"]`.
    fn __getitem__(&self, name: &str) -> PyResult<f64> {
        let id = self.parameter_id(name)?;
        Ok(self.robot().parameter(id))
    }

    /// Sets one parameter: `robot["d3"] = 0.4`.
    fn __setitem__(&mut self, name: &str, value: f64) -> PyResult<()> {
        let id = self.parameter_id(name)?;
        let mut robot = self.robot().clone();
        robot.set_parameter(id, value).py()?;
        // The rules a robot file is loaded by: a robot that could not be
        // saved and read back is refused here, not when it is saved.
        robot.check_stated().py()?;
        self.replace(robot);
        Ok(())
    }

    /// The frame table (frames 0..n+1) as arrays: `sigma` (0 revolute, 1
    /// prismatic, 2 fixed), `alpha`, `d`, `theta`, `r`, `beta`.
    #[getter]
    fn table<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let frames = self.robot().frames();
        let table = PyDict::new(py);
        let sigma = frames
            .iter()
            .map(|f| i64::from(f.frame_type.sigma()))
            .collect();
        table.set_item("sigma", array(py, &[frames.len()], sigma)?)?;
        let table = columns(
            py,
            frames,
            &[
                ("alpha", |f| f.alpha),
                ("d", |f| f.d),
                ("theta", |f| f.theta),
                ("r", |f| f.r),
                ("beta", |f| f.beta),
            ],
        )?;
        let sigma = frames
            .iter()
            .map(|f| i64::from(f.frame_type.sigma()))
            .collect();
        table.set_item("sigma", array(py, &[frames.len()], sigma)?)?;
        Ok(table)
    }

    /// The joints 1..n as arrays: `qmin`, `qmax`, `offset`, `gain` (K).
    #[getter]
    fn joints<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        columns(
            py,
            self.robot().joints(),
            &[
                ("qmin", |j| j.qmin),
                ("qmax", |j| j.qmax),
                ("offset", |j| j.offset),
                ("gain", |j| j.gain),
            ],
        )
    }

    /// The motor coupling matrix Cm of eq. 4 (n×n).
    #[getter]
    fn motor_coupling<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
        matrix(py, self.robot().motor_coupling())
    }

    /// The joint coupling matrix Cj of eq. 4 (n×n).
    #[getter]
    fn joint_coupling<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
        matrix(py, self.robot().joint_coupling())
    }

    /// The priority matrix ((n+2)×6: α, d, θ, r, β, K per frame; 0 = not
    /// identified, larger first), the paper's default rules unless set.
    /// Set it to an array, a priority file's path, or None for the defaults.
    #[getter]
    fn priority<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArrayDyn<i64>>> {
        priority_array(py, self.robot().priority().rows())
    }

    #[setter]
    fn set_priority(&mut self, priority: Option<&Bound<'_, PyAny>>) -> PyResult<()> {
        let matrix = priority
            .map(|value| priority_matrix(self.robot(), value))
            .transpose()?;
        self.file.robot.set_priority_override(matrix).py()
    }

    /// The same robot in another world frame and with another tool frame:
    /// `world` maps old world coordinates to new ones, `tool` is the new tool
    /// frame in the old one; each a 4×4 matrix or [x, y, z, qw, qx, qy, qz].
    #[pyo3(signature = (world = None, tool = None))]
    fn reframe(
        &self,
        world: Option<&Bound<'_, PyAny>>,
        tool: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Self> {
        let identity = IsometryMatrix3::identity();
        let world = world
            .map(|w| pose(w, "world"))
            .transpose()?
            .unwrap_or(identity);
        let tool = tool
            .map(|t| pose(t, "tool"))
            .transpose()?
            .unwrap_or(identity);
        let robot = self.robot().reframed(&world, &tool).py()?;
        let mut file = self.file.clone();
        // Each link keeps its body: its centre moves into the new frames.
        file.masses = file.masses.reframed(self.robot(), &robot, &world).py()?;
        file.robot = robot;
        Ok(PyRobot::new(file))
    }

    /// This robot, calibrated in a measurement frame (a tracker's), in the
    /// base frame of its `nominal` robot: `(frame, robot)`, `frame` the 4×4
    /// pose of the measurement frame in the robot's base frame (maps
    /// measurement coordinates to robot coordinates), `robot` this one with
    /// the nominal's frames 0 and 1 (joint 1 where the nominal puts it), as
    /// `gecaro robot rebase`. `robot.reframe(world=inv(frame))` gives this
    /// one back.
    fn rebased<'py>(
        &self,
        py: Python<'py>,
        nominal: PyRef<'_, PyRobot>,
    ) -> PyResult<(Bound<'py, PyArrayDyn<f64>>, Self)> {
        let (frame, file) = gecaro_app::rebased_file(&self.file, nominal.robot()).py()?;
        let mut values = vec![0.0; 16];
        homogeneous_rows(&frame, &mut values);
        Ok((array(py, &[4, 4], values)?, PyRobot::new(file)))
    }

    /// This robot, calibrated in a measurement frame, in the base frame its
    /// owner defines by points (issue 74): `measured` (N, 3) points in the
    /// measurement frame beside `base` (N, 3), the same points in the base
    /// frame from the drawing (metres), N ≥ 3 not on one line, optionally
    /// `names`. Returns `(registration, robot)`: the registration as
    /// `gecaro robot rebase --base-points … --json` gives it (the base's
    /// pose in the measurement frame, every point's residual, σ, and the
    /// error it adds at 1 m), and this robot in that base frame. `nominal`
    /// is the robot's nominal (joints checked).
    #[pyo3(signature = (nominal, measured, base, *, names = None))]
    fn rebased_by_points<'py>(
        &self,
        py: Python<'py>,
        nominal: PyRef<'_, PyRobot>,
        measured: &Bound<'py, PyAny>,
        base: &Bound<'py, PyAny>,
        names: Option<Vec<String>>,
    ) -> PyResult<(Bound<'py, PyAny>, Self)> {
        let (names, measured) = crate::arrays::named_points(measured, names)?;
        let base = crate::arrays::points(base, "base", Some(measured.len()))?;
        let points = names
            .into_iter()
            .zip(measured.into_iter().zip(base))
            .enumerate()
            .map(|(line, (name, (measured, base)))| gecaro_io::BasePoint {
                name,
                measured,
                base,
                line,
            })
            .collect();
        let mut request = gecaro_app::RebaseRequest::new(
            gecaro_app::RobotSource::Loaded(Box::new(self.file.clone())),
            gecaro_app::RobotSource::Loaded(Box::new(nominal.file.clone())),
        );
        request.base_points = Some(gecaro_app::BasePointsSource::Points(points));
        rebased_with_registration(py, &request)
    }

    /// This robot, calibrated in a measurement frame, in the base frame its
    /// maker defines by joints 1 and 2 (issue 74): `circles`, a `Data` of
    /// motor positions (radians) and positions (m) of a point on the arm
    /// while joint 1 turned alone and while joint 2 turned alone (joint 1
    /// held), at least 4 points each. z along axis 1, the origin where the
    /// common normal of axes 1 and 2 meets it, x along that normal at joint
    /// 1's zero, placed as `nominal` places them. Returns `(registration,
    /// robot)` as `rebased_by_points` (`registration["by"] == "circles"`,
    /// each point's distance from its circle, the radii).
    fn rebased_by_circles<'py>(
        &self,
        py: Python<'py>,
        nominal: PyRef<'_, PyRobot>,
        circles: PyRef<'_, crate::data_set::PyData>,
    ) -> PyResult<(Bound<'py, PyAny>, Self)> {
        let mut request = gecaro_app::RebaseRequest::new(
            gecaro_app::RobotSource::Loaded(Box::new(self.file.clone())),
            gecaro_app::RobotSource::Loaded(Box::new(nominal.file.clone())),
        );
        request.base_circles = Some(gecaro_app::DataSource::Samples {
            samples: circles.samples.clone(),
            label: circles.label.clone(),
        });
        rebased_with_registration(py, &request)
    }

    /// A copy (changes to it leave this robot alone).
    fn copy(&self) -> Self {
        let mut copy = PyRobot::new(self.file.clone());
        copy.notes = self.notes.clone();
        copy
    }

    fn __copy__(&self) -> Self {
        self.copy()
    }

    fn __deepcopy__(&self, _memo: &Bound<'_, PyAny>) -> Self {
        self.copy()
    }

    fn __repr__(&self) -> String {
        format!(
            "Robot({:?}, {} joints {}, {} parameters)",
            self.robot().name(),
            self.robot().joint_count(),
            self.robot().joint_letters(),
            self.robot().parameters().len()
        )
    }

    /// Direct geometric model (eq. 1): the pose of frame n+1 in the world
    /// frame at motor variables `qm`. `qm` of shape (n,) gives a 4×4 matrix;
    /// (m, n) gives (m, 4, 4), computed in one call without the GIL.
    fn fk<'py>(
        &self,
        py: Python<'py>,
        qm: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
        self.batch(py, qm, &[4, 4], |model, chain, configuration, out| {
            model.forward(configuration, chain).py()?;
            homogeneous_rows(chain.world_from_tool(), out);
            Ok(())
        })
    }

    /// Poses of every frame 0..n+1 in the world frame: (n+2, 4, 4) for qm of
    /// shape (n,), (m, n+2, 4, 4) for (m, n).
    fn frames<'py>(
        &self,
        py: Python<'py>,
        qm: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
        let count = self.robot().frames().len();
        self.batch(
            py,
            qm,
            &[count, 4, 4],
            |model, chain, configuration, out| {
                model.forward(configuration, chain).py()?;
                for (frame, out) in out.chunks_exact_mut(16).enumerate() {
                    homogeneous_rows(chain.world_from_frame(frame), out);
                }
                Ok(())
            },
        )
    }

    /// The 6×Np Jacobian of frame n+1 with respect to every geometric
    /// parameter (Appendix II; rows dx, dy, dz, δx, δy, δz in the world frame,
    /// columns in `parameter_names` order). (m, n) gives (m, 6, Np).
    fn jacobian<'py>(
        &self,
        py: Python<'py>,
        qm: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
        let columns = self.model.parameter_count();
        let mut rows = Vec::with_capacity(6 * columns);
        self.batch(
            py,
            qm,
            &[6, columns],
            move |model, chain, configuration, out| {
                model.forward(configuration, chain).py()?;
                model.jacobian_rows(chain, &mut rows, JacobianRows::Full);
                out.copy_from_slice(&rows);
                Ok(())
            },
        )
    }

    /// Numerical inverse geometric model: motor variables qm that put frame
    /// n+1 at `target`: a 4×4 pose, [x, y, z, qw, qx, qy, qz], or a point
    /// [x, y, z] (orientation free). Without `start`, tries the middle of the
    /// joint ranges and then seeded random starts, as `gecaro ik`.
    /// Raises NotConvergedError when the target is not reached.
    #[pyo3(signature = (target, start = None, *, respect_limits = true, tolerance = 1e-12, max_iterations = 200))]
    fn ik<'py>(
        &self,
        py: Python<'py>,
        target: &Bound<'py, PyAny>,
        start: Option<&Bound<'py, PyAny>>,
        respect_limits: bool,
        tolerance: f64,
        max_iterations: usize,
    ) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
        let values = Real::new(target, "target", "a pose or a point")?;
        let target = match values.shape[..] {
            [3] => Target::Position(Vector3::from_column_slice(&values.values)),
            _ => Target::Frame(pose_of(&values, "target")?),
        };
        let start = start
            .map(|start| Real::shaped(start, "start", &[Some(self.robot().joint_count())]))
            .transpose()?;
        let options = InverseOptions {
            max_iterations,
            tolerance,
            respect_limits,
        };
        let robot = self.robot();
        let solution = py
            .detach(|| {
                gecaro_app::inverse_model(
                    robot,
                    &target,
                    start.as_ref().map(|start| start.values.as_slice()),
                    &options,
                )
            })
            .py()?;
        array(
            py,
            &[solution.motor_positions.len()],
            solution.motor_positions,
        )
    }

    /// Joint variables q = Cj·diag(K)·Cm·qm + offset (eq. 4) of motor
    /// variables qm, shape (n,) or (m, n).
    fn joint_positions<'py>(
        &self,
        py: Python<'py>,
        qm: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
        let robot = self.robot();
        let n = robot.joint_count();
        self.batch(py, qm, &[n], |_, _, configuration, out| {
            out.copy_from_slice(robot.joint_positions(configuration).py()?.as_slice());
            Ok(())
        })
    }

    /// Motor variables qm of joint variables q (eq. 4 inverted), shape (n,)
    /// or (m, n).
    fn motor_positions<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
        let robot = self.robot();
        let n = robot.joint_count();
        self.batch(py, q, &[n], |_, _, configuration, out| {
            out.copy_from_slice(robot.motor_positions(configuration).py()?.as_slice());
            Ok(())
        })
    }
}

fn matrix<'py>(py: Python<'py>, matrix: &DMatrix<f64>) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    let values = (0..matrix.nrows())
        .flat_map(|row| (0..matrix.ncols()).map(move |column| matrix[(row, column)]))
        .collect();
    array(py, &[matrix.nrows(), matrix.ncols()], values)
}

/// A robot converted to another format (`Robot.export`).
#[pyclass(name = "Exported", module = "gecaro", frozen)]
pub(crate) struct Exported {
    exported: gecaro_io::Exported,
    format: gecaro_io::RobotFormat,
}

#[pymethods]
impl Exported {
    /// The text of the file (URDF XML, or a DH table in TOML).
    #[getter]
    fn text(&self) -> &str {
        &self.exported.text
    }

    /// The joint calibration (YAML) that a driver must apply when gains or
    /// couplings cannot be written in the format; None when not needed.
    #[getter]
    fn joint_calibration(&self) -> Option<&str> {
        self.exported.joint_calibration.as_deref()
    }

    /// What the conversion changed or moved elsewhere.
    #[getter]
    fn notes(&self) -> Vec<String> {
        self.exported.notes.clone()
    }

    /// Writes the file and, when there is one, the joint calibration beside it
    /// (`FILE.joint_calibration.yaml`): both or neither. Returns the paths written.
    #[pyo3(signature = (path, *, overwrite = false))]
    fn save(&self, path: PathBuf, overwrite: bool) -> PyResult<Vec<PathBuf>> {
        gecaro_app::write_export(
            &self.exported,
            self.format,
            &path_text(&path),
            overwrite,
            &LocalFiles,
        )
        .py()
    }

    fn __repr__(&self) -> String {
        format!(
            "Exported({} bytes{})",
            self.exported.text.len(),
            if self.exported.joint_calibration.is_some() {
                ", with a joint calibration"
            } else {
                ""
            }
        )
    }
}

/// Names of the ready robots shipped with gecaro (`Robot.load(name)`).
#[pyfunction]
pub(crate) fn ready_robots() -> Vec<&'static str> {
    gecaro_io::ready_robots()
        .iter()
        .map(|ready| ready.name)
        .collect()
}
