//! The test planned: the cube stated or searched for, the program written
//! in the units and format asked.

use gecaro_calib::iso9283::{
    Approaches, CubeChoice, DEFAULT_CYCLES, TestCube, TestOptions, TestPlan, plan_test,
};
use gecaro_io::{WrittenRow, format_program};
use nalgebra::{UnitQuaternion, Vector3};
use serde::{Deserialize, Serialize};
use std::path::PathBuf;

use super::KEYS;
use crate::cell::CellSpec;
use crate::error::AppError;
use crate::files::Files;
use crate::measurements::Unknown;
use crate::output::Output;
use crate::sources::{DataFormatSpec, RobotSource};

/// The most cycles a test may run (the standard asks for 30).
pub const MAX_CYCLES: usize = 1000;

/// A test to plan (JSON as the page sends it: `{"robot": "industrial6",
/// "cube": "auto", "cycles": 30, "directions": 3}`).
#[derive(Clone, Debug, Deserialize)]
pub struct Iso9283PlanRequest {
    /// The robot (its nominal model: the controller's).
    pub robot: RobotSource,
    /// `auto` (default), or the cube's centre and side with units
    /// (`800mm,0,600mm,400mm`).
    #[serde(default)]
    pub cube: Option<String>,
    /// Cycles (default 30).
    #[serde(default)]
    pub cycles: Option<usize>,
    /// Approach directions: 1 (default) or 3.
    #[serde(default)]
    pub directions: Option<usize>,
    /// The cell (floor, tracker station).
    #[serde(default)]
    pub cell: CellSpec,
    /// Units, column names and separator of the program written.
    #[serde(default)]
    pub format: DataFormatSpec,
    /// Where the output is written (`save_as`) and whether it may replace a
    /// file (`overwrite`).
    #[serde(flatten)]
    pub output: Output,
    #[serde(flatten)]
    unknown: Unknown,
}

/// A planned test.
#[derive(Clone, Debug)]
pub struct PlannedTest {
    /// The plan.
    pub plan: TestPlan,
    /// The robot's name.
    pub robot: String,
    /// The program's text (CSV).
    pub program: String,
    /// Where it was written.
    pub saved: Option<PathBuf>,
}

/// A planned pose as JSON gives it.
#[derive(Clone, Debug, Serialize)]
pub struct PlannedPoseJson {
    /// 1–5.
    pub pose: usize,
    /// Commanded position of frame n+1 (m, base frame).
    pub position: [f64; 3],
    /// Its orientation (w, x, y, z).
    pub quaternion: [f64; 4],
    /// Motor values (m, rad).
    pub qm: Vec<f64>,
}

/// A planned test as JSON gives it (`gecaro iso9283 plan --json`).
#[derive(Clone, Debug, Serialize)]
pub struct TestPlanJson {
    /// The robot's name.
    pub robot: String,
    /// The cube's centre (m, base frame).
    pub centre: [f64; 3],
    /// Its side (m).
    pub side: f64,
    /// Whether it was searched for.
    pub searched: bool,
    /// Whether the orientation is held at every pose.
    pub orientation_held: bool,
    /// Cycles.
    pub cycles: usize,
    /// Approach directions.
    pub directions: usize,
    /// The program's rows.
    pub rows: usize,
    /// Of which measured.
    pub measured_rows: usize,
    /// P1–P5.
    pub poses: Vec<PlannedPoseJson>,
    /// Where the program was written.
    pub saved: Option<String>,
}

impl Iso9283PlanRequest {
    /// A test of `robot` in the largest cube found, 30 cycles, one direction.
    pub fn new(robot: RobotSource) -> Self {
        Iso9283PlanRequest {
            robot,
            cube: None,
            cycles: None,
            directions: None,
            cell: CellSpec::default(),
            format: DataFormatSpec::default(),
            output: Output::default(),
            unknown: Unknown::default(),
        }
    }

    /// The options and the cube of the request.
    fn options(&self) -> Result<(CubeChoice, TestOptions), AppError> {
        self.unknown.check()?;
        let cube = match self.cube.as_deref() {
            None => CubeChoice::Largest,
            Some(text) => match gecaro_io::parse_test_cube(text)
                .map_err(|message| AppError::setting("cube", message))?
            {
                None => CubeChoice::Largest,
                Some((centre, side)) => {
                    CubeChoice::Stated(TestCube::new(Vector3::from(centre), side)?)
                }
            },
        };
        let cycles = self.cycles.unwrap_or(DEFAULT_CYCLES);
        if !(2..=MAX_CYCLES).contains(&cycles) {
            return Err(AppError::setting_value(
                "cycles",
                cycles,
                format!(
                    "between 2 and {MAX_CYCLES} cycles (repeatability needs 2; ISO 9283 asks for \
                     {DEFAULT_CYCLES})"
                ),
            ));
        }
        let approaches = match self.directions.unwrap_or(1) {
            1 => Approaches::One,
            3 => Approaches::Three,
            other => {
                return Err(AppError::setting_value(
                    "directions",
                    other,
                    "1 (the pose test) or 3 (the multi-directional test)",
                ));
            }
        };
        Ok((
            cube,
            TestOptions {
                cycles,
                approaches,
                cell: self.cell.cell()?,
            },
        ))
    }

    /// Plans the test and writes the program if asked (checked before any
    /// work).
    ///
    /// # Errors
    /// Bad settings or robot, a cube outside the working space, no cube in
    /// the cell, an output that cannot be written.
    pub fn run(&self, files: &dyn Files) -> Result<PlannedTest, AppError> {
        let (cube, options) = self.options()?;
        let format = self.format.format()?;
        self.output.check(files, "csv")?;
        let file = self.robot.load(files)?;
        let robot = &file.robot;
        let plan = plan_test(robot, cube, &options)?;
        let rows: Vec<WrittenRow<'_>> = plan
            .rows()
            .into_iter()
            .map(|row| WrittenRow {
                keys: vec![
                    row.pose.to_string(),
                    row.cycle.to_string(),
                    row.direction.to_string(),
                    u8::from(row.measured).to_string(),
                ],
                motor_positions: &row.point.motor_positions,
                target: &row.point.target,
            })
            .collect();
        let program = format_program(
            &gecaro_io::joint_types(robot),
            &KEYS,
            &rows,
            plan.orientation_held,
            &format,
        );
        let saved = self.output.write(files, "csv", program.as_bytes())?;
        Ok(PlannedTest {
            plan,
            robot: robot.name().to_owned(),
            program,
            saved,
        })
    }
}

impl PlannedTest {
    /// The JSON document.
    pub fn document(&self) -> TestPlanJson {
        let plan = &self.plan;
        let rows = plan.rows();
        TestPlanJson {
            robot: self.robot.clone(),
            centre: plan.cube.centre.into(),
            side: plan.cube.side,
            searched: plan.searched,
            orientation_held: plan.orientation_held,
            cycles: plan.cycles,
            directions: plan.directions(),
            rows: rows.len(),
            measured_rows: rows.iter().filter(|row| row.measured).count(),
            poses: plan
                .poses
                .iter()
                .enumerate()
                .map(|(index, point)| {
                    let q = UnitQuaternion::from_rotation_matrix(&point.target.rotation);
                    let sign = if q.w < 0.0 { -1.0 } else { 1.0 };
                    PlannedPoseJson {
                        pose: index + 1,
                        position: point.target.translation.vector.into(),
                        quaternion: [q.w, q.i, q.j, q.k].map(|value| sign * value),
                        qm: point.motor_positions.clone(),
                    }
                })
                .collect(),
            saved: self.saved.as_ref().map(|path| path.display().to_string()),
        }
    }
}
