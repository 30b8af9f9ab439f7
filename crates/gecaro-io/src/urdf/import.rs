//! URDF → robot: the serial chain between two links, written as
//! Khalil–Kleinfinger frames (see [`gecaro_core::AxisChain`] for the
//! placement rules).
//!
//! - The chain runs from the base link (default: the root) to the tip link
//!   (default: the leaf below the base whose chain has the most moving
//!   joints; a tie is an error that lists the leaves).
//! - revolute, continuous and prismatic joints become joints 1..n with the
//!   **same joint variable** (sign and zero); fixed joints are folded into the
//!   neighbouring frames. `<limit>` gives qmin/qmax (continuous joints: ±π
//!   unless limits are given; a missing or empty range: the defaults, with a
//!   note).
//! - `<mimic joint="a" multiplier="m" offset="o">` on joint k becomes the
//!   coupling q_k = m·q_a + o + qm_k of eq. 4 (a row of Cj and the offset of
//!   joint k): qm_k is the deviation from the mimic relation, 0 when the
//!   mechanism follows it. Joint a must be in the chain.
//! - floating, planar and spherical joints, closed loops, xacro macros and
//!   malformed XML are errors naming the line.

use std::collections::{HashMap, HashSet};
use std::path::Path;

use gecaro_core::{AxisChain, ChainJoint, FrameType, Joint, LinkMass, MassModel, Robot, RobotSpec};
use nalgebra::{DMatrix, IsometryMatrix3, Unit, Vector3};
use urdf_rs::JointType;

use super::names::{UrdfFixedLink, UrdfJointNames, UrdfNames};
use crate::Error;
use crate::conversion::{ChainEnds, Imported};
use crate::pose::from_xyz_rpy;
use crate::robot_file::{AngleUnit, RobotFile};

/// The text of a URDF file, to name lines in messages.
struct Source<'a> {
    path: &'a Path,
    text: &'a str,
}

impl Source<'_> {
    fn line_at(&self, offset: usize) -> usize {
        // Offsets are the XML parser's, in bytes: not always at a character.
        crate::error::line_at(self.text, offset)
    }

    /// The line of the element `<tag … name="name"`, or 1.
    fn element_line(&self, tag: &str, name: &str) -> usize {
        let opening = format!("<{tag}");
        let quoted = [format!("name=\"{name}\""), format!("name='{name}'")];
        let mut from = 0;
        while let Some(found) = self.text[from..].find(&opening) {
            let start = from + found;
            let end = self.text[start..]
                .find('>')
                .map_or(self.text.len(), |e| start + e);
            let element = &self.text[start..end];
            let after = element[opening.len()..].chars().next();
            if after.is_some_and(char::is_whitespace) && quoted.iter().any(|q| element.contains(q))
            {
                return self.line_at(start);
            }
            from = start + opening.len();
        }
        1
    }

    fn joint_error(&self, joint: &str, message: impl Into<String>) -> Error {
        Error::parse(
            self.path,
            self.element_line("joint", joint),
            Some(format!("joint \"{}\"", joint.escape_debug())),
            message,
        )
    }

    fn link_error(&self, link: &str, message: impl Into<String>) -> Error {
        Error::parse(
            self.path,
            self.element_line("link", link),
            Some(format!("link \"{}\"", link.escape_debug())),
            message,
        )
    }

    fn error(&self, line: usize, message: impl Into<String>) -> Error {
        Error::parse(self.path, line, None, message)
    }

    /// The offset of the first `<xacro:…>` element (comments do not count).
    fn first_xacro_element(&self) -> Option<usize> {
        let mut reader = quick_xml::Reader::from_str(self.text);
        loop {
            let before = usize::try_from(reader.buffer_position()).unwrap_or(0);
            match reader.read_event() {
                Ok(
                    quick_xml::events::Event::Start(element)
                    | quick_xml::events::Event::Empty(element),
                ) if element.name().as_ref().starts_with(b"xacro:") => {
                    return Some(before);
                }
                Ok(quick_xml::events::Event::Eof) | Err(_) => return None,
                Ok(_) => {}
            }
        }
    }

    /// The first well-formedness error of the XML (quick-xml), with its line.
    fn xml_error(&self) -> Option<(usize, String)> {
        let mut reader = quick_xml::Reader::from_str(self.text);
        reader.config_mut().check_end_names = true;
        loop {
            match reader.read_event() {
                Err(error) => {
                    let offset = usize::try_from(reader.error_position()).unwrap_or(0);
                    return Some((self.line_at(offset), brief(&error.to_string())));
                }
                Ok(quick_xml::events::Event::Eof) => return None,
                Ok(_) => {}
            }
        }
    }

    /// Where urdf-rs found a problem of content it does not locate: the
    /// first line holding the value its message quotes.
    fn locate(&self, message: &str) -> usize {
        let quoted = message
            .split('`')
            .nth(1)
            .or_else(|| {
                message
                    .rsplit_once('[')
                    .and_then(|(_, rest)| rest.split(']').next())
            })
            .filter(|value| !value.is_empty());
        quoted
            .and_then(|value| self.text.find(&format!("\"{value}\"")))
            .map_or(1, |offset| self.line_at(offset))
    }
}

/// A parser's message as one short line: its first line, at most 200
/// characters (a malformed tag can make the parser quote pages of the file).
fn brief(message: &str) -> String {
    const LONGEST: usize = 200;
    let first = message.lines().next().unwrap_or("");
    if first.chars().count() > LONGEST || first.len() < message.trim_end().len() {
        format!("{}…", first.chars().take(LONGEST).collect::<String>())
    } else {
        first.to_owned()
    }
}

/// At most the first 10 of `names`, and how many more there are.
fn shortened(names: &[&str]) -> String {
    const SHOWN: usize = 10;
    if names.len() <= SHOWN {
        names.join(", ")
    } else {
        format!(
            "{}, … and {} more",
            names[..SHOWN].join(", "),
            names.len() - SHOWN
        )
    }
}

/// The tree of a URDF: which joint carries each link, and which joints
/// hang from each link.
struct Tree<'a> {
    robot: &'a urdf_rs::Robot,
    parent_joint: HashMap<&'a str, &'a urdf_rs::Joint>,
    child_joints: HashMap<&'a str, Vec<&'a urdf_rs::Joint>>,
    links: HashSet<&'a str>,
}

impl<'a> Tree<'a> {
    fn new(robot: &'a urdf_rs::Robot, source: &Source<'_>) -> Result<Self, Error> {
        let mut links = HashSet::new();
        for link in &robot.links {
            if link.name.trim().is_empty() {
                return Err(source.error(
                    source.element_line("link", ""),
                    "a <link> without a name: every link of a URDF is named",
                ));
            }
            if !links.insert(link.name.as_str()) {
                return Err(source.link_error(&link.name, "a second link of this name"));
            }
        }
        let mut names = HashSet::new();
        let mut parent_joint = HashMap::new();
        let mut child_joints: HashMap<&str, Vec<&urdf_rs::Joint>> = HashMap::new();
        for joint in &robot.joints {
            if !names.insert(joint.name.as_str()) {
                return Err(source.joint_error(&joint.name, "a second joint of this name"));
            }
            for (role, link) in [("parent", &joint.parent.link), ("child", &joint.child.link)] {
                if !links.contains(link.as_str()) {
                    return Err(source.joint_error(
                        &joint.name,
                        format!("its {role} link `{link}` is not a <link> of the file"),
                    ));
                }
            }
            if let Some(other) = parent_joint.insert(joint.child.link.as_str(), joint) {
                return Err(source.joint_error(
                    &joint.name,
                    format!(
                        "link `{}` is already the child of joint `{}`: a closed loop, which a \
                         serial robot does not have",
                        joint.child.link, other.name
                    ),
                ));
            }
            child_joints
                .entry(joint.parent.link.as_str())
                .or_default()
                .push(joint);
        }
        Ok(Tree {
            robot,
            parent_joint,
            child_joints,
            links,
        })
    }

    fn root(&self, source: &Source<'_>) -> Result<&'a str, Error> {
        let roots: Vec<&str> = self
            .robot
            .links
            .iter()
            .map(|link| link.name.as_str())
            .filter(|link| !self.parent_joint.contains_key(link))
            .collect();
        match roots.as_slice() {
            [root] => Ok(root),
            [] if self.robot.links.is_empty() => {
                Err(source.error(1, "no <link>: a URDF describes its robot's links"))
            }
            [] => Err(source.error(
                1,
                "every link is the child of a joint: the joints form a closed loop",
            )),
            many => Err(source.error(
                1,
                format!(
                    "the links form {} separate trees (roots {}); a URDF has one root",
                    many.len(),
                    shortened(many)
                ),
            )),
        }
    }

    /// The joints from `base` down to `tip`, in order.
    fn path(
        &self,
        base: &str,
        tip: &str,
        source: &Source<'_>,
    ) -> Result<Vec<&'a urdf_rs::Joint>, Error> {
        let mut joints = Vec::new();
        let mut link = tip;
        while link != base {
            let Some(joint) = self.parent_joint.get(link) else {
                return Err(source.link_error(
                    tip,
                    format!("link `{tip}` is not below the base link `{base}`"),
                ));
            };
            if joints.len() > self.robot.joints.len() {
                return Err(source.joint_error(&joint.name, "the joints form a closed loop"));
            }
            joints.push(*joint);
            link = joint.parent.link.as_str();
        }
        joints.reverse();
        Ok(joints)
    }

    /// The leaves below `base` with the number of moving joints above each.
    fn leaves(&self, base: &'a str) -> Vec<(&'a str, usize)> {
        let mut leaves = Vec::new();
        let mut stack = vec![(base, 0_usize)];
        let mut visited = HashSet::new();
        while let Some((link, moving)) = stack.pop() {
            if !visited.insert(link) {
                continue;
            }
            match self.child_joints.get(link) {
                None => leaves.push((link, moving)),
                Some(joints) => {
                    for joint in joints {
                        let moves = usize::from(joint.joint_type != JointType::Fixed);
                        stack.push((joint.child.link.as_str(), moving + moves));
                    }
                }
            }
        }
        leaves.sort_by(|a, b| b.1.cmp(&a.1).then(a.0.cmp(b.0)));
        leaves
    }

    /// The tip: as given, or the leaf with the most moving joints.
    fn tip(
        &self,
        base: &'a str,
        given: Option<&'a str>,
        source: &Source<'_>,
    ) -> Result<&'a str, Error> {
        if let Some(tip) = given {
            if !self.links.contains(tip) {
                return Err(source.error(
                    1,
                    format!("no link `{tip}` in the file (the tip asked for)"),
                ));
            }
            return Ok(tip);
        }
        let leaves = self.leaves(base);
        let most = leaves.first().map_or(0, |leaf| leaf.1);
        let best: Vec<&str> = leaves.iter().filter(|l| l.1 == most).map(|l| l.0).collect();
        match best.as_slice() {
            [tip] => Ok(tip),
            _ => Err(source.error(
                1,
                format!(
                    "the chain branches below `{base}`: leaves {} have {most} moving joints \
                     each; choose the tip link (leaves: {})",
                    shortened(&best),
                    shortened(
                        &leaves
                            .iter()
                            .map(|(leaf, moving)| format!("{leaf} ({moving})"))
                            .collect::<Vec<_>>()
                            .iter()
                            .map(String::as_str)
                            .collect::<Vec<_>>()
                    )
                ),
            )),
        }
    }
}

/// A mimic relation resolved to motor variables: q_k = Σ row_i·qm_i + constant.
fn resolve_mimic(
    index: usize,
    chain: &[&urdf_rs::Joint],
    by_name: &HashMap<&str, usize>,
    source: &Source<'_>,
    visiting: &mut Vec<usize>,
) -> Result<(Vec<f64>, f64), Error> {
    let n = chain.len();
    let mut row = vec![0.0; n];
    row[index] = 1.0;
    let Some(mimic) = &chain[index].mimic else {
        return Ok((row, 0.0));
    };
    let name = &chain[index].name;
    let Some(&target) = by_name.get(mimic.joint.as_str()) else {
        return Err(source.joint_error(
            name,
            format!(
                "mimics joint `{}`, which is not a moving joint of the chain: the relation \
                 cannot be written as a coupling (choose a tip whose chain holds both joints)",
                mimic.joint
            ),
        ));
    };
    if visiting.contains(&target) || target == index {
        return Err(source.joint_error(name, "mimic relations that form a loop"));
    }
    let multiplier = mimic.multiplier.unwrap_or(1.0);
    let offset = mimic.offset.unwrap_or(0.0);
    if !multiplier.is_finite() || !offset.is_finite() {
        return Err(source.joint_error(name, "<mimic> multiplier or offset is not a finite number"));
    }
    visiting.push(index);
    let (target_row, target_constant) = resolve_mimic(target, chain, by_name, source, visiting)?;
    visiting.pop();
    for (value, target) in row.iter_mut().zip(target_row) {
        *value += multiplier * target;
    }
    Ok((row, multiplier * target_constant + offset))
}

/// The limits of a moving joint, and a note when the defaults stand in.
fn limits(joint: &urdf_rs::Joint, frame_type: FrameType) -> (f64, f64, Option<String>) {
    let (lower, upper) = (joint.limit.lower, joint.limit.upper);
    let bounded = |value: f64| value.abs() <= gecaro_core::MAX_MAGNITUDE;
    let given = bounded(lower) && bounded(upper) && lower < upper;
    let defaults = Joint::default_for(frame_type);
    if given {
        return (lower, upper, None);
    }
    let why = if joint.joint_type == JointType::Continuous {
        return (defaults.qmin, defaults.qmax, None);
    } else if lower.is_finite() && upper.is_finite() && lower == upper {
        "no range in <limit>"
    } else if lower.is_finite() && upper.is_finite() && lower < upper {
        "a <limit> beyond ±1000 stands for no limit"
    } else {
        "no finite <limit>"
    };
    let range = match frame_type {
        FrameType::Prismatic => "0..1 m",
        _ => "±π",
    };
    (
        defaults.qmin,
        defaults.qmax,
        Some(format!(
            "joint `{}`: {why}; limits set to {range}",
            joint.name
        )),
    )
}

/// Imports the chain `ends` of a URDF text; `path` names it in messages.
pub(crate) fn import_urdf(text: &str, path: &Path, ends: &ChainEnds) -> Result<Imported, Error> {
    let source = Source { path, text };
    if let Some(offset) = source.first_xacro_element() {
        return Err(source.error(
            source.line_at(offset),
            "this is a xacro file (`<xacro:` macros), not a URDF: expand it first, e.g. \
             `xacro robot.urdf.xacro > robot.urdf`, then import robot.urdf",
        ));
    }
    if let Err((offset, message)) = super::bounds::check(text) {
        return Err(source.error(source.line_at(offset), message));
    }
    let robot = urdf_rs::read_from_string(text).map_err(|error| match source.xml_error() {
        Some((line, message)) => source.error(line, format!("not well-formed XML: {message}")),
        None => {
            let message = error.to_string();
            source.error(
                source.locate(&message),
                format!(
                    "not a valid URDF: {}",
                    brief(message.trim_start_matches("custom: "))
                ),
            )
        }
    })?;
    let tree = Tree::new(&robot, &source)?;
    let root = tree.root(&source)?;
    // A URDF gecaro wrote names its chain: read back without being told.
    let written = written_chain(text).filter(|(base, tip)| {
        ends.base.is_none()
            && ends.tip.is_none()
            && tree.links.contains(base.as_str())
            && tree.links.contains(tip.as_str())
    });
    let ends = match &written {
        Some((base, tip)) => &ChainEnds {
            base: Some(base.clone()),
            tip: Some(tip.clone()),
            name: ends.name.clone(),
        },
        None => ends,
    };
    let base = match ends.base.as_deref() {
        Some(base) if !tree.links.contains(base) => {
            return Err(source.error(
                1,
                format!("no link `{base}` in the file (the base asked for)"),
            ));
        }
        Some(base) => base,
        None => root,
    };
    let tip = tree.tip(base, ends.tip.as_deref(), &source)?;
    if tip == base {
        return Err(source.link_error(tip, "the tip link is the base link: no joint between them"));
    }
    let path_joints = tree.path(base, tip, &source)?;

    let mut world_from_link = IsometryMatrix3::identity();
    let mut world_from_base_link = None;
    let mut chain_joints: Vec<ChainJoint> = Vec::new();
    let mut moving: Vec<&urdf_rs::Joint> = Vec::new();
    let mut child_poses = Vec::new();
    let mut folded = Vec::new();
    // Every link of the chain at q = 0 with the frame it moves with: the
    // base link frame 0, a link after k moving joints frame k.
    let mut placed: Vec<(&str, IsometryMatrix3<f64>, usize)> =
        vec![(base, IsometryMatrix3::identity(), 0)];
    for joint in &path_joints {
        let origin = from_xyz_rpy(joint.origin.xyz.0, joint.origin.rpy.0);
        if !origin.to_homogeneous().iter().all(|v| v.is_finite()) {
            return Err(source.joint_error(
                &joint.name,
                "<origin> holds a value that is not a finite number",
            ));
        }
        let world_from_parent = world_from_link;
        world_from_link = world_from_parent * origin;
        let frame_type = match &joint.joint_type {
            JointType::Fixed => {
                folded.push(joint.name.clone());
                placed.push((joint.child.link.as_str(), world_from_link, moving.len()));
                continue;
            }
            JointType::Revolute | JointType::Continuous => FrameType::Revolute,
            JointType::Prismatic => FrameType::Prismatic,
            other => {
                return Err(source.joint_error(
                    &joint.name,
                    format!(
                        "a {} joint moves in more than one direction: it is not a joint of a \
                         serial robot; choose a base link below it or a tip link above it",
                        format!("{other:?}").to_lowercase()
                    ),
                ));
            }
        };
        let axis = Vector3::from(joint.axis.xyz.0);
        let axis = Unit::try_new(axis, 1e-9)
            .filter(|axis| axis.iter().all(|v| v.is_finite()))
            .ok_or_else(|| {
                source.joint_error(
                    &joint.name,
                    format!(
                        "<axis xyz> = ({} {} {}) has no direction",
                        axis.x, axis.y, axis.z
                    ),
                )
            })?;
        world_from_base_link.get_or_insert(world_from_parent);
        chain_joints.push(ChainJoint {
            frame_type,
            world_from_joint: world_from_link,
            axis,
        });
        child_poses.push(world_from_link);
        moving.push(joint);
        placed.push((joint.child.link.as_str(), world_from_link, moving.len()));
    }
    let n = moving.len();
    if n == 0 {
        return Err(source.link_error(
            tip,
            format!("no revolute, continuous or prismatic joint between `{base}` and `{tip}`"),
        ));
    }
    let chain = AxisChain {
        world_from_base_link: world_from_base_link.unwrap_or_else(IsometryMatrix3::identity),
        joints: chain_joints,
        world_from_tool: world_from_link,
    };
    let frames = chain.khalil_kleinfinger_frames().map_err(|error| {
        let joint = match &error {
            gecaro_core::Error::Invalid {
                field: gecaro_core::Field::Frame { index, .. },
                ..
            } => moving.get(index.saturating_sub(1)).map(|j| j.name.as_str()),
            _ => None,
        };
        match joint {
            Some(joint) => source.joint_error(joint, error.to_string()),
            None => source.error(1, error.to_string()),
        }
    })?;

    // Joint parameters and couplings.
    let mut notes = Vec::new();
    let by_name: HashMap<&str, usize> = moving
        .iter()
        .enumerate()
        .map(|(index, joint)| (joint.name.as_str(), index))
        .collect();
    let mut coupling = DMatrix::<f64>::identity(n, n);
    let mut joints = Vec::with_capacity(n);
    for (index, joint) in moving.iter().enumerate() {
        let (row, offset) = resolve_mimic(index, &moving, &by_name, &source, &mut Vec::new())?;
        if joint.mimic.is_some() {
            coupling.row_mut(index).copy_from_slice(&row);
            notes.push(format!(
                "joint `{}` mimics `{}`: coupling row {} of Cj (eq. 4), offset {offset}; its \
                 column qm{} is the deviation from the mimic relation (0 in use)",
                joint.name,
                joint.mimic.as_ref().map_or("", |m| m.joint.as_str()),
                index + 1,
                index + 1
            ));
        }
        let frame_type = frames[index + 1].frame_type;
        let (qmin, qmax, note) = limits(joint, frame_type);
        notes.extend(note);
        joints.push(Joint {
            qmin,
            qmax,
            offset,
            gain: 1.0,
        });
    }
    if !folded.is_empty() {
        notes.push(format!(
            "{} fixed joint(s) folded into the frames: {}",
            folded.len(),
            shortened(&folded.iter().map(String::as_str).collect::<Vec<_>>())
        ));
    }
    let name = ends.name.clone().unwrap_or_else(|| {
        if robot.name.is_empty() {
            crate::robot_file::fallback_name(path)
        } else {
            robot.name.clone()
        }
    });
    let has_coupling = coupling != DMatrix::identity(n, n);
    let robot_model = Robot::new(RobotSpec {
        name,
        frames: frames.clone(),
        joints,
        motor_coupling: None,
        joint_coupling: has_coupling.then_some(coupling),
        priority: None,
        compliances: None,
    })
    .map_err(|error| source.error(1, error.to_string()))?;

    // Where each link sits on its frame (q = 0).
    let frame_poses = super::frame_poses(&robot_model);
    let masses = chain_masses(&robot, &placed, &frame_poses, &mut notes);
    let finite_or_zero = |value: f64| if value.is_finite() { value } else { 0.0 };
    // The link a joint hangs from when nothing is folded between: the
    // previous joint's link, or the base.
    let chain_parent = |index: usize| {
        index
            .checked_sub(1)
            .map_or(base, |previous| moving[previous].child.link.as_str())
    };
    let names = moving
        .iter()
        .enumerate()
        .map(|(index, joint)| UrdfJointNames {
            name: joint.name.clone(),
            link: joint.child.link.clone(),
            frame_from_link: frame_poses[index + 1].inverse() * child_poses[index],
            effort: finite_or_zero(joint.limit.effort),
            velocity: finite_or_zero(joint.limit.velocity),
            parent: (joint.parent.link != chain_parent(index)).then(|| joint.parent.link.clone()),
        })
        .collect();
    let last = path_joints
        .last()
        .filter(|joint| joint.joint_type == JointType::Fixed);
    let description = format!(
        "imported from {} (URDF `{}`, chain {base} → {tip}: {n} moving joints{})",
        path.file_name().map_or_else(
            || path.display().to_string(),
            |f| f.to_string_lossy().into_owned()
        ),
        robot.name,
        if folded.is_empty() {
            String::new()
        } else {
            format!(", {} fixed folded", folded.len())
        }
    );
    let urdf_robot_name = if robot.name.trim().is_empty() {
        robot_model.name().to_owned()
    } else {
        robot.name.clone()
    };
    Ok(Imported {
        file: RobotFile {
            masses,
            measured_region: None,
            tools: Vec::new(),
            tool_frame_observed: true,
            robot: robot_model,
            description: Some(description),
            angle_unit: AngleUnit::Radians,
            urdf: Some(UrdfNames {
                // A URDF without a robot name gets the robot's (written back, it must have one).
                robot: urdf_robot_name,
                base_link: base.to_owned(),
                world_from_base_link: IsometryMatrix3::identity(),
                joints: names,
                tip_joint: last.map(|joint| joint.name.clone()),
                tip_parent: last
                    .filter(|joint| joint.parent.link != chain_parent(moving.len()))
                    .map(|joint| joint.parent.link.clone()),
                fixed: kept_fixed_links(&robot, base, &moving, tip),
                tip_link: tip.to_owned(),
                tool_from_tip_link: IsometryMatrix3::identity(),
            }),
        },
        notes,
    })
}

/// The chain a URDF written by gecaro names in its header comment
/// (`chain `base_link` → `tool0``; see `super::export`), if it is one.
fn written_chain(text: &str) -> Option<(String, String)> {
    let header = text.get(..text.len().min(2_000))?;
    let comment = header.split("<!-- written by gecaro robot export").nth(1)?;
    let comment = comment.split("-->").next()?;
    let chain = comment.split("chain `").nth(1)?;
    let (base, rest) = chain.split_once("` → `")?;
    let (tip, _) = rest.split_once('`')?;
    Some((base.to_owned(), tip.to_owned()))
}

/// The links fixed to the chain but not on it (a flange between the last
/// joint and the tip, a camera mount, a link folded between two joints),
/// parents first, as the URDF places each on its parent: kept so that an
/// export writes every link back.
fn kept_fixed_links(
    robot: &urdf_rs::Robot,
    base: &str,
    moving: &[&urdf_rs::Joint],
    tip: &str,
) -> Vec<UrdfFixedLink> {
    let mut known: Vec<&str> = std::iter::once(base)
        .chain(moving.iter().map(|joint| joint.child.link.as_str()))
        .chain(std::iter::once(tip))
        .collect();
    let mut kept = Vec::new();
    let mut grown = true;
    while grown {
        grown = false;
        for joint in &robot.joints {
            if joint.joint_type != JointType::Fixed
                || known.contains(&joint.child.link.as_str())
                || !known.contains(&joint.parent.link.as_str())
            {
                continue;
            }
            known.push(joint.child.link.as_str());
            kept.push(UrdfFixedLink {
                joint: joint.name.clone(),
                parent: joint.parent.link.clone(),
                link: joint.child.link.clone(),
                origin: from_xyz_rpy(joint.origin.xyz.0, joint.origin.rpy.0),
            });
            grown = true;
        }
    }
    kept
}

/// The masses of the chain's links from their `<inertial>`: each link's
/// centre of mass moved into the frame it moves with (`placed`: link, its
/// pose at q = 0 in the base link's frame, its frame), the links of one
/// frame (folded fixed joints, and links fixed to a chain link off the
/// path: a camera on the flange) summed with their mass-weighted centre. A
/// note says how many links weigh something and what is left out: links
/// that other joints move (a gripper's fingers) or on another branch.
fn chain_masses(
    robot: &urdf_rs::Robot,
    placed: &[(&str, IsometryMatrix3<f64>, usize)],
    frame_poses: &[IsometryMatrix3<f64>],
    notes: &mut Vec<String>,
) -> MassModel {
    let mut masses = MassModel::new(frame_poses.len());
    let mut sums = vec![(0.0, Vector3::zeros()); frame_poses.len()];
    let mut weighed = 0;
    // Links fixed to a link of the chain move with its frame (a camera on
    // the flange, a tool's mount): placed with it.
    let mut placed: Vec<(&str, IsometryMatrix3<f64>, usize)> = placed.to_vec();
    let mut grown = true;
    while grown {
        grown = false;
        for joint in &robot.joints {
            let known = |name: &str| placed.iter().any(|(link, _, _)| *link == name);
            if joint.joint_type != JointType::Fixed || known(&joint.child.link) {
                continue;
            }
            let Some(&(_, world_from_parent, frame)) = placed
                .iter()
                .find(|(link, _, _)| *link == joint.parent.link)
            else {
                continue;
            };
            let origin = from_xyz_rpy(joint.origin.xyz.0, joint.origin.rpy.0);
            placed.push((joint.child.link.as_str(), world_from_parent * origin, frame));
            grown = true;
        }
    }
    for (name, world_from_link, frame) in &placed {
        let Some(link) = robot.links.iter().find(|link| link.name == *name) else {
            continue;
        };
        let mass = link.inertial.mass.value;
        if !(mass.is_finite() && (0.0..=gecaro_core::MAX_LINK_MASS).contains(&mass)) {
            // Named, not dropped without a word (issue 75).
            notes.push(format!(
                "link `{name}`'s <inertial> mass {mass} is no link's mass (0 to {} kg): left out",
                gecaro_core::MAX_LINK_MASS
            ));
            continue;
        }
        if mass == 0.0 {
            continue;
        }
        let centre =
            world_from_link * nalgebra::Point3::from(Vector3::from(link.inertial.origin.xyz.0));
        let in_frame = frame_poses[*frame].inverse() * centre;
        if !in_frame.coords.iter().all(|v| v.is_finite()) {
            continue;
        }
        weighed += 1;
        sums[*frame].0 += mass;
        sums[*frame].1 += mass * in_frame.coords;
    }
    for (frame, (mass, moment)) in sums.into_iter().enumerate() {
        if mass > 0.0 {
            // A mass and a finite centre: always accepted.
            let _ = masses.set_link(
                frame,
                LinkMass {
                    mass,
                    com: moment / mass,
                },
            );
        }
    }
    if weighed > 0 {
        let total: f64 = robot
            .links
            .iter()
            .map(|link| link.inertial.mass.value)
            .filter(|m| m.is_finite() && *m > 0.0)
            .sum();
        let chain: f64 = (0..frame_poses.len())
            .filter_map(|j| masses.link(j))
            .map(|link| link.mass)
            .sum();
        let off = total - chain;
        notes.push(format!(
            "masses of {weighed} links read from their <inertial> ({} kg on the chain{})",
            gecaro_core::Compact(chain),
            if off > 1e-9 {
                format!(
                    "; {} kg on links off the chain not counted",
                    gecaro_core::Compact(off)
                )
            } else {
                String::new()
            }
        ));
    }
    masses
}
