//! The work around a calibration in the cell: compensation, joined files, tool points and user frames, the ISO 9283 test.

use crate::util::*;

#[tokio::test]
async fn a_program_is_compensated_target_by_target_and_saved_beside_it() {
    let api = Api::new();
    let document = api.document("stanford").await;
    let (training, calibrated) = api.calibrated(&document).await;
    // A controller's program: named points, joints in degrees (the
    // prismatic joint 3 in metres), a speed column, from the training poses.
    let csv = training["csv"].as_str().expect("csv");
    let mut text = String::from("point,qm1,qm2,qm3,qm4,qm5,qm6,speed\n");
    for (i, line) in data_lines(csv).skip(1).take(12).enumerate() {
        let q: Vec<f64> = line
            .split(',')
            .take(6)
            .map(|v| v.parse().expect("number"))
            .collect();
        let degrees: Vec<String> = q
            .iter()
            .enumerate()
            .map(|(j, v)| {
                if j == 2 {
                    v.to_string()
                } else {
                    v.to_degrees().to_string()
                }
            })
            .collect();
        text += &format!("P{i},{},250\n", degrees.join(","));
    }
    let request = json!({
        "nominal": document,
        "calibrated": calibrated,
        "program": { "csv": { "text": text, "name": "weld.csv" } },
        "format": { "angle_unit": "deg" },
        "match": "position",
        "save_as": "weld-compensated.csv",
    });
    let (status, compensated) = api.post("/api/compensate", &request).await;
    assert_eq!(status, StatusCode::OK, "{compensated}");
    assert_eq!(compensated["targets"], 12);
    assert_eq!(compensated["reached"], 12, "{compensated}");
    assert_eq!(compensated["points"].as_array().expect("points").len(), 12);
    assert_eq!(compensated["points"][0]["line"], 2, "lines of the file");
    assert_eq!(compensated["file_name"], "weld-compensated.csv");
    assert_eq!(
        compensated["output"], "weld-compensated.csv",
        "the name in the folder"
    );
    // The corrected file keeps the program's columns and units, corrected.
    let corrected = compensated["csv"].as_str().expect("csv");
    assert_eq!(corrected.lines().count(), 13);
    assert!(
        corrected
            .lines()
            .next()
            .expect("header")
            .starts_with("point,")
    );
    let row = corrected.lines().nth(1).expect("row");
    assert!(
        row.starts_with("P0,") && row.contains(",250"),
        "{corrected}"
    );
    assert!(
        compensated["largest_correction"]
            .as_f64()
            .expect("correction")
            > 0.0
    );
    assert!(api.names().contains(&"weld-compensated.csv".to_owned()));
    assert_eq!(
        std::fs::read_to_string(api.folder.path().join("weld-compensated.csv")).expect("saved"),
        corrected
    );
    // Saved once: the same name again is refused, nothing overwritten.
    let (status, body) = api.post("/api/compensate", &request).await;
    assert!(status.is_client_error(), "{body}");
    // A Cartesian target 5 m away is flagged, never dropped.
    let cartesian = json!({
        "nominal": document,
        "calibrated": calibrated,
        "program": { "csv": { "text": "x,y,z\n0.5,0.2,0.3\n5,0,0\n", "name": "points.csv" } },
    });
    let (status, flagged) = api.post("/api/compensate", &cartesian).await;
    assert_eq!(status, StatusCode::OK, "{flagged}");
    // (The Stanford's prismatic joint reaches it, 4.9 m out: beyond its limit.)
    assert_eq!(flagged["reached"], 1, "{flagged}");
    assert_eq!(flagged["outside_limits"], json!([3]), "{flagged}");
    // Without a calibrated robot the request is refused by its field.
    let (status, body) = api
        .post(
            "/api/compensate",
            &json!({ "nominal": document, "program": { "csv": { "text": text } } }),
        )
        .await;
    assert!(status.is_client_error(), "{body}");
    assert!(error_text(&body).contains("calibrated"), "{body}");
    // The position match says how far it turned the tool.
    assert!(
        compensated["largest_tool_turn"].as_f64().is_some() && compensated["turned"].is_array(),
        "{compensated}"
    );
    // A robot calibrated by a reflector study: frame n+1 was not observed,
    // so the program is compensated for a reflector it names, not tool0.
    let mut reflected = calibrated.clone();
    reflected["tool_frame_observed"] = json!(false);
    reflected["tools"] = json!({ "smr_a": { "position": [0.0, 0.0, 0.1] } });
    let program = json!({ "csv": { "text": text, "name": "weld.csv" } });
    let (status, body) = api
        .post(
            "/api/compensate",
            &json!({ "nominal": document, "calibrated": reflected, "program": program,
                     "format": { "angle_unit": "deg" }, "match": "position" }),
        )
        .await;
    assert_eq!(status, StatusCode::BAD_REQUEST, "{body}");
    assert!(
        error_text(&body).contains("is not calibrated") && error_text(&body).contains("smr_a"),
        "{body}"
    );
    let (status, body) = api
        .post(
            "/api/compensate",
            &json!({ "nominal": document, "calibrated": reflected, "program": program,
                     "format": { "angle_unit": "deg" }, "match": "position",
                     "tool": "smr_a", "max_tool_turn": "180deg" }),
        )
        .await;
    assert_eq!(status, StatusCode::OK, "{body}");
    assert_eq!(body["reached"], 12, "{body}");
    // The owner's base by four plate points (here where the nominal's is),
    // an upload in mm with `;` and decimal commas: the registration is
    // stated with the result.
    let plate = "name;x;y;z;base_x;base_y;base_z\nH1;250;250;0;250;250;0\n\
                 H2;-250;250;0,01;-250;250;0\nH3;-250;-250;0;-250;-250;0\nH4;250;-250;0;250;-250;0\n";
    let (status, body) = api
        .post(
            "/api/compensate",
            &json!({ "nominal": document, "calibrated": calibrated, "program": program,
                     "format": { "angle_unit": "deg" },
                     "base_points": { "csv": { "text": plate, "name": "plate.csv" } },
                     "base_points_format": { "length_unit": "mm" } }),
        )
        .await;
    assert_eq!(status, StatusCode::OK, "{body}");
    let registration = &body["registration"];
    assert_eq!(registration["points"][1]["name"], "H2", "{body}");
    assert!(
        registration["max"].as_f64().expect("m") < 1e-5,
        "{registration}"
    );
    let (status, body) = api
        .post(
            "/api/compensate",
            &json!({ "nominal": document, "calibrated": calibrated, "program": program,
                     "format": { "angle_unit": "deg" },
                     "base_points": { "csv": { "text": "x;y;z;base_x;base_y;base_z\n2500;0;0;0;0;0\n", "name": "plate.csv" } } }),
        )
        .await;
    assert!(status.is_client_error(), "{body}");
    assert!(error_text(&body).contains("plate.csv:2"), "{body}");
    // The maker's base by the circles of joints 1 and 2, the points where
    // the calibrated robot puts them (its axes as the table's robot puts
    // them: nothing to move), uploaded in mm.
    let start = [0.0, 0.4, 0.5, 0.3, -0.6, 0.2];
    let mut circles = String::from("qm1,qm2,qm3,qm4,qm5,qm6,x,y,z\n");
    let turned: Vec<(usize, f64)> = (-4..=4)
        .map(|k| (0, f64::from(k) * 0.3))
        .chain((-4..=3).map(|k| (1, 0.4 + f64::from(k) * 0.15)))
        .collect();
    for (joint, value) in turned {
        let mut q = start;
        q[joint] = value;
        if joint == 1 {
            q[0] = 0.25;
        }
        let (status, pose) = api
            .post("/api/robots/pose", &json!({ "robot": document, "q": q }))
            .await;
        assert_eq!(status, StatusCode::OK, "{pose}");
        let frames = pose["frames"].as_array().expect("frames");
        let tool = &frames[frames.len() - 1]["origin"];
        let mm = |axis: usize| tool[axis].as_f64().expect("number") * 1e3;
        let joints: Vec<String> = q.iter().map(f64::to_string).collect();
        circles += &format!("{},{},{},{}\n", joints.join(","), mm(0), mm(1), mm(2));
    }
    let (status, body) = api
        .post(
            "/api/compensate",
            &json!({ "nominal": document, "calibrated": document, "program": program,
                     "format": { "angle_unit": "deg" },
                     "base_circles": { "csv": { "text": circles, "name": "circles.csv" } },
                     "base_points_format": { "length_unit": "mm" } }),
        )
        .await;
    assert_eq!(status, StatusCode::OK, "{body}");
    let registration = &body["registration"];
    assert_eq!(registration["by"], "circles", "{body}");
    assert_eq!(registration["points"][0]["name"], "joint 1", "{body}");
    assert!(
        registration["max"].as_f64().expect("m") < 1e-6,
        "{registration}"
    );
    // The base by its points or by the convention, not both.
    let (status, body) = api
        .post(
            "/api/compensate",
            &json!({ "nominal": document, "calibrated": calibrated, "program": program,
                     "format": { "angle_unit": "deg" }, "rebase": true,
                     "base_points": { "csv": { "text": plate, "name": "plate.csv" } } }),
        )
        .await;
    assert_eq!(status, StatusCode::BAD_REQUEST, "{body}");
    assert!(error_text(&body).contains("give one of them"), "{body}");
}

/// `/api/join` (issue 74): an export in mm with `;` and decimal commas, a
/// log in degrees with a row nothing measured, joined by name and saved in
/// the folder; by row order, the counts that differ are named.
#[tokio::test]
async fn an_export_and_a_log_are_joined_through_the_api() {
    let api = Api::new();
    let document = api.document("stanford").await;
    let mut export = String::from("Point;X;Y;Z\n");
    let mut log = String::from("Name,qm1,qm2,qm3,qm4,qm5,qm6\nHOME,0,0,0.5,0,0,0\n");
    for i in 0..12 {
        let t = f64::from(i);
        let q = [
            (0.7 * t).sin(),
            (0.4 * t).cos() - 0.5,
            0.4 + 0.1 * (0.9 * t).sin(),
            (1.3 * t).sin(),
            0.8 * (0.5 * t).cos(),
            0.3 * t - 1.5,
        ];
        let (status, pose) = api
            .post("/api/robots/pose", &json!({ "robot": document, "q": q }))
            .await;
        assert_eq!(status, StatusCode::OK, "{pose}");
        let frames = pose["frames"].as_array().expect("frames");
        let tool = &frames[frames.len() - 1]["origin"];
        let mm =
            |axis: usize| format!("{:.6}", tool[axis].as_f64().expect("m") * 1e3).replace('.', ",");
        export += &format!("P{i};{};{};{}\n", mm(0), mm(1), mm(2));
        let degrees: Vec<String> = q
            .iter()
            .enumerate()
            .map(|(j, v)| {
                if j == 2 {
                    v.to_string()
                } else {
                    v.to_degrees().to_string()
                }
            })
            .collect();
        log += &format!("P{i},{}\n", degrees.join(","));
    }
    let request = |key: bool, save_as: &str| {
        let mut request = json!({
            "robot": document,
            "tracker": { "csv": { "text": export, "name": "export.csv" } },
            "log": { "csv": { "text": log, "name": "log.csv" } },
            "tracker_format": { "length_unit": "mm", "columns": "x=X,y=Y,z=Z" },
            "log_format": { "angle_unit": "deg" },
            "save_as": save_as,
        });
        if key {
            request["key"] = json!("Point");
            request["log_key"] = json!("Name");
        }
        request
    };
    let (status, body) = api.post("/api/join", &request(true, "joined.csv")).await;
    assert_eq!(status, StatusCode::OK, "{body}");
    assert_eq!(body["rows"], 12, "{body}");
    assert_eq!(body["unmeasured"][0]["key"], "HOME", "{body}");
    assert!(body["distance_rms"].as_f64().expect("m") < 1e-5, "{body}");
    assert!(api.names().contains(&"joined.csv".to_owned()));
    // By row order, the export is one row short of the log: named.
    let (status, body) = api.post("/api/join", &request(false, "by_order.csv")).await;
    assert!(status.is_client_error(), "{body}");
    assert!(
        error_text(&body).contains("12 measured points and 13 log rows"),
        "{body}"
    );
}

/// The owner's frames from the page (issue 74): a tool point taught from
/// a pivot's joint values (an upload, degrees), as `gecaro tcp`; a pivot
/// about one axis refused by its field; a user frame from three points.
#[tokio::test]
async fn a_tool_point_and_a_user_frame_are_made_through_the_api() {
    let api = Api::new();
    let document = api.document("industrial6").await;
    let robot = gecaro_io::load_robot("industrial6").expect("robot").robot;
    let tool = nalgebra::Vector3::new(0.015, -0.02, 0.18);
    let tooled = robot
        .reframed(
            &nalgebra::IsometryMatrix3::identity(),
            &nalgebra::IsometryMatrix3::translation(tool.x, tool.y, tool.z),
        )
        .expect("tooled");
    let mut text = String::from("qm1,qm2,qm3,qm4,qm5,qm6\n");
    for (rx, ry) in [
        (0.4, 0.0),
        (-0.4, 0.0),
        (0.0, 0.4),
        (0.0, -0.4),
        (0.3, 0.3),
        (-0.3, 0.2),
    ] {
        let rotation = nalgebra::Rotation3::from_euler_angles(rx, ry, 0.0)
            * nalgebra::Rotation3::from_euler_angles(std::f64::consts::PI, 0.0, 0.0);
        let target = nalgebra::IsometryMatrix3::from_parts(
            nalgebra::Translation3::new(0.75, 0.1, 0.3),
            rotation,
        );
        let solution = gecaro_core::inverse_kinematics(
            &tooled,
            &gecaro_core::Target::Frame(target),
            &[0.0, -0.3, 0.9, 0.0, 0.9, 0.0],
            &gecaro_core::InverseOptions::default(),
        )
        .expect("reached");
        let row: Vec<String> = solution
            .motor_positions
            .iter()
            .map(|q| q.to_degrees().to_string())
            .collect();
        text += &(row.join(",") + "\n");
    }
    let (status, taught) = api
        .post(
            "/api/tcp",
            &json!({ "robot": document, "data": { "csv": { "text": text, "name": "pivot.csv" } },
                     "format": { "angle_unit": "deg" } }),
        )
        .await;
    assert_eq!(status, StatusCode::OK, "{taught}");
    for axis in 0..3 {
        let found = taught["tool"][axis].as_f64().expect("m");
        assert!((found - tool[axis]).abs() < 1e-6, "{taught}");
    }
    let about_axis: String = (0..5)
        .map(|i| format!("0,-17,52,0,52,{}\n", 30 * i))
        .collect();
    let (status, body) = api
        .post(
            "/api/tcp",
            &json!({ "robot": document, "format": { "angle_unit": "deg" },
                     "data": { "csv": { "text": format!("qm1,qm2,qm3,qm4,qm5,qm6\n{about_axis}"), "name": "pivot.csv" } } }),
        )
        .await;
    assert_eq!(status, StatusCode::BAD_REQUEST, "{body}");
    assert!(error_text(&body).contains("not determined"), "{body}");
    let (status, frame) = api
        .post(
            "/api/frame",
            &json!({ "points": { "csv": { "text": "name;x;y;z\norigin;1000;2000;500\nx;1000;2500;500\nxy;200;2100;500\n", "name": "fixture.csv" } },
                     "format": { "length_unit": "mm" } }),
        )
        .await;
    assert_eq!(status, StatusCode::OK, "{frame}");
    assert_eq!(frame["way"], "three points");
    assert!(
        (frame["position"][1].as_f64().expect("m") - 2.0).abs() < 1e-12,
        "{frame}"
    );
    // Data measured from a tracker 2 m away: named, then registered on 30 %.
    let world = nalgebra::IsometryMatrix3::from_parts(
        nalgebra::Translation3::new(2.0, 0.5, -0.2),
        nalgebra::Rotation3::from_euler_angles(0.0, 0.0, 1.2),
    );
    let seen = gecaro_io::RobotFile::of(
        robot
            .reframed(&world, &nalgebra::IsometryMatrix3::identity())
            .expect("seen"),
    );
    let real = serde_json::to_value(gecaro_io::RobotDocument::from_robot_file(&seen)).expect("doc");
    let (status, generated) = api
        .post(
            "/api/generate",
            &json!({ "robot": document, "method": { "name": "position" }, "count": 40,
                     "noise": 2e-5, "seed": 2, "real": real }),
        )
        .await;
    assert_eq!(status, StatusCode::OK, "{generated}");
    let data = json!({ "csv": { "text": generated["csv"], "name": "other.csv" } });
    let (status, plain) = api
        .post(
            "/api/evaluate",
            &json!({ "robot": document, "method": { "name": "position" }, "data": data }),
        )
        .await;
    assert_eq!(status, StatusCode::OK, "{plain}");
    assert!(
        plain["notes"].to_string().contains("another frame"),
        "{plain}"
    );
    let (status, registered) = api
        .post(
            "/api/evaluate",
            &json!({ "robot": document, "method": { "name": "position" }, "data": data,
                     "register": "30%" }),
        )
        .await;
    assert_eq!(status, StatusCode::OK, "{registered}");
    assert!(
        registered["errors"]["rms"].as_f64().expect("m") < 6e-5,
        "{registered}"
    );
}

/// ISO 9283's test from the page (issue 78): planned into the folder (the
/// program's text beside the plan), a measured upload evaluated against it
/// in millimetres with a stated frame, a bad cube refused by its field.
#[tokio::test]
async fn an_iso9283_test_is_planned_and_evaluated_through_the_api() {
    let api = Api::new();
    let document = api.document("industrial6").await;
    let (status, plan) = api
        .post(
            "/api/iso9283/plan",
            &json!({ "robot": document, "cycles": 3, "directions": 3, "save_as": "test.csv" }),
        )
        .await;
    assert_eq!(status, StatusCode::OK, "{plan}");
    assert_eq!(plan["rows"], 90);
    assert_eq!(plan["measured_rows"], 45);
    let program = plan["program"].as_str().expect("program");
    assert_eq!(
        std::fs::read_to_string(api.folder.path().join("test.csv")).expect("saved"),
        program
    );
    // A tracker 1 m along x saw each visit 0.05 mm off along z.
    let mut measured = String::from("pose;cycle;direction;x;y;z\n");
    for line in program.lines().skip(1) {
        let fields: Vec<&str> = line.split(',').collect();
        if fields[3] != "1" {
            continue;
        }
        let at = |i: usize| fields[i].parse::<f64>().expect("number") * 1e3;
        measured.push_str(&format!(
            "{};{};{};{};{};{}\n",
            fields[0],
            fields[1],
            fields[2],
            (at(10) - 1000.0).to_string().replace('.', ","),
            at(11).to_string().replace('.', ","),
            (at(12) + 0.05).to_string().replace('.', ",")
        ));
    }
    let (status, report) = api
        .post(
            "/api/iso9283/evaluate",
            &json!({ "program": { "file": "test.csv" },
                     "data": { "csv": { "text": measured, "name": "tracker.csv" } },
                     "format": { "length_unit": "mm" }, "frame": "1m,0,0",
                     "conditions": { "speed": "50 %" } }),
        )
        .await;
    assert_eq!(status, StatusCode::OK, "{report}");
    let before = &report["before"];
    assert_eq!(before["registration"], "stated");
    assert_eq!(before["directions"], 3);
    for pose in before["poses"].as_array().expect("poses") {
        assert!(
            (pose["ap"]["z"].as_f64().expect("m") - 5e-5).abs() < 1e-9,
            "{pose}"
        );
        assert!(pose["vap"]["p"].as_f64().expect("m") < 1e-9, "{pose}");
    }
    assert_eq!(report["conditions"]["speed"], "50 %");
    let (status, body) = api
        .post(
            "/api/iso9283/plan",
            &json!({ "robot": document, "cube": "1,0,0.5,0.3mm" }),
        )
        .await;
    assert_eq!(status, StatusCode::BAD_REQUEST, "{body}");
    assert!(error_text(&body).contains("cube"), "{body}");
}
