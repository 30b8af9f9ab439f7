//! The test profile names every workspace member (Cargo.toml, "One profile
//! for everything CI builds"): the profile's own opt-level 3 is for the
//! dependencies, and each member states opt-level 1 with line tables. A
//! member left out of the list would still build, at opt-level 3 without
//! line tables: slower to build, its backtraces without file and line, and
//! nothing would say so but this test.

use std::path::Path;
use std::process::Command;

/// The `[profile.dev.package.<name>]` sections of `manifest`: each name
/// with the lines up to the next section.
fn member_profiles(manifest: &str) -> Vec<(String, Vec<String>)> {
    let mut profiles: Vec<(String, Vec<String>)> = Vec::new();
    let mut inside = false;
    for line in manifest.lines().map(str::trim) {
        if line.starts_with('[') {
            let name = line
                .strip_prefix("[profile.dev.package.")
                .and_then(|rest| rest.strip_suffix(']'))
                .map(|name| name.trim_matches('"'));
            inside = name.is_some_and(|name| name != "*");
            if let Some(name) = name.filter(|_| inside) {
                profiles.push((name.to_string(), Vec::new()));
            }
        } else if inside
            && !line.is_empty()
            && !line.starts_with('#')
            && let Some((_, lines)) = profiles.last_mut()
        {
            lines.push(line.replace(' ', ""));
        }
    }
    profiles
}

#[test]
fn every_workspace_member_states_its_test_profile() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let output = Command::new(cargo)
        .args([
            "metadata",
            "--no-deps",
            "--format-version",
            "1",
            "--offline",
        ])
        .current_dir(root)
        .output()
        .expect("cargo metadata runs");
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let metadata: serde_json::Value =
        serde_json::from_slice(&output.stdout).expect("cargo metadata's JSON");
    let members: Vec<String> = metadata["packages"]
        .as_array()
        .expect("packages")
        .iter()
        .map(|package| package["name"].as_str().expect("name").to_string())
        .collect();
    let manifest = std::fs::read_to_string(root.join("Cargo.toml")).expect("Cargo.toml");
    let profiles = member_profiles(&manifest);
    let named: Vec<&String> = profiles.iter().map(|(name, _)| name).collect();
    let missing: Vec<&String> = members.iter().filter(|m| !named.contains(m)).collect();
    let stale: Vec<&&String> = named.iter().filter(|n| !members.contains(n)).collect();
    assert!(
        missing.is_empty() && stale.is_empty(),
        "Cargo.toml: members without a [profile.dev.package.<member>] section: {missing:?}; \
         sections of no member: {stale:?}"
    );
    for (name, lines) in &profiles {
        for setting in ["opt-level=1", "debug=\"line-tables-only\""] {
            assert!(
                lines.iter().any(|line| line == setting),
                "[profile.dev.package.{name}] lacks {setting}: {lines:?}"
            );
        }
    }
}

/// The scan reads sections as Cargo.toml writes them, and leaves out the
/// profiles of all packages and of other profiles.
#[test]
fn the_profile_sections_are_read_as_written() {
    let manifest = "[profile.dev]\nopt-level = 3\n\n[profile.dev.package.\"*\"]\nopt-level = 3\n\
                    [profile.dev.package.one]\n# why\nopt-level = 1\ndebug = \"line-tables-only\"\n\n\
                    [profile.release.package.two]\nopt-level = 2\n[profile.dev.package.\"three\"]\n";
    assert_eq!(
        member_profiles(manifest),
        vec![
            (
                "one".to_string(),
                vec![
                    "opt-level=1".to_string(),
                    "debug=\"line-tables-only\"".to_string()
                ]
            ),
            ("three".to_string(), vec![]),
        ]
    );
}

/// The Rust files under `folder` (recursively), `target` folders left out.
fn rust_files(folder: &Path, files: &mut Vec<std::path::PathBuf>) {
    let Ok(entries) = std::fs::read_dir(folder) else {
        return;
    };
    for entry in entries.flatten() {
        let path = entry.path();
        if path.is_dir() && path.file_name().is_some_and(|name| name != "target") {
            rust_files(&path, files);
        } else if path.extension().is_some_and(|extension| extension == "rs") {
            files.push(path);
        }
    }
}

/// The workspace denies `unsafe` code (Cargo.toml's `[workspace.lints]`),
/// and one module allows it: gecaro-io's mapping of small data files
/// (`whole.rs`, whose docs state why it is sound enough). A second
/// `allow(unsafe_code)` must come with its own reasons, and this list.
#[test]
fn one_module_may_use_unsafe() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut files = Vec::new();
    for folder in ["src", "crates", "tests", "benches", "examples", "fuzz"] {
        rust_files(&root.join(folder), &mut files);
    }
    assert!(files.len() > 100, "the sources were not found: {files:?}");
    // Written in two halves, so that this file does not name itself.
    let (inner, outer) = (
        concat!("#![allow(", "unsafe_code)]"),
        concat!("#[allow(", "unsafe_code)]"),
    );
    let allowing: Vec<String> = files
        .iter()
        .filter(|path| {
            std::fs::read_to_string(path).is_ok_and(|text| {
                text.lines()
                    .any(|line| line.trim_start().starts_with(inner))
                    || text.contains(outer)
            })
        })
        .map(|path| {
            path.strip_prefix(root)
                .unwrap_or(path)
                .display()
                .to_string()
        })
        .collect();
    assert_eq!(allowing, ["crates/gecaro-io/src/whole.rs"]);
    let manifest = std::fs::read_to_string(root.join("Cargo.toml")).expect("the manifest");
    assert!(manifest.contains("unsafe_code = \"deny\""));
}
