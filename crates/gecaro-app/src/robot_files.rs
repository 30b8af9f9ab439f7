//! The robot files a job writes: the calibrated robot of an identification
//! and the simulated real robot of a points generation, each described by how
//! it was obtained, in the nominal file's angle unit and with its URDF names.

use gecaro_calib::frames::FrameRole;
use gecaro_calib::identification::Identification;
use gecaro_calib::study::Study;
use gecaro_core::{LinkMass, MassModel, Robot};
use gecaro_io::{IdentifiedTool, RobotFile};
use nalgebra::Point3;

/// The calibrated robot as a robot file: the identified robot, named
/// "`<name> (calibrated)`", with a description of how it was obtained from the
/// data labelled `data`.
pub fn calibrated_robot_file(
    nominal: &RobotFile,
    study: &Study,
    result: &Identification,
    data: &str,
) -> RobotFile {
    let mut robot = result.calibrated.clone();
    robot.set_name(format!("{} (calibrated)", nominal.robot.name()));
    // A file states its angles within a turn (and is read back).
    robot.wrap_angles();
    // A result that holds in the measured region only keeps that region:
    // compensation and evaluation flag poses outside it.
    let region = result
        .verdict
        .region
        .as_ref()
        .filter(|region| !region.holds_everywhere);
    let holds = region.map_or_else(String::new, |region| {
        format!(
            "; holds within the measured joint ranges (predicted {:.4} mm there, {:.4} mm over {})",
            region.inside * 1e3,
            region.work_rms * 1e3,
            region.work_words()
        )
    });
    RobotFile {
        description: Some(format!(
            "{} calibrated by gecaro: {} method on {data}, {} parameters identified, residual RMS {:.3e} → {:.3e}{holds}",
            nominal.robot.name(),
            study.method_names(),
            result.parameters.len(),
            result.rms_before(),
            result.rms_after()
        )),
        measured_region: region.map(|region| region.measured.clone()),
        // The study's tools as identified, for `compensate --tool NAME`; a
        // study whose every set names a tool keeps frame n+1 nominal.
        tools: result
            .frames
            .iter()
            .filter(|frame| frame.role == FrameRole::Tool)
            .map(|frame| IdentifiedTool {
                name: frame.name.clone(),
                pose: frame.pose,
            })
            .collect(),
        tool_frame_observed: study.sets.iter().any(|set| set.tool.is_none()),
        angle_unit: nominal.angle_unit,
        urdf: nominal.urdf.clone(),
        // The masses are the nominal's (a calibration does not weigh the
        // links): each centre in its link's frame, and gravity as stated in
        // the measurement frame, which is the calibrated robot's world
        // (docs/elastic.md). A tilt the calibration finds at frame 1 is the
        // robot's, not gravity's; gravity's own tilts (`elastic-gravity`)
        // are folded into the gravity the file states. The base's centre
        // rides with the base (`calibrated_masses`).
        masses: calibrated_masses(nominal, &robot),
        robot,
    }
    .with_gravity_tilt_folded()
}

/// The nominal's masses for `calibrated`: each link's centre in its own
/// frame as stated, but the base's (frame 0), which no joint carries and
/// whose frame a calibration in a measurement frame (a tracker's) puts by
/// the instrument (issue 74: a 60 kg base at the tracker in the exported
/// URDF). Its centre keeps where it sits against frame 1 at q1 = 0 (joint
/// 1's axis), so that it rides with the robot's base.
fn calibrated_masses(nominal: &RobotFile, calibrated: &Robot) -> MassModel {
    let mut masses = nominal.masses.clone();
    let Some(base) = nominal.masses.link(0) else {
        return masses;
    };
    let frame_1 = |robot: &Robot| gecaro_core::frame_transform(&robot.frames()[1], 0.0);
    let against_axis_1 = frame_1(&nominal.robot).inverse() * Point3::from(base.com);
    let moved = LinkMass {
        com: (frame_1(calibrated) * against_axis_1).coords,
        ..*base
    };
    // Both robots are valid, so the centre is finite and the frame there.
    if masses.set_link(0, moved).is_err() {
        return nominal.masses.clone();
    }
    masses
}

/// The simulated real robot of a points generation as a robot file: `real`,
/// described as drawn from `nominal` at `error_level` with `seed`.
pub fn simulated_robot_file(
    nominal: &RobotFile,
    real: Robot,
    error_level: f64,
    seed: u64,
) -> RobotFile {
    RobotFile {
        description: Some(format!(
            "simulated real robot: {} at error level {error_level}, seed {seed}",
            nominal.robot.name()
        )),
        robot: real,
        angle_unit: nominal.angle_unit,
        urdf: nominal.urdf.clone(),
        masses: nominal.masses.clone(),
        measured_region: None,
        tools: Vec::new(),
        tool_frame_observed: true,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use gecaro_calib::identification::IdentificationOptions;

    /// A calibrated robot keeps the nominal's masses and gravity as stated:
    /// the measurement frame's, whatever tilt the calibration finds; the
    /// base's centre moves with the base.
    #[test]
    fn a_calibrated_robot_keeps_the_stated_masses_and_gravity() {
        let mut nominal = gecaro_io::load_robot("industrial6").expect("ready");
        nominal
            .masses
            .set_gravity(nalgebra::Vector3::new(0.1, 0.0, -9.8))
            .expect("gravity");
        let mut real = nominal.robot.clone();
        let alpha1 = gecaro_core::ParameterId::new(gecaro_core::ParameterKind::Alpha, 1);
        real.set_parameter(alpha1, 0.02).expect("tilted");
        let mut sampler = gecaro_calib::simulation::Sampler::new(3);
        let method =
            gecaro_calib::methods::method("position", &Default::default()).expect("method");
        let samples = gecaro_calib::simulation::simulate_measurements(
            &real,
            method.as_ref(),
            60,
            0.0,
            &mut sampler,
            &mut gecaro_calib::Quiet,
        )
        .expect("data");
        let study = Study::single(method, samples, "tilted");
        let result = gecaro_calib::identification::identify(
            &nominal.robot,
            &study,
            &IdentificationOptions::default(),
            &mut gecaro_calib::Quiet,
        )
        .expect("identified");
        let calibrated = calibrated_robot_file(&nominal, &study, &result, "tilted");
        assert!((calibrated.robot.parameter(alpha1) - 0.02).abs() < 1e-6);
        assert_eq!(calibrated.masses.gravity(), nominal.masses.gravity());
        for frame in 1..nominal.robot.frames().len() {
            assert_eq!(calibrated.masses.link(frame), nominal.masses.link(frame));
        }
        // The base's centre rides with the base: where it sits against
        // frame 1 (joint 1's axis, tilted here by α1) at q1 = 0.
        let against_axis_1 = |file: &RobotFile| {
            let base = file.masses.link(0).expect("a base mass");
            let frame_1 = gecaro_core::frame_transform(&file.robot.frames()[1], 0.0);
            (
                base.mass,
                (frame_1.inverse() * Point3::from(base.com)).coords,
            )
        };
        let (mass, offset) = against_axis_1(&calibrated);
        let (nominal_mass, nominal_offset) = against_axis_1(&nominal);
        assert_eq!(mass, nominal_mass);
        assert!(
            (offset - nominal_offset).norm() < 1e-12,
            "{offset} vs {nominal_offset}"
        );
    }
}
