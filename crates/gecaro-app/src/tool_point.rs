//! A tool point taught by pivoting as a job ([`ToolPointRequest`], issue
//! 74): `gecaro tcp ROBOT --data pivot.csv`, Python `gecaro.tool_point`,
//! the page's `/api/tcp`. The joint values of N ≥ 4 orientations with the
//! tool's tip on one fixed point, the poses of frame n+1 from the robot's
//! model (the calibrated one gives the tip in its calibrated frame n+1),
//! and the least squares of [`gecaro_calib::tool_point::pivot`].

use gecaro_calib::tool_point::{PivotFit, pivot};
use nalgebra::IsometryMatrix3;
use serde::{Deserialize, Serialize};

use crate::error::AppError;
use crate::files::Files;
use crate::measurements::Unknown;
use crate::sources::{DataFormatSpec, DataSource, RobotSource};

/// An orientation spread (rad) below which the tip's precision suffers:
/// 10° (tilts of about ±15° about two axes). Below it the result is given
/// with a warning.
pub const SMALL_SPREAD: f64 = 10.0 * std::f64::consts::PI / 180.0;

/// Joint values of a pivot, for a robot.
#[derive(Clone, Debug, Deserialize)]
pub struct ToolPointRequest {
    /// The robot (nominal or calibrated).
    pub robot: RobotSource,
    /// The configurations: `qm1..qmn`, one per orientation.
    pub data: DataSource,
    /// Units and column names of the file.
    #[serde(default)]
    pub format: DataFormatSpec,
    #[serde(flatten)]
    unknown: Unknown,
}

/// A taught tool point and what it rests on.
#[derive(Clone, Debug)]
pub struct TaughtToolPoint {
    /// The fit.
    pub fit: PivotFit,
    /// The data as messages name them.
    pub label: String,
    /// The robot's name.
    pub robot: String,
}

/// A taught tool point as JSON gives it (`gecaro tcp --json`).
#[derive(Clone, Debug, Serialize)]
pub struct ToolPointJson {
    /// The tip in frame n+1 (tool0), m.
    pub tool: [f64; 3],
    /// The fixed point in the robot's world frame, m.
    pub fixed_point: [f64; 3],
    /// Orientations used.
    pub orientations: usize,
    /// Per orientation, `‖R t + p − P‖` (m).
    pub residuals: Vec<f64>,
    /// Their RMS (m).
    pub rms: f64,
    /// The largest (m).
    pub max: f64,
    /// The residuals' σ per coordinate, 3N − 6 degrees of freedom (m).
    pub sigma: f64,
    /// The σ of the tip's coordinates (m, per axis).
    pub tool_sigma: f64,
    /// The σ of the fixed point's coordinates (m, per axis).
    pub fixed_sigma: f64,
    /// The orientations' spread: the smallest RMS turn about any axis (rad).
    pub spread: f64,
    /// What a user should know: a small spread.
    pub warnings: Vec<String>,
}

impl ToolPointRequest {
    /// A pivot of `robot` from `data`.
    pub fn new(robot: RobotSource, data: DataSource) -> Self {
        ToolPointRequest {
            robot,
            data,
            format: DataFormatSpec::default(),
            unknown: Unknown::default(),
        }
    }

    /// Reads the configurations and teaches the tool point.
    ///
    /// # Errors
    /// Files that cannot be read, configurations that do not fit the robot,
    /// fewer than 4 orientations or orientations about one axis only.
    pub fn run(&self, files: &dyn Files) -> Result<TaughtToolPoint, AppError> {
        self.unknown.check()?;
        let file = self.robot.load(files)?;
        let robot = &file.robot;
        let read = self.data.read(
            files,
            &gecaro_io::joint_types(robot),
            &[],
            &self.format.format()?,
        )?;
        let poses = read
            .samples
            .iter()
            .map(|sample| gecaro_core::terminal_pose(robot, sample.motor_positions()))
            .collect::<Result<Vec<IsometryMatrix3<f64>>, _>>()?;
        let fit = pivot(&poses)
            .map_err(|message| AppError::setting("data", format!("{}: {message}", read.label)))?;
        Ok(TaughtToolPoint {
            fit,
            label: read.label,
            robot: robot.name().to_owned(),
        })
    }
}

impl TaughtToolPoint {
    /// The warnings: a spread below [`SMALL_SPREAD`].
    pub fn warnings(&self) -> Vec<String> {
        let mut warnings = Vec::new();
        if self.fit.spread < SMALL_SPREAD {
            warnings.push(format!(
                "the orientations of {} spread over only {:.1}° in their least-turned \
                 direction: the tip is known to {:.4} mm per axis; tilt the tool by 20–40° \
                 about two axes for a better one",
                self.label,
                self.fit.spread.to_degrees(),
                self.fit.tool_sigma * 1e3
            ));
        }
        warnings
    }

    /// The JSON document.
    pub fn document(&self) -> ToolPointJson {
        let fit = &self.fit;
        let residuals = fit.residuals.clone();
        let rms = (residuals.iter().map(|r| r * r).sum::<f64>() / residuals.len() as f64).sqrt();
        ToolPointJson {
            tool: fit.tool.into(),
            fixed_point: fit.fixed.into(),
            orientations: residuals.len(),
            max: residuals.iter().copied().fold(0.0, f64::max),
            rms,
            residuals,
            sigma: fit.sigma,
            tool_sigma: fit.tool_sigma,
            fixed_sigma: fit.fixed_sigma,
            spread: fit.spread,
            warnings: self.warnings(),
        }
    }
}
