//! Robot → URDF: one link per frame that carries one, one joint per joint,
//! named after the URDF the robot was imported from (its [`UrdfNames`]) or
//! after the robot.
//!
//! - Joint origins are the frames at the zero of the URDF joint variables,
//!   β included; each link keeps its imported frame (so meshes and child
//!   frames of the original description stay where they were).
//! - The offsets of eq. 4 move the zero of their joint: they are folded into
//!   the joint origins (and limits), q_urdf = q − offset.
//! - A coupling that is exactly a mimic (Cj = I plus single entries m at
//!   independent joints, Cm = I, K = 1) becomes `<mimic multiplier=m
//!   offset=…>`; the mimic joint's offset stays in the relation.
//! - Any other gain or coupling cannot be written in a URDF: the URDF then
//!   takes joint values `q_urdf = Cj·diag(K)·Cm·qm` and the map is returned
//!   as a joint calibration (YAML) for the driver, with a note. Nothing is
//!   dropped silently.

use gecaro_core::{FrameType, Robot, frame_transform};
use nalgebra::{IsometryMatrix3, Vector3};

use super::names::{UrdfJointNames, UrdfNames};
use crate::conversion::Exported;
use crate::joint_calibration::joint_calibration;
use crate::pose::rpy;
use crate::robot_file::RobotFile;

/// Names for a robot that was not imported from a URDF.
fn generated_names(robot: &Robot) -> UrdfNames {
    UrdfNames {
        robot: robot
            .name()
            .chars()
            .map(|c| if c.is_ascii_alphanumeric() { c } else { '_' })
            .collect(),
        base_link: "base_link".into(),
        world_from_base_link: IsometryMatrix3::identity(),
        joints: (1..=robot.joint_count())
            .map(|j| UrdfJointNames {
                name: format!("joint_{j}"),
                link: format!("link_{j}"),
                frame_from_link: IsometryMatrix3::identity(),
                effort: 0.0,
                velocity: 0.0,
                parent: None,
            })
            .collect(),
        tip_joint: None,
        tip_link: "tool0".into(),
        tool_from_tip_link: IsometryMatrix3::identity(),
        tip_parent: None,
        fixed: Vec::new(),
    }
}

/// For each joint, the independent joint it mimics and the multiplier, if
/// the map Cj·diag(K)·Cm is exactly "identity plus mimic rows"; `None` when
/// it is not (then the whole map goes to the joint calibration).
fn mimics(robot: &Robot) -> Option<Vec<Option<(usize, f64)>>> {
    let map = robot.motor_to_joint();
    let n = robot.joint_count();
    let unit_row = |row: usize| (0..n).all(|c| map[(row, c)] == f64::from(u8::from(c == row)));
    let mut relations = Vec::with_capacity(n);
    for row in 0..n {
        if unit_row(row) {
            relations.push(None);
            continue;
        }
        let others: Vec<usize> = (0..n)
            .filter(|c| *c != row && map[(row, *c)] != 0.0)
            .collect();
        match others.as_slice() {
            [target] if map[(row, row)] == 1.0 && unit_row(*target) => {
                relations.push(Some((*target, map[(row, *target)])));
            }
            _ => return None,
        }
    }
    Some(relations)
}

fn origin(pose: &IsometryMatrix3<f64>) -> urdf_rs::Pose {
    let t = pose.translation.vector;
    urdf_rs::Pose {
        xyz: urdf_rs::Vec3([t.x, t.y, t.z]),
        rpy: urdf_rs::Vec3(rpy(&pose.rotation)),
    }
}

fn link(name: &str) -> urdf_rs::Link {
    urdf_rs::Link {
        name: name.to_owned(),
        inertial: urdf_rs::Inertial::default(),
        visual: Vec::new(),
        collision: Vec::new(),
    }
}

/// A link carrying the mass the robot file states for its frame: its
/// centre moved from the frame's coordinates (`world_from_frame`) into the
/// link's (`world_from_link`). The inertia tensor stays zero: gecaro
/// models the masses' gravity, not their inertia.
fn weighed_link(
    name: &str,
    mass: Option<&gecaro_core::LinkMass>,
    world_from_frame: &IsometryMatrix3<f64>,
    world_from_link: &IsometryMatrix3<f64>,
) -> urdf_rs::Link {
    let mut link = link(name);
    if let Some(mass) = mass {
        let centre =
            world_from_link.inverse() * (world_from_frame * nalgebra::Point3::from(mass.com));
        link.inertial.mass.value = mass.mass;
        link.inertial.origin.xyz = urdf_rs::Vec3([centre.x, centre.y, centre.z]);
    }
    link
}

fn fixed_joint(
    name: String,
    parent: &str,
    child: &str,
    pose: &IsometryMatrix3<f64>,
) -> urdf_rs::Joint {
    urdf_rs::Joint {
        name,
        joint_type: urdf_rs::JointType::Fixed,
        origin: origin(pose),
        parent: urdf_rs::LinkName {
            link: parent.to_owned(),
        },
        child: urdf_rs::LinkName {
            link: child.to_owned(),
        },
        axis: urdf_rs::Axis::default(),
        limit: urdf_rs::JointLimit::default(),
        calibration: None,
        dynamics: None,
        mimic: None,
        safety_controller: None,
    }
}

/// The URDF of a robot file (see the module docs).
///
/// # Errors
/// When urdf-rs cannot write the document (names that are not valid XML
/// text are escaped, so this does not happen for a valid robot).
pub(crate) fn export_urdf(file: &RobotFile) -> Result<Exported, String> {
    let robot = &file.robot;
    let n = robot.joint_count();
    let names = file.urdf.clone().unwrap_or_else(|| generated_names(robot));
    // An elastic robot's compliances go to the joint calibration file, and
    // its whole map with them (mimic tags too would apply it twice).
    let relations = if robot.is_elastic() {
        None
    } else {
        mimics(robot)
    };
    let mut notes = Vec::new();
    // The offset folded into each joint's origin (all but mimic joints').
    let folded: Vec<f64> = robot
        .joints()
        .iter()
        .enumerate()
        .map(|(j, joint)| match &relations {
            Some(relations) if relations[j].is_some() => 0.0,
            _ => joint.offset,
        })
        .collect();
    if folded.iter().any(|offset| *offset != 0.0) {
        notes.push(
            "joint offsets are folded into the joint origins: the URDF joint value is q − offset"
                .to_owned(),
        );
    }
    // Frames at the zero of the URDF joint values.
    let world_from_frame: Vec<IsometryMatrix3<f64>> = robot
        .frames()
        .iter()
        .enumerate()
        .scan(IsometryMatrix3::identity(), |pose, (j, frame)| {
            let q = if (1..=n).contains(&j) {
                folded[j - 1]
            } else {
                0.0
            };
            *pose *= frame_transform(frame, q);
            Some(*pose)
        })
        .collect();
    let taken = |name: &str| {
        names.base_link == name
            || names.tip_link == name
            || names.joints.iter().any(|j| j.link == name)
    };
    let mut links = Vec::new();
    let mut joints = Vec::new();
    if names.world_from_base_link != IsometryMatrix3::identity() {
        let world = if taken("world") {
            "gecaro_world"
        } else {
            "world"
        };
        links.push(link(world));
        joints.push(fixed_joint(
            format!("{world}_to_{}", names.base_link),
            world,
            &names.base_link,
            &names.world_from_base_link,
        ));
        notes.push(format!(
            "the robot's world frame is not its base link (it was reframed): root link `{world}` carries `{}`",
            names.base_link
        ));
    }
    links.push(weighed_link(
        &names.base_link,
        file.masses.link(0),
        &world_from_frame[0],
        &names.world_from_base_link,
    ));
    // Where every link stands: the chain's on the robot's frames, the kept
    // fixed links on their parents as the URDF had them.
    let world_from_tip = world_from_frame[n + 1] * names.tool_from_tip_link;
    let mut placed: Vec<(&str, IsometryMatrix3<f64>)> =
        vec![(names.base_link.as_str(), names.world_from_base_link)];
    placed.extend(names.joints.iter().enumerate().map(|(j, joint)| {
        (
            joint.link.as_str(),
            world_from_frame[j + 1] * joint.frame_from_link,
        )
    }));
    if !placed.iter().any(|(name, _)| *name == names.tip_link) {
        placed.push((names.tip_link.as_str(), world_from_tip));
    }
    for kept in &names.fixed {
        // `UrdfDocument::read` checked that every parent is named before.
        let parent = placed
            .iter()
            .find(|(name, _)| *name == kept.parent)
            .map_or(world_from_tip, |(_, pose)| *pose);
        placed.push((kept.link.as_str(), parent * kept.origin));
    }
    let world_from = |name: &str, otherwise: IsometryMatrix3<f64>| {
        placed
            .iter()
            .find(|(link, _)| *link == name)
            .map_or(otherwise, |(_, pose)| *pose)
    };
    let mut parent_link = names.base_link.clone();
    let mut world_from_parent = names.world_from_base_link;
    for (j, joint_names) in names.joints.iter().enumerate() {
        if let Some(parent) = &joint_names.parent {
            world_from_parent = world_from(parent, world_from_parent);
            parent_link = parent.clone();
        }
        let world_from_link = world_from_frame[j + 1] * joint_names.frame_from_link;
        let axis = joint_names.frame_from_link.rotation.inverse() * Vector3::z();
        let frame = &robot.frames()[j + 1];
        let limits = &robot.joints()[j];
        let mimic =
            relations
                .as_ref()
                .and_then(|relations| relations[j])
                .map(|(target, multiplier)| urdf_rs::Mimic {
                    joint: names.joints[target].name.clone(),
                    multiplier: Some(multiplier),
                    offset: Some(limits.offset),
                });
        joints.push(urdf_rs::Joint {
            name: joint_names.name.clone(),
            joint_type: match frame.frame_type {
                FrameType::Prismatic => urdf_rs::JointType::Prismatic,
                _ => urdf_rs::JointType::Revolute,
            },
            origin: origin(&(world_from_parent.inverse() * world_from_link)),
            parent: urdf_rs::LinkName {
                link: parent_link.clone(),
            },
            child: urdf_rs::LinkName {
                link: joint_names.link.clone(),
            },
            axis: urdf_rs::Axis {
                xyz: urdf_rs::Vec3([axis.x, axis.y, axis.z]),
            },
            limit: urdf_rs::JointLimit {
                lower: limits.qmin - folded[j],
                upper: limits.qmax - folded[j],
                effort: joint_names.effort,
                velocity: joint_names.velocity,
                ..urdf_rs::JointLimit::default()
            },
            calibration: None,
            dynamics: None,
            mimic,
            safety_controller: None,
        });
        links.push(weighed_link(
            &joint_names.link,
            file.masses.link(j + 1),
            &world_from_frame[j + 1],
            &world_from_link,
        ));
        parent_link = joint_names.link.clone();
        world_from_parent = world_from_link;
    }
    let mut tip = names.tip_link.clone();
    if names.joints.iter().any(|joint| joint.link == tip) {
        tip = format!("{tip}_tool");
        notes.push(format!(
            "the tool frame n+1 gets its own link `{tip}` (the URDF's tip was the last joint's link)"
        ));
    }
    if let Some(parent) = &names.tip_parent {
        world_from_parent = world_from(parent, world_from_parent);
        parent_link = parent.clone();
    }
    joints.push(fixed_joint(
        names
            .tip_joint
            .clone()
            .unwrap_or_else(|| format!("{parent_link}_to_{tip}")),
        &parent_link,
        &tip,
        &(world_from_parent.inverse() * world_from_tip),
    ));
    links.push(weighed_link(
        &tip,
        file.masses.link(n + 1),
        &world_from_frame[n + 1],
        &world_from_tip,
    ));

    for kept in &names.fixed {
        links.push(link(&kept.link));
        joints.push(fixed_joint(
            kept.joint.clone(),
            &kept.parent,
            &kept.link,
            &kept.origin,
        ));
    }

    let joint_calibration = if relations.is_some() {
        None
    } else {
        notes.push(
            "gains K or couplings are not expressible in a URDF: its joint values are \
             q_urdf = Cj·diag(K)·Cm·qm, a map written to the joint calibration file for the driver"
                .to_owned(),
        );
        let joint_names: Vec<String> = names
            .joints
            .iter()
            .map(|joint| joint.name.clone())
            .collect();
        joint_calibration(robot, &joint_names, "URDF")
    };
    let document = urdf_rs::Robot {
        name: names.robot.clone(),
        version: None,
        links,
        joints,
        materials: Vec::new(),
    };
    let text = urdf_rs::write_to_string(&document).map_err(|error| error.to_string())?;
    Ok(Exported {
        text: format!(
            "<?xml version=\"1.0\"?>\n<!-- written by gecaro robot export from `{}`: chain `{}` → `{tip}`; {} -->\n{text}\n",
            robot.name().replace("--", "- -"),
            names.base_link.replace("--", "- -"),
            if file.masses.is_empty() {
                "kinematic chain only (no meshes, no inertia)"
            } else {
                "kinematic chain and the links' masses (no meshes, no inertia tensors)"
            }
        ),
        joint_calibration,
        notes,
    })
}
