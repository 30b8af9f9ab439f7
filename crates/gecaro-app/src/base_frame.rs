//! The customer's base frame (issue 74): a calibrated robot, identified in
//! its instrument's frame, re-expressed in the base its owner uses — the
//! mounting plate, the dowel holes of a drawing — registered by points
//! measured in the instrument's frame beside their place in that base
//! ([`gecaro_io::parse_base_points`]).
//!
//! Why not the nominal's base: `robot rebase` without points defines the
//! base by the robot file's convention (frame 0 from joint 1's axis, x
//! towards axis 2, at the calibrated joint 1's zero). A tracker cannot see
//! where the owner's base is against that axis: the plate of the trial of
//! issue 74 sat 2.44 mm from it, and every job taught in the plate's frame
//! missed by that much.
//!
//! The registration is the closed-form rigid fit of the base points onto
//! the measured ones ([`register_points`]): `T` (the base's pose in the
//! measurement frame) with each point's residual, the residuals' σ with
//! 3N − 6 degrees of freedom, and the σ of the base's origin and rotation
//! from `s² (JᵀJ)⁻¹`. The robot is then re-expressed with `T⁻¹` as the new
//! world from the old ([`Robot::reframed`](gecaro_core::Robot::reframed)),
//! its masses moved with their links and gravity into the base frame.

use gecaro_calib::registration::{PointRegistration, register_points};
use gecaro_io::{BasePoint, RobotFile};
use nalgebra::{IsometryMatrix3, UnitQuaternion, Vector3};
use serde::Serialize;

use crate::error::AppError;
use crate::files::Files;
use crate::sources::{DataFormatSpec, PointsSource};

/// Where base points come from ([`PointsSource`]).
pub type BasePointsSource = PointsSource<BasePoint>;

/// The base points of `source`, read in `format`.
///
/// # Errors
/// A file that cannot be read or is not a base-points file.
pub(crate) fn load_base_points(
    source: &BasePointsSource,
    files: &dyn Files,
    format: &DataFormatSpec,
) -> Result<Vec<BasePoint>, AppError> {
    let format = format.format()?;
    source.load(files, "a base-points file", |text, path| {
        gecaro_io::parse_base_points(text, path, &format)
    })
}

/// What a base was registered by.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum BaseBy {
    /// Points measured beside their place in the base (a drawing's).
    Points,
    /// The circles of joints 1 and 2 turned alone
    /// ([`gecaro_calib::axis_circles`]).
    Circles,
}

/// A point a base was registered by: its name and line.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct RegisteredPoint {
    /// Its name (`line N` where the file names none; `joint 1` or `joint
    /// 2` and the line for a circle's point).
    pub name: String,
    /// Its line in the file.
    pub line: usize,
}

/// A base registered by points or circles: where it stands in the
/// measurement frame and how well the points agree.
#[derive(Clone, Debug)]
pub struct BaseRegistration {
    /// What it was registered by.
    pub by: BaseBy,
    /// The points, in the order of the fit's residuals.
    pub points: Vec<RegisteredPoint>,
    /// The fit: the base's pose in the measurement frame, each point's
    /// residual (its distance from its circle, for circles), σ.
    pub fit: PointRegistration,
    /// For circles: each circle's radius (m), joint 1's first.
    pub radii: Vec<f64>,
}

/// One point of a registration, as JSON gives it.
#[derive(Clone, Debug, Serialize)]
pub struct BasePointJson {
    /// Its name.
    pub name: String,
    /// Its line in the file.
    pub line: usize,
    /// `‖T base − measured‖` (m).
    pub residual: f64,
}

/// A base registration as JSON gives it (`robot rebase --base-points
/// --json`, the page, Python).
#[derive(Clone, Debug, Serialize)]
pub struct BaseRegistrationJson {
    /// What it was registered by: `points` or `circles`.
    pub by: BaseBy,
    /// For circles: each circle's radius (m), joint 1's first.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub radii: Vec<f64>,
    /// The base's origin in the measurement frame (m).
    pub position: [f64; 3],
    /// The base's orientation in the measurement frame, `[w, x, y, z]`.
    pub quaternion: [f64; 4],
    /// Every point's residual.
    pub points: Vec<BasePointJson>,
    /// The residuals' RMS (m).
    pub rms: f64,
    /// The largest residual (m).
    pub max: f64,
    /// The residuals' σ per coordinate, 3N − 6 degrees of freedom (m).
    pub sigma: f64,
    /// The σ of the base's origin, per axis (m).
    pub origin_sigma: f64,
    /// The σ of the base's rotation, per axis (rad).
    pub rotation_sigma: f64,
    /// The RMS error the registration adds at 1 m from the base's origin
    /// (m; [`BaseRegistration::error_at`]).
    pub at_one_metre: f64,
}

impl BaseRegistration {
    /// Registers the base of `points` (see the module docs).
    ///
    /// # Errors
    /// Fewer than 3 points, or points on one line.
    pub fn new(points: Vec<BasePoint>, label: &str) -> Result<Self, AppError> {
        let base: Vec<Vector3<f64>> = points.iter().map(|point| point.base).collect();
        let measured: Vec<Vector3<f64>> = points.iter().map(|point| point.measured).collect();
        let fit = register_points(&base, &measured)
            .map_err(|message| AppError::setting("base_points", format!("{label}: {message}")))?;
        Ok(BaseRegistration {
            by: BaseBy::Points,
            points: points
                .into_iter()
                .map(|point| RegisteredPoint {
                    name: point.name,
                    line: point.line,
                })
                .collect(),
            fit,
            radii: Vec::new(),
        })
    }

    /// The base's pose in the measurement frame.
    pub fn base_in_measurement_frame(&self) -> IsometryMatrix3<f64> {
        self.fit.transform
    }

    /// The worst point: its name and residual (m).
    pub fn worst(&self) -> (&str, f64) {
        self.points
            .iter()
            .zip(&self.fit.residuals)
            .max_by(|a, b| a.1.total_cmp(b.1))
            .map_or(("", 0.0), |(point, residual)| {
                (point.name.as_str(), *residual)
            })
    }

    /// The RMS 3-D error (m) the registration adds at a point `distance`
    /// from the base's origin: `√(3σ_t² + 2σ_r²d²)` with the per-axis σ of
    /// the origin and the rotation (a rotation error moves a point across
    /// two axes).
    pub fn error_at(&self, distance: f64) -> f64 {
        let (origin, rotation) = (self.fit.origin_sigma, self.fit.rotation_sigma);
        (3.0 * origin * origin + 2.0 * (rotation * distance).powi(2)).sqrt()
    }

    /// The residuals' RMS (m).
    pub fn rms(&self) -> f64 {
        let residuals = &self.fit.residuals;
        (residuals.iter().map(|r| r * r).sum::<f64>() / residuals.len() as f64).sqrt()
    }

    /// One sentence: how many points, their RMS and worst residual, the
    /// precision of the base.
    pub fn summary(&self) -> String {
        let (worst, largest) = self.worst();
        let what = match self.by {
            BaseBy::Points => format!("{} base points: residual", self.points.len()),
            BaseBy::Circles => format!(
                "the circles of joints 1 and 2 ({} points, radii {} m): distance from the \
                 circles",
                self.points.len(),
                self.radii
                    .iter()
                    .map(|radius| significant(*radius))
                    .collect::<Vec<_>>()
                    .join(" and ")
            ),
        };
        format!(
            "{what} RMS {} mm, max {} mm ({worst}); the base's origin to {} mm and its rotation \
             to {} mrad (1σ per axis): about {} mm added at 1 m from its origin",
            significant(self.rms() * 1e3),
            significant(largest * 1e3),
            significant(self.fit.origin_sigma * 1e3),
            significant(self.fit.rotation_sigma * 1e3),
            significant(self.error_at(1.0) * 1e3)
        )
    }

    /// The JSON document.
    pub fn document(&self) -> BaseRegistrationJson {
        let pose = self.fit.transform;
        let t = pose.translation.vector;
        let q = UnitQuaternion::from_rotation_matrix(&pose.rotation);
        BaseRegistrationJson {
            by: self.by,
            radii: self.radii.clone(),
            position: [t.x, t.y, t.z],
            quaternion: [q.w, q.i, q.j, q.k],
            points: self
                .points
                .iter()
                .zip(&self.fit.residuals)
                .map(|(point, residual)| BasePointJson {
                    name: point.name.clone(),
                    line: point.line,
                    residual: *residual,
                })
                .collect(),
            rms: self.rms(),
            max: self.worst().1,
            sigma: self.fit.sigma,
            origin_sigma: self.fit.origin_sigma,
            rotation_sigma: self.fit.rotation_sigma,
            at_one_metre: self.error_at(1.0),
        }
    }

    /// `calibrated` (in the measurement frame) re-expressed in the base
    /// frame: the robot file, described as such.
    ///
    /// # Errors
    /// A robot that cannot be re-framed (never for a valid robot).
    pub fn rebased(&self, calibrated: &RobotFile) -> Result<RobotFile, AppError> {
        // Gravity's tilts folded first: they turn with the frame
        // ([`crate::rebased_file`]).
        let calibrated = &calibrated.clone().with_gravity_tilt_folded();
        let base_from_measurement = self.fit.transform.inverse();
        let robot = calibrated
            .robot
            .reframed(&base_from_measurement, &IsometryMatrix3::identity())?;
        let masses =
            calibrated
                .masses
                .reframed(&calibrated.robot, &robot, &base_from_measurement)?;
        let note = format!("re-expressed in the base of {}", self.summary());
        Ok(RobotFile {
            description: Some(match &calibrated.description {
                Some(text) => format!("{text}; {note}"),
                None => note,
            }),
            robot,
            masses,
            ..calibrated.clone()
        })
    }
}

/// `value` with three significant digits (`0.00256`, `12.8`).
fn significant(value: f64) -> String {
    if value == 0.0 || !value.is_finite() {
        return format!("{value}");
    }
    let digits = (2 - value.abs().log10().floor() as i32).max(0);
    format!("{value:.*}", digits as usize)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A robot seen from a tracker 3 m away: the base registered by four
    /// exact plate points gives the robot back in its own frame.
    #[test]
    fn exact_points_give_the_robot_back() {
        let file = gecaro_io::load_robot("industrial6").expect("ready");
        let tracker = IsometryMatrix3::from_parts(
            nalgebra::Translation3::new(3.0, -0.4, 0.2),
            nalgebra::Rotation3::from_euler_angles(0.004, -0.006, 2.4),
        );
        let seen = RobotFile {
            robot: file
                .robot
                .reframed(&tracker.inverse(), &IsometryMatrix3::identity())
                .expect("seen"),
            ..file.clone()
        };
        let points: Vec<BasePoint> = [(0.3, 0.3), (-0.3, 0.3), (-0.3, -0.3), (0.3, -0.3)]
            .iter()
            .enumerate()
            .map(|(i, (x, y))| {
                let base = Vector3::new(*x, *y, 0.0);
                BasePoint {
                    name: format!("H{}", i + 1),
                    measured: (tracker.inverse() * nalgebra::Point3::from(base)).coords,
                    base,
                    line: i + 2,
                }
            })
            .collect();
        let registration = BaseRegistration::new(points, "plate.csv").expect("registered");
        assert!(registration.rms() < 1e-12);
        let back = registration.rebased(&seen).expect("rebased");
        let qm = [0.3, -0.5, 0.8, 1.1, -0.4, 2.0];
        let (a, b) = (
            gecaro_core::terminal_pose(&back.robot, &qm).expect("pose"),
            gecaro_core::terminal_pose(&file.robot, &qm).expect("pose"),
        );
        assert!((a.to_homogeneous() - b.to_homogeneous()).norm() < 1e-9);
        let message = BaseRegistration::new(Vec::new(), "plate.csv")
            .expect_err("no points")
            .to_string();
        assert!(message.contains("plate.csv: 0 point(s)"), "{message}");
    }
}
