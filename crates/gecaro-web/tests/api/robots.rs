//! Robot files: opened, checked, created, converted, saved inside the folder and never broken, their poses.

use crate::util::*;

#[tokio::test]
async fn robots_are_opened_checked_and_their_problems_located() {
    let api = Api::new();
    let (status, view) = api.get("/api/robots/ready/stanford").await;
    assert_eq!(status, StatusCode::OK);
    assert_eq!(view["summary"]["letters"], "RRPRRR");
    assert_eq!(view["summary"]["parameter_count"], 43);
    assert_eq!(view["problems"], json!([]));
    let (status, missing) = api.get("/api/robots/ready/r2d2").await;
    assert_eq!(status, StatusCode::NOT_FOUND);
    assert!(error_text(&missing).contains("stanford"));

    let mut document = view["document"].clone();
    document["frame"][2]["sigma"] = json!(7);
    document["frame"][4]["alpha"] = json!(100.0);
    let (status, checked) = api
        .post("/api/robots/check", &json!({ "robot": document }))
        .await;
    assert_eq!(status, StatusCode::OK);
    assert!(checked.get("summary").is_none());
    let problems = checked["problems"].as_array().expect("problems");
    assert_eq!(problems.len(), 2, "{checked}");
    assert_eq!(
        problems[0]["location"],
        json!({ "kind": "frame", "frame": 2, "key": "sigma" })
    );
    assert_eq!(
        problems[1]["location"],
        json!({ "kind": "frame", "frame": 4, "key": "alpha" })
    );
    assert!(
        problems[1]["message"]
            .as_str()
            .expect("text")
            .contains("angle_unit")
    );

    // The same document, refused by a computing route with the same problems.
    let (status, refused) = api
        .post(
            "/api/identifiable",
            &json!({ "robot": document, "method": { "name": "position" } }),
        )
        .await;
    assert_eq!(status, StatusCode::UNPROCESSABLE_ENTITY);
    assert_eq!(refused["problems"].as_array().expect("problems").len(), 2);
}

#[tokio::test]
async fn new_robots_follow_the_joint_letters() {
    let api = Api::new();
    let (status, view) = api
        .post(
            "/api/robots/new",
            &json!({ "joints": "RRPR", "name": "Mine" }),
        )
        .await;
    assert_eq!(status, StatusCode::OK, "{view}");
    assert_eq!(view["summary"]["letters"], "RRPR");
    assert_eq!(view["document"]["name"], "Mine");
    let (status, refused) = api
        .post("/api/robots/new", &json!({ "joints": "RXR" }))
        .await;
    assert_eq!(status, StatusCode::BAD_REQUEST);
    assert!(error_text(&refused).contains("joint 2 is `X`"));
}

#[tokio::test]
async fn saves_stay_inside_the_folder_and_never_break_a_file() {
    let api = Api::new();
    let document = api.document("puma560").await;
    let save = |name: &str, overwrite: bool| json!({ "robot": document, "name": name, "overwrite": overwrite });
    let (status, saved) = api
        .post("/api/robots/save", &save("puma.toml", false))
        .await;
    assert_eq!(status, StatusCode::OK, "{saved}");
    let path = api.folder.path().join("puma.toml");
    let written = std::fs::read_to_string(&path).expect("saved");
    let loaded = gecaro_io::read_robot_file(&path).expect("a valid robot file");
    assert_eq!(loaded.robot.joint_letters(), "RRRRRR");

    // Exists: 409 without overwrite, file untouched.
    let (status, conflict) = api
        .post("/api/robots/save", &save("puma.toml", false))
        .await;
    assert_eq!(status, StatusCode::CONFLICT);
    assert!(error_text(&conflict).contains("already exists"));
    // An invalid robot is not saved over a good file.
    let mut broken = document.clone();
    broken["frame"][1]["qmin"] = json!(3.0);
    broken["frame"][1]["qmax"] = json!(-3.0);
    let (status, refused) = api
        .post(
            "/api/robots/save",
            &json!({ "robot": broken, "name": "puma.toml", "overwrite": true }),
        )
        .await;
    assert_eq!(status, StatusCode::UNPROCESSABLE_ENTITY, "{refused}");
    assert_eq!(std::fs::read_to_string(&path).expect("kept"), written);
    // Outside the folder, hidden, or not a robot file: 403.
    for name in [
        "../escape.toml",
        "/tmp/escape.toml",
        ".hidden.toml",
        "robot.txt",
        "a/../../x.toml",
    ] {
        let (status, body) = api.post("/api/robots/save", &save(name, true)).await;
        assert_eq!(status, StatusCode::FORBIDDEN, "{name}: {body}");
    }
    assert!(
        !api.folder
            .path()
            .parent()
            .expect("parent")
            .join("escape.toml")
            .exists()
    );

    // Listed, and opened back to the same document.
    let (_, files) = api.get("/api/files").await;
    assert_eq!(files["robots"], json!(["puma.toml"]));
    let (status, opened) = api.get("/api/robots/file?name=puma.toml").await;
    assert_eq!(status, StatusCode::OK);
    assert_eq!(opened["origin"], "file");
    assert_eq!(opened["summary"]["letters"], "RRRRRR");
    let (status, _) = api.get("/api/robots/file?name=../etc/passwd.toml").await;
    assert_eq!(status, StatusCode::FORBIDDEN);
    let (status, _) = api.get("/api/robots/file?name=nothing.toml").await;
    assert_eq!(status, StatusCode::NOT_FOUND);
    let (status, _) = api.get("/api/robots/file").await;
    assert_eq!(status, StatusCode::BAD_REQUEST);

    // A file with a TOML mistake: 422 naming the line.
    std::fs::write(
        api.folder.path().join("bad.toml"),
        "name = \"x\"\n[[frame]]\nsigma = \n",
    )
    .expect("write");
    let (status, bad) = api.get("/api/robots/file?name=bad.toml").await;
    assert_eq!(status, StatusCode::UNPROCESSABLE_ENTITY);
    assert!(error_text(&bad).contains("bad.toml:3"), "{bad}");
}

/// The listing names each data file's columns (from its header, past its
/// comment lines and in its own separator), so that a method's menu lists
/// the files it can read; a file with no complete header line has none.
#[tokio::test]
async fn data_files_are_listed_with_their_columns() {
    let api = Api::new();
    let folder = api.folder.path();
    std::fs::write(
        folder.join("positions.csv"),
        "# gecaro generate: stanford\nqm1,qm2,qm3,qm4,qm5,qm6,x,y,z\n0,0,0,0,0,0,1,2,3\n",
    )
    .expect("write");
    std::fs::write(
        folder.join("tracker.csv"),
        "\u{feff}\"time\";\"A1\";\"X_mm\"\n0;0,1;12,5\n",
    )
    .expect("write");
    std::fs::write(folder.join("empty.csv"), "# nothing but a comment\n").expect("write");
    let (status, files) = api.get("/api/files").await;
    assert_eq!(status, StatusCode::OK, "{files}");
    assert_eq!(
        files["data"],
        json!(["empty.csv", "positions.csv", "tracker.csv"])
    );
    assert_eq!(
        files["data_columns"],
        json!({
            "positions.csv": ["qm1", "qm2", "qm3", "qm4", "qm5", "qm6", "x", "y", "z"],
            "tracker.csv": ["time", "A1", "X_mm"],
        })
    );
}

#[tokio::test]
async fn urdf_dh_and_symoro_files_open_converted_and_robots_save_as_urdf() {
    let api = Api::new();
    let data = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/data");
    for (from, to) in [
        ("urdf/kuka_kr16_2.urdf", "kr16.urdf"),
        ("urdf/panda.urdf", "panda.urdf"),
        ("robots/stanford.par", "stanford.par"),
        ("robots/puma560_mdh.toml", "puma-table.toml"),
    ] {
        std::fs::copy(data.join(from), api.folder.path().join(to)).expect("copy");
    }
    let (_, files) = api.get("/api/files").await;
    assert_eq!(
        files["imports"],
        json!(["kr16.urdf", "panda.urdf", "stanford.par"])
    );
    assert_eq!(files["robots"], json!(["puma-table.toml"]));

    // Converted, shown in the table, with what the conversion did.
    let (status, kuka) = api.get("/api/robots/file?name=kr16.urdf").await;
    assert_eq!(status, StatusCode::OK, "{kuka}");
    assert_eq!(kuka["origin"], "imported");
    assert_eq!(kuka["summary"]["letters"], "RRRRRR");
    assert!(
        kuka["notes"][0].as_str().expect("note").contains("folded"),
        "{kuka}"
    );
    for (name, letters) in [("stanford.par", "RRPRRR"), ("puma-table.toml", "RRRRRR")] {
        let (status, opened) = api.get(&format!("/api/robots/file?name={name}")).await;
        assert_eq!(status, StatusCode::OK, "{name}: {opened}");
        assert_eq!(opened["summary"]["letters"], letters);
    }
    // A branching URDF: the error names the leaves; a tip resolves it.
    let (status, branching) = api.get("/api/robots/file?name=panda.urdf").await;
    assert_eq!(status, StatusCode::UNPROCESSABLE_ENTITY);
    assert!(
        error_text(&branching).contains("choose the tip link"),
        "{branching}"
    );
    let (status, panda) = api
        .get("/api/robots/file?name=panda.urdf&tip=ball_link")
        .await;
    assert_eq!(status, StatusCode::OK, "{panda}");
    assert_eq!(panda["summary"]["letters"], "RRRRRRR");

    // Save as URDF: the original names come back; a gain goes beside it.
    let mut document = kuka["document"].clone();
    let (status, saved) = api
        .post(
            "/api/robots/save",
            &json!({ "robot": document, "name": "out.urdf" }),
        )
        .await;
    assert_eq!(status, StatusCode::OK, "{saved}");
    assert!(saved.get("joint_calibration").is_none());
    let text = std::fs::read_to_string(api.folder.path().join("out.urdf")).expect("written");
    assert!(
        text.contains("name=\"joint_a6-tool0\"") && text.contains("name=\"link_3\""),
        "{text}"
    );
    document["frame"][2]["K"] = json!(1.002);
    let (status, saved) = api
        .post(
            "/api/robots/save",
            &json!({ "robot": document, "name": "geared.urdf" }),
        )
        .await;
    assert_eq!(status, StatusCode::OK, "{saved}");
    assert_eq!(saved["joint_calibration"], "geared.joint_calibration.yaml");
    assert!(
        api.folder
            .path()
            .join("geared.joint_calibration.yaml")
            .is_file()
    );
    let (status, _) = api
        .post(
            "/api/robots/save",
            &json!({ "robot": document, "name": "geared.urdf" }),
        )
        .await;
    assert_eq!(
        status,
        StatusCode::CONFLICT,
        "an existing URDF is kept without overwrite"
    );
    // Neither file is written when one of the two exists.
    std::fs::remove_file(api.folder.path().join("geared.joint_calibration.yaml")).expect("remove");
    let (status, _) = api
        .post(
            "/api/robots/save",
            &json!({ "robot": document, "name": "geared.urdf" }),
        )
        .await;
    assert_eq!(status, StatusCode::CONFLICT);
    assert!(
        !api.folder
            .path()
            .join("geared.joint_calibration.yaml")
            .exists()
    );
    // Issue 35 §1: a URDF that is a link or a folder, saved over with
    // overwrite, is refused before anything is written: the joint
    // calibration that was there stays as it was.
    let kept = "joints: [\"kept\"]\n";
    for (target, expected) in [
        ("linked", StatusCode::FORBIDDEN),
        ("folder", StatusCode::CONFLICT),
    ] {
        let urdf = api.folder.path().join(format!("{target}.urdf"));
        if target == "linked" {
            #[cfg(unix)]
            std::os::unix::fs::symlink(api.folder.path().join("out.urdf"), &urdf).expect("link");
        } else {
            std::fs::create_dir(&urdf).expect("folder");
        }
        let calibration = api
            .folder
            .path()
            .join(format!("{target}.joint_calibration.yaml"));
        std::fs::write(&calibration, kept).expect("calibration");
        let (status, body) = api
            .post(
                "/api/robots/save",
                &json!({ "robot": document, "name": format!("{target}.urdf"), "overwrite": true }),
            )
            .await;
        assert_eq!(status, expected, "{target}: {body}");
        assert_eq!(
            std::fs::read_to_string(&calibration).expect("still there"),
            kept,
            "{target}: the calibration beside it is untouched"
        );
    }
}

#[tokio::test]
async fn poses_give_every_frame() {
    let api = Api::new();
    let document = api.document("stanford").await;
    let (status, pose) = api
        .post(
            "/api/robots/pose",
            &json!({ "robot": document, "q": [0.0, 0.0, 0.5, 0.0, 0.0, 0.0] }),
        )
        .await;
    assert_eq!(status, StatusCode::OK);
    let frames = pose["frames"].as_array().expect("frames");
    assert_eq!(frames.len(), 8);
    // Matches the direct geometric model of the library (and the CLI's fk test).
    let tool = &frames[7]["origin"];
    let expected = [-0.0505392, 0.2, 1.0344655];
    for (axis, want) in expected.iter().enumerate() {
        assert!(
            (tool[axis].as_f64().expect("number") - want).abs() < 1e-7,
            "{tool}"
        );
    }
    let (status, wrong) = api
        .post(
            "/api/robots/pose",
            &json!({ "robot": document, "q": [0.0] }),
        )
        .await;
    assert_eq!(status, StatusCode::UNPROCESSABLE_ENTITY);
    assert!(error_text(&wrong).contains("6 motor values"));
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn parallel_saves_of_one_file_never_corrupt_it() {
    let api = Api::new();
    let stanford = api.document("stanford").await;
    let puma = api.document("puma560").await;
    let mut saves = Vec::new();
    for index in 0..40 {
        let robot = if index % 2 == 0 {
            stanford.clone()
        } else {
            puma.clone()
        };
        let app = api.app.clone();
        saves.push(tokio::spawn(async move {
            let body = json!({ "robot": robot, "name": "shared.toml", "overwrite": true });
            let request = Request::post("/api/robots/save")
                .header(header::CONTENT_TYPE, "application/json")
                .body(Body::from(body.to_string()))
                .expect("request");
            app.oneshot(request).await.expect("infallible").status()
        }));
    }
    for save in saves {
        assert_eq!(save.await.expect("task"), StatusCode::OK);
    }
    // One of the two robots, whole; no temporary file left behind.
    let path = api.folder.path().join("shared.toml");
    let saved = gecaro_io::read_robot_file(&path).expect("a valid robot file");
    assert!(["RRPRRR", "RRRRRR"].contains(&saved.robot.joint_letters().as_str()));
    let names = api.names();
    assert_eq!(names, ["shared.toml"]);
}

/// Eight clients saving one URDF at once, each robot needing its joint
/// calibration beside it: the URDF and the yaml left are always one
/// client's (they were written under separate locks: 5–8 of 20 trials
/// mixed them).
#[tokio::test]
async fn parallel_saves_of_a_urdf_and_its_calibration_stay_a_pair() {
    let api = Api::new();
    let stanford = api.document("stanford").await;
    let robots: Vec<Value> = (0..8)
        .map(|k| {
            let mut robot = stanford.clone();
            // A gain the URDF cannot carry (the yaml does), and a tool the
            // URDF does: both say which client wrote them.
            robot["frame"][1]["K"] = json!(1.01 + 0.01 * f64::from(k));
            robot["frame"][7]["r"] = json!(0.1 + 0.01 * f64::from(k));
            robot
        })
        .collect();
    for trial in 0..5 {
        let mut saves = Vec::new();
        for robot in &robots {
            let app = api.app.clone();
            let body = json!({ "robot": robot, "name": "pair.urdf", "overwrite": true });
            saves.push(tokio::spawn(async move {
                let request = Request::post("/api/robots/save")
                    .header(header::CONTENT_TYPE, "application/json")
                    .body(Body::from(body.to_string()))
                    .expect("request");
                app.oneshot(request).await.expect("infallible").status()
            }));
        }
        for save in saves {
            assert_eq!(save.await.expect("task"), StatusCode::OK);
        }
        let mut imported = gecaro_io::import_robot(
            &api.folder.path().join("pair.urdf"),
            &gecaro_io::ImportOptions::default(),
        )
        .expect("the pair imports");
        let yaml = api.folder.path().join("pair.joint_calibration.yaml");
        let text = std::fs::read_to_string(&yaml).expect("a joint calibration");
        gecaro_io::apply_joint_calibration(&mut imported.file, &text, &yaml).expect("applies");
        let robot = &imported.file.robot;
        // The yaml's map q = M·qm (imported as a coupling): M₁₁ is K1.
        let m11 = robot
            .joint_positions(&[1.0, 0.0, 0.0, 0.0, 0.0, 0.0])
            .expect("q")[0];
        let by_gain = ((m11 - 1.01) / 0.01).round();
        let qm = [0.3, -0.5, 0.6, 0.2, 1.0, -0.4];
        let reach = |robot: &gecaro_core::Robot| {
            gecaro_core::terminal_pose(robot, &qm)
                .expect("pose")
                .translation
                .vector
        };
        let by_tool = robots
            .iter()
            .position(|document| {
                let file: gecaro_io::RobotDocument =
                    serde_json::from_value(document.clone()).expect("document");
                let candidate = file.to_robot_file("k").expect("robot").robot;
                // Same joint values: the gain is undone through qm/K.
                let mut same_gain = candidate.clone();
                let parameters = same_gain.parameters();
                let id = parameters.id(parameters.index_of_name("K1").expect("K1"));
                same_gain.set_parameter(id, m11).expect("gain");
                (reach(&same_gain) - reach(robot)).norm() < 1e-6
            })
            .expect("the URDF is one client's");
        assert_eq!(
            by_gain as usize, by_tool,
            "trial {trial}: URDF and yaml of two clients"
        );
    }
}

/// Two people editing one file: the second save of the one who opened it
/// first is refused (409) with the choice, not silently lost; the version a
/// save answers lets the next save through.
#[tokio::test]
async fn a_file_changed_since_it_was_opened_is_not_overwritten_silently() {
    let api = Api::new();
    let stanford = api.document("stanford").await;
    let save = |robot: &Value, expected: Option<&str>| json!({ "robot": robot, "name": "arm.toml", "overwrite": true, "expected_version": expected });
    let (status, _) = api.post("/api/robots/save", &save(&stanford, None)).await;
    assert_eq!(status, StatusCode::OK);
    // Alice and Bob open it.
    let (status, alice) = api.get("/api/robots/file?name=arm.toml").await;
    assert_eq!(status, StatusCode::OK, "{alice}");
    let (_, bob) = api.get("/api/robots/file?name=arm.toml").await;
    let opened = alice["version"].as_str().expect("a version").to_owned();
    assert_eq!(bob["version"], alice["version"]);
    // Bob saves his edit.
    let mut edited = bob["document"].clone();
    edited["frame"][3]["d"] = json!(0.05);
    let (status, saved) = api
        .post("/api/robots/save", &save(&edited, Some(&opened)))
        .await;
    assert_eq!(status, StatusCode::OK, "{saved}");
    assert_ne!(saved["version"].as_str(), Some(opened.as_str()));
    // Alice's save from the version she opened is refused, Bob's edit kept.
    let mut hers = alice["document"].clone();
    hers["frame"][2]["alpha"] = json!(0.5);
    let (status, body) = api
        .post("/api/robots/save", &save(&hers, Some(&opened)))
        .await;
    assert_eq!(status, StatusCode::CONFLICT, "{body}");
    assert!(
        error_text(&body).contains("arm.toml changed since it was opened"),
        "{body}"
    );
    let kept = gecaro_io::read_robot_file(&api.folder.path().join("arm.toml")).expect("kept");
    assert!((kept.robot.frames()[3].d - 0.05).abs() < 1e-12);
    // Saving from the version the last save answered goes through.
    let current = saved["version"].as_str().expect("version");
    let (status, _) = api
        .post("/api/robots/save", &save(&edited, Some(current)))
        .await;
    assert_eq!(status, StatusCode::OK);
}

/// A robot file uploaded from the page opens as one of the folder would,
/// and nothing is written into the folder.
#[tokio::test]
async fn an_uploaded_robot_file_opens_without_touching_the_folder() {
    let api = Api::new();
    let urdf = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/data/urdf/panda.urdf"),
    )
    .expect("panda.urdf");
    let (status, opened) = api
        .post(
            "/api/robots/upload",
            &json!({ "name": "panda.urdf", "text": urdf, "tip": "panda_link8" }),
        )
        .await;
    assert_eq!(status, StatusCode::OK, "{opened}");
    assert_eq!(opened["origin"], "uploaded");
    assert!(opened["name"].is_null(), "no file of the folder: {opened}");
    assert_eq!(opened["summary"]["letters"], "RRRRRRR");
    // A gecaro robot file, and its mistakes named at their line.
    let puma = gecaro_io::robot_file_text(
        &gecaro_io::load_robot("puma560").expect("ready robot"),
        std::path::Path::new("puma.toml"),
    )
    .expect("text");
    let (status, opened) = api
        .post(
            "/api/robots/upload",
            &json!({ "name": "puma.toml", "text": puma }),
        )
        .await;
    assert_eq!(status, StatusCode::OK, "{opened}");
    assert_eq!(opened["summary"]["letters"], "RRRRRR");
    // `ARM.TOML` as the command line reads it (issue 75: read as a DH
    // table, "unknown field `frame`").
    let (status, opened) = api
        .post(
            "/api/robots/upload",
            &json!({ "name": "PUMA.TOML", "text": puma }),
        )
        .await;
    assert_eq!(status, StatusCode::OK, "{opened}");
    assert_eq!(opened["summary"]["letters"], "RRRRRR");
    let (status, bad) = api
        .post(
            "/api/robots/upload",
            &json!({ "name": "bad.toml", "text": "name = \"x\"\n[[frame]]\nsigma = \n" }),
        )
        .await;
    assert_eq!(status, StatusCode::UNPROCESSABLE_ENTITY);
    assert!(error_text(&bad).contains("bad.toml:3"), "{bad}");
    let (status, _) = api
        .post(
            "/api/robots/upload",
            &json!({ "name": "robot.exe", "text": "x" }),
        )
        .await;
    assert_eq!(status, StatusCode::BAD_REQUEST);
    assert!(api.names().is_empty(), "nothing written");
}
