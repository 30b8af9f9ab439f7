//! The page itself: one HTML file, one style sheet and the page's ES modules
//! (`assets/js`, served as they are under `/js/`: no build step, no
//! network), embedded in the binary. Written by the gecaro developers; no
//! third-party code.

use axum::extract::Path;
use axum::http::header;
use axum::response::{IntoResponse, Response};

use crate::error::ApiError;

const INDEX: &str = include_str!("../assets/index.html");
const STYLE: &str = include_str!("../assets/style.css");

/// Every module of `assets/js` by its path under `/js/` (a test checks that
/// the folder holds these and no others).
const MODULES: &[(&str, &str)] = &[
    ("acceptance.js", include_str!("../assets/js/acceptance.js")),
    ("parallel.js", include_str!("../assets/js/parallel.js")),
    ("api.js", include_str!("../assets/js/api.js")),
    ("cell.js", include_str!("../assets/js/cell.js")),
    (
        "data-choices.js",
        include_str!("../assets/js/data-choices.js"),
    ),
    ("deviations.js", include_str!("../assets/js/deviations.js")),
    ("dialogs.js", include_str!("../assets/js/dialogs.js")),
    ("dom.js", include_str!("../assets/js/dom.js")),
    ("events.js", include_str!("../assets/js/events.js")),
    ("fields.js", include_str!("../assets/js/fields.js")),
    ("file-fit.js", include_str!("../assets/js/file-fit.js")),
    ("format.js", include_str!("../assets/js/format.js")),
    ("help.js", include_str!("../assets/js/help.js")),
    ("history.js", include_str!("../assets/js/history.js")),
    ("jobs.js", include_str!("../assets/js/jobs.js")),
    ("main.js", include_str!("../assets/js/main.js")),
    (
        "method-options.js",
        include_str!("../assets/js/method-options.js"),
    ),
    ("navigation.js", include_str!("../assets/js/navigation.js")),
    ("results.js", include_str!("../assets/js/results.js")),
    ("robot-menu.js", include_str!("../assets/js/robot-menu.js")),
    (
        "robot-table.js",
        include_str!("../assets/js/robot-table.js"),
    ),
    ("stale.js", include_str!("../assets/js/stale.js")),
    ("state.js", include_str!("../assets/js/state.js")),
    ("steps.js", include_str!("../assets/js/steps.js")),
    ("study.js", include_str!("../assets/js/study.js")),
    ("study-plan.js", include_str!("../assets/js/study-plan.js")),
    ("study-spec.js", include_str!("../assets/js/study-spec.js")),
    ("units.js", include_str!("../assets/js/units.js")),
    ("view.js", include_str!("../assets/js/view.js")),
    (
        "panels/compensate.js",
        include_str!("../assets/js/panels/compensate.js"),
    ),
    (
        "panels/evaluate.js",
        include_str!("../assets/js/panels/evaluate.js"),
    ),
    (
        "panels/generate.js",
        include_str!("../assets/js/panels/generate.js"),
    ),
    (
        "panels/identifiable.js",
        include_str!("../assets/js/panels/identifiable.js"),
    ),
    (
        "panels/identify.js",
        include_str!("../assets/js/panels/identify.js"),
    ),
    (
        "panels/plan.js",
        include_str!("../assets/js/panels/plan.js"),
    ),
];

pub(crate) async fn index() -> impl IntoResponse {
    ([(header::CONTENT_TYPE, "text/html; charset=utf-8")], INDEX)
}

/// The module at `/js/{path}`, or 404.
pub(crate) async fn module(Path(path): Path<String>) -> Response {
    match MODULES.iter().find(|(name, _)| *name == path) {
        Some((_, text)) => (
            [(header::CONTENT_TYPE, "text/javascript; charset=utf-8")],
            *text,
        )
            .into_response(),
        None => ApiError::NotFound(format!("no page module {path}")).into_response(),
    }
}

pub(crate) async fn style() -> impl IntoResponse {
    ([(header::CONTENT_TYPE, "text/css; charset=utf-8")], STYLE)
}

#[cfg(test)]
mod tests {
    use super::MODULES;
    use std::path::{Path, PathBuf};

    fn modules_in(folder: &Path, prefix: &str, found: &mut Vec<String>) {
        for entry in std::fs::read_dir(folder).expect("assets/js") {
            let path: PathBuf = entry.expect("entry").path();
            let name = path.file_name().and_then(|n| n.to_str()).expect("name");
            if path.is_dir() {
                modules_in(&path, &format!("{prefix}{name}/"), found);
            } else if name.ends_with(".js") {
                found.push(format!("{prefix}{name}"));
            }
        }
    }

    #[test]
    fn every_module_of_the_folder_is_served_and_no_other() {
        let folder = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/js");
        let mut found = Vec::new();
        modules_in(&folder, "", &mut found);
        found.sort();
        let mut served: Vec<String> = MODULES.iter().map(|(n, _)| (*n).to_string()).collect();
        served.sort();
        assert_eq!(found, served);
    }
}
