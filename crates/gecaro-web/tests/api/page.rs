//! The page itself: the ready robots and methods it lists, its modules and assets served with safe headers.

use crate::util::*;

#[tokio::test]
async fn info_lists_the_ready_robots_and_the_seven_methods() {
    let api = Api::new();
    let (status, info) = api.get("/api/info").await;
    assert_eq!(status, StatusCode::OK);
    let methods: Vec<&str> = info["methods"]
        .as_array()
        .expect("methods")
        .iter()
        .map(|m| m["name"].as_str().expect("name"))
        .collect();
    assert_eq!(
        methods,
        [
            "position",
            "frame",
            "point-link",
            "frame-link",
            "plane1",
            "plane2",
            "distance"
        ]
    );
    assert_eq!(
        info["methods"][1]["columns"],
        json!(["x", "y", "z", "qw", "qx", "qy", "qz"])
    );
    assert_eq!(info["methods"][4]["uses_plane"], true);
    // The page checks its fields against the application layer's bounds.
    assert_eq!(
        info["limits"]["generate"],
        json!(gecaro_app::limits::MAX_GENERATE)
    );
    assert_eq!(
        info["limits"]["folds"],
        json!(gecaro_app::limits::MAX_FOLDS)
    );
    // The parallel card's pose count starts at the application's default.
    assert_eq!(
        info["defaults"]["parallel_poses"],
        json!(gecaro_app::parallel::DEFAULT_POSES)
    );
    assert!(
        info["ready"]
            .as_array()
            .expect("ready")
            .contains(&json!("stanford"))
    );
}

/// The page's modules as the browser loads them: from `/js/main.js`, every
/// relative import is served (as JavaScript), so no module is missing from
/// the binary.
#[tokio::test]
async fn every_module_the_page_imports_is_served() {
    let api = Api::new();
    let mut pending = vec!["main.js".to_string()];
    let mut seen = std::collections::BTreeSet::new();
    while let Some(path) = pending.pop() {
        if !seen.insert(path.clone()) {
            continue;
        }
        let (status, bytes, headers) = api
            .send(
                Request::get(format!("/js/{path}"))
                    .body(Body::empty())
                    .expect("request"),
            )
            .await;
        assert_eq!(status, StatusCode::OK, "/js/{path}");
        let content_type = headers[header::CONTENT_TYPE].to_str().expect("ascii");
        assert!(content_type.starts_with("text/javascript"), "{path}");
        let text = String::from_utf8(bytes.to_vec()).expect("utf-8");
        let folder = path.rsplit_once('/').map_or("", |(folder, _)| folder);
        for line in text.lines().filter(|l| l.starts_with("import ")) {
            let target = line
                .rsplit(" from '")
                .next()
                .expect("from")
                .trim_end_matches("';");
            let mut parts: Vec<&str> = folder.split('/').filter(|p| !p.is_empty()).collect();
            for part in target.split('/') {
                match part {
                    "." => {}
                    ".." => {
                        parts.pop();
                    }
                    name => parts.push(name),
                }
            }
            pending.push(parts.join("/"));
        }
    }
    assert!(seen.len() > 20, "{seen:?}");
    let (status, _) = api.get("/js/no-such-module.js").await;
    assert_eq!(status, StatusCode::NOT_FOUND);
}

#[tokio::test]
async fn the_page_and_its_assets_are_served_with_safe_headers() {
    let api = Api::new();
    for (path, kind) in [
        ("/", "text/html"),
        ("/js/main.js", "text/javascript"),
        ("/js/panels/identify.js", "text/javascript"),
        ("/style.css", "text/css"),
    ] {
        let (status, bytes, headers) = api
            .send(Request::get(path).body(Body::empty()).expect("request"))
            .await;
        assert_eq!(status, StatusCode::OK, "{path}");
        assert!(!bytes.is_empty());
        let content_type = headers[header::CONTENT_TYPE].to_str().expect("ascii");
        assert!(content_type.starts_with(kind), "{path}: {content_type}");
        assert_eq!(headers[header::X_CONTENT_TYPE_OPTIONS], "nosniff");
        assert!(headers.contains_key(header::CONTENT_SECURITY_POLICY));
    }
    let (status, body) = api.get("/no/such/page").await;
    assert_eq!(status, StatusCode::NOT_FOUND);
    assert!(error_text(&body).contains("no such"));
}
