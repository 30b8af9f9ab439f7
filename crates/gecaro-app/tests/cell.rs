//! Points generation and planning in a cell: only configurations the cell
//! can measure (above the floor, seen by the tracker) are drawn.

use gecaro_app::{CellSpec, GenerateRequest, LocalFiles, MethodSpec, PlanRequest, RobotSource};
use gecaro_calib::Quiet;
use gecaro_core::forward_kinematics;

fn generate(robot: &str, method: &str, cell: CellSpec) -> gecaro_app::Generated {
    let mut request = GenerateRequest::new(
        RobotSource::Named(robot.into()),
        MethodSpec::named(method),
        200,
    );
    request.cell = cell;
    request.noise = 1e-5;
    request
        .run(&LocalFiles, &mut gecaro_calib::Quiet)
        .expect("generated")
}

/// The lowest origin of frames 1..=n+1 of the real robot over the samples.
fn lowest(generated: &gecaro_app::Generated) -> f64 {
    generated
        .samples
        .iter()
        .flat_map(|sample| {
            let chain =
                forward_kinematics(&generated.real.robot, sample.motor_positions()).expect("fk");
            chain
                .poses()
                .iter()
                .skip(1)
                .map(|pose| pose.translation.vector.z)
                .collect::<Vec<_>>()
        })
        .fold(f64::INFINITY, f64::min)
}

#[test]
fn a_floor_keeps_every_joint_and_the_tool_above_it() {
    for robot in ["ur10e", "puma560", "panda"] {
        let free = generate(robot, "position", CellSpec::default());
        assert!(
            lowest(&free) < 0.0,
            "{robot}: some free poses go below the base"
        );
        let floored = generate(
            robot,
            "position",
            CellSpec {
                floor: Some(0.0),
                ..CellSpec::default()
            },
        );
        assert_eq!(floored.samples.len(), 200);
        assert!(lowest(&floored) >= -1e-9, "{robot}: {}", lowest(&floored));
    }
}

#[test]
fn a_station_sees_every_reflector_within_its_cone() {
    let station = nalgebra::Vector3::new(2.3, 0.0, 0.4);
    let generated = generate(
        "ur10e",
        "frame",
        CellSpec {
            floor: Some(0.0),
            station: Some([2.3, 0.0, 0.4]),
            max_incidence: Some("30deg".into()),
            clearance: None,
        },
    );
    for sample in &generated.samples {
        let chain =
            forward_kinematics(&generated.real.robot, sample.motor_positions()).expect("fk");
        let tool = chain.world_from_tool();
        let to_station = (station - tool.translation.vector).normalize();
        let axis = tool.rotation * nalgebra::Vector3::z();
        assert!(axis.dot(&to_station).acos().to_degrees() <= 30.0 + 1e-9);
    }
    // A cell that leaves nothing: refused with the reason.
    let mut request = GenerateRequest::new(
        RobotSource::Named("ur10e".into()),
        MethodSpec::named("position"),
        10,
    );
    request.cell.floor = Some(5.0);
    let error = request
        .run(&LocalFiles, &mut gecaro_calib::Quiet)
        .expect_err("nothing above 5 m");
    assert!(
        error.to_string().contains("leaves next to nothing"),
        "{error}"
    );
}

#[test]
fn plans_draw_their_pool_in_the_cell() {
    let mut request = PlanRequest::new(
        RobotSource::Named("ur10e".into()),
        MethodSpec::named("position"),
        20,
    );
    request.cell.floor = Some(0.0);
    let planning = request.run(&LocalFiles, &mut Quiet).expect("planned");
    let plan = planning.planned.expect("a plan").plan;
    let robot = gecaro_io::load_robot("ur10e").expect("robot").robot;
    for sample in &plan.samples {
        let chain = forward_kinematics(&robot, &sample.motor_positions).expect("fk");
        assert!(
            chain.poses()[1..]
                .iter()
                .all(|pose| pose.translation.vector.z >= -1e-9)
        );
    }
}
