//! The Denavit–Hartenberg table as gecaro reads and writes it: its
//! convention, its rows in SI units, and the TOML documents of rows and
//! transforms shared by the reader and the writer.

use gecaro_core::{Frame, FrameType, frame_transform};
use nalgebra::{IsometryMatrix3, Vector3};
use serde::{Deserialize, Serialize};

use crate::pose::from_xyz_rpy;
use crate::robot_file::AngleUnit;
use crate::units::LengthUnit;

/// Which Denavit–Hartenberg convention a table uses.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum DhConvention {
    /// Standard: `Rz(θ)·Tz(d)·Tx(a)·Rx(α)` per row.
    Standard,
    /// Craig's modified: `Rx(α)·Tx(a)·Rz(θ)·Tz(d)` per row.
    Modified,
}

impl DhConvention {
    pub(super) fn name(self) -> &'static str {
        match self {
            DhConvention::Standard => "dh",
            DhConvention::Modified => "mdh",
        }
    }

    pub(super) fn from_name(name: &str) -> Option<Self> {
        match name {
            "dh" | "standard" => Some(DhConvention::Standard),
            "mdh" | "modified" | "craig" => Some(DhConvention::Modified),
            _ => None,
        }
    }

    /// The transform of one row at q = 0 (SI units).
    pub(super) fn step(self, row: &Step) -> IsometryMatrix3<f64> {
        match self {
            DhConvention::Standard => {
                IsometryMatrix3::rotation(Vector3::z() * row.theta)
                    * IsometryMatrix3::translation(row.a, 0.0, row.d)
                    * IsometryMatrix3::rotation(Vector3::x() * row.alpha)
            }
            DhConvention::Modified => frame_transform(
                &Frame {
                    alpha: row.alpha,
                    d: row.a,
                    theta: row.theta,
                    r: row.d,
                    ..Frame::new(FrameType::Fixed)
                },
                0.0,
            ),
        }
    }
}

/// Units for table columns that do not state theirs.
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq)]
pub struct TableUnits {
    /// Angles (default radians).
    pub angle: Option<AngleUnit>,
    /// Lengths (default metres).
    pub length: Option<LengthUnit>,
}

/// One row in SI units.
#[derive(Copy, Clone, Debug, Default, PartialEq)]
pub(super) struct Step {
    pub(super) a: f64,
    pub(super) alpha: f64,
    pub(super) d: f64,
    pub(super) theta: f64,
}

#[derive(Clone, Debug)]
pub(super) struct Row {
    pub(super) frame_type: FrameType,
    pub(super) step: Step,
    pub(super) limits: (Option<f64>, Option<f64>),
}

/// A table read from TOML or CSV, in SI units.
pub(super) struct Table {
    pub(super) name: Option<String>,
    pub(super) description: Option<String>,
    pub(super) convention: Option<DhConvention>,
    pub(super) world_from_base: Option<IsometryMatrix3<f64>>,
    pub(super) last_from_tool: Option<IsometryMatrix3<f64>>,
    pub(super) rows: Vec<Row>,
}

#[derive(Clone, Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(super) struct TransformDocument {
    #[serde(default)]
    pub(super) xyz: [f64; 3],
    #[serde(default)]
    pub(super) rpy: [f64; 3],
}

#[derive(Clone, Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RowDocument {
    #[serde(rename = "type")]
    pub(super) joint_type: String,
    #[serde(default)]
    pub(super) a: f64,
    #[serde(default)]
    pub(super) alpha: f64,
    #[serde(default)]
    pub(super) d: f64,
    #[serde(default)]
    pub(super) theta: f64,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(super) qmin: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(super) qmax: Option<f64>,
    /// The joint's name, as the CSV form's `name` column: kept for the
    /// reader, not used by the model.
    #[serde(default, alias = "joint", skip_serializing_if = "Option::is_none")]
    pub(super) name: Option<String>,
}

pub(super) struct Units {
    pub(super) angle: f64,
    pub(super) length: f64,
}

impl Units {
    pub(super) fn step(&self, a: f64, alpha: f64, d: f64, theta: f64) -> Step {
        Step {
            a: a * self.length,
            alpha: alpha * self.angle,
            d: d * self.length,
            theta: theta * self.angle,
        }
    }

    pub(super) fn transform(&self, transform: &TransformDocument) -> IsometryMatrix3<f64> {
        let xyz = transform.xyz.map(|v| v * self.length);
        let rpy = transform.rpy.map(|v| v * self.angle);
        from_xyz_rpy(xyz, rpy)
    }

    pub(super) fn joint(&self, frame_type: FrameType) -> f64 {
        match frame_type {
            FrameType::Prismatic => self.length,
            _ => self.angle,
        }
    }
}

pub(super) fn joint_type(text: &str) -> Option<FrameType> {
    match text.trim().to_ascii_lowercase().as_str() {
        "r" | "revolute" => Some(FrameType::Revolute),
        "p" | "prismatic" => Some(FrameType::Prismatic),
        _ => None,
    }
}
