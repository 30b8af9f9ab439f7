//! The deviation of every measured point from the calibrated robot's — the
//! table an engineer reads first after a calibration (dx, dy, dz, |d| with
//! the data file's line), and the vectors the page draws on the measured
//! points.
//!
//! For the point measures — the position and frame methods, with their
//! named tools and stations — a sample `y` (measured in its station `S`,
//! or the world) and the calibrated robot's tool point `X_p = P(q)·T`
//! (frame n+1's pose `P` in the world, the set's tool `T` as identified)
//! give the deviation in the world `d_W = S·y − X_p`; it is stated in the
//! robot's base frame 0 (`d = R₀ᵀ d_W`, `R₀` the orientation of frame 0 in
//! the calibrated robot's world), so that dx, dy, dz are along the robot's
//! own axes whatever frame the instrument measured in.
//!
//! The measured point is given in the nominal robot's world, the one its
//! table and 3D view are drawn in: the point relative to the calibrated
//! robot's base placed at the nominal base, `N₁·C₁⁻¹·(S·y)` with `C₁`, `N₁`
//! the calibrated and nominal [`base_pose`](gecaro_core::Robot::base_pose)s,
//! [`measurement_frame_in`](gecaro_core::Robot::measurement_frame_in)
//! (a tracker 3 m away draws its points on the robot, not 3 m off).
//!
//! `|d|` is checked against the identification's own error of the same
//! observation: deviations are given only where they are what the fit saw
//! (a rigid robot; an elastic one's sag, a tilted gravity, are in its
//! errors and not in the rigid model used here — none are given then).

use gecaro_calib::identification::{Identification, locate_observations};
use gecaro_calib::study::{DataColumn, Study};
use gecaro_core::{Robot, forward_kinematics, frame_transform};
use nalgebra::{IsometryMatrix3, Point3, Vector3};
use serde::Serialize;

/// The largest difference between a deviation's length and the fit's
/// error of the same observation (metres) for the deviations to be given.
const AGREEMENT: f64 = 1e-9;

/// One measured point's deviation (JSON: `deviations` of an identification).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct PointDeviation {
    /// Its measurement set (from 1).
    pub set: usize,
    /// The set's label (its data file).
    pub file: String,
    /// Its configuration's number in the set (from 1).
    pub observation: usize,
    /// Its observation's index among the identification's (from 0, across
    /// the sets: the residuals' and the errors' order).
    #[serde(skip)]
    pub index: usize,
    /// The data file's line of the sample, when known.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub line: Option<usize>,
    /// The measured point in the nominal robot's world (m).
    pub point: [f64; 3],
    /// Measured minus the calibrated robot's point, along the robot's base
    /// frame 0 axes (m).
    pub deviation: [f64; 3],
    /// Its length with the nominal robot (m): the fit's error before.
    pub before: f64,
}

/// The deviation of every point measured by a point-measure set of
/// `study`, identified as `result` from `nominal`; `None` when the study
/// has no point measures or the deviations would not be what the fit saw
/// (an elastic robot, a tilted gravity).
pub fn point_deviations(
    nominal: &Robot,
    study: &Study,
    result: &Identification,
) -> Option<Vec<PointDeviation>> {
    let calibrated = &result.calibrated;
    if calibrated.is_elastic() {
        return None;
    }
    let frames = if result.frames.len() == study.frames.len() {
        &result.frames
    } else {
        &study.frames
    };
    let base_rotation = frame_transform(&calibrated.frames()[0], 0.0).rotation;
    let view = calibrated.measurement_frame_in(nominal);
    let mut deviations = Vec::new();
    for (index, located) in locate_observations(study).iter().enumerate() {
        // The sets whose samples are measured points (position, frame).
        let set = &study.sets[located.set];
        if !set.method.data_columns().contains(&DataColumn::Position) {
            continue;
        }
        let &[sample] = located.samples.as_slice() else {
            return None;
        };
        let sample = set.samples.get(sample);
        let measured = sample.position()?;
        let station = set
            .station
            .map_or_else(IsometryMatrix3::identity, |k| frames[k].pose);
        let tool = set
            .tool
            .map_or_else(IsometryMatrix3::identity, |k| frames[k].pose);
        let chain = forward_kinematics(calibrated, sample.motor_positions()).ok()?;
        let predicted = (chain.world_from_tool() * tool).translation.vector;
        let world = station * Point3::from(measured);
        let difference: Vector3<f64> = world.coords - predicted;
        let after = result.errors_after.get(index)?.0;
        if (difference.norm() - after).abs() > AGREEMENT.max(1e-9 * after) {
            return None;
        }
        let deviation = base_rotation.inverse() * difference;
        let point = view * world;
        deviations.push(PointDeviation {
            set: located.set + 1,
            file: located.label.clone(),
            observation: located.observation + 1,
            index,
            line: located.lines.first().copied(),
            point: [point.x, point.y, point.z],
            deviation: [deviation.x, deviation.y, deviation.z],
            before: result.errors_before.get(index)?.0,
        });
    }
    (!deviations.is_empty()).then_some(deviations)
}

#[cfg(test)]
mod tests {
    use super::point_deviations;
    use gecaro_calib::Quiet;
    use gecaro_calib::identification::{IdentificationOptions, identify};
    use gecaro_calib::methods::{MethodOptions, method};
    use gecaro_calib::simulation::{Sampler, perturbed_robot, simulate_measurements};
    use gecaro_calib::study::Study;
    use gecaro_core::forward_kinematics;

    /// Simulated truth: a Stanford arm with level-1 errors measured at 40
    /// points with 10 µm noise; each deviation is the measured point minus
    /// the calibrated robot's tool point, taken along frame 0's axes from
    /// the frame chain (another route than the module's), and is at the
    /// noise.
    #[test]
    fn each_point_deviates_from_the_calibrated_robot_by_the_noise() {
        let nominal = gecaro_io::load_robot("stanford").expect("robot").robot;
        let real = perturbed_robot(&nominal, 1.0, &mut Sampler::new(3)).expect("real");
        let position = method("position", &MethodOptions::default()).expect("method");
        let samples = simulate_measurements(
            &real,
            position.as_ref(),
            40,
            1e-5,
            &mut Sampler::new(5),
            &mut Quiet,
        )
        .expect("data");
        let study = Study::single(position, samples, "sim.csv");
        let result = identify(
            &nominal,
            &study,
            &IdentificationOptions::default(),
            &mut Quiet,
        )
        .expect("identified");
        let deviations = point_deviations(&nominal, &study, &result).expect("points");
        assert_eq!(deviations.len(), 40);
        let set = &study.sets[0];
        let mut squares = 0.0;
        for (k, point) in deviations.iter().enumerate() {
            let sample = set.samples.get(k);
            let chain =
                forward_kinematics(&result.calibrated, sample.motor_positions()).expect("fk");
            let world =
                sample.position().expect("point") - chain.world_from_tool().translation.vector;
            let along_base = chain.poses()[0].rotation.inverse() * world;
            for axis in 0..3 {
                assert!(
                    (point.deviation[axis] - along_base[axis]).abs() < 1e-12,
                    "{point:?}"
                );
            }
            assert_eq!((point.set, point.observation, point.index), (1, k + 1, k));
            assert!((point.before - result.errors_before.get(k).expect("before").0).abs() < 1e-15);
            squares += along_base.norm_squared();
        }
        let rms = (squares / 40.0).sqrt();
        assert!(
            rms < 3e-5 && rms > 5e-6,
            "RMS deviation {rms} m at 10 µm of noise per axis"
        );
    }
}
