//! A user frame as a job ([`UserFrameRequest`], issue 74): `gecaro frame
//! --points fixture.csv`, Python `gecaro.user_frame`, the page's
//! `/api/frame`. From a file of measured points
//! ([`gecaro_io::parse_frame_points`]): the three points `origin`, `x` and
//! `xy` ([`frame_from_three`]: exact, no σ), or any number of points with
//! their place in the frame (`frame_x, frame_y, frame_z`: the least-squares
//! registration of [`register_points`], with every point's residual and
//! the frame's σ).

use gecaro_calib::registration::register_points;
use gecaro_calib::tool_point::frame_from_three;
use gecaro_io::FramePoint;
use nalgebra::{IsometryMatrix3, UnitQuaternion, Vector3};
use serde::{Deserialize, Serialize};

use crate::error::AppError;
use crate::files::Files;
use crate::measurements::Unknown;
use crate::sources::{DataFormatSpec, PointsSource};

/// Where a frame's points come from ([`PointsSource`]).
pub type FramePointsSource = PointsSource<FramePoint>;

/// A user frame to make from measured points.
#[derive(Clone, Debug, Deserialize)]
pub struct UserFrameRequest {
    /// The points.
    pub points: FramePointsSource,
    /// Units and column names of the file.
    #[serde(default)]
    pub format: DataFormatSpec,
    #[serde(flatten)]
    unknown: Unknown,
}

/// A user frame: its pose in the points' frame, and how well the points
/// agree (least squares only).
#[derive(Clone, Debug)]
pub struct UserFrame {
    /// The frame's pose in the frame the points were measured in.
    pub pose: IsometryMatrix3<f64>,
    /// The points.
    pub points: Vec<FramePoint>,
    /// Per point, its residual (m), for a least-squares frame.
    pub residuals: Option<Vec<f64>>,
    /// The residuals' σ per coordinate (m), for a least-squares frame.
    pub sigma: Option<f64>,
    /// The σ of the frame's origin and rotation (m, rad; per axis).
    pub precision: Option<(f64, f64)>,
}

/// A user frame as JSON gives it (`gecaro frame --json`).
#[derive(Clone, Debug, Serialize)]
pub struct UserFrameJson {
    /// Its origin in the points' frame (m).
    pub position: [f64; 3],
    /// Its orientation, `[w, x, y, z]`.
    pub quaternion: [f64; 4],
    /// Roll, pitch, yaw about the fixed x, y, z axes (rad; URDF's rpy).
    pub rpy: [f64; 3],
    /// `three points` or `least squares`.
    pub way: &'static str,
    /// Per point: name and residual (m), for a least-squares frame.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub residuals: Vec<(String, f64)>,
    /// The residuals' σ per coordinate (m).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub sigma: Option<f64>,
    /// The σ of the origin (m, per axis).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub origin_sigma: Option<f64>,
    /// The σ of the rotation (rad, per axis).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rotation_sigma: Option<f64>,
}

impl UserFrameRequest {
    /// A frame from `points`.
    pub fn new(points: FramePointsSource) -> Self {
        UserFrameRequest {
            points,
            format: DataFormatSpec::default(),
            unknown: Unknown::default(),
        }
    }

    /// Reads the points and makes the frame.
    ///
    /// # Errors
    /// A file that cannot be read; three points without `origin`, `x` and
    /// `xy`, points too close or in a line.
    pub fn run(&self, files: &dyn Files) -> Result<UserFrame, AppError> {
        self.unknown.check()?;
        let (points, label) = self.read(files)?;
        let refuse = |message: String| AppError::setting("points", format!("{label}: {message}"));
        if points.iter().all(|point| point.frame.is_some()) {
            let reference: Vec<Vector3<f64>> =
                points.iter().filter_map(|point| point.frame).collect();
            let measured: Vec<Vector3<f64>> = points.iter().map(|point| point.measured).collect();
            let fit = register_points(&reference, &measured).map_err(refuse)?;
            return Ok(UserFrame {
                pose: fit.transform,
                residuals: Some(fit.residuals.clone()),
                sigma: Some(fit.sigma),
                precision: Some((fit.origin_sigma, fit.rotation_sigma)),
                points,
            });
        }
        let named = |name: &str| {
            points
                .iter()
                .find(|point| point.name.eq_ignore_ascii_case(name))
                .map(|point| point.measured)
                .ok_or_else(|| {
                    refuse(format!(
                        "no point named `{name}`: a frame from three points names them origin, \
                         x (on the +x axis) and xy (in the xy plane, +y side); or give every \
                         point's place in the frame (frame_x, frame_y, frame_z)"
                    ))
                })
        };
        let pose =
            frame_from_three(&named("origin")?, &named("x")?, &named("xy")?).map_err(refuse)?;
        Ok(UserFrame {
            pose,
            points,
            residuals: None,
            sigma: None,
            precision: None,
        })
    }

    fn read(&self, files: &dyn Files) -> Result<(Vec<FramePoint>, String), AppError> {
        let format = self.format.format()?;
        let points = self
            .points
            .load(files, "a file of a frame's points", |text, path| {
                gecaro_io::parse_frame_points(text, path, &format)
            })?;
        Ok((points, self.points.label()))
    }
}

impl UserFrame {
    /// The JSON document.
    pub fn document(&self) -> UserFrameJson {
        let t = self.pose.translation.vector;
        let q = UnitQuaternion::from_rotation_matrix(&self.pose.rotation);
        let (roll, pitch, yaw) = self.pose.rotation.euler_angles();
        UserFrameJson {
            position: [t.x, t.y, t.z],
            quaternion: [q.w, q.i, q.j, q.k],
            rpy: [roll, pitch, yaw],
            way: if self.residuals.is_some() {
                "least squares"
            } else {
                "three points"
            },
            residuals: self
                .residuals
                .iter()
                .flatten()
                .zip(&self.points)
                .map(|(residual, point)| (point.name.clone(), *residual))
                .collect(),
            sigma: self.sigma,
            origin_sigma: self.precision.map(|(origin, _)| origin),
            rotation_sigma: self.precision.map(|(_, rotation)| rotation),
        }
    }
}
