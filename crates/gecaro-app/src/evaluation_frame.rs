//! The measurement frame of an evaluation (issue 74): data measured from
//! another tracker position are off by the tracker's pose, not by the
//! robot's geometry. `evaluate --register` registers that frame in closed
//! form — the rigid fit of the robot's predicted points onto the measured
//! ones ([`rigid_fit`]) — on a stated share of the rows (spread evenly over
//! the file), and judges the robot on the others; on every row when the
//! share is all of them, said so (the errors then exclude any frame error
//! by construction). Without it, errors far beyond what any geometry errs
//! by are named as a frame mismatch ([`frame_mismatch`]).

use gecaro_calib::registration::rigid_fit;
use gecaro_calib::study::{DataColumn, Samples, Study};
use gecaro_core::{Robot, terminal_pose};
use nalgebra::{IsometryMatrix3, Point3};

use crate::error::AppError;
use crate::measurements::Note;

/// Errors of an evaluation beyond which they are not the robot's geometry
/// (m): 50 mm, where a calibration's errors are tenths of millimetres and
/// a nominal model's a few millimetres.
const FRAME_MISMATCH: f64 = 0.05;

/// The share of the rows a frame is registered on, as a user states it:
/// `all`, or a percentage (`30%`) of them.
#[derive(Copy, Clone, Debug, PartialEq)]
pub enum RegisterShare {
    /// Every row: the frame registered and the errors judged on them all.
    All,
    /// A fraction in (0, 1): registered on these rows, judged on the rest.
    Fraction(f64),
}

impl RegisterShare {
    /// `all` or `N%` (0 < N < 100).
    ///
    /// # Errors
    /// Another text, naming the setting.
    pub fn parse(text: &str) -> Result<Self, AppError> {
        let text = text.trim();
        if text == "all" {
            return Ok(RegisterShare::All);
        }
        let percent = text
            .strip_suffix('%')
            .and_then(|number| number.trim().parse::<f64>().ok())
            .filter(|percent| *percent > 0.0 && *percent < 100.0)
            .ok_or_else(|| {
                AppError::setting(
                    "register",
                    format!(
                        "`{text}` is not a share of the rows: `all`, or a percentage such as 30%"
                    ),
                )
            })?;
        Ok(RegisterShare::Fraction(percent / 100.0))
    }
}

/// `robot` in the measurement frame of `study`'s one position set,
/// registered on `share` of its rows; the study keeps the rows the robot
/// is judged on. A note says where the frame stands and on which rows.
///
/// # Errors
/// A study that is not one set of points measured (position or frame
/// method), or fewer than 3 rows to register on.
pub(crate) fn register(
    robot: &Robot,
    study: &mut Study,
    share: RegisterShare,
) -> Result<(Robot, Note), AppError> {
    let [set] = study.sets.as_mut_slice() else {
        return Err(AppError::setting(
            "register",
            "the measurement frame is registered on one data file of a position or frame method",
        ));
    };
    if !set.method.data_columns().contains(&DataColumn::Position) || set.tool.is_some() {
        return Err(AppError::setting(
            "register",
            format!(
                "the {} method's data are not points of frame n+1: the measurement frame is \
                 registered on position or frame data",
                set.method.name()
            ),
        ));
    }
    let rows = set.samples.len();
    let registering: Vec<bool> = match share {
        RegisterShare::All => vec![true; rows],
        RegisterShare::Fraction(fraction) => {
            let count = ((fraction * rows as f64).round() as usize).clamp(1, rows);
            let mut chosen = vec![false; rows];
            for k in 0..count {
                chosen[k * rows / count] = true;
            }
            chosen
        }
    };
    let (mut predicted, mut measured) = (Vec::new(), Vec::new());
    for (sample, chosen) in set.samples.iter().zip(&registering) {
        if let (true, Some(position)) = (*chosen, sample.position()) {
            predicted.push(
                (terminal_pose(robot, sample.motor_positions())
                    .map_err(gecaro_calib::Error::from)?
                    * Point3::origin())
                .coords,
            );
            measured.push(position);
        }
    }
    if predicted.len() < 3 {
        return Err(AppError::setting(
            "register",
            format!(
                "{} row(s) to register the measurement frame on: give at least 3 (a larger share)",
                predicted.len()
            ),
        ));
    }
    let frame = rigid_fit(&predicted, &measured);
    let registered = robot.reframed(&frame, &IsometryMatrix3::identity())?;
    let judged = match share {
        RegisterShare::All => rows,
        RegisterShare::Fraction(_) => {
            let kept: Samples = set
                .samples
                .iter()
                .zip(&registering)
                .filter(|(_, chosen)| !**chosen)
                .map(|(sample, _)| sample.to_sample())
                .collect();
            set.samples = kept;
            set.samples.len()
        }
    };
    if judged == 0 {
        return Err(AppError::setting(
            "register",
            "no row is left to judge the robot on: give a smaller share",
        ));
    }
    let t = frame.translation.vector;
    let (roll, pitch, yaw) = frame.rotation.euler_angles();
    let rows_said = match share {
        RegisterShare::All => format!(
            "on all {rows} rows, and judged on them: the errors below exclude any frame error"
        ),
        RegisterShare::Fraction(_) => format!(
            "on {} of the {rows} rows (spread over the file); the errors below are on the other \
             {judged}",
            predicted.len()
        ),
    };
    let note = Note::plain(format!(
        "registered the measurement frame in closed form {rows_said}: the robot's world stands \
         at x {:.3} y {:.3} z {:.3} mm, rpy {:.4} {:.4} {:.4}° in it",
        t.x * 1e3,
        t.y * 1e3,
        t.z * 1e3,
        roll.to_degrees(),
        pitch.to_degrees(),
        yaw.to_degrees()
    ));
    Ok((registered, note))
}

/// A warning when the errors of position data (RMS `rms`, m) are beyond
/// what any robot's geometry errs by ([`FRAME_MISMATCH`]): the data are
/// measured in another frame than the robot's world.
pub(crate) fn frame_mismatch(rms: f64, reach: f64) -> Option<Note> {
    (rms > FRAME_MISMATCH.max(0.1 * reach)).then(|| {
        Note::warning(format!(
            "errors of RMS {:.1} mm are no robot's geometry (a calibration errs by tenths of a \
             millimetre, a nominal model by millimetres, on a robot reaching {:.2} m): the data \
             look measured in another frame than the robot's world — another tracker position; \
             register it (evaluate --register 30%) or state the station",
            rms * 1e3,
            reach
        ))
    })
}

/// The largest distance of the robot's frame n+1 from its world origin
/// over `study`'s configurations (m), its reach as the data see it.
pub(crate) fn reach(robot: &Robot, study: &Study) -> f64 {
    study
        .sets
        .iter()
        .flat_map(|set| set.samples.iter())
        .filter_map(|sample| terminal_pose(robot, sample.motor_positions()).ok())
        .map(|pose| (pose * Point3::origin()).coords.norm())
        .fold(0.0, f64::max)
}
