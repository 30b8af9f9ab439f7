//! The measured points' size against the robot's, before any fitting: a
//! length unit mistaken for another (millimetres read as metres, metres as
//! millimetres) is named as such, instead of a fit that "diverges" at a
//! million millimetres or calibrates a robot a thousandth of its size.
//!
//! A rotation and a translation keep a point cloud's spread, so the spread of
//! a set's measured points — their RMS distance from their centre — can be
//! held against the nominal model's at the same configurations whatever
//! frame the instrument measured in (a tracker 4 m away, a station turned
//! 130°). Two bounds, each far from any honest data:
//!
//! - **Too large.** A point `P_i = O_i + R_i p` on the last link, with `|p|`
//!   up to [`TOOL_ALLOWANCE`] from the frame n+1 origin `O_i`, spreads at
//!   most `|p|` more than the `O_i` do (the RMS of `R_i p` about its mean is
//!   at most `|p|`). Measured points that spread more than
//!   [`MODEL_ALLOWANCE`] × the nominal's spread + [`TOOL_ALLOWANCE`] are no
//!   point of this robot.
//! - **Too small.** Points that stay within [`STILL`] of their centre while
//!   the last joint's frame spreads over [`SHRINK`] × as much (at least
//!   [`MOVED`]) did not move with the robot.
//!
//! Each set is judged apart (each may be measured in its own frame), on at
//! most [`MAXIMUM_POINTS`] of its points, evenly spread over the data.

use gecaro_core::{ChainBuffer, KinematicModel, Robot};
use nalgebra::Vector3;

use super::subsample::spread_points;
use super::words::significant;
use crate::Error;
use crate::study::{MeasurementSet, Study};

/// The farthest a measured point may sit from the frame n+1 origin (a tool
/// or reflector the robot file leaves out), metres.
const TOOL_ALLOWANCE: f64 = 1.0;
/// How much larger than the nominal's the real robot may make the spread.
const MODEL_ALLOWANCE: f64 = 1.1;
/// Measured points spread less than this (metres)…
const STILL: f64 = 5e-3;
/// …while the last joint's frame spreads over this many times as much…
const SHRINK: f64 = 100.0;
/// …and at least this much (metres) did not move with the robot.
const MOVED: f64 = 0.05;
/// Points of a set judged at most.
const MAXIMUM_POINTS: usize = 500;
/// Points needed to judge a set's spread.
const MINIMUM_POINTS: usize = 4;

/// Refuses a set whose measured points cannot be this robot's in the
/// data's stated length unit (see the module docs).
///
/// # Errors
/// [`Error::InvalidData`] naming the set, both spreads and the likely
/// mistake; a configuration that does not fit the robot.
pub(super) fn check_data_scale(robot: &Robot, study: &Study) -> Result<(), Error> {
    for set in &study.sets {
        check_set(robot, set)?;
    }
    Ok(())
}

fn check_set(robot: &Robot, set: &MeasurementSet) -> Result<(), Error> {
    let n = robot.joint_count();
    let picked = spread_points(&[set.samples.as_slice()], MAXIMUM_POINTS);
    if picked.len() < MINIMUM_POINTS {
        return Ok(());
    }
    let mut measured = Vec::new();
    let mut terminal = Vec::new();
    let mut wrist = Vec::new();
    let model = KinematicModel::new(robot);
    let mut chain = ChainBuffer::default();
    for (motors, point) in picked {
        model.forward(motors, &mut chain)?;
        measured.push(point);
        terminal.push(chain.world_from_tool().translation.vector);
        wrist.push(chain.world_from_frame(n).translation.vector);
    }
    let (measured, terminal, wrist) = (spread(&measured), spread(&terminal), spread(&wrist));
    let bound = MODEL_ALLOWANCE * terminal + TOOL_ALLOWANCE;
    let too_large = measured > bound;
    let too_small = measured < STILL && wrist >= MOVED && measured * SHRINK < wrist;
    if !(too_large || too_small) {
        return Ok(());
    }
    // The ratio to the terminal point's spread is the unit's factor.
    let ratio = measured / terminal.max(f64::MIN_POSITIVE);
    Err(Error::InvalidData {
        line: None,
        message: format!(
            "{}: the measured points spread over {} m (RMS about their centre) where the \
             robot's terminal point, at the same configurations, spreads over {terminal:.3} m \
             ({}× as much). {} State the data's length unit.",
            set.label,
            significant(measured),
            significant(ratio),
            likely_mistake(ratio)
        ),
    })
}

/// The RMS distance of `points` from their centre.
fn spread(points: &[Vector3<f64>]) -> f64 {
    let centre = points.iter().sum::<Vector3<f64>>() / points.len() as f64;
    (points
        .iter()
        .map(|point| (point - centre).norm_squared())
        .sum::<f64>()
        / points.len() as f64)
        .sqrt()
}

/// What a ratio of measured to nominal spread most likely means.
fn likely_mistake(ratio: f64) -> &'static str {
    match ratio {
        r if (300.0..3000.0).contains(&r) => "Millimetres read as metres?",
        r if (50.0..200.0).contains(&r) => "Centimetres read as metres?",
        r if (15.0..50.0).contains(&r) => "Inches read as metres?",
        r if (3e-4..3e-3).contains(&r) => "Metres read as millimetres?",
        r if r > 1.0 => "These are no points of this robot: another robot's data, or another unit?",
        _ => "The points did not move with the robot: another robot's data, or another unit?",
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Quiet;
    use crate::methods::{MethodOptions, method};
    use crate::simulation::{Sampler, perturbed_robot, simulate_measurements};

    /// Simulated position data of the Stanford arm (errors at level 1), its
    /// points multiplied by `factor` as a unit mistake would, and moved as
    /// far as a tracker 4 m away would.
    fn scaled(factor: f64) -> (Robot, Study) {
        let nominal = gecaro_io::load_robot("stanford").expect("ready").robot;
        let position = method("position", &MethodOptions::default()).expect("method");
        let mut sampler = Sampler::new(3);
        let real = perturbed_robot(&nominal, 1.0, &mut sampler).expect("real");
        let mut samples =
            simulate_measurements(&real, position.as_ref(), 40, 1e-5, &mut sampler, &mut Quiet)
                .expect("data");
        for sample in &mut samples {
            let point = sample.position.as_mut().expect("position");
            *point = *point * factor + Vector3::new(4.0, -1.0, 0.5);
        }
        (nominal, Study::single(position, samples, "gen.csv"))
    }

    #[test]
    fn honest_points_pass_wherever_the_instrument_stood() {
        let (robot, study) = scaled(1.0);
        check_data_scale(&robot, &study).expect("honest data");
        // A unit mistake's factor short of the bounds passes too: 1.5× is a
        // wrong robot file, for the verdict and the plausibility check.
        let (robot, study) = scaled(1.5);
        check_data_scale(&robot, &study).expect("not a unit's factor");
    }

    #[test]
    fn millimetres_read_as_metres_are_named_before_fitting() {
        let (robot, study) = scaled(1000.0);
        let error = check_data_scale(&robot, &study)
            .expect_err("1000×")
            .to_string();
        assert!(error.contains("gen.csv"), "{error}");
        assert!(error.contains("Millimetres read as metres?"), "{error}");
        assert!(error.contains("State the data's length unit."), "{error}");
        let (robot, study) = scaled(100.0);
        let error = check_data_scale(&robot, &study)
            .expect_err("100×")
            .to_string();
        assert!(error.contains("Centimetres read as metres?"), "{error}");
    }

    /// Through [`identify`](crate::identification::identify): the check's
    /// error is the one returned, not the fit's, from this thread and
    /// within a split's part alike. (Run beside the fit's start, the checks
    /// gained 0.1 ms at 5,000 rows and let a doomed fit run to its first
    /// report: a refusal 0.5 ms later at 5,000 rows, 15 ms at 10⁵.)
    #[test]
    fn an_identification_returns_the_check_s_error() {
        let (robot, study) = scaled(1000.0);
        let identified = || {
            crate::identification::identify(
                &robot,
                &study,
                &crate::identification::IdentificationOptions::default(),
                &mut Quiet,
            )
            .expect_err("1000×")
            .to_string()
        };
        let error = identified();
        assert!(error.contains("Millimetres read as metres?"), "{error}");
        for error in crate::parallel::run_parts((0..4).collect(), |_: usize| identified()) {
            assert!(error.contains("Millimetres read as metres?"), "{error}");
        }
    }

    #[test]
    fn metres_read_as_millimetres_are_named_before_fitting() {
        let (robot, study) = scaled(1e-3);
        let error = check_data_scale(&robot, &study)
            .expect_err("1/1000")
            .to_string();
        assert!(error.contains("Metres read as millimetres?"), "{error}");
    }

    #[test]
    fn a_set_that_only_turns_the_wrist_is_not_taken_for_a_unit_mistake() {
        // Joints 1–3 still: the wrist centre does not move, a reflector
        // 20 cm out on the flange sweeps its sphere. Neither bound applies.
        let (robot, mut study) = scaled(1.0);
        let set = &mut study.sets[0];
        let mut rows = set.samples.to_rows();
        for sample in &mut rows {
            sample.motor_positions[..3].copy_from_slice(&[0.3, -0.4, 0.5]);
            let flange = gecaro_core::terminal_pose(&robot, &sample.motor_positions).expect("pose");
            sample.position = Some(flange * nalgebra::Point3::new(0.0, 0.2, 0.1)).map(|p| p.coords);
        }
        set.samples = rows.into();
        check_data_scale(&robot, &study).expect("wrist-only data are not a unit mistake");
    }
}
