//! The robot files a job writes: the calibrated robot of an identification
//! and the simulated real robot of a points generation, each described by how
//! it was obtained, in the nominal file's angle unit and with its URDF names.

use gecaro_calib::identification::Identification;
use gecaro_calib::study::Study;
use gecaro_core::Robot;
use gecaro_io::RobotFile;

/// The calibrated robot as a robot file: the identified robot, named
/// "<name> (calibrated)", with a description of how it was obtained from the
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
    RobotFile {
        description: Some(format!(
            "{} calibrated by gecaro: {} method on {data}, {} parameters identified, residual RMS {:.3e} → {:.3e}",
            nominal.robot.name(),
            study.method_names(),
            result.parameters.len(),
            result.rms_before(),
            result.rms_after()
        )),
        angle_unit: nominal.angle_unit,
        urdf: nominal.urdf.clone(),
        // The masses are the nominal's (a geometric calibration does not weigh
        // the links), moved into the calibrated robot's world.
        masses: carried_masses(nominal, &robot),
        robot,
    }
}

/// The nominal's masses on `calibrated`, which may stand in another world
/// (a tracker's, where the closed-form start registered it): each link's
/// centre moved into its calibrated frame and gravity into that world, the
/// worlds related by frame 1 (joint 1's axis) at zero. A nominal that states
/// no masses and the default gravity carries nothing to move.
pub(crate) fn carried_masses(nominal: &RobotFile, calibrated: &Robot) -> gecaro_core::MassModel {
    let masses = &nominal.masses;
    if masses.is_empty() && masses.gravity() == gecaro_core::upright_gravity() {
        return masses.clone();
    }
    let zero = vec![0.0; calibrated.joint_count()];
    let frame_one = |robot: &Robot| {
        gecaro_core::forward_kinematics(robot, &zero).map(|chain| *chain.world_from_frame(1))
    };
    match (frame_one(&nominal.robot), frame_one(calibrated)) {
        (Ok(before), Ok(after)) => masses
            .reframed(&nominal.robot, calibrated, &(after * before.inverse()))
            .unwrap_or_else(|_| masses.clone()),
        _ => masses.clone(),
    }
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
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{IsometryMatrix3, Vector3};

    /// A calibrated robot in a tracker's world (3 m away, turned, tilted)
    /// carries the nominal's masses there: every joint holds the same load.
    #[test]
    fn masses_follow_the_calibrated_robot_into_the_tracker_s_world() {
        let nominal = gecaro_io::load_robot("industrial6").expect("ready");
        assert!(!nominal.masses.is_empty());
        let tracker_from_base =
            IsometryMatrix3::new(Vector3::new(3.0, -1.2, 0.4), Vector3::new(0.02, -0.01, 2.1));
        let calibrated = nominal
            .robot
            .reframed(&tracker_from_base, &IsometryMatrix3::identity())
            .expect("reframed");
        let carried = carried_masses(&nominal, &calibrated);
        assert!(
            (carried.gravity() - tracker_from_base.rotation * nominal.masses.gravity()).norm()
                < 1e-12
        );
        for qm in [
            [0.3, -0.7, 0.4, 1.1, -0.5, 2.0],
            [-1.0, -1.2, 0.9, -0.3, 1.4, -1.0],
        ] {
            let before = gecaro_core::gravity_torques(&nominal.robot, &nominal.masses, None, &qm)
                .expect("τ");
            let after = gecaro_core::gravity_torques(&calibrated, &carried, None, &qm).expect("τ");
            assert!(
                (&before - &after).norm() < 1e-9 * before.norm(),
                "{before} vs {after}"
            );
        }
        // Nothing stated: nothing carried, no gravity line written.
        let stanford = gecaro_io::load_robot("stanford").expect("ready");
        let moved = stanford
            .robot
            .reframed(&tracker_from_base, &IsometryMatrix3::identity())
            .expect("reframed");
        assert_eq!(carried_masses(&stanford, &moved), stanford.masses);
    }
}
