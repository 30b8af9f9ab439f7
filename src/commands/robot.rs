//! `gecaro robot show | check | reframe | new` (`import` and `export` are
//! in [`super::interchange`]).

use gecaro_core::{FrameType, Joint, Robot};
use gecaro_io::{RobotFile, format_robot_file, load_robot, write_atomically};
use nalgebra::IsometryMatrix3;

use super::options::output_policy;

use crate::cli::RobotCommand;
use crate::failure::Failure;
use crate::format::{number, shown, table};

pub(crate) fn run(command: RobotCommand) -> Result<(), Failure> {
    match command {
        RobotCommand::Show { robot, .. } if super::is_parallel(Some(&robot)) => {
            super::parallel::show(&robot)
        }
        RobotCommand::Check { robot } if super::is_parallel(Some(&robot)) => {
            super::parallel::check(&robot)
        }
        RobotCommand::Show { robot, deg } => show(&robot, deg),
        RobotCommand::Check { robot } => check(&robot),
        RobotCommand::Reframe {
            robot,
            world,
            tool,
            output,
            force,
        } => reframe(&robot, world.as_deref(), tool.as_deref(), &output, force),
        RobotCommand::New {
            joints,
            output,
            force,
        } => new(&joints, &output, force),
        RobotCommand::Rebase(args) => super::interchange::rebase(&args),
        RobotCommand::Import(args) => super::interchange::import(&args),
        RobotCommand::Export(args) => super::interchange::export(&args),
    }
}

fn show(name: &str, degrees: bool) -> Result<(), Failure> {
    let file = load_robot(name)?;
    let robot = &file.robot;
    let angle = |value: f64| {
        if degrees {
            number(value.to_degrees(), 4)
        } else {
            number(value, 6)
        }
    };
    let unit = if degrees { "m, deg" } else { "m, rad" };
    println!(
        "{} — {} joints ({}), {} parameters ({unit})",
        shown(robot.name()),
        robot.joint_count(),
        robot.joint_letters(),
        robot.parameters().len()
    );
    if let Some(description) = &file.description {
        println!("{}", shown(description));
    }
    let mut frames = table(
        &[
            "j", "σ", "α", "d", "θ", "r", "β", "K", "qmin", "qmax", "offset",
        ],
        2,
    );
    for (j, frame) in robot.frames().iter().enumerate() {
        let mut row = vec![
            j.to_string(),
            frame.frame_type.sigma().to_string(),
            angle(frame.alpha),
            number(frame.d, 6),
            angle(frame.theta),
            number(frame.r, 6),
            angle(frame.beta),
        ];
        match (j, frame.frame_type) {
            (1.., FrameType::Revolute | FrameType::Prismatic) => {
                let joint = &robot.joints()[j - 1];
                let joint_value = |value: f64| {
                    if frame.frame_type == FrameType::Revolute {
                        angle(value)
                    } else {
                        number(value, 6)
                    }
                };
                row.extend([
                    number(joint.gain, 6),
                    joint_value(joint.qmin),
                    joint_value(joint.qmax),
                    joint_value(joint.offset),
                ]);
            }
            _ => row.extend(["–", "–", "–", "–"].map(String::from)),
        }
        frames.add_row(row);
    }
    println!("{frames}");
    print_loads(&file);
    let n = robot.joint_count();
    for (name, matrix) in [
        ("Cm", robot.motor_coupling()),
        ("Cj", robot.joint_coupling()),
    ] {
        if *matrix != nalgebra::DMatrix::identity(n, n) {
            println!("{name} = {matrix:.6}");
        }
    }
    let origin = if robot.priority_override().is_some() {
        "from the file"
    } else {
        "default rules of §4"
    };
    println!("Priority matrix ({origin}; 0 = not identified):");
    let mut priority = table(&["j", "α", "d", "θ", "r", "β", "K"], 1);
    for (j, row) in robot.priority().rows().iter().enumerate() {
        let mut cells = vec![j.to_string()];
        cells.extend(row.iter().map(ToString::to_string));
        priority.add_row(cells);
    }
    println!("{priority}");
    Ok(())
}

/// An elastic robot's compliances, and the masses that load its joints
/// (docs/elastic.md); nothing for a robot that states neither.
fn print_loads(file: &gecaro_io::RobotFile) {
    let robot = &file.robot;
    if let Some(compliances) = robot.compliances() {
        let listed: Vec<String> = compliances
            .iter()
            .enumerate()
            .map(|(index, c)| format!("c{} = {}", index + 1, number(*c, 4)))
            .collect();
        println!(
            "Compliances (rad/(N·m); m/N for a prismatic joint): {}",
            listed.join(", ")
        );
    }
    if file.masses.is_empty() {
        return;
    }
    let mut total = 0.0;
    let listed: Vec<String> = (0..robot.frames().len())
        .filter_map(|frame| file.masses.link(frame).map(|link| (frame, link)))
        .map(|(frame, link)| {
            total += link.mass;
            format!(
                "frame {frame} {} kg at ({}, {}, {}) m",
                number(link.mass, 4),
                number(link.com.x, 4),
                number(link.com.y, 4),
                number(link.com.z, 4)
            )
        })
        .collect();
    let g = file.masses.gravity();
    println!(
        "Masses ({} kg; gravity ({}, {}, {}) m/s² in the world frame): {}",
        number(total, 4),
        number(g.x, 5),
        number(g.y, 5),
        number(g.z, 5),
        listed.join("; ")
    );
}

fn check(name: &str) -> Result<(), Failure> {
    let file = load_robot(name)?;
    let robot = &file.robot;
    println!(
        "ok: {} — {} joints ({}), {} frames, {} parameters",
        shown(robot.name()),
        robot.joint_count(),
        robot.joint_letters(),
        robot.frames().len(),
        robot.parameters().len()
    );
    for note in notes(robot) {
        println!("note: {note}");
    }
    Ok(())
}

/// Things worth knowing about a valid robot: parallel axes (β is then the
/// parameter that keeps the model continuous) and nearly parallel ones (the
/// common normal of the Khalil table is far away and ill-conditioned).
fn notes(robot: &Robot) -> Vec<String> {
    let mut notes = Vec::new();
    let n = robot.joint_count();
    for j in 2..=n {
        let frame = &robot.frames()[j];
        let sine = frame.alpha.sin().abs();
        if sine < 1e-12 {
            notes.push(format!(
                "axes {} and {j} are parallel: beta{j} (Hayati, eq. 3) models their misalignment",
                j - 1
            ));
        } else if sine < 1e-2 {
            notes.push(format!(
                "axes {} and {j} are nearly parallel (alpha{j} = {} rad): their common normal \
                 is ill-conditioned; consider modelling them as parallel and using beta{j}",
                j - 1,
                number(frame.alpha, 6)
            ));
        }
    }
    let limits_default = robot.joints().iter().enumerate().filter(|(index, joint)| {
        let frame_type = robot.frames()[index + 1].frame_type;
        **joint
            == Joint {
                offset: joint.offset,
                gain: joint.gain,
                ..Joint::default_for(frame_type)
            }
    });
    let defaulted: Vec<String> = limits_default
        .map(|(index, _)| (index + 1).to_string())
        .collect();
    if !defaulted.is_empty() {
        notes.push(format!(
            "joint(s) {} use the default limits (±π rad, or 0..1 m for prismatic joints)",
            defaulted.join(", ")
        ));
    }
    notes
}

fn reframe(
    name: &str,
    world: Option<&[f64]>,
    tool: Option<&[f64]>,
    output: &std::path::Path,
    force: bool,
) -> Result<(), Failure> {
    if world.is_none() && tool.is_none() {
        return Err(Failure::usage(
            "nothing to change: give --world, --tool or both",
            Some(
                "for example: --world 0,0,-0.5,1,0,0,0 (the old world 0.5 m below the new one)"
                    .to_owned(),
            ),
        ));
    }
    let original = load_robot(name)?;
    let pose = |values: Option<&[f64]>, option| {
        values.map_or(Ok(IsometryMatrix3::identity()), |values| {
            super::options::pose(values, option)
        })
    };
    let new_world_from_old_world = pose(world, "--world")?;
    let old_tool_from_new_tool = pose(tool, "--tool")?;
    let robot = original
        .robot
        .reframed(&new_world_from_old_world, &old_tool_from_new_tool)?;
    // What was rewritten: the frames' names and numbers.
    let n = robot.joint_count();
    let (frames, numbers): (Vec<&str>, Vec<String>) = [
        (world.is_some(), "world", "0, 1".to_owned()),
        (tool.is_some(), "tool", format!("{n}, {}", n + 1)),
    ]
    .into_iter()
    .filter(|(given, _, _)| *given)
    .map(|(_, frame, numbers)| (frame, numbers))
    .unzip();
    let file = RobotFile {
        description: Some(format!(
            "{} with a new {} frame (gecaro robot reframe)",
            robot.name(),
            frames.join(" and ")
        )),
        urdf: original.urdf.as_ref().map(|names| {
            names.reframed(
                &original.robot,
                &robot,
                &new_world_from_old_world,
                &old_tool_from_new_tool,
            )
        }),
        // Each link keeps its body: the centres of mass move into the new
        // frames' coordinates, gravity into the new world's.
        masses: original
            .masses
            .reframed(&original.robot, &robot, &new_world_from_old_world)?,
        robot,
        angle_unit: original.angle_unit,
        // The joints move as before: the region a calibration measured stays.
        measured_region: original.measured_region.clone(),
        // A tool identified in the old frame n+1, posed in the new one.
        tools: original
            .tools
            .iter()
            .map(|tool| gecaro_io::IdentifiedTool {
                name: tool.name.clone(),
                pose: old_tool_from_new_tool.inverse() * tool.pose,
            })
            .collect(),
        tool_frame_observed: original.tool_frame_observed,
    };
    write_atomically(
        output,
        gecaro_io::robot_file_text(&file, output)?.as_bytes(),
        output_policy(force),
    )?;
    println!(
        "wrote {} (frames {} rewritten)",
        output.display(),
        numbers.join(" and ")
    );
    Ok(())
}

fn new(letters: &str, output: &std::path::Path, force: bool) -> Result<(), Failure> {
    let name = output.file_stem().map_or_else(
        || "robot".into(),
        |stem| stem.to_string_lossy().into_owned(),
    );
    let robot = Robot::template(name, letters).map_err(|error| {
        Failure::usage(
            format!(
                "--joints {letters}: {}",
                error.to_string().trim_start_matches("frames: ")
            ),
            Some("for example: --joints RRPRRR".to_owned()),
        )
    })?;
    let text = format!(
        "# Template written by `gecaro robot new --joints {letters}`: edit the values.\n\
         # Keys per frame: sigma, alpha, d, theta, r, beta (all frames; frame 0 has only theta, r)\n\
         # and qmin, qmax, offset, K (joints). q_j is added to theta_j (R) or r_j (P).\n\
         # Optional tables: [coupling] Cm, Cj (n×n) and [priority] matrix ((n+2)×6).\n{}",
        format_robot_file(&RobotFile {
            description: Some(format!("{letters} arm (template)")),
            ..RobotFile::of(robot)
        })
    );
    write_atomically(output, text.as_bytes(), output_policy(force))?;
    println!(
        "wrote {} ({} joints: {letters})",
        output.display(),
        letters.len()
    );
    Ok(())
}
