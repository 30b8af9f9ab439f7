//! The test's program (clauses 6.2, 7.2.1, 7.2.4 and 7.3.1): the cube
//! placed or searched for, its five poses and their approach points solved
//! on the robot's model, and the cycles in the order the robot runs them.
//!
//! - **The reference configuration**: of 64 configurations drawn within
//!   the joint limits (and admitted by the cell), the one farthest from a
//!   singularity — the largest smallest singular value of the joint
//!   Jacobian, its position rows divided by the robot's reach. The middle
//!   of the ranges is no reference: it is often singular (a wrist
//!   stretched straight).
//! - **The orientation** is held: every pose and approach point has the
//!   orientation frame n+1 has in the reference configuration (a robot of
//!   six joints or more; with fewer, positions only are commanded and the
//!   orientation is what the model gives there).
//! - **The cube is inside the working space** when its eight corners are
//!   reached (in position, any orientation) and its five poses and their
//!   approach points with the held orientation, within the joint limits and
//!   in the cell (floor, a tracker's line of sight) — each from the
//!   previous pose's joints first, so that the robot does not change its
//!   configuration between them. A searched cube also keeps its poses'
//!   joints [`JOINT_MARGIN`] of their ranges inside the limits, so that the
//!   compensated program for a calibrated robot reaches them too, and
//!   room in space: a cube [`SPACE_MARGIN`] larger about its centre fits.
//! - **The largest cube** ([`CubeChoice::Largest`]) is searched about the
//!   tool's position in the reference configuration (in the region a robot
//!   works in, away from the boundary of its reach) and six centres a quarter of the reach away along the
//!   axes; for each, the largest side by bisection (to 1 mm). The largest of
//!   them is kept, its centre and side rounded down to whole millimetres: a
//!   cube found by this search, not a proven maximum.
//! - **Approach points** for the multi-directional test: each pose is
//!   reached moving along the base frame's x, y, then z axis, from a point
//!   [`APPROACH_SHARE`] of the side away on the side of the cube's centre
//!   (inside the cube).

use gecaro_core::{InverseOptions, InverseSolver, Robot, Target, terminal_pose};
use nalgebra::{IsometryMatrix3, Rotation3, Translation3, Vector3};

use super::cube::TestCube;
use crate::Error;
use crate::cell::Cell;
use crate::error::Setting;
use crate::sampler::Sampler;

/// The room a searched cube leaves its poses' joints inside their limits,
/// as a share of each joint's range: a calibrated robot reaches them too
/// (compensation moves joints by a degree or two), where a cube touching a
/// limit would be the nominal model's only.
pub const JOINT_MARGIN: f64 = 0.03;

/// How much larger than a searched cube a cube about the same centre must
/// fit: the room the searched cube leaves in space (its poses 7 % of the
/// side inside where the search could reach).
pub const SPACE_MARGIN: f64 = 0.2;

/// Cycles the standard asks for (7.2.1).
pub const DEFAULT_CYCLES: usize = 30;

/// The distance of an approach point from its pose, as a share of the
/// cube's side.
pub const APPROACH_SHARE: f64 = 0.1;

/// Random starts of the inverse model after the previous pose's joints and
/// the middle of the ranges.
const RANDOM_STARTS: usize = 3;

/// Centres the largest cube is searched about: the reference's tool
/// position and these shares of the reach along ±x, ±y, ±z.
const CENTRE_SHIFT: f64 = 0.25;

/// Bisections of a cube's side (the reach / 2¹² is below a millimetre for
/// any arm up to 4 m).
const BISECTIONS: usize = 12;

/// Whether each pose is approached from one direction (the pose test:
/// P1 → P2 → … → P5) or from three (the multi-directional test).
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum Approaches {
    /// One: the cycle's previous pose.
    One,
    /// Three: along x, y and z, from an approach point each.
    Three,
}

impl Approaches {
    /// Directions per pose (1 or 3).
    pub fn count(self) -> usize {
        match self {
            Approaches::One => 1,
            Approaches::Three => 3,
        }
    }
}

/// Where the cube stands.
#[derive(Copy, Clone, Debug, PartialEq)]
pub enum CubeChoice {
    /// A stated cube.
    Stated(TestCube),
    /// The largest the search finds (module docs).
    Largest,
}

/// How the test is run.
#[derive(Clone, Debug, PartialEq)]
pub struct TestOptions {
    /// Cycles (≥ 2; the standard's 30 by default).
    pub cycles: usize,
    /// One or three approach directions.
    pub approaches: Approaches,
    /// The cell the robot is measured in.
    pub cell: Cell,
}

impl Default for TestOptions {
    fn default() -> Self {
        TestOptions {
            cycles: DEFAULT_CYCLES,
            approaches: Approaches::One,
            cell: Cell::default(),
        }
    }
}

/// A point of the program: where frame n+1 goes (base frame; the model's
/// pose at the joints) and the joints that put it there.
#[derive(Clone, Debug, PartialEq)]
pub struct PlannedPoint {
    /// The commanded pose of frame n+1.
    pub target: IsometryMatrix3<f64>,
    /// Motor values qm (eq. 4).
    pub motor_positions: Vec<f64>,
}

/// One row of the program, in the order the robot runs them.
#[derive(Clone, Debug, PartialEq)]
pub struct TestRow<'a> {
    /// The pose (1–5) the row reaches or approaches.
    pub pose: usize,
    /// The cycle (from 1).
    pub cycle: usize,
    /// The approach direction (1; 1–3 in the multi-directional test).
    pub direction: usize,
    /// Whether the pose is measured here (an approach point is not).
    pub measured: bool,
    /// The point.
    pub point: &'a PlannedPoint,
}

/// The planned test: the cube, its poses and the program's rows.
#[derive(Clone, Debug, PartialEq)]
pub struct TestPlan {
    /// The cube.
    pub cube: TestCube,
    /// Whether it was searched for (else stated).
    pub searched: bool,
    /// Whether the orientation is held (a robot of six joints or more).
    pub orientation_held: bool,
    /// P1–P5.
    pub poses: Vec<PlannedPoint>,
    /// Per pose, its approach points (x, y, z; empty with one direction).
    pub approaches: Vec<Vec<PlannedPoint>>,
    /// Cycles.
    pub cycles: usize,
}

impl TestPlan {
    /// Directions per pose.
    pub fn directions(&self) -> usize {
        self.approaches
            .first()
            .map_or(1, |points| points.len().max(1))
    }

    /// The program's rows: cycle after cycle, P1 to P5, each (with three
    /// directions) after its approach point.
    pub fn rows(&self) -> Vec<TestRow<'_>> {
        let mut rows = Vec::with_capacity(self.cycles * 5 * 2 * self.directions());
        for cycle in 1..=self.cycles {
            for (index, point) in self.poses.iter().enumerate() {
                let pose = index + 1;
                if self.approaches[index].is_empty() {
                    rows.push(TestRow {
                        pose,
                        cycle,
                        direction: 1,
                        measured: true,
                        point,
                    });
                }
                for (h, approach) in self.approaches[index].iter().enumerate() {
                    let direction = h + 1;
                    rows.push(TestRow {
                        pose,
                        cycle,
                        direction,
                        measured: false,
                        point: approach,
                    });
                    rows.push(TestRow {
                        pose,
                        cycle,
                        direction,
                        measured: true,
                        point,
                    });
                }
            }
        }
        rows
    }
}

/// Configurations drawn to find the reference one.
const REFERENCE_DRAWS: usize = 64;

/// The configuration the test is planned about, and the robot's reach.
struct Reference {
    /// Motor values: of the configurations drawn within the limits and
    /// admitted by the cell, the farthest from a singularity (the largest
    /// smallest singular value of the joint Jacobian, its position rows
    /// divided by the reach).
    motor_positions: Vec<f64>,
    /// The farthest tool position from joint 1's origin over them (m).
    reach: f64,
}

impl Reference {
    fn of(robot: &Robot, cell: &Cell) -> Result<Self, Error> {
        let mut sampler = Sampler::new(9283).with_cell(cell.clone());
        let drawn: Vec<Vec<f64>> = (0..REFERENCE_DRAWS)
            .map(|_| sampler.configuration(robot))
            .filter(|motor| cell.admits(robot, motor))
            .collect();
        let mut reach: f64 = 0.0;
        let mut chains = Vec::with_capacity(drawn.len());
        for motor in &drawn {
            let chain = gecaro_core::forward_kinematics(robot, motor)?;
            let origin = chain.poses()[1].translation.vector;
            reach = reach.max((chain.world_from_tool().translation.vector - origin).norm());
            chains.push(chain);
        }
        let rows = if robot.joint_count() >= 6 { 6 } else { 3 };
        let dexterity = |chain: &gecaro_core::FrameChain| {
            let mut jacobian = gecaro_core::joint_jacobian(robot, chain);
            for mut column in jacobian.column_iter_mut() {
                for value in column.rows_mut(0, 3).iter_mut() {
                    *value /= reach.max(1e-3);
                }
            }
            let rows = jacobian.rows(0, rows).into_owned();
            rows.singular_values().min()
        };
        let best = chains
            .iter()
            .zip(&drawn)
            .map(|(chain, motor)| (dexterity(chain), motor))
            .max_by(|a, b| a.0.total_cmp(&b.0))
            .map(|(_, motor)| motor.clone())
            .ok_or_else(|| Error::InvalidData {
                line: None,
                message: format!(
                    "the cell admits none of {REFERENCE_DRAWS} configurations of {} drawn within \
                     its joint limits: no test can be planned there",
                    robot.name()
                ),
            })?;
        Ok(Reference {
            motor_positions: best,
            reach,
        })
    }
}

/// A cube's five poses and, per pose, its approach points.
type Fitted = (Vec<PlannedPoint>, Vec<Vec<PlannedPoint>>);

/// The inverse model as the plan uses it: the held orientation, the cell,
/// the starts.
struct Solver<'a> {
    robot: &'a Robot,
    inverse: InverseSolver<'a>,
    /// The held orientation, or none (positions only).
    orientation: Option<Rotation3<f64>>,
    cell: &'a Cell,
    /// The middle of the ranges, then random starts.
    starts: Vec<Vec<f64>>,
    options: InverseOptions,
}

impl<'a> Solver<'a> {
    /// The solver, the reference configuration and the reach (module docs).
    fn new(robot: &'a Robot, cell: &'a Cell) -> Result<(Self, Reference), Error> {
        let reference = Reference::of(robot, cell)?;
        let orientation = (robot.joint_count() >= 6)
            .then(|| terminal_pose(robot, &reference.motor_positions).map(|pose| pose.rotation))
            .transpose()?;
        let mut sampler = Sampler::new(9283);
        let middle: Vec<f64> = robot
            .joints()
            .iter()
            .map(|joint| 0.5 * (joint.qmin + joint.qmax))
            .collect();
        let mut starts = vec![robot.motor_positions(&middle)?.as_slice().to_vec()];
        starts.extend((0..RANDOM_STARTS).map(|_| sampler.configuration(robot)));
        let solver = Solver {
            robot,
            inverse: InverseSolver::new(robot),
            orientation,
            cell,
            starts,
            options: InverseOptions::default(),
        };
        Ok((solver, reference))
    }

    /// Joints reaching `point` (with the held orientation when `oriented`),
    /// from `near` first, within the limits (and `margin` of each joint's
    /// range inside them) and admitted by the cell.
    fn reach(
        &self,
        point: Vector3<f64>,
        (oriented, margin): (bool, f64),
        near: &[f64],
    ) -> Option<Vec<f64>> {
        let target = match (oriented, self.orientation) {
            (true, Some(rotation)) => Target::Frame(IsometryMatrix3::from_parts(
                Translation3::from(point),
                rotation,
            )),
            _ => Target::Position(point),
        };
        std::iter::once(near)
            .chain(self.starts.iter().map(Vec::as_slice))
            .find_map(|start| {
                let solution = self.inverse.solve(&target, start, &self.options).ok()?;
                let inside = solution
                    .joint_positions
                    .iter()
                    .zip(self.robot.joints())
                    .all(|(q, joint)| {
                        let room = margin * (joint.qmax - joint.qmin);
                        *q >= joint.qmin + room && *q <= joint.qmax - room
                    });
                let motor = solution.motor_positions;
                (inside && self.cell.admits(self.robot, &motor)).then_some(motor)
            })
    }

    /// The point the model gives at `motor_positions`.
    fn point(&self, motor_positions: Vec<f64>) -> Result<PlannedPoint, Error> {
        Ok(PlannedPoint {
            target: terminal_pose(self.robot, &motor_positions)?,
            motor_positions,
        })
    }

    /// The cube's poses and approach points, when it is inside the working
    /// space (module docs), the poses' joints `margin` of their ranges
    /// inside the limits; `None` when not.
    fn fit(
        &self,
        cube: &TestCube,
        (approaches, margin): (Approaches, f64),
        middle: &[f64],
    ) -> Result<Option<Fitted>, Error> {
        let h = cube.side / 2.0;
        for corner in 0..8 {
            let sign = |bit: usize| if corner >> bit & 1 == 1 { h } else { -h };
            let point = cube.centre + Vector3::new(sign(0), sign(1), sign(2));
            if self.reach(point, (false, 0.0), middle).is_none() {
                return Ok(None);
            }
        }
        let mut poses = Vec::with_capacity(5);
        let mut near = middle.to_vec();
        for point in cube.poses() {
            let Some(motor) = self.reach(point, (true, margin), &near) else {
                return Ok(None);
            };
            near.clone_from(&motor);
            poses.push(self.point(motor)?);
        }
        let distance = APPROACH_SHARE * cube.side;
        let mut all_approaches = Vec::with_capacity(5);
        for (pose, planned) in cube.poses().iter().zip(&poses) {
            let mut points = Vec::new();
            if approaches == Approaches::Three {
                for axis in 0..3 {
                    // Inside the cube: towards its centre (P1: below it).
                    let side = if pose[axis] > cube.centre[axis] + 1e-12 {
                        -1.0
                    } else if pose[axis] < cube.centre[axis] - 1e-12 {
                        1.0
                    } else {
                        -1.0
                    };
                    let mut point = *pose;
                    point[axis] += side * distance;
                    let Some(motor) = self.reach(point, (true, margin), &planned.motor_positions)
                    else {
                        return Ok(None);
                    };
                    points.push(self.point(motor)?);
                }
            }
            all_approaches.push(points);
        }
        Ok(Some((poses, all_approaches)))
    }
}

/// Plans the test on `robot` (module docs).
///
/// # Errors
/// [`Error::InvalidOption`] for fewer than 2 cycles; [`Error::InvalidData`]
/// for a robot of fewer than 3 joints, a stated cube outside the working
/// space (naming what is not reached), or no cube found in the cell.
pub fn plan_test(
    robot: &Robot,
    cube: CubeChoice,
    options: &TestOptions,
) -> Result<TestPlan, Error> {
    if options.cycles < 2 {
        return Err(Error::InvalidOption {
            setting: Setting::Count,
            message: format!(
                "{} cycle(s): repeatability needs at least 2 (ISO 9283 asks for {DEFAULT_CYCLES})",
                options.cycles
            ),
        });
    }
    if robot.joint_count() < 3 {
        return Err(Error::InvalidData {
            line: None,
            message: format!(
                "{} has {} joint(s): the test's poses are points in space, which need at least 3",
                robot.name(),
                robot.joint_count()
            ),
        });
    }
    options.cell.check()?;
    let (solver, reference) = Solver::new(robot, &options.cell)?;
    let (cube, searched, margin) = match cube {
        CubeChoice::Stated(cube) => (cube, false, 0.0),
        CubeChoice::Largest => (
            largest_cube(&solver, options.approaches, &reference)?,
            true,
            JOINT_MARGIN,
        ),
    };
    let start = &reference.motor_positions;
    let Some((poses, approaches)) = solver.fit(&cube, (options.approaches, margin), start)? else {
        return Err(Error::InvalidData {
            line: None,
            message: format!(
                "the cube of side {:.1} mm at ({:.1}, {:.1}, {:.1}) mm is not inside {}'s working \
                 space{}: a corner, a pose{} is not reached within the joint limits{}; a smaller \
                 cube, another centre, or the largest cube found (auto)",
                cube.side * 1e3,
                cube.centre.x * 1e3,
                cube.centre.y * 1e3,
                cube.centre.z * 1e3,
                robot.name(),
                if solver.orientation.is_some() {
                    " with the orientation held"
                } else {
                    ""
                },
                if options.approaches == Approaches::Three {
                    " or an approach point"
                } else {
                    ""
                },
                if options.cell.is_open() {
                    ""
                } else {
                    " in the cell"
                }
            ),
        });
    };
    Ok(TestPlan {
        cube,
        searched,
        orientation_held: solver.orientation.is_some(),
        poses,
        approaches,
        cycles: options.cycles,
    })
}

/// The largest cube the search finds (module docs).
fn largest_cube(
    solver: &Solver<'_>,
    approaches: Approaches,
    reference: &Reference,
) -> Result<TestCube, Error> {
    let robot = solver.robot;
    let middle = reference.motor_positions.as_slice();
    let home = terminal_pose(robot, middle)?.translation.vector;
    let reach = reference.reach;
    let millimetres = |value: f64| (value * 1e3).floor() / 1e3;
    let mut centres = vec![home];
    for axis in 0..3 {
        for sign in [1.0, -1.0] {
            let mut centre = home;
            centre[axis] += sign * CENTRE_SHIFT * reach;
            centres.push(centre);
        }
    }
    let mut best: Option<TestCube> = None;
    for centre in centres {
        let centre = centre.map(|x| (x * 1e3).round() / 1e3);
        // Room in space too: a cube this much larger fits (a calibrated
        // robot's links are millimetres longer or shorter than nominal).
        let fits = |side: f64| -> Result<bool, Error> {
            let cube = TestCube::new(centre, side * (1.0 + SPACE_MARGIN))?;
            Ok(solver
                .fit(&cube, (approaches, JOINT_MARGIN), middle)?
                .is_some())
        };
        let smallest = 0.01;
        if best.is_some_and(|best| best.side >= reach) || !fits(smallest)? {
            continue;
        }
        let (mut low, mut high) = (smallest, reach);
        for _ in 0..BISECTIONS {
            let side = 0.5 * (low + high);
            if fits(side)? {
                low = side;
            } else {
                high = side;
            }
        }
        let side = millimetres(low).max(smallest);
        if best.is_none_or(|best| side > best.side) && fits(side)? {
            best = Some(TestCube::new(centre, side)?);
        }
    }
    best.ok_or_else(|| Error::InvalidData {
        line: None,
        message: format!(
            "no test cube of side 10 mm or more fits {}'s working space{} about the tool's \
             position in its reference configuration ({:.1}, {:.1}, {:.1}) mm; state a cube \
             that fits",
            robot.name(),
            if solver.cell.is_open() {
                ""
            } else {
                " and the cell"
            },
            home.x * 1e3,
            home.y * 1e3,
            home.z * 1e3
        ),
    })
}
