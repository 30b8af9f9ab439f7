//! What a robot keeps of the URDF it was imported from: the names of its
//! chain and where each link's frame sits on the Khalil–Kleinfinger frames.
//! With them, `gecaro robot export --to urdf` writes a calibrated robot back
//! with the original link and joint names and link frames, so that it can
//! replace the original chain in a ROS description.
//!
//! In a robot file it is the `[urdf]` table:
//!
//! ```toml
//! [urdf]
//! robot = "kuka_kr16_2"
//! base_link = "base_link"
//! tip_link = "tool0"
//! tip_joint = "joint_a6-tool0"      # the fixed joint that carries the tip link
//! # base_link_frame = [x, y, z, qw, qx, qy, qz]   # the base link in the world frame (default: it is the world)
//! # tip_link_frame = [...]                        # the tip link in frame n+1 (default: it is frame n+1)
//!
//! [[urdf.joint]]                    # joints 1..n
//! name = "joint_a1"
//! link = "link_1"                   # its child link
//! link_frame = [0.0, 0.0, 0.675, 1.0, 0.0, 0.0, 0.0]  # that link's frame in frame j
//! effort = 0.0
//! velocity = 2.72271363311
//! # parent = "link_1_mount"         # its parent link, when not the previous joint's link
//!
//! [[urdf.fixed]]                    # every link fixed to the chain but not on it
//! joint = "joint_a6-flange"         # (a flange, a camera mount), kept for the export
//! parent = "link_6"
//! link = "flange"
//! origin = [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0]        # the link in its parent, as the URDF had it
//! ```
//!
//! `tip_parent` names the tip joint's parent link when it is such a link
//! (`flange`, with `tool0` fixed below it). An export writes every kept
//! link where the URDF had it on its parent, and the chain's links where
//! the robot's (calibrated) frames put them.

use gecaro_core::Robot;
use nalgebra::IsometryMatrix3;
use serde::{Deserialize, Serialize};

use crate::pose::{pose_from_seven, to_seven};
use crate::problem::{DocumentError, Location};

/// The names and link frames kept from an imported URDF (see the module docs).
#[derive(Clone, Debug, PartialEq)]
pub struct UrdfNames {
    /// `<robot name>`.
    pub robot: String,
    /// The link whose frame is the world frame −1 (unless reframed).
    pub base_link: String,
    /// The base link's frame in the world frame −1: identity, unless the
    /// robot was re-expressed in another world frame.
    pub world_from_base_link: IsometryMatrix3<f64>,
    /// Joints 1..n.
    pub joints: Vec<UrdfJointNames>,
    /// The fixed joint whose child is the tip link, if the URDF had one.
    pub tip_joint: Option<String>,
    /// The link whose frame is frame n+1 (unless reframed).
    pub tip_link: String,
    /// The tip link's frame in frame n+1: identity, unless the tool frame
    /// was re-expressed.
    pub tool_from_tip_link: IsometryMatrix3<f64>,
    /// The tip joint's parent link, when it is a kept fixed link (a
    /// flange) rather than the last joint's link.
    pub tip_parent: Option<String>,
    /// The links fixed to the chain but not on it, parents first.
    pub fixed: Vec<UrdfFixedLink>,
}

/// A link fixed to the chain but not on it (see the module docs).
#[derive(Clone, Debug, PartialEq)]
pub struct UrdfFixedLink {
    /// The fixed `<joint name>` that carries it.
    pub joint: String,
    /// Its parent link: a link of the chain or another kept link.
    pub parent: String,
    /// The link.
    pub link: String,
    /// The link's frame in its parent's, as the URDF had it.
    pub origin: IsometryMatrix3<f64>,
}

impl UrdfNames {
    /// The same names for `reframed`, the robot `original` re-expressed by
    /// [`Robot::reframed`] with the same two transforms: every link keeps
    /// its place in the world, so the base link moves in the new world frame,
    /// the tip link in the new tool frame, and the links of the rewritten
    /// frames 1 and n on those frames.
    pub fn reframed(
        &self,
        original: &Robot,
        reframed: &Robot,
        new_world_from_old_world: &IsometryMatrix3<f64>,
        old_tool_from_new_tool: &IsometryMatrix3<f64>,
    ) -> UrdfNames {
        let old_frames = super::frame_poses(original);
        let new_frames = super::frame_poses(reframed);
        UrdfNames {
            world_from_base_link: new_world_from_old_world * self.world_from_base_link,
            tool_from_tip_link: old_tool_from_new_tool.inverse() * self.tool_from_tip_link,
            joints: self
                .joints
                .iter()
                .enumerate()
                .map(|(index, joint)| UrdfJointNames {
                    frame_from_link: new_frames[index + 1].inverse()
                        * new_world_from_old_world
                        * old_frames[index + 1]
                        * joint.frame_from_link,
                    ..joint.clone()
                })
                .collect(),
            ..self.clone()
        }
    }
}

/// One joint of [`UrdfNames`].
#[derive(Clone, Debug, PartialEq)]
pub struct UrdfJointNames {
    /// `<joint name>`.
    pub name: String,
    /// Its child link.
    pub link: String,
    /// That link's frame in the Khalil–Kleinfinger frame j (constant).
    pub frame_from_link: IsometryMatrix3<f64>,
    /// `<limit effort>` (kept for the export; not used by gecaro).
    pub effort: f64,
    /// `<limit velocity>` (kept for the export; not used by gecaro).
    pub velocity: f64,
    /// Its parent link, when it is a kept fixed link rather than the
    /// previous joint's link (or the base link).
    pub parent: Option<String>,
}

/// The `[urdf]` table as written.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
#[allow(missing_docs)]
pub struct UrdfDocument {
    pub robot: String,
    pub base_link: String,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub base_link_frame: Option<Vec<f64>>,
    pub tip_link: String,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tip_joint: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tip_link_frame: Option<Vec<f64>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tip_parent: Option<String>,
    #[serde(default)]
    pub joint: Vec<UrdfJointDocument>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub fixed: Vec<UrdfFixedDocument>,
}

/// One `[[urdf.fixed]]` table.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
#[allow(missing_docs)]
pub struct UrdfFixedDocument {
    pub joint: String,
    pub parent: String,
    pub link: String,
    pub origin: Vec<f64>,
}

/// One `[[urdf.joint]]` table.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
#[allow(missing_docs)]
pub struct UrdfJointDocument {
    pub name: String,
    pub link: String,
    pub link_frame: Vec<f64>,
    #[serde(default)]
    pub effort: f64,
    #[serde(default)]
    pub velocity: f64,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub parent: Option<String>,
}

fn optional_frame(pose: &IsometryMatrix3<f64>) -> Option<Vec<f64>> {
    (*pose != IsometryMatrix3::identity()).then(|| to_seven(pose).to_vec())
}

impl UrdfDocument {
    /// The document of kept names.
    pub fn from_names(names: &UrdfNames) -> Self {
        UrdfDocument {
            robot: names.robot.clone(),
            base_link: names.base_link.clone(),
            base_link_frame: optional_frame(&names.world_from_base_link),
            tip_link: names.tip_link.clone(),
            tip_joint: names.tip_joint.clone(),
            tip_link_frame: optional_frame(&names.tool_from_tip_link),
            joint: names
                .joints
                .iter()
                .map(|joint| UrdfJointDocument {
                    name: joint.name.clone(),
                    link: joint.link.clone(),
                    link_frame: to_seven(&joint.frame_from_link).to_vec(),
                    effort: joint.effort,
                    velocity: joint.velocity,
                    parent: joint.parent.clone(),
                })
                .collect(),
            tip_parent: names.tip_parent.clone(),
            fixed: names
                .fixed
                .iter()
                .map(|fixed| UrdfFixedDocument {
                    joint: fixed.joint.clone(),
                    parent: fixed.parent.clone(),
                    link: fixed.link.clone(),
                    origin: to_seven(&fixed.origin).to_vec(),
                })
                .collect(),
        }
    }

    /// The kept names, checked against a robot of `joint_count` joints.
    ///
    /// # Errors
    /// A joint count that does not match, an empty or repeated name, or a
    /// frame that is not seven numbers of a pose.
    pub fn read(&self, joint_count: usize) -> Result<UrdfNames, DocumentError> {
        let at =
            |message: String| DocumentError::new(Location::Key { key: "urdf".into() }, message);
        if self.joint.len() != joint_count {
            return Err(at(format!(
                "names {} joints ([[urdf.joint]]) for a robot of {joint_count}",
                self.joint.len()
            )));
        }
        let frame = |values: &Option<Vec<f64>>, key: &str| {
            values
                .as_deref()
                .map_or(Ok(IsometryMatrix3::identity()), |values| {
                    pose_from_seven(values).map_err(|message| at(format!("{key} {message}")))
                })
        };
        let mut seen = std::collections::HashSet::new();
        let mut joints = Vec::with_capacity(self.joint.len());
        for (index, joint) in self.joint.iter().enumerate() {
            if joint.name.is_empty() || joint.link.is_empty() {
                return Err(at(format!("joint {} has an empty name or link", index + 1)));
            }
            if !seen.insert(joint.name.as_str()) {
                return Err(at(format!("joint name `{}` appears twice", joint.name)));
            }
            joints.push(UrdfJointNames {
                name: joint.name.clone(),
                link: joint.link.clone(),
                frame_from_link: pose_from_seven(&joint.link_frame)
                    .map_err(|message| at(format!("joint {} link_frame {message}", index + 1)))?,
                effort: joint.effort,
                velocity: joint.velocity,
                parent: joint.parent.clone(),
            });
        }
        if self.robot.is_empty() || self.base_link.is_empty() || self.tip_link.is_empty() {
            return Err(at("robot, base_link and tip_link must not be empty".into()));
        }
        // Every kept link hangs from a link named before it: the export
        // places it from its parent.
        let mut links: Vec<&str> = std::iter::once(self.base_link.as_str())
            .chain(self.joint.iter().map(|joint| joint.link.as_str()))
            .chain(std::iter::once(self.tip_link.as_str()))
            .collect();
        let mut fixed = Vec::with_capacity(self.fixed.len());
        for (index, kept) in self.fixed.iter().enumerate() {
            if kept.joint.is_empty() || kept.link.is_empty() || kept.parent.is_empty() {
                return Err(at(format!("fixed link {} has an empty name", index + 1)));
            }
            if !links.contains(&kept.parent.as_str()) {
                return Err(at(format!(
                    "fixed link `{}` hangs from `{}`, which is no link named before it",
                    kept.link, kept.parent
                )));
            }
            if links.contains(&kept.link.as_str()) {
                return Err(at(format!("link `{}` appears twice", kept.link)));
            }
            links.push(&kept.link);
            fixed.push(UrdfFixedLink {
                joint: kept.joint.clone(),
                parent: kept.parent.clone(),
                link: kept.link.clone(),
                origin: pose_from_seven(&kept.origin).map_err(|message| {
                    at(format!("fixed link `{}` origin {message}", kept.link))
                })?,
            });
        }
        for parent in joints
            .iter()
            .filter_map(|joint| joint.parent.as_deref())
            .chain(self.tip_parent.as_deref())
        {
            if !fixed.iter().any(|kept| kept.link == parent) {
                return Err(at(format!(
                    "parent link `{parent}` is not a kept fixed link ([[urdf.fixed]])"
                )));
            }
        }
        Ok(UrdfNames {
            robot: self.robot.clone(),
            base_link: self.base_link.clone(),
            world_from_base_link: frame(&self.base_link_frame, "base_link_frame")?,
            joints,
            tip_joint: self.tip_joint.clone(),
            tip_link: self.tip_link.clone(),
            tool_from_tip_link: frame(&self.tip_link_frame, "tip_link_frame")?,
            tip_parent: self.tip_parent.clone(),
            fixed,
        })
    }
}
