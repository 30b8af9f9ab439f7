//! `gecaro fk`, `gecaro jacobian` and `gecaro ik`.

use gecaro_core::{InverseOptions, Target, forward_kinematics, parameter_jacobian};
use gecaro_io::load_robot;
use nalgebra::IsometryMatrix3;
use serde::Serialize;

use crate::cli::{ConfigurationArgs, IkArgs};
use crate::failure::Failure;
use crate::format::{number, table};

#[derive(Serialize)]
struct PoseJson {
    position: [f64; 3],
    rotation: [[f64; 3]; 3],
}

/// The robot and `--qm` in gecaro's units (radians, metres).
fn configuration(
    args: &ConfigurationArgs,
) -> Result<(gecaro_core::Robot, Vec<f64>, gecaro_io::DataUnits), Failure> {
    let robot = load_robot(&args.robot)?.robot;
    let units = super::options::data_units(&args.units)?;
    let qm = units.configuration_to_si(&gecaro_io::joint_types(&robot), &args.qm);
    Ok((robot, qm, units))
}

pub(crate) fn forward(args: &ConfigurationArgs) -> Result<(), Failure> {
    let (robot, qm, units) = configuration(args)?;
    let chain = forward_kinematics(&robot, &qm)?;
    let tool = chain.world_from_tool();
    let position = tool.translation.vector;
    let rotation = tool.rotation.matrix();
    let pose = PoseJson {
        position: [position.x, position.y, position.z],
        rotation: std::array::from_fn(|i| std::array::from_fn(|j| rotation[(i, j)])),
    };
    if args.json {
        return super::output::print_json(&pose);
    }
    println!(
        "{} at qm = ({})",
        robot.name(),
        crate::format::list(&args.qm)
    );
    let scale = 1.0 / units.length.to_metres();
    println!(
        "position ({}):  x = {}  y = {}  z = {}",
        units.length.name(),
        number(position.x * scale, 7),
        number(position.y * scale, 7),
        number(position.z * scale, 7)
    );
    println!(
        "rotation (columns s, n, a of frame {}):",
        robot.frames().len() - 1
    );
    for row in pose.rotation {
        println!(
            "  [{:>10} {:>10} {:>10}]",
            number(row[0], 7),
            number(row[1], 7),
            number(row[2], 7)
        );
    }
    Ok(())
}

#[derive(Serialize)]
struct JacobianJson {
    parameters: Vec<String>,
    rows: Vec<Vec<f64>>,
}

pub(crate) fn jacobian(args: &ConfigurationArgs) -> Result<(), Failure> {
    let (robot, qm, _) = configuration(args)?;
    let jacobian = parameter_jacobian(&robot, &qm)?;
    let names = robot.parameters().names();
    if args.json {
        return super::output::print_json(&JacobianJson {
            parameters: names,
            rows: jacobian
                .row_iter()
                .map(|row| row.iter().copied().collect())
                .collect(),
        });
    }
    println!(
        "Jacobian of frame {} w.r.t. the {} parameters at qm = ({}); one row per parameter (column of J)",
        robot.frames().len() - 1,
        names.len(),
        crate::format::list(&args.qm)
    );
    let mut rows = table(&["parameter", "∂x", "∂y", "∂z", "δx", "δy", "δz"], 1);
    for (name, column) in names.iter().zip(jacobian.column_iter()) {
        let mut cells = vec![name.clone()];
        cells.extend(column.iter().map(|v| number(*v, 6)));
        rows.add_row(cells);
    }
    println!("{rows}");
    Ok(())
}

#[derive(Serialize)]
struct InverseJson {
    motor_positions: Vec<f64>,
    joint_positions: Vec<f64>,
    iterations: usize,
    residual: f64,
}

pub(crate) fn inverse(args: &IkArgs) -> Result<(), Failure> {
    let robot = load_robot(&args.robot)?.robot;
    let position = super::options::vector3(&args.position, "--position")?;
    let target = match &args.orientation {
        None => Target::Position(position),
        Some(values) => {
            let rotation = super::options::rotation(values, "--orientation")?;
            Target::Frame(IsometryMatrix3::from_parts(position.into(), rotation))
        }
    };
    let solution = gecaro_app::inverse_model(
        &robot,
        &target,
        args.start.as_deref(),
        &InverseOptions::default(),
    )?;
    if args.json {
        return super::output::print_json(&InverseJson {
            motor_positions: solution.motor_positions.clone(),
            joint_positions: solution.joint_positions.clone(),
            iterations: solution.iterations,
            residual: solution.residual,
        });
    }
    println!(
        "{} reaches the target in {} iterations (remaining error {:.1e})",
        robot.name(),
        solution.iterations,
        solution.residual
    );
    println!("qm = {}", crate::format::list(&solution.motor_positions));
    println!("q  = {}", crate::format::list(&solution.joint_positions));
    Ok(())
}
