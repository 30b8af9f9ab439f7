//! Writes `examples/owner-base/`: the KR 16-2 of `examples/tracker` as its
//! owner's cell has it — a laser tracker 2.8 m away, turned 150° and tilted
//! 0.3°, the robot standing on a mounting plate whose holes the drawing
//! gives, a tool whose tip is taught by pivoting, and a job of joint
//! targets in the owner's base with that tool. What `README.md`'s walk
//! from an empty folder to a compensated job uses; the truth (`real.toml`,
//! in the plate's frame, and `truth.toml`'s tool) for checking only.

use gecaro_calib::simulation::{Sampler, perturbed_robot};
use gecaro_core::{InverseOptions, Robot, Target, inverse_kinematics, terminal_pose};
use gecaro_io::{RobotFile, format_robot_file};
use nalgebra::{IsometryMatrix3, Point3, Rotation3, Translation3, Unit, Vector3};
use std::fmt::Write as _;

use crate::Result;

/// The tracker's standard deviation per axis (m), over the robot's poses.
const POSE_SIGMA: f64 = 2e-5;
/// The same for a static point (a plate's hole), averaged by the tracker.
const STATIC_SIGMA: f64 = 5e-6;
/// The tool's tip in frame n+1 (m): what pivoting teaches.
pub(crate) const TOOL_TIP: [f64; 3] = [0.015, -0.02, 0.18];

/// A reflector of the cell: its name, its true position in frame n+1 (m;
/// none: the flange's centre) and the position the study states (mm).
type Reflector = (&'static str, Option<[f64; 3]>, Option<[f64; 3]>);

/// The tracker in the plate's frame: 2.8 m away, turned 150°, tilted 0.3°.
fn tracker_in_plate() -> IsometryMatrix3<f64> {
    IsometryMatrix3::from_parts(
        Translation3::new(2.2, -1.7, 0.4),
        Rotation3::from_axis_angle(&Vector3::z_axis(), 150f64.to_radians())
            * Rotation3::from_axis_angle(&Vector3::x_axis(), 0.3f64.to_radians()),
    )
}

fn degrees(qm: &[f64]) -> String {
    qm.iter()
        .map(|q| format!("{:.4}", q.to_degrees()))
        .collect::<Vec<_>>()
        .join(",")
}

/// A pose of the working region: the nominal's random configuration within
/// its limits, away from the folded ones (joints 2, 3 and 5 bent) and with
/// the wrist's joints 4 and 6 within a turn and a half (as a job is taught).
fn working(robot: &Robot, sampler: &mut Sampler) -> Vec<f64> {
    loop {
        let qm = sampler.configuration(robot);
        if qm[1] < -0.6
            && qm[1] > -2.0
            && qm[2] > 0.5
            && qm[4].abs() > 0.3
            && qm[3].abs() < 2.5
            && qm[5].abs() < 2.5
        {
            return qm;
        }
    }
}

/// Joint values of `count` orientations of `real` with the tool's tip on
/// `fixed` (the plate's frame), tilted up to 40° from looking down.
fn pivot(real: &Robot, fixed: Vector3<f64>, count: usize, sampler: &mut Sampler) -> Vec<Vec<f64>> {
    let tip = Vector3::from(TOOL_TIP);
    let tooled = real
        .reframed(
            &IsometryMatrix3::identity(),
            &IsometryMatrix3::translation(tip.x, tip.y, tip.z),
        )
        .expect("a tool on the flange");
    let down = Rotation3::from_euler_angles(std::f64::consts::PI, 0.0, 0.0);
    let start = [0.0, -1.2, 1.6, 0.0, 1.1, 0.0];
    let mut configurations = Vec::new();
    while configurations.len() < count {
        let axis = Unit::new_normalize(sampler.gaussian_vector(1.0));
        let turn = Rotation3::from_axis_angle(&axis, sampler.uniform(-0.7, 0.7));
        let target = IsometryMatrix3::from_parts(Translation3::from(fixed), turn * down);
        if let Ok(solution) = inverse_kinematics(
            &tooled,
            &Target::Frame(target),
            &start,
            &InverseOptions::default(),
        ) && real.within_limits(&solution.joint_positions)
        {
            configurations.push(solution.motor_positions);
        }
    }
    configurations
}

/// Writes the owner's cell of `nominal` into `write` (a file name and its text).
pub(crate) fn write_owner_cell(
    nominal: &Robot,
    write: &dyn Fn(&str, &str) -> Result<()>,
) -> Result<()> {
    let mut sampler = Sampler::new(17);
    // The real robot in the plate's frame: its base where the plate holds
    // it (a few mm and tenths of a degree from the drawing's), its links off.
    let real = perturbed_robot(nominal, 0.3, &mut sampler)?;
    write(
        "real.toml",
        &format_robot_file(&RobotFile {
            description: Some(
                "the simulated real KR 16-2 of examples/owner-base in its plate's frame (error \
                 level 0.3, seed 17): the truth, for checking"
                    .into(),
            ),
            ..RobotFile::of(real.clone())
        }),
    )?;
    let plate_from_tracker = tracker_in_plate();
    let tracker_from_plate = plate_from_tracker.inverse();
    let mm = |v: f64| format!("{:.4}", v * 1e3);
    // The calibration: the tracker sees a reflector in the flange's centre
    // (an adapter on tool0) and two on the tool plate, 30 poses each; a
    // study states them (the two offset ones by the drawing, within a mm).
    let reflectors: [Reflector; 3] = [
        ("flange", None, None),
        (
            "smr_b",
            Some([0.0405, 0.0248, 0.0903]),
            Some([40.0, 25.0, 90.0]),
        ),
        (
            "smr_c",
            Some([-0.0512, 0.0321, 0.0688]),
            Some([-51.0, 32.0, 69.0]),
        ),
    ];
    let mut study = String::from(
        "# The owner's cell: a reflector in the flange's centre and two on the tool plate,\n\
         # seen by a tracker 2.8 m from the robot (docs/studies.md)\n\
         robot = \"kr16.toml\"\nlength_unit = \"mm\"\nangle_unit = \"deg\"\n",
    );
    for (name, _, stated) in &reflectors {
        if let Some([x, y, z]) = stated {
            let _ = writeln!(study, "\n[tools.{name}]\nposition = [{x}, {y}, {z}]");
        }
    }
    for (name, truth, _) in &reflectors {
        let offset = truth.map_or_else(Vector3::zeros, Vector3::from);
        let mut data = String::from("qm1,qm2,qm3,qm4,qm5,qm6,x,y,z\n");
        for _ in 0..30 {
            let qm = working(nominal, &mut sampler);
            let seen = terminal_pose(&real, &qm)? * Point3::from(offset);
            let p = tracker_from_plate * seen + sampler.gaussian_vector(POSE_SIGMA);
            let _ = writeln!(data, "{},{},{},{}", degrees(&qm), mm(p.x), mm(p.y), mm(p.z));
        }
        write(&format!("{name}.csv"), &data)?;
        let _ = write!(
            study,
            "\n[[measurements]]\nmethod = \"position\"\ndata = \"{name}.csv\"\n"
        );
        if truth.is_some() {
            let _ = writeln!(study, "tool = \"{name}\"");
        }
        let _ = writeln!(study, "sigma = 0.02");
    }
    write("study.toml", &study)?;
    // The plate's holes: where the drawing puts them, as the tracker measured them.
    let mut plate = String::from(
        "# Holes of the mounting plate: measured by the tracker (mm, its frame) beside the drawing's (mm)\n\
         name;x;y;z;base_x;base_y;base_z\n",
    );
    let holes = [
        ("H1", 0.25, 0.25),
        ("H2", -0.25, 0.25),
        ("H3", -0.25, -0.25),
        ("H4", 0.25, -0.25),
        ("H5", 0.0, 0.32),
    ];
    for (name, x, y) in holes {
        let p = tracker_from_plate * Point3::new(x, y, 0.0) + sampler.gaussian_vector(STATIC_SIGMA);
        let comma = |v: f64| mm(v).replace('.', ",");
        let _ = writeln!(
            plate,
            "{name};{};{};{};{};{};0",
            comma(p.x),
            comma(p.y),
            comma(p.z),
            x * 1e3,
            y * 1e3
        );
    }
    write("plate.csv", &plate)?;
    // The tool's tip held on a cone, eight orientations, as the controller logged them.
    let cone = Vector3::new(1.1, 0.2, 0.3);
    let mut pivot_file = String::from(
        "# The tool's tip on the cone, eight orientations (degrees)\nqm1,qm2,qm3,qm4,qm5,qm6\n",
    );
    for qm in pivot(&real, cone, 8, &mut sampler) {
        let _ = writeln!(pivot_file, "{}", degrees(&qm));
    }
    write("pivot.csv", &pivot_file)?;
    // A job of joint targets taught on the nominal model, for the tool.
    let mut job = String::from(
        "# A job of joint targets (degrees) taught on the nominal model, for the tool\nPoint,A1,A2,A3,A4,A5,A6\n",
    );
    for index in 0..25 {
        let qm = working(nominal, &mut sampler);
        let _ = writeln!(job, "J{:02},{}", index + 1, degrees(&qm));
    }
    write("job.csv", &job)?;
    Ok(())
}
