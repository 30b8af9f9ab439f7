//! Every seed and every former crash of the fuzz targets, through the same
//! checks as the fuzzers: `seeds/<target>/` (valid and invalid inputs of the
//! project) and `regressions/<target>/` (inputs that once failed a check,
//! kept when fixed). Runs in `.ci/run`.

use std::path::Path;

fn replay(target: &str, check: fn(&[u8])) {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut count = 0;
    for folder in ["seeds", "regressions"] {
        let Ok(entries) = std::fs::read_dir(root.join(folder).join(target)) else {
            continue;
        };
        let mut paths: Vec<_> = entries.map(|entry| entry.expect("entry").path()).collect();
        paths.sort();
        for path in paths {
            let input = std::fs::read(&path).expect("input");
            let outcome = std::panic::catch_unwind(|| check(&input));
            assert!(outcome.is_ok(), "{} fails its check", path.display());
            count += 1;
        }
    }
    assert!(count > 10, "only {count} inputs for {target}");
}

#[test]
fn robot_file_inputs() {
    replay("robot_file", gecaro_fuzz::robot_file);
}

#[test]
fn data_file_inputs() {
    replay("data_file", gecaro_fuzz::data_file);
}

#[test]
fn symoro_file_inputs() {
    replay("symoro_file", gecaro_fuzz::symoro_file);
}

#[test]
fn study_file_inputs() {
    replay("study_file", gecaro_fuzz::study_file);
}

#[test]
fn web_api_inputs() {
    replay("web_api", gecaro_fuzz::web_api);
}

#[test]
fn urdf_file_inputs() {
    replay("urdf_file", gecaro_fuzz::urdf_file);
    // The third-party URDFs of the tests, kept once with their licences
    // (make-seeds.py copies them into the fuzzer's corpus).
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    for folder in ["tests/data/urdf", "examples/tracker"] {
        for entry in std::fs::read_dir(root.join(folder)).expect("folder") {
            let path = entry.expect("entry").path();
            if path.extension().is_some_and(|e| e == "urdf") {
                let input = std::fs::read(&path).expect("input");
                let outcome = std::panic::catch_unwind(|| gecaro_fuzz::urdf_file(&input));
                assert!(outcome.is_ok(), "{} fails its check", path.display());
            }
        }
    }
}
