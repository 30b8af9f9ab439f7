//! The inverse geometric model as the front ends ask for it (`gecaro ik`,
//! Python's `Robot.ik`): from a start configuration when one is given,
//! else from the middle of the joint ranges and then seeded random starts
//! ([`gecaro_calib::simulation::solve_from_starts`]); a target none of them
//! reaches is named with what was tried and the setting that chooses
//! another start, in each front end's words.

use gecaro_calib::simulation::{DEFAULT_SEED, RANDOM_STARTS, solve_from_starts};
use gecaro_core::{InverseOptions, InverseSolution, Robot, Target, inverse_kinematics};

use crate::error::{AppError, ErrorKind, Part};

/// Motor values that put frame n+1 of `robot` at `target` (see the module
/// docs).
///
/// ```
/// use gecaro_core::{InverseOptions, Target};
/// use nalgebra::Vector3;
///
/// let robot = gecaro_io::load_robot("stanford")?.robot;
/// let target = Target::Position(Vector3::new(0.3, 0.2, 0.6));
/// let solution = gecaro_app::inverse_model(&robot, &target, None, &InverseOptions::default())?;
/// let reached = gecaro_core::terminal_pose(&robot, &solution.motor_positions)?;
/// assert!((reached.translation.vector - Vector3::new(0.3, 0.2, 0.6)).norm() < 1e-9);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
///
/// # Errors
/// [`ErrorKind::NotConverged`] for a target not reached, a start that does
/// not fit the robot ([`ErrorKind::Input`]).
pub fn inverse_model(
    robot: &Robot,
    target: &Target,
    start: Option<&[f64]>,
    options: &InverseOptions,
) -> Result<InverseSolution, AppError> {
    match start {
        Some(start) => Ok(inverse_kinematics(robot, target, start, options)?),
        None => {
            solve_from_starts(robot, target, options, DEFAULT_SEED).map_err(|error| match error {
                error @ gecaro_core::Error::Unreachable { .. } => AppError::new(
                    ErrorKind::NotConverged,
                    vec![
                        format!(
                            "{error} (tried the middle of the joint ranges and {RANDOM_STARTS} \
                             random starts; "
                        )
                        .into(),
                        Part::Setting("start".into()),
                        " chooses another)".into(),
                    ],
                ),
                other => other.into(),
            })
        }
    }
}
