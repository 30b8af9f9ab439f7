//! The server under stress: jobs cancelled and never lost, bad and hostile requests answered, other hosts refused, slow bodies let go.

use crate::util::*;

/// A cancelled job stops and says so; cancelling a finished one changes nothing.
#[tokio::test]
async fn jobs_can_be_cancelled() {
    let api = Api::new();
    let document = api.document("stanford").await;
    let (_, generated) = api
        .post(
            "/api/generate",
            &json!({ "robot": document, "method": { "name": "position" }, "count": 3000, "error_level": 1.0, "seed": 2 }),
        )
        .await;
    // Twenty folds of cross-validation on 3000 configurations: long enough.
    let (_, submitted) = api
        .post(
            "/api/identify",
            &json!({ "robot": document, "method": { "name": "position" }, "cv": 20, "data": { "csv": { "text": generated["csv"], "name": "long.csv" } } }),
        )
        .await;
    let job = submitted["job"].as_u64().expect("job");
    let (status, view) = api
        .post(&format!("/api/jobs/{job}/cancel"), &json!({}))
        .await;
    assert_eq!(status, StatusCode::OK, "{view}");
    let view = api.finished(job).await;
    assert_eq!(view["state"], "cancelled", "{view}");
    let (status, _) = api.get(&format!("/api/jobs/{job}/report")).await;
    assert_eq!(status, StatusCode::CONFLICT);
    // A finished job stays finished.
    let (_, small) = api
        .post(
            "/api/identify",
            &json!({ "robot": document, "method": { "name": "position" }, "data": { "csv": { "text": generated["csv"], "name": "long.csv" } } }),
        )
        .await;
    let small = small["job"].as_u64().expect("job");
    assert_eq!(api.finished(small).await["state"], "done");
    let (_, view) = api
        .post(&format!("/api/jobs/{small}/cancel"), &json!({}))
        .await;
    assert_eq!(view["state"], "done");
    let (status, _) = api.post("/api/jobs/999999/cancel", &json!({})).await;
    assert_eq!(status, StatusCode::NOT_FOUND);
}

/// No job is lost under load (issue 75: 802 of 1,000 jobs answered 404 to
/// the client that started them): 12 clients submit 5 identifications
/// each, cancel every third, poll every 20 ms until it ends, then fetch
/// the report; a 503 (every kept job still owed to its client) is retried.
/// Every client finds its every job until it has seen it end.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn no_job_is_lost_under_load() {
    let api = std::sync::Arc::new(Api::new());
    let document = api.document("stanford").await;
    let (_, generated) = api
        .post(
            "/api/generate",
            &json!({ "robot": document, "method": { "name": "position" }, "count": 30, "error_level": 1.0, "seed": 4 }),
        )
        .await;
    let request = json!({ "robot": document, "method": { "name": "position" },
                          "data": { "csv": { "text": generated["csv"], "name": "small.csv" } } });
    let mut clients = Vec::new();
    for client in 0..12u64 {
        let (api, request) = (std::sync::Arc::clone(&api), request.clone());
        clients.push(tokio::spawn(async move {
            let mut seen = Vec::new();
            for round in 0..5u64 {
                let mut tries = 0;
                let job = loop {
                    let (status, submitted) = api.post("/api/identify", &request).await;
                    if status == StatusCode::ACCEPTED {
                        break submitted["job"].as_u64().expect("job");
                    }
                    assert_eq!(status, StatusCode::SERVICE_UNAVAILABLE, "{submitted}");
                    tries += 1;
                    assert!(tries < 2000, "never admitted");
                    tokio::time::sleep(Duration::from_millis(20)).await;
                };
                if (client + round) % 3 == 0 {
                    api.post(&format!("/api/jobs/{job}/cancel"), &json!({}))
                        .await;
                }
                let state = loop {
                    let (status, view) = api.get(&format!("/api/jobs/{job}")).await;
                    assert_eq!(
                        status,
                        StatusCode::OK,
                        "client {client}: job {job} lost: {view}"
                    );
                    let state = view["state"].as_str().expect("state").to_owned();
                    if state != "queued" && state != "running" {
                        break state;
                    }
                    tokio::time::sleep(Duration::from_millis(20)).await;
                };
                if state == "done" {
                    let (status, _) = api.get(&format!("/api/jobs/{job}/report")).await;
                    assert_eq!(status, StatusCode::OK, "client {client}: report of {job}");
                }
                seen.push(state);
            }
            seen
        }));
    }
    let mut ended = 0;
    for client in clients {
        ended += client.await.expect("client").len();
    }
    assert_eq!(ended, 60);
}

#[tokio::test]
async fn bad_data_is_an_answer_not_a_failed_job() {
    let api = Api::new();
    let document = api.document("stanford").await;
    let identify =
        |data: Value| json!({ "robot": document, "method": { "name": "position" }, "data": data });
    let cases = [
        (json!({ "csv": { "text": "qm1,qm2\n1,2\n" } }), "qm3"),
        (
            json!({ "csv": { "text": "qm1,qm2,qm3,qm4,qm5,qm6,x,y,z\n0,0,0.5,0,0,0,1,2,nan\n" } }),
            "uploaded data:2: z",
        ),
        (json!({ "file": "missing.csv" }), "no file"),
    ];
    for (data, expected) in cases {
        let (status, body) = api.post("/api/identify", &identify(data.clone())).await;
        assert!(status.is_client_error(), "{data}: {status} {body}");
        assert!(error_text(&body).contains(expected), "{data}: {body}");
    }
    let (status, body) = api
        .post("/api/identify", &identify(json!({ "file": "../x.csv" })))
        .await;
    assert_eq!(status, StatusCode::FORBIDDEN, "{body}");
    // Well-formed but too few: found by the identification itself, a failed job.
    let one = json!({ "csv": { "text": "qm1,qm2,qm3,qm4,qm5,qm6,x,y,z\n0,0,0.5,0,0,0,1,2,3\n" } });
    let (status, submitted) = api.post("/api/identify", &identify(one)).await;
    assert_eq!(status, StatusCode::ACCEPTED);
    let view = api.finished(submitted["job"].as_u64().expect("job")).await;
    assert_eq!(view["state"], "failed");
    assert!(
        view["error"]
            .as_str()
            .expect("error")
            .contains("too few equations"),
        "{view}"
    );
    let (status, _) = api
        .get(&format!("/api/jobs/{}/report", submitted["job"]))
        .await;
    assert_eq!(status, StatusCode::CONFLICT);
}

#[tokio::test]
async fn malformed_requests_get_4xx_with_a_message() {
    let api = Api::new();
    let document = api.document("stanford").await;
    let (status, body) = api.post_raw("/api/identifiable", "{not json".into()).await;
    assert_eq!(status, StatusCode::BAD_REQUEST);
    assert!(!error_text(&body).is_empty());
    let (status, body) = api
        .post(
            "/api/identifiable",
            &json!({ "robot": document, "method": { "name": "laser" } }),
        )
        .await;
    assert_eq!(status, StatusCode::BAD_REQUEST);
    assert!(error_text(&body).contains("position"), "{body}");
    let (status, body) = api
        .post(
            "/api/identifiable",
            &json!({ "robot": document, "method": { "name": "position" }, "colour": 1 }),
        )
        .await;
    assert_eq!(status, StatusCode::BAD_REQUEST);
    assert!(error_text(&body).contains("colour"), "{body}");
    let (status, body) = api
        .post("/api/identifiable", &json!({ "robot": document, "method": { "name": "plane1", "plane_normal": [0, 0, 0], "plane_point": [0, 0, 0] } }))
        .await;
    assert_eq!(status, StatusCode::BAD_REQUEST, "{body}");
    // Without a JSON content type.
    let request = Request::post("/api/robots/check")
        .body(Body::from("{}"))
        .expect("request");
    let (status, _, _) = api.send(request).await;
    assert_eq!(status, StatusCode::BAD_REQUEST);
    // Too large.
    let huge = format!(
        "{{\"robot\": {{\"name\": \"{}\"}}}}",
        "x".repeat(gecaro_web::limits::MAX_BODY_BYTES + 10)
    );
    let (status, body) = api.post_raw("/api/robots/check", huge).await;
    assert_eq!(status, StatusCode::PAYLOAD_TOO_LARGE, "{body}");
    // Too many joints.
    let mut long = document.clone();
    let joint = long["frame"][1].clone();
    let frames = long["frame"].as_array_mut().expect("frames");
    for _ in 0..40 {
        frames.insert(1, joint.clone());
    }
    let (status, body) = api
        .post("/api/robots/pose", &json!({ "robot": long, "q": [] }))
        .await;
    assert_eq!(status, StatusCode::UNPROCESSABLE_ENTITY);
    assert!(error_text(&body).contains("32 joints"), "{body}");
}

#[tokio::test]
async fn garbage_never_gets_a_server_error() {
    let api = Api::new();
    let document = api.document("stanford").await;
    // The list is the router's: every route exists (else the checks below
    // would pass on 404s).
    for route in POST_ROUTES {
        let (status, answer) = api.post(route, &json!({})).await;
        assert!(
            status != StatusCode::NOT_FOUND && status != StatusCode::METHOD_NOT_ALLOWED,
            "{route}: {status} {answer}"
        );
    }
    let bodies = [
        json!(null),
        json!([]),
        json!({}),
        json!({ "robot": null }),
        json!({ "robot": {} }),
        json!({ "robot": { "frame": [] } }),
        json!({ "robot": { "frame": [{ "sigma": 2 }] } }),
        json!({ "robot": { "frame": [{ "sigma": 2 }, { "sigma": 2 }] } }),
        json!({ "robot": { "frame": [{ "sigma": -1 }, { "sigma": 0 }, { "sigma": 2 }] } }),
        json!({ "robot": { "frame": [{ "sigma": 2 }, { "sigma": 0, "qmin": 1e308, "qmax": -1e308 }, { "sigma": 2 }] } }),
        json!({ "robot": document, "q": [1e308, -1e308, 1e300, 0, 0, 0] }),
        json!({ "robot": document, "method": { "name": "position" }, "count": 1 }),
        json!({ "robot": document, "method": { "name": "plane1" }, "count": 3 }),
        json!({ "robot": document, "method": { "name": "point-link", "set_size": 1 }, "count": 3 }),
        json!({ "robot": document, "method": { "name": "distance" }, "data": { "csv": { "text": "" } } }),
        json!({ "robot": document, "method": { "name": "position" }, "data": { "csv": { "text": "\u{0}\u{1}" } } }),
        json!({ "robot": document, "name": "", "joints": "" }),
        json!({ "robot": document, "name": "x".repeat(5000), "overwrite": true }),
        json!({ "joints": "R".repeat(100) }),
    ];
    for route in POST_ROUTES {
        for body in &bodies {
            let (status, answer) = api.post(route, body).await;
            assert!(
                status.is_success() || status.is_client_error(),
                "{route} {body}: {status} {answer}"
            );
            if !status.is_success() {
                assert!(!error_text(&answer).is_empty());
            }
        }
    }
}

#[tokio::test]
async fn requests_for_other_hosts_and_cross_site_writes_are_refused() {
    let api = Api::with_hosts(vec!["127.0.0.1:8080".into(), "localhost:8080".into()]);
    let get = |host: &str| {
        Request::get("/api/info")
            .header(header::HOST, host)
            .body(Body::empty())
            .expect("request")
    };
    assert_eq!(api.send(get("127.0.0.1:8080")).await.0, StatusCode::OK);
    assert_eq!(api.send(get("localhost:8080")).await.0, StatusCode::OK);
    assert_eq!(
        api.send(get("attacker.example:8080")).await.0,
        StatusCode::FORBIDDEN
    );
    // Host names are case-insensitive.
    assert_eq!(api.send(get("LOCALHOST:8080")).await.0, StatusCode::OK);
    // A second Host header is not a way in.
    let doubled = Request::get("/api/info")
        .header(header::HOST, "127.0.0.1:8080")
        .header(header::HOST, "evil.example")
        .body(Body::empty())
        .expect("request");
    assert_eq!(api.send(doubled).await.0, StatusCode::BAD_REQUEST);
    let new = |origin: &str| {
        Request::post("/api/robots/new")
            .header(header::HOST, "127.0.0.1:8080")
            .header(header::ORIGIN, origin)
            .header(header::CONTENT_TYPE, "application/json")
            .body(Body::from(r#"{"joints": "RR"}"#))
            .expect("request")
    };
    assert_eq!(
        api.send(new("http://127.0.0.1:8080")).await.0,
        StatusCode::OK
    );
    assert_eq!(
        api.send(new("https://attacker.example")).await.0,
        StatusCode::FORBIDDEN
    );
    // Nor a second Origin header behind an allowed one.
    let doubled = Request::post("/api/robots/new")
        .header(header::HOST, "127.0.0.1:8080")
        .header(header::ORIGIN, "http://127.0.0.1:8080")
        .header(header::ORIGIN, "https://attacker.example")
        .header(header::CONTENT_TYPE, "application/json")
        .body(Body::from(r#"{"joints": "RR"}"#))
        .expect("request");
    assert_eq!(api.send(doubled).await.0, StatusCode::BAD_REQUEST);
}

#[tokio::test]
async fn a_stalled_request_times_out_with_a_message() {
    let folder = tempfile::tempdir().expect("folder");
    let state = AppState::new(
        Workspace::new(folder.path()).expect("workspace"),
        Vec::new(),
    )
    .with_request_timeout(Duration::from_millis(200));
    let app = router(state);
    // A body that never finishes arriving.
    let stalled = futures_util::stream::pending::<Result<bytes::Bytes, std::io::Error>>();
    let request = Request::post("/api/robots/check")
        .header(header::CONTENT_TYPE, "application/json")
        .body(Body::from_stream(stalled))
        .expect("request");
    let response = app.oneshot(request).await.expect("infallible");
    assert_eq!(response.status(), StatusCode::REQUEST_TIMEOUT);
    let bytes = response
        .into_body()
        .collect()
        .await
        .expect("body")
        .to_bytes();
    let body: Value = serde_json::from_slice(&bytes).expect("JSON");
    assert!(error_text(&body).contains("longer than 0.2 s"), "{body}");
}

/// Identification jobs never hold up the page's quick requests: with eight
/// jobs queued or running, the folder's listing answers while some are still
/// at work (before, it waited behind all of them for a computing slot).
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_listing_answers_while_jobs_run() {
    let api = Api::new();
    let document = api.document("industrial6").await;
    let (status, generated) = api
        .post(
            "/api/generate",
            &json!({ "robot": document, "method": { "name": "frame" }, "count": 3000, "error_level": 1.0, "seed": 5 }),
        )
        .await;
    assert_eq!(status, StatusCode::OK, "{generated}");
    let csv = generated["csv"].as_str().expect("csv");
    let request = json!({ "robot": document, "method": { "name": "frame" }, "data": { "csv": { "text": csv, "name": "gen.csv" } } });
    let mut jobs = Vec::new();
    for _ in 0..8 {
        let (status, submitted) = api.post("/api/identify", &request).await;
        assert_eq!(status, StatusCode::ACCEPTED, "{submitted}");
        jobs.push(submitted["job"].as_u64().expect("job number"));
    }
    let (status, listing) = api.get("/api/files").await;
    assert_eq!(status, StatusCode::OK, "{listing}");
    let mut active = 0;
    for job in &jobs {
        let (_, view) = api.get(&format!("/api/jobs/{job}")).await;
        if view["state"] == "queued" || view["state"] == "running" {
            active += 1;
        }
    }
    // Before, the listing waited for a computing slot behind the queued jobs
    // and answered when at most one was left.
    assert!(
        active >= 4,
        "only {active} of 8 jobs were at work when the listing answered"
    );
    for job in jobs {
        assert_eq!(api.finished(job).await["state"], "done");
    }
}

/// Values that cannot give finite output, hostile robot files in the folder:
/// each is a 4xx with a message, and the server lives on.
#[tokio::test]
async fn hostile_values_and_files_are_answers_not_crashes() {
    let api = Api::new();
    let document = api.document("stanford").await;
    for (field, value) in [
        ("error_level", json!(1e308)),
        ("noise", json!(1e308)),
        ("count", json!(1_000_000_000_000u64)),
    ] {
        let mut request =
            json!({ "robot": document, "method": { "name": "position" }, "count": 10 });
        request[field] = value.clone();
        let (status, body) = api.post("/api/generate", &request).await;
        assert_eq!(status, StatusCode::BAD_REQUEST, "{field} = {value}: {body}");
    }
    let mut unlimited = document.clone();
    unlimited["frame"][1]["qmax"] = json!(1e308);
    let (status, body) = api
        .post(
            "/api/generate",
            &json!({ "robot": unlimited, "method": { "name": "position" }, "count": 10 }),
        )
        .await;
    assert!(status.is_client_error(), "{status}: {body}");
    // A URDF nested 5,000 deep and one of 100,000 joints, opened from the folder.
    std::fs::write(
        api.folder.path().join("deep.urdf"),
        format!(
            "<robot name=\"d\">{}{}</robot>",
            "<a>".repeat(5000),
            "</a>".repeat(5000)
        ),
    )
    .expect("write");
    let joints: String = (1..=100_000)
        .map(|i| {
            format!(
                "<link name=\"l{i}\"/><joint name=\"j{i}\" type=\"revolute\"><parent link=\"l{}\"/>\
                 <child link=\"l{i}\"/><axis xyz=\"0 0 1\"/></joint>",
                i - 1
            )
        })
        .collect();
    std::fs::write(
        api.folder.path().join("huge.urdf"),
        format!("<robot name=\"h\"><link name=\"l0\"/>{joints}</robot>"),
    )
    .expect("write");
    for name in ["deep.urdf", "huge.urdf"] {
        let (status, body) = api.get(&format!("/api/robots/file?name={name}")).await;
        assert!(status.is_client_error(), "{name}: {status} {body}");
        assert!(error_text(&body).contains(name), "{body}");
    }
    let (status, _) = api.get("/api/info").await;
    assert_eq!(status, StatusCode::OK);
}

/// A client that sends its headers and part of a body, then stops: answered
/// 408 once the body is overdue (5 s), not after the request timeout
/// (300 s), so that such clients cannot hold every connection.
#[tokio::test]
async fn a_body_that_stops_arriving_is_let_go() {
    let api = Api::new();
    let part = futures_util::stream::once(async {
        Ok::<_, std::io::Error>(bytes::Bytes::from_static(b"{\"joints\": "))
    })
    .chain(futures_util::stream::pending());
    let request = Request::post("/api/robots/new")
        .header(header::CONTENT_TYPE, "application/json")
        .header(header::CONTENT_LENGTH, "40")
        .body(Body::from_stream(part))
        .expect("request");
    let started = std::time::Instant::now();
    let (status, bytes, _) = api.send(request).await;
    assert_eq!(status, StatusCode::REQUEST_TIMEOUT);
    assert!(started.elapsed() < Duration::from_secs(20));
    let body: Value = serde_json::from_slice(&bytes).expect("JSON");
    assert!(
        error_text(&body).contains("body stopped arriving"),
        "{body}"
    );
}

/// A generation whose client went away stops at its next configuration: it
/// frees its computing slot at once and writes nothing (before, every slot
/// stayed taken until the generations ended, and their files appeared after).
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn an_abandoned_generation_frees_its_slot_and_writes_nothing() {
    let api = Api::new();
    let document = api.document("stanford").await;
    let slots = std::thread::available_parallelism().map_or(2, std::num::NonZero::get);
    for index in 0..slots {
        // Frame-link sets are drawn by the inverse model: 20,000 rows take
        // seconds in release, minutes in a test build.
        let body = json!({
            "robot": document, "method": { "name": "frame-link" }, "count": 20000,
            "seed": index, "save_as": format!("abandoned-{index}.csv"),
        });
        let request = Request::post("/api/generate")
            .header(header::CONTENT_TYPE, "application/json")
            .body(Body::from(body.to_string()))
            .expect("request");
        let leaving =
            tokio::time::timeout(Duration::from_millis(300), api.app.clone().oneshot(request))
                .await;
        assert!(leaving.is_err(), "the generation ended within 300 ms");
    }
    // Every computing slot was taken by a generation; this one needs a slot.
    let quick = json!({ "robot": document, "method": { "name": "position" }, "count": 30 });
    let (status, answer) =
        tokio::time::timeout(Duration::from_secs(60), api.post("/api/generate", &quick))
            .await
            .expect("a slot was freed by the abandoned generations");
    assert_eq!(status, StatusCode::OK, "{answer}");
    let names = api.names();
    assert!(names.is_empty(), "written after the client left: {names:?}");
}
